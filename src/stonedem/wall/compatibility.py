"""Interface compatibility matrices H: relative displacements from block DOFs (Eq. 3, A1-A3).

Block DOFs q = (u1, u2, u3, w1, w2, w3). The relative displacement of an interface is the
motion of the second block minus that of the first, both evaluated at the interface
centroid c: d = u_j + w_j x (c - y_j) - u_i - w_i x (c - y_i), and delta = w_j - w_i.
When c is midway between the centres this is manuscript Eq. A1-A3 (``interface_matrix``);
the general form also covers half blocks at the ends and support joints.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from stonedem.wall.panel import SUPPORT, Panel


def skew(r):
    """Matrix S(r) with S(r) w = r x w."""
    r = np.asarray(r, dtype=float)
    out = np.zeros(r.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -r[..., 2], r[..., 1]
    out[..., 1, 0], out[..., 1, 2] = r[..., 2], -r[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -r[..., 1], r[..., 0]
    return out


def interface_matrix(dy1: float, dy2: float) -> np.ndarray:
    """The 6 x 12 H of manuscript Eq. A2-A3 for centres dy = (dy1, dy2) apart."""
    Di = 0.5 * np.array([[0, 0, -dy2], [0, 0, dy1], [dy2, -dy1, 0]])
    Dj = 0.5 * np.array([[0, 0, dy2], [0, 0, -dy1], [-dy2, dy1, 0]])
    eye, zero = np.eye(3), np.zeros((3, 3))
    return np.block([[-eye, -Di, eye, Dj], [zero, -eye, zero, eye]])


def block_blocks(panel: Panel):
    """Per interface the 6 x 6 blocks mapping the first and second block's DOFs to d."""
    ni = panel.n_interfaces
    Hi = np.zeros((ni, 6, 6))
    Hj = np.zeros((ni, 6, 6))
    eye = np.eye(3)
    for H, idx, sign in ((Hi, panel.first, -1.0), (Hj, panel.second, 1.0)):
        real = idx != SUPPORT
        r = panel.centroid[real] - panel.centre[idx[real]]
        # u + w x r = u - S(r) w
        H[real, :3, :3] = sign * eye
        H[real, :3, 3:] = -sign * skew(r)
        H[real, 3:, 3:] = sign * eye
    return Hi, Hj


def panel_compatibility(panel: Panel) -> sp.csr_matrix:
    """Sparse H_panel (6 ni x 6 nb): d_panel = H_panel q_panel (manuscript 2)."""
    Hi, Hj = block_blocks(panel)
    rows, cols, vals = [], [], []
    r6 = np.arange(6)
    for H, idx in ((Hi, panel.first), (Hj, panel.second)):
        for k in np.flatnonzero(idx != SUPPORT):
            rr, cc = np.meshgrid(6 * k + r6, 6 * idx[k] + r6, indexing="ij")
            rows.append(rr.ravel()), cols.append(cc.ravel()), vals.append(H[k].ravel())
    rows, cols, vals = (np.concatenate(x) for x in (rows, cols, vals))
    keep = vals != 0.0
    shape = (6 * panel.n_interfaces, 6 * panel.n_blocks)
    return sp.csr_matrix((vals[keep], (rows[keep], cols[keep])), shape=shape)
