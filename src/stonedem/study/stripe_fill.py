"""The stripe fills of an ensemble study's threshold searches (issue 44, item 3).

With ``ensemble: {members: K}`` every search system runs once per member; each member's search
finds its own bracket at its own values. a50 is fitted over stripes: every member run at the
same values (Baker 2015), so the values any member ran inside the zone [lowest survived,
highest threshold] are run by the members that have not run them
(:func:`stonedem.study.stripes.missing_stripe_runs`). The search runs on disk are reused, only
the missing ones are simulated (each a case file, kept in the case store like any run).

The workflow runs one job per system as configured (``stripes_<study>_<k>``, after its members'
searches); the study's cube carries the fills beside each member's search runs
(``stripe_value``, ``stripe_collapsed`` on ``stripe_run``) and Table 7.1 fits a50 over both.
The stored baseline's runner (:mod:`stonedem.study.ensemble`) fills its stripes the same way.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.netcdf import open_result, write_dataset
from stonedem.study.grid import MEMBER, Case, case_id, search_case

STRIPE_RUN = "stripe_run"


def member_groups(systems: list[Case]) -> dict[str, list[Case]]:
    """An ensemble search study's systems by the system as configured: {its id: its member
    systems, by increasing member j}. Systems without a member (K = 1) are left out."""
    groups: dict[str, list[Case]] = {}
    for system in systems:
        if system.search is None or MEMBER not in system.params:
            continue
        base = case_id({k: v for k, v in system.params.items() if k != MEMBER})
        groups.setdefault(base, []).append(system)
    return {
        base: sorted(members, key=lambda s: int(s.params[MEMBER]))
        for base, members in groups.items()
    }


def search_runs(path: Path | str) -> dict:
    """A member's search file as the fill reads it: {values, threshold, survived} (the search's
    values run and its bracket's upper and lower end, NaN where it has none)."""
    with open_result(path) as ds:
        parameter = ds.attrs.get("search_parameter")
        if parameter not in ds.variables or "collapse_threshold" not in ds:
            raise InputError(
                "searches",
                f"{path} is not a threshold search's file (no {parameter or 'parameter'} runs)",
                "give the files its threshold searches wrote",
            )
        return {
            "values": np.asarray(ds[parameter].values, dtype=float).ravel(),
            "threshold": float(ds["collapse_threshold"]),
            "survived": float(ds["survived_below_threshold"]),
            "parameter": parameter,
            "units": str(ds[parameter].attrs.get("units", "")),
        }


def fill_stripes(
    systems: list[Case],
    search_paths: list,
    runs_dir: Path | str | None,
    output: Path | str,
    store,
    log=None,
) -> xr.Dataset:
    """Run the stripe fills of one system's members (``systems``, their searches in
    ``search_paths``, the same order): the fills' table in ``output`` (one row per fill: the
    member's system id, j, value, collapsed), and each missing (member, value) run as a case
    file in ``runs_dir`` (None: no run files, as a search without them). Returns that table."""
    from stonedem.study.ensemble import stripe_requests
    from stonedem.study.runner import run_one, run_slim

    if len(systems) != len(search_paths) or not systems:
        raise InputError(
            "searches",
            f"{len(systems)} member systems and {len(search_paths)} search files",
            "give one search file per member system",
        )
    found = [search_runs(path) for path in search_paths]
    members = [int(s.params[MEMBER]) for s in systems]
    missing = stripe_requests(
        members,
        [f["values"] for f in found],
        [f["threshold"] for f in found],
        [f["survived"] for f in found],
    )  # (j, value), in the order (value, j)
    by_member = dict(zip(members, systems))
    if runs_dir is not None:
        runs_dir = Path(runs_dir)
        runs_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    for n, (j, value) in enumerate(missing):
        case = search_case(by_member[j], value)
        label = f"[stripe {n + 1}/{len(missing)}] "
        if runs_dir is None:
            collapsed = run_slim(case, store.records_dir, label, log).collapsed
        else:
            collapsed = run_one(case, runs_dir / f"{case.id}.nc", store, label, log)["collapsed"]
        rows.append((by_member[j].id, j, value, int(collapsed)))
    base = systems[0]
    parameter, units = found[0]["parameter"], found[0]["units"]
    ds = xr.Dataset(
        {
            "stripe_system": (
                "stripe",
                np.array([r[0] for r in rows], dtype=object),
                {"long_name": "the member's search system (case id)"},
            ),
            "stripe_member": (
                "stripe",
                np.array([r[1] for r in rows], dtype=np.int32),
                {"units": "1", "long_name": "ensemble member j of the fill"},
            ),
            "stripe_value": (
                "stripe",
                np.array([r[2] for r in rows], dtype=float),
                {
                    "units": units,
                    "long_name": f"{parameter} of the fill (a value another member ran)",
                },
            ),
            "stripe_collapsed": (
                "stripe",
                np.array([r[3] for r in rows], dtype=np.int8),
                {"units": "1", "long_name": "1: the fill collapsed"},
            ),
        },
        coords={
            "stripe": (
                "stripe",
                np.arange(len(rows), dtype=np.int32),
                {"long_name": "fill, by (value, j)"},
            )
        },
        attrs={
            "title": f"stonedem stripe fills: {base.study}, {len(systems)} members",
            "study": base.study,
            "search_parameter": parameter,
            "members": len(systems),
            "systems": " ".join(s.id for s in systems),
            "method": "every value a member ran inside the zone [lowest survived, highest "
            "threshold], run by "
            "every member (stonedem.study.stripes.missing_stripe_runs)",
        },
    )
    write_dataset(ds, output)
    print(
        f"{base.study}: {len(rows)} stripe fills over {len(systems)} members",
        file=log or sys.stderr,
        flush=True,
    )
    return ds


def stripe_pieces(stripe_paths) -> dict[str, xr.Dataset]:
    """{member system id: its fills on ``stripe_run`` (stripe_value, stripe_collapsed)} from
    the fill tables of :func:`fill_stripes`, to merge into each member's search piece."""
    out = {}
    for path in stripe_paths:
        with open_result(path) as ds:
            ds = ds.load()
        systems = [str(s) for s in ds["stripe_system"].values]
        for system in dict.fromkeys(systems):
            rows = [k for k, s in enumerate(systems) if s == system]
            mine = (
                ds[["stripe_value", "stripe_collapsed"]]
                .isel(stripe=rows)
                .drop_vars("stripe", errors="ignore")
            )
            out[system] = mine.rename({"stripe": STRIPE_RUN}).assign_coords(
                {
                    STRIPE_RUN: (
                        STRIPE_RUN,
                        np.arange(len(rows), dtype=np.int32),
                        {"long_name": "stripe fill of the member's search"},
                    )
                }
            )
    return out
