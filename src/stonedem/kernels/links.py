"""Shear links between two bodies (dowels, empolia; thesis 8.3): a contact-law extension.

A link joins a lower body a and an upper body b across their interface. Its anchor is one
point of the interface as built (before any initial tilt), stored in each body's frame,
with the interface's unit tangent in a's frame (the normal is the tangent turned +90 deg).
At each step, with P_a and P_b the anchors in the world and t, n the tangent and normal
turned with a:

- slip s = (P_b - P_a) . t and opening u = (P_b - P_a) . n;
- shear: elastic-perfectly plastic with a clearance: with e = s - s_p (s_p the plastic
  slip), no force while |e| <= gap, then k (|e| - gap) capped at the capacity; at the cap
  s_p grows and the capacity times its growth is dissipated. The link BREAKS for good once
  the total slip |s| exceeds the ultimate slip;
- axial (pull-out): min(k u, pullout) while 0 < u <= embedment, a nonlinear elastic spring;
  once u exceeds the embedment the dowel has left its hole: PULLED OUT for good.

A broken or pulled-out link exerts nothing from then on; the energy it stored is booked as
dissipated at that step. The forces act on b at P_b and equal and opposite on a at P_a, in
parallel with the contact's Coulomb friction, so the interface resists sliding with
mu N + V_link. :func:`link_forces` is stage 3b of :func:`stonedem.kernels.step.steps_under_law`,
called only for a scene with links: a scene without them runs the same floats as before.
"""

import math

from numba import njit

from stonedem.kernels import NO_ALLOC_OPTIONS
from stonedem.kernels.contact import E_TANGENTIAL

LINK_ENGAGED = 0
LINK_BROKEN = 1  # total slip beyond the ultimate slip
LINK_PULLED_OUT = 2  # opening beyond the embedment
LINK_STATUS = ("engaged", "broken", "pulled_out")


@njit(**NO_ALLOC_OPTIONS)
def link_energy(k, capacity, gap, pullout, e, u):
    """Energy stored in a link [J] at elastic slip e = s - s_p [m] and opening u [m]."""
    stored = 0.0
    over = abs(e) - gap
    if over > 0.0:
        stored += 0.5 * k * over * over
    if u > 0.0 and pullout > 0.0:
        u_cap = pullout / k
        if u <= u_cap:
            stored += 0.5 * k * u * u
        else:
            stored += pullout * (u - 0.5 * u_cap)
    return stored


@njit(**NO_ALLOC_OPTIONS)
def link_forces(model, state, work):
    """Add every engaged link's forces and torques to work (and the base's share to
    work.base_force_*), update the links' plastic slip, status and peak force, and book
    their losses in state.energy_acc[E_TANGENTIAL]. Returns the energy they store [J]."""
    links = model.links
    body_x, body_y = state.body_x, state.body_y
    cos_t, sin_t = work.cos_theta, work.sin_theta
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    base_force_x, base_force_y = work.base_force_x, work.base_force_y
    driven = model.body_driven
    slip_p, status, peak, stored_last = (
        state.link_slip,
        state.link_status,
        state.link_peak,
        state.link_energy,
    )
    total = 0.0
    for i in range(links.a.shape[0]):
        if status[i] != LINK_ENGAGED:
            continue
        a = links.a[i]
        b = links.b[i]
        ca, sa, cb, sb = cos_t[a], sin_t[a], cos_t[b], sin_t[b]
        pax = body_x[a] + ca * links.a_x[i] - sa * links.a_y[i]
        pay = body_y[a] + sa * links.a_x[i] + ca * links.a_y[i]
        pbx = body_x[b] + cb * links.b_x[i] - sb * links.b_y[i]
        pby = body_y[b] + sb * links.b_x[i] + cb * links.b_y[i]
        tx = ca * links.t_x[i] - sa * links.t_y[i]
        ty = sa * links.t_x[i] + ca * links.t_y[i]
        nx = -ty
        ny = tx
        dx = pbx - pax
        dy = pby - pay
        s = dx * tx + dy * ty
        u = dx * nx + dy * ny
        k = links.stiffness[i]
        if abs(s) > links.ultimate_slip[i]:
            status[i] = LINK_BROKEN
        elif u > links.embedment[i]:
            status[i] = LINK_PULLED_OUT
        if status[i] != LINK_ENGAGED:
            state.energy_acc[E_TANGENTIAL] += stored_last[i]
            stored_last[i] = 0.0
            continue
        # shear, elastic-perfectly plastic beyond the clearance
        e = s - slip_p[i]
        over = abs(e) - links.gap[i]
        f_s = 0.0
        if over > 0.0:
            f_s = k * over
            cap = links.capacity[i]
            if f_s > cap:
                grow = over - cap / k
                slip_p[i] += math.copysign(grow, e)
                state.energy_acc[E_TANGENTIAL] += cap * grow
                f_s = cap
                e = s - slip_p[i]
            f_s = math.copysign(f_s, e)
        # pull-out resistance while the dowel is in its hole
        f_n = 0.0
        if u > 0.0:
            f_n = min(k * u, links.pullout[i])
        fx = -(f_s * tx + f_n * nx)  # on b; -F on a
        fy = -(f_s * ty + f_n * ny)
        magnitude = math.sqrt(fx * fx + fy * fy)
        if magnitude > peak[i]:
            peak[i] = magnitude
        force_x[b] += fx
        force_y[b] += fy
        torque[b] += (pbx - body_x[b]) * fy - (pby - body_y[b]) * fx
        force_x[a] -= fx
        force_y[a] -= fy
        torque[a] -= (pax - body_x[a]) * fy - (pay - body_y[a]) * fx
        if driven[a]:
            base_force_x[b] += fx
            base_force_y[b] += fy
        if driven[b]:
            base_force_x[a] -= fx
            base_force_y[a] -= fy
        energy = link_energy(k, links.capacity[i], links.gap[i], links.pullout[i], e, u)
        stored_last[i] = energy
        total += energy
    return total
