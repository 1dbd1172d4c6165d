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

from stonedem.wall import return_map_kernel as kernel
from stonedem.wall.return_map_kernel import DETACHED, ELASTIC, FLEXURAL, SHEAR, SHEAR_FLEXURAL

STATE_NAMES = {
    ELASTIC: "elastic",
    SHEAR: "shear",
    FLEXURAL: "flexural",
    SHEAR_FLEXURAL: "shear and flexural",
    DETACHED: "detached",
}


@dataclass
class JointStrength:
    """Per-interface strength parameters."""

    mu: np.ndarray
    tensile_strength: np.ndarray  # sigma_t [Pa]
    cohesion: np.ndarray  # c [Pa]
    alpha: np.ndarray  # exponent of Eq. 14
    brittle: bool = False  # True: tensile strength lost at detachment (not the manuscript)
    n_eps: object = 0.0  # [N] smoothing width of the capacities near zero compression
    # Fig. 10 torsion reduction under bending on every joint (False: no-tension joints only)
    torsion_all_joints: bool = True
    # Eq. 13 read literally: both rotational stiffnesses zeroed when one bending component
    # yields. Off by default: it moves no table limit load and stops S23 at its first step
    release_both_rotations: bool = False


@dataclass
class ReturnMap:
    forces: np.ndarray  # (ni, 6) local actions
    plastic: np.ndarray  # (ni, 6) plastic relative displacements
    state: np.ndarray  # (ni,) ELASTIC ... DETACHED
    cracked: np.ndarray  # (ni,) bool: tensile strength lost
    tangent: np.ndarray  # (ni, 6) factors on K-bar: 1 elastic, 0 yielded (Eq. 13-14)


def _flat(*arrays):
    """Broadcast to one shape; returns the shape and contiguous 1-D float copies."""
    b = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in arrays))
    return b[0].shape, [np.ascontiguousarray(x).ravel() for x in b]


def smooth_plus(x, eps):
    """C1 positive part: 0 for x <= 0, x^2 / (2 eps) up to eps, x - eps/2 beyond (eps = 0: max(x,
    0)).

    Regularises the capacities of an interface near zero compression (N_eps): the friction,
    bending and torsion caps then vanish smoothly, without a kink, as a joint opens.
    """
    shape, (x, eps) = _flat(x, eps)
    return kernel.smooth_plus_array(x, eps).reshape(shape)


def project_shear_torsion(r, s, F, M, alpha, k_s, k_m):
    """Closest point of (r, s) >= 0 on the domain (y/M)^alpha + (x/F)^2 <= 1 (Eq. 14).

    Distance in the elastic energy metric (x - r)^2 / k_s + (y - s)^2 / k_m, i.e. Euclidean in
    (f / sqrt(k_s), m3 / sqrt(k_m)): the associated (closest-point) return of perfect
    plasticity. Returns (x, y). For alpha >= 1 the domain is convex; on the boundary arc
    x in [x_lo, min(r, F)] (where y(x) <= s) the squared distance is convex in x, so the
    stationary point is found by bisection. M = 0 (torsion strength lost, e.g. edge contact)
    degenerates continuously to x = min(r, F), y = 0; F = 0 to the origin.
    """
    shape, arrays = _flat(r, s, F, M, alpha, k_s, k_m)
    x, y = kernel.closest_points_shear_torsion(*arrays)
    return x.reshape(shape), y.reshape(shape)


def _state_arguments(d, plastic_old, cracked_old, k):
    return (
        np.ascontiguousarray(d, dtype=float),
        np.ascontiguousarray(plastic_old, dtype=float),
        np.ascontiguousarray(cracked_old, dtype=np.bool_),
        np.ascontiguousarray(k, dtype=float),
    )


def _section_arguments(sec, strength: JointStrength, ni):
    """Per-interface geometry and strength in the order of ``kernel.interface_actions``."""

    def per_interface(v):
        return np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float), (ni,)))

    return (
        per_interface(sec.area),
        np.ascontiguousarray(sec.lever, dtype=float),
        per_interface(sec.width),
        per_interface(sec.depth),
        per_interface(strength.mu),
        per_interface(strength.tensile_strength),
        per_interface(strength.cohesion),
        per_interface(strength.alpha),
        bool(strength.brittle),
        per_interface(strength.n_eps),
        bool(strength.torsion_all_joints),
        bool(strength.release_both_rotations),
    )


def _old_forces(forces_old, d):
    if forces_old is None:
        return np.zeros_like(d)
    return np.ascontiguousarray(forces_old, dtype=float)


def return_map(
    d, plastic_old, cracked_old, k, sec, strength: JointStrength, forces_old=None
) -> ReturnMap:
    """Actions of every interface for local relative displacements ``d`` (ni x 6).

    A pure function of (d, plastic_old, cracked_old, forces_old): within a load step the solver
    calls it with the state of the last converged step, so the result does not depend on the
    iteration path (fully implicit in the normal force). ``forces_old`` (default zero) is what
    a released bending component keeps (``strength.release_both_rotations``).
    """
    d, p, c, k = _state_arguments(d, plastic_old, cracked_old, k)
    f, plastic, tangent, state, cracked = kernel.interface_actions(
        d, p, c, _old_forces(forces_old, d), k, *_section_arguments(sec, strength, len(d))
    )
    return ReturnMap(f, plastic, state, cracked, tangent)


def return_map_derivative(
    d,
    rm: ReturnMap,
    plastic_old,
    cracked_old,
    k,
    sec,
    strength: JointStrength,
    eps,
    forces_old=None,
) -> np.ndarray:
    """(ni, 6, 6) derivative of the forces of ``rm`` (the return map at ``d``): K-bar on elastic
    interfaces, forward differences elsewhere (normal perturbed towards contact), each
    diagonal term at least ``eps`` x K-bar."""
    d, p, c, k = _state_arguments(d, plastic_old, cracked_old, k)
    sec_args = _section_arguments(sec, strength, len(d))
    return kernel.interface_tangents(
        d,
        np.ascontiguousarray(rm.forces, dtype=float),
        np.ascontiguousarray(rm.state),
        p,
        c,
        _old_forces(forces_old, d),
        k,
        *sec_args,
        float(eps),
    )
