"""Broad phase: candidate pairs equal brute force; stacks give O(N) pairs."""

import numpy as np
import pytest

from stonedem.kernels.broad_phase import candidate_pairs_into, find_candidate_pairs


def brute_force(lo, hi, driven, margin):
    pairs = set()
    n = len(lo)
    for i in range(n):
        for j in range(i + 1, n):
            if driven[i] and driven[j]:
                continue
            if np.all(lo[i] - margin <= hi[j] + margin) and np.all(
                lo[j] - margin <= hi[i] + margin
            ):
                pairs.add((i, j))
    return pairs


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("axis", [0, 1])
def test_pairs_equal_brute_force_on_random_boxes(seed, axis):
    rng = np.random.default_rng(seed)
    n = 60
    lo = rng.uniform(0, 10, (n, 2))
    hi = lo + rng.uniform(0.1, 2.0, (n, 2))
    driven = rng.uniform(size=n) < 0.1
    a, b = find_candidate_pairs(
        n, driven, lo[:, 0].copy(), lo[:, 1].copy(), hi[:, 0].copy(), hi[:, 1].copy(), 0.05, axis
    )
    assert set(zip(a.tolist(), b.tolist())) == brute_force(lo, hi, driven, 0.05)
    assert np.all(a < b)


def test_stack_of_drums_has_linear_pair_count():
    for n in (10, 100, 1000):
        lo = np.column_stack([np.zeros(n), np.arange(n) * 0.75])
        hi = lo + [1.0, 0.75]
        a, b = find_candidate_pairs(
            n,
            np.zeros(n, dtype=bool),
            lo[:, 0].copy(),
            lo[:, 1].copy(),
            hi[:, 0].copy(),
            hi[:, 1].copy(),
            0.07,
            1,
        )
        assert len(a) == n - 1, "each drum pairs only with its neighbour"


def test_pairs_come_sorted_and_a_short_buffer_reports_the_full_count():
    rng = np.random.default_rng(7)
    n = 40
    lo = rng.uniform(0, 3, (n, 2))
    hi = lo + rng.uniform(0.5, 2.0, (n, 2))
    args = (
        n,
        np.zeros(n, dtype=bool),
        lo[:, 0].copy(),
        lo[:, 1].copy(),
        hi[:, 0].copy(),
        hi[:, 1].copy(),
        0.05,
        0,
    )
    a, b = find_candidate_pairs(*args)
    keys = a * n + b
    assert len(a) > 4 * n + 16, "dense enough to outgrow the first buffer"
    assert np.array_equal(keys, np.sort(keys)), "sorted by (a, b)"
    short = [np.zeros(10, dtype=np.int64) for _ in range(4)]
    assert candidate_pairs_into(*args, np.arange(n), *short) == len(a)
    # a permutation kept from an earlier sweep gives the same list
    full = [np.zeros(len(a), dtype=np.int64) for _ in range(4)]
    assert candidate_pairs_into(*args, rng.permutation(n), *full) == len(a)
    assert np.array_equal(full[0], a) and np.array_equal(full[1], b)
