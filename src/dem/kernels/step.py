"""The time loop of the 2D rigid-block engine, compiled whole (thesis 3.10, Fig. 3.14).

Stages of one step at time t_n = n dt:

1. drive_bodies             driven bodies take the base pose and velocity at t_n
2. update_world_vertices    world vertices and bounds from the poses
3. find_candidate_pairs     only when some body has moved half the margin since the last sweep
4. contact_forces           overlap polygons -> spring-dashpot + Coulomb forces (velocities v_{n-1/2})
5. sample                   every ``out_every`` steps: poses, energies, contact count; NaN and collapse checks
6. central_difference_step  v_{n+1/2} = v_{n-1/2} + dt a_n (first step: a half kick), x_{n+1} = x_n + dt v_{n+1/2}

Python never sees a single step: :func:`run` is called once per simulation.
"""

import numpy as np
from numba import njit

from dem.kernels import JIT_OPTIONS
from dem.kernels.broad_phase import body_bounds, find_candidate_pairs
from dem.kernels.contact import E_BASE_WORK, E_DAMPING, E_TANGENTIAL, area_contact_forces, contact_power
from dem.kernels.point_contact import point_contact_forces
from dem.kernels.excitation import base_motion
from dem.kernels.integrate import central_difference_step, drive_bodies, update_world_vertices
from dem.kernels.overlap import MAX_OVERLAP_VERTICES

STATUS_OK = 0
STATUS_COLLAPSED = 1  # stopped early: the structure collapsed
STATUS_NONFINITE = 2  # a position or velocity became NaN or infinite
STATUS_AT_REST = 3  # stopped early: the base is quiet from here on and every body rests on it

CONTACT_AREA = 0  # thesis overlap-area law (dem.kernels.contact)
CONTACT_POINT = 1  # point contacts at the face ends (dem.kernels.point_contact)

# columns of the sampled energy array
ENERGY_KINETIC = 0
ENERGY_POTENTIAL = 1
ENERGY_ELASTIC = 2
ENERGY_DAMPING = 3
ENERGY_TANGENTIAL = 4
ENERGY_BASE_WORK = 5
N_ENERGY = 6


@njit(**JIT_OPTIONS)
def collapse_state(n_body, body_driven, body_group, n_group, group_theta_cr, body_theta,
                   body_y, ref_y, fall_depth, d_v):
    """True when a group's mean |theta| exceeds its theta_cr, or a body dropped below its support.

    body_group: group (column, epistyle, block) of each body, -1 for none (n_body,)
    group_theta_cr: critical mean rotation of each group, atan(b/h) (n_group,) [rad]
    fall_depth: drop of a body's centroid, relative to the base, that means it fell (n_body,) [m]
    """
    sums = np.zeros(n_group)
    counts = np.zeros(n_group)
    for b in range(n_body):
        if body_driven[b]:
            continue
        if ref_y[b] - (body_y[b] - d_v) > fall_depth[b]:
            return True
        g = body_group[b]
        if g >= 0:
            sums[g] += abs(body_theta[b])
            counts[g] += 1.0
    for g in range(n_group):
        if counts[g] > 0.0 and sums[g] / counts[g] > group_theta_cr[g]:
            return True
    return False


@njit(**JIT_OPTIONS)
def at_rest(n_body, body_driven, body_radius, vel_x, vel_y, vel_om, vel_h, vel_v, rest_speed):
    """True when every free body moves slower than rest_speed [m s-1] relative to the base."""
    for b in range(n_body):
        if body_driven[b]:
            continue
        speed = abs(vel_x[b] - vel_h) + abs(vel_y[b] - vel_v) + body_radius[b] * abs(vel_om[b])
        if speed > rest_speed:
            return False
    return True


@njit(**JIT_OPTIONS)
def run(
    vert_start, local_x, local_y, body_mass, body_inertia, body_driven, body_radius,
    ref_x, ref_y, ref_theta, pair_mu, contact_model, k_n, c_n, impact, k_t, c_t, frame_rule, gravity,
    body_group, group_theta_cr, fall_depth,
    h_kind, h_params, h_accel, h_vel, h_disp, h_dt,
    v_kind, v_params, v_accel, v_vel, v_disp, v_dt,
    dt, step_start, step_stop, n_steps, out_every, margin, sweep_axis, stop_on_collapse,
    step_first, rest_from_step, rest_speed, rest_samples, rest_count,
    body_x, body_y, body_theta, body_vx, body_vy, body_omega,
    pair_ft, pair_memory, energy_acc,
    out_step, out_x, out_y, out_theta, out_energy, out_n_contact, n_sample, collapse_sample,
):
    """Run steps step_start..step_stop-1 (of 0..n_steps); return (status, n_sample, collapse_sample).

    Scene arrays (read only) are described in :class:`dem.simulate.SceneArrays`; h_* / v_*
    describe the horizontal / vertical base motion (:func:`dem.kernels.excitation.base_motion`).
    State (read and written, so a run can be split into chunks): body_* hold velocities at
    t = 0 before step 0 and at mid-steps after; pair_ft, pair_memory and energy_acc are the
    contact memory and energy accumulators of :mod:`dem.kernels.contact`; base_force_prev
    (n_body, 2) [N] is the force driven bodies exerted on each body at the previous step.
    out_*: preallocated samples (n_sample, n_body) and (n_sample, N_ENERGY), taken every
    out_every steps and at the last step; out_step holds each sample's step number.
    Samples are written from index n_sample on. collapse_sample is the first collapsed sample, or -1.
    step_first: the step the run starts from (its kick is a half step; body_* hold the
    velocities at that instant). From step rest_from_step on (the base motion is quiet for
    good), rest_samples samples in a row at which every free body moves slower than
    rest_speed [m s-1] relative to the base (rotation times bounding radius included) end
    the run with STATUS_AT_REST; rest_count (1,) int64 carries the run of them across calls.
    """
    n_body = body_mass.shape[0]
    n_group = group_theta_cr.shape[0]
    n_vert = local_x.shape[0]
    world_x = np.empty(n_vert)
    world_y = np.empty(n_vert)
    lo_x = np.empty(n_body)
    lo_y = np.empty(n_body)
    hi_x = np.empty(n_body)
    hi_y = np.empty(n_body)
    force_x = np.zeros(n_body)
    force_y = np.zeros(n_body)
    torque = np.zeros(n_body)
    base_force_x = np.zeros(n_body)
    base_force_y = np.zeros(n_body)
    vel_x = np.zeros(n_body)
    vel_y = np.zeros(n_body)
    vel_om = np.zeros(n_body)
    scratch = np.zeros((4, MAX_OVERLAP_VERTICES))
    sweep_x = np.empty(n_body)
    sweep_y = np.empty(n_body)
    sweep_theta = np.empty(n_body)
    pair_a = np.zeros(0, dtype=np.int64)
    pair_b = np.zeros(0, dtype=np.int64)
    need_sweep = True
    status = STATUS_OK

    for n in range(step_start, min(step_stop, n_steps + 1)):
        t = n * dt
        d_h, vel_h, acc_h = base_motion(t, h_kind, h_params, h_accel, h_vel, h_disp, h_dt)
        d_v, vel_v, acc_v = base_motion(t, v_kind, v_params, v_accel, v_vel, v_disp, v_dt)
        drive_bodies(n_body, body_driven, ref_x, ref_y, ref_theta, d_h, vel_h, d_v, vel_v,
                     body_x, body_y, body_theta, body_vx, body_vy, body_omega)
        update_world_vertices(n_body, vert_start, local_x, local_y, body_x, body_y, body_theta,
                              world_x, world_y)
        body_bounds(n_body, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y)

        if not need_sweep:
            for b in range(n_body):
                moved = (abs(body_x[b] - sweep_x[b]) + abs(body_y[b] - sweep_y[b])
                         + body_radius[b] * abs(body_theta[b] - sweep_theta[b]))
                if moved > 0.5 * margin:
                    need_sweep = True
                    break
        if need_sweep:
            pair_a, pair_b = find_candidate_pairs(n_body, body_driven, lo_x, lo_y, hi_x, hi_y,
                                                  margin, sweep_axis)
            for b in range(n_body):
                sweep_x[b] = body_x[b]
                sweep_y[b] = body_y[b]
                sweep_theta[b] = body_theta[b]
            need_sweep = False

        force_x[:] = 0.0
        force_y[:] = 0.0
        torque[:] = 0.0
        base_force_x[:] = 0.0
        base_force_y[:] = 0.0
        sample = n % out_every == 0 or n == n_steps
        if contact_model == CONTACT_POINT:
            n_contact, elastic = point_contact_forces(
                pair_a, pair_b, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y,
                body_x, body_y, body_vx, body_vy, body_omega, body_driven, body_mass, body_inertia,
                pair_mu, k_n, c_n, impact, k_t, c_t, dt, frame_rule, pair_ft, pair_memory,
                force_x, force_y, torque, base_force_x, base_force_y, energy_acc, scratch, sample,
            )
        else:
            n_contact, elastic = area_contact_forces(
                pair_a, pair_b, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y,
                body_x, body_y, body_vx, body_vy, body_omega, body_driven, pair_mu,
                k_n, c_n, k_t, c_t, dt, frame_rule, pair_ft, pair_memory,
                force_x, force_y, torque, base_force_x, base_force_y, energy_acc, scratch, sample,
            )
        # velocities at t_n: half a kick on from v_{n-1/2} (the start holds v_0 itself)
        half = 0.0 if n == step_first else 0.5 * dt
        for b in range(n_body):
            if body_driven[b]:
                vel_x[b] = body_vx[b]
                vel_y[b] = body_vy[b]
                vel_om[b] = 0.0
            else:
                vel_x[b] = body_vx[b] + half * force_x[b] / body_mass[b]
                vel_y[b] = body_vy[b] + half * (force_y[b] / body_mass[b] - gravity)
                vel_om[b] = body_omega[b] + half * torque[b] / body_inertia[b]
        # powers at t_n; each covers [t_n - dt/2, t_n + dt/2] (the first step only its second half)
        p_damp, p_tan = contact_power(pair_a, pair_b, pair_memory, body_x, body_y, vel_x, vel_y, vel_om)
        p_base = 0.0
        for b in range(n_body):
            p_base += base_force_x[b] * vel_h + base_force_y[b] * vel_v

        if sample:
            out_step[n_sample] = n
            kinetic = 0.0
            potential = 0.0
            finite = True
            for b in range(n_body):
                out_x[n_sample, b] = body_x[b]
                out_y[n_sample, b] = body_y[b]
                out_theta[n_sample, b] = body_theta[b]
                if body_driven[b]:
                    continue
                vx = vel_x[b]
                vy = vel_y[b]
                om = vel_om[b]
                kinetic += 0.5 * body_mass[b] * (vx * vx + vy * vy)
                kinetic += 0.5 * body_inertia[b] * om * om
                potential += body_mass[b] * gravity * body_y[b]
                if not (np.isfinite(body_x[b]) and np.isfinite(body_y[b])
                        and np.isfinite(body_theta[b]) and np.isfinite(om)):
                    finite = False
            out_energy[n_sample, ENERGY_KINETIC] = kinetic
            out_energy[n_sample, ENERGY_POTENTIAL] = potential
            out_energy[n_sample, ENERGY_ELASTIC] = elastic
            # accumulated up to t_n: the running sums plus the first half of this step's power
            out_energy[n_sample, ENERGY_DAMPING] = energy_acc[E_DAMPING] + half * p_damp
            out_energy[n_sample, ENERGY_TANGENTIAL] = energy_acc[E_TANGENTIAL] + half * p_tan
            out_energy[n_sample, ENERGY_BASE_WORK] = energy_acc[E_BASE_WORK] + half * p_base
            out_n_contact[n_sample] = n_contact
            n_sample += 1
            if not finite:
                status = STATUS_NONFINITE
                break
            if n >= rest_from_step and at_rest(n_body, body_driven, body_radius, vel_x, vel_y,
                                               vel_om, vel_h, vel_v, rest_speed):
                rest_count[0] += 1
                if rest_count[0] >= rest_samples:
                    status = STATUS_AT_REST
                    break
            else:
                rest_count[0] = 0
            if collapse_sample < 0 and collapse_state(
                n_body, body_driven, body_group, n_group, group_theta_cr, body_theta,
                body_y, ref_y, fall_depth, d_v,
            ):
                collapse_sample = n_sample - 1
                if stop_on_collapse:
                    status = STATUS_COLLAPSED
                    break
        if n == n_steps:
            break
        # the first kick is a half step, so velocities sit at t + dt/2 from then on
        kick = 0.5 * dt if n == step_first else dt
        energy_acc[E_DAMPING] += kick * p_damp
        energy_acc[E_TANGENTIAL] += kick * p_tan
        energy_acc[E_BASE_WORK] += kick * p_base
        central_difference_step(n_body, body_driven, body_mass, body_inertia, gravity, kick, dt,
                                force_x, force_y, torque,
                                body_x, body_y, body_theta, body_vx, body_vy, body_omega)
    return status, n_sample, collapse_sample
