"""MuJoCo engine on the canonical scenes against the exact references (dem.analytic)."""

import math

import numpy as np
import pytest

from dem import analytic
from dem.bench import mujoco_engine as me
from dem.bench.canonical import (COLUMN_FRICTION, COLUMN_HEIGHT, COLUMN_WIDTH, G, PULSE_ACCEL,
                                 PULSE_BLOCK, PULSE_DURATION, PULSE_FRICTION, ROCKING_RATIO)

WIDTH, HEIGHT = 0.25, 1.0
THETA0 = ROCKING_RATIO * math.atan(WIDTH / HEIGHT)


def zero_crossings(t, y):
    """Instants where y changes sign, by linear interpolation between samples."""
    i = np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i]), i


@pytest.fixture(scope="module")
def rocking():
    period = float(analytic.rocking_period_exact(WIDTH, HEIGHT, THETA0))
    # a full undamped period covers the quarter before the first impact and the (shorter)
    # half cycle after it
    return period, me.free_rocking(WIDTH, HEIGHT, THETA0, dt=1e-3, duration=period)


def test_free_rocking_shape_and_start(rocking):
    _, tr = rocking
    assert tr.theta.shape == tr.x.shape == (len(tr.time), 1)
    assert tr.time[0] == 0.0 and tr.theta[0, 0] == pytest.approx(-THETA0, abs=1e-15)
    assert tr.steps == round(tr.time[-1] / 1e-3) and tr.wall_seconds > 0.0


def test_free_rocking_first_impact_time(rocking):
    # reference: a quarter of the exact rigid period; tolerance 1 % (measured -0.11 %)
    period, tr = rocking
    t_zero, _ = zero_crossings(tr.time, tr.theta[:, 0])
    assert t_zero[0] == pytest.approx(period / 4.0, rel=0.01)


def test_free_rocking_first_peak(rocking):
    # reference: Eq. 5.3 with Housner's r, one impact; tolerance 3 % (measured +0.09 %)
    _, tr = rocking
    r = analytic.housner_restitution(WIDTH, HEIGHT)
    expected = analytic.rocking_peak_angles_eq53(WIDTH, HEIGHT, THETA0, r, 1)[1]
    _, idx = zero_crossings(tr.time, tr.theta[:, 0])
    after = tr.theta[idx[0] + 1: (idx[1] + 1 if len(idx) > 1 else None), 0]
    assert np.max(np.abs(after)) == pytest.approx(expected, rel=0.03)


def test_pulse_sliding_newmark():
    # reference: Newmark's u_max (Eq. 5.5); tolerance 1 % (measured +0.015 %)
    width, height = PULSE_BLOCK
    duration = PULSE_DURATION * PULSE_ACCEL / (PULSE_FRICTION * G) + 0.3
    tr = me.pulse_sliding(width, height, PULSE_FRICTION, PULSE_ACCEL, PULSE_DURATION,
                          dt=1e-3, duration=duration)
    u_max = analytic.newmark_pulse_max_sliding(PULSE_ACCEL, PULSE_DURATION, PULSE_FRICTION)
    assert np.max(np.abs(tr.x)) == pytest.approx(u_max, rel=0.01)
    assert tr.x[-1, 0] < 0.0  # a positive base acceleration leaves the block behind
    assert np.max(np.abs(tr.theta)) < 1e-4  # a squat block slides without rocking


def sine_record(amplitude, seconds=2.0, freq=2.0, spacing=0.01):
    t = np.arange(0.0, seconds + 0.5 * spacing, spacing)
    return t, amplitude * np.sin(2.0 * math.pi * freq * t)


def test_column_record_finite_shape():
    t, a = sine_record(0.3 * G)
    tr = me.column_record(8, COLUMN_WIDTH, COLUMN_HEIGHT, COLUMN_FRICTION, t, a, dt=1e-3,
                          duration=2.0, sample_every=0.01)
    assert tr.theta.shape == tr.x.shape == (201, 8) and tr.time.shape == (201,)
    assert np.all(np.isfinite(tr.theta)) and np.all(np.isfinite(tr.x))
    assert tr.steps == 2000


def test_column_tiny_record_stays_at_rest():
    # 0.01 g is far below the uplift threshold g tan(alpha) of any drum; reference 0 rad,
    # tolerance 1e-4 rad
    t, a = sine_record(0.01 * G)
    tr = me.column_record(8, COLUMN_WIDTH, COLUMN_HEIGHT, COLUMN_FRICTION, t, a, dt=1e-3,
                          duration=2.0, sample_every=0.01)
    assert np.max(np.abs(tr.theta)) < 1e-4
