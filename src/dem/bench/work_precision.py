"""Work-precision benchmark: wall time per simulated second against error (issue 6, DESIGN §6).

Scenes (:mod:`dem.bench.canonical`): (a) free rocking, error = worst relative error of the
first three impact times and peaks against the exact rigid block (worst of two blocks);
(b) pulse sliding, error = |u_max / Newmark - 1|; (c) an 8-drum column under a record,
error = worst of the rotation and sliding histories against the same engine at dt / 16.
Engines, in the same process and run: ours (a sweep of k_n and dt as a fraction of the
stability limit), pymunk (:mod:`dem.bench.pymunk_engine`) and MuJoCo
(:mod:`dem.bench.mujoco_engine`), each over dt. Wall time is the stepping alone (ours: the
compiled loop, warm; theirs: the loop of step calls), single thread, sampling included.

    python -m dem.bench.work_precision [--quick] [--out results/bench] [--figures results/figures]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from dem.bench import canonical as cn
from dem.bench import ours

SCENES = ("a", "b", "c")
SCENE_TITLES = {"a": "free rocking from theta0 = 0.5 alpha (0.25 x 1 m and 1 x 6 m blocks)",
                "b": "Newmark pulse sliding (a_p = 0.5 g, T_p = 0.5 s, mu = 0.2)",
                "c": "8-drum 6 x 1 m column under a record (PGA 16 m/s2, 10 s)"}
ERROR_LEVELS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4)
COLUMN_PGA = 16.0  # [m s-2]: the column rocks and slides but stands

FULL = {
    "ours": {"a": {"k_n": (1e9, 1e10, 1e11), "dt_ratio": (0.9, 0.5, 0.25, 0.1)},
             "b": {"k_n": (1e6, 1e7, 1e8, 1e9), "dt_ratio": (0.9, 0.5, 0.25)},
             "c": {"k_n": (1e8, 1e9, 1e10), "dt_ratio": (0.9, 0.5, 0.25)}},
    "pymunk": {"a": (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5), "b": (1e-2, 3e-3, 1e-3, 3e-4, 1e-4),
               "c": (3e-3, 1e-3, 3e-4)},
    "mujoco": {"a": (3e-3, 1e-3, 3e-4, 1e-4, 3e-5), "b": (3e-3, 1e-3, 3e-4, 1e-4),
               "c": (3e-3, 1e-3, 3e-4)},
}
QUICK = {
    "ours": {"a": {"k_n": (1e10,), "dt_ratio": (0.5,)}, "b": {"k_n": (1e8,), "dt_ratio": (0.5,)},
             "c": {"k_n": (1e9,), "dt_ratio": (0.9,)}},
    "pymunk": {"a": (1e-3,), "b": (1e-3,), "c": (3e-3,)},
    "mujoco": {"a": (1e-3,), "b": (1e-3,), "c": (3e-3,)},
}


def competitor(name):
    """The adapter module of a competing engine (imported only when it runs)."""
    if name == "pymunk":
        from dem.bench import pymunk_engine as module
    elif name == "mujoco":
        from dem.bench import mujoco_engine as module
    else:
        raise ValueError(f"unknown engine {name!r}")
    return module


def _row(engine, scene, k_n, dt, dt_ratio, wall, sim, steps, **errors):
    return {"engine": engine, "scene": scene, "k_n": k_n, "dt": dt, "dt_ratio": dt_ratio,
            "wall_per_sim_second": wall / sim, "steps": steps, **errors}


def rocking_runs(run_block):
    """Worst errors and summed cost of free rocking over :data:`canonical.ROCKING_BLOCKS`."""
    t_err = p_err = wall = sim = steps = 0.0
    for width, height in cn.ROCKING_BLOCKS:
        duration = cn.rocking_duration(width, height)
        traj = run_block(width, height, cn.rocking_theta0(width, height), duration)
        te, pe = cn.rocking_errors(traj, width, height)
        t_err, p_err = max(t_err, te), max(p_err, pe)
        wall, sim, steps = wall + traj.wall_seconds, sim + duration, steps + traj.steps
    return dict(error=max(t_err, p_err), error_impact_time=t_err, error_peak=p_err), wall, sim, steps


def ours_points(scene, grid, column_duration):
    """Rows of our engine over k_n x dt_ratio for one scene."""
    rows = []
    for k_n in grid["k_n"]:
        for ratio in grid["dt_ratio"]:
            if scene == "a":
                dts = []

                def run_block(w, h, theta0, duration):
                    c_n = ours.calibrate_rocking_damping(w, h, k_n)
                    traj = ours.free_rocking(w, h, theta0, duration, k_n=k_n, c_n=c_n, dt_ratio=ratio)
                    dts.append(duration / max(traj.steps, 1))
                    return traj

                errors, wall, sim, steps = rocking_runs(run_block)
                rows.append(_row("ours", scene, k_n, min(dts), ratio, wall, sim, steps, **errors))
            elif scene == "b":
                w, h = cn.PULSE_BLOCK
                mass = cn.DENSITY * w * h * cn.DEPTH
                sim = cn.pulse_run_duration()
                traj = ours.pulse_sliding(w, h, cn.PULSE_FRICTION, cn.PULSE_ACCEL, cn.PULSE_DURATION, sim,
                                          k_n=k_n, c_n=0.5 * ours.critical_damping(k_n, w, mass),
                                          dt_ratio=ratio, sample_every=1e-3)
                dt = sim / max(traj.steps, 1)
                rows.append(_row("ours", scene, k_n, dt, ratio, traj.wall_seconds, sim, traj.steps,
                                 error=cn.pulse_error(traj)))
            else:
                c_n = column_damping(k_n)
                run, table = ours.column_record(column_duration, k_n=k_n, c_n=c_n, pga=COLUMN_PGA,
                                                dt_ratio=ratio)
                dt = column_duration / max(run.steps, 1)
                ref, _ = ours.column_record(column_duration, k_n=k_n, c_n=c_n, pga=COLUMN_PGA,
                                            dt=dt / cn.COLUMN_REFERENCE_REFINEMENT)
                e_rot, e_slide = cn.history_errors(run, ref)
                rows.append(_row("ours", scene, k_n, dt, ratio, run.wall_seconds, column_duration,
                                 run.steps, error=max(e_rot, e_slide), error_rotation=e_rot,
                                 error_sliding=e_slide))
            _progress(rows[-1])
    return rows


def column_damping(k_n):
    """c_n of scene (c): 5 % of critical for one drum on its bed joint [N s m-1]."""
    drum_mass = cn.DENSITY * cn.COLUMN_WIDTH * cn.COLUMN_HEIGHT / cn.COLUMN_DRUMS * cn.DEPTH
    return 0.05 * ours.critical_damping(k_n, cn.COLUMN_WIDTH, drum_mass)


def competitor_points(engine, scene, dts, column_duration, record):
    """Rows of a competing engine over dt for one scene."""
    module = competitor(engine)
    rows = []
    for dt in dts:
        if scene == "a":
            errors, wall, sim, steps = rocking_runs(
                lambda w, h, theta0, duration: module.free_rocking(w, h, theta0, dt, duration))
            rows.append(_row(engine, scene, math.nan, dt, math.nan, wall, sim, steps, **errors))
        elif scene == "b":
            w, h = cn.PULSE_BLOCK
            sim = cn.pulse_run_duration()
            traj = module.pulse_sliding(w, h, cn.PULSE_FRICTION, cn.PULSE_ACCEL, cn.PULSE_DURATION, dt, sim)
            rows.append(_row(engine, scene, math.nan, dt, math.nan, traj.wall_seconds, sim, traj.steps,
                             error=cn.pulse_error(traj)))
        else:
            args = (cn.COLUMN_DRUMS, cn.COLUMN_WIDTH, cn.COLUMN_HEIGHT, cn.COLUMN_FRICTION, *record)
            run = module.column_record(*args, dt, column_duration, sample_every=1e-2)
            ref = module.column_record(*args, dt / cn.COLUMN_REFERENCE_REFINEMENT, column_duration,
                                       sample_every=1e-2)
            e_rot, e_slide = cn.history_errors(run, ref)
            rows.append(_row(engine, scene, math.nan, dt, math.nan, run.wall_seconds, column_duration,
                             run.steps, error=max(e_rot, e_slide), error_rotation=e_rot,
                             error_sliding=e_slide))
        _progress(rows[-1])
    return rows


def _progress(row):
    k_n = "" if math.isnan(row["k_n"]) else f"k_n {row['k_n']:.0e} "
    print(f"  ({row['scene']}) {row['engine']:7s} {k_n:12s}dt {row['dt']:.2e} s  "
          f"{1e3 * row['wall_per_sim_second']:9.3f} ms per sim s  error {row['error']:.2e}",
          file=sys.stderr, flush=True)


def warm_up():
    """Compile our loop and load the other engines before anything is timed."""
    ours.pulse_sliding(*cn.PULSE_BLOCK, cn.PULSE_FRICTION, cn.PULSE_ACCEL, 0.01, 0.02, k_n=1e8, c_n=1e5)
    for engine in ("pymunk", "mujoco"):
        competitor(engine).pulse_sliding(*cn.PULSE_BLOCK, cn.PULSE_FRICTION, cn.PULSE_ACCEL, 0.01, 1e-3, 0.02)


def run_sweep(sweep=FULL, scenes=SCENES, column_duration=cn.COLUMN_DURATION) -> xr.Dataset:
    """Every engine on every scene; returns the dataset of :func:`sweep_dataset`."""
    warm_up()
    # scene (c) gives every engine the record exactly as ours applies it
    _, record = ours.column_record(0.01, k_n=1e9, c_n=0.0, pga=COLUMN_PGA, dt=1e-4)
    rows = []
    for scene in scenes:
        print(f"scene ({scene}): {SCENE_TITLES[scene]}", file=sys.stderr)
        rows += ours_points(scene, sweep["ours"][scene], column_duration)
        for engine in ("pymunk", "mujoco"):
            rows += competitor_points(engine, scene, sweep[engine][scene], column_duration, record)
    return sweep_dataset(rows, column_duration)


VARIABLES = {
    "wall_per_sim_second": ("1", "wall time of the stepping per simulated second, one thread"),
    "steps": ("1", "time steps taken"),
    "error": ("1", "benchmark error of the run (see the scene's error attrs)"),
    "error_impact_time": ("1", "(a) worst relative error of the first three impact times"),
    "error_peak": ("1", "(a) worst relative error of the peak angles after them"),
    "error_rotation": ("1", "(c) max |rotation - reference| / max |reference rotation|"),
    "error_sliding": ("1", "(c) max |joint sliding - reference| / max |reference sliding|"),
}


def sweep_dataset(rows, column_duration) -> xr.Dataset:
    """The runs as one self-describing dataset (dim ``run``; engine, scene, k_n, dt as coords)."""
    from dem.dataset import code_version

    n = len(rows)
    data = {}
    for key, (units, long_name) in VARIABLES.items():
        values = np.array([float(r.get(key, math.nan)) for r in rows])
        data[key] = ("run", values, {"units": units, "long_name": long_name})
    coords = {
        "run": ("run", np.arange(n), {"units": "1", "long_name": "run number"}),
        "engine": ("run", [r["engine"] for r in rows], {"units": "1", "long_name": "engine (ours, pymunk, mujoco)"}),
        "scene": ("run", [r["scene"] for r in rows], {"units": "1", "long_name": "canonical scene a, b or c"}),
        "k_n": ("run", np.array([r["k_n"] for r in rows]), {"units": "N m-2", "long_name": "normal contact stiffness (ours only)"}),
        "dt": ("run", np.array([r["dt"] for r in rows]), {"units": "s", "long_name": "time step"}),
        "dt_ratio": ("run", np.array([r["dt_ratio"] for r in rows]), {"units": "1", "long_name": "dt / stability limit (ours only)"}),
    }
    import mujoco
    import pymunk

    ds = xr.Dataset(data, coords=coords, attrs={
        "title": "work-precision benchmark: wall time per simulated second against error",
        "source": code_version(), "pymunk_version": pymunk.version, "mujoco_version": mujoco.__version__,
        "machine": f"{os.cpu_count()} cores, {sys.platform}",
        "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
        **{f"scene_{s}": SCENE_TITLES[s] for s in SCENES},
        "scene_c_duration": column_duration, "scene_c_pga": COLUMN_PGA,
        "scene_c_reference": f"same engine at dt / {cn.COLUMN_REFERENCE_REFINEMENT}",
        "ours_rocking_damping": "c_n calibrated per block and k_n to Housner's first-impact energy ratio at 0.1 x the stability limit",
        "ours_pulse_damping": "c_n = 0.5 x critical", "ours_column_damping": "c_n = 0.05 x critical of one drum",
    })
    speedup = speedup_table(ds)
    for scene in speedup.scene.values:
        for level in speedup.error_level.values:
            value = float(speedup.sel(scene=scene, error_level=level))
            ds.attrs[f"speedup_{scene}_error_{level:g}"] = value
    return ds


def fastest_at(ds: xr.Dataset, engine: str, scene: str, level: float) -> float:
    """Least wall time per simulated second of an engine's runs with error <= level (NaN if none)."""
    sel = (ds.engine == engine) & (ds.scene == scene) & (ds.error <= level)
    values = ds.wall_per_sim_second.where(sel, drop=True)
    return float(values.min()) if values.size else math.nan


def speedup_table(ds: xr.Dataset) -> xr.DataArray:
    """Best competitor's wall time / ours at each error level (> 1: we are faster; NaN: one has no run there)."""
    scenes = [s for s in SCENES if (ds.scene == s).any()]
    table = np.full((len(scenes), len(ERROR_LEVELS)), math.nan)
    for i, scene in enumerate(scenes):
        for j, level in enumerate(ERROR_LEVELS):
            theirs = [fastest_at(ds, e, scene, level) for e in ("pymunk", "mujoco")]
            theirs = [t for t in theirs if np.isfinite(t)]
            mine = fastest_at(ds, "ours", scene, level)
            if theirs and np.isfinite(mine):
                table[i, j] = min(theirs) / mine
    return xr.DataArray(table, dims=("scene", "error_level"),
                        coords={"scene": scenes, "error_level": list(ERROR_LEVELS)},
                        attrs={"units": "1", "long_name": "best competitor's wall time / ours at equal or better error"})


def plot_work_precision(ds: xr.Dataset, scene: str, path: Path) -> Path:
    """Log-log wall time per simulated second against error, every engine on one axes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dem.atomic import write_atomically

    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    sub = ds.where(ds.scene == scene, drop=True)
    for engine, marker in (("pymunk", "s"), ("mujoco", "^")):
        e = sub.where(sub.engine == engine, drop=True)
        if e.run.size:
            order = np.argsort(e.dt.values)
            ax.plot(e.error.values[order], e.wall_per_sim_second.values[order], marker=marker, ls="--",
                    label=f"{engine} (dt {e.dt.min().item():.0e}-{e.dt.max().item():.0e} s)")
    o = sub.where(sub.engine == "ours", drop=True)
    for k_n in np.unique(o.k_n.values):
        e = o.where(o.k_n == k_n, drop=True)
        order = np.argsort(e.dt_ratio.values)
        ax.plot(e.error.values[order], e.wall_per_sim_second.values[order], marker="o",
                label=f"ours, k_n {k_n:.0e} N/m2 (dt {e.dt_ratio.min().item():g}-{e.dt_ratio.max().item():g} x limit)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("error [1]")
    ax.set_ylabel("wall time per simulated second [s]")
    ax.set_title(f"({scene}) {SCENE_TITLES[scene]}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)
    return path


def summary_text(ds: xr.Dataset) -> str:
    """The speed-up table as text: one line per scene, one column per error level."""
    table = speedup_table(ds)
    head = "scene  " + "  ".join(f"err<={level:<7g}" for level in table.error_level.values)
    lines = [head]
    for scene in table.scene.values:
        cells = [f"{v:11.2f}" if np.isfinite(v) else f"{'-':>11s}" for v in table.sel(scene=scene).values]
        lines.append(f"({scene})   " + " ".join(cells))
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a few points per engine (CI)")
    parser.add_argument("--out", type=Path, default=Path("results/bench"))
    parser.add_argument("--figures", type=Path, default=Path("results/figures"))
    args = parser.parse_args(argv)
    from dem.dataset import write_dataset

    start = time.perf_counter()
    if args.quick:
        ds = run_sweep(QUICK)
    else:
        ds = run_sweep(FULL)
    ds.attrs["profile"] = "quick" if args.quick else "full"
    write_dataset(ds, args.out / "work_precision.nc")
    for scene in SCENES:
        plot_work_precision(ds, scene, args.figures / f"work_precision_{scene}.png")
    print("best competitor's wall time / ours at equal or better error:")
    print(summary_text(ds))
    print(f"wrote {args.out / 'work_precision.nc'} in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
