"""The rigid rocking equation under a sampled accelerogram or one sine pulse, compiled (thesis
5.1.5).

The same model as :func:`stonedem.reference.analytic.rigid_rocking_response` (Housner; Zhang and
Makris: a rigid block that cannot slide, impacts that keep a fraction r of the kinetic energy),
integrated in compiled code because the scipy version spends 4-5 s of Python per record
(2 M right-hand-side calls) and the record_rocking validations call it ten times a study.
The scipy version stays the reference; tests hold this one to it.

Method: classical Runge-Kutta (order 4) on a fixed grid of ``substeps`` steps per sample
interval, so the piecewise-linear a_g is smooth inside every step. An impact (theta crosses
0 from the side of the current pivot) or an overturn (|theta| reaches pi/2) inside a step is
located by bisection on a single Runge-Kutta step of variable length from the start of the
step, to 2^-60 of the step; the impact then multiplies theta' by sqrt(r) (thesis Eq. 5.2)
and the step goes on from there. Imported by :mod:`stonedem.reference.analytic` only.

:func:`one_sine_pulse` is the same integrator under a_g = a_p sin(omega_p t) (evaluated
exactly at every stage) for the pulse of
:func:`stonedem.reference.analytic.rigid_one_sine_response`, which it replaces in the overturning
thresholds: 5-7 s of ``solve_ivp`` per one_sine job."""

import math

import numpy as np
from numba import njit

from stonedem.kernels import JIT_OPTIONS

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
    return (
        theta + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t),
        omega + h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w),
    )


LINEAR, SINE = 0, 1  # the input over a step: a_g = q0 + q1 s, or q0 sin(q1 (q2 + s))


@njit(**JIT_OPTIONS)
def input_step(theta, omega, h, kind, q0, q1, q2, side, alpha, p2, g):
    """One RK4 step of length h under a sampled record between two samples (``LINEAR``: a_g =
    q0 + q1 s, s from the step's start) or the one-sine pulse (``SINE``: a_g = q0 sin(q1 (q2 +
    s)), q2 the step's start time)."""
    if kind == LINEAR:
        return runge_kutta_step(
            theta, omega, h, q0, q0 + q1 * 0.5 * h, q0 + q1 * h, side, alpha, p2, g
        )
    return runge_kutta_step(
        theta,
        omega,
        h,
        q0 * math.sin(q1 * q2),
        q0 * math.sin(q1 * (q2 + 0.5 * h)),
        q0 * math.sin(q1 * (q2 + h)),
        side,
        alpha,
        p2,
        g,
    )


@njit(**JIT_OPTIONS)
def _event_value(theta, side):
    """Positive before an event, <= 0 at or past it: impact (theta back through 0) or overturn."""
    return min(side * theta, 0.5 * math.pi - abs(theta))


@njit(**JIT_OPTIONS)
def bracket_in_step(theta, omega, h, kind, q0, q1, q2, side, alpha, p2, g, turning):
    """(lo, hi), 2^-60 h apart, by bisection on the step's length: the event (impact or
    overturn) of a step that ends past one, or with ``turning`` the instant theta' turns
    from outwards to inwards, lies in (lo, hi]."""
    lo, hi = 0.0, h
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        tm, wm = input_step(theta, omega, mid, kind, q0, q1, q2, side, alpha, p2, g)
        before = side * wm > 0.0 if turning else _event_value(tm, side) > 0.0
        if before:
            lo = mid
        else:
            hi = mid
    return lo, hi


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
            while (
                k < substeps and (k + 1) * h_grid <= x
            ):  # after an uplift or an event inside a step
                k += 1
            if x >= length:
                break
            end = length if k + 1 >= substeps else (k + 1) * h_grid
            h = end - x
            a0 = accel[i] + slope * x
            th1, om1 = input_step(th, om, h, LINEAR, a0, slope, 0.0, side, alpha, p2, g)
            if _event_value(th1, side) > 0.0:
                th, om, x = th1, om1, end
                k += 1
                continue
            _lo, hi = bracket_in_step(th, om, h, LINEAR, a0, slope, 0.0, side, alpha, p2, g, False)
            th1, om1 = input_step(th, om, hi, LINEAR, a0, slope, 0.0, side, alpha, p2, g)
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


PULSE_ENDED, PULSE_OVERTURNED, PULSE_AT_REST = 0, 1, 2  # how one_sine_pulse ends


@njit(**JIT_OPTIONS)
def sine_uplift_instant(t, a_p, omega_p, onset, period):
    """First instant >= t in [0, period) where |a_p sin(omega_p t)| > onset, and the pivot
    side there (a_g > 0 tips onto the left pivot); (period, 0) if none. As
    :func:`stonedem.reference.analytic._one_sine_uplift`: the windows (phi1, pi - phi1) and (pi +
    phi1, 2 pi - phi1) of the phase, phi1 = asin(onset / |a_p|)."""
    phi1 = math.asin(onset / abs(a_p))
    phase = omega_p * t
    sign_ap = 1.0 if a_p > 0.0 else -1.0
    for start, end, sign in (
        (phi1, math.pi - phi1, 1.0),
        (math.pi + phi1, 2.0 * math.pi - phi1, -1.0),
    ):
        if phase < end:
            side = -1 if sign_ap * sign > 0.0 else 1
            return max(phase, start) / omega_p, side
    return period, 0


@njit(**JIT_OPTIONS)
def turning_point(theta, omega, h, kind, q0, q1, q2, side, alpha, p2, g):
    """|theta| where theta' turns from outwards to inwards inside the step (0, h]."""
    _lo, hi = bracket_in_step(theta, omega, h, kind, q0, q1, q2, side, alpha, p2, g, True)
    th, _om = input_step(theta, omega, hi, kind, q0, q1, q2, side, alpha, p2, g)
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
        th1, om1 = input_step(th, om, h, SINE, a_p, omega_p, t, side, alpha, p2, g)
        if _event_value(th1, side) > 0.0:
            if side * om > 0.0 and side * om1 <= 0.0:  # a turning point inside the step
                peak = max(
                    peak, turning_point(th, om, h, SINE, a_p, omega_p, t, side, alpha, p2, g)
                )
            peak = max(peak, abs(th1))
            th, om, t = th1, om1, end
            k += 1
            continue
        lo, hi = bracket_in_step(th, om, h, SINE, a_p, omega_p, t, side, alpha, p2, g, False)
        if lo > 0.0:  # the way to the event may pass a turning point too
            tl, wl = input_step(th, om, lo, SINE, a_p, omega_p, t, side, alpha, p2, g)
            if side * om > 0.0 and side * wl <= 0.0:
                peak = max(
                    peak, turning_point(th, om, lo, SINE, a_p, omega_p, t, side, alpha, p2, g)
                )
            peak = max(peak, abs(tl))
        th1, om1 = input_step(th, om, hi, SINE, a_p, omega_p, t, side, alpha, p2, g)
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
