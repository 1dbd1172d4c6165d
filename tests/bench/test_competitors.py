"""The competing engines (pymunk, MuJoCo) on the canonical scenes against the exact references.

One set of checks for both adapters, so the work-precision benchmark compares engines that
pass the same tests. Measured at dt = 1 ms (pymunk / MuJoCo): first impact +0.15 % / -0.11 %,
peak after it -0.23 % / +0.09 %, pulse u_max -0.0000 % / +0.015 %, resting column under
0.01 g 3.8e-5 / < 1e-6 rad.
"""

import math

import numpy as np
import pytest

from benchmarks import canonical as cn
from stonedem.reference import analytic
from stonedem.validation.cases import zero_crossings

WIDTH, HEIGHT = 0.25, 1.0
THETA0 = cn.ROCKING_RATIO * math.atan(WIDTH / HEIGHT)
DT = 1e-3


@pytest.fixture(scope="module", params=["pymunk", "mujoco"])
def engine(request):
    from benchmarks.work_precision import competitor

    pytest.importorskip(request.param)
    return competitor(request.param)


@pytest.fixture(scope="module")
def rocking(engine):
    period = float(analytic.rocking_period_exact(WIDTH, HEIGHT, THETA0))
    # a full undamped period covers the quarter before the first impact and the (shorter)
    # half cycle after it
    return period, engine.free_rocking(WIDTH, HEIGHT, THETA0, dt=DT, duration=period)


def test_free_rocking_shape_and_start(rocking):
    _, tr = rocking
    assert tr.theta.shape == tr.x.shape == (len(tr.time), 1)
    assert tr.time[0] == 0.0 and tr.theta[0, 0] == pytest.approx(
        -THETA0, abs=1e-15
    )  # clockwise release
    assert tr.steps == round(tr.time[-1] / DT) and tr.wall_seconds > 0.0


def test_free_rocking_first_impact_time(rocking):
    # reference: a quarter of the exact rigid period; tolerance 1 %
    period, tr = rocking
    assert zero_crossings(tr.time, tr.theta[:, 0])[0] == pytest.approx(period / 4.0, rel=0.01)


def test_free_rocking_peak_after_first_impact_matches_housner(rocking):
    # reference: Eq. 5.3 with Housner's r, one impact; tolerance 3 %
    _, tr = rocking
    r = analytic.housner_restitution(WIDTH, HEIGHT)
    expected = analytic.rocking_peak_angles_eq53(WIDTH, HEIGHT, THETA0, r, 1)[1]
    crossings = zero_crossings(tr.time, tr.theta[:, 0])
    # the half cycle between the first and second impacts (or the end of the run)
    end = crossings[1] if len(crossings) > 1 else np.inf
    peak = np.abs(tr.theta[(tr.time > crossings[0]) & (tr.time < end), 0]).max()
    assert peak == pytest.approx(expected, rel=0.03)


def test_pulse_sliding_matches_newmark(engine):
    # reference: Newmark's u_max (Eq. 5.5); tolerance 1 %
    width, height = cn.PULSE_BLOCK
    duration = cn.pulse_run_duration()
    tr = engine.pulse_sliding(
        width,
        height,
        cn.PULSE_FRICTION,
        cn.PULSE_ACCEL,
        cn.PULSE_DURATION,
        dt=DT,
        duration=duration,
    )
    assert np.max(np.abs(tr.x)) == pytest.approx(cn.pulse_reference(), rel=0.01)
    assert tr.steps == round(duration / DT)
    assert tr.x[-1, 0] < 0.0  # a positive base acceleration leaves the block behind
    assert np.max(np.abs(tr.theta)) < 1e-4  # a squat block slides without rocking


def sine_record(amplitude, seconds=2.0, freq=2.0, spacing=0.01):
    t = np.arange(0.0, seconds + 0.5 * spacing, spacing)
    return t, amplitude * np.sin(2.0 * math.pi * freq * t)


def column(engine, amplitude):
    t, a = sine_record(amplitude)
    return engine.column_record(
        8,
        cn.COLUMN_WIDTH,
        cn.COLUMN_HEIGHT,
        cn.COLUMN_FRICTION,
        t,
        a,
        dt=DT,
        duration=2.0,
        sample_every=0.01,
    )


def test_column_record_shapes_and_finite(engine):
    tr = column(engine, 0.3 * cn.G)
    assert tr.theta.shape == tr.x.shape == (201, 8) and tr.time.shape == (201,)
    assert np.all(np.isfinite(tr.theta)) and np.all(np.isfinite(tr.x))
    assert tr.steps == 2000 and tr.wall_seconds > 0.0


def test_column_tiny_record_stays_at_rest(engine):
    # 0.01 g is far below the uplift threshold g tan(alpha) of any drum: the stack starts
    # without a jolt and stays (nearly) rigid; reference 0 rad, tolerance 1e-4 rad
    assert np.max(np.abs(column(engine, 0.01 * cn.G).theta)) < 1e-4
