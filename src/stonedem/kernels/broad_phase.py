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


@njit(**NO_ALLOC_OPTIONS)
def sort_by_key(index, key, n):
    """Order index[:n] by key[index[k]], stably, in place (insertion sort: a list kept from
    the last sweep is nearly sorted already, so this is about n comparisons)."""
    for i in range(1, n):
        item = index[i]
        value = key[item]
        j = i - 1
        while j >= 0 and key[index[j]] > value:
            index[j + 1] = index[j]
            j -= 1
        index[j + 1] = item


@njit(**NO_ALLOC_OPTIONS)
def candidate_pairs_into(
    n_body,
    body_driven,
    lo_x,
    lo_y,
    hi_x,
    hi_y,
    margin,
    sweep_axis,
    order,
    pair_a,
    pair_b,
    pair_key,
    pair_order,
):
    """Pairs (a < b) whose bounds, inflated by ``margin`` [m], overlap, into pair_a, pair_b;
    returns their number. Driven-driven pairs are skipped.

    sweep_axis: 0 sorts along x, 1 along y (choose the axis the scene extends along).
    order (n_body,) holds a permutation of the bodies, kept from call to call (sorted here);
    pair_a, pair_b, pair_key, pair_order: buffers of the same length. The pairs come out
    sorted by (a, b), so runs are deterministic whatever the order of ties. If there are more
    pairs than the buffers hold, only their number is right: the caller grows the buffers
    and sweeps again. Nothing is allocated, so the time loop runs without Numba's runtime.
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
    sort_by_key(order, lo_s, n_body)
    capacity = pair_a.shape[0]
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
            if n_pair < capacity:
                a = min(i, j)
                b = max(i, j)
                pair_key[n_pair] = a * n_body + b
                pair_order[n_pair] = n_pair
            n_pair += 1
    if n_pair > capacity:
        return n_pair
    sort_by_key(pair_order, pair_key, n_pair)
    # apply the permutation through the key buffer: keys are unique, a = key // n, b = key % n
    for k in range(n_pair):
        pair_a[k] = pair_key[pair_order[k]]
    for k in range(n_pair):
        key = pair_a[k]
        pair_a[k] = key // n_body
        pair_b[k] = key - (key // n_body) * n_body
    return n_pair


@njit(**JIT_OPTIONS)
def find_candidate_pairs(n_body, body_driven, lo_x, lo_y, hi_x, hi_y, margin, sweep_axis):
    """:func:`candidate_pairs_into` into fresh buffers: pair_a, pair_b (n_pair,) int64, sorted by
    (a, b)."""
    capacity = 4 * n_body + 16
    order = np.arange(n_body)
    while True:
        pa = np.empty(capacity, dtype=np.int64)
        pb = np.empty(capacity, dtype=np.int64)
        key = np.empty(capacity, dtype=np.int64)
        sort = np.empty(capacity, dtype=np.int64)
        n_pair = candidate_pairs_into(
            n_body,
            body_driven,
            lo_x,
            lo_y,
            hi_x,
            hi_y,
            margin,
            sweep_axis,
            order,
            pa,
            pb,
            key,
            sort,
        )
        if n_pair <= capacity:
            return pa[:n_pair].copy(), pb[:n_pair].copy()
        capacity = n_pair
