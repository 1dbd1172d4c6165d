"""Skipping the quiet lead and the at-rest tail of a run (stonedem.engine.quiet.quiet_steps): the
answer must not move beyond the stated bounds, and fewer steps are integrated."""

import math

import numpy as np
import pytest

from stonedem.engine.quiet import quiet_steps, quiet_threshold
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.engine.structures import standalone_column


def column_under(record_path, duration, skip, n_drums=1):
    # one heavily damped drum (c_n 0.5 x critical), so the rocking dies out within the run;
    # a lightly damped multi-drum column keeps rocking at ~1e-3 rad for many seconds
    return scene_from_dict(
        {
            "bodies": standalone_column(n_drums, height=3.0, width=0.6),
            "friction": 0.6,
            "contact": {"k_n": 1e9, "c_n": 1.2e6},
            "excitation": {"kind": "record", "file": str(record_path), "baseline": False},
            "solver": {"duration": duration, "stop_on_collapse": False, "skip_quiet": skip},
            "output": {"every": 0.01},
        }
    )


@pytest.fixture()
def quiet_loud_quiet(tmp_path):
    """1.5 s of silence, 1 s of a 2 Hz, 0.3 g sine, then silence to 6 s."""
    t = np.arange(0.0, 6.0 + 1e-9, 0.005)
    a = np.zeros_like(t)
    loud = (t >= 1.5) & (t < 2.5)
    a[loud] = 0.3 * 9.81 * np.sin(2 * np.pi * 2 * (t[loud] - 1.5))
    path = tmp_path / "quiet_loud_quiet.txt"
    np.savetxt(path, np.column_stack([t, a]), header="time [s], acceleration [m/s2]")
    return path


def test_threshold_is_half_the_smallest_of_friction_and_slenderness():
    spec = {
        "bodies": standalone_column(3, height=3.0, width=0.6),
        "friction": 0.6,
        "solver": {"duration": 1.0},
    }
    # narrowest free body 0.6 m over twice the 3 m height = 0.1 < mu = 0.6; halved
    assert quiet_threshold(scene_from_dict(spec)) == pytest.approx(0.05, rel=1e-12)


def test_quiet_lead_is_skipped_once_settled_and_the_answer_holds(quiet_loud_quiet):
    full = simulate(column_under(quiet_loud_quiet, 4.0, skip=False))
    fast = simulate(column_under(quiet_loud_quiet, 4.0, skip=True))
    assert np.array_equal(full.time, fast.time), "the same samples, filled where skipped"
    # settled within REST_SECONDS (0.5 s) of the start, carried to the sample before t = 1.5 s
    assert 0.8 <= fast.quiet_lead <= 1.0
    assert fast.steps_run < 0.8 * full.steps_run
    # error bound (measured 0.1 %: "at rest" still allows 1e-3 m/s of contact vibration):
    # peak rotation within 0.3 %, final rotation within 1e-4 rad, final sliding within 1e-4 m
    peak_full = np.abs(full.theta[:, 1]).max()
    assert peak_full > 1e-2, "the loud part rocks the drum"
    assert abs(np.abs(fast.theta[:, 1]).max() / peak_full - 1.0) < 3e-3
    assert np.abs(fast.theta[-1, 1] - full.theta[-1, 1]) < 1e-4
    assert np.abs((fast.x[-1, 1] - fast.x[-1, 0]) - (full.x[-1, 1] - full.x[-1, 0])) < 1e-4


def test_rest_tail_after_a_pulse_is_carried_and_the_sliding_holds():
    from stonedem.validation.cases import block_scene

    def run(skip):
        spec = block_scene(
            2.0,
            0.5,
            friction=0.2,
            k_n=1e8,
            c_n=0.5 * 2 * math.sqrt(1e8 * 2.0 * 2700.0),
            excitation={"kind": "rect_pulse", "accel": 0.5 * 9.81, "duration": 0.5},
            duration=4.0,
            every=0.01,
            base_width=20.0,
        )
        spec["solver"]["skip_quiet"] = skip
        return simulate(scene_from_dict(spec))

    full, fast = run(False), run(True)
    # the block stops sliding at T_p a_p / (mu g) = 1.25 s, then rests for REST_SECONDS
    assert 1.25 < fast.rest_time < 2.5
    assert fast.steps_run < 0.7 * full.steps_run
    slide_full = full.x[-1, 1] - full.x[-1, 0]
    slide_fast = fast.x[-1, 1] - fast.x[-1, 0]
    assert abs(slide_fast - slide_full) < 1e-5, "residual sliding (0.92 m) within 10 um"


def test_a_tilted_start_is_never_skipped():
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 4, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {
                "name": "block",
                "box": {"width": 0.25, "height": 1.0, "center": [0, 0.5]},
                "tilt": {"angle": 0.05, "about": "bottom_right"},
            },
        ],
        "friction": 10.0,
        "contact": {"k_n": 1e9, "c_n": 1e3},
        "solver": {"duration": 1.0},
        "output": {"every": 0.01},
    }
    scene = scene_from_dict(spec)
    assert quiet_steps(scene, 1e-4, 10000, 100)[0] == 0
    r = simulate(scene)
    assert math.isnan(r.rest_time), "a rocking block is not at rest at its peaks"


def test_peaks_count_a_carried_stretch_at_its_entry_state():
    """The compiled loop keeps the peaks at every step it integrates; a stretch carried at
    rest keeps every measure at its entry state, which the loop has counted."""
    from stonedem.engine.run import run_scene
    from stonedem.validation.cases import block_scene

    def run(skip):
        spec = block_scene(
            2.0,
            0.5,
            friction=0.2,
            k_n=1e8,
            c_n=0.5 * 2 * math.sqrt(1e8 * 2.0 * 2700.0),
            excitation={"kind": "rect_pulse", "accel": 0.5 * 9.81, "duration": 0.5},
            duration=4.0,
            every=0.01,
            base_width=20.0,
        )
        spec["solver"]["skip_quiet"] = skip
        return run_scene(scene_from_dict(spec))

    full, fast = run(False), run(True)
    assert 1.25 < fast.attrs["at_rest_from"] < 2.5
    # the block slides one way and stops: the peak is the residual, carried to the end, but
    # for the tangential spring's give as the friction force relaxes (mu m g / k_t = 53 um)
    for ds in (full, fast):
        peak = float(ds.max_total_sliding)
        assert peak >= float(ds.total_sliding.max()) * (1 - 1e-12)
        assert 0.0 <= peak - float(ds.residual_total_sliding) < 6e-5
    assert float(fast.max_total_sliding) == pytest.approx(float(full.max_total_sliding), abs=1e-5)


def test_a_body_released_in_the_air_is_not_carried_through_the_quiet_lead(quiet_loud_quiet):
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 4, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {"name": "block", "box": {"width": 0.6, "height": 1.0, "center": [0, 0.8]}},
        ],
        "excitation": {"kind": "record", "file": str(quiet_loud_quiet), "baseline": False},
        "solver": {"duration": 2.0},
        "output": {"every": 0.01},
    }
    scene = scene_from_dict(spec)
    assert quiet_steps(scene, 1e-4, 20000, 100)[0] == 0, "it falls first: nothing to skip"
    spec["bodies"][1]["box"]["center"] = [0, 0.5]
    assert quiet_steps(scene_from_dict(spec), 1e-4, 20000, 100)[0] > 0, (
        "standing on the base: skipped"
    )
