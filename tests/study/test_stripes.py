"""Table 7.1 as a probability (stonedem.study.stripes, issue 44): stripes of K members' runs,
the probit a50 by binomial MLE (Baker 2015), its bootstrap band over members, the transition
zone and the stripe completion. Synthetic data only, no engine runs."""

import math

import numpy as np
import pytest
from scipy import optimize, stats

from stonedem.errors import InputError
from stonedem.study.stripes import (
    BETA_MAX,
    BETA_MIN,
    bootstrap_band,
    missing_stripe_runs,
    probit_fit,
    stripes,
    threshold_band,
    transition_zone,
)

A50, BETA = 9.0, 0.08  # an Athens-like cell: a50 9 m/s2, collapse spread over about +-12 %


def _ensemble(rng, k=20, levels=None, a50=A50, beta=BETA):
    """K members each run at every level (complete stripes), collapse drawn from the probit."""
    levels = a50 * np.exp(beta * np.linspace(-2.0, 2.0, 10)) if levels is None else levels
    levels = np.array([float(f"{v:.4g}") for v in levels])  # the search's 4 significant digits
    p = stats.norm.cdf(np.log(levels / a50) / beta)
    collapsed = (rng.random((k, levels.size)) < p).astype(np.int8)
    return np.tile(levels, k), np.repeat(np.arange(k), levels.size), collapsed.ravel()


def _fisher_sd(levels, n, a50, beta):
    """Asymptotic sd of ln a50 and beta from the expected Fisher information of the binomial
    probit in (b0, b1), eta = b0 + b1 ln a, b1 = 1/beta, ln a50 = -b0/b1 (delta method)."""
    x = np.log(levels)
    b1 = 1.0 / beta
    b0 = -b1 * math.log(a50)
    eta = b0 + b1 * x
    w = n * stats.norm.pdf(eta) ** 2 / (stats.norm.cdf(eta) * stats.norm.sf(eta))
    info = np.array([[w.sum(), (w * x).sum()], [(w * x).sum(), (w * x * x).sum()]])
    cov = np.linalg.inv(info)
    g_mu = np.array([-1.0 / b1, b0 / b1**2])
    g_beta = np.array([0.0, -1.0 / b1**2])
    return math.sqrt(g_mu @ cov @ g_mu), math.sqrt(g_beta @ cov @ g_beta)


def _scipy_log_likelihood(levels, n, k, start):
    """The same likelihood maximised by Nelder-Mead on (ln a50, ln beta): the fit's check."""

    def nll(q):
        z = (np.log(levels) - q[0]) / math.exp(q[1])
        return -np.sum(k * stats.norm.logcdf(z) + (n - k) * stats.norm.logsf(z))

    res = optimize.minimize(
        nll, start, method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 5000}
    )
    return -res.fun


def test_probit_fit_recovers_a50_and_beta_within_the_fisher_error():
    # K = 20 members x 10 levels = 200 runs; tolerance 4 asymptotic sd (Fisher information at
    # the true values: sd(ln a50) ~ 0.009, sd(beta) ~ 0.012), over 20 synthetic ensembles
    rng = np.random.default_rng(11)
    z_mu, z_beta = [], []
    for _ in range(20):
        values, members, collapsed = _ensemble(rng)
        levels, n, k = stripes(values, members, collapsed)
        fit = probit_fit(levels, n, k)
        assert fit["status"] == "fitted"
        sd_mu, sd_beta = _fisher_sd(levels, n, A50, BETA)
        assert 0.005 < sd_mu < 0.02 and 0.005 < sd_beta < 0.03
        z_mu.append(math.log(fit["a50"] / A50) / sd_mu)
        z_beta.append((fit["beta"] - BETA) / sd_beta)
        # the MLE itself: no higher likelihood than scipy's optimum, and none lower
        best = _scipy_log_likelihood(levels, n, k, [math.log(fit["a50"]) + 0.05, math.log(0.2)])
        assert fit["log_likelihood"] >= best - 1e-8
    assert np.max(np.abs(z_mu)) < 4 and np.max(np.abs(z_beta)) < 4
    assert abs(np.mean(z_mu)) < 4 / math.sqrt(20)  # unbiased to within 4 sd of the mean


def test_probit_fit_matches_scipy_on_irregular_stripes():
    # unequal runs per level, non-monotone fractions: still the likelihood's maximum
    levels = np.array([7.5, 8.0, 8.4, 9.1, 9.6, 10.1, 11.0])
    n = np.array([3, 8, 8, 20, 20, 6, 2])
    k = np.array([1, 0, 3, 9, 14, 6, 1])
    fit = probit_fit(levels, n, k)
    assert fit["status"] == "fitted" and BETA_MIN < fit["beta"] < BETA_MAX
    best = _scipy_log_likelihood(levels, n, k, [math.log(9.0), math.log(0.1)])
    assert fit["log_likelihood"] == pytest.approx(best, abs=1e-8)


def _threshold_members(rng, k=20, n_levels=10):
    """K members each with a threshold of its own, T_j = a50 exp(beta z_j), run at every level:
    a member's runs are wholly correlated (it collapses at every level >= T_j), as the
    chaotic members of a real cell are more than independent draws per run."""
    levels = np.array(
        [float(f"{v:.4g}") for v in A50 * np.exp(BETA * np.linspace(-2.0, 2.0, n_levels))]
    )
    thresholds = A50 * np.exp(BETA * rng.standard_normal(k))
    collapsed = (levels[None, :] >= thresholds[:, None]).astype(np.int8)
    return np.tile(levels, k), np.repeat(np.arange(k), n_levels), collapsed.ravel()


@pytest.mark.parametrize("make, ensembles", [(_threshold_members, 200), (_ensemble, 100)])
def test_bootstrap_band_covers_the_true_a50(make, ensembles):
    # synthetic ensembles of K = 20 members; the 90 % band over members must cover the true
    # a50 in 80-97 % of them (binomial sd of the rate 2-3 %; the percentile bootstrap of 20
    # units runs a little narrow: 85-90 % measured). Members with thresholds of their own are
    # the case for resampling whole members: resampling runs instead covers 42-60 % of them.
    rng = np.random.default_rng(3)
    covered, widths = 0, []
    for i in range(ensembles):
        values, members, collapsed = make(rng)
        low, high = bootstrap_band(values, members, collapsed, n_boot=400, seed=i)
        covered += low <= A50 <= high
        widths.append(math.log(high / low))
    assert 0.80 <= covered / ensembles <= 0.97
    # about 2 x 1.645 sd of ln a50 wide (0.0285 measured for independent runs)
    assert 0.015 < np.median(widths) < 0.08


def test_bootstrap_band_is_reproducible_and_holds_the_fit():
    values, members, collapsed = _ensemble(np.random.default_rng(5))
    band = bootstrap_band(values, members, collapsed, n_boot=300, seed=7)
    assert band == bootstrap_band(values, members, collapsed, n_boot=300, seed=7)
    fit = probit_fit(*stripes(values, members, collapsed))
    assert band[0] < fit["a50"] < band[1]


def test_no_spread_gives_the_common_bracket():
    # every member survives 8.4 and collapses at 9.1: beta -> 0, a50 the bracket's geometric mean
    values = np.tile([7.0, 8.4, 9.1, 10.0], 5)
    members = np.repeat(np.arange(5), 4)
    collapsed = np.tile([0, 0, 1, 1], 5)
    fit = probit_fit(*stripes(values, members, collapsed))
    assert fit["status"] == "no spread" and fit["beta"] == 0.0
    assert fit["a50"] == pytest.approx(math.sqrt(8.4 * 9.1), rel=1e-12)
    # with one split stripe between: beta -> 0 at that stripe
    collapsed = collapsed.reshape(5, 4).copy()
    collapsed[:2, 1] = 1
    fit = probit_fit(*stripes(values, members, collapsed.ravel()))
    assert fit["status"] == "no spread beyond one stripe" and fit["beta"] == 0.0
    assert fit["a50"] == pytest.approx(8.4, rel=1e-12)
    assert fit["log_likelihood"] == pytest.approx(2 * math.log(0.4) + 3 * math.log(0.6), rel=1e-12)


@pytest.mark.parametrize("flag, status", [(0, "nothing collapsed"), (1, "everything collapsed")])
def test_one_outcome_gives_no_a50(flag, status):
    values, members = np.array([1.0, 1.8, 3.24, 1.0, 1.8]), np.array([0, 0, 0, 1, 1])
    collapsed = np.full(5, flag)
    fit = probit_fit(*stripes(values, members, collapsed))
    assert fit["status"] == status and math.isnan(fit["a50"]) and math.isnan(fit["beta"])
    assert all(math.isnan(v) for v in bootstrap_band(values, members, collapsed, n_boot=50))
    band = threshold_band(
        values, members, collapsed, [np.nan, np.nan] if flag == 0 else [1.0, 1.0], n_boot=50
    )
    assert band["status"] == status and math.isnan(band["a50_low"])
    assert probit_fit([], [], [])["status"] == "no runs"


def test_non_monotone_stripes_stay_within_the_beta_bounds():
    # collapse more frequent at the low end: the best increasing probit is flat, beta on its bound
    fit = probit_fit([2.0, 4.0, 8.0, 16.0], [10, 10, 10, 10], [9, 7, 3, 1])
    assert fit["status"] == "beta at its upper bound" and fit["beta"] == pytest.approx(BETA_MAX)
    assert np.isfinite(fit["a50"]) and np.isfinite(fit["log_likelihood"])


def test_stripes_pool_a_members_repeat_once():
    values = [9.1, 9.1, 9.1, 8.4, 9.1]
    members = [0, 0, 1, 0, 2]  # member 0 ran 9.1 twice (search, then a stripe fill)
    collapsed = [1, 1, 0, 0, 1]
    levels, n, k = stripes(values, members, collapsed)
    assert levels.tolist() == [8.4, 9.1] and n.tolist() == [1, 3] and k.tolist() == [0, 2]
    with pytest.raises(InputError, match="member 0 both collapsed and stood at 9.1"):
        stripes(values, members, [1, 0, 0, 0, 1])


def test_transition_zone():
    # 8.4: 0/3, 9.1: 1/3, 9.6: 3/3, 10.1: 2/3 (a resurrection), 11: 3/3, 12: 1/1
    values = [8.4] * 3 + [9.1] * 3 + [9.6] * 3 + [10.1] * 3 + [11.0] * 3 + [12.0]
    members = [0, 1, 2] * 5 + [1]
    collapsed = [0, 0, 0, 1, 0, 0, 1, 1, 1, 1, 0, 1, 1, 1, 1, 1]
    assert transition_zone(values, members, collapsed) == (9.1, 11.0)
    a_first, a_all = transition_zone(
        values[:-4], members[:-4], collapsed[:-4]
    )  # ends at 10.1 with a survivor
    assert a_first == 9.1 and math.isnan(a_all)
    a_first, a_all = transition_zone([1.0, 2.0], [0, 0], [0, 0])
    assert math.isnan(a_first) and math.isnan(a_all)


def test_missing_stripe_runs_on_a_hand_example():
    # member 0 brackets [1.4, 1.6]; member 1 [2.1, 2.4] with a survivor at 1.8; member 2 found
    # no collapse up to 3.24 (its largest run is its upper end). Zone [1.4, 3.24]; 1.0 lies below.
    runs = {0: [1.0, 1.8, 1.4, 1.6], 1: [1.0, 1.8, 3.24, 2.4, 2.1], 2: [1.0, 1.8, 3.24]}
    values = [v for j in runs for v in runs[j]]
    members = [j for j in runs for _ in runs[j]]
    thresholds, survived = [1.6, 2.4, np.nan], [1.4, 2.1, 3.24]
    expected = [
        (0, 2.1),
        (0, 2.4),
        (0, 3.24),
        (1, 1.4),
        (1, 1.6),
        (2, 1.4),
        (2, 1.6),
        (2, 2.1),
        (2, 2.4),
    ]
    assert missing_stripe_runs(values, members, thresholds, survived) == expected
    # mappings, and explicit member ids, give the same
    assert (
        missing_stripe_runs(
            values,
            members,
            dict(enumerate(thresholds)),
            dict(enumerate(survived)),
            member_ids=[0, 1, 2],
        )
        == expected
    )
    # a member that collapsed at its minimum (no survivor) starts the zone at its smallest run
    extra_values, extra_members = values + [0.5], members + [3]
    missing = missing_stripe_runs(
        extra_values, extra_members, thresholds + [0.5], survived + [np.nan]
    )
    assert (0, 0.5) in missing and (3, 1.0) in missing and (3, 3.24) in missing
    assert (0, 1.0) not in missing  # member 0 ran 1.0
    assert missing_stripe_runs([], [], [], []) == []


def test_threshold_band_summarises_members():
    values, members, collapsed = _ensemble(np.random.default_rng(8), k=5)
    thresholds = [8.4, 9.1, np.nan, 9.1, 10.1]
    band = threshold_band(values, members, collapsed, thresholds, n_boot=200)
    assert band["members"] == 5 and band["status"] == "fitted"
    assert band["threshold_median"] == 9.1 and band["threshold_min"] == 8.4
    assert math.isnan(band["threshold_max"])  # a member found none: the max lies above the maximum
    assert band["threshold_none"] == 1 and band["threshold_distinct"] == 3
    assert band["a50_low"] < band["a50"] < band["a50_high"]
    assert band["a_first"] <= band["a50"] and band["runs"] == values.size
    band = threshold_band(values, members, collapsed, [8.4, np.nan, np.nan, 9.1, np.nan], n_boot=20)
    assert math.isnan(band["threshold_median"]) and band["threshold_min"] == 8.4


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: stripes([1.0, 2.0], [0], [0, 1]), "values"),
        (lambda: stripes([1.0, -2.0], [0, 0], [0, 1]), "values"),
        (lambda: stripes([1.0, 2.0], [0, 0], [0, 2]), "collapsed"),
        (lambda: stripes([1.0, 2.0], [0.5, 0], [0, 1]), "members"),
        (lambda: probit_fit([1.0, 2.0], [2, 2], [1]), "levels"),
        (lambda: probit_fit([1.0, 2.0], [2, 2], [3, 1]), "n_collapses"),
        (lambda: missing_stripe_runs([1.0, 2.0], [0, 1], [2.0], [1.0, 1.0]), "thresholds"),
        (
            lambda: missing_stripe_runs([1.0, 2.0], [0, 1], [2.0, 2.0], [1.0, 1.0], member_ids=[0]),
            "members",
        ),
        (lambda: threshold_band([1.0, 2.0], [0, 1], [0, 1], [2.0]), "thresholds"),
        (lambda: bootstrap_band([1.0, 2.0], [0, 1], [0, 1], n_boot=0), "n_boot"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(InputError) as error:
        call()
    assert str(error.value).startswith(f"{field}:")
