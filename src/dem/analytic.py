"""Reference solutions of thesis 5.1: rigid-block rocking and sliding, slow and exact.

Plain NumPy/SciPy (no Numba): Housner's free-rocking period (Eq. 5.1) and the exact
rigid-block period, impact energy loss (Eq. 5.2-5.4), Newmark's sliding under a
rectangular pulse (Eq. 5.5), the rigid-plastic sliding block integrated exactly under a
piecewise-linear accelerogram, its Bouc-Wen approximation (Eq. 5.6-5.7), and the rigid
rocking equation with impacts under base acceleration (Housner; Zhang and Makris, 5.1.5).

Conventions: a rectangular block of full width ``width`` (2b) and height ``height`` (2h);
R = sqrt(b^2 + h^2), alpha = atan(b/h), I_O = 4/3 m R^2 about a base corner,
p^2 = m g R / I_O = 3 g / (4 R). Rotations here are positive when the block leans onto
its right corner (towards +x); the engine's counter-clockwise angle is the negative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import quad, solve_ivp


@dataclass(frozen=True)
class RockingBlock:
    alpha: float  # slenderness atan(b/h) [rad]
    radius: float  # half diagonal R [m]
    p: float  # frequency parameter sqrt(m g R / I_O) [rad s-1]
    inertia_corner: float  # I_O about a base corner [kg m2]


def rectangle_rocking_properties(width, height, mass=1.0, g=9.81) -> RockingBlock:
    radius = 0.5 * math.hypot(width, height)
    inertia = 4.0 / 3.0 * mass * radius**2
    return RockingBlock(math.atan(width / height), radius, math.sqrt(mass * g * radius / inertia), inertia)


def housner_period_slender(width, height, theta0, g=9.81):
    """Free-rocking period [s] of a slender block, thesis Eq. 5.1: T = 4/p acosh(1 / (1 - theta0/alpha))."""
    blk = rectangle_rocking_properties(width, height, g=g)
    return 4.0 / blk.p * np.arccosh(1.0 / (1.0 - np.asarray(theta0) / blk.alpha))


def rocking_period_exact(width, height, theta0, g=9.81):
    """Free-rocking period [s] of the exact rigid rocking equation I_O theta'' = -m g R sin(alpha - theta).

    T = 4 int_0^theta0 dtheta / theta', with theta'^2 = 2 p^2 [cos(alpha - theta0) - cos(alpha - theta)];
    the substitution theta = theta0 (1 - s^2) removes the endpoint singularity.
    """
    blk = rectangle_rocking_properties(width, height, g=g)
    a, th0 = blk.alpha, float(theta0)

    def integrand(s):
        theta = th0 * (1.0 - s * s)
        # cos(a - th0) - cos(a - theta) = 2 sin(a - (th0 + theta)/2) sin((th0 - theta)/2), no cancellation
        gap = 2.0 * math.sin(a - 0.5 * (th0 + theta)) * math.sin(0.5 * th0 * s * s)
        return 2.0 * th0 * s / math.sqrt(2.0 * blk.p**2 * gap)

    quarter, _ = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-11, limit=200)
    return 4.0 * quarter


def rocking_peak_angles_eq53(width, height, theta0, r, n_impacts):
    """Peak angles theta_0..theta_n [rad] after each impact, thesis Eq. 5.3."""
    alpha = math.atan(width / height)
    n = np.arange(n_impacts + 1)
    return alpha * (1.0 - np.sqrt(1.0 - r**n * (1.0 - (1.0 - theta0 / alpha) ** 2)))


def rocking_half_periods_eq54(width, height, theta0, r, n_impacts, g=9.81):
    """Half-cycle durations [s] after impacts 0..n, thesis Eq. 5.4."""
    blk = rectangle_rocking_properties(width, height, g=g)
    n = np.arange(n_impacts + 1)
    return 2.0 / blk.p * np.arctanh(np.sqrt(r**n * (1.0 - (1.0 - theta0 / blk.alpha) ** 2)))


def restitution_from_peaks(width, height, peaks):
    """Energy ratio of each impact implied by successive peaks through Eq. 5.3."""
    alpha = math.atan(width / height)
    e = 1.0 - (1.0 - np.asarray(peaks) / alpha) ** 2
    return e[1:] / e[:-1]


def restitution_from_peaks_exact(width, height, peaks):
    """Energy ratio of each impact from the exact potential energy at successive peaks."""
    alpha = math.atan(width / height)
    e = np.cos(alpha - np.asarray(peaks)) - math.cos(alpha)
    return e[1:] / e[:-1]


def housner_restitution(width, height):
    """Housner's energy ratio of a rigid block impact, (1 - 3/2 sin^2 alpha)^2 (angular momentum)."""
    alpha = math.atan(width / height)
    return (1.0 - 1.5 * math.sin(alpha) ** 2) ** 2


def newmark_pulse_max_sliding(a_p, T_p, mu, g=9.81):
    """Maximum sliding [m] under a rectangular pulse, thesis Eq. 5.5 (0 when a_p <= mu g)."""
    mu = np.asarray(mu, dtype=float)
    u = a_p * T_p**2 / 2.0 * (a_p / (mu * g) - 1.0)
    return np.where(a_p > mu * g, u, 0.0)


@dataclass
class SlidingResponse:
    u: np.ndarray  # relative displacement, block minus ground [m]
    v: np.ndarray  # relative velocity [m s-1]


def rigid_plastic_sliding(time, ground_accel, mu, g=9.81) -> SlidingResponse:
    """Exact sliding of a rigid block on a rigid plane (Coulomb mu) under piecewise-linear a_g.

    Relative motion u = x_block - x_ground: while sliding with direction s,
    u'' = -a_g(t) - mu g s; while stuck, u' = 0 until |a_g| exceeds mu g. Within each
    sample interval a_g is linear, so v is quadratic and u cubic: stop and start instants
    are found as roots, not by stepping.
    """
    t = np.asarray(time, dtype=float)
    a = np.asarray(ground_accel, dtype=float)
    limit = mu * g
    u_out = np.zeros_like(t)
    v_out = np.zeros_like(t)
    u, v, s = 0.0, 0.0, 0  # s = sliding direction, 0 when stuck
    for i in range(len(t) - 1):
        h = t[i + 1] - t[i]
        a0, k = a[i], (a[i + 1] - a[i]) / h
        tau = 0.0
        while tau < h:
            ag = a0 + k * tau
            if s == 0:
                # stuck: find when |a_g| first exceeds mu g in [tau, h]
                if abs(ag) > limit:
                    s = -1 if ag > 0 else 1
                    continue
                times = _linear_roots(a0, k, limit, tau, h)
                if not times:
                    break
                # |a_g| reaches mu g here and grows: sliding starts from rest
                tau = min(times)
                s = -1 if a0 + k * tau > 0 else 1
                continue
            # sliding with direction s: v(x) = v + c1 x + c2 x^2 with x = tau' - tau
            b0 = -(a0 + k * tau) - limit * s
            c2 = -0.5 * k
            stop = _first_root_quadratic(v, b0, c2, h - tau)
            step = (h - tau) if stop is None else stop
            u += v * step + 0.5 * b0 * step**2 - k * step**3 / 6.0
            v += b0 * step + c2 * step**2
            tau += step
            if stop is not None:
                v = 0.0
                ag = a0 + k * tau
                # restart the other way at once if the ground still overcomes friction
                reverse = -1 if ag > 0 else 1
                s = reverse if abs(ag) > limit and reverse != s else 0
        u_out[i + 1] = u
        v_out[i + 1] = v
    return SlidingResponse(u_out, v_out)


def _linear_roots(a0, k, limit, lo, hi):
    """Instants x in (lo, hi] where a0 + k x = +-limit."""
    out = []
    if k != 0.0:
        for target in (limit, -limit):
            x = (target - a0) / k
            if lo < x <= hi:
                out.append(x)
    return out


def _first_root_quadratic(v0, b, c, length):
    """First x in (0, length] where v0 + b x + c x^2 = 0, or None."""
    roots = []
    if c == 0.0:
        if b != 0.0:
            roots = [-v0 / b]
    else:
        disc = b * b - 4.0 * c * v0
        if disc >= 0.0:
            sq = math.sqrt(disc)
            # numerically stable pair
            q = -0.5 * (b + math.copysign(sq, b)) if b != 0.0 else 0.5 * sq
            roots = [q / c] + ([v0 / q] if q != 0.0 else [])
    roots = sorted(x for x in roots if 1e-15 < x <= length)
    return roots[0] if roots else None


def bouc_wen_sliding(time, ground_accel, mu, u_y=1e-6, gamma=0.5, beta=0.5, n=50, g=9.81) -> SlidingResponse:
    """Sliding block with the Bouc-Wen hysteretic friction of thesis Eq. 5.6-5.7.

    u'' + mu g z = -a_g and u_y z' + gamma |u'| |z|^(n-1) z + beta u' |z|^n - u' = 0. The
    printed Eq. 5.6 reads "mu gamma z'"; the force term is mu g z (Konstantinidis and
    Makris), as implemented here. Stiff: integrated with LSODA.
    """
    t = np.asarray(time, dtype=float)
    a = np.asarray(ground_accel, dtype=float)

    def rhs(tt, y):
        _, v, z = y
        ag = np.interp(tt, t, a)
        az = abs(z)
        dz = (v - gamma * abs(v) * az ** (n - 1) * z - beta * v * az**n) / u_y
        return [v, -ag - mu * g * z, dz]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0, 0.0], method="LSODA", t_eval=t,
                    rtol=1e-8, atol=[1e-10, 1e-10, 1e-8], max_step=float(np.min(np.diff(t))))
    return SlidingResponse(sol.y[0], sol.y[1])


@dataclass
class RockingResponse:
    theta: np.ndarray  # rotation, positive leaning right [rad]; NaN after overturning
    omega: np.ndarray  # [rad s-1]
    overturned: bool
    impact_times: list


def rigid_rocking_response(time, ground_accel, width, height, r, g=9.81, theta0=0.0, omega0=0.0,
                           rest_omega=1e-8) -> RockingResponse:
    """Rocking of a rigid block that cannot slide under horizontal ground acceleration a_g.

    theta > 0 (pivot on the right corner): theta'' = -p^2 [sin(alpha - theta) + a_g/g cos(alpha - theta)];
    theta < 0: theta'' = p^2 [sin(alpha + theta) - a_g/g cos(alpha + theta)]. A ground
    acceleration towards -x pushes the block onto its right corner. From rest, rocking
    starts when |a_g| > g tan(alpha). At each impact (theta = 0) the angular velocity is
    multiplied by sqrt(r), r being the kinetic energy ratio of thesis Eq. 5.2.
    """
    t = np.asarray(time, dtype=float)
    a = np.asarray(ground_accel, dtype=float)
    blk = rectangle_rocking_properties(width, height, g=g)
    alpha, p2 = blk.alpha, blk.p**2
    onset = g * math.tan(alpha)
    theta = np.full_like(t, np.nan)
    omega = np.full_like(t, np.nan)
    impacts: list = []

    def ag(tt):
        return np.interp(tt, t, a)

    def rhs(tt, y, side):
        th = y[0]
        if side > 0:
            acc = -p2 * (math.sin(alpha - th) + ag(tt) / g * math.cos(alpha - th))
        else:
            acc = p2 * (math.sin(alpha + th) - ag(tt) / g * math.cos(alpha + th))
        return [y[1], acc]

    def hit_zero(tt, y, side):
        return y[0]

    def topple(tt, y, side):
        return abs(y[0]) - 0.5 * math.pi

    hit_zero.terminal = True
    topple.terminal = True
    state = np.array([theta0, omega0], dtype=float)
    t_now = t[0]
    side = 0 if theta0 == 0.0 and omega0 == 0.0 else (1 if (theta0 > 0 or (theta0 == 0 and omega0 > 0)) else -1)
    i_next = 0
    overturned = False
    max_step = float(np.min(np.diff(t)))
    while t_now < t[-1]:
        if side == 0:
            # at rest: find the first instant |a_g| > g tan(alpha)
            idx = np.flatnonzero((np.abs(a) > onset) & (t >= t_now))
            while i_next < len(t) and t[i_next] <= t_now:
                theta[i_next], omega[i_next] = 0.0, 0.0
                i_next += 1
            if len(idx) == 0:
                theta[i_next:], omega[i_next:] = 0.0, 0.0
                break
            j = idx[0]
            if j > 0 and t[j - 1] >= t_now:
                target = math.copysign(onset, a[j])
                t_start = t[j - 1] + (target - a[j - 1]) / (a[j] - a[j - 1]) * (t[j] - t[j - 1])
            else:
                t_start = max(t[j], t_now)
            while i_next < len(t) and t[i_next] < t_start:
                theta[i_next], omega[i_next] = 0.0, 0.0
                i_next += 1
            t_now = t_start
            side = 1 if a[j] < 0 else -1
            state = np.array([0.0, 0.0])
            continue
        hit_zero.direction = -1 if side > 0 else 1
        sol = solve_ivp(rhs, (t_now, t[-1]), state, args=(side,), events=(hit_zero, topple),
                        dense_output=True, rtol=1e-10, atol=1e-12, max_step=max_step)
        t_end = sol.t[-1]
        mask = (t >= t_now) & (t <= t_end)
        if np.any(mask):
            y = sol.sol(t[mask])
            theta[mask], omega[mask] = y[0], y[1]
        i_next = int(np.searchsorted(t, t_end, side="right"))
        if sol.status == 1 and len(sol.t_events[1]):
            overturned = True
            break
        if sol.status == 1 and len(sol.t_events[0]):
            impacts.append(float(t_end))
            w = sol.y_events[0][0][1] * math.sqrt(r)
            t_now = t_end
            if abs(w) < rest_omega:
                side = 0
                continue
            side = -side
            state = np.array([0.0, w])
            continue
        break
    return RockingResponse(theta, omega, overturned, impacts)
