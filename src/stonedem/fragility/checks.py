"""Physics checks of the IDA (issue 16): do the fragility results order as the thesis
predicts, and does a single block under the pulse records fall where rigid rocking theory
says a one-sine pulse of the same period would topple it?

- colonnade >= column (thesis 7.4: the epistyle ties the columns, Table 7.1): the median
  collapse PGA of each colonnade against the column of the same drums, per record set;
- lower-frequency excitation is more damaging in PGA terms (thesis 6.2, 7.3): the median
  collapse PGA of the record sets ordered as their median predominant frequency, and the
  rank correlation of each record's collapse PGA with its predominant frequency;
- lesser limit states first: rocking onset <= theta_cr / 2 <= collapse (medians);
- Makris & Vassiliou (2012): a rigid block's overturning under a pulse of period T_p scales
  with a_p / (g tan alpha) against omega_p / p; for each pulse record we place the block's
  collapse in those coordinates (a_p from PGV, a one-sine pulse of peak velocity PGV:
  a_p = omega_p PGV / 2) beside the exact minimum overturning one-sine amplitude
  (stonedem.reference.analytic.rigid_one_sine_min_overturning, Housner's restitution).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from stonedem.reference.analytic import (
    housner_restitution,
    rectangle_rocking_properties,
    rigid_one_sine_min_overturning,
)
from stonedem.units import GRAVITY as G


def _median(
    fits: xr.Dataset,
    structure: str,
    record_set: str,
    limit_state: str = "collapse",
    measure: str = "pga",
) -> float:
    return float(
        fits[f"median_{measure}"].sel(
            structure=structure, record_set=record_set, limit_state=limit_state
        )
    )


def _row(check, subject, expected, measured, holds, note=""):
    return {
        "check": check,
        "subject": subject,
        "expected": expected,
        "measured": measured,
        "holds": "yes" if holds else ("n/a" if holds is None else "no"),
        "note": note,
    }


def ordering_checks(cube: xr.Dataset, fits: xr.Dataset, structures: dict) -> list[dict]:
    """Rows (check, subject, expected, measured, holds, note) of the ordering checks.
    ``structures``: {name: fragility spec} (kind and drums of each)."""
    rows = []
    sets = [str(s) for s in fits.record_set.values]
    names = [str(s) for s in cube.structure.values]
    spec = {n: structures[n]["structure"] for n in names}
    for name in names:  # colonnade >= the column of the same drums
        if spec[name].get("kind") != "colonnade":
            continue
        peers = [
            c
            for c in names
            if spec[c].get("kind") == "column"
            and spec[c].get("n_drums", 1) == spec[name].get("n_drums", 1)
            and spec[c].get("capital") == spec[name].get("capital")
        ]
        for column in peers:
            for rset in sets:
                a, b = _median(fits, name, rset), _median(fits, column, rset)
                pick = slice(None) if rset == "all" else (cube.suite.values == rset)
                x = cube.pga_at_limit.sel(structure=name, limit_state="collapse").values[pick]
                y = cube.pga_at_limit.sel(structure=column, limit_state="collapse").values[pick]
                ok = np.isfinite(x) & np.isfinite(y)
                share = float(np.mean(x[ok] >= y[ok])) if ok.any() else math.nan
                rows.append(
                    _row(
                        "colonnade >= column",
                        f"{name} vs {column}, {rset}",
                        "median collapse PGA of the colonnade >= the column's",
                        f"{a:.3g} vs {b:.3g} m/s2 ({a / b - 1:+.1%}); colonnade >= column on "
                        f"{share:.0%} of {int(ok.sum())} records",
                        a >= b,
                    )
                )
    suites = [s for s in sets if s != "all"]
    freq = {
        s: float(np.median(cube.predominant_frequency.values[cube.suite.values == s]))
        for s in suites
    }
    for name in names:
        present = [s for s in suites if np.isfinite(_median(fits, name, s))]
        for i, low in enumerate(present):
            for high in present[i + 1 :]:
                lo_set, hi_set = sorted((low, high), key=lambda s: freq[s])
                if freq[hi_set] / freq[lo_set] < 1.2:
                    continue  # frequencies too close to predict an order
                a, b = _median(fits, name, lo_set), _median(fits, name, hi_set)
                rows.append(
                    _row(
                        "lower frequency more damaging",
                        f"{name}: {lo_set} vs {hi_set}",
                        f"median collapse PGA under {lo_set} (f_p {freq[lo_set]:.2f} Hz) < under "
                        f"{hi_set} ({freq[hi_set]:.2f} Hz)",
                        f"{a:.3g} vs {b:.3g} m/s2",
                        a < b,
                    )
                )
        x = cube.pga_at_limit.sel(structure=name, limit_state="collapse").values
        cen = cube.censored.sel(structure=name, limit_state="collapse").values
        ok = np.isfinite(x) & (cen == 0)
        if ok.sum() >= 5:
            rho = _spearman(cube.predominant_frequency.values[ok], x[ok])
            rows.append(
                _row(
                    "lower frequency more damaging",
                    f"{name}: all records",
                    "collapse PGA rises with the record's predominant frequency (Spearman rho > 0)",
                    f"rho = {rho:.2f} over {int(ok.sum())} records",
                    rho > 0,
                )
            )
        medians = [
            _median(fits, name, "all", ls)
            for ls in ("rocking_onset", "half_critical_rotation", "collapse")
        ]
        if all(np.isfinite(medians)):
            rows.append(
                _row(
                    "limit states in order",
                    name,
                    "median rocking onset <= theta_cr / 2 <= collapse",
                    " <= ".join(f"{m:.3g}" for m in medians) + " m/s2",
                    medians[0] <= medians[1] <= medians[2],
                )
            )
    return rows


def _spearman(x, y) -> float:
    from scipy import stats

    return float(stats.spearmanr(x, y).statistic)


def pulse_check(cube: xr.Dataset, structure: str, spec: dict) -> xr.Dataset:
    """The single block ``structure`` under the pulse records, in Makris & Vassiliou's
    coordinates: omega_p / p and the collapse a_p / (g tan alpha) of each record, beside the
    rigid block's minimum overturning one-sine amplitude at that omega_p / p."""
    width, height = float(spec["width"]), float(spec["height"])
    block = rectangle_rocking_properties(width, height)
    r = housner_restitution(width, height)
    pick = (cube.suite.values == "near_field_pulse") & np.isfinite(
        cube.pga_at_limit.sel(structure=structure, limit_state="collapse").values
    )
    sub = cube.isel(record=np.flatnonzero(pick)).sel(structure=structure, limit_state="collapse")
    omega_p = 2 * math.pi / sub.pulse_period.values
    ratio = omega_p / block.p
    a_pgv = omega_p * sub.pgv_at_limit.values / 2.0 / (G * math.tan(block.alpha))
    a_pga = sub.pga_at_limit.values / (G * math.tan(block.alpha))
    rigid = np.array([rigid_one_sine_min_overturning(w, width, height, r).amplitude for w in ratio])
    ds = xr.Dataset(coords={"record": sub.record.values})
    ds["omega_ratio"] = (
        "record",
        ratio,
        {"units": "1", "long_name": "omega_p / p (T_p: peak of the 5 % PSV)"},
    )
    ds["collapse_ap_pgv"] = (
        "record",
        a_pgv,
        {
            "units": "1",
            "long_name": "collapse a_p / (g tan alpha), a_p = omega_p PGV / 2 (one-sine pulse "
            "of the record's PGV)",
        },
    )
    ds["collapse_ap_pga"] = (
        "record",
        a_pga,
        {"units": "1", "long_name": "collapse PGA / (g tan alpha)"},
    )
    ds["rigid_one_sine"] = (
        "record",
        rigid,
        {
            "units": "1",
            "long_name": "minimum overturning one-sine a_p / (g tan alpha) of the rigid block "
            "(Housner r)",
        },
    )
    ds["censored"] = (
        "record",
        sub.censored.values,
        {"units": "1", "long_name": "1: no collapse up to the maximum"},
    )
    ds.attrs = {
        "structure": structure,
        "alpha": block.alpha,
        "p": block.p,
        "restitution": r,
        "title": "single block under the near-field pulse records against rigid one-sine "
        "overturning",
    }
    return ds


def pulse_rows(check: xr.Dataset) -> list[dict]:
    """Summary rows of :func:`pulse_check`: the records' collapse over the rigid one-sine
    minimum (median ratio and its spread), in PGV and PGA terms."""
    rows = []
    ok = check.censored.values == 0
    for var, what in (("collapse_ap_pgv", "a_p from PGV"), ("collapse_ap_pga", "PGA")):
        ratio = check[var].values[ok] / check.rigid_one_sine.values[ok]
        if not ratio.size:
            continue
        lo, med, hi = np.percentile(ratio, [10, 50, 90])
        rows.append(
            _row(
                "pulse records vs one-sine theory",
                f"{check.attrs['structure']}: {what}",
                "a record topples the block near the rigid one-sine minimum of its pulse "
                "(ratio ~ 1); "
                "below it when the pulse comes with other cycles",
                f"ours / rigid: median {med:.2f}, 10-90 % {lo:.2f}-{hi:.2f} over {ratio.size} "
                "records",
                None,
                "a comparison, not a pass/fail: a record is not a one-sine pulse",
            )
        )
    return rows
