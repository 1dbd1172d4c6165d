"""The compiled Bouc-Wen sliding block (stonedem.reference.bouc_wen) against closed forms."""

import math

import numpy as np
import pytest

from stonedem.reference.bouc_wen import bouc_wen_history, bouc_wen_rate, implicit_step

G, MU, U_Y = 9.81, 0.3, 1e-6


def test_rate_derivatives_match_finite_differences():
    for v, z in ((0.3, 0.2), (-0.4, 0.97), (0.05, -0.999), (-0.2, -0.5)):
        rate, d_v, d_z = bouc_wen_rate(v, z, U_Y, 0.5, 0.5, 50.0)
        h = 1e-7
        fd_v = (
            bouc_wen_rate(v + h, z, U_Y, 0.5, 0.5, 50.0)[0]
            - bouc_wen_rate(v - h, z, U_Y, 0.5, 0.5, 50.0)[0]
        ) / (2 * h)
        fd_z = (
            bouc_wen_rate(v, z + h, U_Y, 0.5, 0.5, 50.0)[0]
            - bouc_wen_rate(v, z - h, U_Y, 0.5, 0.5, 50.0)[0]
        ) / (2 * h)
        assert d_v == pytest.approx(fd_v, rel=1e-6), (v, z)
        assert d_z == pytest.approx(fd_z, rel=1e-5, abs=1e-3 * abs(rate) + 1.0), (v, z)
    # thesis Eq. 5.7 with gamma = beta = 1/2: z' = u'/u_y while unloading (u' z < 0)
    assert bouc_wen_rate(-0.1, 0.9, U_Y, 0.5, 0.5, 50.0)[0] == pytest.approx(-0.1 / U_Y, rel=1e-12)


def test_implicit_step_solves_its_equations():
    weight, a_new = 1e-5, 0.5 * MU * G
    v, z, ok = implicit_step(0.1, 0.95, weight, a_new, 0.1, 0.95, MU * G, U_Y, 0.5, 0.5, 50.0)
    assert ok
    rate = bouc_wen_rate(v, z, U_Y, 0.5, 0.5, 50.0)[0]
    assert abs(v - 0.1 + weight * (a_new + MU * G * z)) < 1e-12
    assert abs(z - 0.95 - weight * rate) < 1e-12
    assert 0.95 < z <= 1.0 + 1e-9, "loading towards saturation, not past it"


def _run(t, a, substeps):
    u, v = np.empty_like(t), np.empty_like(t)
    failures = bouc_wen_history(t, a, MU, G, U_Y, 0.5, 0.5, 50.0, substeps, u, v)
    return failures, u, v


def test_stick_phase_is_the_linear_oscillator():
    # a_g = 0.1 mu g held: |z| <= 0.2, |z|^50 < 1e-34, so u_y z'' = -a_g - mu g z exactly:
    # z = -0.1 (1 - cos(w t)), u = u_y z, w = sqrt(mu g / u_y)
    w = math.sqrt(MU * G / U_Y)
    t = np.linspace(0.0, 4.0 * 2.0 * math.pi / w, 41)
    failures, u, _v = _run(t, np.full_like(t, 0.1 * MU * G), 50)  # 500 steps per period
    exact = -0.1 * U_Y * (1.0 - np.cos(w * t))
    assert failures == 0
    assert np.abs(u - exact).max() < 0.02 * 0.2 * U_Y, (
        f"worst {np.abs(u - exact).max()} m, tol 2 % of 0.2 u_y"
    )


def test_sliding_under_constant_acceleration_is_rigid_plastic():
    # a_g = 2 mu g held: z reaches -1 within t* = sqrt(2 u_y / a_g) (z' = u'/u_y, u' = -a_g t), and
    # from then on u'' = -a_g + mu g exactly; during t* the block gains at most mu g t* extra speed
    a_g = 2.0 * MU * G
    t = np.linspace(0.0, 0.1, 11)
    failures, u, v = _run(t, np.full_like(t, a_g), 200)
    assert failures == 0
    slope = np.diff(v[1:]) / np.diff(t[1:])
    assert np.abs(slope / (-MU * G) - 1.0).max() < 1e-9, f"u'' = -mu g once sliding: {slope}"
    t_star = math.sqrt(2.0 * U_Y / a_g)
    offset = v[1:] + MU * G * t[1:]
    assert np.all(offset < 0.0) and np.all(-offset < MU * G * t_star), (
        f"extra speed {offset} m/s within mu g t* = {MU * G * t_star:.2e}"
    )
