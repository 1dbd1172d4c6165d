"""Contact forces from overlap polygons: spring-dashpots with Coulomb friction (thesis 3.8).

For every candidate pair the overlap polygon gives the area A, centroid C and the contact
frame (n from body a to body b, t = n turned clockwise; :mod:`stonedem.kernels.overlap`):

    F_N = k_n A + c_n v_N,  clipped at 0 (no tension)            # thesis Eq. 3.4
    F_T,el <- F_T,el + k_t v_T dt;  F_T = F_T,el + c_t v_T        # thesis Eq. 3.5
    |F_T| <= mu F_N  (on slip the elastic part is set to the cap)  # thesis Eq. 3.6

with v_N the approach speed and v_T the tangential velocity of b relative to a. The
elastic part k_n A is the resultant of springs spread over the contact (a Winkler layer:
k_n x depth per unit length of the chord), so it acts at the area centroid C and stores
k_n/2 int depth(s)^2 ds. The dashpots are spread the same way, evenly along the contact
chord (the overlap's extent along t, midpoint M): their resultant is c_n v_N(M) at M plus a
moment -c_n (omega_b - omega_a) l^2 / 12, dissipating c_n (v_N(M)^2 + (omega_b -
omega_a)^2 l^2 / 12) >= 0. A single dashpot at C would miss the landing corner of a rocking
block (C stays near the loaded pivot), which is where impact energy is lost (thesis 5.1.2).

The tangential force acts at C. k_t is a stiffness per contact [N m-1], constant, so the
tangential spring stores F_T,el^2 / (2 k_t) and gives it back. The elastic tangential force
is stored per pair as a scalar in the contact frame, so it is invariant to rigid rotations
of the pair, and is released when the pair separates. Force b receives: F_N n - F_T t
(normal damping at M), a the opposite.

Energy: stored energy is evaluated as a state function when sampled (Winkler layer +
tangential springs); dissipation is the dashpots' power plus friction times slip rate,
accumulated with the trapezoidal rule; in the tangential channel (where slip and the
spring's unloading mix) dissipation is the work of F_T minus the change of the spring's
energy. The normal channel is not booked by difference, so the balance (kinetic +
potential + stored + dissipated - base work) checks the integrator and the contact law.
"""

import numpy as np
from numba import njit

from stonedem.kernels import INLINE_OPTIONS, NO_ALLOC_OPTIONS
from stonedem.kernels.overlap import clip_convex_polygons, contact_frame, polygon_area_centroid

# energy accumulator slots
E_DAMPING = 0  # normal dashpot dissipation [J]
E_TANGENTIAL = 1  # friction slip + tangential dashpot dissipation [J]
# work done by driven bodies on the others [J] (booked by the time loop and
# point_contact.plastic_impulse)
E_BASE_WORK = 2
N_ENERGY_ACC = 3

# per-pair memory slots besides the elastic tangential force: the current step's forces
# and points, for booking dissipation with the velocities at t_n (contact_power). Both
# laws book them as up to two point forces, each with its own normal, dashpot force and
# tangential force, plus a dashpot moment (area law: dashpots at M, F_T at C; point law:
# one per contact end).
MEM_ACTIVE = 0  # 1 while the pair is in contact
MEM_M_DAMP = 1  # dashpot moment on b [N m]
MEM_POINT_FORCE = 2  # first of two point-force records: point x, y, normal x, y [m, m, 1, 1],
# normal dashpot force and tangential force F_T (b receives -F_T t, t = n turned clockwise) [N]
POINT_FORCE_SLOTS = 6
N_POINT_FORCES = 2
# point law only: per contact end, whether it touched at the last step, which vertex
# carried it (body a: index + 1, body b: -(index + 1)), its plastic offset [m] and the
# elastic part of its own tangential spring [N] (stiffness k_t / 2)
MEM_END = MEM_POINT_FORCE + N_POINT_FORCES * POINT_FORCE_SLOTS
END_SLOTS = 4
END_FT = 3
N_MEMORY = MEM_END + 2 * END_SLOTS


@njit(**NO_ALLOC_OPTIONS)
def release_contact(a, b, pair_ft, pair_memory, k_t, energy_acc):
    """Forget the stored state of pair (a, b) once it has separated; its spring energy is lost."""
    energy_acc[E_TANGENTIAL] += 0.5 * pair_ft[a, b] ** 2 / k_t
    for end in range(2):
        # the point law's end springs, k_t / 2 each (zero under the area law)
        energy_acc[E_TANGENTIAL] += pair_memory[a, b, MEM_END + end * END_SLOTS + END_FT] ** 2 / k_t
    pair_ft[a, b] = 0.0
    for k in range(N_MEMORY):
        pair_memory[a, b, k] = 0.0


@njit(**NO_ALLOC_OPTIONS)
def winkler_integral(x, y, n, tx, ty, nx, ny):
    """int depth(s)^2 ds [m3] of the overlap polygon x[:n], y[:n] over its chord along t.

    depth(s) is the overlap's extent along n at chord coordinate s; it is piecewise
    linear between the vertices' s, so each piece integrates exactly: ds (d0^2 + d0 d1 + d1^2) / 3.
    """
    total = 0.0
    s_prev = 0.0
    d_prev = 0.0
    first = True
    # vertices' chord coordinates, visited in increasing order (n is small)
    last = -np.inf
    for _ in range(n):
        s_next = np.inf
        for k in range(n):
            sk = x[k] * tx + y[k] * ty
            if last < sk < s_next:
                s_next = sk
        if s_next == np.inf:
            break
        last = s_next
        lo = np.inf
        hi = -np.inf
        for k in range(n):
            k1 = (k + 1) % n
            s0 = x[k] * tx + y[k] * ty
            s1 = x[k1] * tx + y[k1] * ty
            if (s0 - s_next) * (s1 - s_next) <= 0.0:
                h0 = x[k] * nx + y[k] * ny
                h1 = x[k1] * nx + y[k1] * ny
                h = h0 if s1 == s0 else h0 + (h1 - h0) * (s_next - s0) / (s1 - s0)
                if s1 == s0:
                    lo = min(lo, h0, h1)
                    hi = max(hi, h0, h1)
                else:
                    lo = min(lo, h)
                    hi = max(hi, h)
        d = hi - lo if hi > lo else 0.0
        if not first:
            total += (s_next - s_prev) * (d_prev * d_prev + d_prev * d + d * d) / 3.0
        first = False
        s_prev = s_next
        d_prev = d
    return total


@njit(**INLINE_OPTIONS)
def relative_velocity(body_x, body_y, body_vx, body_vy, body_omega, a, b, px, py, nx, ny, tx, ty):
    """(approach speed v_N, > 0 closing; tangential v_T) of b relative to a at point p [m s-1]."""
    vax = body_vx[a] - body_omega[a] * (py - body_y[a])
    vay = body_vy[a] + body_omega[a] * (px - body_x[a])
    vbx = body_vx[b] - body_omega[b] * (py - body_y[b])
    vby = body_vy[b] + body_omega[b] * (px - body_x[b])
    rel_x = vbx - vax
    rel_y = vby - vay
    return -(rel_x * nx + rel_y * ny), rel_x * tx + rel_y * ty


@njit(**INLINE_OPTIONS)
def apply_force(a, b, body_x, body_y, px, py, fx, fy, force_x, force_y, torque):
    """Force (fx, fy) on b at point p and its opposite on a, with their moments about the
    centroids."""
    force_x[b] += fx
    force_y[b] += fy
    torque[b] += (px - body_x[b]) * fy - (py - body_y[b]) * fx
    force_x[a] -= fx
    force_y[a] -= fy
    torque[a] -= (px - body_x[a]) * fy - (py - body_y[a]) * fx


@njit(**INLINE_OPTIONS)
def record_point_force(mem, k, px, py, nx, ny, force, f_t=0.0):
    """Record point force k of a pair on b at (px, py) [m]: normal dashpot force [N] along
    (nx, ny) and tangential force F_T [N] (b receives -F_T t), for :func:`contact_power`."""
    base = MEM_POINT_FORCE + k * POINT_FORCE_SLOTS
    mem[base] = px
    mem[base + 1] = py
    mem[base + 2] = nx
    mem[base + 3] = ny
    mem[base + 4] = force
    mem[base + 5] = f_t


@njit(**INLINE_OPTIONS)
def tangential_force(ft_old, mu, f_n, v_t, k_t, c_t, dt, energy_acc):
    """Thesis Eq. 3.5-3.6: (F_T, elastic part) of a tangential spring after this step [N].

    The elastic part ft_old is updated incrementally and capped by Coulomb mu F_N (on slip
    it is set to the cap); the change of its spring energy is taken from the tangential
    dissipation, whose work of F_T is booked in :func:`contact_power`.
    """
    ft_el = ft_old + k_t * v_t * dt
    f_t = ft_el + c_t * v_t
    cap = mu * f_n
    if abs(f_t) > cap:
        f_t = cap if f_t > 0.0 else -cap
        ft_el = f_t
    energy_acc[E_TANGENTIAL] -= 0.5 * (ft_el * ft_el - ft_old * ft_old) / k_t
    return f_t, ft_el


@njit(**INLINE_OPTIONS)
def push_pair(
    a,
    b,
    body_x,
    body_y,
    body_driven,
    px,
    py,
    fx,
    fy,
    force_x,
    force_y,
    torque,
    base_force_x,
    base_force_y,
):
    """Force (fx, fy) on b at p and its opposite on a; booked as base force if the other is
    driven."""
    if body_driven[a]:
        base_force_x[b] += fx
        base_force_y[b] += fy
    if body_driven[b]:
        base_force_x[a] -= fx
        base_force_y[a] -= fy
    apply_force(a, b, body_x, body_y, px, py, fx, fy, force_x, force_y, torque)


@njit(**INLINE_OPTIONS)
def area_contact_forces(model, state, work, n_pair, dt, want_energy):
    """The thesis' overlap-area law (``contact.model: area``): add every candidate pair's forces.

    Returns (n_contact, stored elastic energy [J]); the energy is evaluated only when
    want_energy is true (sample steps), else 0.

    model, state, work: the time loop's bundles (:mod:`stonedem.kernels.step`). Read: work's
    world vertices (body b's are world_x[vert_start[b]:vert_start[b+1]]), bounds and first
    n_pair candidate pairs (a < b); state's poses and mid-step velocities; model's masses,
    driven flags, pair friction and law: k_n, the normal stiffness per unit overlap area
    [N m-2]; damping, the normal dashpot c_n [N s m-1]; k_t [N m-1] and c_t [N s m-1], the
    tangential spring and dashpot; frame_rule, FRAME_BOUNDARY or FRAME_THESIS
    (:mod:`stonedem.kernels.overlap`). Written: work's force, torque and base-force
    accumulators (what driven bodies exert), state's pair_ft (elastic tangential force in
    the contact frame), pair_memory (slots MEM_*) and energy accumulators (slots E_*). dt:
    the time step [s].

    Inlined into the loop by Numba, so handing it the bundles costs nothing.
    """
    law = model.law
    k_n, c_n, k_t, c_t, frame_rule = law.k_n, law.params[0], law.k_t, law.c_t, law.frame_rule
    vert_start, body_driven, pair_mu = model.vert_start, model.body_driven, model.pair_mu
    body_x, body_y = state.body_x, state.body_y
    body_vx, body_vy, body_omega = state.body_vx, state.body_vy, state.body_omega
    pair_ft, pair_memory, energy_acc = state.pair_ft, state.pair_memory, state.energy_acc
    world_x, world_y = work.world_x, work.world_y
    lo_x, lo_y, hi_x, hi_y = work.lo_x, work.lo_y, work.hi_x, work.hi_y
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    base_force_x, base_force_y, scratch = work.base_force_x, work.base_force_y, work.scratch
    pair_a, pair_b = work.pair_a, work.pair_b
    n_contact = 0
    stored = 0.0
    out_x = scratch[0]
    out_y = scratch[1]
    for p in range(n_pair):
        a = pair_a[p]
        b = pair_b[p]
        # narrow phase: bounds, overlap polygon, area, frame; written out here (and in the
        # point law) rather than called: as a call it made the step 1.6x slower (8-drum column)
        if lo_x[a] > hi_x[b] or lo_x[b] > hi_x[a] or lo_y[a] > hi_y[b] or lo_y[b] > hi_y[a]:
            if pair_memory[a, b, MEM_ACTIVE] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, k_t, energy_acc)
            continue
        sa = vert_start[a]
        ea = vert_start[a + 1]
        sb = vert_start[b]
        eb = vert_start[b + 1]
        n_over = clip_convex_polygons(
            world_x[sa:ea],
            world_y[sa:ea],
            world_x[sb:eb],
            world_y[sb:eb],
            out_x,
            out_y,
            scratch[2],
            scratch[3],
        )
        area = 0.0
        if n_over >= 3:
            area, cx, cy = polygon_area_centroid(out_x, out_y, n_over)
        if area <= 0.0:
            if pair_memory[a, b, MEM_ACTIVE] != 0.0:
                release_contact(a, b, pair_ft, pair_memory, k_t, energy_acc)
            continue
        nx, ny, tx, ty, _ = contact_frame(
            out_x,
            out_y,
            n_over,
            world_x[sa:ea],
            world_y[sa:ea],
            world_x[sb:eb],
            world_y[sb:eb],
            body_x[a],
            body_y[a],
            body_x[b],
            body_y[b],
            frame_rule,
        )
        n_contact += 1
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
        _, v_t = relative_velocity(
            body_x, body_y, body_vx, body_vy, body_omega, a, b, cx, cy, nx, ny, tx, ty
        )
        v_nm, _ = relative_velocity(
            body_x, body_y, body_vx, body_vy, body_omega, a, b, mx, my, nx, ny, tx, ty
        )
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
        f_t, ft_el = tangential_force(
            pair_ft[a, b], pair_mu[a, b], f_el + f_damp, v_t, k_t, c_t, dt, energy_acc
        )
        pair_ft[a, b] = ft_el
        mem = pair_memory[a, b]
        mem[MEM_ACTIVE] = 1.0
        mem[MEM_M_DAMP] = m_damp
        record_point_force(mem, 0, mx, my, nx, ny, f_damp)
        record_point_force(mem, 1, cx, cy, nx, ny, 0.0, f_t)
        if want_energy:
            stored += 0.5 * k_n * winkler_integral(out_x, out_y, n_over, tx, ty, nx, ny)
            stored += 0.5 * ft_el * ft_el / k_t

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
    return n_contact, stored


@njit(**INLINE_OPTIONS)
def contact_power(
    pair_a, pair_b, n_pair, pair_memory, body_x, body_y, body_vx, body_vy, body_omega
):
    """(dashpot power, tangential work rate) [W] of this step's contact forces at the given
    velocities.

    Called with the velocities at t_n (the mean of the two half-step velocities), the same
    ones whose kinetic energy the samples report, so the booking matches the integrator.
    """
    p_damp = 0.0
    p_tan = 0.0
    for p in range(n_pair):
        a = pair_a[p]
        b = pair_b[p]
        mem = pair_memory[a, b]
        if mem[MEM_ACTIVE] == 0.0:
            continue
        p_damp -= mem[MEM_M_DAMP] * (body_omega[b] - body_omega[a])
        for k in range(N_POINT_FORCES):
            base = MEM_POINT_FORCE + k * POINT_FORCE_SLOTS
            force = mem[base + 4]
            f_t = mem[base + 5]
            if force != 0.0 or f_t != 0.0:
                dnx = mem[base + 2]
                dny = mem[base + 3]
                v_n, v_tk = relative_velocity(
                    body_x,
                    body_y,
                    body_vx,
                    body_vy,
                    body_omega,
                    a,
                    b,
                    mem[base],
                    mem[base + 1],
                    dnx,
                    dny,
                    dny,
                    -dnx,
                )
                p_damp += force * v_n
                p_tan += f_t * v_tk
    return p_damp, p_tan
