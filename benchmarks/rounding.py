"""Rounding sensitivity: how far the study's verdicts and thresholds move when only the last
bits of the arithmetic change (issue 32).

Each case of the chosen studies runs once as configured (perturbation 0) and once per
perturbation j = 1..K with its contact stiffness k_n times 1 - j 2^-52: j units in the last
place of k_n, so every contact force differs from the configured run's in its last bits and
nothing else does (the time step, snapped to the output clock, stays the same; the
tangential stiffness keeps its configured value).
A grid case gives its collapse verdict, a threshold-search system its whole search
(:func:`stonedem.study.search.search`, the study's rule and settings). Where a perturbed
verdict differs from the configured one, or a threshold moves by more than its search
bracket, the result was never determined more finely than that by the engine as it stands:
any change of the arithmetic in the last bits (another compiler, CPU, libm, or a faster
formula for the same physics) moves it as much.

    python -m benchmarks.rounding [--config config/config.yaml] [--perturbations 3] [--jobs 2]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.study.members import RELATIVE_STEP, member_scene, stiffness_factor  # noqa: F401 - re-exported

MAX_PERTURBATIONS = 64
MAX_JOBS = 256
MAX_LIMIT = 100_000
RECORDS = Path("records")  # the cases' records, from the repository root (as the workflow runs)
OUTPUT = "rounding.nc"


def perturbed_scene(case, j: int, base_dir: Path = RECORDS):
    """The case's Scene (:func:`stonedem.study.runner.case_scene`) with its contact law's k_n
    times stiffness_factor(j)."""
    from stonedem.study.runner import case_scene

    return member_scene(case_scene(case, base_dir), j)


def run_verdict(case, j: int) -> dict:
    """One grid case under perturbation j: {collapsed, max_rocking [rad], dt [s]}."""
    from stonedem.study.ensemble import member_verdict

    return member_verdict(case, j)


def run_threshold(system, j: int) -> dict:
    """One threshold-search system under perturbation j: the search's bracket and runs."""
    from stonedem.study.ensemble import member_search

    return threshold_result(member_search(system, j))


def threshold_result(result: dict) -> dict:
    """A member's search (:func:`stonedem.study.ensemble.member_search`) as this benchmark
    keeps it: its runs as a collapse map, "value:X" (collapsed) or "value:." in value order."""
    runs = sorted(result["runs"], key=lambda run: run[0])
    return {
        **{key: result[key] for key in ("lower", "upper", "n_runs", "status")},
        "collapse_map": " ".join(
            f"{value:.4g}:{'X' if collapsed else '.'}" for value, collapsed, _ in runs
        ),
        "dt": result["dt"],
    }


def run_all(cases, systems, n_perturbations: int, jobs: int, log=sys.stderr):
    """(verdicts[i][j], thresholds[i][j]) of every grid case and search system, j = 0..K,
    over ``jobs`` worker processes (:func:`stonedem.study.ensemble.run_members`, without
    stripe fills: the searches first, they are the longest tasks)."""
    from stonedem.study.ensemble import run_members

    results = run_members(
        cases,
        systems,
        range(n_perturbations + 1),
        jobs,
        log=log,
        stripes=False,
        label="perturbation",
    )
    return results.verdicts, [
        [threshold_result(result) for result in row] for row in results.searches
    ]


def rounding_dataset(cases, systems, verdicts, thresholds, n_perturbations: int) -> xr.Dataset:
    """The runs as a self-describing dataset (:func:`run_all`'s verdicts and thresholds), with
    :func:`summarize`'s spreads and verdict changes."""
    from stonedem.io.netcdf import code_version
    from stonedem.study.grid import PARAMETERS

    perturbation = np.arange(n_perturbations + 1)
    coords = {
        "perturbation": (
            "perturbation",
            perturbation,
            {
                "units": "1",
                "long_name": "j: contact stiffness k_n times 1 - j 2^-52 (0: as configured)",
            },
        ),
        "stiffness_factor": (
            "perturbation",
            np.array([stiffness_factor(j) for j in perturbation]),
            {"units": "1", "long_name": "factor on the contact stiffness k_n"},
        ),
    }
    data = {}
    if cases:

        def table(key, dtype=float):
            return np.array([[v[key] for v in row] for row in verdicts], dtype=dtype)

        coords["case"] = (
            "case",
            [f"{c.study}/{c.id}" for c in cases],
            {"units": "1", "long_name": "study/case"},
        )
        coords["case_study"] = (
            "case",
            [c.study for c in cases],
            {"units": "1", "long_name": "study of the case"},
        )
        data["collapsed"] = (
            ("case", "perturbation"),
            table("collapsed", np.int8),
            {"units": "1", "long_name": "collapse verdict (1: collapsed)"},
        )
        data["max_rocking"] = (
            ("case", "perturbation"),
            table("max_rocking"),
            {"units": "rad", "long_name": "peak mean rotation of the rocking bodies"},
        )
        data["case_dt"] = (
            ("case", "perturbation"),
            table("dt"),
            {"units": "s", "long_name": "time step of the run"},
        )
    if systems:

        def grid(key, dtype=float):
            return np.array([[t[key] for t in row] for row in thresholds], dtype=dtype)

        measures = [s.search.parameter for s in systems]
        unit = PARAMETERS[measures[0]][1] if len(set(measures)) == 1 else "see search_parameter"
        coords["system"] = (
            "system",
            [f"{s.study}/{s.id}" for s in systems],
            {"units": "1", "long_name": "study/system of a threshold search"},
        )
        coords["search_parameter"] = (
            "system",
            measures,
            {"units": "1", "long_name": "intensity measure searched"},
        )
        coords["search_tolerance"] = (
            "system",
            np.array([s.search.tolerance for s in systems]),
            {"units": "1", "long_name": "bracket the search aims for"},
        )
        data["collapse_value"] = (
            ("system", "perturbation"),
            grid("upper"),
            {"units": unit, "long_name": "smallest value run that collapsed (the threshold)"},
        )
        data["survived_value"] = (
            ("system", "perturbation"),
            grid("lower"),
            {"units": unit, "long_name": "largest value below it that survived"},
        )
        data["search_status"] = (
            ("system", "perturbation"),
            grid("status", object),
            {"units": "1", "long_name": "how the search ended"},
        )
        data["n_runs"] = (
            ("system", "perturbation"),
            grid("n_runs", np.int32),
            {"units": "1", "long_name": "runs"},
        )
        data["collapse_map"] = (
            ("system", "perturbation"),
            grid("collapse_map", object),
            {"units": "1", "long_name": "every run, value:X collapsed, value:. survived"},
        )
        data["search_dt"] = (
            ("system", "perturbation"),
            grid("dt"),
            {"units": "s", "long_name": "time step of the search's first run"},
        )
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": "rounding sensitivity: the study's verdicts and thresholds with k_n "
            "changed in its last bits",
            "source": code_version(),
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
            "perturbation": "contact stiffness k_n times 1 - j 2^-52, j = 1..K",
            "n_perturbations": int(n_perturbations),
        },
    )
    return summarize(ds)


def summarize(ds: xr.Dataset) -> xr.Dataset:
    """ds with what the runs show, against perturbation 0: each case's verdict changes, each
    study's (variables on a ``study`` dimension), each threshold's spread and largest shift
    in units of its search bracket; the totals in attrs."""
    ds = ds.copy()
    first = ds.perturbation.values[0]
    if "case" in ds.dims:
        changed = ds.collapsed.sel(perturbation=ds.perturbation[1:]) != ds.collapsed.sel(
            perturbation=first
        )
        ds["verdict_flips"] = (
            changed.sum("perturbation")
            .astype(np.int32)
            .assign_attrs(
                units="1", long_name="perturbations whose verdict differs from perturbation 0"
            )
        )
        studies = list(dict.fromkeys(str(s) for s in ds.case_study.values))
        in_study = xr.DataArray(
            np.array([[str(s) == name for s in ds.case_study.values] for name in studies]),
            dims=("study", "case"),
        )
        ds = ds.assign_coords(
            study=("study", studies, {"units": "1", "long_name": "study of the config"})
        )
        ds["study_cases"] = (
            in_study.sum("case").astype(np.int32).assign_attrs(units="1", long_name="cases")
        )
        ds["study_verdicts_changed"] = (
            (in_study & changed)
            .sum("case")
            .max("perturbation")
            .astype(np.int32)
            .assign_attrs(units="1", long_name="most verdicts one perturbation changed")
        )
        ds["study_cases_changed"] = (
            (in_study & (ds.verdict_flips > 0))
            .sum("case")
            .astype(np.int32)
            .assign_attrs(units="1", long_name="cases whose verdict any perturbation changed")
        )
        ds.attrs["n_cases"] = int(ds.sizes["case"])
        ds.attrs["verdicts_changed_per_perturbation"] = np.array(
            changed.sum("case").values, dtype=np.int32
        )
        ds.attrs["cases_with_any_change"] = int((ds.verdict_flips > 0).sum())
    if "system" in ds.dims:
        upper = ds.collapse_value
        unit = upper.attrs.get("units", "1")
        base = upper.sel(perturbation=first)
        shift = abs(upper.sel(perturbation=ds.perturbation[1:]) / base - 1.0).max("perturbation")
        width = base / ds.survived_value.sel(perturbation=first) - 1.0
        ds["threshold"] = base.assign_attrs(
            units=unit, long_name="threshold as configured (perturbation 0)"
        )
        ds["threshold_min"] = upper.min("perturbation").assign_attrs(
            units=unit, long_name="smallest threshold over the perturbations"
        )
        ds["threshold_max"] = upper.max("perturbation").assign_attrs(
            units=unit, long_name="largest threshold over the perturbations"
        )
        ds["threshold_spread"] = (
            upper.max("perturbation") / upper.min("perturbation") - 1.0
        ).assign_attrs(units="1", long_name="largest / smallest threshold - 1")
        ds["threshold_shift"] = shift.assign_attrs(
            units="1", long_name="largest |threshold / configured threshold - 1| of a perturbation"
        )
        ds["bracket_width"] = width.assign_attrs(
            units="1", long_name="search bracket as configured: collapse / survived - 1"
        )
        ds["shift_in_brackets"] = (shift / width).assign_attrs(
            units="1", long_name="threshold_shift / bracket_width"
        )
        ds.attrs["n_systems"] = int(ds.sizes["system"])
        ds.attrs["systems_shifted_past_bracket"] = int((ds.shift_in_brackets > 1.0).sum())
        ds.attrs["largest_threshold_shift"] = float(ds.threshold_shift.max())
    return ds


def summary_lines(ds: xr.Dataset) -> list[str]:
    """What the run found, a line per study and per search system."""
    lines = []
    if "study" in ds.dims:
        for k, study in enumerate(ds.study.values):
            lines.append(
                f"{study}: {int(ds.study_cases[k])} cases, {int(ds.study_cases_changed[k])} "
                "with a verdict "
                f"changed (at most {int(ds.study_verdicts_changed[k])} by one perturbation)"
            )
        per = [int(v) for v in np.atleast_1d(ds.attrs["verdicts_changed_per_perturbation"])]
        lines.append(f"verdicts changed per perturbation: {per} of {ds.attrs['n_cases']}")
    if "system" in ds.dims:
        for k, name in enumerate(ds.system.values):
            values = ", ".join(f"{v:.4g}" for v in ds.collapse_value.values[k])
            lines.append(
                f"{name}: thresholds {values}; largest shift "
                f"{100 * float(ds.threshold_shift[k]):.1f} % = "
                f"{float(ds.shift_in_brackets[k]):.2f} brackets"
            )
    return lines


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.rounding", __doc__)
    options.add_study_arguments(parser)
    parser.add_argument(
        "--perturbations",
        type=int,
        default=3,
        help=f"K, perturbations besides the configured run, 1 to {MAX_PERTURBATIONS} (default 3)",
    )
    parser.add_argument(
        "--jobs",
        type=int,
        default=os.cpu_count() or 1,
        help=f"worker processes, 1 to {MAX_JOBS} (default: the CPUs)",
    )
    parser.add_argument(
        "--limit",
        type=int,
        default=0,
        help=f"at most this many grid cases and this many search systems, 0 to {MAX_LIMIT} (0: "
        "all)",
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=Path("results/bench"),
        help=f"output folder (writes {OUTPUT})",
    )
    return parser


def check_args(args):
    """(grid cases, search systems, K, jobs, output path), every scene built once (records
    found), or an InputError before anything runs."""
    from benchmarks import options

    n_perturbations = options.number(
        args.perturbations, "--perturbations", lo=1, hi=MAX_PERTURBATIONS, whole=True, example="3"
    )
    jobs = options.number(args.jobs, "--jobs", lo=1, hi=MAX_JOBS, whole=True, example="2")
    limit = options.number(args.limit, "--limit", lo=0, hi=MAX_LIMIT, whole=True, example="4")
    path = options.output_folder(args.out, "--out", files=(OUTPUT,)) / OUTPUT
    config, known = options.study_config(args.config, RECORDS)
    cases, systems = options.chosen_cases(config, known, args.studies, RECORDS, limit)
    return cases, systems, n_perturbations, jobs, path


def main(argv=None) -> int:
    """Options, config, cases and output path checked first (one line, exit 2); then the runs."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import code_version, write_dataset

        # the commit as the run starts (asked once a process): a checkout may move during it
        code_version()
        cases, systems, n_perturbations, jobs, path = check_args(args)
        start = time.perf_counter()
        print(
            f"{len(cases)} cases and {len(systems)} threshold searches, each as configured and "
            "with "
            f"{n_perturbations} perturbation(s) of k_n in its last bits, on {jobs} process(es)",
            file=sys.stderr,
            flush=True,
        )
        verdicts, thresholds = run_all(cases, systems, n_perturbations, jobs)
        ds = rounding_dataset(cases, systems, verdicts, thresholds, n_perturbations)
        ds.attrs["wall_seconds"] = time.perf_counter() - start
        write_dataset(ds, path)
        for line in summary_lines(ds):
            print(line)
        print(f"wrote {path} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
