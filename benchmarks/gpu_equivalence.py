"""Is the GPU's full-record agreement within the CPU's own rounding noise? (issue 44, item 7)

The H100 run of ``benchmarks.gpu_check`` (benchmarks/device/h100-2026-11-27/gpu_check.nc)
compared the GPU's and its host CPU's collapse verdicts on 160 members (``ida_column_1_drum``,
FEMA far-field FF01a ... FF10b x PGA 1 ... 15 m/s2) and found 3 that differ (98.1 %). This
runs the same cases on this machine's CPU as K members, k_n x (1 - j 2^-52), j = 0..K-1
(:func:`stonedem.study.members.member_scene`), and judges the GPU as layer C judges a
candidate (ENSEMBLES.md sections 2.2 and 4; :mod:`stonedem.study.permutation`):

- pairwise CPU-vs-CPU verdict flips (mean, range): what a last-bit change alone does;
- the split cases (0 < collapse fraction < 1) and which GPU disagreements fall on them;
- S_v of the GPU as a one-member candidate against the K CPU members, with its permutation
  p-value over all K + 1 label assignments (a leave-one-out conformal p-value). With one GPU
  draw the smallest attainable p is 1 / (K + 1), so this cannot reach alpha = 0.005: the real
  test needs 8 GPU members on a device. The H100 host's CPU draw, judged the same way, is
  the control;
- the short-horizon GPU gaps of gpu_check beside this code's last-bit floors
  (:func:`stonedem.study.exact_checks.layer_b`).

Writes the CPU verdicts (case x member) with the H100's beside them, and the statistics, to
``--out`` (atomically); ``--reuse`` re-reads such a file instead of running the members.

    python -m benchmarks.gpu_equivalence [--members 8] [--jobs 2] [--records 20]
        [--gpu-check benchmarks/device/h100-2026-11-27/gpu_check.nc] [--reuse FILE]
        [--out results/bench/gpu_equivalence.nc]

The full run (160 cases x 8 members) takes about 8 min on 2 cores.
"""

from __future__ import annotations

import itertools
import os
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np
import xarray as xr

from benchmarks import options
from stonedem.errors import InputError

GPU_CHECK = Path("benchmarks/device/h100-2026-11-27/gpu_check.nc")
OUT = Path("results/bench/gpu_equivalence.nc")
ALPHA = 0.005  # layer C's per-statistic level (ENSEMBLES.md section 4)
MAX_MEMBERS = 64
MAX_JOBS = 256
# the candidates judged against the CPU members: the dataset's name, gpu_check.nc's variable
CANDIDATES = {"gpu_h100": "gpu_collapsed", "cpu_h100_host": "cpu_collapsed"}
CANDIDATE_NAMES = {"gpu_h100": "the H100 GPU", "cpu_h100_host": "the H100 host's CPU (control)"}
SHORT_KINDS = ("lone_block", "column_1_area_law")  # the short-horizon scenes gpu_check missed


def pair_flips(collapsed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(pairs (P, 2) of member columns a < b, verdicts that differ between them (P,)) of a
    (case, member) 0/1 array."""
    k = collapsed.shape[1]
    pairs = np.array(list(itertools.combinations(range(k), 2)), dtype=np.int64).reshape(-1, 2)
    flips = np.array(
        [int((collapsed[:, a] != collapsed[:, b]).sum()) for a, b in pairs], dtype=np.int64
    )
    return pairs, flips


def judge(cpu: np.ndarray, candidate: np.ndarray) -> dict:
    """One candidate draw (case,) against the CPU members (case, K): its flips against each
    member, the cases every member agrees on that it flips, and layer C's S_v with its
    permutation p over all K + 1 assignments
    (:func:`stonedem.study.permutation.permutation_test`)."""
    from stonedem.study.permutation import permutation_test

    k = cpu.shape[1]
    flips = (cpu != candidate[:, None]).sum(axis=0)
    test = permutation_test(
        cpu, np.zeros((0, k)), candidate[:, None], np.zeros((0, 1)), 0.02, alpha=ALPHA
    )
    return {
        "flips_mean": float(flips.mean()),
        "flips_min": int(flips.min()),
        "flips_max": int(flips.max()),
        "flips_member_0": int(flips[0]),
        "unanimous_flips": test["unanimous_flips"],
        "s_v": test["s_v"],
        "p_v": test["p_v"],
        "n_assignments": test["n_assignments"],
        "exact": test["exact"],
    }


def cpu_members(cases, k: int, jobs: int, log=sys.stderr) -> tuple[np.ndarray, np.ndarray]:
    """(collapsed (case, member) int8, peak rotation (case, member) [rad]) of every case run
    by members j = 0..k-1 over ``jobs`` processes (:func:`stonedem.study.ensemble.run_members`:
    :func:`stonedem.study.runner.case_scene`, :func:`~stonedem.study.members.member_scene`,
    :func:`stonedem.engine.run.run_scene`), one progress line per run on ``log``."""
    from stonedem.study.ensemble import run_members

    results = run_members(cases, [], range(k), jobs, log=log, stripes=False)
    collapsed = np.array([[v["collapsed"] for v in row] for row in results.verdicts], dtype=np.int8)
    rocking = np.array([[v["max_rocking"] for v in row] for row in results.verdicts], dtype=float)
    return collapsed, rocking


def device_verdicts(path: Path, case_ids: list[str]) -> tuple[dict, dict]:
    """({candidate: verdicts (case,)} in the order of ``case_ids``, gpu_check.nc's attrs and
    short-horizon gaps); one line naming --gpu-check when a case or variable is missing."""
    ds = options.read_netcdf(
        path, "--gpu-check", "gpu_check.nc", "give the gpu_check.nc of a device run"
    )
    missing = [
        v
        for v in (*CANDIDATES.values(), "position_difference", "rotation_difference")
        if v not in ds
    ]
    if missing or "case" not in ds.dims:
        raise InputError(
            "--gpu-check",
            f"{path} has no {', '.join(missing) or 'case dimension'}",
            "give the gpu_check.nc of a device run",
        )
    known = [str(c) for c in ds.case.values]
    absent = [c for c in case_ids if c not in known]
    if absent:
        raise InputError(
            "--gpu-check",
            f"{path} has no case {absent[0]} ({len(absent)} of {len(case_ids)} absent)",
            "give --records and a config matching the device run's",
        )
    sel = ds.sel(case=case_ids)
    verdicts = {name: sel[var].values.astype(np.int8) for name, var in CANDIDATES.items()}
    device = {
        "attrs": dict(ds.attrs),
        "kind": [str(k) for k in ds.kind.values],
        "position_difference": ds.position_difference.values,
        "rotation_difference": ds.rotation_difference.values,
    }
    return verdicts, device


def short_horizon_floors() -> xr.Dataset:
    """Layer B's last-bit floors of the scenes the GPU missed
    (:func:`stonedem.study.exact_checks.layer_b`, 0.5 s, k_n and geometry j = 1..3)."""
    from stonedem.study.exact_checks import layer_b

    b = layer_b(kinds=SHORT_KINDS)
    floors = xr.Dataset(
        {"floor_position": b.floor_position, "floor_rotation": b.floor_rotation},
        coords={"scene": [str(s) for s in b.scene.values]},
    )
    if (
        "family_position" in b
    ):  # which last-bit family sets each floor (a contact tie's length, ...)
        family = [
            str(b.family.values[np.nanargmax(row)]) if np.any(np.isfinite(row)) else "none"
            for row in b.family_position.values
        ]
        floors["floor_family"] = ("scene", family)
    return floors


def _var(dims, values, units, long_name):
    return (
        dims,
        values,
        ({"long_name": long_name} if units is None else {"units": units, "long_name": long_name}),
    )


def equivalence_dataset(cases, cpu, rocking, verdicts, device, floors, attrs) -> xr.Dataset:
    """The verdicts, the statistics of :func:`judge` and the short-horizon gaps in floors."""
    k = cpu.shape[1]
    member = np.arange(k)
    count = cpu.sum(axis=1)
    split = (count > 0) & (count < k)
    gpu, host = verdicts["gpu_h100"], verdicts["cpu_h100_host"]
    pairs, flips = pair_flips(cpu)
    judged = {name: judge(cpu, verdicts[name]) for name in CANDIDATES}
    names = list(CANDIDATES)

    def per(key, dtype=float):
        return np.array([judged[n][key] for n in names], dtype=dtype)

    unanimous_flip = np.zeros((len(cases), len(names)), dtype=np.int8)
    for c, name in enumerate(names):
        unanimous_flip[judged[name]["unanimous_flips"], c] = 1
    kind_of = {kind: i for i, kind in enumerate(device["kind"])}
    scenes = [str(s) for s in floors.scene.values]
    gap_position = np.array(
        [device["position_difference"][kind_of[s.split("/")[0]]] for s in scenes]
    )
    gap_rotation = np.array(
        [device["rotation_difference"][kind_of[s.split("/")[0]]] for s in scenes]
    )
    differ = gpu != host
    data = {
        "cpu_collapsed": _var(
            ("case", "member"), cpu, "1", "collapse verdict of the CPU member here (1: collapsed)"
        ),
        "cpu_max_rocking": _var(
            ("case", "member"), rocking, "rad", "peak mean rotation of the CPU member here"
        ),
        "gpu_collapsed": _var("case", gpu, "1", "collapse verdict on the H100 GPU (gpu_check.nc)"),
        "h100_cpu_collapsed": _var(
            "case", host, "1", "collapse verdict on the H100 host's CPU, member 0 (gpu_check.nc)"
        ),
        "collapse_count": _var(
            "case", count.astype(np.int32), "1", "CPU members here that collapsed"
        ),
        "collapse_fraction": _var(
            "case", count / k, "1", "share of the CPU members here that collapsed"
        ),
        "split": _var(
            "case",
            split.astype(np.int8),
            "1",
            "1: the CPU members here disagree (0 < collapse fraction < 1)",
        ),
        "gpu_differs_from_host": _var(
            "case", differ.astype(np.int8), "1", "1: the GPU's verdict differs from its host CPU's"
        ),
        "unanimous_flip": _var(
            ("case", "candidate"),
            unanimous_flip,
            "1",
            "1: every CPU member here agrees and the candidate does not",
        ),
        "pair_flips": _var("pair", flips, "1", "verdicts that differ between two CPU members here"),
        "flips_mean": _var(
            "candidate",
            per("flips_mean"),
            "1",
            "verdicts that differ from a CPU member here, mean over the members",
        ),
        "flips_min": _var(
            "candidate",
            per("flips_min", np.int32),
            "1",
            "verdicts that differ from a CPU member here, fewest",
        ),
        "flips_max": _var(
            "candidate",
            per("flips_max", np.int32),
            "1",
            "verdicts that differ from a CPU member here, most",
        ),
        "flips_member_0": _var(
            "candidate",
            per("flips_member_0", np.int32),
            "1",
            "verdicts that differ from CPU member 0 here (the same scenes)",
        ),
        "unanimous_flips": _var(
            "candidate",
            unanimous_flip.sum(axis=0).astype(np.int32),
            "1",
            "flips of cases every CPU member here agrees on",
        ),
        "s_v": _var(
            "candidate",
            per("s_v"),
            "1",
            "layer C verdict distance S_v, candidate (1 draw) vs the CPU members",
        ),
        "p_v": _var(
            "candidate", per("p_v"), "1", "permutation p of S_v over all K + 1 label assignments"
        ),
        "p_v_smallest": _var(
            "candidate",
            np.full(len(names), 1.0 / (k + 1)),
            "1",
            "smallest attainable p with one candidate draw, 1 / (K + 1)",
        ),
        "floor_position": _var(
            "scene",
            floors.floor_position.values,
            "m",
            "last-bit floor of positions over 0.5 s (layer B, this code on this CPU)",
        ),
        "floor_rotation": _var(
            "scene",
            floors.floor_rotation.values,
            "rad",
            "last-bit floor of rotations over 0.5 s (layer B, this code on this CPU)",
        ),
        **(
            {
                "floor_family": _var(
                    "scene",
                    [str(f) for f in floors.floor_family.values],
                    None,
                    "last-bit family whose divergence sets floor_position (layer B)",
                )
            }
            if "floor_family" in floors
            else {}
        ),
        "gpu_position_gap": _var(
            "scene",
            gap_position,
            "m",
            "|GPU - CPU| of a position over 0.5 s, the kind's largest over its PGAs (gpu_check.nc)",
        ),
        "gpu_rotation_gap": _var(
            "scene",
            gap_rotation,
            "rad",
            "|GPU - CPU| of a rotation over 0.5 s, the kind's largest over its PGAs (gpu_check.nc)",
        ),
        "position_gap_in_floors": _var(
            "scene",
            gap_position / floors.floor_position.values,
            "1",
            "gpu_position_gap / floor_position",
        ),
        "rotation_gap_in_floors": _var(
            "scene",
            gap_rotation / floors.floor_rotation.values,
            "1",
            "gpu_rotation_gap / floor_rotation",
        ),
    }
    coords = {
        "case": _var("case", [c["id"] for c in cases], None, "full-record case (record and PGA)"),
        "record": _var(
            "case", [c["record"] for c in cases], None, "FEMA far-field record component"
        ),
        "pga": _var(
            "case",
            np.array([c["pga"] for c in cases], dtype=float),
            "m s-2",
            "peak ground acceleration of the scaled record",
        ),
        "member": _var(
            "member", member, "1", "j: contact stiffness k_n times 1 - j 2^-52 (0: as configured)"
        ),
        "stiffness_factor": _var(
            "member", 1.0 - member * 2.0**-52, "1", "factor on the contact stiffness k_n"
        ),
        "member_a": _var("pair", pairs[:, 0], "1", "first CPU member of the pair"),
        "member_b": _var("pair", pairs[:, 1], "1", "second CPU member of the pair"),
        "candidate": _var(
            "candidate",
            names,
            None,
            "verdicts judged against the CPU members: "
            + "; ".join(f"{n}: {CANDIDATE_NAMES[n]}" for n in names),
        ),
        "scene": _var("scene", scenes, None, "short-horizon scene (kind/PGA)"),
    }
    gpu_judged = judged["gpu_h100"]
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": "GPU full-record verdicts against the CPU's own last-bit ensemble (issue "
            "44, item 7)",
            **attrs,
            "n_members": int(k),
            "n_cases": int(len(cases)),
            "cpu_pair_flips_mean": float(flips.mean()) if flips.size else 0.0,
            "cpu_pair_flips_min": int(flips.min()) if flips.size else 0,
            "cpu_pair_flips_max": int(flips.max()) if flips.size else 0,
            "split_cases": int(split.sum()),
            "gpu_host_disagreements": int(differ.sum()),
            "gpu_host_disagreements_on_split": int((differ & split).sum()),
            "gpu_p_v": float(gpu_judged["p_v"]),
            "smallest_p_one_draw": 1.0 / (k + 1),
            "alpha": ALPHA,
            "permutation_exact": int(gpu_judged["exact"]),
            "gpu_unanimous_flips": int(unanimous_flip[:, 0].sum()),
        },
    )
    return ds


def summary_lines(ds: xr.Dataset) -> list[str]:
    """What the comparison found, in a few lines."""
    k, n = ds.attrs["n_members"], ds.attrs["n_cases"]
    lines = [
        f"CPU vs CPU ({k} members, {ds.sizes['pair']} pairs): "
        f"{ds.attrs['cpu_pair_flips_mean']:.2f} of {n} "
        f"verdicts differ on average, {ds.attrs['cpu_pair_flips_min']} ... "
        f"{ds.attrs['cpu_pair_flips_max']}"
    ]
    split = ds.split.values == 1
    shown = ", ".join(
        f"{c} {int(m)}/{k}" for c, m in zip(ds.case.values[split], ds.collapse_count.values[split])
    )
    lines.append(f"split cases (0 < p < 1): {int(split.sum())}" + (f": {shown}" if shown else ""))
    differ = ds.gpu_differs_from_host.values == 1
    marked = ", ".join(
        f"{c} ({'split' if s else 'NOT split'})"
        for c, s in zip(ds.case.values[differ], split[differ])
    )
    lines.append(
        f"GPU vs its host CPU: {int(differ.sum())} of {n} differ, "
        f"{ds.attrs['gpu_host_disagreements_on_split']} on split cases"
        + (f": {marked}" if marked else "")
    )
    for c, name in enumerate(ds.candidate.values):
        flipped = ds.case.values[ds.unanimous_flip.values[:, c] == 1]
        lines.append(
            f"{CANDIDATE_NAMES[str(name)]} vs the {k} CPU members: "
            f"{float(ds.flips_mean[c]):.2f} flips per member "
            f"({int(ds.flips_min[c])} ... {int(ds.flips_max[c])}, {int(ds.flips_member_0[c])} "
            "vs member 0); "
            f"S_v {float(ds.s_v[c]):.3g}, p {float(ds.p_v[c]):.3g} over all {k + 1} assignments; "
            f"unanimous cases flipped: {', '.join(flipped) if flipped.size else 'none'}"
        )
    lines.append(
        f"one candidate draw: the smallest attainable p is 1/(K+1) = {1.0 / (k + 1):.3g} "
        f"> alpha = {ALPHA:g}, so this cannot reject; the real test needs 8 GPU members run on "
        "a device"
    )
    for s, scene in enumerate(ds.scene.values):
        family = f" ({ds.floor_family.values[s]})" if "floor_family" in ds else ""
        lines.append(
            f"short horizon {scene}: GPU gap {float(ds.gpu_position_gap[s]):.3g} m = "
            f"{float(ds.position_gap_in_floors[s]):.3g} floors of "
            f"{float(ds.floor_position[s]):.3g} m{family}, "
            f"{float(ds.gpu_rotation_gap[s]):.3g} rad = "
            f"{float(ds.rotation_gap_in_floors[s]):.3g} floors "
            f"(open until a device re-runs gpu_check without FMA contraction)"
        )
    return lines


def reused(path: Path) -> tuple[list[dict], np.ndarray, np.ndarray, xr.Dataset, dict]:
    """(cases, CPU verdicts, peak rotations, floors, attrs) of an earlier output; its case
    list replaces the config's."""
    ds = options.read_netcdf(
        path, "--reuse", "NetCDF file", "give an earlier output of this script"
    )
    need = ("cpu_collapsed", "cpu_max_rocking", "floor_position", "floor_rotation", "record", "pga")
    missing = [v for v in need if v not in ds.variables]
    if missing:
        raise InputError(
            "--reuse",
            f"{path} has no {', '.join(missing)}",
            "give an earlier output of this script",
        )
    cases = [
        {"id": str(c), "record": str(r), "pga": float(p)}
        for c, r, p in zip(ds.case.values, ds.record.values, ds.pga.values)
    ]
    floors = ds[[v for v in ("floor_position", "floor_rotation", "floor_family") if v in ds]]
    keep = {
        key: ds.attrs[key]
        for key in ("source", "machine", "cpu_wall_seconds", "config", "members_run_by", "history")
        if key in ds.attrs
    }
    return cases, ds.cpu_collapsed.values.astype(np.int8), ds.cpu_max_rocking.values, floors, keep


def build_parser():
    parser = options.parser("python -m benchmarks.gpu_equivalence", __doc__)
    parser.add_argument(
        "--members",
        type=int,
        default=8,
        help=f"K, CPU members j = 0..K-1, 2 to {MAX_MEMBERS} (default 8)",
    )
    parser.add_argument(
        "--jobs", type=int, default=2, help=f"worker processes, 1 to {MAX_JOBS} (default 2)"
    )
    parser.add_argument(
        "--records",
        type=int,
        default=20,
        help="records of the IDA's first structure, 1 to 10000 (default 20, as on the H100)",
    )
    parser.add_argument(
        "--config",
        type=options.path_arg,
        default=Path("config/config.yaml"),
        help="the config whose fragility: section gives the structure and records",
    )
    parser.add_argument(
        "--gpu-check",
        type=options.path_arg,
        default=GPU_CHECK,
        help=f"the device run's file (default {GPU_CHECK})",
    )
    parser.add_argument(
        "--reuse",
        type=options.path_arg,
        default=None,
        help="an earlier output: re-read its CPU verdicts instead of running the members",
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=OUT, help=f"output NetCDF file (default {OUT})"
    )
    return parser


def main(argv=None) -> int:
    """Options, inputs and output path checked first (one line, exit 2); then the runs."""
    args = build_parser().parse_args(argv)

    def command():
        from benchmarks.gpu_check import PGAS, RECORDS, full_record_cases
        from stonedem.io.netcdf import code_version, write_dataset
        from stonedem.study.ensemble import machine

        k = options.number(args.members, "--members", lo=2, hi=MAX_MEMBERS, whole=True, example="8")
        jobs = options.number(args.jobs, "--jobs", lo=1, hi=MAX_JOBS, whole=True, example="2")
        n_records = options.number(
            args.records, "--records", lo=1, hi=10_000, whole=True, example="20"
        )
        gpu_check = options.input_file(
            args.gpu_check, "--gpu-check", "gpu_check.nc of a device run"
        )
        path = options.output_file(args.out, "--out", suffixes=(".nc",), inputs=(gpu_check,))
        start = time.perf_counter()
        if args.reuse is not None:
            earlier = options.input_file(args.reuse, "--reuse", "earlier output")
            cases, cpu, rocking, floors, attrs = reused(earlier)
            verdicts, device = device_verdicts(gpu_check, [c["id"] for c in cases])
            print(
                f"re-read {len(cases)} cases x {cpu.shape[1]} CPU members from {earlier}",
                file=sys.stderr,
                flush=True,
            )
        else:
            options.input_file(args.config, "--config", "YAML config file")
            if not RECORDS.is_dir():
                raise InputError(
                    "records", f"no folder {RECORDS} here", "run from the repository root"
                )
            study, found = full_record_cases(n_records, PGAS, args.config)
            cases = [
                {
                    "id": c.id,
                    "record": str(c.params.get("component", "")),
                    "pga": float(c.params["pga"]),
                }
                for c in found
            ]
            verdicts, device = device_verdicts(
                gpu_check, [c["id"] for c in cases]
            )  # before the runs
            options.check_case_scenes(found, RECORDS)
            print(
                f"{len(found)} cases of {study} x {k} CPU members (k_n x (1 - j 2^-52), j = "
                f"0..{k - 1}) "
                f"on {jobs} process(es)",
                file=sys.stderr,
                flush=True,
            )
            cpu, rocking = cpu_members(found, k, jobs)
            floors = short_horizon_floors()
            attrs = {
                "source": code_version(),
                "machine": machine(),
                "cpu_wall_seconds": time.perf_counter() - start,
                "config": str(args.config),
                "members_run_by": "python -m benchmarks.gpu_equivalence",
            }
        host = device["attrs"]
        attrs.update(
            {
                "gpu_check_file": str(args.gpu_check),
                "gpu_device": str(host.get("device", "")),
                "gpu_check_source": str(host.get("source", "")),
                "gpu_check_numba_version": str(host.get("numba_version", "")),
                "perturbation": "contact stiffness k_n times 1 - j 2^-52, j = 0..K-1",
                "report_source": code_version(),
            }
        )
        ds = equivalence_dataset(cases, cpu, rocking, verdicts, device, floors, attrs)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_dataset(ds, path)
        for line in summary_lines(ds):
            print(line)
        print(f"wrote {path} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
