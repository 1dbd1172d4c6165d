"""Reference solutions for the analytical validation of thesis section 5.1, slow and exact.

Plain NumPy/SciPy, written to be obviously correct rather than fast. The exceptions are
the ``*_compiled`` twins (:func:`rigid_rocking_response_compiled`,
:func:`rigid_one_sine_response_compiled`, :func:`bouc_wen_sliding_compiled`): the same
equations through the compiled integrators of :mod:`stonedem.reference.rigid_rocking` and
:mod:`stonedem.reference.bouc_wen`, which the validations use, held to the scipy ones by tests. It
covers Housner's free-rocking period of a slender block (5.1.1, Eq. 5.1) and the exact period of
the rigid rocking equation; energy loss at impact, the peak angles and half periods that
follow from it (5.1.2, Eq. 5.2-5.4) and the inverse problem (energy ratio from measured
peaks); Newmark's maximum sliding under a rectangular pulse (5.1.3, Eq. 5.5); the
rigid-plastic sliding block integrated exactly under a piecewise-linear accelerogram and
its Bouc-Wen approximation (5.1.4, Eq. 5.6-5.7); the rigid rocking equation with impacts
under ground acceleration (Housner; Zhang and Makris, 5.1.5), and under the engine's one-sine
pulse the overturning verdict, minimum overturning amplitude and overturning spectrum,
integrated exactly without sampling the pulse (5.1.5). Geometry follows
Housner: a rectangle of full width ``width`` = 2b and full height ``height`` = 2h,
R = sqrt(b^2 + h^2), alpha = atan(b/h), I_O = 4/3 m R^2 about a base corner,
p = sqrt(m g R / I_O) = sqrt(3 g / (4 R)). Sign convention for rotations: theta > 0
means the block stands on its RIGHT bottom corner and leans towards +x (clockwise when
x points right and y up); the engine measures angles counter-clockwise, so its angle is
-theta. Sliding: u = x_block - x_ground, and a positive ground acceleration drives u
negative.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy.integrate import quad, solve_ivp

from stonedem.units import GRAVITY as G  # default gravitational acceleration [m s-2]

# --- geometry ----------------------------------------------------------------------------


@dataclass(frozen=True)
class RockingProperties:
    """Rocking constants of a rectangular block (thesis Figure 5.1)."""

    alpha: float  # slenderness atan(b/h) [rad]
    radius: float  # half diagonal R = sqrt(b^2 + h^2) [m]
    inertia_corner: float  # moment of inertia about a base corner I_O = 4/3 m R^2 [kg m2]
    p: float  # frequency parameter sqrt(m g R / I_O) [rad s-1]


def rectangle_rocking_properties(width, height, mass=1.0, g=G) -> RockingProperties:
    """Slenderness, half diagonal, corner inertia and frequency parameter of a rectangle.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    mass: mass m of the block [kg]; alpha, R and p do not depend on it
    g: gravitational acceleration [m s-2]

    Returns
    -------
    RockingProperties with alpha [rad], radius R [m], inertia_corner I_O [kg m2], p [rad s-1].
    """
    if not (width > 0.0 and height > 0.0 and mass > 0.0 and g > 0.0):
        raise ValueError(
            f"width, height, mass and g must be positive, got {width}, {height}, {mass}, {g}"
        )
    b, h = 0.5 * width, 0.5 * height
    radius = math.hypot(b, h)
    inertia = 4.0 / 3.0 * mass * radius**2  # rectangle: I_G = m R^2 / 3, plus m R^2 (parallel axes)
    return RockingProperties(
        alpha=math.atan(b / h),
        radius=radius,
        inertia_corner=inertia,
        p=math.sqrt(mass * g * radius / inertia),
    )


# --- 5.1.1 free rocking period -------------------------------------------------------------


def housner_period_slender(width, height, theta0, g=G):
    """Full-cycle free-rocking period of a slender block without energy loss, thesis Eq. 5.1.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    theta0: initial rotation amplitude, scalar or array; its sign is ignored [rad]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    T = 4/p acosh(1 / (1 - theta0/alpha)) [s], same shape as theta0; inf where |theta0| >= alpha.
    """
    blk = rectangle_rocking_properties(width, height, g=g)
    ratio = np.abs(np.asarray(theta0, dtype=float)) / blk.alpha
    with np.errstate(divide="ignore", invalid="ignore"):
        period = 4.0 / blk.p * np.arccosh(1.0 / (1.0 - ratio))  # thesis Eq. 5.1
    period = np.where(ratio >= 1.0, np.inf, period)
    return period[()] if period.ndim == 0 else period


def _exact_period_scalar(blk: RockingProperties, theta0: float) -> float:
    """Exact free-rocking period [s] for one amplitude theta0 [rad] (see rocking_period_exact)."""
    a, th0 = blk.alpha, abs(theta0)
    if th0 == 0.0:
        return 0.0
    if th0 >= a:
        return math.inf

    def integrand(s):
        # theta = th0 (1 - s^2), dtheta = -2 th0 s ds: the 1/sqrt endpoint singularity at
        # theta = th0 (s = 0) becomes a finite limit
        theta = th0 * (1.0 - s * s)
        # cos(a - th0) - cos(a - theta) = 2 sin(a - (th0 + theta)/2) sin((th0 - theta)/2),
        # written as a product to avoid cancellation near the turning point
        gap = 2.0 * math.sin(a - 0.5 * (th0 + theta)) * math.sin(0.5 * th0 * s * s)
        if s == 0.0:
            # limit s -> 0: gap ~ sin(a - th0) th0 s^2 / 2
            return 2.0 * th0 / math.sqrt(blk.p**2 * math.sin(a - th0) * th0)
        # theta'^2 = 2 p^2 gap (energy: 1/2 I_O theta'^2 = m g R [cos(a - th0) - cos(a - theta)])
        return 2.0 * th0 * s / math.sqrt(2.0 * blk.p**2 * gap)

    quarter, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-12, limit=200)
    return 4.0 * quarter


def rocking_period_exact(width, height, theta0, g=G):
    """Full-cycle period of free rocking governed by the exact (not linearised) rigid equation.

    I_O theta'' = -m g R sin(alpha - theta) for theta > 0 (mirror image for theta < 0), no
    energy loss. By energy conservation 1/2 I_O theta'^2 = m g R [cos(alpha - theta0) -
    cos(alpha - theta)], and T = 4 int_0^theta0 dtheta / theta'. The integral is evaluated
    with scipy.integrate.quad (relative tolerance 1e-12) after the substitution
    theta = theta0 (1 - s^2), which removes the inverse square root at theta = theta0. It
    tends to Eq. 5.1 as alpha -> 0.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    theta0: initial rotation amplitude (released at rest), scalar or array; sign ignored [rad]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    T [s], same shape as theta0; 0 for theta0 = 0 and inf where |theta0| >= alpha.
    """
    blk = rectangle_rocking_properties(width, height, g=g)
    th = np.asarray(theta0, dtype=float)
    out = np.array([_exact_period_scalar(blk, float(x)) for x in th.ravel()]).reshape(th.shape)
    return out[()] if out.ndim == 0 else out


# --- 5.1.2 energy loss at impact -----------------------------------------------------------


def rocking_peak_angles_eq53(width, height, theta0, r, n_impacts):
    """Peak rotation after each of n impacts of a freely rocking slender block, thesis Eq. 5.3.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    theta0: initial rotation, released at rest [rad]
    r: kinetic energy ratio after/before each impact, thesis Eq. 5.2 [-]
    n_impacts: number of impacts n [-]

    Returns
    -------
    Array of n_impacts + 1 peak angles theta_0 .. theta_n [rad].
    """
    alpha = rectangle_rocking_properties(width, height).alpha
    n = np.arange(n_impacts + 1)
    # thesis Eq. 5.3: theta_n = alpha (1 - sqrt(1 - r^n [1 - (1 - theta0/alpha)^2]))
    return alpha * (1.0 - np.sqrt(1.0 - r**n * (1.0 - (1.0 - theta0 / alpha) ** 2)))


def rocking_half_periods_eq54(width, height, theta0, r, n_impacts, g=G):
    """Half-cycle durations of a freely rocking slender block losing energy at impact, Eq. 5.4.

    The value for index n is the duration of the half cycle whose amplitude is the peak
    theta_n of Eq. 5.3 (from the impact that starts it to the next impact).

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    theta0: initial rotation, released at rest [rad]
    r: kinetic energy ratio after/before each impact, thesis Eq. 5.2 [-]
    n_impacts: number of impacts n [-]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    Array of n_impacts + 1 half periods T_n / 2 [s].
    """
    blk = rectangle_rocking_properties(width, height, g=g)
    n = np.arange(n_impacts + 1)
    # thesis Eq. 5.4: T/2 = 2 sqrt(I_O / (W R)) atanh(sqrt(r^n [1 - (1 - theta0/alpha)^2]))
    return 2.0 / blk.p * np.arctanh(np.sqrt(r**n * (1.0 - (1.0 - theta0 / blk.alpha) ** 2)))


def restitution_from_peaks(width, height, peaks):
    """Energy ratio of each impact implied by successive peak angles through Eq. 5.3.

    r_i = [1 - (1 - theta_i/alpha)^2] / [1 - (1 - theta_{i-1}/alpha)^2], the inverse of
    thesis Eq. 5.3 between consecutive peaks (slender-block approximation).

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    peaks: successive peak rotation magnitudes theta_0, theta_1, ... [rad]

    Returns
    -------
    Array of len(peaks) - 1 energy ratios r_i [-].
    """
    alpha = rectangle_rocking_properties(width, height).alpha
    level = 1.0 - (1.0 - np.abs(np.asarray(peaks, dtype=float)) / alpha) ** 2  # thesis Eq. 5.3
    return level[1:] / level[:-1]


def restitution_from_peaks_exact(width, height, peaks):
    """Energy ratio of each impact from the exact potential energy at successive peaks.

    At a peak the energy is all potential, m g R [cos(alpha - theta) - cos(alpha)], and none
    is lost between impacts, so r_i = [cos(alpha - theta_i) - cos alpha] /
    [cos(alpha - theta_{i-1}) - cos alpha] is exactly the kinetic energy ratio of Eq. 5.2.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    peaks: successive peak rotation magnitudes theta_0, theta_1, ... [rad]

    Returns
    -------
    Array of len(peaks) - 1 energy ratios r_i [-].
    """
    alpha = rectangle_rocking_properties(width, height).alpha
    energy = np.cos(alpha - np.abs(np.asarray(peaks, dtype=float))) - math.cos(alpha)
    return energy[1:] / energy[:-1]  # thesis Eq. 5.2 with the kinetic energy at theta = 0


def housner_restitution(width, height):
    """Housner's kinetic energy ratio of a rigid-block impact, r = (1 - 3/2 sin^2 alpha)^2.

    From conservation of angular momentum about the new pivot corner (rectangle,
    I_O = 4/3 m R^2); for reference with thesis Eq. 5.2.

    Parameters
    ----------
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]

    Returns
    -------
    r [-].
    """
    alpha = rectangle_rocking_properties(width, height).alpha
    return (1.0 - 1.5 * math.sin(alpha) ** 2) ** 2


# --- 5.1.3 sliding under a rectangular pulse -----------------------------------------------


def newmark_pulse_max_sliding(a_p, T_p, mu, g=G):
    """Maximum sliding of a rigid block under a rectangular acceleration pulse, thesis Eq. 5.5.

    Parameters
    ----------
    a_p: pulse amplitude [m s-2]
    T_p: pulse duration [s]
    mu: Coulomb friction coefficient, scalar or array [-]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    u_max = a_p T_p^2 / 2 (a_p / (mu g) - 1) [m] where a_p > mu g, else 0; shape of mu.
    """
    mu = np.asarray(mu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        u_max = a_p * T_p**2 / 2.0 * (a_p / (mu * g) - 1.0)  # thesis Eq. 5.5
    out = np.where(a_p > mu * g, u_max, 0.0)
    return out[()] if out.ndim == 0 else out


# --- 5.1.4 sliding under an accelerogram ---------------------------------------------------


@dataclass
class SlidingResponse:
    """Sliding of a block relative to the ground, sampled on the input time grid."""

    u: np.ndarray  # relative displacement x_block - x_ground [m]
    v: np.ndarray  # relative velocity [m s-1]


def _series(time, ground_accel, strictly_increasing):
    """(t, a) as float arrays, checked: same length >= 2, finite, time increasing."""
    t = np.asarray(time, dtype=float)
    a = np.asarray(ground_accel, dtype=float)
    if t.ndim != 1 or t.shape != a.shape or len(t) < 2:
        raise ValueError(
            f"time and ground_accel must be 1-D of equal length >= 2, got {t.shape}, {a.shape}"
        )
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
        raise ValueError("time and ground_accel must be finite")
    steps = np.diff(t)
    if strictly_increasing and np.any(steps <= 0.0):
        raise ValueError("time must be strictly increasing")
    if np.any(steps < 0.0):
        raise ValueError("time must be non-decreasing")
    return t, a


def _slip_onset(a0, slope, limit, x, h, now_allowed=True):
    """First instant in [x, h] at which a stuck block starts to slide, and its direction.

    The ground acceleration is a0 + slope s on the interval 0 <= s <= h; sliding starts
    where |a_g| > limit = mu g, decided from the exact crossing instants of the line with
    +-limit (not from re-evaluating a_g, which rounding could put on either side).
    ``now_allowed=False`` refuses a start at x inside a band the line is leaving (used
    after a start that rounding made void).

    Returns (direction, instant): direction -1 when a_g > mu g (the block lags, u decreases),
    +1 when a_g < -mu g; (0, h) when it stays stuck up to h.
    """
    best = (0, h)
    for sense in (1.0, -1.0):
        level, rate = sense * a0, sense * slope  # outside the band: level + rate s > limit
        if rate == 0.0:
            start = x if (level > limit and now_allowed) else None
        elif rate > 0.0:  # outside for s > cross
            cross = (limit - level) / rate
            start = max(x, cross) if cross < h else None
        else:  # outside for s < cross, i.e. leaving the region
            cross = (limit - level) / rate
            start = x if (x < cross and now_allowed) else None
        if start is not None and (best[0] == 0 or start < best[1]):
            best = (int(-sense), start)
    return best


def _first_zero_of_quadratic(v0, b, c, length):
    """Smallest s in (0, length] with v0 + b s + c s^2 = 0 (v0 != 0), or None."""
    if c == 0.0:
        roots = [-v0 / b] if b != 0.0 else []
    else:
        disc = b * b - 4.0 * c * v0
        if disc < 0.0:
            return None
        q = -0.5 * (b + math.copysign(math.sqrt(disc), b))  # stable pair q/c, v0/q
        roots = [q / c] + ([v0 / q] if q != 0.0 else [])
    roots = [s for s in roots if 0.0 < s <= length]
    return min(roots) if roots else None


def rigid_plastic_sliding(time, ground_accel, mu, g=G) -> SlidingResponse:
    """Exact sliding of a rigid block on a rigid plane with Coulomb friction (thesis 5.1.4).

    Static and kinetic friction coefficients are both mu. The ground acceleration a_g is
    linear between samples. Relative motion u = x_block - x_ground obeys, while sliding with
    direction s = sign(v), u'' = -a_g(t) - mu g s; while stuck u' = 0, until |a_g| exceeds
    mu g, when sliding starts in direction -sign(a_g) (a positive ground acceleration drives u
    negative). Within each sample interval a_g is linear, so v is quadratic and u cubic in
    time: the stop instants (v = 0, root of a quadratic) and the start instants (|a_g| = mu g,
    root of a line) are found exactly and the motion is summed in closed form, with no time
    step. After a stop the block sticks unless |a_g| > mu g there, in which case it slides
    back at once.

    Parameters
    ----------
    time: sample instants, non-decreasing; a repeated instant is a jump of a_g [s]
    ground_accel: horizontal ground acceleration a_g at those instants [m s-2]
    mu: Coulomb friction coefficient [-]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    SlidingResponse with u [m] and v [m s-1] at the sample instants; the block starts at rest.
    """
    t, a = _series(time, ground_accel, strictly_increasing=False)
    if not mu >= 0.0:
        raise ValueError(f"mu must be >= 0, got {mu}")
    limit = mu * g  # friction force per unit mass [m s-2]
    u_out = np.zeros_like(t)
    v_out = np.zeros_like(t)
    u, v, direction = 0.0, 0.0, 0  # direction = sign of sliding, 0 when stuck
    for i in range(len(t) - 1):
        h = t[i + 1] - t[i]
        if h > 0.0:
            a0, slope = a[i], (a[i + 1] - a[i]) / h
            x, now_allowed = 0.0, True
            for _ in range(10_000):  # a handful of stops and starts per interval at most
                if x >= h:
                    break
                if direction == 0:
                    direction, x = _slip_onset(a0, slope, limit, x, h, now_allowed)
                    now_allowed = True
                    continue
                # sliding: relative acceleration -a_g - mu g s, linear in the local time s
                b = -(a0 + slope * x) - limit * direction  # u'' at s = 0
                c = -0.5 * slope  # v(s) = v + b s + c s^2
                if direction * v <= 0.0:
                    # sliding from rest: u'' has the sign of s away from rounding at a start instant
                    v = 0.0
                    b = direction * max(direction * b, 0.0)
                    if b == 0.0 and direction * c <= 0.0:
                        direction, now_allowed = 0, False  # touched mu g and turned back: no slip
                        continue
                    stop = -b / c if b * c < 0.0 else None
                    if stop is not None and stop > h - x:
                        stop = None
                else:
                    stop = _first_zero_of_quadratic(v, b, c, h - x)
                step = h - x if stop is None else stop
                u += v * step + 0.5 * b * step**2 + c * step**3 / 3.0  # exact cubic
                v += b * step + c * step**2
                x = h if stop is None else x + step
                if stop is not None:
                    v, direction = 0.0, 0  # stopped; the next pass decides whether it restarts
            else:
                raise RuntimeError(
                    f"rigid_plastic_sliding: no progress in interval {i} at t = {t[i]}"
                )
        u_out[i + 1] = u
        v_out[i + 1] = v
    return SlidingResponse(u_out, v_out)


class _PiecewiseLinear:
    """Scalar evaluation of a piecewise-linear function given by samples (constant outside)."""

    def __init__(self, t, a):
        self.t = [float(x) for x in t]
        self.a = [float(x) for x in a]

    def __call__(self, x):
        t, a = self.t, self.a
        if x <= t[0]:
            return a[0]
        if x >= t[-1]:
            return a[-1]
        j = bisect.bisect_right(t, x) - 1
        return a[j] + (a[j + 1] - a[j]) * (x - t[j]) / (t[j + 1] - t[j])


def bouc_wen_sliding(
    time, ground_accel, mu, u_y=1e-6, gamma=0.5, beta=0.5, n=50, g=G
) -> SlidingResponse:
    """Sliding block with Bouc-Wen hysteretic friction, thesis Eq. 5.6-5.7.

    u''(t) + mu g z(t) = -a_g(t) and u_y z' + gamma |u'| |z|^(n-1) z + beta u' |z|^n - u' = 0,
    with u = x_block - x_ground and z the dimensionless hysteretic variable (|z| <= 1). As
    u_y -> 0 this tends to the rigid-plastic block of :func:`rigid_plastic_sliding`. The
    ground acceleration is interpolated linearly between samples. The system is stiff
    (elastic frequency sqrt(mu g / u_y)): integrated with LSODA, max_step = sample spacing.

    Parameters
    ----------
    time: sample instants, strictly increasing [s]
    ground_accel: horizontal ground acceleration a_g at those instants [m s-2]
    mu: Coulomb friction coefficient [-]
    u_y: yield displacement of the rigid-plastic limit [m]
    gamma: Bouc-Wen shape parameter [-]
    beta: Bouc-Wen shape parameter [-]
    n: Bouc-Wen sharpness exponent [-]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    SlidingResponse with u [m] and v [m s-1] at the sample instants; starts at rest, z = 0.
    """
    t, a = _series(time, ground_accel, strictly_increasing=True)
    accel = _PiecewiseLinear(t, a)

    def rhs(tt, y):
        _, v, z = y
        az = abs(z)
        # thesis Eq. 5.7: u_y z' = u' - gamma |u'| |z|^(n-1) z - beta u' |z|^n
        dz = (v - gamma * abs(v) * az ** (n - 1) * z - beta * v * az**n) / u_y
        # thesis Eq. 5.6 as printed reads "u'' + mu gamma z' = -a_g", a garbled transcription;
        # the Konstantinidis and Makris model is u'' + mu g z = -a_g, implemented here
        return [v, -accel(tt) - mu * g * z, dz]

    sol = solve_ivp(
        rhs,
        (t[0], t[-1]),
        [0.0, 0.0, 0.0],
        method="LSODA",
        t_eval=t,
        rtol=1e-8,
        atol=[1e-10, 1e-10, 1e-8],
        max_step=float(np.min(np.diff(t))),
    )
    if not sol.success:
        raise RuntimeError(f"bouc_wen_sliding: {sol.message}")
    return SlidingResponse(sol.y[0], sol.y[1])


BOUC_WEN_STEPS_PER_PERIOD = 768  # BDF2 steps per elastic period 2 pi sqrt(u_y / (mu g))


def bouc_wen_sliding_compiled(
    time,
    ground_accel,
    mu,
    u_y=1e-6,
    gamma=0.5,
    beta=0.5,
    n=50,
    g=G,
    steps_per_period=BOUC_WEN_STEPS_PER_PERIOD,
) -> SlidingResponse:
    """:func:`bouc_wen_sliding` by the compiled BDF2 integrator :mod:`stonedem.reference.bouc_wen`.

    The step is the elastic period 2 pi sqrt(u_y / (mu g)) over ``steps_per_period`` (5 us
    for mu = 0.3, u_y = 1e-6), shortened to fit the sample intervals: BDF2 damps the
    elastic ringing of the stick phases, which a shorter step keeps (error 2nd order; at 768
    per period 6e-5 of the peak against LSODA under Northridge, in 0.6 s instead of 7-12 s).
    Parameters as :func:`bouc_wen_sliding`."""
    from stonedem.reference.bouc_wen import bouc_wen_history  # compiled: imported only when used

    t, a = _series(time, ground_accel, strictly_increasing=True)
    for name, value in (("mu", mu), ("u_y", u_y), ("n", n), ("g", g)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise ValueError(f"{name} must be a positive number, got {value!r}")
    if isinstance(steps_per_period, bool) or not (
        isinstance(steps_per_period, int) and steps_per_period >= 8
    ):
        raise ValueError(f"steps_per_period must be a whole number >= 8, got {steps_per_period!r}")
    step = 2.0 * math.pi * math.sqrt(u_y / (mu * g)) / steps_per_period
    substeps = max(1, math.ceil(float(np.max(np.diff(t))) / step))
    u, v = np.empty_like(t), np.empty_like(t)
    failures = bouc_wen_history(
        t, a, float(mu), float(g), float(u_y), float(gamma), float(beta), float(n), substeps, u, v
    )
    if failures:
        raise RuntimeError(
            f"bouc_wen_sliding_compiled: Newton's method did not converge in {failures} "
            f"steps; use more steps_per_period"
        )
    return SlidingResponse(u, v)


# --- 5.1.5 rigid rocking under ground acceleration -----------------------------------------


@dataclass
class RockingResponse:
    """Rocking of a rigid block, sampled on the input time grid."""

    theta: (
        np.ndarray
    )  # rotation, > 0 on the right corner leaning to +x [rad]; NaN after overturning
    omega: np.ndarray  # angular velocity d theta / dt [rad s-1]; NaN after overturning
    overturned: bool  # |theta| reached pi/2
    impact_times: list = field(default_factory=list)  # instants of theta = 0 crossings [s]


def rigid_rocking_response(
    time, ground_accel, width, height, r, g=G, theta0=0.0, omega0=0.0, rest_omega=1e-8
) -> RockingResponse:
    """Rocking of a rigid block that cannot slide, under horizontal ground acceleration.

    Housner / Zhang and Makris rigid rocking equation (thesis 5.1.5), with theta > 0 the
    block standing on its right corner and leaning to +x (the engine's angle is -theta):

        theta > 0:  I_O theta'' = -m g R sin(alpha - theta) - m a_g R cos(alpha - theta)
        theta < 0:  I_O theta'' = +m g R sin(alpha + theta) - m a_g R cos(alpha + theta)

    Derivation: relative to the pivot the centre of mass is at R(-sin(alpha - theta),
    cos(alpha - theta)); weight and the d'Alembert force -m a_g of the accelerating ground
    give these moments, so a negative a_g (ground accelerating to -x) tips the block onto its
    right corner. From rest, rocking starts when |a_g| > g tan(alpha), towards theta > 0 if
    a_g < 0; while at rest it stays there. At each impact (theta = 0) theta' is multiplied by
    sqrt(r), r being the kinetic energy ratio of thesis Eq. 5.2, and the pivot switches
    corner; impacts are located with solve_ivp terminal events and the integration restarted.
    When theta' after an impact is below ``rest_omega`` (chattering) the block is put at rest.
    Integration: DOP853, rtol 1e-10, atol 1e-12, max_step = smallest sample spacing, a_g
    linear between samples.

    Parameters
    ----------
    time: sample instants, strictly increasing [s]
    ground_accel: horizontal ground acceleration a_g at those instants [m s-2]
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    r: kinetic energy ratio after/before impact, thesis Eq. 5.2 [-]
    g: gravitational acceleration [m s-2]
    theta0: rotation at time[0] [rad]
    omega0: angular velocity at time[0] [rad s-1]
    rest_omega: |theta'| after an impact below which the block settles to rest [rad s-1]

    Returns
    -------
    RockingResponse with theta [rad] and omega [rad s-1] at the sample instants (NaN after
    overturning, i.e. once |theta| reaches pi/2), overturned, and the impact instants [s].
    """
    t, a = _series(time, ground_accel, strictly_increasing=True)
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"r must be in [0, 1], got {r}")
    blk = rectangle_rocking_properties(width, height, g=g)
    alpha, p2 = blk.alpha, blk.p**2  # p^2 = m g R / I_O
    onset = g * math.tan(alpha)  # uplift threshold |a_g| > g tan(alpha)
    accel = _PiecewiseLinear(t, a)
    theta = np.full_like(t, np.nan)
    omega = np.full_like(t, np.nan)
    impacts: list = []
    max_step = float(np.min(np.diff(t)))

    def rhs(tt, y, side):
        th = y[0]
        ag = accel(tt)
        if side > 0:  # pivot on the right corner
            acc = -p2 * (math.sin(alpha - th) + ag / g * math.cos(alpha - th))
        else:  # pivot on the left corner
            acc = p2 * (math.sin(alpha + th) - ag / g * math.cos(alpha + th))
        return [y[1], acc]

    def impact(tt, y, side):
        return y[0]

    def topple(tt, y, side):
        return abs(y[0]) - 0.5 * math.pi

    impact.terminal = True
    topple.terminal = True

    def rest_until(t_from):
        """First instant >= t_from at which |a_g| > g tan(alpha), and the side; (None, 0) if
        never."""
        j0 = bisect.bisect_right(accel.t, t_from)  # first sample strictly after t_from
        a_from = accel(t_from)
        if abs(a_from) > onset:
            return t_from, (1 if a_from < 0.0 else -1)
        t_prev, a_prev = t_from, a_from
        for j in range(j0, len(t)):
            if abs(a[j]) > onset:
                target = math.copysign(onset, a[j])
                t_start = t_prev + (target - a_prev) / (a[j] - a_prev) * (t[j] - t_prev)
                return min(max(t_start, t_prev), t[j]), (1 if a[j] < 0.0 else -1)
            t_prev, a_prev = t[j], a[j]
        return None, 0

    t_now = float(t[0])
    state = np.array([theta0, omega0], dtype=float)
    if theta0 == 0.0 and omega0 == 0.0:
        side = 0
    elif theta0 > 0.0 or (theta0 == 0.0 and omega0 > 0.0):
        side = 1
    else:
        side = -1
    overturned = False
    while t_now < t[-1]:
        if side == 0:
            t_start, side = rest_until(t_now)
            resting = (t >= t_now) & ((t < t_start) if t_start is not None else True)
            theta[resting], omega[resting] = 0.0, 0.0
            if t_start is None:
                break
            t_now, state = t_start, np.array([0.0, 0.0])
            if t_now >= t[-1]:
                break
            continue
        # impact when theta returns to 0 from the current side
        impact.direction = -1.0 if side > 0 else 1.0
        sol = solve_ivp(
            rhs,
            (t_now, t[-1]),
            state,
            method="DOP853",
            args=(side,),
            events=(impact, topple),
            dense_output=True,
            rtol=1e-10,
            atol=1e-12,
            max_step=max_step,
        )
        if not sol.success:
            raise RuntimeError(f"rigid_rocking_response: {sol.message}")
        t_end = float(sol.t[-1])
        inside = (t >= t_now) & (t <= t_end)
        if np.any(inside):
            theta[inside], omega[inside] = sol.sol(t[inside])
        if sol.status == 1 and len(sol.t_events[1]):
            overturned = True
            theta[t > t_end], omega[t > t_end] = np.nan, np.nan
            break
        if sol.status == 1 and len(sol.t_events[0]):
            impacts.append(t_end)
            w = float(sol.y_events[0][0][1]) * math.sqrt(
                r
            )  # thesis Eq. 5.2: r = (w_after / w_before)^2
            theta[t == t_end], omega[t == t_end] = 0.0, w
            t_now = t_end
            if abs(w) < rest_omega:
                side = 0  # chattering has died out
                continue
            side = -side  # pivot switches corner, rotation continues in the same sense
            state = np.array([0.0, w])
            continue
        break
    return RockingResponse(theta, omega, overturned, impacts)


def rigid_rocking_response_compiled(
    time, ground_accel, width, height, r, g=G, rest_omega=1e-8, substeps=16
) -> RockingResponse:
    """:func:`rigid_rocking_response` from rest, by the compiled integrator of
    :mod:`stonedem.reference.rigid_rocking` (classical Runge-Kutta, ``substeps`` steps per sample
    interval, impacts located by bisection), for speed; tests/reference/test_analytic.py holds
    it to the scipy version."""
    from stonedem.reference.rigid_rocking import (
        rocking_history,
    )  # compiled: imported only when used

    t, a = _series(time, ground_accel, strictly_increasing=True)
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"r must be in [0, 1], got {r}")
    if isinstance(substeps, bool) or not (isinstance(substeps, int) and substeps >= 1):
        raise ValueError(f"substeps must be a whole number >= 1, got {substeps!r}")
    blk = rectangle_rocking_properties(width, height, g=g)
    theta = np.empty_like(t)
    omega = np.empty_like(t)
    impacts = np.empty(100_000)
    n_impacts, overturned = rocking_history(
        t,
        a,
        blk.alpha,
        blk.p**2,
        float(g),
        float(r),
        float(rest_omega),
        substeps,
        theta,
        omega,
        impacts,
    )
    return RockingResponse(
        theta, omega, bool(overturned), impacts[: min(n_impacts, len(impacts))].tolist()
    )


# --- 5.1.5 one-sine pulse: exact overturning spectrum (Zhang and Makris 2001) -------------
#
# The pulse is the engine's ``excitation: {kind: sine_pulse, accel: a_p, frequency: f}``,
# a_g(t) = a_p sin(omega_p t) for 0 <= t < T = 2 pi / omega_p and 0 after, with the base at
# rest at t = 0. Zhang and Makris (2001) instead shift the phase of their pulse so that it
# starts at the uplift instant, a_g = a_p sin(omega_p t + psi) with psi = asin(g tan(alpha) /
# a_p); here the block rests until a_g first exceeds g tan(alpha) and the pulse still ends at
# T, so the engine and this reference see the same input (its spectra need not match theirs).
# Energies below are per m g R, so the kinetic energy is 1/2 theta'^2 / p^2 (I_O = m g R /
# p^2) and the potential energy on a pivot is cos(alpha - |theta|), 1 at the crest.

ONE_SINE_MODES = ("none", "impact", "no_impact")  # codes 0, 1, 2 of OneSineSpectrum.mode


class OneSineOutcome(NamedTuple):
    """Fate of a block under one sine pulse; see rigid_one_sine_response."""

    overturned: bool  # |theta| reached pi/2
    mode: str  # "none", "impact" (overturned after >= 1 impact) or "no_impact"
    peak: float  # max |theta| / alpha [-]; pi / (2 alpha) when overturned


def _one_sine_uplift(phase, level):
    """First phase >= ``phase`` of a sine at which |sin| > level (0 < level < 1) within one cycle.

    The block at rest uplifts where |a_g| > g tan(alpha), i.e. |sin(omega_p t)| > level =
    g tan(alpha) / |a_p|: inside (phi1, pi - phi1) (sin > 0) or (pi + phi1, 2 pi - phi1)
    (sin < 0), phi1 = asin(level). Returns (phase of uplift, phase at which that window
    closes [rad], sign of sin there), or (None, None, 0) when |sin| stays below level up to 2 pi.
    """
    phi1 = math.asin(level)
    for start, end, sign in ((phi1, math.pi - phi1, 1), (math.pi + phi1, 2.0 * math.pi - phi1, -1)):
        if phase < end:
            return max(phase, start), end, sign
    return None, None, 0


def _free_rocking_outcome(theta, omega, alpha, p):
    """Free rocking (a_g = 0) from (theta, omega) up to its first impact, decided by energy.

    The pivot is the corner on the side of theta (of omega when theta = 0). Per m g R the
    energy 1/2 theta'^2 / p^2 + cos(alpha - |theta|) is conserved until the next impact
    (Housner 1963; thesis Eq. 5.2), and the potential has its crest, 1, at |theta| = alpha.

    Returns (topples, k0, peak): topples is True when the block falls before returning to
    theta = 0; otherwise k0 is its kinetic energy per m g R on reaching theta = 0 (before the
    impact) and peak the largest |theta| [rad] on the way.
    """
    side = math.copysign(1.0, theta) if theta != 0.0 else math.copysign(1.0, omega)
    a, u = abs(theta), side * omega  # |theta| [rad] and its rate, > 0 outwards [rad s-1]
    k = 0.5 * u * u / p**2  # kinetic energy per m g R [-]
    level = math.cos(alpha - a)  # potential energy per m g R, crest 1 at |theta| = alpha
    excess = k + level - 1.0  # energy above the crest [-]
    if a >= alpha:  # past the crest: falls unless it moves back over it
        if u >= 0.0 or excess <= 0.0:
            return True, 0.0, 0.5 * math.pi
        peak = a
    elif u > 0.0:  # moving outwards: over the crest iff its energy exceeds the crest
        if excess > 0.0:
            return True, 0.0, 0.5 * math.pi
        peak = alpha - math.acos(min(1.0, level + k))  # theta' = 0: cos(alpha - peak) = level + k
    else:
        peak = a
    return False, k + level - math.cos(alpha), peak  # energy at theta = 0


def _one_sine_after_pulse(theta, omega, alpha, p, r, n_impacts, peak) -> OneSineOutcome:
    """Exact fate of a block rocking freely from (theta, omega) after the pulse, by energy.

    Without input, energy is conserved between impacts and each impact keeps a fraction r
    of the kinetic energy (thesis Eq. 5.2). If the block does not fall before its next impact
    it leaves theta = 0 on the other corner with kinetic energy r k0 and falls iff r k0 > 1 -
    cos(alpha), the climb to the crest; if not, the energy at theta = 0 only shrinks (r^n k0)
    and it never falls.

    ``n_impacts`` and ``peak`` [rad]: the impacts and largest |theta| during the pulse.
    Returns the OneSineOutcome of the whole pulse.
    """
    topples, k0, free_peak = _free_rocking_outcome(theta, omega, alpha, p)
    after_impact = False
    if not topples:
        k1 = r * k0  # thesis Eq. 5.2: kinetic energy kept by the impact
        topples = after_impact = k1 > 1.0 - math.cos(alpha)
        free_peak = max(free_peak, alpha - math.acos(min(1.0, math.cos(alpha) + k1)))
    if not topples:
        return OneSineOutcome(False, "none", max(peak, free_peak) / alpha)
    return OneSineOutcome(
        True, "impact" if n_impacts or after_impact else "no_impact", 0.5 * math.pi / alpha
    )


def _check_one_sine_input(a_p, omega_p, r):
    if not 0.0 <= r <= 1.0:
        raise ValueError(f"r must be in [0, 1], got {r}")
    if not (omega_p > 0.0 and math.isfinite(a_p)):
        raise ValueError(f"omega_p must be positive and a_p finite, got {omega_p}, {a_p}")


def rigid_one_sine_response(
    a_p, omega_p, width, height, r, g=G, *, early_stop=True, rest_omega=None, free_time=None
) -> OneSineOutcome:
    """Whether a rigid block overturns under one sine acceleration pulse, exactly.

    The rigid rocking equation of :func:`rigid_rocking_response` (same sign convention:
    theta > 0 on the right corner; Housner 1963, Zhang and Makris 2001) with the pulse
    a_g = a_p sin(omega_p t) for 0 <= t < T = 2 pi / omega_p, 0 after (the engine's
    ``sine_pulse``), the block at rest at t = 0. It stays at rest until |a_g| > g tan(alpha),
    tipping towards theta < 0 when a_g > 0. Integrated with solve_ivp DOP853 (rtol 1e-10,
    atol 1e-12) between events: impact (theta = 0; theta' times sqrt(r), pivot switches),
    topple (|theta| = pi/2), turning points (theta' = 0, for the peak) and the end of the
    pulse, a breakpoint the integrator never steps across. After an impact with |theta'| <
    ``rest_omega`` the block is put at rest and uplifts again where |a_g| > g tan(alpha): the
    chattering it cuts short (impacts accumulating while |a_g| < g tan(alpha)) would end within
    about 2 rest_omega / (p^2 alpha (1 - sqrt(r))), some 1e-4 / p for the default.

    With ``early_stop`` the free rocking after the pulse is not integrated: its outcome
    follows from energy (see _one_sine_after_pulse). Otherwise it is integrated until the
    block falls, settles (rest_omega) or ``free_time`` has passed (default 200 / p).

    Parameters
    ----------
    a_p: pulse amplitude, either sign [m s-2]
    omega_p: pulse circular frequency 2 pi f [rad s-1]
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    r: kinetic energy ratio after/before impact, thesis Eq. 5.2 [-]
    g: gravitational acceleration [m s-2]
    early_stop: decide the free rocking after the pulse by energy instead of integrating it
    rest_omega: |theta'| after an impact below which the block settles to rest; default
        1e-6 p, so that the result does not depend on the block's size [rad s-1]
    free_time: duration of free rocking integrated after the pulse without early_stop [s]

    Returns
    -------
    OneSineOutcome (a tuple) overturned, mode and peak: mode "none" when it does not
    overturn, "impact" when it overturns after at least one impact, "no_impact" when
    without any; peak = max |theta| / alpha [-], pi / (2 alpha) when overturned.
    """
    _check_one_sine_input(a_p, omega_p, r)
    blk = rectangle_rocking_properties(width, height, g=g)
    alpha, p, p2 = blk.alpha, blk.p, blk.p**2
    onset = g * math.tan(alpha)  # uplift threshold |a_g| > g tan(alpha)
    period = 2.0 * math.pi / omega_p
    rest_omega = 1e-6 * p if rest_omega is None else rest_omega
    if abs(a_p) <= onset:
        return OneSineOutcome(False, "none", 0.0)

    def rhs(tt, y, side, pulse):
        th = y[0]
        ag = a_p * math.sin(omega_p * tt) if pulse else 0.0
        if side > 0:  # as in rigid_rocking_response: pivot on the right corner
            return [y[1], -p2 * (math.sin(alpha - th) + ag / g * math.cos(alpha - th))]
        return [y[1], p2 * (math.sin(alpha + th) - ag / g * math.cos(alpha + th))]

    def impact(tt, y, side, pulse):
        return y[0]

    def topple(tt, y, side, pulse):
        return abs(y[0]) - 0.5 * math.pi

    def turn(tt, y, side, pulse):
        return y[1]

    impact.terminal = topple.terminal = True
    t_now, state, side, pulse = 0.0, [0.0, 0.0], 0, True
    t_stop = math.inf if early_stop else period + (200.0 / p if free_time is None else free_time)
    n_impacts, peak, first_step = 0, 0.0, None
    for _ in range(100_000):
        if pulse and t_now >= period:
            pulse = False  # the pulse is over: free rocking (a_g = 0) from here
            if side != 0 and early_stop:
                return _one_sine_after_pulse(*state, alpha, p, r, n_impacts, peak)
        if (side == 0 and not pulse) or t_now >= t_stop:
            return OneSineOutcome(False, "none", peak / alpha)  # at rest for good, or out of time
        if side == 0:  # at rest during the pulse: wait for |a_g| > g tan(alpha)
            phase, closes, sign = _one_sine_uplift(omega_p * t_now, onset / abs(a_p))
            if phase is None:
                return OneSineOutcome(False, "none", peak / alpha)
            t_now, state = phase / omega_p, [0.0, 0.0]
            side = -int(math.copysign(1.0, a_p)) * sign  # a_g > 0 tips the block to theta < 0
            # it cannot come back while |a_g| > g tan(alpha): a first step inside the window
            first_step = 0.1 * (closes - phase) / omega_p
        elif state[0] == 0.0:  # leaving theta = 0 after an impact, at speed |w|
            acc = rhs(t_now, state, side, pulse)[1]
            first_step = 0.1 * abs(state[1] / acc) if acc * side < 0.0 else 1e-3 * period
        t_end = period if pulse else t_stop
        # leaving theta = 0, the first step must end on the block's side: a return within it
        # would put the event's root at the start (where theta = 0 too), not at the return
        first_step = None if first_step is None else min(first_step, 0.5 * (t_end - t_now))
        impact.direction = -1.0 if side > 0 else 1.0  # theta returns to 0 from its side
        turn.direction = impact.direction  # theta' changes from outwards to inwards: a peak
        sol = solve_ivp(
            rhs,
            (t_now, t_end),
            state,
            method="DOP853",
            args=(side, pulse),
            events=(impact, topple, turn),
            rtol=1e-10,
            atol=1e-12,
            first_step=first_step,
        )
        if not sol.success:
            raise RuntimeError(f"rigid_one_sine_response: {sol.message}")
        turns = np.reshape(sol.y_events[2], (-1, 2))[:, 0]  # theta at the peaks of this leg
        peak = max(peak, float(np.abs(sol.y[0]).max()), float(np.abs(turns).max(initial=0.0)))
        t_now, first_step = float(sol.t[-1]), None
        if len(sol.t_events[1]):
            mode = "impact" if n_impacts else "no_impact"
            return OneSineOutcome(True, mode, 0.5 * math.pi / alpha)
        if len(sol.t_events[0]):
            n_impacts += 1
            w = float(sol.y_events[0][0][1]) * math.sqrt(r)  # thesis Eq. 5.2: r = (w+ / w-)^2
            side = 0 if abs(w) < rest_omega else -side  # settled, or the pivot switches corner
            state = [0.0, w if side else 0.0]
        else:  # end of the pulse or of free_time
            state, t_now = [float(sol.y[0, -1]), float(sol.y[1, -1])], t_end
    raise RuntimeError(
        f"rigid_one_sine_response: no end after 100000 legs, a_p {a_p}, omega_p {omega_p}"
    )


ONE_SINE_STEPS = 2000  # RK4 steps per pulse of the compiled one-sine response


def rigid_one_sine_response_compiled(
    a_p, omega_p, width, height, r, g=G, *, rest_omega=None, steps=ONE_SINE_STEPS
) -> OneSineOutcome:
    """:func:`rigid_one_sine_response` (with early stop) by the compiled integrator
    :func:`stonedem.reference.rigid_rocking.one_sine_pulse`: classical Runge-Kutta on ``steps``
    steps per pulse, events by bisection; the free rocking after the pulse decided by energy
    as there. For speed; tests/reference/test_analytic.py holds it to the scipy version."""
    from stonedem.reference.rigid_rocking import PULSE_AT_REST, PULSE_OVERTURNED, one_sine_pulse

    _check_one_sine_input(a_p, omega_p, r)
    if isinstance(steps, bool) or not (isinstance(steps, int) and steps >= 1):
        raise ValueError(f"steps must be a whole number >= 1, got {steps!r}")
    blk = rectangle_rocking_properties(width, height, g=g)
    alpha, p = blk.alpha, blk.p
    if abs(a_p) <= g * math.tan(alpha):
        return OneSineOutcome(False, "none", 0.0)
    rest_omega = 1e-6 * p if rest_omega is None else rest_omega
    how, theta, omega, _side, n_impacts, peak = one_sine_pulse(
        float(a_p), float(omega_p), alpha, p * p, float(g), float(r), float(rest_omega), steps
    )
    if how == PULSE_OVERTURNED:
        return OneSineOutcome(True, "impact" if n_impacts else "no_impact", 0.5 * math.pi / alpha)
    if how == PULSE_AT_REST:
        return OneSineOutcome(False, "none", peak / alpha)
    return _one_sine_after_pulse(theta, omega, alpha, p, r, n_impacts, peak)


class OverturningThreshold(NamedTuple):
    """Minimum overturning one-sine pulse; see rigid_one_sine_min_overturning."""

    amplitude: float  # smallest a_p / (g tan alpha) that overturns [-]; inf if none up to the cap
    mode: str  # "impact" or "no_impact" at that amplitude; "none" if not found


def rigid_one_sine_min_overturning(
    omega_ratio, width, height, r, g=G, rel_tol=1e-4, step=1.01, cap=50.0, compiled=True
) -> OverturningThreshold:
    """Smallest one-sine pulse amplitude that overturns a rigid block (Zhang and Makris 2001).

    Overturning is not monotonic in the amplitude: above the band of overturning after an
    impact there is a safe band before overturning without impact sets in (the two modes of
    Zhang and Makris), and for omega_p / p <~ 1 the lower boundary breaks into narrow
    overturning tongues (0.1 - 1 % of the amplitude wide). So no bisection on [1, cap]
    directly: a hunt A_k = step^k (k = 1, 2, ...) up to ``cap`` finds the first amplitude
    that overturns, then bisection on (A_{k-1}, A_k], whose lower end does not, narrows it
    to rel_tol. A_0 = 1 is safe by construction (no uplift). A tongue narrower than the hunt
    step can be stepped over, and inside the bracket bisection finds one boundary, not
    necessarily the lowest: the result is the minimum as resolved by the hunt grid.

    Parameters
    ----------
    omega_ratio: omega_p / p, pulse circular frequency over the block's frequency parameter [-]
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    r: kinetic energy ratio after/before impact, thesis Eq. 5.2 [-]
    g: gravitational acceleration [m s-2]
    rel_tol: relative width of the final bracket [-]
    step: ratio of successive amplitudes in the hunt (> 1) [-]
    cap: largest amplitude a_p / (g tan alpha) tried [-]
    compiled: each outcome by :func:`rigid_one_sine_response_compiled` (False: by the scipy
        :func:`rigid_one_sine_response`, ~200x slower)

    Returns
    -------
    OverturningThreshold (a tuple) amplitude, the upper end of the final bracket as a_p /
    (g tan alpha) [-] (inf when nothing up to cap overturns), and the mode there.
    """
    if not (omega_ratio > 0.0 and step > 1.0 and rel_tol > 0.0):
        raise ValueError(
            f"omega_ratio, step - 1 and rel_tol must be positive, got "
            f"{omega_ratio}, {step}, {rel_tol}"
        )
    blk = rectangle_rocking_properties(width, height, g=g)
    onset, omega_p = g * math.tan(blk.alpha), omega_ratio * blk.p

    response = rigid_one_sine_response_compiled if compiled else rigid_one_sine_response

    def outcome(amplitude):
        return response(amplitude * onset, omega_p, width, height, r, g=g)

    lo, hi, found = 1.0, 1.0, None
    while found is None and hi < cap:  # hunt: first overturning amplitude on the geometric grid
        lo, hi = hi, min(hi * step, cap)
        res = outcome(hi)
        found = res if res.overturned else None
    if found is None:
        return OverturningThreshold(math.inf, "none")
    while hi - lo > rel_tol * hi:  # bisection on (lo, hi]: lo safe, hi overturns
        mid = 0.5 * (lo + hi)
        res = outcome(mid)
        if res.overturned:
            hi, found = mid, res
        else:
            lo = mid
    return OverturningThreshold(hi, found.mode)


@dataclass
class OneSineSpectrum:
    """Overturning of a rigid block on a grid of one-sine pulses (frequency x amplitude)."""

    omega_ratios: np.ndarray  # omega_p / p [-], shape (n,)
    amplitudes: np.ndarray  # a_p / (g tan alpha) [-], shape (m,)
    overturned: np.ndarray  # bool, shape (n, m)
    mode: np.ndarray  # int8 index into ONE_SINE_MODES: 0 none, 1 impact, 2 no_impact; (n, m)
    peak: np.ndarray  # max |theta| / alpha [-], pi / (2 alpha) where overturned; (n, m)


def rigid_one_sine_spectrum(
    omega_ratios, width, height, r, amplitudes, g=G, compiled=True
) -> OneSineSpectrum:
    """Overturning map of a rigid block under one-sine pulses, for the overturning spectrum.

    Each grid point is one :func:`rigid_one_sine_response` (with early stop), with
    omega_p = omega_ratio p and a_p = amplitude g tan(alpha). The map shows both overturning
    modes and the safe band between them (as in Zhang and Makris 2001, for their pulse).

    Parameters
    ----------
    omega_ratios: omega_p / p values [-]
    width: full width 2b of the block [m]
    height: full height 2h of the block [m]
    r: kinetic energy ratio after/before impact, thesis Eq. 5.2 [-]
    amplitudes: a_p / (g tan alpha) values [-]
    g: gravitational acceleration [m s-2]
    compiled: by :func:`rigid_one_sine_response_compiled` (False: the scipy version)

    Returns
    -------
    OneSineSpectrum with arrays of shape (len(omega_ratios), len(amplitudes)).
    """
    ratios = np.atleast_1d(np.asarray(omega_ratios, dtype=float))
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    blk = rectangle_rocking_properties(width, height, g=g)
    onset = g * math.tan(blk.alpha)
    shape = (len(ratios), len(amps))
    overturned, mode, peak = np.zeros(shape, bool), np.zeros(shape, np.int8), np.zeros(shape)
    response = rigid_one_sine_response_compiled if compiled else rigid_one_sine_response
    for i, ratio in enumerate(ratios):
        for j, amp in enumerate(amps):
            res = response(amp * onset, ratio * blk.p, width, height, r, g=g)
            overturned[i, j], peak[i, j] = res.overturned, res.peak
            mode[i, j] = ONE_SINE_MODES.index(res.mode)
    return OneSineSpectrum(ratios, amps, overturned, mode, peak)


# --- beyond the thesis: earthquake sequences (issue 48) ---------------------------------------


def sequence_pulse_residual_sliding(a_p, T_p, mu, n_pulses, g=G):
    """Residual sliding of a rigid block after each of ``n_pulses`` rectangular pulses in a row.

    Each pulse (a_p for T_p, then 0) is followed by a rest long enough for the block to
    stop (at t_p a_p / (mu g) after the pulse's start, thesis 5.1.3). The block then rests on
    a base moving at a constant velocity, and a rigid-plastic block's motion relative to the
    base is invariant under a translation and a Galilean boost of the base, so each pulse
    adds Newmark's u_max (thesis Eq. 5.5, :func:`newmark_pulse_max_sliding`): the residual
    after pulse k is k u_max.

    Parameters
    ----------
    a_p: pulse amplitude [m s-2]
    T_p: pulse duration [s]
    mu: Coulomb friction coefficient [-]
    n_pulses: number of pulses [-]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    (n_pulses,) residual sliding after each pulse's rest [m].
    """
    u_max = float(newmark_pulse_max_sliding(a_p, T_p, mu, g=g))
    return u_max * np.arange(1, int(n_pulses) + 1, dtype=float)


# --- leaning columns (issue 48: structure.tilt) ------------------------------------------


def leaning_tipping_acceleration(width, height, tilt, toward_lean=True, g=G):
    """Static base acceleration [m s-2] that uplifts a rigid block standing square on a seat
    inclined at ``tilt`` [rad], the base accelerating horizontally.

    The block (full width ``width``, height ``height`` [m], alpha = atan(b/h)) turns about its
    toe once the resultant of gravity and the inertial force passes it: a horizontal
    acceleration a uplifts it toward its lean at a = g tan(alpha - tilt), away from it at
    a = g tan(alpha + tilt) (the inertial force points against a). Vectorised over the
    arguments; NaN where alpha - tilt <= 0 (the block cannot stand) or alpha + tilt >= pi/2.
    """
    alpha = np.arctan2(np.asarray(width, dtype=float), np.asarray(height, dtype=float))
    tilt = np.asarray(tilt, dtype=float)
    angle = alpha - tilt if toward_lean else alpha + tilt
    out = g * np.tan(angle)
    out = np.where((alpha - np.abs(tilt) > 0.0) & (angle < 0.5 * np.pi), out, np.nan)
    return float(out) if out.ndim == 0 else out


def ramp_uplift_rotation(tau, width, height, tilt, rate, toward_lean=True, g=G):
    """Rotation [rad] of a rigid block on a seat inclined at ``tilt`` a time ``tau`` [s] after
    it uplifts under a base acceleration ramp of ``rate`` [m s-3] (linearised about the
    uplift pose).

    Past the threshold a_u (:func:`leaning_tipping_acceleration`) the excess a - a_u = rate tau
    drives the rocking equation, linearised for theta << alpha' (alpha' = alpha -+ tilt, the
    toe's angle from the vertical): theta'' = p^2 theta + q cos(alpha') rate tau, with
    q = m R / I_0 = 3 / (4 R) and p^2 = q g / cos(alpha'). From rest,
    theta = q cos(alpha') rate (sinh(p tau) - p tau) / p^3. A measured rotation threshold is
    reached this long after the uplift; the delay is what a slow ramp adds to the static value.
    """
    alpha = math.atan2(width, height)
    angle = alpha - tilt if toward_lean else alpha + tilt
    q = 3.0 / (2.0 * math.hypot(width, height))  # m R / I_0 about a corner, R = half-diagonal
    p = math.sqrt(q * g / math.cos(angle))
    tau = np.asarray(tau, dtype=float)
    return q * math.cos(angle) * rate * (np.sinh(p * tau) - p * tau) / p**3


# --- shear links (issue 48, thesis 8.3) ----------------------------------------------------


def linked_yield_acceleration(mu, mass, capacity, g=G):
    """Base acceleration at which a block held by friction and a shear link starts to slide.

    The interface resists sliding with Coulomb friction and the link's capacity in parallel
    (thesis 8.3): a_y = (mu m g + V) / m = mu g + V / m.

    Parameters
    ----------
    mu: Coulomb friction coefficient [-]
    mass: block mass [kg]
    capacity: the link's shear capacity V [N]
    g: gravitational acceleration [m s-2]

    Returns
    -------
    a_y [m s-2], shape of the broadcast inputs.
    """
    out = np.asarray(mu, dtype=float) * g + np.asarray(capacity, dtype=float) / mass
    return out[()] if out.ndim == 0 else out


def linked_newmark_max_sliding(a_p, T_p, mu, mass, capacity, g=G):
    """Maximum sliding of a linked rigid block under a rectangular pulse: Eq. 5.5 with the
    resistance of friction and link, a_y = mu g + V / m (:func:`linked_yield_acceleration`).

    u_max = (a_p - a_y) a_p T_p^2 / (2 a_y) where a_p > a_y, else 0 [m]; the link is rigid and
    perfectly plastic (its elastic slip V / k and its clearance are neglected).
    """
    a_y = np.asarray(linked_yield_acceleration(mu, mass, capacity, g), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        u_max = (a_p - a_y) * a_p * T_p**2 / (2.0 * a_y)
    out = np.where(a_p > a_y, u_max, 0.0)
    return out[()] if out.ndim == 0 else out
