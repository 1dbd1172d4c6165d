"""The rigid rocking equation under a sampled accelerogram or one sine pulse, compiled (thesis 5.1.5).

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

:func:`one_sine_pulse` is the same integrator under a_g = a_p sin(omega_p t) (evaluated
exactly at every stage) for the pulse of :func:`dem.analytic.rigid_one_sine_response`,
which it replaces in the overturning thresholds: 5-7 s of ``solve_ivp`` per one_sine job.
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
def runge_kutta_step(theta, omega, h, a0, a_mid, a1, side, alpha, p2, g):
    """(theta, omega) after one classical RK4 step of length h; a_g = a0, a_mid, a1 at its
    start, middle and end."""
    k1t = omega
    k1w = rocking_acceleration(theta, a0, side, alpha, p2, g)
    k2t = omega + 0.5 * h * k1w
    k2w = rocking_acceleration(theta + 0.5 * h * k1t, a_mid, side, alpha, p2, g)
    k3t = omega + 0.5 * h * k2w
    k3w = rocking_acceleration(theta + 0.5 * h * k2t, a_mid, side, alpha, p2, g)
    k4t = omega + h * k3w
    k4w = rocking_acceleration(theta + h * k3t, a1, side, alpha, p2, g)
    return (theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t),
            omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w))


@njit(**JIT_OPTIONS)
def linear_input_step(theta, omega, h, a0, slope, side, alpha, p2, g):
    """One RK4 step under a_g = a0 + slope s (a sampled record between two samples)."""
    return runge_kutta_step(theta, omega, h, a0, a0 + slope * 0.5 * h, a0 + slope * h, side, alpha, p2, g)


@njit(**JIT_OPTIONS)
def sine_input_step(theta, omega, t, h, a_p, omega_p, side, alpha, p2, g):
    """One RK4 step from time t under a_g = a_p sin(omega_p t) (the one-sine pulse)."""
    return runge_kutta_step(theta, omega, h, a_p * math.sin(omega_p * t), a_p * math.sin(omega_p * (t + 0.5 * h)),
                            a_p * math.sin(omega_p * (t + h)), side, alpha, p2, g)


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
            th1, om1 = linear_input_step(th, om, h, a0, slope, side, alpha, p2, g)
            if _event_value(th1, side) > 0.0:
                th, om, x = th1, om1, end
                k += 1
                continue
            lo, hi = 0.0, h  # the event lies in (lo, hi]
            for _ in range(BISECTION_STEPS):
                mid = 0.5 * (lo + hi)
                tm, _om = linear_input_step(th, om, mid, a0, slope, side, alpha, p2, g)
                if _event_value(tm, side) > 0.0:
                    lo = mid
                else:
                    hi = mid
            th1, om1 = linear_input_step(th, om, hi, a0, slope, side, alpha, p2, g)
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


PULSE_ENDED, PULSE_OVERTURNED, PULSE_AT_REST = 0, 1, 2   # how one_sine_pulse ends


@njit(**JIT_OPTIONS)
def sine_uplift_instant(t, a_p, omega_p, onset, period):
    """First instant >= t in [0, period) where |a_p sin(omega_p t)| > onset, and the pivot
    side there (a_g > 0 tips onto the left pivot); (period, 0) if none. As
    :func:`dem.analytic._one_sine_uplift`: the windows (phi1, pi - phi1) and (pi + phi1,
    2 pi - phi1) of the phase, phi1 = asin(onset / |a_p|)."""
    phi1 = math.asin(onset / abs(a_p))
    phase = omega_p * t
    sign_ap = 1.0 if a_p > 0.0 else -1.0
    for start, end, sign in ((phi1, math.pi - phi1, 1.0), (math.pi + phi1, 2.0 * math.pi - phi1, -1.0)):
        if phase < end:
            side = -1 if sign_ap * sign > 0.0 else 1
            return max(phase, start) / omega_p, side
    return period, 0


@njit(**JIT_OPTIONS)
def _turning_point(theta, omega, t, h, a_p, omega_p, side, alpha, p2, g):
    """|theta| where theta' turns from outwards to inwards inside the step (0, h] from t."""
    lo, hi = 0.0, h
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        _th, wm = sine_input_step(theta, omega, t, mid, a_p, omega_p, side, alpha, p2, g)
        if side * wm > 0.0:
            lo = mid
        else:
            hi = mid
    th, _om = sine_input_step(theta, omega, t, hi, a_p, omega_p, side, alpha, p2, g)
    return abs(th)


@njit(**JIT_OPTIONS)
def one_sine_pulse(a_p, omega_p, alpha, p2, g, r, rest_omega, steps):
    """The rigid block from rest through one sine pulse a_g = a_p sin(omega_p t), 0 <= t < T.

    Classical RK4 on a grid of ``steps`` steps per pulse (a_g evaluated exactly at every
    stage); impacts (theta back through 0: theta' x sqrt(r), the pivot switches; at rest when
    |theta'| < rest_omega), overturning (|theta| = pi/2) and the turning points (theta' = 0,
    for the peak) located by bisection inside a step, as in :func:`rocking_history`.

    Returns (how it ended: PULSE_ENDED / PULSE_OVERTURNED / PULSE_AT_REST, theta, theta' and
    pivot side at the end of the pulse, number of impacts, largest |theta| [rad]).
    """
    period = 2.0 * math.pi / omega_p
    h_grid = period / steps
    onset = g * math.tan(alpha)
    restitution = math.sqrt(r)
    side = 0
    th, om, t = 0.0, 0.0, 0.0
    k = 0  # grid steps done
    n_impacts = 0
    peak = 0.0
    while t < period:
        if side == 0:
            t, side = sine_uplift_instant(t, a_p, omega_p, onset, period)
            if side == 0:
                return PULSE_AT_REST, 0.0, 0.0, 0, n_impacts, peak
            th, om = 0.0, 0.0
        while k < steps and (k + 1) * h_grid <= t:
            k += 1
        if t >= period:
            break
        end = period if k + 1 >= steps else (k + 1) * h_grid
        h = end - t
        th1, om1 = sine_input_step(th, om, t, h, a_p, omega_p, side, alpha, p2, g)
        if _event_value(th1, side) > 0.0:
            if side * om > 0.0 and side * om1 <= 0.0:  # a turning point inside the step
                peak = max(peak, _turning_point(th, om, t, h, a_p, omega_p, side, alpha, p2, g))
            peak = max(peak, abs(th1))
            th, om, t = th1, om1, end
            k += 1
            continue
        lo, hi = 0.0, h  # the event lies in (lo, hi]
        for _ in range(BISECTION_STEPS):
            mid = 0.5 * (lo + hi)
            tm, _wm = sine_input_step(th, om, t, mid, a_p, omega_p, side, alpha, p2, g)
            if _event_value(tm, side) > 0.0:
                lo = mid
            else:
                hi = mid
        if lo > 0.0:  # the way to the event may pass a turning point too
            tl, wl = sine_input_step(th, om, t, lo, a_p, omega_p, side, alpha, p2, g)
            if side * om > 0.0 and side * wl <= 0.0:
                peak = max(peak, _turning_point(th, om, t, lo, a_p, omega_p, side, alpha, p2, g))
            peak = max(peak, abs(tl))
        th1, om1 = sine_input_step(th, om, t, hi, a_p, omega_p, side, alpha, p2, g)
        t += hi
        if side * th1 > 0.0:  # not back through 0: |theta| reached pi/2
            return PULSE_OVERTURNED, th1, om1, side, n_impacts, 0.5 * math.pi
        n_impacts += 1
        th, om = 0.0, om1 * restitution  # thesis Eq. 5.2
        side = -side
        if abs(om) < rest_omega:
            side, om = 0, 0.0
    if side == 0:
        return PULSE_AT_REST, 0.0, 0.0, 0, n_impacts, peak
    return PULSE_ENDED, th, om, side, n_impacts, peak
