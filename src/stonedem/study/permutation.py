"""Layer C of the equivalence test: is a candidate ensemble different from the baseline's?

Rocking near collapse is chaotic, so a change that alters only the last bits of the
arithmetic changes some grid verdicts and Table 7.1 thresholds the way a last-bit
perturbation of k_n does. The candidate's K_N runs (members) are therefore compared with
the baseline's K_B runs as samples: a permutation test over whole runs (a run is one
member's column of grid verdicts and of search thresholds together, which keeps the
correlation between cells inside a run), with two statistics (ENSEMBLES.md section 4,
Layer C):

- S_v = sum_c (pN(c) - pB(c))^2 / (pbar(c) (1 - pbar(c)) + 0.01) over the grid cases, pN
  and pB the groups' collapse fractions, pbar the pooled one (the 0.01 keeps cases every run
  agrees on finite);
- S_T = sum_s |median_N ln T_s - median_B ln T_s| / ln(1 + tolerance_s) over the searched
  systems, in search brackets.

p = (1 + #{S_perm >= S_obs}) / (M + 1) over M label assignments: all C(K_B + K_N, K_N) of
them (the observed one as the "1") when there are at most ``n_permutations``, else M random
ones. Reject if either p <= alpha (0.005 each: family-wise false alarms <= 1 %).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import Field

# A search that found no collapse up to its maximum (threshold NaN) lies above every value
# run; its ln T is +inf. Two infinite medians are the same (shift 0); a finite median against
# an infinite one counts this many brackets: one hunt step (ln 1.8 / ln 1.02 = 29.7, the
# default search's factor and tolerance), the least by which the hunt could have missed it.
NO_COLLAPSE_SHIFT = 30.0
# the floor of S_v's denominator, pbar (1 - pbar) + 0.01 (ENSEMBLES.md section 4)
VERDICT_FLOOR = 0.01
# permuted statistics within this relative distance of the observed one count as ties (>=):
# a permuted sum and the observed one of the same numbers may differ in their last bits
TIE = 1e-9

# the test's settings, as permutation_test and fit_shift_tolerance take them
N_PERMUTATIONS = Field(
    "n_permutations", "integer", range="[1, inf)", default=10_000, hint="give e.g. 10000"
)
ALPHA = Field("alpha", "number", range="(0, 1)", default=0.005, hint="give e.g. 0.005")
RECORDS = Field("n", "number", range="[1, inf)", hint="give the records of the fit")
# the searches' relative bracket, one per system (a scalar is every system's); its length is
# the systems', filled in at the call
TOLERANCE = Field(
    "tolerance", "numbers", range="(0, inf)", hint="give the searches' tolerance, e.g. 0.02"
)

# what the values of a (row, member) group must be: (test, problem, fix)
GROUP_VALUES = {
    "verdicts": (
        lambda a: np.all((a == 0) | (a == 1)),
        "verdicts must be 0 (stands) or 1 (collapsed)",
        "give the collapsed flags",
    ),
    "thresholds": (
        lambda a: not (np.any(a[np.isfinite(a)] <= 0) or np.any(np.isneginf(a))),
        "thresholds must be positive (NaN for no collapse up to the maximum)",
        "give each member's smallest collapsing value",
    ),
}


def _group(name, array, values, rows=None):
    """A (row, member) float array of ``values`` (a key of GROUP_VALUES) with ``rows`` rows
    (when given); a flat empty array is (0, 0)."""
    a = np.asarray(array, dtype=float)
    if a.ndim == 1 and a.size == 0:
        a = a.reshape(0, 0)
    valid, problem, fix = GROUP_VALUES[values]
    if a.ndim != 2:
        problem = f"expected a (row, member) array, got shape {a.shape}"
        fix = "give one column per member"
    elif rows is not None and a.shape[0] != rows:
        problem = f"{a.shape[0]} rows where the other group has {rows}"
        fix = "give both groups the same cases or systems, in the same order"
    elif valid(a):
        return a
    raise InputError(name, problem, fix)


def _verdicts(name, array, rows=None):
    return _group(name, array, "verdicts", rows)


def _thresholds(name, array, rows=None):
    return _group(name, array, "thresholds", rows)


def _log_thresholds(a):
    """ln T with no collapse (NaN or +inf) as +inf."""
    with np.errstate(divide="ignore"):
        return np.log(np.where(np.isnan(a), np.inf, a))


def _tolerances(tolerance, systems):
    """The searches' relative brackets, one per system: ``tolerance`` checked as TOLERANCE."""
    if np.ndim(tolerance) == 0:
        return np.full(systems, dataclasses.replace(TOLERANCE, kind="number").check(tolerance))
    return np.asarray(dataclasses.replace(TOLERANCE, length=systems).check(tolerance))


def _verdict_statistic(pooled, candidate_sums, k_cand, k_base):
    """S_v for many assignments: pooled (case, K) 0/1; candidate_sums (case, M) the
    collapses of the candidate group of each assignment."""
    total = pooled.sum(axis=1, keepdims=True)
    pbar = total / pooled.shape[1]
    p_cand = candidate_sums / k_cand
    p_base = (total - candidate_sums) / k_base
    return np.sum((p_cand - p_base) ** 2 / (pbar * (1.0 - pbar) + VERDICT_FLOOR), axis=0)


def _shift(median_cand, median_base, brackets):
    """|median_N - median_B| / ln(1 + tolerance) with the NO_COLLAPSE_SHIFT convention."""
    both = np.isinf(median_cand) & np.isinf(median_base)
    one = np.isinf(median_cand) ^ np.isinf(median_base)
    with np.errstate(invalid="ignore"):
        shift = np.abs(median_cand - median_base) / brackets
    return np.where(both, 0.0, np.where(one, NO_COLLAPSE_SHIFT, shift))


def verdict_distance(base_collapsed, cand_collapsed) -> float:
    """S_v between two groups' grid verdicts, (case, member) arrays of 0/1; 0 with no cases."""
    base = _verdicts("base_collapsed", base_collapsed)
    cand = _verdicts("cand_collapsed", cand_collapsed, base.shape[0])
    if base.shape[0] == 0:
        return 0.0
    _members(base.shape[1], cand.shape[1])
    pooled = np.concatenate([base, cand], axis=1)
    return float(
        _verdict_statistic(pooled, cand.sum(axis=1, keepdims=True), cand.shape[1], base.shape[1])[0]
    )


def threshold_shifts(base_thresholds, cand_thresholds, tolerance) -> np.ndarray:
    """Each system's term of S_T: |median_N ln T - median_B ln T| in brackets of ``tolerance``
    (a scalar or one per system), from (system, member) arrays. NaN = no collapse up to the
    maximum: +inf before the median, then NO_COLLAPSE_SHIFT for a finite median against an
    infinite one, 0 for two infinite medians. Empty with no systems."""
    base = _thresholds("base_thresholds", base_thresholds)
    cand = _thresholds("cand_thresholds", cand_thresholds, base.shape[0])
    if base.shape[0] == 0:
        return np.zeros(0)
    _members(base.shape[1], cand.shape[1])
    brackets = np.log1p(_tolerances(tolerance, base.shape[0]))
    return _shift(
        np.median(_log_thresholds(cand), axis=1), np.median(_log_thresholds(base), axis=1), brackets
    )


def threshold_shift(base_thresholds, cand_thresholds, tolerance) -> float:
    """S_T between two groups' search thresholds: the sum of :func:`threshold_shifts`."""
    return float(threshold_shifts(base_thresholds, cand_thresholds, tolerance).sum())


def _members(k_base, k_cand, thresholds=None):
    """Each group has a member, and (``thresholds``: the runs of the two groups' threshold
    arrays) the same runs in both of its arrays."""
    field, fix = "members", "give each group at least one member"
    problem = f"{k_base} baseline and {k_cand} candidate members"
    if thresholds is not None and thresholds != (k_base, k_cand):
        field, fix = "base_thresholds", "give both arrays of a group the same runs"
        problem = (
            f"verdicts of {k_base} + {k_cand} runs but thresholds of "
            f"{thresholds[0]} + {thresholds[1]}"
        )
    elif k_base and k_cand:
        return
    raise InputError(field, problem, fix)


def _nth_smallest(sorted_values, picked_ranks, n):
    """The n-th smallest (0-based, per row) of the runs NOT picked: sorted_values (S, K) each
    system's pooled values sorted; picked_ranks (S, M, k) the sorted positions of the picked
    runs, increasing along the last axis. Walks past the picked positions at or below it."""
    position = np.broadcast_to(np.asarray(n), picked_ranks.shape[:2]).astype(np.int64)
    for i in range(picked_ranks.shape[2]):
        position = position + (picked_ranks[:, :, i] <= position)
    return np.take_along_axis(sorted_values, position, axis=1)


def _group_medians(ln_t, picks):
    """np.median over each assignment's candidate runs and over the rest, (S, M) each,
    without gathering the larger group: the pool is sorted once per system and the larger
    group's middle order statistics found by walking past the smaller group's ranks."""
    systems, total = ln_t.shape
    order = np.argsort(ln_t, axis=1, kind="stable")
    sorted_values = np.take_along_axis(ln_t, order, axis=1)
    rank = np.empty_like(order)
    np.put_along_axis(rank, order, np.arange(total)[None, :], axis=1)
    k_small = picks.shape[1]
    small_is_cand = k_small <= total - k_small
    if not small_is_cand:  # pick the complement: the smaller group is walked past
        mask = np.ones((picks.shape[0], total), bool)
        mask[np.arange(picks.shape[0])[:, None], picks] = False
        picks = np.nonzero(mask)[1].reshape(picks.shape[0], total - k_small)
    small_ranks = np.sort(rank[:, picks], axis=2)  # (S, M, k)
    k_small, k_large = small_ranks.shape[2], total - small_ranks.shape[2]

    def middle(values_low, values_high):
        return 0.5 * (values_low + values_high)  # as np.median: (inf + x) / 2 = inf, no NaN

    low, high = (k_small - 1) // 2, k_small // 2
    small = middle(
        np.take_along_axis(sorted_values[:, None, :], small_ranks[:, :, low : low + 1], axis=2)[
            ..., 0
        ],
        np.take_along_axis(sorted_values[:, None, :], small_ranks[:, :, high : high + 1], axis=2)[
            ..., 0
        ],
    )
    large = middle(
        _nth_smallest(sorted_values, small_ranks, (k_large - 1) // 2),
        _nth_smallest(sorted_values, small_ranks, k_large // 2),
    )
    return (small, large) if small_is_cand else (large, small)


def _assignments(total, k_cand, n_permutations, rng):
    """Candidate-label index sets (M, k_cand) of the pooled runs, the observed one (the last
    k_cand) excluded: all others when C(total, k_cand) <= n_permutations, else random ones."""
    count = math.comb(total, k_cand)
    if count <= n_permutations:
        observed = tuple(range(total - k_cand, total))
        combos = [c for c in itertools.combinations(range(total), k_cand) if c != observed]
        return np.array(combos, dtype=np.int64).reshape(-1, k_cand), True, count
    picks = np.argsort(rng.random((n_permutations, total)), axis=1)[:, :k_cand]
    return np.sort(picks, axis=1), False, n_permutations


def permutation_test(
    base_collapsed,
    base_thresholds,
    cand_collapsed,
    cand_thresholds,
    tolerance,
    n_permutations=10_000,
    seed=0,
    alpha=0.005,
) -> dict:
    """The whole-run permutation test of Layer C (ENSEMBLES.md section 4).

    ``base_collapsed`` (case, K_B) and ``cand_collapsed`` (case, K_N): grid verdicts 0/1;
    ``base_thresholds`` (system, K_B) and ``cand_thresholds`` (system, K_N): search
    thresholds (NaN = none); column j of a group's two arrays is one run. ``tolerance``: the
    searches' relative bracket (scalar or per system). Either kind of row may be absent (0
    rows): its statistic is then 0 with p = 1.

    Returns dict(s_v, p_v, s_t, p_t, n_assignments, exact, reject, unanimous_flips, alpha,
    members_base, members_candidate): ``exact`` when all C(K_B + K_N, K_N) assignments were
    enumerated (``n_assignments`` = that number, the observed one included), else
    ``n_assignments`` = ``n_permutations`` random ones; ``unanimous_flips`` the indices of
    cases every baseline run agrees on where some candidate run disagrees (to list, not to
    fail on).
    """
    n_permutations = N_PERMUTATIONS.check(n_permutations)
    alpha = ALPHA.check(alpha)
    base_v = _verdicts("base_collapsed", base_collapsed)
    cand_v = _verdicts("cand_collapsed", cand_collapsed, base_v.shape[0])
    base_t = _thresholds("base_thresholds", base_thresholds)
    cand_t = _thresholds("cand_thresholds", cand_thresholds, base_t.shape[0])
    has_cases, has_systems = base_v.shape[0] > 0, base_t.shape[0] > 0
    if not has_cases and not has_systems:
        return {
            "s_v": 0.0,
            "p_v": 1.0,
            "s_t": 0.0,
            "p_t": 1.0,
            "n_assignments": 0,
            "exact": True,
            "reject": False,
            "unanimous_flips": np.zeros(0, np.int64),
            "alpha": float(alpha),
            "members_base": int(base_v.shape[1] or base_t.shape[1]),
            "members_candidate": int(cand_v.shape[1] or cand_t.shape[1]),
        }
    k_base = base_v.shape[1] if has_cases else base_t.shape[1]
    k_cand = cand_v.shape[1] if has_cases else cand_t.shape[1]
    _members(k_base, k_cand, (base_t.shape[1], cand_t.shape[1]) if has_systems else None)
    total = k_base + k_cand
    picks, exact, n_assignments = _assignments(
        total, k_cand, int(n_permutations), np.random.default_rng(seed)
    )
    # the observed assignment first: the candidates are the last k_cand runs of the pool
    picks = np.concatenate([np.arange(k_base, total)[None, :], picks])

    def p_value(stat):
        observed, permuted = stat[0], stat[1:]
        ties = permuted >= observed - TIE * abs(observed)
        return float((1 + ties.sum()) / (permuted.size + 1))

    s_v, p_v = 0.0, 1.0
    flips = np.zeros(0, np.int64)
    if has_cases:
        pooled = np.concatenate([base_v, cand_v], axis=1)
        pooled = pooled[pooled.min(axis=1) != pooled.max(axis=1)]  # cases all runs agree on add 0
        member_of = np.zeros((total, picks.shape[0]))
        member_of[picks.T, np.arange(picks.shape[0])[None, :]] = 1.0
        stat = _verdict_statistic(pooled, pooled @ member_of, k_cand, k_base)
        s_v, p_v = float(stat[0]), p_value(stat)
        base_rate = base_v.mean(axis=1)
        unanimous = (base_rate == 0) | (base_rate == 1)
        flips = np.flatnonzero(unanimous & np.any(cand_v != base_v[:, :1], axis=1))
    s_t, p_t = 0.0, 1.0
    if has_systems:
        brackets = np.log1p(_tolerances(tolerance, base_t.shape[0]))
        ln_t = _log_thresholds(np.concatenate([base_t, cand_t], axis=1))  # (system, K)
        median_cand, median_base = _group_medians(ln_t, picks)
        stat = _shift(median_cand, median_base, brackets[:, None]).sum(axis=0)
        s_t, p_t = float(stat[0]), p_value(stat)
    return {
        "s_v": s_v,
        "p_v": p_v,
        "s_t": s_t,
        "p_t": p_t,
        "n_assignments": int(n_assignments),
        "exact": bool(exact),
        "reject": bool(p_v <= alpha or p_t <= alpha),
        "unanimous_flips": flips,
        "alpha": float(alpha),
        "members_base": int(k_base),
        "members_candidate": int(k_cand),
    }


def fit_shift_tolerance(n) -> float:
    """How far a fragility fit over ``n`` records may move between code versions, in ln theta
    and in beta: 0.02 sqrt(100 / n) (ENSEMBLES.md section 5: about 8 sd of the measured
    rounding movement, 1/4 of the bootstrap 90 % half-width at n = 100)."""
    return 0.02 * math.sqrt(100.0 / RECORDS.check(n))
