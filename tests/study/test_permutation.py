"""Layer C of the equivalence test (stonedem.study.permutation, issue 44): the whole-run
permutation test on grid collapse fractions (S_v) and median search thresholds (S_T).
Synthetic ensembles only."""

import itertools
import math
import time

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.study.permutation import (
    NO_COLLAPSE_SHIFT,
    fit_shift_tolerance,
    permutation_test,
    threshold_shift,
    verdict_distance,
)

TOLERANCE = 0.02


def _population(rng, cases=40, systems=6):
    """A study's per-case collapse probabilities (most cases certain, some split, as in the
    K = 7 rounding data: 15 of 309 split) and per-system thresholds and spreads in ln T."""
    p = rng.choice([0.0, 1.0, 0.2, 0.5, 0.8], size=cases, p=[0.45, 0.35, 0.07, 0.06, 0.07])
    return p, np.log(rng.uniform(1.5, 12.0, systems)), rng.uniform(0.005, 0.05, systems)


def _runs(rng, population, k):
    """k exchangeable runs of the population: (collapsed (case, k), thresholds (system, k))."""
    p, ln_t, spread = population
    collapsed = (rng.random((p.size, k)) < p[:, None]).astype(np.int8)
    thresholds = np.exp(ln_t[:, None] + spread[:, None] * rng.standard_normal((ln_t.size, k)))
    return collapsed, np.round(thresholds, 3)


def test_statistics_by_hand():
    base = np.array([[0, 0, 0, 0], [1, 1, 0, 0]])
    cand = np.array([[1, 0], [1, 1]])
    # case 0: pN 1/2, pB 0, pbar 1/6; case 1: pN 1, pB 1/2, pbar 2/3
    expected = 0.25 / (1 / 6 * 5 / 6 + 0.01) + 0.25 / (2 / 3 * 1 / 3 + 0.01)
    assert verdict_distance(base, cand) == pytest.approx(expected, rel=1e-12)
    t_base = np.array(
        [[1.0, 1.1, 1.2, 1.3], [2.0, np.nan, np.nan, np.nan], [np.nan] * 4, [5.0] * 4]
    )
    t_cand = np.array([[1.2, 1.3], [2.0, 2.0], [np.nan, np.nan], [np.nan, 5.0]])
    # system 0: medians of ln T, ln sqrt(1.1 x 1.2) vs ln sqrt(1.2 x 1.3); 1: inf vs ln 2 (no
    # collapse counts NO_COLLAPSE_SHIFT); 2: inf vs inf (0); 3: ln 5 vs (ln 5 + inf) / 2 = inf
    expected = 0.5 * math.log(1.3 / 1.1) / math.log(1.02) + 2 * NO_COLLAPSE_SHIFT
    assert threshold_shift(t_base, t_cand, TOLERANCE) == pytest.approx(expected, rel=1e-12)
    # a tolerance per system weighs each shift in its own brackets
    per_system = threshold_shift(t_base[:1], t_cand[:1], [0.04])
    assert per_system == pytest.approx(0.5 * math.log(1.3 / 1.1) / math.log(1.04), rel=1e-12)


def test_exact_p_values_match_brute_force():
    rng = np.random.default_rng(4)
    base_v, base_t = _runs(rng, _population(rng, cases=12, systems=4), 5)
    cand_v, cand_t = _runs(rng, _population(rng, cases=12, systems=4), 3)
    base_t[1, 2] = np.nan
    result = permutation_test(base_v, base_t, cand_v, cand_t, TOLERANCE)
    assert result["exact"] and result["n_assignments"] == math.comb(8, 3) == 56
    pool_v, pool_t = np.hstack([base_v, cand_v]), np.hstack([base_t, cand_t])
    s_v, s_t = [], []
    for picked in itertools.combinations(range(8), 3):
        rest = [i for i in range(8) if i not in picked]
        s_v.append(verdict_distance(pool_v[:, rest], pool_v[:, list(picked)]))
        s_t.append(threshold_shift(pool_t[:, rest], pool_t[:, list(picked)], TOLERANCE))
    s_v, s_t = np.array(s_v), np.array(s_t)
    observed_v = verdict_distance(base_v, cand_v)
    observed_t = threshold_shift(base_t, cand_t, TOLERANCE)
    assert result["s_v"] == pytest.approx(observed_v, rel=1e-12)
    assert result["s_t"] == pytest.approx(observed_t, rel=1e-12)
    assert result["p_v"] == np.mean(s_v >= observed_v * (1 - 1e-9))
    assert result["p_t"] == np.mean(s_t >= observed_t * (1 - 1e-9))


def test_exchangeable_groups_give_uniform_p_values():
    # 300 synthetic nulls, baseline K_B = 8 and candidate K_N = 4 runs of the same population
    # (C(12, 4) = 495 assignments, all enumerated): the rejection rate at alpha must sit in the
    # binomial band of +-3.5 sd around alpha (ties of the discrete S_v may only lower it)
    rng = np.random.default_rng(1)
    p_v, p_t = [], []
    for _ in range(300):
        population = _population(rng)
        base, cand = _runs(rng, population, 8), _runs(rng, population, 4)
        result = permutation_test(base[0], base[1], cand[0], cand[1], TOLERANCE)
        assert result["exact"] and result["n_assignments"] == 495
        p_v.append(result["p_v"]), p_t.append(result["p_t"])
    p_v, p_t = np.array(p_v), np.array(p_t)
    for alpha in (0.05, 0.25):
        sd = math.sqrt(alpha * (1 - alpha) / 300)
        assert abs(np.mean(p_t <= alpha) - alpha) <= 3.5 * sd
        assert alpha - 5 * sd <= np.mean(p_v <= alpha) <= alpha + 3.5 * sd
    assert np.mean(p_v <= 0.005) <= 0.02 and np.mean(p_t <= 0.005) <= 0.02


def test_planted_differences_are_rejected():
    rng = np.random.default_rng(2)
    population = _population(rng, cases=309, systems=18)
    (base_v, base_t), (cand_v, cand_t) = _runs(rng, population, 20), _runs(rng, population, 4)
    null = permutation_test(base_v, base_t, cand_v, cand_t, TOLERANCE, n_permutations=2000)
    assert not null["reject"] and not null["exact"] and null["n_assignments"] == 2000
    # every threshold 5 brackets up (x 1.02^5)
    shifted = permutation_test(
        base_v, base_t, cand_v, cand_t * 1.02**5, TOLERANCE, n_permutations=2000
    )
    assert shifted["p_t"] <= 0.005 and shifted["reject"]
    assert shifted["s_t"] > null["s_t"] + 18 * 3
    # three cases every baseline run agrees on, flipped in every candidate run
    unanimous = np.flatnonzero(base_v.min(axis=1) == base_v.max(axis=1))
    flipped = cand_v.copy()
    chosen = unanimous[[0, 7, 19]]
    flipped[chosen] = 1 - base_v[chosen, :1]
    result = permutation_test(base_v, base_t, flipped, cand_t, TOLERANCE, n_permutations=2000)
    assert result["p_v"] <= 0.005 and result["reject"]
    assert set(chosen) <= set(result["unanimous_flips"].tolist())
    assert set(result["unanimous_flips"].tolist()) - set(chosen) == set(
        null["unanimous_flips"].tolist()
    )


def test_missing_rows_give_zero_statistics():
    rng = np.random.default_rng(6)
    base_v, base_t = _runs(rng, _population(rng), 6)
    cand_v, cand_t = _runs(rng, _population(rng), 3)
    no_systems = permutation_test(base_v, np.zeros((0, 6)), cand_v, np.zeros((0, 3)), np.zeros(0))
    assert no_systems["s_t"] == 0.0 and no_systems["p_t"] == 1.0 and no_systems["s_v"] > 0
    no_cases = permutation_test(np.zeros((0, 6)), base_t, np.zeros((0, 3)), cand_t, TOLERANCE)
    assert (
        no_cases["s_v"] == 0.0 and no_cases["p_v"] == 1.0 and no_cases["unanimous_flips"].size == 0
    )
    assert no_cases["s_t"] > 0
    nothing = permutation_test([], [], [], [], TOLERANCE)
    assert nothing["p_v"] == nothing["p_t"] == 1.0 and not nothing["reject"]
    assert verdict_distance(np.zeros((0, 4)), np.zeros((0, 2))) == 0.0


def test_ten_thousand_permutations_of_the_full_study_are_fast():
    # 24 runs x 309 cases x 18 systems, 1e4 random assignments: 0.13 s measured on a loaded
    # 2-core machine; a loop over permutations in Python takes > 10 s
    rng = np.random.default_rng(9)
    population = _population(rng, cases=309, systems=18)
    (base_v, base_t), (cand_v, cand_t) = _runs(rng, population, 20), _runs(rng, population, 4)
    start = time.perf_counter()
    result = permutation_test(base_v, base_t, cand_v, cand_t, TOLERANCE)
    assert time.perf_counter() - start < 3.0
    assert result["n_assignments"] == 10_000 and not result["exact"]  # C(24, 4) = 10626 > 1e4


def test_fit_shift_tolerance():
    assert fit_shift_tolerance(100) == pytest.approx(0.02)
    assert fit_shift_tolerance(25) == pytest.approx(0.04)
    assert fit_shift_tolerance(400.0) == pytest.approx(0.01)


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: verdict_distance(np.zeros((3, 4)), np.zeros((2, 2))), "cand_collapsed"),
        (lambda: verdict_distance(np.full((3, 4), 2), np.zeros((3, 2))), "base_collapsed"),
        (lambda: verdict_distance(np.zeros((3, 4)), np.zeros((3, 0))), "members"),
        (lambda: threshold_shift(np.ones((2, 4)), -np.ones((2, 2)), 0.02), "cand_thresholds"),
        (
            lambda: threshold_shift(np.ones((2, 4)), np.ones((2, 2)), [0.02, 0.02, 0.02]),
            "tolerance",
        ),
        (
            lambda: permutation_test(
                np.zeros((3, 4)), np.ones((2, 5)), np.zeros((3, 2)), np.ones((2, 2)), 0.02
            ),
            "base_thresholds",
        ),
        (
            lambda: permutation_test(
                np.zeros((3, 4)),
                np.ones((2, 4)),
                np.zeros((3, 2)),
                np.ones((2, 2)),
                0.02,
                n_permutations=0,
            ),
            "n_permutations",
        ),
        (lambda: fit_shift_tolerance(0), "n"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InputError) as error:
        call()
    assert str(error.value).startswith(f"{field}:")
