"""Table 7.1 as a probability: the collapse threshold of one system from K members' runs.

Rocking near collapse is chaotic (Yim, Chopra & Penzien 1980; ENSEMBLES.md section 1), so
one search's smallest collapsing PGA is one draw. Here the runs of all K members of one
system (cell), each member a last-bit perturbation of the same model, are pooled by PGA into
"stripes" (runs and collapses at each value), and the probability of collapse is fitted by
binomial maximum likelihood as a probit in ln PGA (Baker 2015, Earthquake Spectra 31(1),
the multiple stripe analysis likelihood):

    P(collapse | a) = Phi(ln(a / a50) / beta).

a50 is the PGA at which half the members collapse; its band is bootstrapped over members
(whole members resampled, each keeping its runs). The transition zone [a_first, a_all] and
the median/min/max of the member search thresholds are reported beside it (ENSEMBLES.md
section 3.3). :func:`missing_stripe_runs` tells the runner which runs complete the stripes,
so that every member has run every value inside the members' brackets.

Everything here is pure numpy/scipy on a long table of runs: ``values`` (the PGA of each
run, rounded to 4 significant digits by the search, so equal values coincide exactly),
``members`` (the member index j of each run) and ``collapsed`` (1 collapsed, 0 stood).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from stonedem.errors import InputError
from stonedem.io.spec import Field
from stonedem.study.search import typed

# probit statuses (probit_fit()["status"])
FITTED = "fitted"
NO_SPREAD = "no spread"  # every survivor below every collapse: beta -> 0, a50 the common bracket
NOTHING_COLLAPSED = "nothing collapsed"
ALL_COLLAPSED = "everything collapsed"
NO_RUNS = "no runs"
# survivors below and collapses above one stripe that has both: beta -> 0, a50 that stripe
ONE_MIXED_STRIPE = "no spread beyond one stripe"
BETA_AT_MINIMUM = "beta at its lower bound"
BETA_AT_MAXIMUM = "beta at its upper bound"  # collapse falls with PGA: the fit is nearly flat

# beta is kept in this range: a wildly non-monotone stripe set (collapse more frequent at low
# PGA) would otherwise drive the fit to a decreasing curve, and a quasi-separated one to beta 0
BETA_MIN = 1e-4
BETA_MAX = 5.0

# the bootstrap's settings (bootstrap_band)
N_BOOT = Field("n_boot", "integer", range="[1, inf)", hint="give e.g. 1000")
LEVEL = Field("level", range="(0, 1)", hint="give e.g. 0.90")


def _require(ok, field: str, problem: str, fix: str) -> None:
    """Refuse a run table that is not one (its arrays' shapes, values and agreement)."""
    if not ok:
        raise InputError(field, problem, fix)


def _runs(values, members, collapsed):
    """The run table as float, int64 and int8 arrays; an InputError for anything else."""
    arrays = []
    for name, data in (("values", values), ("members", members), ("collapsed", collapsed)):
        array = np.asarray(data)
        _require(
            array.ndim == 1,
            name,
            f"expected one entry per run, got an array of shape {array.shape}",
            "give a flat array of the run table",
        )
        arrays.append(array)
    v, m, c = arrays
    _require(
        v.size == m.size == c.size,
        "values",
        f"{v.size} values, {m.size} members and {c.size} collapse flags",
        "give one value, member and collapse flag per run",
    )
    v = v.astype(float)
    _require(
        np.all(np.isfinite(v) & (v > 0)),
        "values",
        "every run value must be finite and positive",
        "give the searched PGA of each run",
    )
    _require(
        not m.size or np.issubdtype(m.dtype, np.integer) or np.all(m == np.round(m)),
        "members",
        "member indices must be integers",
        "give the member index j of each run",
    )
    c = c.astype(float)
    _require(
        np.all((c == 0) | (c == 1)),
        "collapsed",
        "collapse flags must be 0 or 1",
        "give 1 for a collapse, 0 for a survivor",
    )
    return v, m.astype(np.int64), c.astype(np.int8)


def _member_table(v, m, c):
    """Per (member, value): one run. A member run twice at a value is one run (the same
    member at the same value is the same deterministic simulation); if the two disagree
    the table is corrupt. Returns (member_ids, levels, ran[K, L] bool, hit[K, L] bool)."""
    member_ids, mi = np.unique(m, return_inverse=True)
    levels, li = np.unique(v, return_inverse=True)
    ran = np.zeros((member_ids.size, levels.size), bool)
    hit = np.zeros_like(ran)
    miss = np.zeros_like(ran)
    ran[mi, li] = True
    np.logical_or.at(hit, (mi, li), c == 1)
    np.logical_or.at(miss, (mi, li), c == 0)
    if np.any(hit & miss):
        k, level = np.argwhere(hit & miss)[0]
        raise InputError(
            "collapsed",
            f"member {member_ids[k]} both collapsed and stood at {levels[level]:g}",
            "a member's runs at one value must agree: check the run table",
        )
    return member_ids, levels, ran, hit


def stripes(values, members, collapsed):
    """The runs pooled by value: ``(levels, n_runs, n_collapses)``, levels increasing.

    Duplicates of the same member at one value count once (see :func:`_member_table`)."""
    v, m, c = _runs(values, members, collapsed)
    _, levels, ran, hit = _member_table(v, m, c)
    return levels, ran.sum(axis=0).astype(np.int64), hit.sum(axis=0).astype(np.int64)


def _per_member(name, data, member_ids):
    """A per-member quantity as an array aligned with ``member_ids``: a mapping member ->
    value, or an array already in the order of ``member_ids`` (the ensemble's member
    coordinate, increasing)."""
    if isinstance(data, dict):
        missing = [int(j) for j in member_ids if int(j) not in data]
        _require(not missing, name, f"no entry for members {missing}", "give one value per member")
        return np.array([data[int(j)] for j in member_ids], dtype=float)
    array = np.asarray(data, dtype=float)
    _require(
        array.shape == member_ids.shape,
        name,
        f"{array.size} values for the {member_ids.size} members of the runs",
        "give one value per member, in increasing member order",
    )
    return array


def missing_stripe_runs(values, members, thresholds, survived, member_ids=None):
    """The runs that complete the stripes: a sorted list of ``(member, value)`` not yet run.

    The zone is the hull of the members' brackets, [min survived, max threshold]
    (ENSEMBLES.md section 3.3); a member whose search found no collapse (threshold NaN)
    counts its largest value run as its upper end, one that collapsed at the minimum
    (survived NaN) its smallest. Every value that any member ran inside the zone (ends
    included) must be run by every member.

    ``thresholds`` and ``survived`` are the searches' ``upper`` and ``lower`` per member, as
    mappings member -> value or as arrays in the order of ``member_ids`` (default: the
    members of the runs, increasing).
    """
    flags = np.zeros(np.shape(values), np.int8)  # outcomes play no part in the zone
    v, m, _ = _runs(values, members, flags)
    ids = np.unique(m) if member_ids is None else np.asarray(member_ids, dtype=np.int64).ravel()
    _require(
        np.unique(ids).size == ids.size,
        "member_ids",
        "member indices repeat",
        "give each member once",
    )
    _require(
        np.all(np.isin(m, ids)),
        "members",
        "a run belongs to a member not in member_ids",
        "list every member",
    )
    upper = _per_member("thresholds", thresholds, ids)
    lower = _per_member("survived", survived, ids)
    if v.size == 0:
        return []
    ends = []
    for j, up, low in zip(ids, upper, lower):
        mine = v[m == j]
        _require(mine.size, "members", f"member {j} has no runs", "give every member's search runs")
        ends.append(
            (low if np.isfinite(low) else mine.min(), up if np.isfinite(up) else mine.max())
        )
    zone_low = min(e[0] for e in ends)
    zone_high = max(e[1] for e in ends)
    inside = np.unique(v[(v >= zone_low) & (v <= zone_high)])
    missing = []
    for j in ids:
        have = np.unique(v[m == j])
        for value in inside[~np.isin(inside, have)]:
            missing.append((int(j), float(value)))
    return sorted(missing)


def _separable(x, n, k):
    """Rows (R, L) whose every stripe is all-0 or all-1 with every all-0 stripe below every
    all-1 stripe: (mask, highest all-survive x, lowest all-collapse x)."""
    ran = n > 0
    zero = ran & (k == 0)
    one = ran & (k == n)
    top_zero = np.where(zero, x, -np.inf).max(axis=-1)
    low_one = np.where(one, x, np.inf).min(axis=-1)
    clean = np.all(zero | one | ~ran, axis=-1)
    return clean & (top_zero < low_one), top_zero, low_one


def _one_mixed_stripe(x, n, k):
    """Rows (R, L) with quasi-complete separation: one stripe with both outcomes, every
    stripe below it all-survive and every stripe above all-collapse. The likelihood's
    supremum is then beta -> 0 with a50 at that stripe (its curve steps from 0 to k/n to 1
    there). Returns (mask, x of the mixed stripe, its log-likelihood k ln p + (n-k) ln(1-p))."""
    ran = n > 0
    mixed = ran & (k > 0) & (k < n)
    single = mixed.sum(axis=-1) == 1
    x_mixed = np.where(mixed, x, 0.0).sum(axis=-1)
    below = x < x_mixed[:, None]
    ok = np.all(~ran | (below & (k == 0)) | (~below & (k == n)) | mixed, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = np.where(mixed, k / np.where(ran, n, 1.0), 0.5)
        terms = np.where(mixed, k * np.log(frac) + (n - k) * np.log1p(-frac), 0.0)
    return single & ok, x_mixed, terms.sum(axis=-1)


def _log_likelihood(x, n, k, b0, b1):
    """Binomial log-likelihood of probit(b0 + b1 x) for rows (R, L); binomial coefficients
    left out (they do not depend on the parameters)."""
    eta = b0[:, None] + b1[:, None] * x
    return np.sum(k * special.log_ndtr(eta) + (n - k) * special.log_ndtr(-eta), axis=-1)


def _probit_newton(x, n, k, iterations=100):
    """Binomial probit MLE for many stripe sets at once (rows of x, n, k: R x L; x = ln a).

    The log-likelihood is concave in the linear-predictor parameters (b0, b1), eta = b0 + b1 x
    (Pratt 1981, JASA 76:103, concavity of the probit log-likelihood), with b1 = 1/beta and
    ln a50 = -b0/b1. Newton's method with step halving climbs it; b1 is projected onto
    [1/BETA_MAX, 1/BETA_MIN] and, on a bound with the gradient pointing out, only b0 moves
    (the constrained maximum of a concave function on a strip). Rows must have runs with
    both outcomes. Returns (ln a50, beta, log-likelihood), each of length R."""
    rows = x.shape[0]
    b1_low, b1_high = 1.0 / BETA_MAX, 1.0 / BETA_MIN
    # start: slope 1/0.1 through the midpoint of the mean ln a of collapses and of survivors
    with np.errstate(invalid="ignore", divide="ignore"):
        mid = 0.5 * ((k * x).sum(-1) / k.sum(-1) + ((n - k) * x).sum(-1) / (n - k).sum(-1))
    b1 = np.full(rows, 10.0)
    b0 = -b1 * mid
    ll = _log_likelihood(x, n, k, b0, b1)
    active = np.ones(rows, bool)
    for _ in range(iterations):
        if not active.any():
            break
        idx = np.flatnonzero(active)
        xa, na, ka = x[idx], n[idx], k[idx]
        eta = b0[idx, None] + b1[idx, None] * xa
        # inverse Mills ratios phi/Phi of eta and -eta, from logs (no 0/0 in the tails)
        log_phi = -0.5 * eta**2 - 0.5 * math.log(2 * math.pi)
        lam_hit = np.exp(log_phi - special.log_ndtr(eta))
        lam_miss = np.exp(log_phi - special.log_ndtr(-eta))
        u = ka * lam_hit - (na - ka) * lam_miss  # d ll / d eta
        w = ka * lam_hit * (eta + lam_hit) + (na - ka) * lam_miss * (
            lam_miss - eta
        )  # -d2 ll / d eta2
        g0, g1 = u.sum(-1), (u * xa).sum(-1)
        h00, h01, h11 = w.sum(-1), (w * xa).sum(-1), (w * xa * xa).sum(-1)
        det = h00 * h11 - h01**2
        with np.errstate(divide="ignore", invalid="ignore"):
            d0 = (h11 * g0 - h01 * g1) / det
            d1 = (h00 * g1 - h01 * g0) / det
            on_bound = (
                ((b1[idx] <= b1_low) & (d1 < 0))
                | ((b1[idx] >= b1_high) & (d1 > 0))
                | ~np.isfinite(det)
                | (det <= 0)
            )
            d0 = np.where(on_bound, g0 / h00, d0)
            d1 = np.where(on_bound, 0.0, d1)
        d0 = np.nan_to_num(d0, nan=0.0, posinf=0.0, neginf=0.0)
        d1 = np.nan_to_num(d1, nan=0.0, posinf=0.0, neginf=0.0)
        step = np.ones(idx.size)
        best0, best1, best_ll = b0[idx], b1[idx], ll[idx]
        pending = np.ones(idx.size, bool)
        for _ in range(40):  # halve the step until the likelihood does not fall
            p = np.flatnonzero(pending)
            if p.size == 0:
                break
            t0 = b0[idx[p]] + step[p] * d0[p]
            t1 = np.clip(b1[idx[p]] + step[p] * d1[p], b1_low, b1_high)
            t_ll = _log_likelihood(xa[p], na[p], ka[p], t0, t1)
            ok = t_ll >= ll[idx[p]] - 1e-12 * np.abs(ll[idx[p]])
            best0[p[ok]], best1[p[ok]], best_ll[p[ok]] = t0[ok], t1[ok], t_ll[ok]
            pending[p[ok]] = False
            step[p[~ok]] *= 0.5
        # the change of eta at the largest |x|: what the step does to the fitted curve
        moved = np.abs(best0 - b0[idx]) + np.abs(best1 - b1[idx]) * np.abs(xa).max(-1)
        b0[idx], b1[idx], ll[idx] = best0, best1, best_ll
        done = pending | (
            moved <= 1e-10 * (1.0 + np.abs(best0) + np.abs(best1))
        )  # stuck, or converged
        active[idx[done]] = False
    return -b0 / b1, 1.0 / b1, ll


def _fit_rows(x, n, k):
    """probit fits of stripe sets (rows R x L; x = ln a, n and k counts, n 0 for padding):
    (a50, beta, status codes, log-likelihood). Codes index _STATUSES."""
    rows = x.shape[0]
    a50 = np.full(rows, np.nan)
    beta = np.full(rows, np.nan)
    ll = np.full(rows, np.nan)
    code = np.zeros(rows, np.int8)
    runs, hits = n.sum(-1), k.sum(-1)
    code[runs == 0] = 4
    if x.shape[1] == 0:
        return a50, beta, code, ll
    code[(runs > 0) & (hits == 0)] = 2
    code[(runs > 0) & (hits == runs)] = 3
    separable, top_zero, low_one = _separable(x, n, k)
    spread = separable & (code == 0)
    code[spread] = 1
    a50[spread] = np.exp(
        0.5 * (top_zero[spread] + low_one[spread])
    )  # geometric mean of the bracket
    beta[spread] = 0.0
    ll[spread] = 0.0
    quasi, x_mixed, ll_mixed = _one_mixed_stripe(x, n, k)
    quasi &= code == 0
    code[quasi] = 7
    a50[quasi], beta[quasi], ll[quasi] = np.exp(x_mixed[quasi]), 0.0, ll_mixed[quasi]
    fit = code == 0
    if fit.any():
        ln_a50, b, ll_fit = _probit_newton(x[fit], n[fit].astype(float), k[fit].astype(float))
        a50[fit], beta[fit], ll[fit] = np.exp(ln_a50), b, ll_fit
        sub = np.zeros(fit.sum(), np.int8)
        sub[b <= BETA_MIN * (1 + 1e-9)] = 5
        sub[b >= BETA_MAX * (1 - 1e-9)] = 6
        code[fit] = sub
    return a50, beta, code, ll


_STATUSES = (
    FITTED,
    NO_SPREAD,
    NOTHING_COLLAPSED,
    ALL_COLLAPSED,
    NO_RUNS,
    BETA_AT_MINIMUM,
    BETA_AT_MAXIMUM,
    ONE_MIXED_STRIPE,
)


def probit_fit(levels, n_runs, n_collapses) -> dict:
    """Binomial MLE of P(collapse | a) = Phi(ln(a / a50) / beta) over stripes (Baker 2015,
    multiple stripe analysis): ``dict(a50, beta, status, log_likelihood)``.

    Degenerate data: survivors all below collapses (every stripe 0 or 1) have no MLE (beta ->
    0): status "no spread", beta 0 and a50 the geometric mean of the highest all-survive and
    the lowest all-collapse level. With one stripe of both outcomes between all-survive and
    all-collapse stripes the supremum is also at beta -> 0: status "no spread beyond one
    stripe", beta 0, a50 that stripe. Nothing or everything collapsed: a50 and beta NaN, the
    status says which. beta is kept within [BETA_MIN, BETA_MAX] (status says when it sits on
    a bound). ``log_likelihood`` leaves out the binomial coefficients.
    """
    a = np.asarray(levels, dtype=float)
    n = np.asarray(n_runs)
    k = np.asarray(n_collapses)
    _require(
        a.ndim == n.ndim == k.ndim == 1 and a.size == n.size == k.size,
        "levels",
        f"{a.size} levels, {n.size} run counts and {k.size} collapse counts",
        "give one run count and one collapse count per level",
    )
    _require(
        np.all(np.isfinite(a) & (a > 0)),
        "levels",
        "levels must be finite and positive",
        "give the PGA of each stripe",
    )
    _require(
        np.all(n == np.round(n)) and np.all(k == np.round(k)) and np.all((0 <= k) & (k <= n)),
        "n_collapses",
        "counts must be whole numbers with 0 <= collapses <= runs",
        "give the runs and collapses at each level",
    )
    a50, beta, code, ll = _fit_rows(
        np.log(a)[None, :], n[None, :].astype(float), k[None, :].astype(float)
    )
    return {
        "a50": float(a50[0]),
        "beta": float(beta[0]),
        "status": _STATUSES[code[0]],
        "log_likelihood": float(ll[0]),
    }


def bootstrap_band(values, members, collapsed, n_boot=1000, level=0.90, seed=0):
    """Percentile band of a50 by bootstrap over members: ``(low, high)``.

    Each replicate draws K members with replacement, keeping each member's runs together
    (members are the exchangeable units, ENSEMBLES.md section 3.3), pools them into stripes
    and refits. A replicate in which nothing collapsed counts as a50 = +inf, one in which
    everything collapsed as a50 = 0 (the fit lies beyond the levels run); the band ends are
    order statistics (no interpolation across an infinity). NaN band where the fit of the
    data itself has no a50."""
    typed(N_BOOT, n_boot, "n_boot")
    typed(LEVEL, level, "level")
    v, m, c = _runs(values, members, collapsed)
    member_ids, levels, ran, hit = _member_table(v, m, c)
    x = np.log(levels)
    whole = _fit_rows(
        x[None, :], ran.sum(0)[None, :].astype(float), hit.sum(0)[None, :].astype(float)
    )
    if not np.isfinite(whole[0][0]):
        return math.nan, math.nan
    rng = np.random.default_rng(seed)
    count = member_ids.size
    draws = rng.integers(0, count, size=(int(n_boot), count))
    weights = np.zeros((int(n_boot), count))
    np.add.at(weights, (np.arange(int(n_boot))[:, None], draws), 1.0)
    n = weights @ ran.astype(float)
    k = weights @ hit.astype(float)
    a50, _, code, _ = _fit_rows(np.broadcast_to(x, n.shape), n, k)
    a50 = np.where(code == 2, np.inf, np.where(code == 3, 0.0, a50))
    tail = (1.0 - level) / 2.0
    return float(np.quantile(a50, tail, method="lower")), float(
        np.quantile(a50, 1.0 - tail, method="higher")
    )


def transition_zone(values, members, collapsed):
    """``(a_first, a_all)``: the lowest value at which any member collapsed, and the lowest
    value L such that every run at every value >= L collapsed, in all members (ENSEMBLES.md
    section 3.3). NaN where there is none (nothing collapsed; the highest value run has a
    survivor)."""
    levels, n, k = stripes(values, members, collapsed)
    hits = levels[k > 0]
    a_first = float(hits.min()) if hits.size else math.nan
    a_all = math.nan
    for level, runs, collapses in zip(levels[::-1], n[::-1], k[::-1]):
        if collapses < runs:
            break
        a_all = float(level)
    return a_first, a_all


def threshold_band(values, members, collapsed, thresholds, n_boot=1000, level=0.90, seed=0) -> dict:
    """Table 7.1 for one cell: the probit fit, its band, the transition zone, and the K member
    search thresholds summarised (ENSEMBLES.md section 3.3).

    ``thresholds`` holds each member's smallest collapsing value of its search (summary
    "upper"), NaN where the search found no collapse up to its maximum; one per member of the
    runs, in increasing member order. The median, min and max are taken with such a member
    above every value, and are NaN where they fall on one (``threshold_none`` says how many);
    ``threshold_distinct`` counts the distinct finite values."""
    v, m, c = _runs(values, members, collapsed)
    t = np.asarray(thresholds, dtype=float).ravel()
    member_ids = np.unique(m)
    _require(
        t.size == member_ids.size,
        "thresholds",
        f"{t.size} thresholds for the {member_ids.size} members of the runs",
        "give one search threshold per member (NaN for none)",
    )
    _require(
        not (np.any(np.isfinite(t) & (t <= 0)) or np.any(np.isneginf(t))),
        "thresholds",
        "thresholds must be positive (NaN for none)",
        "give each member's upper",
    )
    levels, n, k = stripes(v, m, c)
    fit = probit_fit(levels, n, k)
    low, high = bootstrap_band(v, m, c, n_boot=n_boot, level=level, seed=seed)
    a_first, a_all = transition_zone(v, m, c)
    above = np.where(np.isfinite(t), t, np.inf)

    def finite(value):
        return float(value) if np.isfinite(value) else math.nan

    ordered = np.sort(above)
    median = np.median(ordered) if t.size else math.nan  # (finite + inf) / 2 = inf: no NaN
    return {
        "members": int(member_ids.size),
        "a50": fit["a50"],
        "beta": fit["beta"],
        "status": fit["status"],
        "log_likelihood": fit["log_likelihood"],
        "a50_low": low,
        "a50_high": high,
        "band_level": float(level),
        "a_first": a_first,
        "a_all": a_all,
        "threshold_median": finite(median) if t.size else math.nan,
        "threshold_min": finite(ordered[0]) if t.size else math.nan,
        "threshold_max": finite(ordered[-1]) if t.size else math.nan,
        "threshold_distinct": int(np.unique(t[np.isfinite(t)]).size),
        "threshold_none": int(np.sum(~np.isfinite(t))),
        "levels": int(levels.size),
        "runs": int(n.sum()),
    }
