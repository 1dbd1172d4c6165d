"""Interface return mapping alone (constitutive.return_map): admissibility, elastic trial,
continuity, idempotence and the closest-point property of the shear-torsion return."""

import numpy as np
import pytest

from stonedem.wall.constitutive import (
    ELASTIC,
    JointStrength,
    project_shear_torsion,
    return_map,
    smooth_plus,
)
from stonedem.wall.interface import torsion_constant
from stonedem.wall.panel import build_panel
from stonedem.wall.stiffness import local_stiffness, sections

RNG_SEED = 20160417


def setup(kind="dry", n_eps=0.0, blocks=3, courses=3):
    p = build_panel(0.081, 0.210, 0.070, blocks, courses)
    sec = sections(p)
    ni = p.n_interfaces
    k = local_stiffness(sec, 2.4e9, 1.0e9)
    sig_t = 0.0 if kind == "dry" else 2e4
    strength = JointStrength(
        np.full(ni, 0.7),
        np.full(ni, sig_t),
        np.full(ni, 0.7 * sig_t),
        np.full(ni, 1.43),
        n_eps=n_eps,
    )
    return sec, k, strength, ni


def random_d(rng, k, sec, n, scale=1.0):
    """Relative displacements around the scale of a 100 N normal force (compression mostly)."""
    ni = len(sec.area)
    u = 100.0 / k[:, 2]  # normal displacement of 100 N
    d = rng.normal(size=(n, ni, 6))
    d[..., 2] = -np.abs(d[..., 2]) * (rng.random((n, ni)) < 0.9) + d[..., 2] * 0.1
    d[..., :2] *= (0.7 * 100.0 / k[:, 0] * scale)[:, None]
    d[..., 2] *= u
    d[..., 3] *= 100.0 * sec.lever[:, 0] / k[:, 3] * scale
    d[..., 4] *= 100.0 * sec.lever[:, 1] / k[:, 4] * scale
    d[..., 5] *= 0.7 * 100.0 * torsion_constant(sec.width, sec.depth) / k[:, 5] * scale
    return d


def domain_value(f, sec, strength):
    """Eq. 9, 12-14 with the exact (unsmoothed) caps: returns the violations (<= 0 admissible)."""
    f_t = strength.tensile_strength * sec.area
    N = f[:, 2]
    reserve = np.maximum(f_t - N, 0.0)
    bend = np.abs(f[:, 3:5]) - reserve[:, None] * sec.lever
    f_su = np.maximum(strength.cohesion * sec.area - strength.mu * N, 0.0)
    e = np.where(
        reserve[:, None] > 0, np.abs(f[:, 3:5]) / np.where(reserve > 0, reserve, 1)[:, None], 0
    )
    no_t = f_t <= 0
    w = np.where(no_t, np.clip(sec.width - 2 * e[:, 1], 0, None), sec.width)
    s = np.where(no_t, np.clip(sec.depth - 2 * e[:, 0], 0, None), sec.depth)
    m3u = torsion_constant(w, s) * f_su
    r = np.hypot(f[:, 0], f[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.where(r > 0, (r / f_su) ** 2, 0) + np.where(
            np.abs(f[:, 5]) > 0, (np.abs(f[:, 5]) / m3u) ** strength.alpha, 0
        )
    return N - f_t, bend, g


@pytest.mark.parametrize("kind", ["dry", "mortar"])
def test_forces_inside_the_strength_domain(kind):
    rng = np.random.default_rng(RNG_SEED)
    sec, k, strength, ni = setup(kind)
    for d in random_d(rng, k, sec, 40, scale=3.0):
        rm = return_map(d, np.zeros((ni, 6)), np.zeros(ni, bool), k, sec, strength)
        tension, bend, g = domain_value(rm.forces, sec, strength)
        ref = np.abs(k[:, 2] * d[:, 2]).max()
        assert np.all(tension <= 1e-9 * ref), "normal force above the tensile cut-off"
        assert np.all(bend <= 1e-9 * ref), "bending beyond (f_t - f_n) l_c (Eq. 9)"
        assert np.all(g <= 1 + 1e-9), f"shear-torsion value {g.max():.6f} > 1 (Eq. 14)"
        assert (rm.state != ELASTIC).any()


def test_elastic_trial_inside_is_returned_unchanged():
    rng = np.random.default_rng(RNG_SEED + 1)
    sec, k, strength, ni = setup()
    for d in random_d(rng, k, sec, 20, scale=0.05):
        d[:, 2] = -np.abs(d[:, 2]) - 50.0 / k[:, 2]  # well compressed
        rm = return_map(d, np.zeros((ni, 6)), np.zeros(ni, bool), k, sec, strength)
        _, bend, g = domain_value(k * d, sec, strength)
        inside = (bend.max(axis=1) < 0) & (g < 1)
        assert inside.sum() > ni // 2
        np.testing.assert_array_equal(rm.forces[inside], (k * d)[inside], "elastic trial changed")
        assert np.all(rm.state[inside] == ELASTIC)
        assert np.all(rm.tangent[inside] == 1.0)


@pytest.mark.parametrize("n_eps", [0.0, 0.5])
def test_return_map_is_continuous(n_eps):
    """A tiny perturbation of the relative displacements gives a tiny change of the forces."""
    rng = np.random.default_rng(RNG_SEED + 2)
    sec, k, strength, ni = setup(n_eps=n_eps)
    zero_p, no_c = np.zeros((ni, 6)), np.zeros(ni, bool)
    worst = 0.0
    for d in random_d(rng, k, sec, 30, scale=3.0):
        f0 = return_map(d, zero_p, no_c, k, sec, strength).forces
        for _ in range(4):
            h = rng.normal(size=d.shape) * 1e-9 * np.abs(d).max(axis=0)
            f1 = return_map(d + h, zero_p, no_c, k, sec, strength).forces
            # bound: elastic response to the perturbation, times a generous factor
            worst = max(
                worst, np.max(np.abs(f1 - f0).sum(axis=1) / (np.abs(k * h).sum(axis=1) + 1e-300))
            )
    assert worst < 50, f"force change / elastic change of a 1e-9 perturbation: {worst:.3g}"


def test_rocking_joint_keeps_its_friction_under_a_tiny_twist():
    """Edge contact (bending at the cap): the compressed rectangle is a segment. A tiny relative
    twist must not wipe out the shear force (the former radial return did: m3u -> 0)."""
    sec, k, strength, ni = setup()
    d = np.zeros((ni, 6))
    d[:, 2] = -100.0 / k[:, 2]
    d[:, 3] = 10 * 100.0 * sec.lever[:, 0] / k[:, 3]  # rocking out of plane: at the cap
    d[:, 0] = 0.3 * 70.0 / k[:, 0]  # 30 % of the friction strength
    zero_p, no_c = np.zeros((ni, 6)), np.zeros(ni, bool)
    f0 = return_map(d, zero_p, no_c, k, sec, strength).forces
    d[:, 5] = 1e-12
    f1 = return_map(d, zero_p, no_c, k, sec, strength).forces
    np.testing.assert_allclose(
        f1[:, 0], f0[:, 0], rtol=1e-6, err_msg="shear lost under a tiny twist"
    )
    assert np.allclose(f0[:, 0], 0.3 * 70.0)


def test_continuous_through_detachment():
    sec, k, strength, ni = setup(n_eps=0.5)
    zero_p, no_c = np.zeros((ni, 6)), np.zeros(ni, bool)
    d = np.zeros((ni, 6))
    d[:, [0, 1]] = 1e-4
    d[:, 3] = 1e-4
    d[:, 5] = 1e-3
    prev = None
    for n in np.linspace(-2.0, 2.0, 401):
        d[:, 2] = n / k[:, 2]
        f = return_map(d, zero_p, no_c, k, sec, strength).forces
        if prev is not None:
            assert np.abs(f - prev).max() <= 0.02 * 1.0 + 1e-12, f"jump at N = {n:.3f} N"
        prev = f


def test_idempotent_and_path_independent_within_a_step():
    """Calling the map again at the same total displacement (any iterates in between) gives
    the same forces; feeding back the returned plastic part returns the same forces elastically."""
    rng = np.random.default_rng(RNG_SEED + 3)
    sec, k, strength, ni = setup("mortar")
    zero_p, no_c = np.zeros((ni, 6)), np.zeros(ni, bool)
    for d in random_d(rng, k, sec, 10, scale=3.0):
        rm = return_map(d, zero_p, no_c, k, sec, strength)
        for it in random_d(rng, k, sec, 3, scale=5.0):  # other iterates of the same step
            return_map(it, zero_p, no_c, k, sec, strength)
        again = return_map(d, zero_p, no_c, k, sec, strength)
        np.testing.assert_array_equal(again.forces, rm.forces)
        fed = return_map(d, rm.plastic, rm.cracked, k, sec, strength)
        np.testing.assert_allclose(
            fed.forces, rm.forces, rtol=1e-9, atol=1e-9 * np.abs(rm.forces).max()
        )


def test_shear_torsion_return_is_the_closest_point():
    rng = np.random.default_rng(RNG_SEED + 4)
    n = 200
    F = rng.uniform(10, 100, n)
    M = F * rng.uniform(0.0, 0.1, n)
    M[:10] = 0.0
    alpha = rng.uniform(1.0, 2.6, n)
    ks, km = rng.uniform(1e6, 1e8, n), rng.uniform(1e3, 1e6, n)
    r = F * rng.uniform(0, 3, n)
    s = M * rng.uniform(0, 3, n) + (M == 0) * rng.uniform(0, 1, n)
    x, y = project_shear_torsion(r, s, F, M, alpha, ks, km)
    with np.errstate(divide="ignore", invalid="ignore"):
        g = (x / F) ** 2 + np.where(M > 0, (y / np.where(M > 0, M, 1)) ** alpha, 0)
    assert np.all(g <= 1 + 1e-9)
    dist = (x - r) ** 2 / ks + (y - s) ** 2 / km
    t = np.linspace(0, 1, 20001)
    for i in range(n):
        bx = F[i] * t
        by = M[i] * np.clip(1 - t**2, 0, 1) ** (1 / alpha[i])
        best = ((bx - r[i]) ** 2 / ks[i] + (by - s[i]) ** 2 / km[i]).min()
        inside = (r[i] / F[i]) ** 2 + (s[i] / M[i] if M[i] > 0 else np.inf * s[i]) ** alpha[i] <= 1
        if not inside:
            assert dist[i] <= best * (1 + 1e-6) + 1e-18, f"case {i}: not the closest point"


def test_smooth_plus():
    x = np.array([-1.0, 0.0, 0.25, 0.5, 2.0])
    np.testing.assert_allclose(smooth_plus(x, 0.5), [0, 0, 0.0625, 0.25, 1.75])
    np.testing.assert_allclose(smooth_plus(x, 0.0), [0, 0, 0.25, 0.5, 2.0])
