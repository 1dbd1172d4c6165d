"""Peaks and first times are kept at every step of the compiled loop, not read from the samples.

A peak must not depend on how often one asks to see the run: the same trajectory sampled
every 5 ms and every 0.25 s has the same max_rocking, max_total_sliding, epistyle peak,
per-body max |theta|, rocking onset and collapse time (stonedem.kernels.step.track).

The trajectory itself is the same when the step is: a given dt, or an automatic one, which
is rounded down to divide a fixed 1 ms clock (stonedem.engine.simulate.STEP_CLOCK) rather
than output.every. The quiet-skipping path detects rest at the samples
(stonedem.engine.quiet), so these scenes turn skip_quiet off and the comparison is exact;
with it on, the difference is what tests/engine/test_quiet.py bounds.
"""

import dataclasses

import numpy as np
import pytest

from stonedem.engine import measures
from stonedem.engine.run import run_scene
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import choose_time_step

# a 0.45 g, 2 Hz sine: the columns rock and slide and stand; 0.9 g at 1 Hz: they fall at 1.09 s
EXCITATIONS = {
    "stands": {"kind": "harmonic", "frequency": 2.0, "amplitude": 0.45 * 9.81 / (4 * np.pi) ** 2},
    "falls": {"kind": "harmonic", "frequency": 1.0, "amplitude": 0.9 * 9.81 / (2 * np.pi) ** 2},
}


def colonnade(excitation, every, dt=None, duration=2.0):
    """Two columns of two 1 m drums under an epistyle: every measure has something to measure."""
    spec = {
        "structure": {
            "kind": "colonnade",
            "n_columns": 2,
            "n_drums": 2,
            "height": 2.0,
            "width": 0.4,
            "clear_distance": 1.0,
        },
        "friction": 0.5,
        "excitation": excitation,
        "solver": {"duration": duration, "skip_quiet": False, "dt": "auto" if dt is None else dt},
        "output": {"every": every},
    }
    return scene_from_dict(spec)


def common_step(*everies):
    """A stable step of the scene that divides every output interval."""
    dt, _ = choose_time_step(colonnade(EXCITATIONS["stands"], min(everies)))
    finest = min(everies)
    return finest / np.ceil(finest / dt)


MEASURES = (
    "max_rocking",
    "max_total_sliding",
    "max_epistyle_displacement",
    "rocking_onset_time",
    "collapse_time",
)


@pytest.mark.parametrize("case", list(EXCITATIONS))
def test_peaks_do_not_depend_on_the_output_interval(case):
    dt = common_step(0.005, 0.25)
    fine = run_scene(colonnade(EXCITATIONS[case], 0.005, dt))
    coarse = run_scene(colonnade(EXCITATIONS[case], 0.25, dt))
    # first: it is the same trajectory, sample for sample where both sample
    shared = np.intersect1d(fine.time.values, coarse.time.values)
    assert len(shared) >= 3
    for name in ("x", "y", "theta"):
        assert np.array_equal(
            fine[name].sel(time=shared).values, coarse[name].sel(time=shared).values
        )
    assert int(fine.collapsed) == int(coarse.collapsed) == (case == "falls")
    # then: its peaks and first times are the same
    for name in MEASURES:
        a, b = float(fine[name]), float(coarse[name])
        assert a == pytest.approx(b, rel=1e-12, abs=0.0, nan_ok=True), name
    assert np.allclose(fine.max_abs_theta, coarse.max_abs_theta, rtol=1e-12, atol=0.0)
    assert float(fine.max_rocking) > 0.01 and float(fine.max_total_sliding) > 1e-4
    assert float(fine.max_epistyle_displacement) > 1e-4
    if case == "stands":
        # reading the peak off the coarse samples, as before, misses the peak between them
        assert float(coarse.rocking.max()) < 0.99 * float(coarse.max_rocking)
    else:
        # a collapse is found at its step, which is sampled and ends the run
        assert float(coarse.time[-1]) == pytest.approx(float(coarse.collapse_time), rel=1e-12)
        assert float(fine.time[-1]) == pytest.approx(float(fine.collapse_time), rel=1e-12)


def test_tracked_peaks_equal_the_sampled_ones_when_every_step_is_sampled():
    """The same definitions: sampling every step, the samples' maxima are the tracked peaks."""
    dt = common_step(0.005)
    scene = colonnade(EXCITATIONS["stands"], dt, dt, duration=0.6)
    ds = run_scene(scene)
    assert len(ds.time) == round(0.6 / dt) + 1
    epi = ds.displacement_relative_to_base.isel(body=measures.epistyle_bodies(scene)).mean("body")
    sampled = {
        "max_rocking": float(ds.rocking.max()),
        "max_total_sliding": float(ds.total_sliding.max()),
        "max_epistyle_displacement": float(np.abs(epi).max()),
        "rocking_onset_time": measures.rocking_onset_time(
            ds.time.values, ds.rocking.values, float(ds.theta_cr)
        ),
    }
    for name, value in sampled.items():
        assert float(ds[name]) == pytest.approx(value, rel=1e-12), name
    assert np.allclose(ds.max_abs_theta, np.abs(ds.theta).max("time"), rtol=1e-12, atol=0.0)
    assert float(ds.max_rocking) > 0.005 and float(ds.max_total_sliding) > 1e-5


def test_an_automatic_step_does_not_depend_on_the_output_interval():
    """dt: auto divides the 1 ms clock, not output.every: the same steps, the same peaks
    (before, 0.005 s and 0.25 s gave steps 0.08-1.6 % apart and max sliding 2.10 vs 2.51 mm
    in a rocking column)."""
    scene = colonnade(EXCITATIONS["stands"], 0.005)
    fine = run_scene(scene)
    coarse = run_scene(dataclasses.replace(scene, output_every=0.25))
    assert fine.attrs["dt"] == coarse.attrs["dt"]
    for name in MEASURES:
        assert float(fine[name]) == pytest.approx(
            float(coarse[name]), rel=1e-12, abs=0.0, nan_ok=True
        ), name
