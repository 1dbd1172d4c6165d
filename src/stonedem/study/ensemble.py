"""The study as an ensemble: every grid case and every threshold search run by K members that
differ only in the last bits of k_n (:mod:`stonedem.study.members`), so that the chaotic
answers come with their spread (issue 44; ../shared/research/ENSEMBLES.md, sections 3 and 4).

Each member j runs every grid case (a collapse verdict) and every search system (the study's
search, :func:`stonedem.study.search.search`). Then each system's "stripes" are completed
(:func:`stonedem.study.stripes.missing_stripe_runs`): every member runs every value that any
member ran inside the union of the members' brackets, so that the probit fit of a50 sees the
same values for all members. Optionally the exact checks (layer A) and the short-horizon
trajectories (layer B) of :mod:`stonedem.study.exact_checks` go into the same file, the input
of :mod:`stonedem.study.equivalence`. The file's layout: module docstring of that module and
the issue's file contract (a ``member`` dim; ``case``, ``system``, ``run`` tables).

    python -m stonedem.study.ensemble [--config config/config.yaml] [--studies a b] [--members 20]
        [--first 0] [--perturbation stiffness] [--jobs 2] [--checks full|quick|none]
        [--from-rounding rounding.nc] --out ensemble.nc

``--from-rounding`` takes a :mod:`benchmarks.rounding` file (its perturbations 0..K are
members 0..K of the stiffness perturbation) instead of running the members again: its
searches are replayed from their collapse maps, so only the stripe fills and the checks run.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import math
import os
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.spec import Field, Spec
from stonedem.study import members as members_module
from stonedem.study.members import (
    MAX_MEMBERS,
    PERTURBATION,
    PERTURBATIONS,
    check_member,
    check_perturbation,
    member_scene,
    perturbation_rule,
    perturbation_summary,
)
from stonedem.study.runner import machine

RECORDS = Path("records")  # the cases' records, from the repository root (as the workflow runs)
MAX_JOBS = 256
CHECKS = ("full", "quick", "none")
STRIPE = "stripe"  # run_phase of a stripe fill
ROUNDING_FIX = "give a rounding.nc of python -m benchmarks.rounding"


class MemberResults(NamedTuple):
    """What :func:`run_members` returns, in plain data (index k follows ``members``):

    verdicts[i][k]: {collapsed, max_rocking [rad], dt [s]} of grid case i;
    searches[i][k]: {lower, upper, n_runs, status, dt, runs: [(value, collapsed, phase)]} of
    search system i; stripes[i]: [(j, value, collapsed)] of the stripe fills of system i, in
    the order (value, j).
    """

    members: list
    perturbation: str
    verdicts: list
    searches: list
    stripes: list


# --- one task -------------------------------------------------------------------------------


def member_verdict(case, j: int, perturbation: str = "stiffness") -> dict:
    """One grid case run by member j: {collapsed, max_rocking [rad], dt [s]} (the run's
    measures, without building its dataset)."""
    from stonedem.engine.run import checked_run, response_measures
    from stonedem.study.runner import case_scene

    run = checked_run(member_scene(case_scene(case, RECORDS), j, perturbation))
    measures = response_measures(run.scene, run.result, run.checks)
    return {
        "collapsed": int(measures["collapsed"][1]),
        "max_rocking": float(measures["max_rocking"][1]),
        "dt": float(run.result.dt),
    }


def member_value(system, value: float, j: int, perturbation: str = "stiffness") -> dict:
    """Search system ``system`` run at ``value`` of its parameter by member j: {collapsed, dt
    [s]}."""
    from stonedem.study.grid import search_case

    found = member_verdict(search_case(system, value), j, perturbation)
    return {"collapsed": found["collapsed"], "dt": found["dt"]}


def member_search(system, j: int, perturbation: str = "stiffness") -> dict:
    """The threshold search of ``system`` run by member j: its bracket (search summary), its
    runs [(value, collapsed, phase)] in order and the first run's time step."""
    from stonedem.study.search import search

    dts = []

    def simulate(value: float, phase: str) -> bool:
        result = member_value(system, value, j, perturbation)
        dts.append(result["dt"])
        return bool(result["collapsed"])

    return search_result(
        search(simulate, system.search), system.search, dts[0] if dts else math.nan
    )


def search_result(runs, settings, dt: float) -> dict:
    """A member's search as :func:`member_search` gives it, from its runs."""
    from stonedem.study.search import summary

    result = summary(runs, settings)
    return {
        "lower": float(result["lower"]),
        "upper": float(result["upper"]),
        "n_runs": int(result["n_runs"]),
        "status": str(result["status"]),
        "dt": dt,
        "runs": [(float(r.value), bool(r.collapsed), str(r.phase)) for r in runs],
    }


def _task(item):
    """Worker: (kind, index, case as a dict, j, perturbation, value) -> (item, result, seconds)."""
    from stonedem.study.grid import Case

    kind, _, spec, j, perturbation, value = item
    case = Case.from_dict(spec)
    start = time.perf_counter()
    if kind == "search":
        result = member_search(case, j, perturbation)
    elif kind == STRIPE:
        result = member_value(case, value, j, perturbation)
    else:
        result = member_verdict(case, j, perturbation)
    return item, result, time.perf_counter() - start


def _worker_init():
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")


@contextlib.contextmanager
def _pool(jobs: int):
    """A function mapping _task over items (results in any order): in this process for one
    job, else over ``jobs`` spawned workers (one pool for every phase of a run)."""
    if jobs <= 1:
        yield lambda items: map(_task, items)
        return
    import multiprocessing

    with multiprocessing.get_context("spawn").Pool(jobs, initializer=_worker_init) as pool:
        yield lambda items: pool.imap_unordered(_task, items, chunksize=1)


# --- every task ------------------------------------------------------------------------------


def run_members(
    cases,
    systems,
    members,
    jobs: int,
    perturbation: str = "stiffness",
    log=sys.stderr,
    stripes: bool = True,
    label: str = "member",
) -> MemberResults:
    """Every grid case and search system of the lists run by every member j of ``members``,
    over ``jobs`` worker processes (the searches first: they are the longest tasks); then,
    with ``stripes``, each system's stripe fills (:func:`stripe_requests`) in the same pool.
    One line per finished task goes to ``log`` ("[done/total] ..."; ``label`` names j there)."""
    members = [check_member(j) for j in members]
    if len(set(members)) != len(members):
        raise InputError("members", f"a member index repeats in {members}", "give each j once")
    check_perturbation(perturbation, "perturbation")
    items = [
        ("search", i, s.as_dict(), j, perturbation, None)
        for i, s in enumerate(systems)
        for j in members
    ]
    items += [
        ("case", i, c.as_dict(), j, perturbation, None)
        for i, c in enumerate(cases)
        for j in members
    ]
    tasks = _Tasks(cases, systems, members, log, label)
    with _pool(jobs) as run:
        tasks.run(run, items)
        results = tasks.results(perturbation)
        if stripes:
            tasks.run(run, _stripe_items(results, systems))
    return tasks.results(perturbation)


def run_stripes(results: MemberResults, systems, jobs: int, log=sys.stderr) -> MemberResults:
    """``results`` (searches done) with each system's stripe fills run, as :func:`run_members`
    runs them."""
    items = _stripe_items(results, systems)
    if not items:
        return results
    tasks = _Tasks([], systems, results.members, log, "member")
    with _pool(jobs) as run:
        tasks.run(run, items)
    return results._replace(stripes=tasks.results(results.perturbation).stripes)


def _stripe_items(results: MemberResults, systems) -> list:
    items = []
    for i, system in enumerate(systems):
        searches = results.searches[i]
        requests = stripe_requests(
            results.members,
            [[v for v, _, _ in r["runs"]] for r in searches],
            [r["upper"] for r in searches],
            [r["lower"] for r in searches],
        )
        items += [
            (STRIPE, i, system.as_dict(), j, results.perturbation, value) for j, value in requests
        ]
    return items


class _Tasks:
    """The results of the tasks as they finish (in any order), and a log line for each."""

    def __init__(self, cases, systems, members, log, label):
        self.cases, self.systems, self.members, self.log, self.label = (
            cases,
            systems,
            list(members),
            log,
            label,
        )
        self.column = {j: k for k, j in enumerate(self.members)}
        self.verdicts = [[None] * len(self.members) for _ in cases]
        self.searches = [[None] * len(self.members) for _ in systems]
        self.fills = [{} for _ in systems]
        self.done = self.total = 0

    def run(self, run, items):
        self.total += len(items)
        for out in run(items):
            self.book(*out)

    def book(self, item, result, seconds):
        kind, i, _, j, _, value = item
        self.done += 1
        if kind == "search":
            system = self.systems[i]
            self.searches[i][self.column[j]] = result
            what = (
                f"{system.study}/{system.id} {self.label} {j}: {result['status']}, "
                f"{result['lower']:.4g} ... {result['upper']:.4g}, {result['n_runs']} runs"
            )
        elif kind == STRIPE:
            system = self.systems[i]
            self.fills[i][(value, j)] = int(result["collapsed"])
            what = (
                f"{system.study}/{system.id} {self.label} {j} stripe at {value:.4g}: "
                f"{'collapsed' if result['collapsed'] else 'stands'}"
            )
        else:
            case = self.cases[i]
            self.verdicts[i][self.column[j]] = result
            what = (
                f"{case.study}/{case.id} {self.label} {j}: "
                f"{'collapsed' if result['collapsed'] else 'stands'}"
            )
        print(f"  [{self.done}/{self.total}] {what} ({seconds:.1f} s)", file=self.log, flush=True)

    def results(self, perturbation) -> MemberResults:
        stripes = [[(j, v, c) for (v, j), c in sorted(fills.items())] for fills in self.fills]
        return MemberResults(self.members, perturbation, self.verdicts, self.searches, stripes)


def stripe_requests(members, run_values, thresholds, survived) -> list[tuple[int, float]]:
    """The (j, value) runs that complete one system's stripes
    (:func:`stonedem.study.stripes.missing_stripe_runs`: none a member has run already), in the
    order (value, j). Per member j of ``members``: the values its search ran, and its
    bracket's upper end (threshold) and lower end (survived), NaN where it has none."""
    from stonedem.study.stripes import missing_stripe_runs

    values = [v for mine in run_values for v in mine]
    run_by = [j for j, mine in zip(members, run_values) for _ in mine]
    missing = missing_stripe_runs(
        np.array(values, dtype=float),
        np.array(run_by, dtype=np.int64),
        np.array(thresholds, dtype=float),
        np.array(survived, dtype=float),
        member_ids=np.array(members, dtype=np.int64),
    )
    return sorted(missing, key=lambda pair: (pair[1], pair[0]))


# --- a rounding file as the members' runs ----------------------------------------------------


def read_rounding(path, field: str = "--from-rounding") -> xr.Dataset:
    """A :mod:`benchmarks.rounding` file, in memory, with what :func:`from_rounding` reads
    (perturbations 0..K, the cases' verdicts, the searches' collapse maps and brackets), or an
    InputError naming ``field``."""
    from stonedem import options

    ds = options.read_netcdf(path, field, "rounding.nc of benchmarks.rounding", ROUNDING_FIX)
    needed = [
        name
        for dim, names in (
            ("case", ("collapsed", "max_rocking", "case_dt")),
            (
                "system",
                (
                    "collapse_map",
                    "collapse_value",
                    "survived_value",
                    "n_runs",
                    "search_status",
                    "search_dt",
                ),
            ),
        )
        if dim in ds.dims
        for name in names
        if name not in ds.variables
    ]
    if "perturbation" not in ds.dims:
        problem = f"{path} has no perturbation dimension"
    elif needed:
        problem = f"{path} lacks {', '.join(needed)}"
    elif [int(j) for j in ds.perturbation.values] != list(range(ds.sizes["perturbation"])):
        problem = f"perturbations {[int(j) for j in ds.perturbation.values]} are not 0..K"
    else:
        return ds
    raise InputError(field, problem, ROUNDING_FIX)


def from_rounding(
    rounding, cases, systems, jobs: int = 1, log=sys.stderr, stripes: bool = True
) -> MemberResults:
    """The results :func:`run_members` gives for ``cases`` and ``systems`` (the config's, in
    its order) with members 0..K, read from a :mod:`benchmarks.rounding` file of the same
    cases (its path, or the dataset :func:`read_rounding` gave) instead of run: its
    perturbations 0..K are the stiffness members 0..K. Each search is replayed from its
    collapse map (the rule picks each next value, the map gives its outcome: the same values,
    to the last bit, and phases); then, with ``stripes``, the stripe fills run (``jobs``
    processes). An InputError when the file is not such a file or does not match."""
    from stonedem.study.search import Run, next_value

    field = "--from-rounding"
    ds = rounding if isinstance(rounding, xr.Dataset) else read_rounding(rounding, field)
    members = [int(j) for j in ds.perturbation.values]

    def names(dim, items):
        have = [str(v) for v in ds[dim].values] if dim in ds.dims else []
        want = [f"{c.study}/{c.id}" for c in items]
        if sorted(have) != sorted(want):
            extra, lacking = sorted(set(have) - set(want)), sorted(set(want) - set(have))
            raise InputError(
                field,
                f"its {dim}s differ from the config's ({len(lacking)} missing, e.g. "
                f"{lacking[:1]}; {len(extra)} not in the config, e.g. {extra[:1]})",
                "give the --config and --studies the rounding run was made with",
            )
        return [have.index(name) for name in want]

    case_rows, system_rows = names("case", cases), names("system", systems)
    verdicts = [
        [
            {
                "collapsed": int(ds.collapsed.values[r, k]),
                "max_rocking": float(ds.max_rocking.values[r, k]),
                "dt": float(ds.case_dt.values[r, k]),
            }
            for k in range(len(members))
        ]
        for r in case_rows
    ]
    searches = []
    for system, r in zip(systems, system_rows):
        row = []
        for k, j in enumerate(members):
            outcomes = {}
            for entry in str(ds.collapse_map.values[r, k]).split():
                text, _, mark = entry.rpartition(":")
                outcomes[text] = mark == "X"
            runs = []
            while (step := next_value(runs, system.search)) is not None:
                key = f"{step[0]:.4g}"  # how rounding.run_threshold wrote the value
                if key not in outcomes:
                    break
                runs.append(Run(step[0], outcomes[key], step[1]))
            result = search_result(runs, system.search, float(ds.search_dt.values[r, k]))
            stored = (
                float(ds.survived_value.values[r, k]),
                float(ds.collapse_value.values[r, k]),
                int(ds.n_runs.values[r, k]),
                str(ds.search_status.values[r, k]),
            )
            if step is not None or not _same(
                (result["lower"], result["upper"], result["n_runs"], result["status"]), stored
            ):
                raise InputError(
                    field,
                    f"the search of {system.study}/{system.id}, perturbation {j}, does not "
                    "replay from its collapse map with the config's search settings",
                    "give the config the rounding run was made with, or run the members directly",
                )
            row.append(result)
        searches.append(row)
    results = MemberResults(members, "stiffness", verdicts, searches, [[] for _ in systems])
    if stripes and systems:
        results = run_stripes(results, systems, jobs, log)
    return results


def _same(a, b) -> bool:
    return all(
        x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)) for x, y in zip(a, b)
    )


# --- the file ---------------------------------------------------------------------------------


def ensemble_dataset(
    cases, systems, results: MemberResults, checks: str = "none", attrs: dict | None = None
) -> xr.Dataset:
    """The ensemble as a self-describing dataset (the file contract of issue 44: ``member``,
    ``case``, ``system`` and ``run`` dimensions), with the exact checks (layer A) and the
    short-horizon trajectories (layer B) of :mod:`stonedem.study.exact_checks` unless
    ``checks`` is "none" ("quick": layer A's quick set). ``attrs`` go on top of the file's."""
    from stonedem.io.netcdf import code_version
    from stonedem.study.grid import PARAMETERS
    from stonedem.study.runner import library_versions

    checks = OPTIONS["--checks"].check(checks, "checks")
    members = np.array(results.members, dtype=np.int32)
    coords = {
        "member": (
            "member",
            members,
            {
                "units": "1",
                "long_name": f"member j: contact stiffness k_n times "
                f"1 - j 2^-52 ({results.perturbation})",
            },
        )
    }
    data = {}
    if cases:

        def table(key, dtype=float):
            return np.array([[v[key] for v in row] for row in results.verdicts], dtype=dtype)

        coords["case"] = (
            "case",
            np.array([f"{c.study}/{c.id}" for c in cases], dtype=object),
            {"long_name": "study/case of a grid case"},
        )
        coords["case_study"] = (
            "case",
            np.array([c.study for c in cases], dtype=object),
            {"long_name": "study of the case"},
        )
        data["collapsed"] = (
            ("case", "member"),
            table("collapsed", np.int8),
            {"units": "1", "long_name": "collapse verdict (1: collapsed, 0: stands)"},
        )
        data["max_rocking"] = (
            ("case", "member"),
            table("max_rocking"),
            {"units": "rad", "long_name": "peak mean rotation of the rocking bodies"},
        )
        data["case_dt"] = (
            ("case", "member"),
            table("dt"),
            {"units": "s", "long_name": "time step of the run"},
        )
    if systems:

        def grid(key, dtype=float):
            return np.array([[t[key] for t in row] for row in results.searches], dtype=dtype)

        measures = [s.search.parameter for s in systems]
        unit = PARAMETERS[measures[0]][1] if len(set(measures)) == 1 else "see search_parameter"
        coords["system"] = (
            "system",
            np.array([f"{s.study}/{s.id}" for s in systems], dtype=object),
            {"long_name": "study/system of a threshold search"},
        )
        coords["search_parameter"] = (
            "system",
            np.array(measures, dtype=object),
            {"long_name": "intensity measure searched"},
        )
        coords["search_tolerance"] = (
            "system",
            np.array([s.search.tolerance for s in systems]),
            {"units": "1", "long_name": "bracket the search aims for, relative"},
        )
        coords["search_maximum"] = (
            "system",
            np.array([s.search.maximum for s in systems]),
            {"units": unit, "long_name": "largest value the search runs"},
        )
        data["threshold"] = (
            ("system", "member"),
            grid("upper"),
            {
                "units": unit,
                "long_name": "smallest collapsing value of the member's search "
                "(NaN: no collapse up to the maximum)",
            },
        )
        data["survived"] = (
            ("system", "member"),
            grid("lower"),
            {"units": unit, "long_name": "largest surviving value below the threshold"},
        )
        data["search_status"] = (
            ("system", "member"),
            grid("status", object),
            {"long_name": "how the search ended"},
        )
        data["search_runs"] = (
            ("system", "member"),
            grid("n_runs", np.int32),
            {"units": "1", "long_name": "runs of the member's search"},
        )
        # (system, member, value, collapsed, phase): each search in its order, then the stripes
        rows = []
        for i in range(len(systems)):
            for j, result in zip(results.members, results.searches[i]):
                rows += [
                    (i, j, value, collapsed, phase) for value, collapsed, phase in result["runs"]
                ]
            rows += [(i, j, value, collapsed, STRIPE) for j, value, collapsed in results.stripes[i]]
        columns = list(zip(*rows)) if rows else [[]] * 5
        data["run_system"] = (
            "run",
            np.array(columns[0], dtype=np.int32),
            {"units": "1", "long_name": "index of the run's system on the system dimension"},
        )
        data["run_member"] = (
            "run",
            np.array(columns[1], dtype=np.int32),
            {"units": "1", "long_name": "member j of the run"},
        )
        data["run_value"] = (
            "run",
            np.array(columns[2], dtype=float),
            {"units": unit, "long_name": "value of the searched parameter run"},
        )
        data["run_collapsed"] = (
            "run",
            np.array(columns[3], dtype=np.int8),
            {"units": "1", "long_name": "collapse verdict of the run (1: collapsed)"},
        )
        data["run_phase"] = (
            "run",
            np.array(columns[4], dtype=object),
            {
                "long_name": "phase of the run: the search's (hunt, bisect, fill; search: not "
                "kept) "
                "or stripe (a stripe fill)"
            },
        )
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": f"ensemble of {len(members)} members: the study's verdicts and thresholds "
            "with "
            f"{perturbation_summary(results.perturbation)} in the last bits",
            "members": int(len(members)),
            "first_member": int(members[0]) if len(members) else 0,
            "perturbation": results.perturbation,
            "perturbation_rule": perturbation_rule(results.perturbation),
            "source": code_version(),
            "machine": machine(),
            "checks": checks,
            **library_versions(),
        },
    )
    ds.attrs["llvmlite_version"] = _version("llvmlite")
    ds.member.attrs.update(
        perturbation=results.perturbation,
        members=int(len(members)),
        first_member=ds.attrs["first_member"],
    )
    ds = with_bands(ds, systems)
    if checks != "none":
        from stonedem.study import exact_checks

        for name, layer in (
            ("layer_a", exact_checks.layer_a(quick=checks == "quick")),
            ("layer_b", exact_checks.layer_b(duration=0.5)),
        ):
            ds = xr.merge(
                [ds, layer], combine_attrs="override"
            )  # the layers' provenance is this file's
            if "wall_seconds" in layer.attrs:
                ds.attrs[f"{name}_wall_seconds"] = float(layer.attrs["wall_seconds"])
    ds.attrs.update(attrs or {})
    return ds


def with_bands(ds: xr.Dataset, systems) -> xr.Dataset:
    """The ensemble's answers beside its members (issue 44, what the docs' Table 7.1 and grid
    pages read): each grid case's collapse fraction, and each search's a50, its band, the
    transition zone and the member thresholds (:func:`stonedem.study.stripes.threshold_band`
    over the search and stripe runs of every member), with the thesis' Table 7.1 value."""
    from stonedem.study.reduce import thesis_threshold
    from stonedem.study.stripes import threshold_band

    if "collapsed" in ds:
        fraction = ds["collapsed"].mean("member")
        ds["collapse_fraction"] = fraction.assign_attrs(
            units="1", long_name="share of the members that collapse"
        )
        ds["split"] = (
            ((fraction > 0) & (fraction < 1))
            .astype(np.int8)
            .assign_attrs(
                units="1", long_name="1 where the members disagree (0 < collapse fraction < 1)"
            )
        )
        by_study = ds["split"].groupby(ds["case_study"].rename("study"))
        ds["study_cases"] = (
            by_study.count().astype(np.int32).assign_attrs(units="1", long_name="grid cases")
        )
        ds["study_split_cases"] = (
            by_study.sum()
            .astype(np.int32)
            .assign_attrs(units="1", long_name="grid cases the members disagree on")
        )
        ds["study"].attrs["long_name"] = "study"
    if not systems:
        return ds
    unit = ds["threshold"].attrs.get("units", "1")
    names = {
        "a50": (
            unit,
            "a50: value at which half the members collapse (probit fit over the stripes)",
        ),
        "a50_low": (unit, "lower end of the 90 % band of a50, bootstrapped over members"),
        "a50_high": (unit, "upper end of the 90 % band of a50, bootstrapped over members"),
        "beta": ("1", "probit dispersion of the collapse probability in ln value"),
        "a_first": (unit, "transition zone: lowest value at which any member collapsed"),
        "a_all": (
            unit,
            "transition zone: value from which every run above collapsed in every member",
        ),
        "threshold_median": (unit, "median of the member search thresholds"),
        "threshold_min": (unit, "smallest member search threshold"),
        "threshold_max": (unit, "largest member search threshold"),
        "threshold_distinct": ("1", "distinct member search thresholds"),
        "threshold_member_0": (unit, "member 0's search threshold: the study as configured"),
        "thesis_threshold": (
            unit,
            "thesis Table 7.1: acceleration to cause failure (NaN: not a Table 7.1 cell)",
        ),
    }
    rows = {name: [] for name in names}
    status = []
    first = int(np.argmin(ds["member"].values))  # member 0, or a candidate's first member
    for i, system in enumerate(systems):
        runs = ds["run_system"].values == i
        band = threshold_band(
            ds["run_value"].values[runs],
            ds["run_member"].values[runs],
            ds["run_collapsed"].values[runs],
            ds["threshold"].values[i],
        )
        for name in names:
            if name in band:
                rows[name].append(band[name])
        rows["threshold_member_0"].append(float(ds["threshold"].values[i, first]))
        kind = "colonnade" if "colonnade" in system.study else "single column"
        rows["thesis_threshold"].append(
            thesis_threshold(
                kind, system.params.get("n_drums"), str(system.params.get("record", ""))
            )
        )
        status.append(band["status"])
    for name, (units, long_name) in names.items():
        dtype = np.int32 if name == "threshold_distinct" else float
        ds[name] = (
            "system",
            np.array(rows[name], dtype=dtype),
            {"units": units, "long_name": long_name},
        )
    ds["fit_status"] = (
        "system",
        np.array(status, dtype=object),
        {"long_name": "how the probit fit of a50 ended"},
    )
    ds.attrs["band_level"] = 0.90
    return ds


def _version(name: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return "not installed"


def config_digest(paths) -> str:
    """sha256 of the config files' bytes, in order."""
    digest = hashlib.sha256()
    for path in paths:
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()


def summary_lines(ds: xr.Dataset, wall_seconds: float) -> list[str]:
    """What the ensemble holds and where its members disagree."""
    lines = [
        f"{ds.attrs['members']} members ({ds.attrs['perturbation']}, j = {ds.member.values[0]}.."
        f"{ds.member.values[-1]}), {ds.sizes.get('case', 0)} grid cases, "
        f"{ds.sizes.get('system', 0)} "
        f"threshold searches, {ds.sizes.get('run', 0)} search and stripe runs, {wall_seconds:.0f} s"
    ]
    if "case" in ds.dims:
        split = [str(c) for c in ds.case.values[ds["split"].values.astype(bool)]]
        lines.append(
            f"split cases (0 < collapse fraction < 1): {len(split)} of {ds.sizes['case']}"
            + (f": {', '.join(split[:10])}{' ...' if len(split) > 10 else ''}" if split else "")
        )
    if "system" in ds.dims:
        differ = 0
        for k, name in enumerate(ds.system.values):
            values = ds.threshold.values[k]
            distinct = np.unique(values[np.isfinite(values)])
            if distinct.size > 1 or (distinct.size and not np.isfinite(values).all()):
                differ += 1
                lines.append(
                    f"  {name}: member thresholds {np.nanmin(values):.4g} ... "
                    f"{np.nanmax(values):.4g} "
                    f"({distinct.size} values)"
                )
        lines.append(f"cells whose member thresholds differ: {differ} of {ds.sizes['system']}")
    return lines


# --- the command ------------------------------------------------------------------------------


def build_parser():
    from stonedem import options
    from stonedem.study import config_options

    parser = options.parser("python -m stonedem.study.ensemble", __doc__)
    config_options.add_study_arguments(parser)
    parser.add_argument(
        "--members",
        type=int,
        default=None,
        help=f"K, members to run, 1 to {MAX_MEMBERS} (default 20; with --from-rounding: the "
        "file's)",
    )
    parser.add_argument(
        "--first",
        type=int,
        default=0,
        help="the first member's j (default 0; fresh draws: past a baseline's)",
    )
    parser.add_argument(
        "--perturbation",
        default="stiffness",
        help=f"{' or '.join(PERTURBATIONS)} (default stiffness)",
    )
    parser.add_argument(
        "--jobs",
        type=int,
        default=os.cpu_count() or 1,
        help=f"worker processes, 1 to {MAX_JOBS} (default: the CPUs)",
    )
    parser.add_argument(
        "--checks", default="full", help=f"layers A and B: {', '.join(CHECKS)} (default full)"
    )
    parser.add_argument(
        "--from-rounding",
        type=options.path_arg,
        default=None,
        help="a rounding.nc of benchmarks.rounding: its runs are the members' "
        "(stiffness, j = 0..K)",
    )
    parser.add_argument(
        "--out", type=options.path_arg, required=True, help="the ensemble file to write (.nc)"
    )
    return parser


DEFAULT_MEMBERS = 20
# the options a run takes, as check_args checks them (--members: at most MAX_MEMBERS - --first)
OPTIONS = Spec(
    (
        Field("--jobs", "integer", range=f"[1, {MAX_JOBS}]", hint="give e.g. --jobs 2"),
        Field("--checks", "choice", default="full", choices=CHECKS, doc="layers A and B"),
        dataclasses.replace(PERTURBATION, key="--perturbation"),
        Field(
            "--first",
            "integer",
            range=f"[0, {MAX_MEMBERS - 1}]",
            default=0,
            hint="give e.g. --first 20",
        ),
        Field(
            "--members",
            "integer",
            range=f"[1, {MAX_MEMBERS}]",
            default=DEFAULT_MEMBERS,
            hint="give e.g. --members 20",
        ),
    )
)


def check_args(args) -> dict:
    """Every option, the config, the cases (their scenes built once) and the output path
    checked before anything runs; an InputError otherwise."""
    from stonedem import options
    from stonedem.study import config_options

    names = ("--jobs", "--checks", "--perturbation", "--first")
    values = OPTIONS.check({k: getattr(args, k[2:]) for k in names})
    jobs, checks, perturbation, first = (values[k] for k in names)
    rounding = None
    if args.from_rounding is not None:
        rounding = read_rounding(args.from_rounding)
        members = [int(j) for j in rounding.perturbation.values]
        if perturbation != "stiffness" or first != 0 or args.members not in (None, len(members)):
            raise InputError(
                "--from-rounding",
                f"its runs are members 0..{len(members) - 1} of the stiffness perturbation",
                "leave --members, --first and --perturbation out",
            )
    else:
        most = MAX_MEMBERS - first
        count = dataclasses.replace(
            OPTIONS["--members"],
            range=f"[1, {most}]",
            hint=f"give 1 ... {most} (j < {MAX_MEMBERS} from --first {first})",
        ).check(DEFAULT_MEMBERS if args.members is None else args.members)
        members = list(range(first, first + count))
    config_paths = [Path(args.config).parent / "config.yaml", Path(args.config)]
    config, known = config_options.study_config(args.config, RECORDS)
    path = options.output_file(
        args.out,
        "--out",
        suffixes=(".nc",),
        inputs=[*config_paths, *([args.from_rounding] if rounding is not None else [])],
    )
    cases, systems = config_options.chosen_cases(config, known, args.studies, RECORDS)
    if perturbation != "stiffness":  # a tilt refuses a scene tilted already: here, not in a worker
        from stonedem.study.runner import case_scene

        for case in cases + systems:  # members.member_scene: a benchmark may patch ours
            scene = case_scene(case, RECORDS)
            where = f"--perturbation: {case.study}/{case.id}"
            members_module.member_scene(scene, max(members[-1], 1), perturbation, where)
    return {
        "cases": cases,
        "systems": systems,
        "members": members,
        "first": first,
        "perturbation": perturbation,
        "jobs": jobs,
        "checks": checks,
        "rounding": rounding,
        "path": path,
        "config": [str(p) for p in dict.fromkeys(config_paths)],
    }


def rounding_provenance(rounding: xr.Dataset | None) -> dict:
    """How the members' runs of a rounding file were made (its wall time and history), or {}."""
    if rounding is None:
        return {}
    return {
        f"members_{k}": rounding.attrs[k]
        for k in ("wall_seconds", "history", "source", "machine")
        if k in rounding.attrs
    }


def main(argv=None) -> int:
    """Options, config, cases and output path checked first (one line, exit 2); then the runs."""
    from stonedem import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import code_version, write_dataset

        # the commit as the run starts (asked once a process): a checkout may move during it
        code_version()
        plan = check_args(args)
        start = time.perf_counter()
        cases, systems = plan["cases"], plan["systems"]
        if plan["rounding"] is not None:
            print(
                f"{len(cases)} cases and {len(systems)} threshold searches of "
                f"{args.from_rounding}, "
                f"{len(plan['members'])} members: stripe fills on {plan['jobs']} process(es)",
                file=sys.stderr,
                flush=True,
            )
            results = from_rounding(plan["rounding"], cases, systems, plan["jobs"])
        else:
            print(
                f"{len(cases)} cases and {len(systems)} threshold searches, members "
                f"{plan['members'][0]}.."
                f"{plan['members'][-1]} ({plan['perturbation']}), on {plan['jobs']} process(es)",
                file=sys.stderr,
                flush=True,
            )
            results = run_members(
                cases, systems, plan["members"], plan["jobs"], plan["perturbation"]
            )
        command_line = " ".join(
            ["python -m stonedem.study.ensemble", *(sys.argv[1:] if argv is None else argv)]
        )
        ds = ensemble_dataset(
            cases,
            systems,
            results,
            plan["checks"],
            attrs={
                "config": " ".join(plan["config"]),
                "config_digest": config_digest(plan["config"]),
                "command": command_line,
                **(
                    {"from_rounding": str(args.from_rounding)}
                    if plan["rounding"] is not None
                    else {}
                ),
                **rounding_provenance(plan["rounding"]),
            },
        )
        wall = time.perf_counter() - start
        ds.attrs["wall_seconds"] = wall
        write_dataset(ds, plan["path"])
        for line in summary_lines(ds, wall):
            print(line)
        print(f"wrote {plan['path']}")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
