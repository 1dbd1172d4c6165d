"""Base motion inside the compiled loop: displacement, velocity, acceleration at any time.

Every kind is evaluated in closed form, so d, v and a are exactly consistent (v = d', a = v')
and no integration error enters through the base (thesis 6.3 harmonic and ramp motion,
5.1.3 rectangular pulses, 5.1.5 one-sine pulses, 5.1.4 recorded accelerograms):

- KIND_NONE: at rest.
- KIND_HARMONIC: params [A m, omega rad/s, T_r s]: d = A e(t) sin(omega t), the amplitude
  eased in over T_r by the quintic e = 10 s^3 - 15 s^4 + 6 s^5 (s = t / T_r): the base
  starts at rest with no jump in velocity or acceleration (a jump would excite the contact
  springs and make a column slide or rock at low frequency, against thesis 6.1). T_r = 0
  gives the abrupt d = A sin(omega t).
- KIND_RECT_PULSE: params [a_p m/s2, T_p s]: a = a_p for 0 <= t < T_p, then 0.
- KIND_SINE_PULSE: params [a_p, omega, T = 2 pi / omega]: a = a_p sin(omega t) for one cycle.
- KIND_RAMP: params [rate m/s3]: a = rate t.
- KIND_TABLE: acceleration linear between samples a_i at t_i = i h; the node velocities and
  displacements are its exact integrals (precomputed), and between nodes the exact local
  polynomials are used. After the last sample a = 0 and the base coasts.
All kinds are at rest for t < 0.
"""

import numpy as np
from numba import njit

from stonedem.kernels import JIT_OPTIONS, NO_ALLOC_OPTIONS
from stonedem.kernels.scalar import cos, sin

KIND_NONE = 0
KIND_HARMONIC = 1
KIND_RECT_PULSE = 2
KIND_SINE_PULSE = 3
KIND_RAMP = 4
KIND_TABLE = 5


@njit(**NO_ALLOC_OPTIONS)
def base_motion(t, kind, params, table_accel, table_vel, table_disp, table_dt):
    """(d [m], v [m s-1], a [m s-2]) of the base at time t [s] for the given kind and params
    (4,)."""
    if t < 0.0 or kind == KIND_NONE:
        return 0.0, 0.0, 0.0
    if kind == KIND_HARMONIC:
        amp = params[0]
        w = params[1]
        t_ramp = params[2]
        sn = sin(w * t)
        cs = cos(w * t)
        e, de, dde = 1.0, 0.0, 0.0
        if t < t_ramp:
            x = t / t_ramp
            e = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x)
            de = 30.0 * x * x * (1.0 - x) * (1.0 - x) / t_ramp
            dde = 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x) / (t_ramp * t_ramp)
        return (
            amp * e * sn,
            amp * (de * sn + e * w * cs),
            amp * (dde * sn + 2.0 * de * w * cs - e * w * w * sn),
        )
    if kind == KIND_RECT_PULSE:
        a_p = params[0]
        t_p = params[1]
        if t < t_p:
            return 0.5 * a_p * t * t, a_p * t, a_p
        return 0.5 * a_p * t_p * t_p + a_p * t_p * (t - t_p), a_p * t_p, 0.0
    if kind == KIND_SINE_PULSE:
        a_p = params[0]
        w = params[1]
        period = params[2]
        if t < period:
            return (a_p / w * (t - sin(w * t) / w), a_p / w * (1.0 - cos(w * t)), a_p * sin(w * t))
        return a_p / w * period, 0.0, 0.0
    if kind == KIND_RAMP:
        rate = params[0]
        return rate * t * t * t / 6.0, 0.5 * rate * t * t, rate * t
    # KIND_TABLE
    n = table_accel.shape[0]
    h = table_dt
    t_end = (n - 1) * h
    if t > t_end:
        return table_disp[n - 1] + table_vel[n - 1] * (t - t_end), table_vel[n - 1], 0.0
    i = min(int(t / h), n - 2)
    s = t - i * h
    a0 = table_accel[i]
    slope = (table_accel[i + 1] - a0) / h
    v = table_vel[i] + a0 * s + 0.5 * slope * s * s
    d = table_disp[i] + table_vel[i] * s + 0.5 * a0 * s * s + slope * s * s * s / 6.0
    return d, v, a0 + slope * s


@njit(**JIT_OPTIONS)
def base_motion_many(times, kind, params, table_accel, table_vel, table_disp, table_dt):
    """(d, v, a) rows (3, n) of :func:`base_motion` at every time in ``times`` [s], compiled:
    set-up evaluates whole records on fine grids, where a Python loop took ~2 us a point."""
    out = np.empty((3, times.shape[0]))
    for i in range(times.shape[0]):
        d, v, a = base_motion(times[i], kind, params, table_accel, table_vel, table_disp, table_dt)
        out[0, i] = d
        out[1, i] = v
        out[2, i] = a
    return out
