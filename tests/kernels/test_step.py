"""The staged time loop (stonedem.kernels.step): its bundles, energy columns and stage functions."""

import numpy as np
import pytest

from stonedem.kernels import step
from stonedem.kernels.contact import E_BASE_WORK, E_DAMPING, E_TANGENTIAL, N_ENERGY_ACC, N_MEMORY
from stonedem.kernels.excitation import KIND_NONE
from stonedem.kernels.overlap import FRAME_BOUNDARY

G = 9.81


def test_accumulated_energy_columns_are_the_accumulator_slots():
    assert (step.ENERGY_DAMPING, step.ENERGY_TANGENTIAL, step.ENERGY_BASE_WORK) == tuple(
        step.ENERGY_ACCUMULATED + slot for slot in (E_DAMPING, E_TANGENTIAL, E_BASE_WORK)
    )
    columns = [
        step.ENERGY_KINETIC,
        step.ENERGY_POTENTIAL,
        step.ENERGY_ELASTIC,
        step.ENERGY_DAMPING,
        step.ENERGY_TANGENTIAL,
        step.ENERGY_BASE_WORK,
    ]
    assert sorted(columns) == list(range(step.N_ENERGY))
    assert step.N_ENERGY == step.ENERGY_ACCUMULATED + N_ENERGY_ACC


def box_bundles(n_steps, dt, v0=(1.0, 2.0, 0.5), out_every=10):
    """One free 1 x 1 m box of 1 kg in flight, nothing to touch: (model, settings, state,
    samples)."""
    still = step.Excitation(
        kind=KIND_NONE,
        params=np.zeros(4),
        table_accel=np.zeros(1),
        table_vel=np.zeros(1),
        table_disp=np.zeros(1),
        table_dt=1.0,
    )
    model = step.Model(
        vert_start=np.array([0, 4]),
        local_x=np.array([-0.5, 0.5, 0.5, -0.5]),
        local_y=np.array([-0.5, -0.5, 0.5, 0.5]),
        body_mass=np.ones(1),
        body_inertia=np.full(1, 1 / 6),
        body_driven=np.zeros(1, dtype=np.bool_),
        body_radius=np.full(1, np.sqrt(0.5)),
        ref_x=np.zeros(1),
        ref_y=np.zeros(1),
        ref_theta=np.zeros(1),
        pair_mu=np.full((1, 1), 0.5),
        body_group=np.zeros(1, dtype=np.int64),
        group_theta_cr=np.full(1, np.pi / 4),
        group_lean=np.zeros(1),
        fall_depth=np.full(1, 1e9),
        margin=0.1,
        sweep_axis=1,
        gravity=G,
        law=step.Law(
            kind=step.CONTACT_AREA,
            k_n=1e8,
            k_t=1e6,
            c_t=0.0,
            frame_rule=FRAME_BOUNDARY,
            params=np.array([0.0]),
        ),
        horizontal=still,
        vertical=still,
        watch=step.Watch(
            rocking=np.ones(1),
            n_rocking=1.0,
            onset_rocking=np.pi / 4 / 30,
            support=np.full(1, -1),
            slide_x=np.zeros(1),
            slide_y=np.zeros(1),
            slide_support_x=np.zeros(1),
            slide_support_y=np.zeros(1),
            slide_offset=np.zeros(1),
            epistyle=np.zeros(1),
            n_epistyle=0.0,
            x0=np.zeros(1),
        ),
        links=step.no_links(),
    )
    settings = step.Settings(
        dt=dt,
        n_steps=n_steps,
        out_every=out_every,
        stop_on_collapse=False,
        rest_speed=1e-3,
        rest_samples=1,
    )
    state = step.State(
        body_x=np.zeros(1),
        body_y=np.zeros(1),
        body_theta=np.zeros(1),
        body_vx=np.array([v0[0]]),
        body_vy=np.array([v0[1]]),
        body_omega=np.array([v0[2]]),
        pair_ft=np.zeros((1, 1)),
        pair_memory=np.zeros((1, 1, N_MEMORY)),
        energy_acc=np.zeros(N_ENERGY_ACC),
        rest_count=np.zeros(1, dtype=np.int64),
        peaks=np.zeros(step.N_PEAK),
        peak_theta=np.zeros(1),
        events=np.full(step.N_EVENT, -1, dtype=np.int64),
        link_slip=np.zeros(0),
        link_status=np.zeros(0, dtype=np.int64),
        link_peak=np.zeros(0),
        link_energy=np.zeros(0),
    )
    n_out = n_steps // out_every + 2
    samples = step.Samples(
        step=np.zeros(n_out, dtype=np.int64),
        x=np.zeros((n_out, 1)),
        y=np.zeros((n_out, 1)),
        theta=np.zeros((n_out, 1)),
        energy=np.zeros((n_out, step.N_ENERGY)),
        n_contact=np.zeros(n_out, dtype=np.int64),
    )
    return model, settings, state, samples


def test_run_flies_a_free_box_exactly_and_samples_every_out_every_steps():
    n_steps, dt = 1000, 1e-3
    model, settings, state, samples = box_bundles(n_steps, dt)
    status, n_sample, collapse_sample = step.run(
        model, settings, state, samples, 0, n_steps + 1, 0, n_steps + 1, 0, -1
    )
    assert (status, n_sample, collapse_sample) == (step.STATUS_OK, 101, -1)
    t = samples.step[:n_sample] * dt
    assert np.array_equal(samples.step[:n_sample], np.arange(0, n_steps + 1, 10))
    # leapfrog is exact under a constant force
    assert np.allclose(samples.x[:n_sample, 0], t, rtol=1e-12, atol=1e-12)
    assert np.allclose(samples.y[:n_sample, 0], 2.0 * t - 0.5 * G * t**2, rtol=1e-10, atol=1e-12)
    assert np.allclose(samples.theta[:n_sample, 0], 0.5 * t, rtol=1e-12, atol=1e-12)
    # kinetic + potential energy from the velocities at t_n is constant; nothing else moves
    e = samples.energy[:n_sample]
    total = e[:, step.ENERGY_KINETIC] + e[:, step.ENERGY_POTENTIAL]
    assert np.allclose(total, total[0], rtol=1e-12, atol=1e-9)
    assert not e[:, step.ENERGY_ELASTIC :].any() and not samples.n_contact[:n_sample].any()


def test_run_split_into_calls_equals_one_call():
    n_steps, dt = 1000, 1e-3
    whole = box_bundles(n_steps, dt)
    step.run(*whole, 0, n_steps + 1, 0, n_steps + 1, 0, -1)
    parts = box_bundles(n_steps, dt)
    n_sample, collapse_sample = 0, -1
    for start, stop in ((0, 333), (333, 700), (700, n_steps + 1)):
        _, n_sample, collapse_sample = step.run(
            *parts, start, stop, 0, n_steps + 1, n_sample, collapse_sample
        )
    for a, b in zip(whole[2] + whole[3], parts[2] + parts[3]):
        assert np.array_equal(a, b)


def test_run_stops_when_the_box_comes_to_rest_and_on_nan():
    model, settings, state, samples = box_bundles(100, 1e-3, v0=(0.0, 0.0, 0.0))
    # weightless and still: at rest at the first sample
    model = model._replace(gravity=0.0)
    assert step.run(model, settings, state, samples, 0, 101, 0, 0, 0, -1)[:2] == (
        step.STATUS_AT_REST,
        1,
    )
    model, settings, state, samples = box_bundles(100, 1e-3, v0=(0.0, 0.0, np.nan))
    assert step.run(model, settings, state, samples, 0, 101, 0, 101, 0, -1)[:2] == (
        step.STATUS_NONFINITE,
        1,
    )


def test_collapsed_by_mean_rotation_of_a_group_or_by_a_fall():
    model, _, state, _ = box_bundles(10, 1e-3)
    work = step.allocate_work(model, 16)
    state.body_theta[0] = 0.9 * np.pi / 4
    assert not step.collapsed(model, state, work, 0.0)
    state.body_theta[0] = -1.1 * np.pi / 4
    assert step.collapsed(model, state, work, 0.0)
    state.body_theta[0] = 0.0
    model = model._replace(fall_depth=np.full(1, 0.3))
    assert not step.collapsed(model, state, work, -0.25), "the base went down with the box"
    state.body_y[0] = -0.31
    assert step.collapsed(model, state, work, 0.0)


def test_resweep_once_moved_half_the_margin():
    model, _, state, _ = box_bundles(10, 1e-3)
    work = step.allocate_work(model, 16)
    step.sweep(model, state, work)
    state.body_x[0] = 0.02
    state.body_theta[0] = 0.02 / model.body_radius[0]
    assert not step.needs_resweep(model, state, work), "0.04 m of 0.05 m"
    state.body_y[0] = 0.011
    assert step.needs_resweep(model, state, work)


def test_power_booking_takes_the_base_work_from_the_driven_bodies_force():
    model, _, state, _ = box_bundles(10, 1e-3)
    work = step.allocate_work(model, 16)
    work.base_force_x[0], work.base_force_y[0] = 2.0, 3.0
    step.book_power(work, 5.0, 7.0, 0.5, -1.0)
    assert work.power[E_DAMPING] == 5.0 and work.power[E_TANGENTIAL] == 7.0
    assert work.power[E_BASE_WORK] == pytest.approx(2.0 * 0.5 - 3.0)
    step.book_energy(state, work, 0.1)
    assert state.energy_acc == pytest.approx([0.5, 0.7, -0.2])


def test_peaks_and_first_events_are_kept_at_every_step_not_at_the_samples():
    # the box spins at 0.5 rad/s: |theta| = 0.5 t, sampled every 10 steps of 1 ms
    n_steps, dt = 1000, 1e-3
    model, settings, state, samples = box_bundles(n_steps, dt)
    step.run(model, settings, state, samples, 0, 457, 0, n_steps + 1, 0, -1)
    # the peak is that of step 456, not of the sample at step 450
    assert state.peak_theta[0] == pytest.approx(0.5 * 0.456, rel=1e-12)
    assert state.peaks[step.PEAK_ROCKING] == pytest.approx(0.5 * 0.456, rel=1e-12)
    assert samples.theta[:46, 0].max() == pytest.approx(0.5 * 0.450, rel=1e-12)
    # onset at theta_cr / 30 = pi / 120: 0.5 t > 0.02618 first at step 53, between samples
    assert state.events[step.EVENT_ONSET] == 53
    assert state.events[step.EVENT_COLLAPSE] == -1, "0.23 rad < theta_cr = pi / 4"
    assert state.peaks[step.PEAK_SLIDING] == 0.0 and state.peaks[step.PEAK_EPISTYLE] == 0.0, (
        "nothing to measure"
    )


def test_a_collapse_between_samples_is_sampled_at_its_step_and_stops_the_run():
    n_steps, dt = 1000, 1e-3
    model, settings, state, samples = box_bundles(n_steps, dt)
    # theta_cr 0.0333 rad: 0.5 t passes it first at step 67
    model = model._replace(group_theta_cr=np.full(1, 0.0333))
    status, n_sample, collapse_sample = step.run(
        model,
        settings._replace(stop_on_collapse=True),
        state,
        samples,
        0,
        n_steps + 1,
        0,
        n_steps + 1,
        0,
        -1,
    )
    assert status == step.STATUS_COLLAPSED and state.events[step.EVENT_COLLAPSE] == 67
    assert collapse_sample == n_sample - 1 == 7 and samples.step[collapse_sample] == 67
    assert samples.theta[collapse_sample, 0] == pytest.approx(0.5 * 0.067, rel=1e-12)
    # not stopping: the collapse step is kept, and the first sample after it is flagged
    model2, settings2, state2, samples2 = box_bundles(n_steps, dt)
    status, n_sample, collapse_sample = step.run(
        model2._replace(group_theta_cr=np.full(1, 0.0333)),
        settings2,
        state2,
        samples2,
        0,
        n_steps + 1,
        0,
        n_steps + 1,
        0,
        -1,
    )
    assert status == step.STATUS_OK and n_sample == 101
    assert state2.events[step.EVENT_COLLAPSE] == 67 and samples2.step[collapse_sample] == 70


@pytest.mark.parametrize("lean, first", [(-0.01, 87), (0.01, 47), (0.0, 67)])
def test_a_leaning_group_collapses_sooner_toward_its_lean(lean, first):
    # the box turns counter-clockwise at 0.5 rad/s from its rest pose; its group's rest pose
    # is turned by ``lean`` from upright (structure.tilt): collapse once |theta + lean| passes
    # 0.0333 rad, at 0.0433 rad away from the lean (-0.01) and 0.0233 toward it (+0.01)
    n_steps, dt = 1000, 1e-3
    model, settings, state, samples = box_bundles(n_steps, dt)
    model = model._replace(group_theta_cr=np.full(1, 0.0333), group_lean=np.full(1, lean))
    status, _, _ = step.run(
        model,
        settings._replace(stop_on_collapse=True),
        state,
        samples,
        0,
        n_steps + 1,
        0,
        n_steps + 1,
        0,
        -1,
    )
    assert status == step.STATUS_COLLAPSED and state.events[step.EVENT_COLLAPSE] == first


def block_run_bundles(tilt, duration):
    """(arrays, model, settings, n_steps) of a 0.4 x 1.6 m block tilted by ``tilt`` [rad] on
    the ground under the point law, ``duration`` [s], a sample every 0.01 s, no stopping."""
    from stonedem.engine.pack import kernel_model, pack_scene
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import run_time_step
    from stonedem.validation.cases import block_scene

    scene = scene_from_dict(
        block_scene(
            0.4,
            1.6,
            contact={"model": "point", "k_n": 1e10},
            tilt=tilt,
            duration=duration,
            every=0.01,
        )
    )
    dt, _ = run_time_step(scene)
    arrays = pack_scene(scene)
    n_steps = int(np.ceil(scene.duration / dt - 1e-9))
    settings = step.Settings(
        dt=dt,
        n_steps=n_steps,
        out_every=max(1, round(0.01 / dt)),
        stop_on_collapse=False,
        rest_speed=1e-3,
        rest_samples=10**6,
    )
    return arrays, kernel_model(scene, arrays), settings, n_steps


def test_run_steps_goes_on_with_a_larger_bundle_when_the_pairs_do_not_fit():
    """run grows Work when the pairs outgrow it: run_steps stops before that step's forces, and
    going on from there with more room gives the same run, bit for bit."""
    from stonedem.engine.simulate import empty_samples, initial_state

    arrays, model, settings, n_steps = block_run_bundles(0.1, 0.3)
    runs = []
    for capacities in ((None,), (0, 1)):
        state, samples = initial_state(arrays), empty_samples(n_steps + 2, 2)
        if capacities == (None,):
            result = step.run(
                model, settings, state, samples, 0, n_steps + 1, 0, n_steps + 1, 0, -1
            )
        else:
            status, n_sample, collapse, n = step.run_steps(
                model,
                settings,
                state,
                samples,
                step.allocate_work(model, 1)._replace(pair_a=np.zeros(0, dtype=np.int64)),
                0,
                n_steps + 1,
                0,
                n_steps + 1,
                0,
                -1,
            )
            assert (status, n_sample, n) == (step.STATUS_PAIRS_FULL, 0, 0)
            result = step.run_steps(
                model,
                settings,
                state,
                samples,
                step.allocate_work(model, 1),
                n,
                n_steps + 1,
                0,
                n_steps + 1,
                n_sample,
                collapse,
            )[:3]
        runs.append((result, state, samples))
    (first, state_1, samples_1), (second, state_2, samples_2) = runs
    assert first == second and first[0] == step.STATUS_OK
    for a, b in zip(state_1 + samples_1, state_2 + samples_2):
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def test_the_kept_contact_faces_change_no_run_by_a_bit():
    """The point law keeps each touching pair's separating axes between steps
    (stonedem.kernels.point_contact.faces_hold): a block tipped past its critical angle,
    falling onto its side (its contact faces change, its pair is listed again), runs bit for
    bit as with no faces kept."""
    from stonedem.engine.simulate import empty_samples, initial_state
    from stonedem.kernels.point_contact import FACE_A, FACE_B, N_FACE_CACHE

    arrays, model, settings, n_steps = block_run_bundles(0.4, 1.2)
    runs = []
    for faces in (N_FACE_CACHE, 0):
        work = step.allocate_work(model, 4)
        if not faces:
            work = work._replace(face_cache=np.zeros((0, N_FACE_CACHE)))
        state, samples = initial_state(arrays), empty_samples(n_steps + 2, 2)
        result = step.run_steps(
            model, settings, state, samples, work, 0, n_steps + 1, 0, n_steps + 1, 0, -1
        )
        runs.append((result, state, samples, work))
    (kept, state_1, samples_1, work_1), (none, state_2, samples_2, _) = runs
    assert kept == none and kept[0] == step.STATUS_OK
    assert abs(state_1.body_theta[1]) > 1.4  # it lies on its side,
    assert not np.array_equal(
        work_1.sweep_y, initial_state(arrays).body_y
    )  # its pair was listed again
    assert work_1.face_cache[0, FACE_A] >= 0 and work_1.face_cache[0, FACE_B] in (
        1.0,
        3.0,
    )  # a side face kept
    for a, b in zip(state_1 + samples_1, state_2 + samples_2):
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
