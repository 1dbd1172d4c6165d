"""Broad phase: candidate body pairs from axis-aligned bounding boxes (thesis 3.6).

Bounds are inflated by a margin and pairs are found by sort-and-sweep along one axis, so a
stack of N drums yields O(N) pairs. The list is kept while no body has moved (translation
plus rotation times bounding radius) more than half the margin since it was built, so the
sweep runs rarely and the narrow phase never misses a pair (a Verlet list).
"""

import numpy as np
from numba import njit

from stonedem.kernels import INLINE_OPTIONS, JIT_OPTIONS, NO_ALLOC_OPTIONS


@njit(**INLINE_OPTIONS)
def body_bounds(n_body, vert_start, world_x, world_y, lo_x, lo_y, hi_x, hi_y):
    """Axis-aligned bounds of every body from its world vertices, written to lo/hi (n_body,) [m]."""
    for b in range(n_body):
        s = vert_start[b]
        e = vert_start[b + 1]
        x0 = world_x[s]
        x1 = world_x[s]
        y0 = world_y[s]
        y1 = world_y[s]
        for k in range(s + 1, e):
            x = world_x[k]
            y = world_y[k]
            if x < x0:
                x0 = x
            if x > x1:
                x1 = x
            if y < y0:
                y0 = y
            if y > y1:
                y1 = y
        lo_x[b] = x0
        lo_y[b] = y0
        hi_x[b] = x1
        hi_y[b] = y1


@njit(**JIT_OPTIONS)
def find_candidate_pairs(n_body, body_driven, lo_x, lo_y, hi_x, hi_y, margin, sweep_axis):
    """Pairs (a < b) whose bounds, inflated by ``margin`` [m], overlap; driven-driven pairs skipped.

    sweep_axis: 0 sorts along x, 1 along y (choose the axis the scene extends along)
    Returns pair_a, pair_b (n_pair,) int64, sorted by (a, b) so runs are deterministic.
    """
    if sweep_axis == 0:
        lo_s = lo_x
        hi_s = hi_x
        lo_o = lo_y
        hi_o = hi_y
    else:
        lo_s = lo_y
        hi_s = hi_y
        lo_o = lo_x
        hi_o = hi_x
    order = np.argsort(lo_s, kind="mergesort")
    capacity = 4 * n_body + 16
    pa = np.empty(capacity, dtype=np.int64)
    pb = np.empty(capacity, dtype=np.int64)
    n_pair = 0
    for oi in range(n_body):
        i = order[oi]
        for oj in range(oi + 1, n_body):
            j = order[oj]
            if lo_s[j] - margin > hi_s[i] + margin:
                break
            if body_driven[i] and body_driven[j]:
                continue
            if lo_o[j] - margin > hi_o[i] + margin or lo_o[i] - margin > hi_o[j] + margin:
                continue
            if n_pair == capacity:
                capacity *= 2
                new_a = np.empty(capacity, dtype=np.int64)
                new_b = np.empty(capacity, dtype=np.int64)
                new_a[:n_pair] = pa[:n_pair]
                new_b[:n_pair] = pb[:n_pair]
                pa = new_a
                pb = new_b
            pa[n_pair] = min(i, j)
            pb[n_pair] = max(i, j)
            n_pair += 1
    key = pa[:n_pair] * n_body + pb[:n_pair]
    sort = np.argsort(key, kind="mergesort")
    return pa[:n_pair][sort].copy(), pb[:n_pair][sort].copy()
