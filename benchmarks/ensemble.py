"""Throughput of the ensemble engine: member-steps per second against the number of members
(issue 33), on one CPU thread, on every CPU thread and on the GPU where one can run the loop.

Members are one structure of :data:`benchmarks.kernel.SCENES` under its record, each at
its own PGA (spread over PGA_SPAN, as an IDA's runs are), run by
:func:`stonedem.engine.ensemble.run_ensemble`. Each point is the best of ``--repeats`` calls
after one call that compiles; a member-step is one time step of one member. Writes
results/bench/ensemble.nc and results/figures/ensemble_throughput.png.

    python -m benchmarks.ensemble [--quick] [--scene column_8] [--members 1 2 4 ...] [--out
    results/bench]
"""

from __future__ import annotations

import contextlib
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

MEMBERS = (1, 2, 4, 8, 16, 32)
QUICK_MEMBERS = (1, 2, 4)
GPU_MEMBERS = (64, 256, 1024, 4096)  # added on a GPU: it needs thousands of threads to fill
PGA_SPAN = (2.0, 12.0)  # [m s-2] the members' PGAs, evenly spread
DURATION = 4.0  # [s] simulated per member
QUICK_DURATION = 0.5
MAX_MEMBERS = 100_000


def member_scenes(scene: str, n: int, duration: float) -> list:
    """n members of one structure at PGAs spread over PGA_SPAN."""
    from benchmarks.kernel import SCENES
    from stonedem.engine.scene import scene_from_dict

    out = []
    for pga in np.linspace(*PGA_SPAN, n) if n > 1 else [PGA_SPAN[0]]:
        spec = SCENES[scene][1](duration)
        if "pga" in spec.get("excitation", {}):
            spec["excitation"]["pga"] = float(pga)
        out.append(scene_from_dict(spec))
    return out


def time_ensemble(
    scene: str, n: int, duration: float, device: str, threads: int | None, repeats: int
):
    """(best wall seconds of a run_ensemble call, member-steps it integrated)."""
    from stonedem.engine.ensemble import run_ensemble

    best, steps = np.inf, 0
    for _ in range(repeats):
        scenes = member_scenes(scene, n, duration)  # fresh: a run consumes its plan
        start = time.perf_counter()
        results = run_ensemble(scenes, threads=threads, device=device)
        best = min(best, time.perf_counter() - start)
        steps = sum(r.steps_run for r in results)
    return best, steps


def backends() -> tuple[dict[str, tuple[str, int | None, str]], str]:
    """({name: (device, threads, what it is)} of the backends this machine has, why no GPU is
    among them or "")."""
    import numba

    from stonedem.kernels.gpu import gpu_available

    n = numba.config.NUMBA_NUM_THREADS
    out = {
        "cpu_1_thread": ("cpu", 1, f"{platform.processor() or platform.machine()}, 1 thread"),
        "cpu_all_threads": ("cpu", n, f"{platform.processor() or platform.machine()}, {n} threads"),
    }
    usable, why = gpu_available()
    if usable and not numba.config.ENABLE_CUDASIM:  # the simulator's timings mean nothing
        out["gpu"] = ("gpu", None, why)
        return out, ""
    return out, why if not usable else "the CUDA simulator is on"


@contextlib.contextmanager
def gpu_layout(threads_per_block: int, member_fastest: bool):
    """The GPU ensemble's launch width and stacking layout (stonedem.kernels.gpu) for the
    timings, and back as they were after them (main may run inside another program)."""
    from stonedem.kernels import gpu

    saved = gpu.THREADS_PER_BLOCK, gpu.MEMBER_FASTEST
    gpu.THREADS_PER_BLOCK, gpu.MEMBER_FASTEST = threads_per_block, member_fastest
    try:
        yield
    finally:
        gpu.THREADS_PER_BLOCK, gpu.MEMBER_FASTEST = saved


def ensemble_dataset(
    table: dict, members: list[int], described: dict, scene: str, duration: float, quick: bool
) -> xr.Dataset:
    from stonedem.io.netcdf import code_version
    from stonedem.study.runner import library_versions

    names = list(described)
    wall = np.full((len(names), len(members)), np.nan)
    steps = np.full((len(names), len(members)), np.nan)
    for i, name in enumerate(names):
        for j, n in enumerate(members):
            if (name, n) in table:
                wall[i, j], steps[i, j] = table[name, n]
    ds = xr.Dataset(
        {
            "wall": (
                ("backend", "members"),
                wall,
                {
                    "units": "s",
                    "long_name": "wall time of one run_ensemble call, best of the repeats",
                },
            ),
            "member_steps": (
                ("backend", "members"),
                steps,
                {"units": "1", "long_name": "time steps integrated, summed over the members"},
            ),
            "throughput": (
                ("backend", "members"),
                steps / wall,
                {"units": "s-1", "long_name": "member-steps per second"},
            ),
            "ns_per_member_step": (
                ("backend", "members"),
                1e9 * wall / steps,
                {"units": "ns", "long_name": "wall time per member-step"},
            ),
        },
        coords={
            "backend": ("backend", names, {"long_name": "where the members ran"}),
            "members": (
                "members",
                np.array(members, dtype=np.int64),
                {"units": "1", "long_name": "members run in one call"},
            ),
            "description": (
                "backend",
                [described[name] for name in names],
                {"long_name": "the device, in words"},
            ),
        },
        attrs={
            "title": "stonedem ensemble throughput (issue 33)",
            "scene": scene,
            "duration_s": duration,
            "pga_span_m_s2": f"{PGA_SPAN[0]:g} ... {PGA_SPAN[1]:g}",
            "profile": "quick" if quick else "full",
            "machine": f"{os.cpu_count()} cores, {platform.platform()}",
            "source": code_version(),
            **library_versions(),
        },
    )
    return ds


def figure(ds: xr.Dataset, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from benchmarks.options import save_figure

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for name in ds["backend"].values:
        values = ds["throughput"].sel(backend=name)
        ok = np.isfinite(values.values)
        ax.plot(
            ds["members"].values[ok],
            values.values[ok],
            "o-",
            label=str(ds["description"].sel(backend=name).values),
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("members run in one call")
    ax.set_ylabel("member-steps per second")
    ax.set_title(f"Ensemble throughput: {ds.attrs['scene']}, {ds.attrs['duration_s']:g} s each")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.ensemble", __doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help=f"members {' '.join(map(str, QUICK_MEMBERS))}, {QUICK_DURATION:g} s each (CI)",
    )
    parser.add_argument(
        "--scene",
        default="column_8",
        help="a scene of benchmarks.kernel.SCENES (default column_8)",
    )
    parser.add_argument(
        "--members",
        type=int,
        nargs="+",
        default=None,
        help=f"member counts (default {' '.join(map(str, MEMBERS))}; on a GPU also "
        f"{' '.join(map(str, GPU_MEMBERS))})",
    )
    parser.add_argument("--repeats", type=int, default=2, help="timed calls per point; best kept")
    parser.add_argument(
        "--backend",
        nargs="+",
        default=None,
        help="backends to time: cpu_1_thread, cpu_all_threads, gpu (default: all this machine has)",
    )
    parser.add_argument(
        "--threads-per-block",
        type=int,
        default=None,
        help="GPU threads (members) per block (default: stonedem.kernels.gpu.THREADS_PER_BLOCK)",
    )
    parser.add_argument(
        "--member-fastest",
        action="store_true",
        help="on the GPU, lay the stacked arrays out member index fastest (coalesced loads)",
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=Path("results/bench"), help="folder of ensemble.nc"
    )
    parser.add_argument(
        "--figure",
        type=options.path_arg,
        default=None,
        help="the figure (default: <out>/../figures/ensemble_throughput.png)",
    )
    return parser


def main(argv=None) -> int:
    """Options and output paths checked first (one line, exit 2); then the timings."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        from benchmarks.kernel import SCENES
        from stonedem.errors import InputError
        from stonedem.io.netcdf import write_dataset

        scene = options.chosen([args.scene], "--scene", SCENES)[0]
        repeats = options.number(args.repeats, "--repeats", lo=1, hi=20, whole=True, example="2")
        members = args.members or list(QUICK_MEMBERS if args.quick else MEMBERS)
        members = sorted(
            {
                options.number(n, "--members", lo=1, hi=MAX_MEMBERS, whole=True, example="8")
                for n in members
            }
        )
        path = options.output_folder(args.out, "--out", files=("ensemble.nc",)) / "ensemble.nc"
        figure_path = options.output_file(
            args.figure or args.out.parent / "figures" / "ensemble_throughput.png",
            "--figure",
            suffixes=(".png",),
        )
        duration = QUICK_DURATION if args.quick else DURATION
        available, no_gpu = backends()
        if args.backend and "gpu" in args.backend and no_gpu:
            raise InputError(
                "--backend", f"gpu: none to time here ({no_gpu})", "leave gpu out, or run on a GPU"
            )
        chosen = options.chosen(args.backend or list(available), "--backend", available)
        from stonedem.kernels import gpu

        block = (
            gpu.THREADS_PER_BLOCK
            if args.threads_per_block is None
            else options.number(
                args.threads_per_block,
                "--threads-per-block",
                lo=1,
                hi=1024,
                whole=True,
                example="64",
            )
        )
        fastest = gpu.MEMBER_FASTEST or args.member_fastest
        if no_gpu and not args.backend:
            print(f"note: no GPU timed ({no_gpu})", file=sys.stderr)
        start = time.perf_counter()
        table, described = {}, {}
        with gpu_layout(block, fastest):
            for name in chosen:
                device, threads, what = available[name]
                if device == "gpu":
                    what = f"{what}, {block} members per block" + (
                        ", member index fastest" if fastest else ""
                    )
                described[name] = what
                counts = members + (
                    [n for n in GPU_MEMBERS if n > max(members)]
                    if device == "gpu" and not args.members and not args.quick
                    else []
                )
                # compiles; two members, as one member's arrays may be typed with another layout
                time_ensemble(scene, 2, 0.05, device, threads, 1)
                for n in counts:
                    table[name, n] = time_ensemble(scene, n, duration, device, threads, repeats)
                    wall, steps = table[name, n]
                    print(
                        f"  {name:16s} {n:6d} members  {steps / wall:10.3e} member-steps/s  "
                        f"{1e9 * wall / steps:8.1f} ns each",
                        file=sys.stderr,
                        flush=True,
                    )
        all_members = sorted({n for _, n in table})
        ds = ensemble_dataset(table, all_members, described, scene, duration, args.quick)
        write_dataset(ds, path)
        figure(ds, figure_path)
        for name in ds["backend"].values:
            best = float(ds["throughput"].sel(backend=name).max())
            print(f"{name}: best {best:.3e} member-steps/s ({described[str(name)]})")
        print(f"wrote {path} and {figure_path} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
