"""Interface return mapping: elastic-perfectly-plastic actions (manuscript Eq. 9, 10, 12-14).

Local order (t1, t2, n, b1, b2, tor). Forces are K-bar (d - d_p); d_p is the plastic part.
- detachment: f_n > f_t -> all stiffness zero (Eq. 13). Elastic-perfectly plastic (manuscript
  2.2): the normal force stays at the tensile strength f_t, every other action at zero (their
  caps vanish at f_n = f_t). With ``brittle`` set, a mortar joint instead loses its tensile
  strength and cohesion for good (it cracks) and from then on behaves as a dry joint.
- rotation: |m_i| <= (f_t - f_n) l_ci (Eq. 9) -> capped, k_r = 0 (Eq. 13).
- shear and torsion: (|m3|/m3u)^alpha + (f1^2 + f2^2)/f_su^2 <= 1 with f_su = c S - mu f_n
  (Eq. 10 with c = mu sigma_t by default) and m3u = c_T f_su (Eq. 12), c_T of the compressed
  rectangle when bending acts on a no-tension joint (Fig. 10); closest-point return in the
  elastic energy metric (``project_shear_torsion``), k_t = 0 (Eq. 14).
- near zero compression the caps use the C1 positive part of (f_t - f_n) over ``n_eps``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dem.wall.interface import torsion_constant

ELASTIC, SHEAR, FLEXURAL, SHEAR_FLEXURAL, DETACHED = 0, 1, 2, 3, 4
STATE_NAMES = {ELASTIC: "elastic", SHEAR: "shear", FLEXURAL: "flexural",
               SHEAR_FLEXURAL: "shear and flexural", DETACHED: "detached"}


@dataclass
class JointStrength:
    """Per-interface strength parameters."""

    mu: np.ndarray
    tensile_strength: np.ndarray   # sigma_t [Pa]
    cohesion: np.ndarray           # c [Pa]
    alpha: np.ndarray              # exponent of Eq. 14
    brittle: bool = False          # True: tensile strength lost at detachment (not the manuscript)
    n_eps: object = 0.0            # [N] smoothing width of the capacities near zero compression


@dataclass
class ReturnMap:
    forces: np.ndarray       # (ni, 6) local actions
    plastic: np.ndarray      # (ni, 6) plastic relative displacements
    state: np.ndarray        # (ni,) ELASTIC ... DETACHED
    cracked: np.ndarray      # (ni,) bool: tensile strength lost
    tangent: np.ndarray      # (ni, 6) factors on K-bar: 1 elastic, 0 yielded (Eq. 13-14)


def smooth_plus(x, eps):
    """C1 positive part: 0 for x <= 0, x^2 / (2 eps) up to eps, x - eps/2 beyond (eps = 0: max(x, 0)).

    Regularises the capacities of an interface near zero compression (N_eps): the friction,
    bending and torsion caps then vanish smoothly, without a kink, as a joint opens.
    """
    x = np.asarray(x, dtype=float)
    eps = np.broadcast_to(np.asarray(eps, dtype=float), x.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        quad = np.where(eps > 0, x * x / (2 * eps), 0.0)
    return np.where(x <= 0, 0.0, np.where(x < eps, quad, x - eps / 2))


def project_shear_torsion(r, s, F, M, alpha, k_s, k_m, iterations=56):
    """Closest point of (r, s) >= 0 on the domain (y/M)^alpha + (x/F)^2 <= 1 (Eq. 14).

    Distance in the elastic energy metric (x - r)^2 / k_s + (y - s)^2 / k_m, i.e. Euclidean in
    (f / sqrt(k_s), m3 / sqrt(k_m)): the associated (closest-point) return of perfect
    plasticity. Returns (x, y). For alpha >= 1 the domain is convex; on the boundary arc
    x in [x_lo, min(r, F)] (where y(x) <= s) the squared distance is convex in x, so the
    stationary point is found by bisection. M = 0 (torsion strength lost, e.g. edge contact)
    degenerates continuously to x = min(r, F), y = 0; F = 0 to the origin.
    """
    r, s, F, M = (np.asarray(v, dtype=float) for v in (r, s, F, M))
    alpha = np.broadcast_to(np.asarray(alpha, dtype=float), r.shape)
    k_s = np.broadcast_to(np.asarray(k_s, dtype=float), r.shape)
    k_m = np.broadcast_to(np.asarray(k_m, dtype=float), r.shape)
    Fs = np.where(F > 0, F, 1.0)
    Ms = np.where(M > 0, M, 1.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = np.where(M > 0, s / Ms, np.inf)
        x_lo = np.where(ratio < 1, Fs * np.sqrt(np.clip(1 - ratio**alpha, 0, 1)), 0.0)
    x_hi = np.minimum(r, Fs)
    x_lo = np.minimum(x_lo, x_hi)
    lo, hi = x_lo.copy(), x_hi.copy()
    for _ in range(iterations):
        x = 0.5 * (lo + hi)
        u = x / Fs
        w = np.clip(1 - u * u, 0.0, 1.0)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            y = M * w ** (1 / alpha)
            dy = -np.where(M > 0, 2 * M * u / (alpha * Fs) * w ** (1 / alpha - 1), 0.0)
            g = (x - r) / k_s + (y - s) * dy / k_m
        g = np.where(np.isfinite(g), g, np.inf)   # vertical tangent at the pure-shear corner
        up = g > 0
        hi = np.where(up, x, hi)
        lo = np.where(up, lo, x)
    x = 0.5 * (lo + hi)
    x = np.where(M > 0, x, x_hi)
    y = np.where(M > 0, M * np.clip(1 - (x / Fs) ** 2, 0.0, 1.0) ** (1 / alpha), 0.0)
    y = np.minimum(y, s)
    ok = F > 0
    return np.where(ok, x, 0.0), np.where(ok, y, 0.0)


def return_map(d, plastic_old, cracked_old, k, sec, strength: JointStrength) -> ReturnMap:
    """Actions of every interface for local relative displacements ``d`` (ni x 6).

    A pure function of (d, plastic_old, cracked_old): within a load step the solver calls it
    with the plastic state of the last converged step, so the result does not depend on the
    iteration path (fully implicit in the normal force).
    """
    trial = k * (d - plastic_old)
    f = trial.copy()
    tangent = np.ones_like(f)
    area = sec.area
    sig_t = np.where(cracked_old, 0.0, strength.tensile_strength)
    coh = np.where(cracked_old, 0.0, strength.cohesion)
    f_t = sig_t * area
    N = trial[:, 2]
    detached = N > f_t
    cracked = cracked_old | (detached & (strength.tensile_strength > 0) & bool(strength.brittle))
    n_eps = np.broadcast_to(np.asarray(strength.n_eps, dtype=float), N.shape)
    # compressive reserve f_t - f_n, smoothed over n_eps near zero (N_eps regularisation)
    reserve = smooth_plus(f_t - N, n_eps)

    # rotation conditions, Eq. 9
    cap = reserve[:, None] * sec.lever
    over_b = np.abs(trial[:, 3:5]) > cap
    f[:, 3:5] = np.where(over_b, np.sign(trial[:, 3:5]) * cap, trial[:, 3:5])
    tangent[:, 3:5] = np.where(over_b, 0.0, 1.0)

    # shear and torsion, Eq. 10, 12, 14: f_su = c S - mu f_n (= mu (f_t - f_n) for c = mu sigma_t)
    f_su = smooth_plus(coh * area - strength.mu * N, strength.mu * n_eps)
    no_tension = f_t <= 0.0
    # Fig. 10: compressed rectangle of a no-tension joint under bending (eccentricity |m| / N <= l_c)
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.where(reserve[:, None] > 0, np.abs(f[:, 3:5]) / reserve[:, None], 0.0)
    w_eff = np.where(no_tension, np.clip(sec.width - 2 * e[:, 1], 0, None), sec.width)
    s_eff = np.where(no_tension, np.clip(sec.depth - 2 * e[:, 0], 0, None), sec.depth)
    m3u = torsion_constant(w_eff, s_eff) * f_su
    alpha = np.broadcast_to(np.asarray(strength.alpha, dtype=float), N.shape)
    r = np.hypot(trial[:, 0], trial[:, 1])
    s = np.abs(trial[:, 5])
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(s > 0, (s / np.where(m3u > 0, m3u, 1.0)) ** alpha, 0.0)
        a = np.where((s > 0) & ~(m3u > 0), np.inf, a)
        b = np.where(r > 0, (r / np.where(f_su > 0, f_su, 1.0)) ** 2, 0.0)
        b = np.where((r > 0) & ~(f_su > 0), np.inf, b)
    over_s = a + b > 1.0
    if over_s.any():
        i = np.flatnonzero(over_s)
        x, y = project_shear_torsion(r[i], s[i], f_su[i], m3u[i], alpha[i], k[i, 0], k[i, 5])
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(r[i] > 0, x / np.where(r[i] > 0, r[i], 1.0), 0.0)
        f[i, 0] = trial[i, 0] * scale
        f[i, 1] = trial[i, 1] * scale
        f[i, 5] = np.sign(trial[i, 5]) * y
    tangent[:, [0, 1, 5]] = np.where(over_s[:, None], 0.0, 1.0)

    # detachment, Eq. 13: everything released
    f[detached] = 0.0
    f[detached, 2] = f_t[detached]
    tangent[detached] = 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        plastic = np.where(k > 0, d - f / k, plastic_old)
    # a detached joint keeps no normal plastic gap: it recloses where it opened
    plastic[:, 2] = np.where(detached, plastic_old[:, 2], plastic[:, 2])

    state = np.full(len(d), ELASTIC, dtype=np.int8)
    flex = over_b.any(axis=1)
    state[over_s & ~flex] = SHEAR
    state[flex & ~over_s] = FLEXURAL
    state[flex & over_s] = SHEAR_FLEXURAL
    state[detached] = DETACHED
    return ReturnMap(f, plastic, state, cracked, tangent)
