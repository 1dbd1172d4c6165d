"""Reductions of study cubes into the thesis' tables (chapter 7) as CSV."""

from __future__ import annotations

import numpy as np
import xarray as xr

from stonedem.study.cube import member_summary
from stonedem.study.grid import MEMBER
from stonedem.study.search import Run, bracket
from stonedem.units import GRAVITY

# thesis Table 7.1: acceleration required to cause failure [m/s2]
THESIS_TABLE_7_1 = {
    ("colonnade", 1): {"mexico": 1.39, "kalamata": 16.02, "athens": 27.69},
    ("single column", 1): {"mexico": 1.15, "kalamata": 8.94, "athens": 20.77},
    ("colonnade", 2): {"mexico": 1.42, "kalamata": 16.42, "athens": 28.60},
    ("single column", 2): {"mexico": 1.15, "kalamata": 9.01, "athens": 21.37},
    ("colonnade", 3): {"mexico": 1.42, "kalamata": 17.30, "athens": 31.91},
    ("single column", 3): {"mexico": 1.15, "kalamata": 9.28, "athens": 24.98},
}


def thesis_record(name: str) -> str:
    """'mexico' for 'mexico_standin_chichi_tcu102', etc.; '' for records that stand in for none."""
    head = name.split("_")[0]
    return head if head in ("mexico", "kalamata", "athens") else ""


def thesis_threshold(system: str, n_drums, record: str) -> float:
    """Thesis Table 7.1's acceleration to cause failure [m/s2] of a system ("colonnade" or
    "single column") of ``n_drums`` under the thesis record ``record`` stands in for (NaN: none)."""
    return THESIS_TABLE_7_1.get((system, n_drums), {}).get(thesis_record(record), float("nan"))


def table_7_1(standalone: xr.Dataset, colonnade: xr.Dataset) -> list[dict]:
    """Rows of Table 7.1: our collapse threshold of each system beside the thesis' value.

    Our records are stand-ins, so absolute values differ. ``collapse_pga_m_s2`` is the
    smallest PGA run that collapsed, ``survived_pga_m_s2`` the largest below it that did not
    (:func:`collapse_brackets`); a threshold search's cube adds how it ended.
    """
    rows = []
    for system, full in (("colonnade", colonnade), ("single column", standalone)):
        cube = member_summary(full)  # an ensemble: member 0's searches as today's columns
        for found in collapse_brackets(cube, "pga"):
            rows.append(
                {
                    "system": system,
                    "n_drums": found["n_drums"],
                    "record": found["record"],
                    "thesis_record": thesis_record(found["record"]),
                    "collapse_pga_m_s2": found["upper"],
                    "survived_pga_m_s2": found["lower"],
                    "bracket_width": found["width"],
                    "n_runs": found["n_runs"],
                    "monotonic": int(found["monotonic"]),
                    "resurrections_m_s2": " ".join(f"{v:g}" for v in found["resurrections"]),
                    "search_status": found["status"],
                    "collapse_map": found["map"],
                    "thesis_accel_to_failure_m_s2": thesis_threshold(
                        system, found["n_drums"], found["record"]
                    ),
                }
            )
            if MEMBER in full.dims:
                rows[-1].update(
                    ensemble_columns(full.sel(record=found["record"], n_drums=found["n_drums"]))
                )
    return rows


def ensemble_columns(system: xr.Dataset) -> dict:
    """Table 7.1 as a probability, from one system's searches by every member of an ensemble
    (issue 44, stonedem.study.stripes): a50 by probit over the pooled runs with its band
    bootstrapped over members, the transition zone, and the member thresholds. The runs are
    the searches' own and, where the cube has them, the stripe fills that run every member at
    every value inside the zone (stonedem.study.stripe_fill; the stored baseline's runner
    fills them the same way)."""
    from stonedem.study.stripes import threshold_band

    collapsed = system["collapsed"].transpose(MEMBER, "run").values
    values = system["pga"].broadcast_like(system["collapsed"]).transpose(MEMBER, "run").values
    filled = "stripe_fills" in system.attrs  # the fills ran (none may have been needed)
    if "stripe_value" in system:  # the fills beside the search runs, one member's row each
        collapsed = np.concatenate(
            [collapsed, system["stripe_collapsed"].transpose(MEMBER, "stripe_run").values], axis=1
        )
        values = np.concatenate(
            [values, system["stripe_value"].transpose(MEMBER, "stripe_run").values], axis=1
        )
    members = np.broadcast_to(system[MEMBER].values[:, None], values.shape)
    ran = np.isfinite(values) & np.isfinite(collapsed)
    band = threshold_band(
        values[ran],
        members[ran],
        collapsed[ran] > 0,
        system["collapse_threshold"].transpose(MEMBER).values,
    )
    return {
        "members": band["members"],
        "a50_m_s2": band["a50"],
        "a50_low_m_s2": band["a50_low"],
        "a50_high_m_s2": band["a50_high"],
        "beta": band["beta"],
        "fit_status": band["status"],
        "a_first_m_s2": band["a_first"],
        "a_all_m_s2": band["a_all"],
        "member_threshold_median_m_s2": band["threshold_median"],
        "member_threshold_min_m_s2": band["threshold_min"],
        "member_threshold_max_m_s2": band["threshold_max"],
        "member_thresholds_distinct": band["threshold_distinct"],
        "stripes": "search runs and stripe fills" if filled else "search runs",
    }


def collapse_brackets(cube: xr.Dataset, along: str = "pga") -> list[dict]:
    """Per system (every combination of the other parameters) of a study cube: the smallest
    value of ``along`` that collapsed (upper), the largest below it that survived (lower),
    width = upper / lower - 1, the survivors above the first collapse (resurrections: collapse
    not monotonic), the runs as a map ``"1:. 1.8:X"`` (X collapsed), and the search status.

    Works on a grid cube (``along`` a dimension) and on a threshold-search cube (``along`` a
    coordinate on a ``run`` dimension, NaN where a system ran fewer cases)."""
    runs = "run" if "run" in cube["collapsed"].dims else along
    collapsed = cube["collapsed"]
    values = cube[along].broadcast_like(collapsed)
    systems = [d for d in collapsed.dims if d != runs]
    stacked_c = collapsed.stack(system=systems) if systems else collapsed.expand_dims(system=[0])
    stacked_v = values.stack(system=systems) if systems else values.expand_dims(system=[0])
    out = []
    for i in range(stacked_c.sizes["system"]):
        system = stacked_c.isel(system=i)
        c, v = system.values, stacked_v.isel(system=i).values
        ran = np.isfinite(c) & np.isfinite(v)
        order = np.argsort(v[ran], kind="stable")
        runs = [Run(float(x), bool(h > 0), "") for x, h in zip(v[ran][order], c[ran][order])]
        row = {d: _plain(system[d].values) for d in systems}
        status = str(cube["search_status"].sel(row).values) if "search_status" in cube else ""
        out.append(
            {
                **row,
                **bracket(runs),
                "n_runs": len(runs),
                "status": status,
                "map": " ".join(f"{r.value:g}:{'X' if r.collapsed else '.'}" for r in runs),
            }
        )
    return out


def _excitation(cube: xr.Dataset) -> dict:
    import json

    return json.loads(cube.attrs.get("excitation", "{}"))


def ramp_thresholds(cube: xr.Dataset, along: str) -> list[dict]:
    """PGA to initiate rocking and to overturn under a linear acceleration ramp (thesis Fig. 6.10,
    6.13).

    The ramp's acceleration at time t is rate x t, so the thresholds are rate times the
    rocking onset time (mean rotation > theta_cr / 30) and the collapse time.
    """
    cube = member_summary(cube)  # an ensemble's medians over members
    rate = _excitation(cube).get("rate")
    if rate is None:
        raise ValueError("the cube's cases share no ramp rate (excitation attribute)")
    rows = []
    for value in cube[along].values:
        case = cube.sel({along: value})
        rows.append(
            {
                along: value.item() if hasattr(value, "item") else value,
                "rocking_onset_pga_m_s2": rate * float(case["rocking_onset_time"]),
                "overturning_pga_m_s2": rate * float(case["collapse_time"]),
                "static_rocking_pga_m_s2": GRAVITY * float(np.tan(case["theta_cr"])),
                "ramp_rate_m_s3": rate,
            }
        )
    return rows


def case_rows(cube: xr.Dataset, columns: dict) -> list[dict]:
    """One row per case of a cube: its swept parameters, then each scalar variable of
    ``columns`` ({variable: column name}) under its column name, in that order."""
    names = list(columns)
    dims = [d for d in cube[names[0]].dims if d != "time"]
    stacked = cube[names].stack(case=dims) if dims else cube[names].expand_dims(case=[0])
    rows = []
    for i in range(stacked.sizes["case"]):
        case = stacked.isel(case=i)
        row = {d: _plain(case[d].values) for d in dims}
        row.update({columns[n]: _plain(case[n].values) for n in names})
        rows.append(row)
    return rows


def _plain(value):
    return value.item() if hasattr(value, "item") else value


def frequency_response(cube: xr.Dataset) -> list[dict]:
    """Total sliding and rocking vs harmonic frequency (thesis Fig. 6.1, 6.5, 6.6), one row per
    case.

    ``sliding_to_base_ratio`` is the maximum total sliding over the displacement amplitude
    of the base (from the base history): near 1 when the base slides under a column that
    stays put (high frequency).
    """
    cube = member_summary(cube)  # an ensemble: collapse fractions, medians, member 0's histories
    amplitude = np.abs(cube["base_displacement"]).max("time")
    cube = cube.assign(
        base_amplitude=amplitude,
        base_pga=np.abs(cube["base_acceleration"]).max("time"),
        sliding_to_base_ratio=cube["max_total_sliding"] / amplitude,
    )
    rows = case_rows(
        cube,
        {
            "base_amplitude": "base_amplitude_m",
            "base_pga": "pga_m_s2",
            "max_total_sliding": "max_total_sliding_m",
            "sliding_to_base_ratio": "sliding_to_base_ratio",
            "max_rocking": "max_rocking_rad",
            "collapsed": "collapsed",
        },
    )
    for row in rows:
        row["collapsed"] = verdict(row["collapsed"])
    return rows


def verdict(collapsed: float):
    """A case's collapse as a table gives it: 0 or 1, or an ensemble's collapse fraction."""
    return int(collapsed) if collapsed in (0.0, 1.0) else round(float(collapsed), 4)


def epistyle_response(cube: xr.Dataset) -> list[dict]:
    """Maximum epistyle displacement relative to the base, rocking and collapse for every case of
    a colonnade study (thesis Fig. 7.19-7.49: one parameter varied at a time)."""
    cube = member_summary(cube)
    rows = case_rows(
        cube,
        {
            "max_epistyle_displacement": "max_epistyle_displacement_m",
            "max_rocking": "max_rocking_rad",
            "collapsed": "collapsed",
        },
    )
    for row in rows:  # -1: a combination a sparse cube of listed cases did not run
        row["collapsed"] = verdict(row["collapsed"]) if np.isfinite(row["collapsed"]) else -1
    return rows
