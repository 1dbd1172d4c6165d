"""Running-bond panel builder: blocks, interfaces and supports (manuscript 2, Fig. 1).

Global axes: e1 along the wall length, e2 up, e3 out of plane. Block (i, j) of course j
has its centre at mid-thickness. Courses alternate full-block and half-block starts
(running bond: bed interfaces are half a block wide). A joint thickness e enlarges each
block to its cell (b + e) x (a + e) x s (rigid block plus half the mortar all round).
Interfaces join block ``first`` to block ``second``; index -1 is a fixed rigid support.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SUPPORT = -1  # index of the fixed rigid support (foundation, side wall)
KIND_HEAD, KIND_BED, KIND_SUPPORT = 0, 1, 2
KIND_NAMES = {KIND_HEAD: "head joint", KIND_BED: "bed joint", KIND_SUPPORT: "support joint"}
EDGES = ("base", "top", "left", "right")
_TOL = 1e-9


@dataclass
class Panel:
    """Blocks (centre, size, course) and interfaces (blocks, centroid, normal axis, sides)."""

    block: dict  # a, b, s, joint (thickness e)
    centre: np.ndarray  # (nb, 3) block centres [m]
    size: np.ndarray  # (nb, 3) cell sides along e1, e2, e3 [m]
    course: np.ndarray  # (nb,) course index from the bottom
    first: np.ndarray = field(default=None)  # (ni,) block index (or SUPPORT)
    second: np.ndarray = field(default=None)  # (ni,)
    centroid: np.ndarray = field(default=None)  # (ni, 3) interface centroid [m]
    normal_axis: np.ndarray = field(
        default=None
    )  # (ni,) 0: normal e1 (vertical), 1: e2 (horizontal)
    width: np.ndarray = field(default=None)  # (ni,) in-plane side (along e1 or e2) [m]
    depth: np.ndarray = field(default=None)  # (ni,) side along e3 (the thickness) [m]
    kind: np.ndarray = field(default=None)  # (ni,) KIND_*
    edge: np.ndarray = field(default=None)  # (ni,) edge name for support joints, "" otherwise
    length: float = 0.0
    height: float = 0.0

    @property
    def n_blocks(self) -> int:
        return len(self.centre)

    @property
    def n_interfaces(self) -> int:
        return len(self.first)

    @property
    def volume(self) -> np.ndarray:
        return self.size.prod(axis=1)

    def touching(self, edge: str) -> np.ndarray:
        """Indices of the blocks whose cell lies on an edge of the panel (``base``: the bottom of
        the panel, ``top``, ``left``, ``right``): the only blocks a support on that edge acts on.
        Where an opening reaches the edge, no block is left there for it; the next block inward
        does not touch the edge and is not supported (the first course removed leaves a wall
        hovering above its base, not one standing on it)."""
        lo = self.centre - self.size / 2
        hi = self.centre + self.size / 2
        tol = _TOL * max(self.length, self.height, 1.0)
        if edge == "base":
            return np.flatnonzero(lo[:, 1] <= tol)
        if edge == "top":
            return np.flatnonzero(hi[:, 1] >= self.height - tol)
        if edge == "left":
            return np.flatnonzero(lo[:, 0] <= tol)
        if edge == "right":
            return np.flatnonzero(hi[:, 0] >= self.length - tol)
        raise ValueError(f"unknown edge {edge!r}")

    def edge_blocks(self, edge: str) -> np.ndarray:
        """Indices of the outermost blocks left along an edge: the bottom/top course that is left,
        the first/last block left in each course. Loads on the top of the wall use it; supports
        act only on the blocks that touch the edge (:meth:`touching`)."""
        if edge == "base":
            return np.flatnonzero(self.course == self.course.min())
        if edge == "top":
            return np.flatnonzero(self.course == self.course.max())
        x = self.centre[:, 0]
        out = []
        for c in np.unique(self.course):
            idx = np.flatnonzero(self.course == c)
            out.append(idx[np.argmin(x[idx])] if edge == "left" else idx[np.argmax(x[idx])])
        return np.array(out, dtype=int)


def course_cuts(length: float, pitch: float, offset: float) -> np.ndarray:
    """Block boundaries of one course: 0, offset + k pitch (inside), length."""
    inner = np.arange(offset, length - _TOL, pitch)
    inner = inner[(inner > _TOL) & (inner < length - _TOL)]
    return np.concatenate([[0.0], inner, [length]])


def build_panel(
    a: float,
    b: float,
    s: float,
    blocks_per_course: float,
    courses: int,
    joint_thickness: float = 0.0,
    openings=(),
    first_course_offset: bool = False,
    support_edges=(),
) -> Panel:
    """Running-bond panel of ``courses`` courses, ``blocks_per_course`` (x 0.5) blocks long.

    ``openings``: rectangles {"x": [x0, x1], "y": [y0, y1]} [m]; blocks whose centre falls
    inside are removed. ``support_edges``: edges joined to a fixed support by interfaces
    (the base of a wall standing on a foundation), one support joint for each block that
    touches the edge (:meth:`Panel.touching`).
    """
    p1, p2 = b + joint_thickness, a + joint_thickness
    length, height = blocks_per_course * p1, courses * p2
    centres, sizes, course_idx, spans = [], [], [], []
    for j in range(courses):
        staggered = (j % 2 == 1) != bool(first_course_offset)
        cuts = course_cuts(length, p1, p1 / 2 if staggered else p1)
        for x0, x1 in zip(cuts[:-1], cuts[1:]):
            xc, yc = 0.5 * (x0 + x1), (j + 0.5) * p2
            if any(o["x"][0] < xc < o["x"][1] and o["y"][0] < yc < o["y"][1] for o in openings):
                continue
            centres.append((xc, yc, 0.0))
            sizes.append((x1 - x0, p2, s))
            course_idx.append(j)
            spans.append((x0, x1))
    centre = np.array(centres, dtype=float).reshape(
        -1, 3
    )  # (0, 3) when openings remove every block
    size = np.array(sizes, dtype=float).reshape(-1, 3)
    course = np.array(course_idx, dtype=int)
    spans = np.array(spans, dtype=float).reshape(-1, 2)

    first, second, cen, axis, width, kind, edge = [], [], [], [], [], [], []

    def add(i, k, c, ax, w, kd, ed=""):
        first.append(i), second.append(k), cen.append(c), axis.append(ax), width.append(w)
        kind.append(kd), edge.append(ed)

    by_course = {j: np.flatnonzero(course == j) for j in range(courses)}
    for j, idx in by_course.items():
        idx = idx[np.argsort(spans[idx, 0])]
        for i, k in zip(idx[:-1], idx[1:]):  # head joints: touching neighbours in a course
            if abs(spans[i, 1] - spans[k, 0]) < _TOL:
                add(i, k, (spans[i, 1], (j + 0.5) * p2, 0.0), 0, p2, KIND_HEAD)
        if j + 1 in by_course:  # bed joints: overlaps with the course above
            above = by_course[j + 1]  # left to right, like every course
            for i in idx:
                # only the blocks above whose span can overlap block i (linear, not quadratic, in
                # the blocks per course): x1_k > x0_i and x0_k < x1_i
                first_k = np.searchsorted(spans[above, 1], spans[i, 0] + _TOL, side="right")
                last_k = np.searchsorted(spans[above, 0], spans[i, 1] - _TOL, side="left")
                for k in above[first_k:last_k]:
                    lo, hi = max(spans[i, 0], spans[k, 0]), min(spans[i, 1], spans[k, 1])
                    if hi - lo > _TOL:
                        add(i, k, (0.5 * (lo + hi), (j + 1) * p2, 0.0), 1, hi - lo, KIND_BED)
    panel = Panel(
        {"a": a, "b": b, "s": s, "joint_thickness": joint_thickness},
        centre,
        size,
        course,
        length=length,
        height=height,
    )
    for ed in support_edges:
        for i in panel.touching(ed):  # only blocks on the edge: none where an opening reaches it
            x0, x1 = spans[i]
            y0, y1 = centre[i, 1] - p2 / 2, centre[i, 1] + p2 / 2
            if ed == "base":
                add(SUPPORT, i, (centre[i, 0], y0, 0.0), 1, x1 - x0, KIND_SUPPORT, ed)
            elif ed == "top":
                add(i, SUPPORT, (centre[i, 0], y1, 0.0), 1, x1 - x0, KIND_SUPPORT, ed)
            elif ed == "left":
                add(SUPPORT, i, (x0, centre[i, 1], 0.0), 0, p2, KIND_SUPPORT, ed)
            else:
                add(i, SUPPORT, (x1, centre[i, 1], 0.0), 0, p2, KIND_SUPPORT, ed)
    panel.first = np.array(first, dtype=int)
    panel.second = np.array(second, dtype=int)
    panel.centroid = np.array(cen, dtype=float).reshape(-1, 3)
    panel.normal_axis = np.array(axis, dtype=int)
    panel.width = np.array(width, dtype=float)
    panel.depth = np.full(len(first), float(s))
    panel.kind = np.array(kind, dtype=int)
    panel.edge = np.array(edge, dtype=object)
    return panel
