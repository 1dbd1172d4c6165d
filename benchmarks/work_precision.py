"""Work-precision benchmark: wall time per simulated second against error (issue 6, DESIGN §6).

Scenes (:mod:`benchmarks.canonical`): (a) free rocking, error = worst relative error of the
first three impact times and peaks against the exact rigid block (worst of two blocks);
(a1) free rocking to the first impact, the blocks of (a) released from the same tilt, error =
worst over the two blocks of |t_1 / exact t_1 - 1|, the relative error of the first impact
time (:func:`benchmarks.canonical.first_impact_error`);
(b) pulse sliding, error = |u_max / Newmark - 1|; (c) an 8-drum column under a record,
error = worst of the rotation and sliding histories against the same engine at dt / 16.
Engines, in the same process and run: ours, with three contact variants
(:data:`benchmarks.ours.VARIANTS`: the thesis' overlap-area law with a calibrated dashpot,
point contacts with a calibrated dashpot, point contacts with Housner's plastic landing
and zeta 0.05), each a sweep of k_n and dt as a fraction of the stability limit; pymunk
(:mod:`benchmarks.pymunk_engine`) and MuJoCo (:mod:`benchmarks.mujoco_engine`), each over
dt.

How the runs of (a1) stop: every engine runs each block for a fixed duration,
:data:`benchmarks.canonical.FIRST_IMPACT_MARGIN` (1.2) x the exact rigid block's first
impact time (0.349 s and 0.847 s, so 0.419 s and 1.017 s; 1.436 simulated seconds in all),
sampled every 1 ms as in (a); the impact is the first sign change of theta, linearly
interpolated between samples, exactly as (a) detects each of its impacts (no sign change
within the run: error 1). No engine stops at the impact itself: a fixed duration keeps the
simulated time, hence wall time per simulated second, equal for all. The sampling sets a
floor on the measure: interpolating across the kink of theta(t) at the impact shifts the
detected time by up to ~1e-4 x t_1 (measured: our point law 6.5e-5 on the 0.25 x 1 m block
with 1 ms samples against 3e-6 with 0.1 ms), so the 1e-4 level is at the floor of the
measure; from 3e-4 up it is resolved. Ours runs the same contacts as (a) (calibrated
dashpots, or the point law's defaults) over the same k_n x dt grid; pymunk and MuJoCo the
same dt as in (a).

Wall time is the stepping alone (ours: the compiled loop, warm; theirs: the loop of
step calls), single thread, sampling included; each timed run is repeated ``repeats`` times
(every engine is deterministic) and the least wall time kept, so a busy machine inflates
fewer timings. The comparison (:func:`speedup_table`) is
the best competitor's wall time over ours at equal or better error, for the best of our
variants and for each.

    python -m benchmarks.work_precision [--quick] [--scenes a a1 c] [--contacts point area]
    [--repeats 3]
                                       [--out results/bench] [--figures results/figures]
"""

from __future__ import annotations

import functools
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from benchmarks import canonical as cn
from benchmarks import ours
from stonedem.reference import analytic

SCENES = ("a", "a1", "b", "c")
ROCKING_SCENES = ("a", "a1")  # free rocking: the same blocks, contacts and sweeps
SCENE_TITLES = {
    "a": "free rocking from theta0 = 0.5 alpha (0.25 x 1 m and 1 x 6 m blocks)",
    "a1": "free rocking to the first impact (scene a's blocks and tilt, run to 1.2 x the exact "
    "first impact time)",
    "b": "Newmark pulse sliding (a_p = 0.5 g, T_p = 0.5 s, mu = 0.2)",
    "c": "8-drum 6 x 1 m column under a record (PGA 16 m/s2, 10 s)",
}
ERROR_LEVELS = (1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4)
COLUMN_PGA = 16.0  # [m s-2]: the column rocks and slides but stands
REPEATS = {"full": 3, "quick": 1}  # identical runs per timed point; the least wall time counts

NO_VARIANT = "-"  # the contact coordinate of the other engines' runs

# ours: every contact variant x k_n [N m-2] x dt / stability limit, per scene
FULL = {
    "ours": {
        "a": {
            "contact": ours.VARIANTS,
            "k_n": (1e8, 1e9, 1e10, 1e11),
            "dt_ratio": (1.0, 0.5, 0.25, 0.1),
        },
        "a1": {
            "contact": ours.VARIANTS,
            "k_n": (1e8, 1e9, 1e10, 1e11),
            "dt_ratio": (1.0, 0.5, 0.25, 0.1),
        },
        "b": {"contact": ours.VARIANTS, "k_n": (1e6, 1e7, 1e8, 1e9), "dt_ratio": (0.9, 0.5, 0.25)},
        "c": {"contact": ours.VARIANTS, "k_n": (1e8, 1e9, 1e10), "dt_ratio": (1.0, 0.5, 0.25)},
    },
    "pymunk": {
        "a": (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5),
        "a1": (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5),
        "b": (1e-2, 3e-3, 1e-3, 3e-4, 1e-4),
        "c": (3e-3, 1e-3, 3e-4),
    },
    "mujoco": {
        "a": (3e-3, 1e-3, 3e-4, 1e-4, 3e-5),
        "a1": (3e-3, 1e-3, 3e-4, 1e-4, 3e-5),
        "b": (3e-3, 1e-3, 3e-4, 1e-4),
        "c": (3e-3, 1e-3, 3e-4),
    },
}
QUICK = {
    "ours": {
        "a": {"contact": ours.VARIANTS, "k_n": (1e10,), "dt_ratio": (0.5,)},
        "a1": {"contact": ours.VARIANTS, "k_n": (1e10,), "dt_ratio": (0.5,)},
        "b": {"contact": ours.VARIANTS, "k_n": (1e8,), "dt_ratio": (0.5,)},
        "c": {"contact": ("area", "point"), "k_n": (1e9,), "dt_ratio": (1.0,)},
    },
    "pymunk": {"a": (1e-3,), "a1": (1e-3,), "b": (1e-3,), "c": (3e-3,)},
    "mujoco": {"a": (1e-3,), "a1": (1e-3,), "b": (1e-3,), "c": (3e-3,)},
}


def competitor(name):
    """The adapter module of a competing engine (imported only when it runs)."""
    if name == "pymunk":
        from benchmarks import pymunk_engine as module
    elif name == "mujoco":
        from benchmarks import mujoco_engine as module
    else:
        raise ValueError(f"unknown engine {name!r}")
    return module


def _row(
    engine,
    scene,
    k_n,
    dt,
    dt_ratio,
    wall,
    sim,
    steps,
    contact=NO_VARIANT,
    status=0,
    c_n=math.nan,
    zeta=math.nan,
    rocking_c_n=None,
    rocking_zeta=None,
    rocking_restitution=None,
    **errors,
):
    none = [math.nan] * len(cn.ROCKING_BLOCKS)
    return {
        "engine": engine,
        "scene": scene,
        "contact": contact,
        "k_n": k_n,
        "dt": dt,
        "dt_ratio": dt_ratio,
        "wall_per_sim_second": wall / sim,
        "steps": steps,
        "status": status,
        "c_n": c_n,
        "zeta": zeta,
        "rocking_c_n": rocking_c_n or none,
        "rocking_zeta": rocking_zeta or none,
        "rocking_restitution": rocking_restitution or none,
        **errors,
    }


def timed(run, repeats=1):
    """``run()`` (a Trajectory) ``repeats`` times; the first result, with the least wall time of
    all."""
    traj = run()
    for _ in range(repeats - 1):
        traj.wall_seconds = min(traj.wall_seconds, run().wall_seconds)
    return traj


def rocking_runs(run_block, repeats=1, scene="a"):
    """Worst errors, summed cost and worst status of free rocking over
    :data:`canonical.ROCKING_BLOCKS`.

    scene "a": each block to :func:`canonical.rocking_duration`, errors of the first three
    impacts and peaks; "a1": each block to :func:`canonical.first_impact_duration`, error of the
    first impact time alone (error_peak NaN).
    """
    t_err = p_err = wall = sim = steps = 0.0
    status = 0
    for width, height in cn.ROCKING_BLOCKS:
        if scene == "a1":
            duration = cn.first_impact_duration(width, height)
        else:
            duration = cn.rocking_duration(width, height)
        theta0 = cn.rocking_theta0(width, height)
        traj = timed(functools.partial(run_block, width, height, theta0, duration), repeats)
        if scene == "a1":
            te, pe = cn.first_impact_error(traj, width, height), 0.0
        else:
            te, pe = cn.rocking_errors(traj, width, height)
        t_err, p_err = max(t_err, te), max(p_err, pe)
        wall, sim, steps = wall + traj.wall_seconds, sim + duration, steps + traj.steps
        status = max(status, traj.status)
    if scene == "a1":
        return (
            {"error": t_err, "error_impact_time": t_err, "error_peak": math.nan},
            wall,
            sim,
            steps,
            status,
        )
    return (
        dict(error=max(t_err, p_err), error_impact_time=t_err, error_peak=p_err),
        wall,
        sim,
        steps,
        status,
    )


def ours_points(scene, grid, column_duration, repeats=1):
    """Rows of our engine over contact variant x k_n x dt_ratio for one scene."""
    rows = []
    for variant in grid["contact"]:
        for k_n in grid["k_n"]:
            for ratio in grid["dt_ratio"]:
                rows.append(ours_point(scene, variant, k_n, ratio, column_duration, repeats))
                _progress(rows[-1])
    return rows


def ours_point(scene, variant, k_n, ratio, column_duration, repeats=1):
    """One row of our engine: a contact variant at k_n [N m-2] and dt = ratio x stability limit."""
    if scene in ROCKING_SCENES:
        dts, laws = {}, {}

        def run_block(w, h, theta0, duration):
            contact = ours.rocking_contact(variant, w, h, k_n)
            reached = (
                math.nan
                if variant == "point"
                else ours.rocking_calibration(w, h, k_n, model=contact["model"])[1]
            )
            laws[w, h] = (*ours.contact_damping(contact), reached)
            traj = ours.free_rocking(w, h, theta0, duration, contact=contact, dt_ratio=ratio)
            dts[w, h] = duration / max(traj.steps, 1)
            return traj

        errors, wall, sim, steps, status = rocking_runs(run_block, repeats, scene)
        laws = [laws[block] for block in cn.ROCKING_BLOCKS]
        dts = list(dts.values())
        return _row(
            "ours",
            scene,
            k_n,
            min(dts),
            ratio,
            wall,
            sim,
            steps,
            contact=variant,
            status=status,
            rocking_c_n=[c for c, _, _ in laws],
            rocking_zeta=[z for _, z, _ in laws],
            rocking_restitution=[r for _, _, r in laws],
            **errors,
        )
    if scene == "b":
        w, h = cn.PULSE_BLOCK
        sim = cn.pulse_run_duration()
        contact = ours.pulse_contact(variant, k_n)
        traj = timed(
            lambda: ours.pulse_sliding(
                w,
                h,
                cn.PULSE_FRICTION,
                cn.PULSE_ACCEL,
                cn.PULSE_DURATION,
                sim,
                contact=contact,
                dt_ratio=ratio,
                sample_every=1e-3,
            ),
            repeats,
        )
        c_n, zeta = ours.contact_damping(contact)
        return _row(
            "ours",
            scene,
            k_n,
            sim / max(traj.steps, 1),
            ratio,
            traj.wall_seconds,
            sim,
            traj.steps,
            contact=variant,
            status=traj.status,
            c_n=c_n,
            zeta=zeta,
            error=cn.pulse_error(traj),
        )
    contact = ours.column_contact(variant, k_n)
    run = timed(
        lambda: ours.column_record(
            column_duration, contact=contact, pga=COLUMN_PGA, dt_ratio=ratio
        )[0],
        repeats,
    )
    dt = column_duration / max(run.steps, 1)
    ref, _ = ours.column_record(
        column_duration, contact=contact, pga=COLUMN_PGA, dt=dt / cn.COLUMN_REFERENCE_REFINEMENT
    )
    e_rot, e_slide = cn.history_errors(run, ref)
    c_n, zeta = ours.contact_damping(contact)
    return _row(
        "ours",
        scene,
        k_n,
        dt,
        ratio,
        run.wall_seconds,
        column_duration,
        run.steps,
        contact=variant,
        status=max(run.status, ref.status),
        c_n=c_n,
        zeta=zeta,
        error=max(e_rot, e_slide),
        error_rotation=e_rot,
        error_sliding=e_slide,
    )


def competitor_points(engine, scene, dts, column_duration, record, repeats=1):
    """Rows of a competing engine over dt for one scene."""
    module = competitor(engine)
    rows = []
    for dt in dts:
        if scene in ROCKING_SCENES:
            errors, wall, sim, steps, _ = rocking_runs(
                lambda w, h, theta0, duration, dt=dt: module.free_rocking(
                    w, h, theta0, dt, duration
                ),
                repeats,
                scene,
            )
            rows.append(_row(engine, scene, math.nan, dt, math.nan, wall, sim, steps, **errors))
        elif scene == "b":
            w, h = cn.PULSE_BLOCK
            sim = cn.pulse_run_duration()
            traj = timed(
                functools.partial(
                    module.pulse_sliding,
                    w,
                    h,
                    cn.PULSE_FRICTION,
                    cn.PULSE_ACCEL,
                    cn.PULSE_DURATION,
                    dt,
                    sim,
                ),
                repeats,
            )
            rows.append(
                _row(
                    engine,
                    scene,
                    math.nan,
                    dt,
                    math.nan,
                    traj.wall_seconds,
                    sim,
                    traj.steps,
                    error=cn.pulse_error(traj),
                )
            )
        else:
            args = (cn.COLUMN_DRUMS, cn.COLUMN_WIDTH, cn.COLUMN_HEIGHT, cn.COLUMN_FRICTION, *record)
            run = timed(
                functools.partial(
                    module.column_record, *args, dt, column_duration, sample_every=1e-2
                ),
                repeats,
            )
            ref = module.column_record(
                *args, dt / cn.COLUMN_REFERENCE_REFINEMENT, column_duration, sample_every=1e-2
            )
            e_rot, e_slide = cn.history_errors(run, ref)
            rows.append(
                _row(
                    engine,
                    scene,
                    math.nan,
                    dt,
                    math.nan,
                    run.wall_seconds,
                    column_duration,
                    run.steps,
                    error=max(e_rot, e_slide),
                    error_rotation=e_rot,
                    error_sliding=e_slide,
                )
            )
        _progress(rows[-1])
    return rows


def _progress(row):
    k_n = "" if math.isnan(row["k_n"]) else f"k_n {row['k_n']:.0e} x {row['dt_ratio']:<4g} "
    name = row["engine"] if row["contact"] == NO_VARIANT else f"{row['engine']} {row['contact']}"
    status = "" if row["status"] == 0 else f"  status {row['status']}"
    print(
        f"  ({row['scene']}) {name:19s} {k_n:17s}dt {row['dt']:.2e} s  "
        f"{1e3 * row['wall_per_sim_second']:9.3f} ms per sim s  error {row['error']:.2e}{status}",
        file=sys.stderr,
        flush=True,
    )


def warm_up():
    """Compile our loop and load the other engines before anything is timed."""
    for variant in ours.VARIANTS:
        ours.pulse_sliding(
            *cn.PULSE_BLOCK,
            cn.PULSE_FRICTION,
            cn.PULSE_ACCEL,
            0.01,
            0.02,
            contact=ours.pulse_contact(variant, 1e8),
        )
    for engine in ("pymunk", "mujoco"):
        competitor(engine).pulse_sliding(
            *cn.PULSE_BLOCK, cn.PULSE_FRICTION, cn.PULSE_ACCEL, 0.01, 1e-3, 0.02
        )


def run_sweep(
    sweep=FULL, scenes=SCENES, column_duration=cn.COLUMN_DURATION, contacts=None, repeats=1
) -> xr.Dataset:
    """Every engine on every scene; returns the dataset of :func:`sweep_dataset`.

    contacts: our contact variants to run (default: each scene's grid["contact"]);
    repeats: identical runs per timed point, the least wall time counts.
    """
    warm_up()
    # scene (c) gives every engine the record exactly as ours applies it
    _, record = ours.column_record(
        0.01, contact=ours.column_contact("point", 1e9), pga=COLUMN_PGA, dt=1e-4
    )
    rows = []
    for scene in scenes:
        print(f"scene ({scene}): {SCENE_TITLES[scene]}", file=sys.stderr)
        grid = dict(sweep["ours"][scene])
        if contacts is not None:
            grid["contact"] = tuple(v for v in grid["contact"] if v in contacts)
        rows += ours_points(scene, grid, column_duration, repeats)
        for engine in ("pymunk", "mujoco"):
            rows += competitor_points(
                engine, scene, sweep[engine][scene], column_duration, record, repeats
            )
    ds = sweep_dataset(rows, column_duration)
    ds.attrs["timing_repeats"] = repeats
    ds.attrs["timing"] = f"least wall time of {repeats} identical run(s) per point"
    return ds


VARIABLES = {
    "wall_per_sim_second": ("1", "wall time of the stepping per simulated second, one thread"),
    "steps": ("1", "time steps taken"),
    "status": (
        "1",
        "worst run status of our engine (0 ok, 2 non-finite; stonedem.kernels.step), 0 for the "
        "others",
    ),
    "error": ("1", "benchmark error of the run (see the scene's error attrs)"),
    "error_impact_time": (
        "1",
        "(a) worst relative error of the first three impact times; (a1) of the first impact time",
    ),
    "error_peak": ("1", "(a) worst relative error of the peak angles after them (NaN for a1)"),
    "error_rotation": ("1", "(c) max |rotation - reference| / max |reference rotation|"),
    "error_sliding": ("1", "(c) max |joint sliding - reference| / max |reference sliding|"),
    "c_n": (
        "N s m-1",
        "(b), (c) normal dashpot of our area law (NaN: point law, scene a or another engine)",
    ),
    "zeta": (
        "1",
        "(b), (c) damping of each contact point of our point law, fraction of critical "
        "(NaN: area law, scene a or another engine)",
    ),
}
BLOCK_VARIABLES = {
    "rocking_c_n": (
        "N s m-1",
        "(a), (a1) normal dashpot of our area law per rocking block, calibrated to "
        "Housner's first impact (NaN: point law or another engine)",
    ),
    "rocking_zeta": (
        "1",
        "(a), (a1) damping of each contact point of our point law per rocking block, fraction "
        "of critical (calibrated for point_dashpot; NaN: area law or another engine)",
    ),
    "rocking_restitution": (
        "1",
        "(a), (a1) first-impact energy ratio the calibrated damping gives at 0.1 x the "
        "stability limit (target: housner_restitution; NaN: point or another engine)",
    ),
}


def sweep_dataset(rows, column_duration) -> xr.Dataset:
    """The runs as one self-describing dataset (dim ``run``; engine, contact, scene, k_n, dt as
    coords)."""
    from stonedem.io.netcdf import code_version

    n = len(rows)
    data = {}
    for key, (units, long_name) in VARIABLES.items():
        values = np.array([float(r.get(key, math.nan)) for r in rows])
        data[key] = ("run", values, {"units": units, "long_name": long_name})
    for key, (units, long_name) in BLOCK_VARIABLES.items():
        values = np.array([[float(v) for v in r[key]] for r in rows]).reshape(
            n, len(cn.ROCKING_BLOCKS)
        )
        data[key] = (("run", "block"), values, {"units": units, "long_name": long_name})
    coords = {
        "run": ("run", np.arange(n), {"units": "1", "long_name": "run number"}),
        "engine": (
            "run",
            [r["engine"] for r in rows],
            {"units": "1", "long_name": "engine (ours, pymunk, mujoco)"},
        ),
        "contact": (
            "run",
            [r["contact"] for r in rows],
            {
                "units": "1",
                "long_name": f"contact variant of ours ({', '.join(ours.VARIANTS)}; "
                f"'{NO_VARIANT}' for the other engines)",
            },
        ),
        "scene": (
            "run",
            [r["scene"] for r in rows],
            {"units": "1", "long_name": "canonical scene a, a1, b or c"},
        ),
        "k_n": (
            "run",
            np.array([r["k_n"] for r in rows]),
            {
                "units": "N m-2",
                "long_name": "normal contact stiffness (ours only): per unit overlap area "
                "(area law) or per unit contact length (point law)",
            },
        ),
        "dt": ("run", np.array([r["dt"] for r in rows]), {"units": "s", "long_name": "time step"}),
        "dt_ratio": (
            "run",
            np.array([r["dt_ratio"] for r in rows]),
            {"units": "1", "long_name": "dt / stability limit (ours only)"},
        ),
        "block": (
            "block",
            np.arange(len(cn.ROCKING_BLOCKS)),
            {"units": "1", "long_name": "rocking block of scenes (a), (a1)"},
        ),
        "block_width": (
            "block",
            np.array([w for w, _ in cn.ROCKING_BLOCKS]),
            {"units": "m", "long_name": "width of the rocking block"},
        ),
        "block_height": (
            "block",
            np.array([h for _, h in cn.ROCKING_BLOCKS]),
            {"units": "m", "long_name": "height of the rocking block"},
        ),
        "housner_restitution": (
            "block",
            np.array([analytic.housner_restitution(w, h) for w, h in cn.ROCKING_BLOCKS]),
            {"units": "1", "long_name": "Housner's energy ratio of an impact of the rocking block"},
        ),
    }
    import mujoco
    import pymunk

    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": "work-precision benchmark: wall time per simulated second against error",
            "source": code_version(),
            "pymunk_version": pymunk.version,
            "mujoco_version": mujoco.__version__,
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
            **{f"scene_{s}": SCENE_TITLES[s] for s in SCENES},
            "scene_a1_stop": f"each block runs {cn.FIRST_IMPACT_MARGIN:g} x its exact first "
            "impact time, sampled "
            f"every 1 ms; the impact: the first sign change of theta, as in (a)",
            "scene_c_duration": column_duration,
            "scene_c_pga": COLUMN_PGA,
            "scene_c_reference": f"same engine at dt / {cn.COLUMN_REFERENCE_REFINEMENT}",
            **{f"contact_{v}": ours.VARIANT_TITLES[v] for v in ours.VARIANTS},
            "ours_rocking_damping": "area: c_n, point_dashpot: zeta, calibrated per block and "
            "k_n to Housner's "
            "first-impact energy ratio at 0.1 x the stability limit "
            "(benchmarks.ours.calibrate_rocking_damping); point: zeta = 0.05",
            "ours_pulse_damping": f"area: c_n = {ours.PULSE_DAMPING} x critical; "
            f"point_dashpot, point: zeta = {ours.POINT_DAMPING}",
            "ours_column_damping": f"area: c_n = {ours.COLUMN_DAMPING} x critical of one drum; "
            "point_dashpot, point: "
            f"zeta = {ours.POINT_DAMPING}",
            "speedup": "speedup_[<variant>_]<scene>_error_<level>: best competitor's wall time "
            "/ ours at error <= level, "
            "for the best of our variants (no variant in the name) or one variant; NaN: one "
            "side never reaches it",
        },
    )
    table = speedup_table(ds)
    for contact in table.contact.values:
        prefix = "speedup" if contact == "best" else f"speedup_{contact}"
        for scene in table.scene.values:
            for level in table.error_level.values:
                ds.attrs[f"{prefix}_{scene}_error_{level:g}"] = float(
                    table.sel(contact=contact, scene=scene, error_level=level)
                )
    return ds


def fastest_at(
    ds: xr.Dataset, engine: str, scene: str, level: float, contact: str | None = None
) -> float:
    """Least wall time per simulated second of an engine's runs with error <= level (NaN if none);
    contact: only our runs of that variant (None: any)."""
    sel = (ds.engine == engine) & (ds.scene == scene) & (ds.error <= level)
    if contact is not None:
        sel = sel & (ds.contact == contact)
    values = ds.wall_per_sim_second.where(sel, drop=True)
    return float(values.min()) if values.size else math.nan


def _ours_contacts(ds: xr.Dataset) -> list[str]:
    present = set(ds.contact.values[ds.engine.values == "ours"])
    return ["best"] + [v for v in ours.VARIANTS if v in present]


def fastest_table(ds: xr.Dataset) -> xr.DataArray:
    """Least wall time per simulated second at error <= level: ours (best variant and each), pymunk,
    MuJoCo."""
    scenes = [s for s in SCENES if (ds.scene == s).any()]
    rows = [f"ours_{c}" for c in _ours_contacts(ds)] + ["pymunk", "mujoco"]
    table = np.full((len(rows), len(scenes), len(ERROR_LEVELS)), math.nan)
    for i, row in enumerate(rows):
        engine, _, contact = row.partition("_")
        contact = None if contact in ("", "best") else contact
        for j, scene in enumerate(scenes):
            for k, level in enumerate(ERROR_LEVELS):
                table[i, j, k] = fastest_at(ds, engine, scene, level, contact)
    return xr.DataArray(
        table,
        dims=("entry", "scene", "error_level"),
        coords={"entry": rows, "scene": scenes, "error_level": list(ERROR_LEVELS)},
        attrs={
            "units": "s",
            "long_name": "least wall time per simulated second at equal or better error",
        },
    )


def speedup_table(ds: xr.Dataset) -> xr.DataArray:
    """Best competitor's wall time / ours at each error level, for the best of our variants and
    for each (> 1: we are faster; NaN: one side has no run there)."""
    fastest = fastest_table(ds)
    theirs = fastest.sel(entry=["pymunk", "mujoco"]).min("entry", skipna=True)
    contacts = _ours_contacts(ds)
    table = theirs.values[None, :, :] / fastest.sel(entry=[f"ours_{c}" for c in contacts]).values
    return xr.DataArray(
        table,
        dims=("contact", "scene", "error_level"),
        coords={
            "contact": contacts,
            "scene": list(fastest.scene.values),
            "error_level": list(ERROR_LEVELS),
        },
        attrs={
            "units": "1",
            "long_name": "best competitor's wall time / ours at equal or better error",
        },
    )


VARIANT_STYLES = {"area": ("o", "-"), "point_dashpot": ("D", "-."), "point": ("v", ":")}


def plot_work_precision(ds: xr.Dataset, scene: str, path: Path) -> Path:
    """Log-log wall time per simulated second against error, every engine and variant on one
    axes."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stonedem.io.atomic import write_atomically

    fig, ax = plt.subplots(figsize=(7.2, 5.4))
    sub = ds.where(ds.scene == scene, drop=True)
    for engine, marker in (("pymunk", "s"), ("mujoco", "^")):
        e = sub.where(sub.engine == engine, drop=True)
        if e.run.size:
            order = np.argsort(e.dt.values)
            ax.plot(
                e.error.values[order],
                e.wall_per_sim_second.values[order],
                marker=marker,
                ls="--",
                color="k" if engine == "pymunk" else "0.5",
                label=f"{engine} (dt {e.dt.min().item():.0e}-{e.dt.max().item():.0e} s)",
            )
    o = sub.where(sub.engine == "ours", drop=True)
    k_values = np.unique(o.k_n.values) if o.run.size else []
    for variant in ours.VARIANTS:
        marker, ls = VARIANT_STYLES[variant]
        for c, k_n in enumerate(k_values):
            e = o.where((o.k_n == k_n) & (o.contact == variant), drop=True)
            if not e.run.size:
                continue
            order = np.argsort(e.dt_ratio.values)
            ax.plot(
                e.error.values[order],
                e.wall_per_sim_second.values[order],
                marker=marker,
                ls=ls,
                color=f"C{c}",
                label=f"ours {variant}, k_n {k_n:.0e} "
                f"(dt {e.dt_ratio.min().item():g}-{e.dt_ratio.max().item():g} x limit)",
            )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("error [1]")
    ax.set_ylabel("wall time per simulated second [s]")
    ax.set_title(f"({scene}) {SCENE_TITLES[scene]}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)
    return path


def summary_text(ds: xr.Dataset) -> str:
    """The speed-up table (best of our variants and each) and the fastest wall times, as text."""
    table = speedup_table(ds)
    fastest = fastest_table(ds)
    head = "scene  ours            " + "  ".join(
        f"err<={level:<7g}" for level in table.error_level.values
    )
    lines = ["best competitor's wall time / ours at equal or better error:", head]
    for scene in table.scene.values:
        for contact in table.contact.values:
            cells = [
                f"{v:11.2f}" if np.isfinite(v) else f"{'-':>11s}"
                for v in table.sel(scene=scene, contact=contact).values
            ]
            lines.append(f"{'(' + scene + ')':7s}{contact:15s} " + " ".join(cells))
    lines += [
        "",
        "least wall time per simulated second [ms] at equal or better error:",
        "scene  engine              "
        + "  ".join(f"err<={level:<7g}" for level in fastest.error_level.values),
    ]
    for scene in fastest.scene.values:
        for entry in fastest.entry.values:
            cells = [
                f"{1e3 * v:11.3f}" if np.isfinite(v) else f"{'-':>11s}"
                for v in fastest.sel(scene=scene, entry=entry).values
            ]
            lines.append(f"{'(' + scene + ')':7s}{entry:19s} " + " ".join(cells))
    lines += ["", "best error reached (wall time per simulated second of that run):"]
    for scene in fastest.scene.values:
        for entry in fastest.entry.values:
            engine, _, contact = entry.partition("_")
            sel = (ds.scene == scene) & (ds.engine == engine)
            if contact not in ("", "best"):
                sel = sel & (ds.contact == contact)
            runs = ds.where(sel, drop=True)
            if not runs.run.size:
                continue
            i = int(np.nanargmin(runs.error.values))
            r = runs.isel(run=i)
            where = (
                f"k_n {float(r.k_n):.0e}, dt {float(r.dt_ratio):g} x limit = {float(r.dt):.2e} s"
                if engine == "ours"
                else f"dt {float(r.dt):.0e} s"
            )
            lines.append(
                f"{'(' + scene + ')':7s}{entry:19s} {float(r.error):.3e}  at {where}, "
                f"{1e3 * float(r.wall_per_sim_second):.3f} ms"
            )
    return "\n".join(lines)


MAX_REPEATS = 100


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.work_precision", __doc__)
    parser.add_argument("--quick", action="store_true", help="a few points per engine (CI)")
    parser.add_argument(
        "--scenes",
        nargs="+",
        choices=SCENES,
        default=list(SCENES),
        help="scenes to run, each once (default: all)",
    )
    parser.add_argument(
        "--contacts",
        nargs="+",
        choices=ours.VARIANTS,
        default=None,
        help="our contact variants to run, each once (default: every variant of the grid)",
    )
    parser.add_argument(
        "--repeats",
        type=int,
        default=None,
        help=f"identical runs per timed point, least wall time counts, 1 to {MAX_REPEATS} "
        f"(default {REPEATS['full']}, --quick {REPEATS['quick']})",
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=Path("results/bench"),
        help="output folder (writes work_precision.nc)",
    )
    parser.add_argument(
        "--figures",
        type=options.path_arg,
        default=Path("results/figures"),
        help="figure folder (writes work_precision_<scene>.png)",
    )
    return parser


def check_args(args):
    """(scenes, contacts, repeats, dataset path, {scene: figure path}), or an InputError before
    anything runs; the record of scene (c) is looked up too."""
    from benchmarks import options
    from stonedem.engine.scene import scene_from_dict

    scenes = options.chosen(args.scenes, "--scenes", SCENES)
    contacts = (
        None
        if args.contacts is None
        else options.chosen(args.contacts, "--contacts", ours.VARIANTS)
    )
    repeats = (
        REPEATS["quick" if args.quick else "full"]
        if args.repeats is None
        else options.number(
            args.repeats, "--repeats", lo=1, hi=MAX_REPEATS, whole=True, example="3"
        )
    )
    nc = (
        options.output_folder(args.out, "--out", files=("work_precision.nc",)) / "work_precision.nc"
    )
    figures = options.output_folder(
        args.figures, "--figures", files=[f"work_precision_{scene}.png" for scene in scenes]
    )
    # the record every sweep applies (scene (c) and its table for the other engines)
    scene_from_dict(
        ours.column_scene_spec(0.01, contact=ours.column_contact("point", 1e9), pga=COLUMN_PGA)
    )
    return (
        scenes,
        contacts,
        repeats,
        nc,
        {scene: figures / f"work_precision_{scene}.png" for scene in scenes},
    )


def main(argv=None) -> int:
    """Options and output paths checked first (one line, exit 2); then the sweep."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import write_dataset

        scenes, contacts, repeats, nc, figures = check_args(args)
        start = time.perf_counter()
        profile = "quick" if args.quick else "full"
        ds = run_sweep(
            QUICK if args.quick else FULL, scenes=tuple(scenes), contacts=contacts, repeats=repeats
        )
        ds.attrs["profile"] = profile
        ds.attrs["scenes_run"] = " ".join(scenes)
        write_dataset(ds, nc)
        for scene, path in figures.items():
            plot_work_precision(ds, scene, path)
        print(summary_text(ds))
        print(f"wrote {nc} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
