"""Lognormal fragility curves from incremental dynamic analysis (IDA).

IDA gives, per record, the intensity at which a limit state is first exceeded (the collapse
intensity of the hunt-and-fill search, ``stonedem.study.search``), or only a lower bound when
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
from scipy import optimize, special

from stonedem.errors import InputError

# ln of the standard normal density's constant, as scipy.stats.norm computes it: the
# likelihood below calls the ufuncs that norm.logpdf, logsf and cdf call, without their
# ~50 us of argument checks a call (a bootstrap makes ~10^5 of them; the same numbers)
LOG_NORM_C = np.log(np.sqrt(2 * np.pi))


@dataclass(frozen=True)
class LognormalFit:
    median: float  # theta, in the units of the intensities
    beta: float  # dispersion (standard deviation of ln IM)
    n: int  # records
    censored: int  # of which only a lower bound is known

    def probability(self, x):
        """P(exceed | IM = x)."""
        x = np.asarray(x, dtype=float)
        with np.errstate(divide="ignore"):
            return special.ndtr(np.log(x / self.median) / self.beta)


def _check(intensities, censored):
    """(intensities, censored flags) as flat arrays, or the InputError of the first problem."""
    x = np.asarray(intensities, dtype=float).ravel()
    c = np.zeros(x.size, bool) if censored is None else np.asarray(censored, dtype=bool).ravel()
    if c.size != x.size:
        field, problem, fix = (
            "censored",
            f"{c.size} flags for {x.size} intensities",
            "give one flag per record",
        )
    elif x.size < 2 or not np.all(np.isfinite(x) & (x > 0)):
        field, problem, fix = (
            "intensities",
            "need at least two finite positive intensities",
            "give the IDA intensity of every record",
        )
    elif c.all():
        field, problem, fix = (
            "censored",
            "every record is censored: no limit state was reached",
            "raise the search maximum",
        )
    else:
        return x, c
    raise InputError(field, problem, fix)


def fit_lognormal(intensities, censored=None) -> LognormalFit:
    """MLE of (theta, beta) from per-record IDA intensities; ``censored`` marks lower bounds."""
    x, c = _check(intensities, censored)
    ln = np.log(x)
    mu, sd = ln[~c].mean(), ln[~c].std()
    if not c.any():
        if sd == 0.0:
            raise InputError(
                "intensities",
                "all records give the same intensity: no dispersion",
                "give more records",
            )
        return LognormalFit(float(math.exp(mu)), float(sd), x.size, 0)

    def nll(p):
        m, log_b = p
        b = math.exp(log_b)
        z = (ln - m) / b
        # norm.logpdf(z) is -z**2 / 2 - LOG_NORM_C; norm.logsf(z) is log_ndtr(-z)
        return -(
            np.sum((-(z[~c] ** 2) / 2.0 - LOG_NORM_C) - math.log(b))
            + np.sum(special.log_ndtr(-z[c]))
        )

    start = np.array([ln.mean(), math.log(max(ln.std(), 0.05))])
    res = optimize.minimize(
        nll, start, method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000}
    )
    return LognormalFit(float(math.exp(res.x[0])), float(math.exp(res.x[1])), x.size, int(c.sum()))


def bootstrap_band(intensities, censored=None, grid=None, samples=1000, level=0.90, seed=0):
    """Percentile bootstrap over records: (lo, hi) of theta, beta and of P on ``grid``.

    Resamples whose records are all censored, or all equal, are skipped (counted in 'used')."""
    x, c = _check(intensities, censored)
    rng = np.random.default_rng(seed)
    grid = np.asarray(
        grid if grid is not None else np.geomspace(x.min() / 2, x.max() * 2, 50), dtype=float
    )
    thetas, betas, curves = [], [], []
    for _ in range(samples):
        k = rng.integers(0, x.size, x.size)
        try:
            fit = fit_lognormal(x[k], c[k])
        except InputError:
            continue
        thetas.append(fit.median), betas.append(fit.beta), curves.append(fit.probability(grid))
    q = [(1 - level) / 2 * 100, (1 + level) / 2 * 100]
    return {
        "theta": np.percentile(thetas, q),
        "beta": np.percentile(betas, q),
        "probability": np.percentile(np.array(curves), q, axis=0),
        "grid": grid,
        "used": len(thetas),
    }


def empirical_points(intensities, censored=None):
    """Sorted exceedance intensities and the fraction of records exceeded at each (i / n)."""
    x, c = _check(intensities, censored)
    order = np.sort(x[~c])
    return order, np.arange(1, order.size + 1) / x.size


def fragility_dataset(cube, samples: int = 1000, level: float = 0.90):
    """Lognormal fragility per structure, record set (each suite and all) and limit state, in
    each intensity measure of the IDA cube (stonedem.fragility.ida.MEASURES: pga, pgv): median
    theta, beta, their bootstrap bands, and the curve with its band on a grid of the measure."""
    import xarray as xr

    from stonedem.fragility.ida import MEASURES

    sets = list(dict.fromkeys(str(s) for s in cube.suite.values)) + ["all"]
    grids = {"pga": np.geomspace(0.1, 100.0, 121), "pgv": np.geomspace(0.01, 10.0, 121)}
    dims = ("structure", "record_set", "limit_state")
    shape = (cube.sizes["structure"], len(sets), cube.sizes["limit_state"])
    ds = xr.Dataset(
        coords={
            "structure": cube.structure,
            "record_set": np.array(sets, dtype=object),
            "limit_state": cube.limit_state,
            "bound": np.array(["lo", "hi"], dtype=object),
        }
    )
    ds.coords["record_set"].attrs = {"long_name": "record suite, or all suites together"}
    ds.coords["bound"].attrs = {
        "long_name": f"lower and upper end of the bootstrap {level:.0%} band"
    }
    for measure, (var, units, label) in MEASURES.items():
        median = np.full(shape, math.nan)
        beta = np.full(shape, math.nan)
        median_band = np.full(shape + (2,), math.nan)
        beta_band = np.full(shape + (2,), math.nan)
        n_records = np.zeros(shape, np.int32)
        n_censored = np.zeros(shape, np.int32)
        curve = np.full(shape + (grids[measure].size,), math.nan)
        band = np.full(shape + (2, grids[measure].size), math.nan)
        for s in range(shape[0]):
            for r, rset in enumerate(sets):
                pick = (
                    np.ones(cube.sizes["record"], bool)
                    if rset == "all"
                    else (cube.suite.values == rset)
                )
                for j in range(shape[2]):
                    c = cube.censored.values[s, pick, j]
                    x = cube[var].values[s, pick, j]
                    ok = c >= 0
                    if ok.sum() < 2 or (c[ok] == 1).all():
                        continue
                    try:
                        fit = fit_lognormal(x[ok], c[ok] == 1)
                        boot = bootstrap_band(x[ok], c[ok] == 1, grids[measure], samples, level)
                    except InputError:
                        continue
                    at = (s, r, j)
                    median[at], beta[at] = fit.median, fit.beta
                    median_band[at], beta_band[at] = boot["theta"], boot["beta"]
                    n_records[at], n_censored[at] = fit.n, fit.censored
                    curve[at] = fit.probability(grids[measure])
                    band[at] = boot["probability"]
        grid_dim = f"{measure}_grid"
        ds.coords[grid_dim] = (
            grid_dim,
            grids[measure],
            {"units": units, "long_name": f"{label} of the curves"},
        )
        ds[f"median_{measure}"] = (
            dims,
            median,
            {"units": units, "long_name": f"median {label} theta of the lognormal fragility (MLE)"},
        )
        ds[f"median_{measure}_band"] = (
            dims + ("bound",),
            median_band,
            {"units": units, "long_name": f"bootstrap {level:.0%} band of the median {label}"},
        )
        ds[f"beta_{measure}"] = (
            dims,
            beta,
            {
                "units": "1",
                "long_name": f"lognormal dispersion beta in {label} (standard deviation of ln "
                f"{label})",
            },
        )
        ds[f"beta_{measure}_band"] = (
            dims + ("bound",),
            beta_band,
            {"units": "1", "long_name": f"bootstrap {level:.0%} band of beta in {label}"},
        )
        ds[f"probability_{measure}"] = (
            dims + (grid_dim,),
            curve,
            {"units": "1", "long_name": f"P(limit state exceeded | {label}), lognormal MLE"},
        )
        ds[f"probability_{measure}_band"] = (
            dims + ("bound", grid_dim),
            band,
            {"units": "1", "long_name": f"bootstrap {level:.0%} band of P(exceeded | {label})"},
        )
    ds["n_records"] = (dims, n_records, {"units": "1", "long_name": "records fitted"})
    ds["n_censored"] = (
        dims,
        n_censored,
        {
            "units": "1",
            "long_name": "of which censored (not exceeded up to the search maximum: lower bounds)",
        },
    )
    ds.attrs = {
        "title": "stonedem fragility curves (lognormal MLE over the IDA cube)",
        "method": "maximum likelihood, right-censored records as lower bounds "
        "(stonedem.fragility.fit); "
        f"percentile bootstrap over records, {samples} resamples",
        **{
            k: v
            for k, v in cube.attrs.items()
            if k.startswith("limit_state_") or k.startswith("search_")
        },
    }
    return ds


def fragility_table(fits) -> list[dict]:
    """Rows of the fits: structure, record set, limit state, then per measure the median
    with its band (units in the column names) and beta with its band."""
    rows = []
    for s in fits.structure.values:
        for r in fits.record_set.values:
            for ls in fits.limit_state.values:
                f = fits.sel(structure=s, record_set=r, limit_state=ls)
                if not int(f.n_records):
                    continue
                row = {"structure": str(s), "record_set": str(r), "limit_state": str(ls)}
                for m, units in (("pga", "m_s2"), ("pgv", "m_s")):
                    lo, hi = (float(v) for v in f[f"median_{m}_band"].values)
                    row.update(
                        {
                            f"median_{m}_{units}": round(float(f[f"median_{m}"]), 4),
                            f"median_{m}_lo": round(lo, 4),
                            f"median_{m}_hi": round(hi, 4),
                            f"beta_{m}": round(float(f[f"beta_{m}"]), 3),
                        }
                    )
                    lo, hi = (float(v) for v in f[f"beta_{m}_band"].values)
                    row.update({f"beta_{m}_lo": round(lo, 3), f"beta_{m}_hi": round(hi, 3)})
                row.update(n_records=int(f.n_records), n_censored=int(f.n_censored))
                rows.append(row)
    return rows
