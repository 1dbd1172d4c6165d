"""The compiled rigid rocking integrator (dem.kernels.rigid_rocking) against closed forms."""

import math

import numpy as np

from dem.analytic import rectangle_rocking_properties
from dem.kernels.rigid_rocking import rocking_history, uplift_instant

G = 9.81
W, H = 0.25, 1.0


def _run(t, a, r=0.85, substeps=8):
    blk = rectangle_rocking_properties(W, H, g=G)
    theta, omega, impacts = np.empty_like(t), np.empty_like(t), np.empty(1000)
    n, overturned = rocking_history(t, a, blk.alpha, blk.p**2, G, r, 1e-8, substeps, theta, omega, impacts)
    return blk, theta, omega, impacts[:n], overturned


def test_uplift_instant_on_a_line():
    onset = 1.0
    assert uplift_instant(0.0, 2.0, 0.0, 1.0, onset) == (0.5, -1), "a_g = 2s passes +1 at s = 0.5: left pivot"
    assert uplift_instant(0.0, -4.0, 0.0, 1.0, onset) == (0.25, 1), "a_g = -4s passes -1 at s = 0.25: right pivot"
    assert uplift_instant(0.5, 0.0, 0.0, 1.0, onset) == (1.0, 0), "|a_g| = 0.5 < 1 throughout: no uplift"
    assert uplift_instant(1.5, -1.0, 0.2, 1.0, onset) == (0.2, -1), "already above the onset at x: uplift at x"
    assert uplift_instant(1.5, -1.0, 0.6, 1.0, onset) == (1.0, 0), "left the band at s = 0.5, before x"


def test_constant_acceleration_follows_the_energy_integral_and_overturns():
    # a_g = -A held: theta'' = p^2 ((A/g) cos(alpha - theta) - sin(alpha - theta)), whose first
    # integral is 1/2 theta'^2 = p^2 (A/g (sin alpha - sin(alpha - theta)) + cos alpha - cos(alpha - theta))
    t = np.arange(0.0, 3.0, 0.01)
    blk0 = rectangle_rocking_properties(W, H, g=G)
    ratio = 1.2 * math.tan(blk0.alpha)
    blk, theta, omega, impacts, overturned = _run(t, np.full_like(t, -ratio * G))
    assert overturned and len(impacts) == 0, "a_g = -1.2 g tan(alpha) held: overturns without impact"
    ok = np.isfinite(theta)
    th, om, al = theta[ok], omega[ok], blk.alpha
    assert np.all(th >= 0.0), "a_g < 0 tips the block onto its right corner (theta > 0)"
    energy = 0.5 * om**2 - blk.p**2 * (ratio * (math.sin(al) - np.sin(al - th)) + math.cos(al) - np.cos(al - th))
    assert np.abs(energy).max() < 1e-10 * blk.p**2, f"first integral kept to 1e-10 p^2, worst {np.abs(energy).max()}"
    assert np.isnan(theta[-1]), "NaN after overturning"


def test_free_rocking_impact_keeps_r_of_the_energy():
    # a short pulse lifts the block, then free rocking: each impact multiplies theta' by sqrt(r)
    t = np.arange(0.0, 4.0, 0.005)
    blk0 = rectangle_rocking_properties(W, H, g=G)
    a = np.where(t < 0.1, -2.0 * G * math.tan(blk0.alpha), 0.0)
    blk, theta, omega, impacts, overturned = _run(t, a, r=0.7, substeps=16)
    assert not overturned and len(impacts) >= 3
    peaks = [np.abs(theta[(t > a0) & (t < a1)]).max() for a0, a1 in zip(impacts[:3], impacts[1:4])]
    # energy above rest at a crest, per m g R: cos(alpha - theta_max) - cos(alpha); r of it survives each impact
    crest = [math.cos(blk.alpha - p) - math.cos(blk.alpha) for p in peaks]
    for before, after in zip(crest[:-1], crest[1:]):
        assert abs(after / before - 0.7) < 0.002, f"crest energy ratio {after / before} vs r = 0.7, tol 0.002 (crests sampled every 5 ms)"
