"""Lognormal fragility curves from incremental dynamic analysis (IDA).

IDA gives, per record, the intensity at which a limit state is first exceeded (the collapse
intensity of the hunt-and-fill search, ``dem.threshold_search``), or only a lower bound when
the search reached its maximum without exceeding it (a right-censored value). The fragility
P(exceed | IM = x) = Phi(ln(x / theta) / beta) is fitted by maximum likelihood: with no
censored record the MLE is closed form (Baker 2015, Eq. 5 for the IDA case: ln theta the mean
of ln x_i, beta their standard deviation with 1/n); with censored records the likelihood
adds ln(1 - Phi) terms for them and is maximised numerically. Confidence bands by bootstrap
over records (resampled with replacement, the fit redone).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

from dem.errors import InputError


@dataclass(frozen=True)
class LognormalFit:
    median: float        # theta, in the units of the intensities
    beta: float          # dispersion (standard deviation of ln IM)
    n: int               # records
    censored: int        # of which only a lower bound is known

    def probability(self, x):
        """P(exceed | IM = x)."""
        x = np.asarray(x, dtype=float)
        with np.errstate(divide="ignore"):
            return stats.norm.cdf(np.log(x / self.median) / self.beta)


def _check(intensities, censored):
    x = np.asarray(intensities, dtype=float).ravel()
    c = np.zeros(x.size, bool) if censored is None else np.asarray(censored, dtype=bool).ravel()
    if c.size != x.size:
        raise InputError("censored", f"{c.size} flags for {x.size} intensities", "give one flag per record")
    if x.size < 2 or not np.all(np.isfinite(x) & (x > 0)):
        raise InputError("intensities", "need at least two finite positive intensities",
                         "give the IDA intensity of every record")
    if c.all():
        raise InputError("censored", "every record is censored: no limit state was reached",
                         "raise the search maximum")
    return x, c


def fit_lognormal(intensities, censored=None) -> LognormalFit:
    """MLE of (theta, beta) from per-record IDA intensities; ``censored`` marks lower bounds."""
    x, c = _check(intensities, censored)
    ln = np.log(x)
    mu, sd = ln[~c].mean(), ln[~c].std()
    if not c.any():
        if sd == 0.0:
            raise InputError("intensities", "all records give the same intensity: no dispersion",
                             "give more records")
        return LognormalFit(float(math.exp(mu)), float(sd), x.size, 0)

    def nll(p):
        m, log_b = p
        b = math.exp(log_b)
        z = (ln - m) / b
        return -(np.sum(stats.norm.logpdf(z[~c]) - math.log(b)) + np.sum(stats.norm.logsf(z[c])))

    start = np.array([ln.mean(), math.log(max(ln.std(), 0.05))])
    res = optimize.minimize(nll, start, method="Nelder-Mead",
                            options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
    return LognormalFit(float(math.exp(res.x[0])), float(math.exp(res.x[1])), x.size, int(c.sum()))


def bootstrap_band(intensities, censored=None, grid=None, samples=1000, level=0.90, seed=0):
    """Percentile bootstrap over records: (lo, hi) of theta, beta and of P on ``grid``.

    Resamples whose records are all censored, or all equal, are skipped (counted in 'used')."""
    x, c = _check(intensities, censored)
    rng = np.random.default_rng(seed)
    grid = np.asarray(grid if grid is not None else np.geomspace(x.min() / 2, x.max() * 2, 50), dtype=float)
    thetas, betas, curves = [], [], []
    for _ in range(samples):
        k = rng.integers(0, x.size, x.size)
        try:
            fit = fit_lognormal(x[k], c[k])
        except InputError:
            continue
        thetas.append(fit.median), betas.append(fit.beta), curves.append(fit.probability(grid))
    q = [(1 - level) / 2 * 100, (1 + level) / 2 * 100]
    return {"theta": np.percentile(thetas, q), "beta": np.percentile(betas, q),
            "probability": np.percentile(np.array(curves), q, axis=0), "grid": grid, "used": len(thetas)}


def empirical_points(intensities, censored=None):
    """Sorted exceedance intensities and the fraction of records exceeded at each (i / n)."""
    x, c = _check(intensities, censored)
    order = np.sort(x[~c])
    return order, np.arange(1, order.size + 1) / x.size
