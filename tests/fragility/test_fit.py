"""Lognormal fragility fits (stonedem.fragility.fit): maximum likelihood on samples of known law."""

import math

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.fragility.fit import bootstrap_band, empirical_points, fit_lognormal

THETA, BETA = 0.35, 0.45  # a median collapse PGA in g and a typical record-to-record dispersion


def _sample(n, seed):
    return np.exp(np.random.default_rng(seed).normal(math.log(THETA), BETA, n))


def test_closed_form_mle_recovers_the_law():
    fit = fit_lognormal(_sample(4000, 1))
    # standard errors: beta / sqrt(n) on ln theta (0.7 %), beta / sqrt(2 n) on beta (1.1 %)
    assert fit.median == pytest.approx(THETA, rel=0.03) and fit.beta == pytest.approx(
        BETA, rel=0.04
    )
    assert fit.probability(fit.median) == pytest.approx(0.5)


def test_censored_records_are_lower_bounds_not_dropped():
    x = _sample(4000, 2)
    cap = THETA * 1.5  # the search's maximum: above it only "survived"
    censored = x > cap
    fit = fit_lognormal(np.minimum(x, cap), censored)
    assert fit.censored == censored.sum() > 400
    assert fit.median == pytest.approx(THETA, rel=0.03) and fit.beta == pytest.approx(
        BETA, rel=0.05
    )
    naive = fit_lognormal(x[~censored])  # dropping them biases the median low
    assert naive.median < 0.95 * THETA


def test_numerical_mle_equals_the_closed_form_without_censoring():
    x = _sample(50, 3)
    c = np.zeros(50, bool)
    c[0] = True
    x[0] = x.min() / 50  # "not exceeded up to" far below all: no information, no weight
    full = fit_lognormal(x[1:])
    cens = fit_lognormal(x, c)
    assert cens.median == pytest.approx(full.median, rel=1e-3) and cens.beta == pytest.approx(
        full.beta, rel=1e-3
    )


def test_bootstrap_band_holds_the_fit_and_narrows_with_records():
    small, large = _sample(20, 4), _sample(200, 4)
    b20, b200 = bootstrap_band(small, samples=300), bootstrap_band(large, samples=300)
    fit = fit_lognormal(small)
    assert b20["theta"][0] < fit.median < b20["theta"][1]
    assert np.diff(b200["theta"])[0] < 0.5 * np.diff(b20["theta"])[0]
    assert np.all(b20["probability"][0] <= b20["probability"][1])


def test_empirical_points_and_bad_input():
    x, p = empirical_points([0.3, 0.1, 0.2, 0.5], [False, False, False, True])
    assert x.tolist() == [0.1, 0.2, 0.3] and p.tolist() == [0.25, 0.5, 0.75]
    with pytest.raises(InputError, match="intensities"):
        fit_lognormal([0.2, -1.0])
    with pytest.raises(InputError, match="censored"):
        fit_lognormal([0.2, 0.3], [True, True])
