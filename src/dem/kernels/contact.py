"""Contact forces from overlap polygons: spring-dashpots with Coulomb friction (thesis 3.8).

For every candidate pair the overlap polygon gives the area A, centroid C and the contact
frame (n from body a to body b, t = n turned clockwise; :mod:`dem.kernels.overlap`). At C:

    F_N = k_n A + c_n v_N,  clipped at 0 (no tension)            # thesis Eq. 3.4
    F_T,el <- F_T,el + k_t v_T dt;  F_T = F_T,el + c_t v_T        # thesis Eq. 3.5
    |F_T| <= mu F_N  (on slip the elastic part is set to the cap)  # thesis Eq. 3.6

with v_N the approach speed and v_T the tangential velocity of b relative to a. The
elastic part k_n A is the resultant of springs spread over the overlap (depth x k_n per
unit length), so it acts at the area centroid C. The dashpots are spread the same way,
evenly along the contact chord (the overlap's extent along t, midpoint M): their resultant
is c_n v_N(M) at M plus a moment -c_n (omega_b - omega_a) l^2 / 12, and they dissipate
c_n (v_N(M)^2 + (omega_b - omega_a)^2 l^2 / 12) >= 0. A single dashpot at C would miss the
landing corner of a rocking block (C stays near the loaded pivot), which is where impact
energy is lost (thesis 5.1.2). The tangential force acts at C. k_t is
a stiffness per contact [N m-1], constant, so the tangential spring stores energy
F_T,el^2 / (2 k_t) and gives it back (a stiffness scaled by the changing contact length
would not: it loses or creates energy as a rocking contact narrows and widens). The
elastic tangential force is stored per
pair as a scalar in the contact frame, so it is invariant to rigid rotations of the pair,
and is released when the pair separates. Force b receives: F_N n - F_T t; a the opposite.

Energy (per pair, accumulated with the trapezoidal rule over each step, so the bookkeeping
is second order like the integrator): elastic normal energy is the work of k_n A; elastic
tangential energy is F_T,el^2 / (2 k_t); damper work and the tangential work not stored
are dissipation; energy still stored when a contact opens is booked as a contact residual
(zero for a conservative contact law), so the balance can show it. The force each free
body receives from driven bodies is returned so the loop can book the base work.
"""

import numpy as np
from numba import njit

from dem.kernels import JIT_OPTIONS
from dem.kernels.overlap import clip_convex_polygons, contact_frame, polygon_area_centroid

# energy accumulator slots
E_DAMPING = 0  # normal damper dissipation [J]
E_TANGENTIAL = 1  # friction slip + tangential damper dissipation [J]
E_BASE_WORK = 2  # work done by driven bodies on the others [J] (booked by the time loop)
E_RESIDUAL = 3  # elastic energy left in contacts when they opened [J]
N_ENERGY_ACC = 4

# per-pair memory slots besides the elastic tangential force
MEM_ELASTIC_N = 0  # elastic energy of the normal spring [J]
MEM_ELASTIC_T = 1  # elastic energy of the tangential spring [J]
MEM_FN_ELASTIC = 2  # k_n A at the previous step [N]
MEM_DAMPER_POWER = 3  # power of the normal dashpots at the previous step [W]
MEM_FT = 4  # total tangential force at the previous step [N]
N_MEMORY = 5


@njit(**JIT_OPTIONS)
def release_contact(a, b, pair_ft, pair_memory, energy_acc):
    """Forget the stored state of pair (a, b); book its leftover elastic energy as residual."""
    energy_acc[E_RESIDUAL] += pair_memory[a, b, MEM_ELASTIC_N] + pair_memory[a, b, MEM_ELASTIC_T]
    pair_ft[a, b] = 0.0
    for k in range(N_MEMORY):
        pair_memory[a, b, k] = 0.0


@njit(**JIT_OPTIONS)
def relative_velocity(body_x, body_y, body_vx, body_vy, body_omega, a, b, px, py, nx, ny, tx, ty):
    """(approach speed v_N, > 0 closing; tangential v_T) of b relative to a at point p [m s-1]."""
    vax = body_vx[a] - body_omega[a] * (py - body_y[a])
    vay = body_vy[a] + body_omega[a] * (px - body_x[a])
    vbx = body_vx[b] - body_omega[b] * (py - body_y[b])
    vby = body_vy[b] + body_omega[b] * (px - body_x[b])
    rel_x = vbx - vax
    rel_y = vby - vay
    return -(rel_x * nx + rel_y * ny), rel_x * tx + rel_y * ty


@njit(**JIT_OPTIONS)
def apply_force(a, b, body_x, body_y, px, py, fx, fy, force_x, force_y, torque):
    """Force (fx, fy) on b at point p and its opposite on a, with their moments about the centroids."""
    force_x[b] += fx
    force_y[b] += fy
    torque[b] += (px - body_x[b]) * fy - (py - body_y[b]) * fx
    force_x[a] -= fx
    force_y[a] -= fy
    torque[a] -= (px - body_x[a]) * fy - (py - body_y[a]) * fx


@njit(**JIT_OPTIONS)
def contact_forces(
    pair_a, pair_b, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y,
    body_x, body_y, body_vx, body_vy, body_omega, body_driven, pair_mu,
    k_n, c_n, k_t, c_t, dt, frame_rule,
    pair_ft, pair_memory,
    force_x, force_y, torque, base_force_x, base_force_y, energy_acc, scratch,
):
    """Add the contact forces of all candidate pairs to force_x, force_y, torque; return n_contact.

    pair_a, pair_b: candidate pairs, a < b (n_pair,)
    vert_start: body b's vertices are world_x[vert_start[b]:vert_start[b+1]] (n_body + 1,)
    lo_*, hi_*: current bounds of each body (n_body,) [m]
    body_x, body_y, body_omega...: centroid position [m], velocity [m s-1], spin [rad s-1]
    body_driven: 1 for bodies following the base motion (n_body,)
    pair_mu: friction coefficient of every pair (n_body, n_body) [1]
    k_n: normal stiffness per unit overlap area [N m-2]; k_t: tangential stiffness [N m-1]
    c_n, c_t: dashpot coefficients [N s m-1];  dt: time step [s]
    frame_rule: contact frame, FRAME_BOUNDARY or FRAME_THESIS (:mod:`dem.kernels.overlap`)
    pair_ft: stored elastic tangential force, in the contact frame (n_body, n_body) [N]
    pair_memory: per-pair energies and previous forces, slots MEM_* (n_body, n_body, N_MEMORY)
    force_x, force_y, torque: accumulators (n_body,) [N], [N m]
    base_force_x, base_force_y: accumulators of the force from driven bodies (n_body,) [N]
    energy_acc: accumulators, slots E_* (N_ENERGY_ACC,) [J]
    scratch: work array (4, MAX_OVERLAP_VERTICES)
    """
    n_contact = 0
    out_x = scratch[0]
    out_y = scratch[1]
    tmp_x = scratch[2]
    tmp_y = scratch[3]
    for p in range(pair_a.shape[0]):
        a = pair_a[p]
        b = pair_b[p]
        if (lo_x[a] > hi_x[b] or lo_x[b] > hi_x[a] or lo_y[a] > hi_y[b] or lo_y[b] > hi_y[a]):
            if pair_memory[a, b, MEM_FN_ELASTIC] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, energy_acc)
            continue
        sa = vert_start[a]
        ea = vert_start[a + 1]
        sb = vert_start[b]
        eb = vert_start[b + 1]
        n_over = clip_convex_polygons(
            world_x[sa:ea], world_y[sa:ea], world_x[sb:eb], world_y[sb:eb],
            out_x, out_y, tmp_x, tmp_y,
        )
        area = 0.0
        if n_over >= 3:
            area, cx, cy = polygon_area_centroid(out_x, out_y, n_over)
        if area <= 0.0:
            if pair_memory[a, b, MEM_FN_ELASTIC] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, energy_acc)
            continue
        n_contact += 1
        nx, ny, tx, ty, _ = contact_frame(
            out_x, out_y, n_over, world_x[sa:ea], world_y[sa:ea], world_x[sb:eb], world_y[sb:eb],
            body_x[a], body_y[a], body_x[b], body_y[b], frame_rule,
        )
        # the contact chord: the overlap's extent along the tangent, and its midpoint M
        proj_lo = np.inf
        proj_hi = -np.inf
        for k in range(n_over):
            proj = (out_x[k] - cx) * tx + (out_y[k] - cy) * ty
            proj_lo = min(proj_lo, proj)
            proj_hi = max(proj_hi, proj)
        chord = proj_hi - proj_lo
        mx = cx + 0.5 * (proj_lo + proj_hi) * tx
        my = cy + 0.5 * (proj_lo + proj_hi) * ty

        # relative velocity of b with respect to a at C and at M
        v_n, v_t = relative_velocity(body_x, body_y, body_vx, body_vy, body_omega, a, b,
                                     cx, cy, nx, ny, tx, ty)
        v_nm, _ = relative_velocity(body_x, body_y, body_vx, body_vy, body_omega, a, b,
                                    mx, my, nx, ny, tx, ty)
        spin = body_omega[b] - body_omega[a]

        # thesis Eq. 3.4: elastic k_n A at C; c_n v_N from dashpots spread evenly along the
        # chord: resultant c_n v_N(M) at M and moment -c_n spin l^2 / 12 about M; no tension
        f_el = k_n * area
        f_damp = c_n * v_nm
        m_damp = -c_n * spin * chord * chord / 12.0
        if f_el + f_damp < 0.0:
            scale = f_el / -f_damp
            f_damp *= scale
            m_damp *= scale
        f_n = f_el + f_damp
        mem = pair_memory[a, b]
        # trapezoidal work over the last step, v_n dt being the approach in that step
        mem[MEM_ELASTIC_N] += 0.5 * (mem[MEM_FN_ELASTIC] + f_el) * v_n * dt
        power = f_damp * v_nm - m_damp * spin  # >= 0
        energy_acc[E_DAMPING] += 0.5 * (mem[MEM_DAMPER_POWER] + power) * dt
        mem[MEM_FN_ELASTIC] = f_el
        mem[MEM_DAMPER_POWER] = power

        # thesis Eq. 3.5-3.6, at C
        ft_el = pair_ft[a, b] + k_t * v_t * dt
        f_t = ft_el + c_t * v_t
        cap = pair_mu[a, b] * f_n
        if abs(f_t) > cap:
            f_t = cap if f_t > 0.0 else -cap
            ft_el = f_t
        pair_ft[a, b] = ft_el
        stored_t = 0.5 * ft_el * ft_el / k_t
        energy_acc[E_TANGENTIAL] += (0.5 * (mem[MEM_FT] + f_t) * v_t * dt
                                     - (stored_t - mem[MEM_ELASTIC_T]))
        mem[MEM_ELASTIC_T] = stored_t
        mem[MEM_FT] = f_t

        # forces on b (a receives the opposite): at C elastic normal + tangential, at M damping
        fcx = f_el * nx - f_t * tx
        fcy = f_el * ny - f_t * ty
        fmx = f_damp * nx
        fmy = f_damp * ny
        if body_driven[a]:
            base_force_x[b] += fcx + fmx
            base_force_y[b] += fcy + fmy
        if body_driven[b]:
            base_force_x[a] -= fcx + fmx
            base_force_y[a] -= fcy + fmy
        apply_force(a, b, body_x, body_y, cx, cy, fcx, fcy, force_x, force_y, torque)
        apply_force(a, b, body_x, body_y, mx, my, fmx, fmy, force_x, force_y, torque)
        torque[b] += m_damp
        torque[a] -= m_damp
    return n_contact

