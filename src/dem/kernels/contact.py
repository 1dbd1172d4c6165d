"""Contact forces from overlap polygons: spring-dashpots with Coulomb friction (thesis 3.8).

For every candidate pair the overlap polygon gives the area A, centroid C and the contact
frame (n from body a to body b, t = n turned clockwise). At C:

    F_N = k_n A + c_n v_N,  clipped at 0 (no tension)            # thesis Eq. 3.4
    F_T,el <- F_T,el + k_t l v_T dt;  F_T = F_T,el + c_t v_T      # thesis Eq. 3.5
    |F_T| <= mu F_N  (on slip the elastic part is set to the cap)  # thesis Eq. 3.6

with v_N the approach speed and v_T the tangential velocity of b relative to a at C, and
l the chord length of the overlap (its contact length), which makes k_t [N m-2] a
stiffness per unit contact length like k_n. The elastic tangential force is stored per
pair as a scalar in the contact frame, so it is invariant to rigid rotations of the pair,
and is released when the pair separates. Force b receives: F_N n - F_T t; a the opposite.

Energy (per pair, accumulated): elastic normal energy is the work of k_n A; elastic
tangential energy is F_T,el^2 / (2 k_t l); damper power and the tangential work not stored
are dissipation; energy still stored when a contact opens is booked as a contact residual
(zero for a conservative contact law), so the balance can show it.
"""

import numpy as np
from numba import njit

from dem.kernels import JIT_OPTIONS
from dem.kernels.overlap import clip_convex_polygons, contact_frame, polygon_area_centroid

# energy accumulator slots
E_DAMPING = 0  # normal damper dissipation [J]
E_TANGENTIAL = 1  # friction slip + tangential damper dissipation [J]
E_BASE_WORK = 2  # work done by driven bodies on the others [J]
E_RESIDUAL = 3  # elastic energy left in contacts when they opened [J]
N_ENERGY_ACC = 4


@njit(**JIT_OPTIONS)
def release_contact(a, b, pair_elastic_n, pair_elastic_t, pair_ft, energy_acc):
    """Forget the stored state of pair (a, b); book its leftover elastic energy as residual."""
    energy_acc[E_RESIDUAL] += pair_elastic_n[a, b] + pair_elastic_t[a, b]
    pair_elastic_n[a, b] = 0.0
    pair_elastic_t[a, b] = 0.0
    pair_ft[a, b] = 0.0


@njit(**JIT_OPTIONS)
def contact_forces(
    pair_a, pair_b, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y,
    body_x, body_y, body_vx, body_vy, body_omega, body_driven, pair_mu,
    k_n, c_n, k_t, c_t, dt,
    pair_ft, pair_elastic_n, pair_elastic_t,
    force_x, force_y, torque, energy_acc, scratch,
):
    """Add the contact forces of all candidate pairs to force_x, force_y, torque; return n_contact.

    pair_a, pair_b: candidate pairs, a < b (n_pair,)
    vert_start: body b's vertices are world_x[vert_start[b]:vert_start[b+1]] (n_body + 1,)
    lo_*, hi_*: current bounds of each body (n_body,) [m]
    body_x, body_y, body_omega...: centroid position [m], velocity [m s-1], spin [rad s-1]
    body_driven: 1 for bodies following the base motion (n_body,)
    pair_mu: friction coefficient of every pair (n_body, n_body) [1]
    k_n, k_t: stiffness per unit contact area / per unit contact length [N m-2]
    c_n, c_t: dashpot coefficients [N s m-1];  dt: time step [s]
    pair_ft: stored elastic tangential force, in the contact frame (n_body, n_body) [N]
    pair_elastic_n, pair_elastic_t: stored elastic energy per pair [J]
    force_x, force_y, torque: accumulators (n_body,) [N], [N m]
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
            if pair_ft[a, b] != 0.0 or pair_elastic_n[a, b] != 0.0:
                release_contact(a, b, pair_elastic_n, pair_elastic_t, pair_ft, energy_acc)
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
            if pair_ft[a, b] != 0.0 or pair_elastic_n[a, b] != 0.0:
                release_contact(a, b, pair_elastic_n, pair_elastic_t, pair_ft, energy_acc)
            continue
        n_contact += 1
        nx, ny, tx, ty, chord = contact_frame(
            out_x, out_y, n_over, body_x[a], body_y[a], body_x[b], body_y[b]
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
        pair_elastic_n[a, b] += f_el * v_n * dt
        energy_acc[E_DAMPING] += (f_n - f_el) * v_n * dt

        # thesis Eq. 3.5-3.6
        k_t_pair = k_t * chord
        ft_el = pair_ft[a, b] + k_t_pair * v_t * dt
        f_t = ft_el + c_t * v_t
        cap = pair_mu[a, b] * f_n
        if abs(f_t) > cap:
            f_t = cap if f_t > 0.0 else -cap
            ft_el = f_t
        pair_ft[a, b] = ft_el
        stored_t = 0.5 * ft_el * ft_el / k_t_pair if k_t_pair > 0.0 else 0.0
        energy_acc[E_TANGENTIAL] += f_t * v_t * dt - (stored_t - pair_elastic_t[a, b])
        pair_elastic_t[a, b] = stored_t

        # force on b; a receives the opposite
        fbx = f_n * nx - f_t * tx
        fby = f_n * ny - f_t * ty
        if body_driven[a]:
            energy_acc[E_BASE_WORK] += (fbx * body_vx[a] + fby * body_vy[a]) * dt
        if body_driven[b]:
            energy_acc[E_BASE_WORK] -= (fbx * body_vx[b] + fby * body_vy[b]) * dt
        force_x[b] += fbx
        force_y[b] += fby
        torque[b] += rbx * fby - rby * fbx
        force_x[a] -= fbx
        force_y[a] -= fby
        torque[a] -= rax * fby - ray * fbx
    return n_contact

