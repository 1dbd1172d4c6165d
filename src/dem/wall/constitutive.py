"""Interface return mapping: elastic-perfectly-plastic actions (manuscript Eq. 9, 10, 12-14).

Local order (t1, t2, n, b1, b2, tor). Forces are K-bar (d - d_p); d_p is the plastic part.
- detachment: f_n > f_t -> all stiffness zero (Eq. 13). Elastic-perfectly plastic (manuscript
  2.2): the normal force stays at the tensile strength f_t, every other action at zero (their
  caps vanish at f_n = f_t). With ``brittle`` set, a mortar joint instead loses its tensile
  strength and cohesion for good (it cracks) and from then on behaves as a dry joint.
- rotation: |m_i| <= (f_t - f_n) l_ci (Eq. 9) -> capped, k_r = 0 (Eq. 13).
- shear and torsion: (|m3|/m3u)^alpha + (f1^2 + f2^2)/f_su^2 <= 1 with f_su = c S - mu f_n
  (Eq. 10 with c = mu sigma_t by default) and m3u = c_T f_su (Eq. 12), c_T of the compressed
  rectangle when bending acts on a no-tension joint (Fig. 10); radial return, k_t = 0 (Eq. 14).
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


@dataclass
class ReturnMap:
    forces: np.ndarray       # (ni, 6) local actions
    plastic: np.ndarray      # (ni, 6) plastic relative displacements
    state: np.ndarray        # (ni,) ELASTIC ... DETACHED
    cracked: np.ndarray      # (ni,) bool: tensile strength lost
    tangent: np.ndarray      # (ni, 6) factors on K-bar: 1 elastic, 0 yielded (Eq. 13-14)


def _scale_to_surface(a, b, alpha):
    """t in (0, 1] with a t^alpha + b t^2 = 1 (a, b >= 0, a + b > 1): radial return."""
    lo, hi = np.zeros_like(a), np.ones_like(a)
    for _ in range(50):
        t = 0.5 * (lo + hi)
        over = a * t**alpha + b * t**2 > 1.0
        hi = np.where(over, t, hi)
        lo = np.where(over, lo, t)
    return lo


def return_map(d, plastic_old, cracked_old, k, sec, strength: JointStrength) -> ReturnMap:
    """Actions of every interface for local relative displacements ``d`` (ni x 6)."""
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

    # rotation conditions, Eq. 9
    reserve = np.maximum(f_t - N, 0.0)
    cap = reserve[:, None] * sec.lever
    over_b = np.abs(trial[:, 3:5]) > cap
    f[:, 3:5] = np.where(over_b, np.sign(trial[:, 3:5]) * cap, trial[:, 3:5])
    tangent[:, 3:5] = np.where(over_b, 0.0, 1.0)

    # shear and torsion, Eq. 10, 12, 14
    f_su = np.maximum(coh * area - strength.mu * N, 0.0)
    no_tension = f_t <= 0.0
    n_abs = np.maximum(-N, 1e-300)
    w_eff = np.where(no_tension, np.clip(sec.width - 2 * np.abs(f[:, 4]) / n_abs, 0, None), sec.width)
    s_eff = np.where(no_tension, np.clip(sec.depth - 2 * np.abs(f[:, 3]) / n_abs, 0, None), sec.depth)
    m3u = torsion_constant(w_eff, s_eff) * f_su
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(m3u > 0, (np.abs(trial[:, 5]) / m3u) ** strength.alpha, np.inf)
        b = np.where(f_su > 0, (trial[:, 0] ** 2 + trial[:, 1] ** 2) / f_su**2, np.inf)
    a = np.where(trial[:, 5] == 0, 0.0, a)
    b = np.where((trial[:, 0] == 0) & (trial[:, 1] == 0), 0.0, b)
    over_s = a + b > 1.0
    finite = np.isfinite(a) & np.isfinite(b)
    t = np.where(over_s & finite, _scale_to_surface(np.where(finite, a, 0), np.where(finite, b, 0),
                                                    strength.alpha), 1.0)
    t = np.where(over_s & ~finite, 0.0, t)
    f[:, [0, 1, 5]] = trial[:, [0, 1, 5]] * t[:, None]
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
