"""Contact forces from overlap polygons: spring-dashpots with Coulomb friction (thesis 3.8).

For every candidate pair the overlap polygon gives the area A, centroid C and the contact
frame (n from body a to body b, t = n turned clockwise; :mod:`dem.kernels.overlap`). At C:

    F_N = k_n A + c_n v_N,  clipped at 0 (no tension)            # thesis Eq. 3.4
    F_T,el <- F_T,el + k_t v_T dt;  F_T = F_T,el + c_t v_T        # thesis Eq. 3.5
    |F_T| <= mu F_N  (on slip the elastic part is set to the cap)  # thesis Eq. 3.6

with v_N the approach speed and v_T the tangential velocity of b relative to a at C. k_t is
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
MEM_FN_DAMPER = 3  # damper part of F_N at the previous step [N]
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
        # velocities of both bodies at the contact point C
        rax = cx - body_x[a]
        ray = cy - body_y[a]
        rbx = cx - body_x[b]
        rby = cy - body_y[b]
        vax = body_vx[a] - body_omega[a] * ray
        vay = body_vy[a] + body_omega[a] * rax
        vbx = body_vx[b] - body_omega[b] * rby
        vby = body_vy[b] + body_omega[b] * rbx
        rel_x = vbx - vax
        rel_y = vby - vay
        v_n = -(rel_x * nx + rel_y * ny)  # approach speed, > 0 when closing
        v_t = rel_x * tx + rel_y * ty

        # thesis Eq. 3.4, no tension
        f_el = k_n * area
        f_n = f_el + c_n * v_n
        if f_n < 0.0:
            f_n = 0.0
        mem = pair_memory[a, b]
        # trapezoidal work over the last step, v_n dt being the approach in that step
        mem[MEM_ELASTIC_N] += 0.5 * (mem[MEM_FN_ELASTIC] + f_el) * v_n * dt
        energy_acc[E_DAMPING] += 0.5 * (mem[MEM_FN_DAMPER] + f_n - f_el) * v_n * dt
        mem[MEM_FN_ELASTIC] = f_el
        mem[MEM_FN_DAMPER] = f_n - f_el

        # thesis Eq. 3.5-3.6
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

        # force on b; a receives the opposite
        fbx = f_n * nx - f_t * tx
        fby = f_n * ny - f_t * ty
        if body_driven[a]:
            base_force_x[b] += fbx
            base_force_y[b] += fby
        if body_driven[b]:
            base_force_x[a] -= fbx
            base_force_y[a] -= fby
        force_x[b] += fbx
        force_y[b] += fby
        torque[b] += rbx * fby - rby * fbx
        force_x[a] -= fbx
        force_y[a] -= fby
        torque[a] -= rax * fby - ray * fbx
    return n_contact

