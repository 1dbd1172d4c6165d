"""The rigid rocking equation under a sampled accelerogram, compiled (thesis 5.1.5).

The same model as :func:`dem.analytic.rigid_rocking_response` (Housner; Zhang and Makris:
a rigid block that cannot slide, impacts that keep a fraction r of the kinetic energy),
integrated in compiled code because the scipy version spends 4-5 s of Python per record
(2 M right-hand-side calls) and the record_rocking validations call it ten times a study.
The scipy version stays the reference; tests hold this one to it.

Method: classical Runge-Kutta (order 4) on a fixed grid of ``substeps`` steps per sample
interval, so the piecewise-linear a_g is smooth inside every step. An impact (theta crosses
0 from the side of the current pivot) or an overturn (|theta| reaches pi/2) inside a step is
located by bisection on a single Runge-Kutta step of variable length from the start of the
step, to 2^-60 of the step; the impact then multiplies theta' by sqrt(r) (thesis Eq. 5.2)
and the step goes on from there. Imported by :mod:`dem.analytic` only.
"""

import math

import numpy as np
from numba import njit

from dem.kernels import JIT_OPTIONS

BISECTION_STEPS = 60


@njit(**JIT_OPTIONS)
def rocking_acceleration(theta, a_g, side, alpha, p2, g):
    """theta'' on the right (side > 0) or left pivot; thesis 5.1.5 (Housner's equation)."""
    if side > 0:
        return -p2 * (math.sin(alpha - theta) + a_g / g * math.cos(alpha - theta))
    return p2 * (math.sin(alpha + theta) - a_g / g * math.cos(alpha + theta))


@njit(**JIT_OPTIONS)
def runge_kutta_step(theta, omega, h, a0, slope, side, alpha, p2, g):
    """(theta, omega) after one classical RK4 step of length h; a_g = a0 + slope s."""
    k1t = omega
    k1w = rocking_acceleration(theta, a0, side, alpha, p2, g)
    a_mid = a0 + slope * 0.5 * h
    k2t = omega + 0.5 * h * k1w
    k2w = rocking_acceleration(theta + 0.5 * h * k1t, a_mid, side, alpha, p2, g)
    k3t = omega + 0.5 * h * k2w
    k3w = rocking_acceleration(theta + 0.5 * h * k2t, a_mid, side, alpha, p2, g)
    k4t = omega + h * k3w
    k4w = rocking_acceleration(theta + h * k3t, a0 + slope * h, side, alpha, p2, g)
    return (theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t),
            omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w))


@njit(**JIT_OPTIONS)
def _event_value(theta, side):
    """Positive before an event, <= 0 at or past it: impact (theta back through 0) or overturn."""
    return min(side * theta, 0.5 * math.pi - abs(theta))


@njit(**JIT_OPTIONS)
def uplift_instant(a0, slope, x, h, onset):
    """First s in [x, h] where |a0 + slope s| > onset, and the pivot side; (h, 0) if none."""
    best, side = h, 0
    for sense in (1.0, -1.0):
        level, rate = sense * a0, sense * slope  # outside when level + rate s > onset
        start = -1.0
        if rate == 0.0:
            if level > onset:
                start = x
        else:
            cross = (onset - level) / rate
            if rate > 0.0:
                if cross < h:
                    start = max(x, cross)
            elif x < cross:
                start = x
        if start >= 0.0 and (side == 0 or start < best):
            best, side = start, (1 if sense < 0.0 else -1)  # a_g < 0 tips onto the right pivot
    return best, side


@njit(**JIT_OPTIONS)
def rocking_history(time, accel, alpha, p2, g, r, rest_omega, substeps, theta, omega, impacts):
    """Integrate from rest; fill theta, omega at the sample instants (NaN after overturning).

    ``impacts`` receives the impact instants (as many as fit). Returns (number of impacts,
    overturned flag).
    """
    n = len(time)
    onset = g * math.tan(alpha)
    restitution = math.sqrt(r)
    side = 0
    th, om = 0.0, 0.0
    n_impacts = 0
    theta[0], omega[0] = 0.0, 0.0
    for i in range(n - 1):
        length = time[i + 1] - time[i]
        slope = (accel[i + 1] - accel[i]) / length
        h_grid = length / substeps
        x = 0.0  # local time in the interval
        k = 0  # grid steps done in this interval
        while x < length:
            if side == 0:
                start, new_side = uplift_instant(accel[i], slope, x, length, onset)
                if new_side == 0:
                    break
                side, x = new_side, start
                th, om = 0.0, 0.0
            while k < substeps and (k + 1) * h_grid <= x:  # after an uplift or an event inside a step
                k += 1
            if x >= length:
                break
            end = length if k + 1 >= substeps else (k + 1) * h_grid
            h = end - x
            a0 = accel[i] + slope * x
            th1, om1 = runge_kutta_step(th, om, h, a0, slope, side, alpha, p2, g)
            if _event_value(th1, side) > 0.0:
                th, om, x = th1, om1, end
                k += 1
                continue
            lo, hi = 0.0, h  # the event lies in (lo, hi]
            for _ in range(BISECTION_STEPS):
                mid = 0.5 * (lo + hi)
                tm, _om = runge_kutta_step(th, om, mid, a0, slope, side, alpha, p2, g)
                if _event_value(tm, side) > 0.0:
                    lo = mid
                else:
                    hi = mid
            th1, om1 = runge_kutta_step(th, om, hi, a0, slope, side, alpha, p2, g)
            x += hi
            if side * th1 > 0.0:  # not back through 0: |theta| reached pi/2, overturned
                for j in range(i + 1, n):
                    theta[j], omega[j] = np.nan, np.nan
                return n_impacts, True
            if n_impacts < len(impacts):
                impacts[n_impacts] = time[i] + x
            n_impacts += 1
            th, om = 0.0, om1 * restitution  # thesis Eq. 5.2: r = (omega_after / omega_before)^2
            side = -side
            if abs(om) < rest_omega:
                side, om = 0, 0.0  # chattering has died out
        theta[i + 1], omega[i + 1] = th, om
    return n_impacts, False
