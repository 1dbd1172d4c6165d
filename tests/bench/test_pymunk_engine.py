"""The pymunk (Chipmunk2D) engine against the exact references of the canonical scenes."""

import math

import numpy as np
import pytest

pytest.importorskip("pymunk")

from dem import analytic
from dem.bench import pymunk_engine as pe
from dem.bench.canonical import (G, PULSE_ACCEL, PULSE_BLOCK, PULSE_DURATION, PULSE_FRICTION,
                                 ROCKING_RATIO)

WIDTH, HEIGHT = 0.25, 1.0


def _zero_crossings(t, theta):
    """Times where theta changes sign, by linear interpolation between samples."""
    i = np.nonzero(np.sign(theta[:-1]) * np.sign(theta[1:]) < 0)[0]
    return t[i] + (t[i + 1] - t[i]) * theta[i] / (theta[i] - theta[i + 1])


@pytest.fixture(scope="module")
def rocking():
    theta0 = ROCKING_RATIO * math.atan(WIDTH / HEIGHT)
    period = analytic.rocking_period_exact(WIDTH, HEIGHT, theta0)
    tr = pe.free_rocking(WIDTH, HEIGHT, theta0, dt=1e-3, duration=0.75 * period)
    return theta0, period, tr


def test_free_rocking_first_impact_time(rocking):
    theta0, period, tr = rocking
    assert tr.theta.shape == (len(tr.time), 1) and tr.time[0] == 0.0
    assert tr.theta[0, 0] == pytest.approx(-theta0)  # clockwise release
    t1 = _zero_crossings(tr.time, tr.theta[:, 0])[0]
    assert t1 == pytest.approx(period / 4, rel=0.01)


def test_free_rocking_peak_after_first_impact_matches_housner(rocking):
    theta0, _, tr = rocking
    crossings = _zero_crossings(tr.time, tr.theta[:, 0])
    r = analytic.housner_restitution(WIDTH, HEIGHT)
    reference = analytic.rocking_peak_angles_eq53(WIDTH, HEIGHT, theta0, r, 1)[1]
    # the half cycle between the first and second impacts (or the end of the run)
    end = crossings[1] if len(crossings) > 1 else np.inf
    peak = np.abs(tr.theta[(tr.time > crossings[0]) & (tr.time < end), 0]).max()
    assert peak == pytest.approx(reference, rel=0.03)


def test_pulse_sliding_matches_newmark():
    width, height = PULSE_BLOCK
    duration = PULSE_DURATION * PULSE_ACCEL / (PULSE_FRICTION * G) + 0.3
    tr = pe.pulse_sliding(width, height, PULSE_FRICTION, PULSE_ACCEL, PULSE_DURATION,
                          dt=1e-3, duration=duration)
    reference = analytic.newmark_pulse_max_sliding(PULSE_ACCEL, PULSE_DURATION, PULSE_FRICTION)
    assert np.abs(tr.x).max() == pytest.approx(reference, rel=0.01)
    assert tr.steps == round(duration / 1e-3)


def _sine_record(amplitude):
    t = np.linspace(0.0, 2.0, 2001)
    return t, amplitude * np.sin(2.0 * math.pi * 2.0 * t)


def test_column_record_shapes_and_finite():
    t, a = _sine_record(0.3 * G)
    tr = pe.column_record(8, 1.0, 6.0, 0.5, t, a, dt=1e-3, duration=2.0)
    assert tr.theta.shape == tr.x.shape == (len(tr.time), 8) == (2001, 8)
    assert np.isfinite(tr.theta).all() and np.isfinite(tr.x).all()
    assert tr.steps == 2000 and tr.wall_seconds > 0.0


def test_column_starts_without_jolt():
    # 0.01 g is far below every rocking threshold: the stack must stay (nearly) rigid
    t, a = _sine_record(0.01 * G)
    tr = pe.column_record(8, 1.0, 6.0, 0.5, t, a, dt=1e-3, duration=2.0)
    assert np.abs(tr.theta).max() < 1e-4
