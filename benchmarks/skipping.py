"""Skip what a scene does not need: before/after on the study's real cases (issue 6, item 4).

Each case of the chosen studies runs three ways: everything integrated to the end
(``stop_on_collapse`` and ``skip_quiet`` off), then stopping at collapse, then also
skipping the quiet lead and the at-rest tail (:func:`stonedem.engine.quiet.quiet_steps`). Recorded:
the compiled loop's wall time and steps, and the response measures of each way, so the
table shows what each skip saves and that the answers do not move (the error bound).

    python -m benchmarks.skipping [--config config/quick.yaml] [--out results/bench]
"""

from __future__ import annotations

import copy
import os
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.study.grid import config_cases
from stonedem.study.runner import run_case

WAYS = {
    "everything": {"stop_on_collapse": False, "skip_quiet": False},
    "stop_at_collapse": {"stop_on_collapse": True, "skip_quiet": False},
    "stop_and_skip_quiet": {"stop_on_collapse": True, "skip_quiet": True},
}
MEASURES = (
    "collapsed",
    "collapse_time",
    "max_rocking",
    "max_total_sliding",
    "residual_total_sliding",
    "max_epistyle_displacement",
)
STUDIES = ("standalone_records", "colonnade_records", "small_column_pga", "ramp_drums")


def run_ways(case, base_dir="records"):
    """{way: (kernel wall s, steps, measures)} of one case."""
    out = {}
    for way, solver in WAYS.items():
        scene = copy.deepcopy(case.scene)
        scene.setdefault("solver", {}).update(solver)
        ds = run_case(type(case)(case.study, case.id, case.params, scene), base_dir=base_dir)
        out[way] = (
            float(ds.attrs["wall_seconds"]),
            int(ds.attrs["steps_run"]),
            {m: float(ds[m].max()) if m in ds else np.nan for m in MEASURES},
            float(ds.attrs["duration"]),
            float(ds.attrs["quiet_lead_skipped"]),
            float(ds.attrs["at_rest_from"]),
        )
    return out


def skipping_dataset(cases, results) -> xr.Dataset:
    from stonedem.io.netcdf import code_version

    ways = list(WAYS)
    n = len(cases)
    wall = np.array([[results[i][w][0] for w in ways] for i in range(n)])
    steps = np.array([[results[i][w][1] for w in ways] for i in range(n)])
    data = {
        "kernel_wall": (
            ("case", "way"),
            wall,
            {"units": "s", "long_name": "wall time of the compiled loop, one core"},
        ),
        "steps": (("case", "way"), steps, {"units": "1", "long_name": "time steps integrated"}),
        "duration": (
            "case",
            np.array([results[i][ways[0]][3] for i in range(n)]),
            {"units": "s", "long_name": "simulated duration of the case"},
        ),
        "quiet_lead_skipped": (
            "case",
            np.array([results[i][ways[-1]][4] for i in range(n)]),
            {"units": "s", "long_name": "start carried by the base, not integrated (skip_quiet)"},
        ),
        "at_rest_from": (
            "case",
            np.array([results[i][ways[-1]][5] for i in range(n)]),
            {
                "units": "s",
                "long_name": "at rest on a quiet base from here, not integrated (NaN: never)",
            },
        ),
    }
    units = {
        "collapsed": "1",
        "collapse_time": "s",
        "max_rocking": "rad",
        "max_total_sliding": "m",
        "residual_total_sliding": "m",
        "max_epistyle_displacement": "m",
    }
    for m in MEASURES:
        values = np.array([[results[i][w][2][m] for w in ways] for i in range(n)])
        data[m] = (
            ("case", "way"),
            values,
            {"units": units[m], "long_name": f"{m.replace('_', ' ')} of the case"},
        )
    coords = {
        "case": (
            "case",
            [f"{c.study}/{c.id}" for c in cases],
            {"units": "1", "long_name": "study/case"},
        ),
        "way": ("way", ways, {"units": "1", "long_name": "what is skipped"}),
    }
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": "skip what a scene does not need: before/after on the study's cases",
            "source": code_version(),
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
        },
    )
    total = ds.kernel_wall.sum("case")
    for w in ways:
        ds.attrs[f"total_kernel_wall_{w}"] = float(total.sel(way=w))
    # the error bound: answers of the fastest way against everything integrated, where the
    # answer is defined the same way (not collapsed in either: a collapsed run stops early)
    standing = (ds.collapsed.sel(way="everything") == 0) & (
        ds.collapsed.sel(way="stop_and_skip_quiet") == 0
    )
    ds.attrs["collapse_verdicts_differ"] = int(
        (ds.collapsed.sel(way="everything") != ds.collapsed.sel(way="stop_and_skip_quiet")).sum()
    )
    for m in ("max_rocking", "max_total_sliding", "residual_total_sliding"):
        diff = abs(ds[m].sel(way="stop_and_skip_quiet") - ds[m].sel(way="everything")).where(
            standing
        )
        ds.attrs[f"max_change_{m}_standing_cases"] = float(diff.max()) if standing.any() else np.nan
    fell = (ds.collapsed.sel(way="everything") == 1) & (
        ds.collapsed.sel(way="stop_and_skip_quiet") == 1
    )
    diff = abs(
        ds.collapse_time.sel(way="stop_and_skip_quiet") - ds.collapse_time.sel(way="everything")
    ).where(fell)
    ds.attrs["max_change_collapse_time_collapsed_cases"] = (
        float(diff.max()) if fell.any() else np.nan
    )
    ds.attrs["n_standing_cases"] = int(standing.sum())
    ds.attrs["n_cases_with_quiet_lead_skipped"] = int((ds.quiet_lead_skipped > 0).sum())
    ds.attrs["n_cases_with_rest_tail_skipped"] = int(np.isfinite(ds.at_rest_from).sum())
    ds.attrs["n_collapsed_cases"] = int(fell.sum())
    return ds


MAX_LIMIT = 100_000
RECORDS = Path("records")  # the cases' records, from the repository root (as the workflow runs)


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.skipping", __doc__)
    parser.add_argument(
        "--config",
        type=options.path_arg,
        default=Path("config/quick.yaml"),
        help="config file, merged over config.yaml of its folder (default config/quick.yaml)",
    )
    parser.add_argument(
        "--studies",
        nargs="*",
        default=list(STUDIES),
        help="studies of the config to run, each once (default: " + " ".join(STUDIES) + ")",
    )
    parser.add_argument(
        "--limit", type=int, default=0, help=f"at most this many cases, 0 to {MAX_LIMIT} (0: all)"
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=Path("results/bench"),
        help="output folder (writes skipping.nc)",
    )
    return parser


def check_args(args):
    """(cases, output path), every case's scene built once (records found), or an InputError
    before anything runs."""
    from benchmarks import options

    limit = options.number(args.limit, "--limit", lo=0, hi=MAX_LIMIT, whole=True, example="4")
    path = options.output_folder(args.out, "--out", files=("skipping.nc",)) / "skipping.nc"
    config, known = options.study_config(args.config, RECORDS)
    studies = options.chosen(args.studies, "--studies", known)
    cases = [case for group in config_cases(config, studies).values() for case in group]
    if limit:
        cases = cases[:limit]
    if not cases:
        raise InputError(
            "--studies", "no cases in the studies chosen", "give studies that have cases"
        )
    options.check_case_scenes(cases, RECORDS)
    return cases, path


def main(argv=None) -> int:
    """Options, config, cases and output path checked first (one line, exit 2); then the runs."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import write_dataset

        cases, path = check_args(args)
        start = time.perf_counter()
        results = []
        for i, case in enumerate(cases):
            results.append(run_ways(case, base_dir=RECORDS))
            walls = "  ".join(f"{w} {results[-1][w][0]:6.2f} s" for w in WAYS)
            print(
                f"  [{i + 1}/{len(cases)}] {case.study}/{case.id}: {walls}",
                file=sys.stderr,
                flush=True,
            )
        ds = skipping_dataset(cases, results)
        write_dataset(ds, path)
        for key, value in ds.attrs.items():
            if key.startswith(("total_", "max_change", "collapse_verdicts", "n_")):
                print(f"{key}: {value:.4g}")
        print(f"wrote {path} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
