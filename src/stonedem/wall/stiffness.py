"""Interface stiffness (manuscript Eq. 4-5) and the sparse panel stiffness H^T K H.

Each interface is described in its local order (t1, t2, n, b1, b2, tor): two shear
directions, the normal, bending about the axis whose lever arm runs through the thickness
(b1, out-of-plane rocking), bending about e3 (b2, in-plane rocking) and torsion.
``LOCAL_TO_GLOBAL`` maps them to the global components (d1 d2 d3 delta1 delta2 delta3).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from stonedem.wall.panel import Panel

# local (t1, t2, n, b1, b2, tor) -> global component, for normal e1 (0) and e2 (1)
LOCAL_TO_GLOBAL = np.array(
    [
        [1, 2, 0, 4, 5, 3],  # vertical (head) interface, normal e1: manuscript K_v, A_v
        [0, 2, 1, 3, 5, 4],  # horizontal (bed) interface, normal e2: manuscript K_h, A_h
    ]
)


@dataclass
class InterfaceSections:
    """Areas, inertias and characteristic lengths of every interface (manuscript Eq. 5, 9)."""

    area: np.ndarray  # S
    inertia: np.ndarray  # (ni, 2): I_b1 (lever through thickness), I_b2 (lever in plane)
    polar: np.ndarray  # I_b1 + I_b2
    lever: np.ndarray  # (ni, 2): l_c1 = s/2, l_c2 = width/2 (Eq. 9)
    width: np.ndarray
    depth: np.ndarray
    perm: np.ndarray  # (ni, 6) local -> global component


def sections(panel: Panel) -> InterfaceSections:
    w, s = panel.width, panel.depth
    area = w * s
    i1 = w * s**3 / 12.0  # manuscript Eq. 5: I_h1 = (b/2) s^3/12, I_v2 = a s^3/12
    i2 = s * w**3 / 12.0  # I_h3 = s (b/2)^3/12, I_v3 = s a^3/12
    return InterfaceSections(
        area,
        np.stack([i1, i2], 1),
        i1 + i2,
        np.stack([s / 2, w / 2], 1),
        w,
        s,
        LOCAL_TO_GLOBAL[panel.normal_axis],
    )


def local_stiffness(sec: InterfaceSections, k_n, k_t) -> np.ndarray:
    """K-bar = K A in local order (manuscript Eq. 4): k_t S, k_t S, k_n S, k_r I1, k_r I2, k_t J.

    k_r = k_n (manuscript 2); torsion is carried by the shear springs, hence k_t J.
    """
    k_n = np.broadcast_to(k_n, sec.area.shape)
    k_t = np.broadcast_to(k_t, sec.area.shape)
    return np.stack(
        [
            k_t * sec.area,
            k_t * sec.area,
            k_n * sec.area,
            k_n * sec.inertia[:, 0],
            k_n * sec.inertia[:, 1],
            k_t * sec.polar,
        ],
        1,
    )


def to_global_order(local: np.ndarray, perm: np.ndarray) -> np.ndarray:
    out = np.empty_like(local)
    np.put_along_axis(out, perm, local, axis=1)
    return out


def to_local_order(glob: np.ndarray, perm: np.ndarray) -> np.ndarray:
    return np.take_along_axis(glob, perm, axis=1)


def panel_stiffness(H: sp.csr_matrix, k_diag_global: np.ndarray) -> sp.csc_matrix:
    """K_panel = H^T K-bar H with K-bar diagonal (6 ni values), sparse (manuscript Eq. 6)."""
    Kbar = sp.diags(np.asarray(k_diag_global).ravel())
    return (H.T @ Kbar @ H).tocsc()
