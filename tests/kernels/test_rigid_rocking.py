"""The compiled rigid rocking integrators (stonedem.reference.rigid_rocking) against closed forms
and each other."""

import math

import numpy as np
import pytest

from stonedem.reference.analytic import rectangle_rocking_properties
from stonedem.reference.rigid_rocking import (
    PULSE_AT_REST,
    PULSE_ENDED,
    one_sine_pulse,
    rocking_history,
    sine_uplift_instant,
    uplift_instant,
)

G = 9.81
W, H = 0.25, 1.0


def _run(t, a, r=0.85, substeps=8):
    blk = rectangle_rocking_properties(W, H, g=G)
    theta, omega, impacts = np.empty_like(t), np.empty_like(t), np.empty(1000)
    n, overturned = rocking_history(
        t, a, blk.alpha, blk.p**2, G, r, 1e-8, substeps, theta, omega, impacts
    )
    return blk, theta, omega, impacts[:n], overturned


def test_uplift_instant_on_a_line():
    onset = 1.0
    assert uplift_instant(0.0, 2.0, 0.0, 1.0, onset) == (0.5, -1), (
        "a_g = 2s passes +1 at s = 0.5: left pivot"
    )
    assert uplift_instant(0.0, -4.0, 0.0, 1.0, onset) == (0.25, 1), (
        "a_g = -4s passes -1 at s = 0.25: right pivot"
    )
    assert uplift_instant(0.5, 0.0, 0.0, 1.0, onset) == (1.0, 0), (
        "|a_g| = 0.5 < 1 throughout: no uplift"
    )
    assert uplift_instant(1.5, -1.0, 0.2, 1.0, onset) == (0.2, -1), (
        "already above the onset at x: uplift at x"
    )
    assert uplift_instant(1.5, -1.0, 0.6, 1.0, onset) == (1.0, 0), (
        "left the band at s = 0.5, before x"
    )


def test_constant_acceleration_follows_the_energy_integral_and_overturns():
    # a_g = -A held: theta'' = p^2 ((A/g) cos(alpha - theta) - sin(alpha - theta)), whose first
    # integral is 1/2 theta'^2 = p^2 (A/g (sin alpha - sin(alpha - theta)) + cos alpha - cos(alpha -
    # theta))
    t = np.arange(0.0, 3.0, 0.01)
    blk0 = rectangle_rocking_properties(W, H, g=G)
    ratio = 1.2 * math.tan(blk0.alpha)
    blk, theta, omega, impacts, overturned = _run(t, np.full_like(t, -ratio * G))
    assert overturned and len(impacts) == 0, (
        "a_g = -1.2 g tan(alpha) held: overturns without impact"
    )
    ok = np.isfinite(theta)
    th, om, al = theta[ok], omega[ok], blk.alpha
    assert np.all(th >= 0.0), "a_g < 0 tips the block onto its right corner (theta > 0)"
    energy = 0.5 * om**2 - blk.p**2 * (
        ratio * (math.sin(al) - np.sin(al - th)) + math.cos(al) - np.cos(al - th)
    )
    assert np.abs(energy).max() < 1e-10 * blk.p**2, (
        f"first integral kept to 1e-10 p^2, worst {np.abs(energy).max()}"
    )
    assert np.isnan(theta[-1]), "NaN after overturning"


def test_free_rocking_impact_keeps_r_of_the_energy():
    # a short pulse lifts the block, then free rocking: each impact multiplies theta' by sqrt(r)
    t = np.arange(0.0, 4.0, 0.005)
    blk0 = rectangle_rocking_properties(W, H, g=G)
    a = np.where(t < 0.1, -2.0 * G * math.tan(blk0.alpha), 0.0)
    blk, theta, omega, impacts, overturned = _run(t, a, r=0.7, substeps=16)
    assert not overturned and len(impacts) >= 3
    peaks = [np.abs(theta[(t > a0) & (t < a1)]).max() for a0, a1 in zip(impacts[:3], impacts[1:4])]
    # energy above rest at a crest, per m g R: cos(alpha - theta_max) - cos(alpha); r of it survives
    # each impact
    crest = [math.cos(blk.alpha - p) - math.cos(blk.alpha) for p in peaks]
    for before, after in zip(crest[:-1], crest[1:]):
        assert abs(after / before - 0.7) < 0.002, (
            f"crest energy ratio {after / before} vs r = 0.7, tol 0.002 (crests sampled every 5 ms)"
        )


def _approx(x):
    return pytest.approx(x, rel=1e-12, abs=1e-15)


def test_sine_uplift_instant_windows():
    # |a_p sin(w t)| > onset inside (phi1, pi - phi1) and (pi + phi1, 2 pi - phi1), phi1 = asin(1/2)
    w, period = 2.0 * math.pi, 1.0
    phi1 = math.asin(0.5)
    t, side = sine_uplift_instant(0.0, 2.0, w, 1.0, period)
    assert t == _approx(phi1 / w) and side == -1, "a_g > 0 first: tips onto the left pivot"
    t, side = sine_uplift_instant(0.0, -2.0, w, 1.0, period)
    assert t == _approx(phi1 / w) and side == 1, "a_g < 0 first: the right pivot"
    t, side = sine_uplift_instant(0.3, 2.0, w, 1.0, period)
    assert t == 0.3 and side == -1, "inside the first window: at once"
    t, side = sine_uplift_instant(0.45, 2.0, w, 1.0, period)
    assert t == _approx((math.pi + phi1) / w) and side == 1, "between windows: the second, a_g < 0"
    assert sine_uplift_instant(0.95, 2.0, w, 1.0, period) == (period, 0), "past both windows: none"


def test_one_sine_pulse_agrees_with_the_record_integrator_on_the_sampled_pulse():
    # the same pulse sampled every T/4000 (a_g linear between samples: relative error ~3e-7)
    # through rocking_history: theta and theta' at the end of the pulse, and the impacts
    blk = rectangle_rocking_properties(W, H, g=G)
    onset = G * math.tan(blk.alpha)
    for amp, ratio, r in ((1.5, 2.0, 0.85), (1.2, 3.0, 0.7), (3.0, 5.0, 0.9)):
        omega_p = ratio * blk.p
        period = 2.0 * math.pi / omega_p
        how, th, om, side, n_imp, peak = one_sine_pulse(
            amp * onset, omega_p, blk.alpha, blk.p**2, G, r, 1e-8, 400
        )
        t = np.linspace(0.0, period, 4001)
        a = amp * onset * np.sin(omega_p * t)
        a[-1] = 0.0
        _, theta, omega, impacts, overturned = _run(t, a, r=r, substeps=1)
        assert how == PULSE_ENDED and not overturned
        assert n_imp == len(impacts), f"impacts {n_imp} vs {len(impacts)}"
        assert (
            abs(th - theta[-1]) < 1e-5 * blk.alpha
            and abs(om - omega[-1]) < 1e-5 * blk.p * blk.alpha
        ), (
            f"end of pulse: theta {th} vs {theta[-1]}, theta' {om} vs {omega[-1]}; tol 1e-5 "
            "alpha (p alpha)"
        )
        assert peak >= np.abs(theta).max() - 1e-5 * blk.alpha, (
            "the peak is at least the sampled one"
        )
        assert peak <= np.abs(theta).max() + 1e-3 * blk.alpha, (
            "and no more than between two samples"
        )


def test_one_sine_pulse_just_above_the_onset_comes_to_rest():
    blk = rectangle_rocking_properties(W, H, g=G)
    onset = G * math.tan(blk.alpha)
    # just above the onset: lifts for a sliver of each half of the pulse, falls back, settles
    how, th, om, side, n_imp, peak = one_sine_pulse(
        1.000001 * onset, 50.0 * blk.p, blk.alpha, blk.p**2, G, 0.8, 1e-6 * blk.p, 400
    )
    assert how == PULSE_AT_REST and (th, om, side) == (0.0, 0.0, 0), (how, th, om, side)
    assert peak < 1e-12 * blk.alpha, f"peak {peak} rad: barely off the ground"
