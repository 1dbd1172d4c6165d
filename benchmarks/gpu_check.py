"""The GPU checks of issue 33 in one run, for a session lent a GPU (or, tiny, under Numba's
CUDA simulator).

1. Short horizon: members of each scene kind (lone block, 8-drum column under a record,
   colonnade under a harmonic, the area law) run on the GPU and by
   :func:`stonedem.engine.simulate.simulate`; their positions and rotations must agree to
   SHORT_TOLERANCE.
2. Full records: the IDA's first structure under its records at a grid of PGAs, every case
   run on the GPU and on the CPU ensemble; the collapse verdicts must agree on at least
   VERDICT_TARGET of the members (rocking under impacts is chaotic: runs that agree to
   rounding for a second part ways over a record, so members are compared by verdict).

Writes results/bench/gpu_check.nc; prints one line per check and exits 1 when one fails.

    python -m benchmarks.gpu_check [--quick] [--records N] [--out results/bench]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.study.reference_scenes import short_horizon_members  # noqa: F401 - the scenes checked

SHORT_TOLERANCE = 1e-9  # [m], [rad] over SHORT_DURATION (issue 33)
SHORT_DURATION = 0.5  # [s]
VERDICT_TARGET = 0.99  # share of members with the same verdict on the GPU and the CPU
PGAS = (1.0, 2.0, 3.0, 4.5, 6.0, 8.0, 11.0, 15.0)  # [m s-2] the full-record grid
QUICK_PGAS = (3.0, 12.0)
RECORDS = Path("records")


def short_horizon(duration: float) -> dict[str, tuple[float, float, int]]:
    """{kind: (max position difference [m], max rotation difference [rad], members)}."""
    from stonedem.engine.ensemble import run_ensemble
    from stonedem.engine.simulate import simulate

    out = {}
    for kind, scenes in short_horizon_members(duration).items():
        gpu = run_ensemble(scenes, device="gpu")
        position = rotation = 0.0
        for scene, g in zip(scenes, gpu):
            c = simulate(scene)
            if c.x.shape != g.x.shape:  # a member stopped at another sample: no agreement
                position = rotation = np.inf
                continue
            position = max(
                position, float(np.max(np.abs(c.x - g.x))), float(np.max(np.abs(c.y - g.y)))
            )
            rotation = max(rotation, float(np.max(np.abs(c.theta - g.theta))))
        out[kind] = (position, rotation, len(scenes))
    return out


def full_record_cases(n_records: int | None, pgas, config_path: Path):
    """The IDA's first structure: its searches' cases at each PGA of ``pgas``."""
    from stonedem.fragility.ida import check_fragility
    from stonedem.study.grid import load_config, search_case

    config = load_config(config_path)
    studies = check_fragility(config, RECORDS)
    study = next(iter(studies))
    systems = list(studies[study])[:n_records] if n_records else list(studies[study])
    return study, [search_case(system, pga) for system in systems for pga in pgas]


def full_records(cases) -> dict:
    """Verdicts and peak rotations of every case on the GPU and on the CPU ensemble."""
    from stonedem.study.runner import run_cases_together

    out = {}
    for device in ("gpu", "cpu"):
        start = time.perf_counter()
        datasets = run_cases_together(cases, RECORDS, device=device)
        out[f"{device}_wall"] = time.perf_counter() - start
        out[f"{device}_collapsed"] = np.array([float(ds["collapsed"]) > 0 for ds in datasets])
        out[f"{device}_rocking"] = np.array(
            [float(ds["max_rocking"]) if "max_rocking" in ds else np.nan for ds in datasets]
        )
    return out


def check_dataset(
    short: dict, study: str, cases, full: dict, device: str, quick: bool
) -> xr.Dataset:
    from stonedem.io.netcdf import code_version
    from stonedem.study.runner import library_versions

    kinds = list(short)
    agree = full["gpu_collapsed"] == full["cpu_collapsed"]
    share = float(agree.mean()) if agree.size else np.nan
    ratio = full["gpu_rocking"] / full["cpu_rocking"]
    short_ok = all(max(p, r) <= SHORT_TOLERANCE for p, r, _ in short.values())
    return xr.Dataset(
        {
            "position_difference": (
                "kind",
                [short[k][0] for k in kinds],
                {
                    "units": "m",
                    "long_name": "largest |GPU - CPU| of a centroid coordinate over the short "
                    "horizon",
                },
            ),
            "rotation_difference": (
                "kind",
                [short[k][1] for k in kinds],
                {
                    "units": "rad",
                    "long_name": "largest |GPU - CPU| of a rotation over the short horizon",
                },
            ),
            "short_members": (
                "kind",
                np.array([short[k][2] for k in kinds], dtype=np.int64),
                {"units": "1", "long_name": "members run"},
            ),
            "gpu_collapsed": (
                "case",
                full["gpu_collapsed"].astype(np.int8),
                {"units": "1", "long_name": "collapsed on the GPU (1) or not (0)"},
            ),
            "cpu_collapsed": (
                "case",
                full["cpu_collapsed"].astype(np.int8),
                {"units": "1", "long_name": "collapsed on the CPU (1) or not (0)"},
            ),
            "rocking_ratio": (
                "case",
                ratio,
                {"units": "1", "long_name": "peak mean rotation, GPU over CPU"},
            ),
            "verdict_agreement": (
                (),
                share,
                {
                    "units": "1",
                    "long_name": "share of full-record members with the same collapse verdict",
                },
            ),
            "gpu_wall": (
                (),
                full["gpu_wall"],
                {
                    "units": "s",
                    "long_name": "wall time of the full-record members on the GPU, compile "
                    "included",
                },
            ),
            "cpu_wall": (
                (),
                full["cpu_wall"],
                {
                    "units": "s",
                    "long_name": "wall time of the full-record members on the CPU ensemble",
                },
            ),
        },
        coords={
            "kind": ("kind", kinds, {"long_name": "scene kind of the short-horizon members"}),
            "case": (
                "case",
                [c.id for c in cases],
                {"long_name": "full-record case (record and PGA)"},
            ),
        },
        attrs={
            "title": "stonedem GPU checks (issue 33)",
            "device": device,
            "study": study,
            "short_tolerance": SHORT_TOLERANCE,
            "short_duration_s": SHORT_DURATION,
            "verdict_target": VERDICT_TARGET,
            "short_horizon_met": int(short_ok),
            "verdicts_met": int(share >= VERDICT_TARGET),
            "profile": "quick" if quick else "full",
            "source": code_version(),
            **library_versions(),
        },
    )


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.gpu_check", __doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="2 records x 2 PGAs, 0.1 s short horizon (simulator tests)",
    )
    parser.add_argument(
        "--records", type=int, default=0, help="records of the structure to run, 0 for all"
    )
    parser.add_argument(
        "--config",
        type=options.path_arg,
        default=Path("config/config.yaml"),
        help="the config whose fragility: section gives the structure and records",
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=Path("results/bench"), help="folder of gpu_check.nc"
    )
    return parser


def main(argv=None) -> int:
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.errors import InputError
        from stonedem.io.netcdf import write_dataset
        from stonedem.kernels.gpu import gpu_available

        n_records = options.number(
            args.records, "--records", lo=0, hi=10_000, whole=True, example="100"
        )
        options.input_file(args.config, "--config", "YAML config file")
        path = options.output_folder(args.out, "--out", files=("gpu_check.nc",)) / "gpu_check.nc"
        if not RECORDS.is_dir():
            raise InputError("records", f"no folder {RECORDS} here", "run from the repository root")
        usable, device = gpu_available()
        if not usable:
            raise InputError(
                "device",
                device,
                "run this on a machine with an NVIDIA GPU and pip install -e '.[gpu]'",
            )
        print(f"device: {device}", flush=True)
        quick = args.quick
        start = time.perf_counter()
        short = short_horizon(0.1 if quick else SHORT_DURATION)
        for kind, (p, r, n) in short.items():
            print(
                f"short horizon {kind}: {n} members, |dx| <= {p:.3g} m, |dtheta| <= {r:.3g} rad "
                f"({'ok' if max(p, r) <= SHORT_TOLERANCE else 'MISSED'}, tolerance "
                f"{SHORT_TOLERANCE:g})",
                flush=True,
            )
        study, cases = full_record_cases(
            2 if quick and not n_records else n_records or None,
            QUICK_PGAS if quick else PGAS,
            args.config,
        )
        full = full_records(cases)
        ds = check_dataset(short, study, cases, full, device, quick)
        write_dataset(ds, path)
        share = float(ds["verdict_agreement"])
        print(
            f"full records ({study}, {len(cases)} members): same verdict on {share:.1%} "
            f"({'ok' if share >= VERDICT_TARGET else 'MISSED'}, target {VERDICT_TARGET:.0%}); "
            f"GPU {full['gpu_wall']:.1f} s, CPU ensemble {full['cpu_wall']:.1f} s",
            flush=True,
        )
        print(f"wrote {path} in {time.perf_counter() - start:.0f} s")
        return 0 if ds.attrs["short_horizon_met"] and ds.attrs["verdicts_met"] else 1

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
