"""Engine speed benchmark (issue 2, item 6): ns per contact per step and wall s per simulated s.

Scenes: (a) the free-rocking block of the README, (b) an 8-drum 6 m x 1 m column under
0.5 Hz, 0.25 m harmonic base motion for 20 s, (c) five 3-drum columns with capitals and one
epistyle under a 20 s accelerogram. Each scene runs once to warm the compile cache, then is
timed on one core; (b) is also rerun at dt / 2 to show the result changes by < 1 %.
Prints a table and writes results/bench/engine_speed.nc (and .csv).

    python -m benchmarks.engine_speed [--out results/bench]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from benchmarks import options  # noqa: E402
from stonedem.engine.scene import load_scene, scene_from_dict  # noqa: E402
from stonedem.engine.simulate import simulate  # noqa: E402
from stonedem.io.atomic import write_atomically  # noqa: E402
from stonedem.io.netcdf import code_version, write_dataset  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def synthetic_record(path: Path, duration=20.0, dt=0.01, seed=1) -> Path:
    """A deterministic earthquake-like accelerogram: enveloped band-limited noise, PGA 3 m/s2."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration + dt / 2, dt)
    noise = rng.standard_normal(len(t))
    spectrum = np.fft.rfft(noise)
    freq = np.fft.rfftfreq(len(t), dt)
    spectrum[(freq < 0.5) | (freq > 8.0)] = 0.0
    signal = np.fft.irfft(spectrum, len(t))
    envelope = np.minimum(t / 2.0, 1.0) * np.exp(-np.maximum(t - 8.0, 0.0) / 4.0)
    accel = signal * envelope
    accel *= 3.0 / np.abs(accel).max()
    header = (
        "synthetic accelerogram for benchmarks: band-limited (0.5-8 Hz) noise, seed "
        "1\ntime [s], acceleration [m/s2]"
    )
    return write_atomically(
        path, lambda tmp: np.savetxt(tmp, np.column_stack([t, accel]), header=header, fmt="%.6f")
    )


def column_scene(dt=None, duration=20.0):
    return scene_from_dict(
        {
            "name": "bench_b_8_drum_column",
            "structure": {"kind": "column", "n_drums": 8, "height": 6.0, "width": 1.0},
            "friction": 0.5,
            "contact": {"k_n": 1.0e9, "c_n": 1.0e4},
            "excitation": {"kind": "harmonic", "frequency": 0.5, "amplitude": 0.25},
            "solver": {"duration": duration, "dt": dt if dt else "auto", "stop_on_collapse": False},
            "output": {"every": 0.01},
        }
    )


def colonnade_scene(record: Path, duration=20.0):
    return scene_from_dict(
        {
            "name": "bench_c_colonnade",
            "structure": {
                "kind": "colonnade",
                "n_columns": 5,
                "n_drums": 3,
                "epistyle_type": "a",
                "capital": {"height": 0.6, "width": 1.4},
            },
            "friction": 0.5,
            "contact": {"k_n": 1.0e9, "c_n": 1.0e4},
            "excitation": {"kind": "record", "file": str(record), "scale": 1.0},
            "solver": {"duration": duration, "dt": "auto", "stop_on_collapse": False},
            "output": {"every": 0.01},
        }
    )


def timed(scene):
    simulate(scene)  # warm the cache (compiles on the first call of the process)
    start = time.perf_counter()
    result = simulate(scene)
    total = time.perf_counter() - start
    contacts = float(np.mean(result.n_contact))
    ns = 1e9 * result.wall_seconds / max(result.steps_run * contacts, 1.0)
    return result, total, contacts, ns


def response(scene, result):
    """Response measures compared between dt and dt/2 for scene (b).

    The column collapses (0.25 m at 0.5 Hz is 1.5 g tan(alpha)); after the first rocking
    cycles the motion is chaotic, so pointwise measures over the whole run cannot converge.
    Compared: the verdict, the first two seconds (first cycle), and the collapse time.
    """
    first = result.time <= 2.0
    drums = slice(1, None)
    rocking = np.abs(result.theta[:, drums]).mean(axis=1)
    collapsed = result.collapse_sample >= 0
    return {
        "collapsed": float(collapsed),
        "max_rocking_first_2s": float(rocking[first].max()),
        "max_top_rotation_first_2s": float(np.abs(result.theta[first, -1]).max()),
        "collapse_time": float(result.time[result.collapse_sample]) if collapsed else float("nan"),
    }


OUTPUTS = ("synthetic_record_20s.txt", "engine_speed.nc", "engine_speed.csv")
SCENE_A = ROOT / "tests" / "data" / "scenes" / "rocking_block.yaml"


def build_parser():
    parser = options.parser("python -m benchmarks.engine_speed", __doc__)
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=ROOT / "results" / "bench",
        help="output folder (writes " + ", ".join(OUTPUTS) + ")",
    )
    return parser


def check_args(args) -> Path:
    """The output folder, or an InputError before anything runs."""
    out = options.output_folder(args.out, "--out", files=OUTPUTS)
    options.input_file(
        SCENE_A,
        "scene (a)",
        "scene file (tests/data/scenes/rocking_block.yaml of a source checkout)",
    )
    return out


def main(argv=None) -> int:
    """Options and output folder checked first (one line, exit 2); then the benchmark."""
    args = build_parser().parse_args(argv)
    return options.run(lambda: benchmark(check_args(args)))


def benchmark(out: Path) -> int:
    record = synthetic_record(out / "synthetic_record_20s.txt")
    scenes = {
        "a_free_rocking_block": load_scene(SCENE_A),
        "b_8_drum_column_harmonic": column_scene(),
        "c_colonnade_5x3_record": colonnade_scene(record),
    }
    rows = []
    for name, scene in scenes.items():
        result, total, contacts, ns = timed(scene)
        rows.append(
            dict(
                scene=name,
                n_body=len(scene.bodies),
                dt=result.dt,
                steps=result.steps_run,
                mean_contacts=contacts,
                ns_per_contact_step=ns,
                kernel_wall=result.wall_seconds,
                total_wall=total,
                wall_per_sim_second=result.wall_seconds / scene.duration,
            )
        )
        print(
            f"{name:28s} bodies {len(scene.bodies):3d}  dt {result.dt:.3g} s  steps "
            f"{result.steps_run:8d}  "
            f"contacts {contacts:5.1f}  {ns:6.1f} ns/contact/step  kernel "
            f"{result.wall_seconds:6.2f} s  "
            f"total {total:6.2f} s  {result.wall_seconds / scene.duration:.4f} wall s per sim s"
        )
    # (b) at dt/2: how much does the answer move?
    base = simulate(scenes["b_8_drum_column_harmonic"])
    half = simulate(column_scene(dt=base.dt / 2))
    r1 = response(scenes["b_8_drum_column_harmonic"], base)
    r2 = response(scenes["b_8_drum_column_harmonic"], half)
    change = {k: abs(r1[k] - r2[k]) / max(abs(r2[k]), 1e-12) for k in r1}
    for k in r1:
        print(f"  (b) {k:26s} dt: {r1[k]:.5g}  dt/2: {r2[k]:.5g}  change {100 * change[k]:.3f} %")
    ds = xr.Dataset(
        {
            key: ("scene", np.array([r[key] for r in rows]), {"units": unit, "long_name": long})
            for key, unit, long in [
                ("n_body", "1", "number of bodies"),
                ("dt", "s", "time step"),
                ("steps", "1", "steps run"),
                ("mean_contacts", "1", "mean number of contacts"),
                ("ns_per_contact_step", "ns", "kernel time per contact per step"),
                ("kernel_wall", "s", "wall time of the compiled loop, warm cache, one core"),
                ("total_wall", "s", "wall time including set-up"),
                ("wall_per_sim_second", "1", "kernel wall seconds per simulated second"),
            ]
        },
        coords={
            "scene": (
                "scene",
                [r["scene"] for r in rows],
                {"units": "1", "long_name": "benchmark scene"},
            )
        },
        attrs={
            "title": "stonedem engine speed benchmark",
            "source": code_version(),
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
            "b_dt": base.dt,
            **{f"b_{k}_dt": v for k, v in r1.items()},
            **{f"b_{k}_dt_half": v for k, v in r2.items()},
            **{f"b_dt_half_change_{k}": v for k, v in change.items()},
        },
    )
    write_dataset(ds, out / "engine_speed.nc")
    options.write_text(out / "engine_speed.csv", ds.to_dataframe().to_csv())
    print(f"wrote {out / 'engine_speed.nc'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())  # one-line errors, exit 2 on bad input, 130 on Ctrl-C
