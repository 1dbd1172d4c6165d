"""Restraints as linear constraints on the block DOFs, eliminated exactly: q = q0 + T v.

Two kinds of restraint act on a block (DOFs q = (u1, u2, u3, w1, w2, w3) at its centre):

- a *pin* fixes chosen DOFs of the block's centre (``at: centre``: the comb of pins the
  first wave used, one per edge block, alternating between full- and half-block centres);
- a *line* fixes chosen displacement components of every point of a straight line through
  the panel's mid-thickness (``at: edge`` or ``at: offset``): where the line crosses a block
  along a chord P_a P_b, the point displacement u + w x (P - c) is held at both chord ends,
  which holds it along the whole chord (it is linear along the chord). A block on an
  out-of-plane line support can still turn about the line, as a simply supported plate edge.
  ``hold: points`` holds only the middle of each chord: a row of pins on the straight line,
  each block free to turn about any axis through its pin (a line of point bearings, or a
  one-sided support a block can pivot on).

The constraint rows of each block (C_b q_b = 0, at most 12 x 6) are reduced to their null
space by an SVD, so T is block diagonal: 6 x m_b per block (m_b = 6 for a free block). The
solver works in v (K_v = T^T K T, F_v = T^T F): exact elimination, no penalty to tune, and
the factorization is the same size or smaller.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from stonedem.wall.compatibility import skew

RANK_TOLERANCE = 1e-10  # relative singular value below which a constraint row is dependent


@dataclass
class LineRestraint:
    """A straight restraint line along a panel edge, ``distance`` [m] inside it."""

    edge: str  # base, top, left, right
    components: tuple  # displacement components held: 0 e1, 1 e2, 2 e3 (out of plane)
    distance: float = 0.0  # from the panel edge, inwards [m]
    dead_load: bool = False  # also acts while the self-weight is applied
    hold: str = "line"  # "line": every point of the line; "points": the middle of each chord

    def position(self, panel) -> float:
        """The line's coordinate: x for left/right, y for base/top [m]."""
        return {
            "left": self.distance,
            "right": panel.length - self.distance,
            "base": self.distance,
            "top": panel.height - self.distance,
        }[self.edge]

    def chords(self, panel):
        """(block, P_a, P_b) for every block the line crosses: the chord ends [m] (``hold:
        points``: both at the chord's middle, a single pin on the line)."""
        lo = panel.centre - panel.size / 2
        hi = panel.centre + panel.size / 2
        axis = 0 if self.edge in ("left", "right") else 1
        along = 1 - axis
        at = self.position(panel)
        tol = 1e-9 * max(panel.length, panel.height)
        # a line on a cell boundary belongs to the cell inside the panel from it
        inward = self.edge in ("left", "base")
        inside = (
            (lo[:, axis] - tol <= at) & (at < hi[:, axis] - tol)
            if inward
            else (lo[:, axis] + tol < at) & (at <= hi[:, axis] + tol)
        )
        out = []
        for blk in np.flatnonzero(inside):
            a = np.zeros(3)
            b = np.zeros(3)
            a[axis] = b[axis] = at
            a[along], b[along] = lo[blk, along], hi[blk, along]
            if self.hold == "points":
                a = b = 0.5 * (a + b)
            out.append((int(blk), a, b))
        return out


def point_rows(centre, point, components) -> np.ndarray:
    """Rows of the point displacement u + w x (P - c) (components chosen), per block DOF."""
    r = np.asarray(point, dtype=float) - np.asarray(centre, dtype=float)
    full = np.hstack([np.eye(3), -skew(r)])  # u + w x r = u - S(r) w
    return full[list(components)]


def constraint_rows(panel, fixed, lines) -> dict:
    """Block index -> (k, 6) constraint rows: pinned DOFs (``fixed``, 6 nb bool) and lines."""
    rows: dict = {}
    pinned = np.asarray(fixed, dtype=bool).reshape(-1, 6)
    for blk in np.flatnonzero(pinned.any(axis=1)):
        rows.setdefault(int(blk), []).extend(np.eye(6)[pinned[blk]])
    for line in lines:
        for blk, a, b in line.chords(panel):
            for point in (a, b):
                rows.setdefault(blk, []).extend(
                    point_rows(panel.centre[blk], point, line.components)
                )
    return {blk: np.array(r) for blk, r in rows.items()}


def null_space(rows: np.ndarray) -> np.ndarray:
    """Orthonormal basis (6 x m) of {x : rows x = 0}."""
    _, sv, vt = np.linalg.svd(rows)
    rank = int(np.sum(sv > RANK_TOLERANCE * max(sv.max(initial=0.0), 1.0)))
    basis = vt[rank:].T
    basis[np.abs(basis) < 1e-14] = 0.0  # exact zeros: a pinned DOF gives an exactly zero row of T
    return basis


def reduction_matrix(panel, fixed, lines) -> sp.csr_matrix:
    """T (6 nb x m): every displacement satisfying the restraints is T v."""
    nb = panel.n_blocks
    rows = constraint_rows(panel, fixed, lines)
    r_idx, c_idx, vals = [], [], []
    col = 0
    for blk in range(nb):
        if blk in rows:
            basis = null_space(rows[blk])
        else:
            basis = None
        m = 6 if basis is None else basis.shape[1]
        if basis is None:
            r_idx.append(6 * blk + np.arange(6))
            c_idx.append(col + np.arange(6))
            vals.append(np.ones(6))
        elif m:
            rr, cc = np.nonzero(basis)
            r_idx.append(6 * blk + rr)
            c_idx.append(col + cc)
            vals.append(basis[rr, cc])
        col += m
    if not r_idx:
        return sp.csr_matrix((6 * nb, 0))
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(r_idx), np.concatenate(c_idx))), shape=(6 * nb, col)
    )


def restrained_dofs(T: sp.csr_matrix) -> np.ndarray:
    """DOFs that cannot move at all (an all-zero row of T)."""
    return np.diff(T.indptr) == 0
