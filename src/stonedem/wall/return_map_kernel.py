"""Compiled interface return mapping (manuscript Eq. 9, 10, 12-14), one interface at a time.

``constitutive.return_map`` is the Python face of ``interface_actions``; the pushover's
consistent tangent is ``interface_tangents`` (forward differences of the same map, all
interfaces in one call). Local order (t1, t2, n, b1, b2, tor); tension positive.
IEEE arithmetic (``error_model="numpy"``): 0 ** negative is inf, not an exception, which
the closest-point search relies on at the pure-shear corner.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from stonedem.io import numba_cache

numba_cache.guard()  # a damaged cache file costs a compile, not the run

ELASTIC, SHEAR, FLEXURAL, SHEAR_FLEXURAL, DETACHED = 0, 1, 2, 3, 4
ROOT_STEPS = 100  # Newton-bisection steps of the closest-point search (a bound: ~6 are taken)
ROOT_TOLERANCE = 1e-15  # its step, and bracket, relative to F


@njit(cache=True, error_model="numpy")
def smooth_plus_scalar(x, eps):
    """C1 positive part: 0 for x <= 0, x^2 / (2 eps) up to eps, x - eps/2 beyond."""
    if x <= 0.0:
        return 0.0
    if x < eps:
        return x * x / (2.0 * eps)
    return x - 0.5 * eps


@njit(cache=True, error_model="numpy")
def torsion_constant_scalar(l1, l2):
    """c_T of an l1 x l2 rectangle: mean distance from its centroid (segment: l/4)."""
    if l1 > 0.0 and l2 > 0.0:
        c = math.hypot(l1, l2)
        # log((p + c) / q) as log1p: accurate for a thin strip (p << q)
        t1 = l1 * l1 / l2 * math.log1p((l2 + l2 * l2 / (c + l1)) / l1)
        t2 = l2 * l2 / l1 * math.log1p((l1 + l1 * l1 / (c + l2)) / l2)
        return (2.0 * c + t1 + t2) / 12.0
    return max(max(l1, 0.0), max(l2, 0.0)) / 4.0


@njit(cache=True, error_model="numpy")
def closest_point_shear_torsion(r, s, F, M, alpha, k_s, k_m):
    """Closest point of (r, s) >= 0 on (y/M)^alpha + (x/F)^2 <= 1 in the metric
    (x - r)^2 / k_s + (y - s)^2 / k_m (associated return, Eq. 14). The distance along the
    boundary arc x in [x_lo, min(r, F)] is convex: its derivative g is increasing, and its
    root is found by Newton's method kept inside a bracket that every step narrows, with a
    bisection wherever Newton would leave the bracket or not halve the step (Numerical
    Recipes' rtsafe; it replaced a plain bisection, measured in docs/notebook.md). Returns
    (x, y)."""
    if not F > 0.0:
        return 0.0, 0.0
    x_hi = min(r, F)
    if not M > 0.0:  # torsion strength lost: pure friction circle
        return x_hi, 0.0
    ratio = s / M
    x_lo = F * math.sqrt(max(1.0 - ratio**alpha, 0.0)) if ratio < 1.0 else 0.0
    lo = min(x_lo, x_hi)
    hi = x_hi
    inv = 1.0 / alpha
    c = -2.0 * M / (alpha * F)
    x = 0.5 * (lo + hi)
    step_before = hi - lo
    step = step_before
    for _ in range(ROOT_STEPS):
        u = x / F
        w = min(max(1.0 - u * u, 0.0), 1.0)
        wi = w**inv
        w1 = wi / w if w > 0.0 else w ** (inv - 1.0)  # w^(1/alpha - 1)
        y = M * wi
        dy = c * u * w1
        g = (x - r) / k_s + (y - s) * dy / k_m
        if not math.isfinite(g) or g > 0.0:  # vertical tangent at the pure-shear corner
            hi = x
        else:
            lo = x
        w2 = w1 / w if w > 0.0 else w ** (inv - 2.0)
        ddy = c / F * (w1 - 2.0 * (inv - 1.0) * u * u * w2)
        dg = 1.0 / k_s + (dy * dy + (y - s) * ddy) / k_m
        x_new = x - g / dg
        if not (math.isfinite(x_new) and lo < x_new < hi) or abs(2.0 * (x_new - x)) > abs(
            step_before
        ):
            x_new = 0.5 * (lo + hi)
        step_before = step
        step = x_new - x
        x = x_new
        if abs(step) <= ROOT_TOLERANCE * F or hi - lo <= ROOT_TOLERANCE * F:
            break
    y = M * min(max(1.0 - (x / F) ** 2, 0.0), 1.0) ** inv
    return x, min(y, s)


@njit(cache=True, error_model="numpy")
def interface_action(
    d,
    p_old,
    cracked_old,
    f_old,
    k,
    area,
    lever0,
    lever1,
    width,
    depth,
    mu,
    sigma_t,
    cohesion,
    alpha,
    brittle,
    n_eps,
    torsion_all,
    release_both,
    f,
    p_new,
    tangent,
):
    """Return map of one interface: fills f, p_new, tangent (6 each); returns (state, cracked).

    ``f_old``: the actions at the last converged step (``release_both``: a bending component
    whose stiffness is released with the other one keeps its value from there, Eq. 13).
    ``torsion_all``: the Fig. 10 torsion reduction under bending on every joint (False: on
    no-tension joints only)."""
    for j in range(6):
        f[j] = k[j] * (d[j] - p_old[j])
        tangent[j] = 1.0
    sig_t = 0.0 if cracked_old else sigma_t
    coh = 0.0 if cracked_old else cohesion
    f_t = sig_t * area
    N = f[2]
    detached = N > f_t
    cracked = cracked_old or (detached and sigma_t > 0.0 and brittle)
    reserve = smooth_plus_scalar(f_t - N, n_eps)  # compressive reserve, N_eps-smoothed

    # rotation conditions, Eq. 9
    flexural = False
    yielded3 = False
    yielded4 = False
    for j, lever in ((3, lever0), (4, lever1)):
        cap = reserve * lever
        if abs(f[j]) > cap:
            f[j] = math.copysign(cap, f[j])
            tangent[j] = 0.0
            flexural = True
            if j == 3:
                yielded3 = True
            else:
                yielded4 = True
    # Eq. 13 read literally: k_r = 0 for both bending components once one yields; the other
    # then keeps its last converged moment (inside its own cap)
    if release_both and flexural:
        for j, lever, own in ((3, lever0, yielded3), (4, lever1, yielded4)):
            if not own:
                cap = reserve * lever
                f[j] = math.copysign(min(abs(f_old[j]), cap), f_old[j])
                tangent[j] = 0.0

    # shear and torsion, Eq. 10, 12, 14; Fig. 10: compressed rectangle of a no-tension joint
    f_su = smooth_plus_scalar(coh * area - mu * N, mu * n_eps)
    w_eff, s_eff = width, depth
    if (f_t <= 0.0 or torsion_all) and reserve > 0.0:
        w_eff = max(width - 2.0 * abs(f[4]) / reserve, 0.0)
        s_eff = max(depth - 2.0 * abs(f[3]) / reserve, 0.0)
    m3u = torsion_constant_scalar(w_eff, s_eff) * f_su
    r = math.hypot(f[0], f[1])
    s = abs(f[5])
    a = 0.0
    if s > 0.0:
        a = (s / m3u) ** alpha if m3u > 0.0 else math.inf
    b = 0.0
    if r > 0.0:
        b = (r / f_su) ** 2 if f_su > 0.0 else math.inf
    sheared = a + b > 1.0
    if sheared:
        x, y = closest_point_shear_torsion(r, s, f_su, m3u, alpha, k[0], k[5])
        scale = x / r if r > 0.0 else 0.0
        f[0] *= scale
        f[1] *= scale
        f[5] = math.copysign(y, f[5])
        tangent[0] = tangent[1] = tangent[5] = 0.0

    # detachment, Eq. 13: everything released, the normal force stays at f_t
    if detached:
        for j in range(6):
            f[j] = 0.0
            tangent[j] = 0.0
        f[2] = f_t
    for j in range(6):
        p_new[j] = d[j] - f[j] / k[j] if k[j] > 0.0 else p_old[j]
    if detached:  # no normal plastic gap: the joint recloses where it opened
        p_new[2] = p_old[2]

    if detached:
        return DETACHED, cracked
    if flexural and sheared:
        return SHEAR_FLEXURAL, cracked
    if flexural:
        return FLEXURAL, cracked
    if sheared:
        return SHEAR, cracked
    return ELASTIC, cracked


@njit(cache=True, error_model="numpy")
def interface_actions(
    d,
    p_old,
    cracked_old,
    f_old,
    k,
    area,
    lever,
    width,
    depth,
    mu,
    sigma_t,
    cohesion,
    alpha,
    brittle,
    n_eps,
    torsion_all,
    release_both,
):
    """Every interface: forces, plastic parts, tangent factors (ni x 6), state, cracked."""
    ni = d.shape[0]
    f = np.empty((ni, 6))
    p_new = np.empty((ni, 6))
    tangent = np.empty((ni, 6))
    state = np.empty(ni, dtype=np.int8)
    cracked = np.empty(ni, dtype=np.bool_)
    for i in range(ni):
        st, cr = interface_action(
            d[i],
            p_old[i],
            cracked_old[i],
            f_old[i],
            k[i],
            area[i],
            lever[i, 0],
            lever[i, 1],
            width[i],
            depth[i],
            mu[i],
            sigma_t[i],
            cohesion[i],
            alpha[i],
            brittle,
            n_eps[i],
            torsion_all,
            release_both,
            f[i],
            p_new[i],
            tangent[i],
        )
        state[i] = st
        cracked[i] = cr
    return f, p_new, tangent, state, cracked


@njit(cache=True, error_model="numpy")
def interface_tangents(
    d,
    f0,
    state,
    p_old,
    cracked_old,
    f_old,
    k,
    area,
    lever,
    width,
    depth,
    mu,
    sigma_t,
    cohesion,
    alpha,
    brittle,
    n_eps,
    torsion_all,
    release_both,
    eps,
):
    """6 x 6 derivative of each interface's return map by forward differences (normal
    perturbed towards contact), diagonal kept >= eps K-bar so the iteration matrix factors.
    An elastic interface (no cap active) has the exact derivative K-bar: no differences."""
    ni = d.shape[0]
    D = np.empty((ni, 6, 6))
    scale = np.empty(6)
    for j in range(6):
        m = 0.0
        for i in range(ni):
            m = max(m, abs(d[i, j]))
        scale[j] = m + 1e-6
    dp = np.empty(6)
    fp = np.empty(6)
    pp = np.empty(6)
    tp = np.empty(6)
    for i in range(ni):
        if state[i] == ELASTIC:
            for j in range(6):
                for m in range(6):
                    D[i, m, j] = 0.0
                D[i, j, j] = k[i, j]
            continue
        for j in range(6):
            h = 1e-7 * scale[j] * (-1.0 if j == 2 else 1.0)
            for m in range(6):
                dp[m] = d[i, m]
            dp[j] += h
            interface_action(
                dp,
                p_old[i],
                cracked_old[i],
                f_old[i],
                k[i],
                area[i],
                lever[i, 0],
                lever[i, 1],
                width[i],
                depth[i],
                mu[i],
                sigma_t[i],
                cohesion[i],
                alpha[i],
                brittle,
                n_eps[i],
                torsion_all,
                release_both,
                fp,
                pp,
                tp,
            )
            for m in range(6):
                D[i, m, j] = (fp[m] - f0[i, m]) / h
        for j in range(6):
            D[i, j, j] = max(D[i, j, j], eps * k[i, j])
    return D


# array forms of the scalar kernels, for the Python API (interface domains, tests)


@njit(cache=True, error_model="numpy")
def smooth_plus_array(x, eps):
    out = np.empty(x.size)
    for i in range(x.size):
        out[i] = smooth_plus_scalar(x[i], eps[i])
    return out


@njit(cache=True, error_model="numpy")
def torsion_constant_array(l1, l2):
    out = np.empty(l1.size)
    for i in range(l1.size):
        out[i] = torsion_constant_scalar(l1[i], l2[i])
    return out


@njit(cache=True, error_model="numpy")
def closest_points_shear_torsion(r, s, F, M, alpha, k_s, k_m):
    x = np.empty(r.size)
    y = np.empty(r.size)
    for i in range(r.size):
        x[i], y[i] = closest_point_shear_torsion(r[i], s[i], F[i], M[i], alpha[i], k_s[i], k_m[i])
    return x, y
