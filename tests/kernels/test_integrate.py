"""Central-difference integration: free flight is exact, a spring oscillator is second order."""

import numpy as np
import pytest

from stonedem.kernels.integrate import central_difference_step


def fly(n_steps, dt, v0=(1.0, 2.0, 0.5), g=9.81):
    x, y, th = np.zeros(1), np.zeros(1), np.zeros(1)
    vx, vy, om = np.array([v0[0]]), np.array([v0[1]]), np.array([v0[2]])
    zero = np.zeros(1)
    for n in range(n_steps):
        kick = 0.5 * dt if n == 0 else dt
        central_difference_step(
            1,
            np.array([False]),
            np.ones(1),
            np.ones(1),
            g,
            kick,
            dt,
            zero,
            zero,
            zero,
            x,
            y,
            th,
            vx,
            vy,
            om,
        )
    return x[0], y[0], th[0]


def test_free_flight_is_exact():
    t = 1.0
    x, y, th = fly(1000, t / 1000)
    assert x == pytest.approx(1.0, rel=1e-12)
    assert y == pytest.approx(2.0 * t - 0.5 * 9.81 * t**2, rel=1e-10), (
        "leapfrog is exact for constant force"
    )
    assert th == pytest.approx(0.5, rel=1e-12)


def test_harmonic_oscillator_second_order():
    k, m = 100.0, 1.0
    omega = np.sqrt(k / m)
    errors = []
    for dt in (1e-3, 5e-4):
        x, v = np.array([1.0]), np.array([0.0])
        y, th, vy, om = np.zeros(1), np.zeros(1), np.zeros(1), np.zeros(1)
        n = int(round(1.0 / dt))
        for i in range(n):
            f = np.array([-k * x[0]])
            central_difference_step(
                1,
                np.array([False]),
                np.array([1.0 / m]),
                np.ones(1),
                0.0,
                0.5 * dt if i == 0 else dt,
                dt,
                f,
                np.zeros(1),
                np.zeros(1),
                x,
                y,
                th,
                v,
                vy,
                om,
            )
        errors.append(abs(x[0] - np.cos(omega * 1.0)))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1), "halving dt quarters the error"
