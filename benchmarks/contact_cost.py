"""Cost per contact per step for 1 to 990 bodies: a wall of drums (issue 6, cost per contact).

The scene is a row of free-standing multi-drum columns side by side with small gaps (a
"wall of drums") on one driven base, under a harmonic base motion strong enough to rock
them, so contacts open and close and the broad phase re-sweeps. The contact law is the
point law as the study runs it (point contacts at the face ends with Housner's plastic
landing, ``contact.model: point``, k_n = 1e10 N/m2, zeta = 0.05; the engine's default
k_n is 1e11); ``--model area`` times the
thesis' overlap-area law instead (k_n = 1e8 N/m2, c_n = 5e4 N s/m). For each size we report

* steps, mean contacts, the kernel wall time
  (:attr:`stonedem.engine.simulate.RunResult.wall_seconds`) and the wall time of the whole
  :func:`stonedem.engine.simulate.simulate` call, so the single-core fraction spent outside the
  compiled loop is 1 - kernel / total;
* ns per contact per step = 1e9 kernel / (steps x mean contacts), and ns per body per step;
* a least-squares fit of kernel time per step = a + b x contacts (slope, intercept, R^2):
  flat ns/contact/step and R^2 near 1 mean the cost grows linearly with contacts;
* the broad phase before/after, measured by compiled micro-benchmarks outside the engine:
  :func:`stonedem.kernels.broad_phase.find_candidate_pairs` (sort-and-sweep, O(N)) against sending
  every one of the n(n-1)/2 pairs through the narrow phase's AABB rejection (O(N^2)), each
  per call (= per step if it ran every step; the engine's Verlet list sweeps far less often).

    python -m benchmarks.contact_cost [--quick] [--model point|area] [--out results]

writes results/bench/contact_cost.nc and results/figures/contact_cost.png.
"""

from __future__ import annotations

import dataclasses
import math
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

from stonedem.errors import InputError

ROOT = Path(__file__).resolve().parents[1]

# free bodies: 99 columns of 10 drums and the base stay under stonedem.engine.scene.MAX_BODIES (1000
# free bodies were refused once that limit came in)
SIZES = (1, 2, 5, 10, 20, 50, 100, 200, 500, 990)
QUICK_SIZES = (1, 10, 100)
MAX_DRUMS = 10  # drums per column; larger walls add columns

# wall geometry and loading (SI units)
DRUM_WIDTH = 0.5  # [m]
COLUMN_HEIGHT = 3.0  # [m], shared by all columns; drum height = COLUMN_HEIGHT / n_drums
GAP = 0.05  # between neighbouring columns [m]
PRELOAD = 1.0e-7  # initial overlap of stacked faces [m], under the scene check's tolerance,
# so every resting contact has area > 0 and counts from step 0 (static overlap: ~1e-6 m with
# the point law at 1e10 N/m2, ~1e-4 m with the area law at 1e8 N/m2)
FRICTION = 0.5
FREQUENCY = 2.0  # [Hz] of the harmonic base motion
# the laws timed (rows of stonedem.engine.laws.LAWS; numba is imported only where a scene is
# built, so the registry is read there)
CONTACT_MODELS = ("point", "area")
# contact law timed by default (the scene default is stonedem.engine.laws.DEFAULT_LAW)
MODEL = "point"
# point law: the study's; the plastic landing keeps every resting contact closed
# normal stiffness per unit contact length [N m-2] (the study's, not the default 1e11)
K_N_POINT = 1.0e10
ZETA = 0.05  # damping ratio of each contact point [1]
# area law: stiffness per unit overlap area [N m-2] and a dashpot [N s m-1] of ~0.2 of
# critical for a drum, so the drums settle without bouncing off each other at the start
K_N_AREA = 1.0e8
C_N = 5.0e4
K_N = {"point": K_N_POINT, "area": K_N_AREA}
WIDTH_SPREAD = 0.1  # column widths vary by up to this fraction, so columns rock out of step
PGA = 5.0  # [m s-2]: > g tan(alpha) = 1.64 m/s2, so the columns rock; ~ mu g, so bases slip
DURATION = 1.0  # simulated time of each timed run [s]: rocking from rest and first impacts
TARGET_SECONDS = 1.0  # kernel wall time aimed at per size (short runs are repeated) [s]
WARM_DURATION = 0.01  # simulated time of the warm run [s]
N_SAMPLES = 100  # output samples per timed run (mean contacts is their mean)


def drum_wall_size(n_body: int, max_drums: int = MAX_DRUMS) -> tuple[int, int]:
    """(n_columns, n_drums) with n_columns x n_drums = n_body free bodies, columns <= max_drums
    high."""
    if n_body < 1:
        raise ValueError("n_body must be >= 1")
    n_drums = min(n_body, max_drums)
    while n_body % n_drums:
        n_drums -= 1
    return n_body // n_drums, n_drums


def drum_wall_scene(
    n_columns: int,
    n_drums: int,
    *,
    drum_width: float = DRUM_WIDTH,
    column_height: float = COLUMN_HEIGHT,
    gap: float = GAP,
    preload: float = PRELOAD,
    width_spread: float = WIDTH_SPREAD,
    model: str = MODEL,
    k_n: float | None = None,
    damping: float = ZETA,
    c_n: float = C_N,
    frequency: float = FREQUENCY,
    pga: float = PGA,
    friction: float = FRICTION,
    duration: float = 0.1,
    every: float | None = None,
    stop_on_collapse: bool = False,
) -> dict:
    """Scene dict (for :func:`stonedem.engine.scene.scene_from_dict`) of a wall of drum columns on a
    driven base.

    n_columns columns of n_drums drums each (drum_width x column_height / n_drums [m]) stand
    side by side, ``gap`` [m] apart, on one driven base (top at y = 0) that moves as a
    harmonic displacement of ``frequency`` [Hz] and peak acceleration ``pga`` [m s-2],
    switched on abruptly (ramp_cycles 0) so the columns start rocking at once. One column of
    one drum is a single block. Stacked faces overlap by ``preload`` [m] at t = 0, so every
    resting contact counts from the first step. Column c is narrower by a fraction
    width_spread x ((3 c) mod 5) / 4 (centres stay drum_width + gap apart), so neighbours have
    different slenderness, rock out of step and knock into each other. The contact is
    ``model`` point (k_n, zeta = damping, plastic landing) or area (k_n, c_n); k_n defaults
    to K_N[model].
    """
    if model not in CONTACT_MODELS:
        raise ValueError(f"unknown contact model {model!r}; use one of {CONTACT_MODELS}")
    from stonedem.engine.laws import LAWS

    k_n = K_N[model] if k_n is None else float(k_n)
    contact = LAWS[model].mapping(
        model,
        k_n,
        damping if LAWS[model].damping_key == "damping" else c_n,
        **({"impact": "plastic"} if "impact" in LAWS[model].defaults else {}),
    )
    drum_height = column_height / n_drums
    pitch = drum_width + gap
    span = n_columns * pitch - gap
    bodies = [
        {
            "name": "base",
            "driven": True,
            "role": "base",
            "box": {"width": span + 4.0 * column_height, "height": 0.5, "center": [0.0, -0.25]},
        }
    ]
    x0 = -0.5 * span + 0.5 * drum_width
    for c in range(n_columns):
        width = drum_width * (1.0 - width_spread * ((3 * c) % 5) / 4.0)
        for d in range(n_drums):
            bodies.append(
                {
                    "name": f"c{c}_d{d}",
                    "role": "drum" if n_drums > 1 else "block",
                    "column": c,
                    "box": {
                        "width": width,
                        "height": drum_height,
                        "center": [x0 + c * pitch, (d + 0.5) * drum_height - (d + 1) * preload],
                    },
                }
            )
    return {
        "name": f"drum_wall_{n_columns}x{n_drums}",
        "bodies": bodies,
        "friction": friction,
        "contact": contact,
        "excitation": {"kind": "harmonic", "frequency": frequency, "pga": pga, "ramp_cycles": 0},
        "solver": {"duration": duration, "dt": "auto", "stop_on_collapse": stop_on_collapse},
        "output": {"every": every if every is not None else duration / N_SAMPLES},
    }


def drum_wall(n_body: int, **kwargs):
    """Validated :class:`stonedem.engine.scene.Scene` of a drum wall with n_body free bodies."""
    from stonedem.engine.scene import scene_from_dict

    return scene_from_dict(drum_wall_scene(*drum_wall_size(n_body), **kwargs))


# ---------------------------------------------------------------- broad phase micro-benchmarks


def _compiled():
    """The njit micro-benchmark kernels (compiled lazily, on first use)."""
    global _KERNELS
    if _KERNELS is not None:
        return _KERNELS
    from numba import njit

    from stonedem.kernels.broad_phase import find_candidate_pairs

    @njit(cache=True, fastmath=False)
    def all_pairs_aabb(n_body, body_driven, lo_x, lo_y, hi_x, hi_y):
        """Every pair (a < b) through the narrow phase's AABB rejection; returns (tested,
        overlapping)."""
        tested = 0
        hits = 0
        for a in range(n_body):
            for b in range(a + 1, n_body):
                if body_driven[a] and body_driven[b]:
                    continue
                tested += 1
                if lo_x[a] > hi_x[b] or lo_x[b] > hi_x[a] or lo_y[a] > hi_y[b] or lo_y[b] > hi_y[a]:
                    continue
                hits += 1
        return tested, hits

    @njit(cache=True, fastmath=False)
    def repeat_all_pairs(n_rep, n_body, body_driven, lo_x, lo_y, hi_x, hi_y):
        tested = 0
        hits = 0
        for r in range(n_rep):
            # perturb a bound by nothing the compiler can see through, so no call is hoisted
            lo_x[r % n_body] += 0.0 * r
            tested, hits = all_pairs_aabb(n_body, body_driven, lo_x, lo_y, hi_x, hi_y)
        return tested, hits

    @njit(cache=True, fastmath=False)
    def repeat_sweep(n_rep, n_body, body_driven, lo_x, lo_y, hi_x, hi_y, margin, sweep_axis):
        n_pair = 0
        for r in range(n_rep):
            lo_x[r % n_body] += 0.0 * r
            pa, pb = find_candidate_pairs(
                n_body, body_driven, lo_x, lo_y, hi_x, hi_y, margin, sweep_axis
            )
            n_pair = pa.shape[0]
        return n_pair

    _KERNELS = (all_pairs_aabb, repeat_all_pairs, repeat_sweep)
    return _KERNELS


_KERNELS = None


def rest_bounds(scene):
    """(arrays, lo_x, lo_y, hi_x, hi_y) of the bodies at t = 0 (packed scene, AABBs [m])."""
    from stonedem.engine.pack import pack_scene
    from stonedem.engine.scene import posed_vertices

    arrays = pack_scene(scene)
    posed = [posed_vertices(b) for b in scene.bodies]
    lo = np.array([p.min(axis=0) for p in posed])
    hi = np.array([p.max(axis=0) for p in posed])
    return arrays, lo[:, 0].copy(), lo[:, 1].copy(), hi[:, 0].copy(), hi[:, 1].copy()


def candidate_pairs_at_rest(scene) -> int:
    """Number of candidate pairs the engine's broad phase finds for the scene at t = 0."""
    from stonedem.kernels.broad_phase import find_candidate_pairs

    a, lo_x, lo_y, hi_x, hi_y = rest_bounds(scene)
    pa, _ = find_candidate_pairs(
        len(scene.bodies), a.body_driven, lo_x, lo_y, hi_x, hi_y, a.margin, a.sweep_axis
    )
    return int(pa.shape[0])


def _time_reps(call, min_seconds: float) -> tuple[float, int]:
    """Seconds per call, repeating (doubling) until a batch takes min_seconds; returns (s, reps)."""
    call(1)
    reps = 1
    while True:
        start = time.perf_counter()
        call(reps)
        elapsed = time.perf_counter() - start
        if elapsed >= min_seconds or reps >= 1 << 24:
            return elapsed / reps, reps
        reps *= 2 if elapsed <= 0 else max(2, min(16, int(1.2 * min_seconds / elapsed) + 1))


def broad_phase_cost(scene, min_seconds: float = 0.2) -> dict:
    """Per-call cost of the broad phase at rest: sort-and-sweep vs all pairs through the AABB test.

    Returns sweep_seconds, sweep_pairs (candidates found), all_pairs_seconds,
    all_pairs_tested (n(n-1)/2 less driven-driven pairs) and all_pairs_overlapping.
    """
    all_pairs_aabb, repeat_all_pairs, repeat_sweep = _compiled()
    a, lo_x, lo_y, hi_x, hi_y = rest_bounds(scene)
    n = len(scene.bodies)
    drv = a.body_driven
    t_sweep, _ = _time_reps(
        lambda r: repeat_sweep(r, n, drv, lo_x, lo_y, hi_x, hi_y, a.margin, a.sweep_axis),
        min_seconds,
    )
    t_all, _ = _time_reps(
        lambda r: repeat_all_pairs(r, n, drv, lo_x, lo_y, hi_x, hi_y), min_seconds
    )
    tested, hits = all_pairs_aabb(n, drv, lo_x, lo_y, hi_x, hi_y)
    return {
        "sweep_seconds": t_sweep,
        "sweep_pairs": candidate_pairs_at_rest(scene),
        "all_pairs_seconds": t_all,
        "all_pairs_tested": int(tested),
        "all_pairs_overlapping": int(hits),
    }


# ---------------------------------------------------------------- engine timing


def _peak_rss_mb() -> float:
    """Peak resident set size of this process so far [MB] (Linux reports kB, macOS bytes)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 1024.0 if sys.platform != "darwin" else peak / 2**20


def with_duration(scene, duration: float, n_samples: int = N_SAMPLES, dt: float | None = None):
    """The scene with another simulated duration [s] and ~n_samples output samples.

    dt: the automatic step [s] if known; samples are then at least 20 steps apart, so the
    rounding of dt to divide the output interval changes it by < 5 %.
    """
    every = float(duration) / n_samples
    if dt is not None:
        every = max(every, 20.0 * dt)
    changes = {"duration": float(duration), "output_every": every}
    if any(f.name == "skip_quiet" for f in dataclasses.fields(scene)):
        changes["skip_quiet"] = False  # integrate every step: a benchmark of the loop
    return dataclasses.replace(scene, **changes)


def warm_up(model: str = MODEL) -> None:
    """Compile (or load from the numba cache) the engine's loop once in this process."""
    from stonedem.engine.simulate import simulate

    simulate(with_duration(drum_wall(1, model=model), 1e-3, 2))


def measure(
    scene,
    duration: float | None = None,
    *,
    target_seconds: float = TARGET_SECONDS,
    warm_duration: float = WARM_DURATION,
    max_repeats: int = 200,
) -> dict:
    """Time one scene: a short warm run, then timed runs of ``duration`` simulated seconds.

    duration: simulated time [s] of each timed run (default DURATION, the same for every
    size so every size is timed over the same motion: rocking from rest, columns knocking
    into their neighbours). When one run's kernel takes less than ``target_seconds``, the
    run is repeated (identically: the engine is deterministic) until the kernel time adds
    up to about target_seconds, at most max_repeats times; times and steps are summed.
    The first simulate call of a process compiles (or loads the cache); the warm run takes it.

    Returns a dict: steps, repeats, dt [s], duration [s], mean/min/max contacts,
    kernel_seconds (sum of RunResult.wall_seconds), total_seconds (sum of the whole simulate
    calls, including set-up: stability limit, packing, allocation), setup_seconds
    (choose_time_step + pack_scene once, timed separately), outside_fraction = 1 - kernel /
    total, ns_per_contact_step, ns_per_body_step, kernel_per_step [s], status, the largest
    rotation, and memory (engine per-pair arrays, peak RSS of the process).
    """
    from stonedem.engine.pack import pack_scene
    from stonedem.engine.simulate import choose_time_step, simulate
    from stonedem.kernels.contact import N_MEMORY

    duration = DURATION if duration is None else float(duration)
    n_body = len(scene.bodies)
    free = np.array([not b.driven for b in scene.bodies])
    warm = simulate(with_duration(scene, min(warm_duration, duration), 4))
    dt_auto = scene.dt if scene.dt is not None else scene.dt_safety * warm.dt_limit
    timed_scene = with_duration(scene, duration, dt=dt_auto)
    kernel = total = 0.0
    steps = repeats = 0
    while True:
        start = time.perf_counter()
        result = simulate(timed_scene)
        total += time.perf_counter() - start
        kernel += float(result.wall_seconds)
        steps += max(int(result.steps_run), 1)
        repeats += 1
        if kernel >= target_seconds or repeats >= max_repeats:
            break
        if repeats == 1:  # plan the rest from the first run
            max_repeats = min(max_repeats, int(math.ceil(target_seconds / max(kernel, 1e-9))))
            if repeats >= max_repeats:
                break
    start = time.perf_counter()
    choose_time_step(timed_scene)
    pack_scene(timed_scene)
    setup = time.perf_counter() - start
    # mean over the integrated samples only (a skipped quiet lead or rest tail counts none)
    lead = float(getattr(result, "quiet_lead", 0.0) or 0.0)
    rest = float(getattr(result, "rest_time", math.nan))
    integrated = (result.time >= lead) & ~(result.time > rest)
    n_contact = result.n_contact[integrated] if integrated.any() else result.n_contact
    contacts = float(np.mean(n_contact))
    return {
        "n_body_total": n_body,
        "n_free": int(free.sum()),
        "dt": float(result.dt),
        "duration": duration,
        "steps": steps,
        "repeats": repeats,
        "status": int(result.status),
        "mean_contacts": contacts,
        "min_contacts": float(np.min(n_contact)),
        "max_contacts": float(np.max(n_contact)),
        "kernel_seconds": kernel,
        "total_seconds": total,
        "setup_seconds": float(setup),
        "outside_fraction": 1.0 - kernel / total,
        "kernel_per_step": kernel / steps,
        "ns_per_contact_step": 1e9 * kernel / (steps * max(contacts, 1e-12)),
        "ns_per_body_step": 1e9 * kernel / (steps * n_body),
        "max_abs_theta": float(np.nanmax(np.abs(result.theta[:, free]))),
        "pair_array_mb": n_body * n_body * (N_MEMORY + 2) * 8 / 2**20,
        "peak_rss_mb": _peak_rss_mb(),
    }


def linear_fit(x, y, relative: bool = False) -> dict:
    """Least squares y = a + b x; returns intercept a, slope b, R^2 and the largest relative
    residual.

    relative: minimise the relative residuals (y - a - b x) / y instead of the absolute ones,
    so sizes spanning three decades weigh alike. R^2 is 1 - SS_res / SS_tot of the plain data.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    w = 1.0 / np.abs(y) if relative else np.ones_like(y)
    design = np.column_stack([w, w * x])
    (a, b), *_ = np.linalg.lstsq(design, w * y, rcond=None)
    resid = y - (a + b * x)
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(resid**2)) / ss_tot if ss_tot > 0 else float("nan")
    return {
        "intercept": float(a),
        "slope": float(b),
        "r2": r2,
        "max_relative_residual": float(np.max(np.abs(resid / y))),
    }


# ---------------------------------------------------------------- the benchmark

VARIABLES = {
    # name: (units, long_name)
    "n_columns": ("1", "columns in the wall"),
    "n_drums": ("1", "drums per column"),
    "n_body_total": ("1", "bodies including the driven base"),
    "dt": ("s", "time step"),
    "duration": ("s", "simulated time of one timed run"),
    "steps": ("1", "steps run in the timed runs (all repeats)"),
    "repeats": ("1", "identical timed runs summed"),
    "status": ("1", "run status (0 ok, 1 collapsed and stopped, 2 non-finite)"),
    "mean_contacts": ("1", "mean number of contacts over the samples"),
    "min_contacts": ("1", "fewest contacts in a sample"),
    "max_contacts": ("1", "most contacts in a sample"),
    "kernel_seconds": ("s", "wall time of the compiled loop (RunResult.wall_seconds), one core"),
    "total_seconds": ("s", "wall time of the whole simulate call, including set-up"),
    "build_seconds": (
        "s",
        "wall time of scene_from_dict (validation incl. the initial-overlap check), not in total",
    ),
    "setup_seconds": ("s", "wall time of choose_time_step + pack_scene (Python set-up)"),
    "outside_fraction": (
        "1",
        "fraction of the simulate call spent outside the compiled loop, 1 - kernel / total",
    ),
    "kernel_per_step": ("s", "kernel wall time per step"),
    "ns_per_contact_step": ("ns", "kernel time per contact per step"),
    "ns_per_body_step": ("ns", "kernel time per body per step"),
    "fit_per_step": ("s", "fitted kernel time per step, intercept + slope x mean contacts"),
    "max_abs_theta": ("rad", "largest absolute rotation of a free body in the timed run"),
    "pair_array_mb": (
        "1048576 byte",
        "engine per-pair arrays (pair_memory, pair_ft, pair_mu), n_body^2 x (N_MEMORY + 2) x 8 "
        "bytes",
    ),
    "peak_rss_mb": ("1048576 byte", "peak resident memory of the process after the run"),
    "sweep_pairs": ("1", "candidate pairs from sort-and-sweep at rest"),
    "all_pairs_tested": (
        "1",
        "pairs an all-pairs broad phase sends to the AABB test, n(n-1)/2 less driven-driven",
    ),
    "all_pairs_overlapping": ("1", "pairs whose bare AABBs overlap at rest"),
    "sweep_seconds": ("s", "sort-and-sweep broad phase (find_candidate_pairs) per call"),
    "all_pairs_seconds": ("s", "all pairs through the narrow phase's AABB rejection per call"),
}


def run_benchmark(
    sizes=SIZES,
    duration: float | None = None,
    target_seconds: float = TARGET_SECONDS,
    broad_min_seconds: float = 0.2,
    progress: bool = True,
    model: str = MODEL,
):
    """Measure every size with the ``model`` contact law; returns an xarray Dataset on dim n_body
    (free bodies)."""
    import xarray as xr

    from stonedem.io.netcdf import code_version

    log = (lambda msg: print(msg, file=sys.stderr, flush=True)) if progress else (lambda msg: None)
    start = time.perf_counter()
    log("compiling / loading the engine ...")
    warm_up(model)
    rows = []
    for n in sizes:
        n_columns, n_drums = drum_wall_size(n)
        t0 = time.perf_counter()
        scene = drum_wall(n, model=model)
        build = time.perf_counter() - t0
        row = {"n_columns": n_columns, "n_drums": n_drums, "build_seconds": build}
        row.update(measure(scene, duration, target_seconds=target_seconds))
        row.update(broad_phase_cost(scene, broad_min_seconds))
        rows.append(row)
        log(
            f"  n_body {n:5d} ({n_columns} x {n_drums}): build {build:6.2f} s, "
            f"{row['repeats']} x {row['steps'] // row['repeats']} steps, "
            f"{row['mean_contacts']:.0f} contacts, kernel {row['kernel_seconds']:.2f} s of "
            f"{row['total_seconds']:.2f} s, {row['ns_per_contact_step']:.0f} ns/contact/step  "
            f"[{time.perf_counter() - start:.0f} s]"
        )
    xs = [r["mean_contacts"] for r in rows]
    ys = [r["kernel_per_step"] for r in rows]
    fit = linear_fit(xs, ys, relative=True)
    plain = linear_fit(xs, ys)
    for r in rows:
        r["fit_per_step"] = fit["intercept"] + fit["slope"] * r["mean_contacts"]
    sweep_fit = linear_fit([r["n_body_total"] for r in rows], [r["sweep_seconds"] for r in rows])
    ns_contact = np.array([r["ns_per_contact_step"] for r in rows])
    big = np.array(sizes) >= 10
    data = {
        k: ("n_body", np.array([r[k] for r in rows]), {"units": u, "long_name": ln})
        for k, (u, ln) in VARIABLES.items()
    }
    params = {
        "drum_width": (DRUM_WIDTH, "m", "drum width"),
        "column_height": (
            COLUMN_HEIGHT,
            "m",
            "column height (drum height = column height / drums)",
        ),
        "gap": (GAP, "m", "gap between neighbouring columns (widest columns)"),
        "width_spread": (WIDTH_SPREAD, "1", "largest fractional narrowing of a column"),
        **(
            {
                "k_n": (
                    K_N_POINT,
                    "N m-2",
                    "normal contact stiffness per unit contact length (point law)",
                ),
                "zeta": (ZETA, "1", "damping ratio of each contact point (point law)"),
            }
            if model == "point"
            else {
                "k_n": (
                    K_N_AREA,
                    "N m-2",
                    "normal contact stiffness per unit overlap area (area law)",
                ),
                "c_n": (C_N, "N s m-1", "normal contact dashpot (area law)"),
            }
        ),
        "friction": (FRICTION, "1", "friction coefficient"),
        "frequency": (FREQUENCY, "Hz", "frequency of the harmonic base motion"),
        "pga": (PGA, "m s-2", "peak base acceleration"),
    }
    coords = {"n_body": ("n_body", np.array(sizes), {"units": "1", "long_name": "free bodies"})}
    coords.update({k: ((), v, {"units": u, "long_name": ln}) for k, (v, u, ln) in params.items()})
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "title": "stonedem cost per contact per step: walls of drums, 1 to 990 bodies",
            "contact_model": model,
            "contact_law": (
                "point contacts at the contact face's end vertices, Housner's plastic landing"
                if model == "point"
                else "overlap area, thesis Eq. 3.4-3.6"
            ),
            "source": code_version(),
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
            "numba_num_threads": os.environ.get("NUMBA_NUM_THREADS", "unset"),
            "fit": "kernel time per step [s] = intercept + slope x mean contacts (least squares on "
            "relative residuals, so every size weighs alike)",
            "fit_max_relative_residual": fit["max_relative_residual"],
            "plain_fit_intercept_s": plain["intercept"],
            "plain_fit_slope_ns_per_contact": 1e9 * plain["slope"],
            "plain_fit_r2": plain["r2"],
            "fit_intercept_s": fit["intercept"],
            "fit_slope_s_per_contact": fit["slope"],
            "fit_slope_ns_per_contact": 1e9 * fit["slope"],
            "fit_r2": fit["r2"],
            "sweep_fit_slope_ns_per_body": 1e9 * sweep_fit["slope"],
            "sweep_fit_r2": sweep_fit["r2"],
            "ns_per_contact_step_spread_n_ge_10": (
                float(ns_contact[big].max() / ns_contact[big].min())
                if big.sum() > 1
                else float("nan")
            ),
            "target_kernel_seconds": target_seconds,
            "description": __doc__.split("\n\n")[0],
        },
    )
    return ds


def print_table(ds, file=sys.stdout) -> None:
    head = (
        f"{'bodies':>6} {'cols x drums':>12} {'steps':>7} {'contacts':>8} {'kernel s':>8} "
        f"{'total s':>8} {'outside':>7} {'ns/c/step':>9} {'ns/b/step':>9} {'pairs':>6} "
        f"{'sweep us':>9} {'allpairs us':>11} {'pair MiB':>8}"
    )
    print(head, file=file)
    for i, n in enumerate(ds.n_body.values):
        v = {k: ds[k].values[i] for k in ds.data_vars}
        print(
            f"{n:6d} {int(v['n_columns']):5d} x {int(v['n_drums']):4d} {int(v['steps']):7d} "
            f"{v['mean_contacts']:8.1f} {v['kernel_seconds']:8.3f} {v['total_seconds']:8.3f} "
            f"{100 * v['outside_fraction']:6.1f}% {v['ns_per_contact_step']:9.1f} "
            f"{v['ns_per_body_step']:9.1f} {int(v['sweep_pairs']):6d} "
            f"{1e6 * v['sweep_seconds']:9.2f} "
            f"{1e6 * v['all_pairs_seconds']:11.2f} {v['pair_array_mb']:8.1f}",
            file=file,
        )
    a = ds.attrs
    print(
        f"fit (relative residuals): kernel per step = {1e9 * a['fit_intercept_s']:.0f} ns + "
        f"{a['fit_slope_ns_per_contact']:.1f} ns x contacts  (R^2 = {a['fit_r2']:.4f}, worst point "
        f"{100 * a['fit_max_relative_residual']:.0f} % off)",
        file=file,
    )
    print(
        f"fit (absolute residuals): {1e9 * a['plain_fit_intercept_s']:.0f} ns + "
        f"{a['plain_fit_slope_ns_per_contact']:.1f} ns x contacts  (R^2 = {a['plain_fit_r2']:.4f})",
        file=file,
    )
    print(
        f"contact law: {a.get('contact_model', 'area')}; "
        f"sort-and-sweep: {a['sweep_fit_slope_ns_per_body']:.1f} ns per body (R^2 = "
        f"{a['sweep_fit_r2']:.4f}); "
        f"{a['machine']}, NUMBA_NUM_THREADS={a['numba_num_threads']}, {a['source']}",
        file=file,
    )


def plot(ds, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from stonedem.io.atomic import write_atomically

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    c = ds.mean_contacts.values
    per_step = ds.kernel_per_step.values
    ax = axes[0]
    ax.loglog(c, per_step, "o", label="measured")
    cc = np.geomspace(max(c.min(), 1e-3), c.max(), 100)
    line = ds.attrs["fit_intercept_s"] + ds.attrs["fit_slope_s_per_contact"] * cc
    ax.loglog(
        cc[line > 0],
        line[line > 0],
        "-",
        label=f"a + b x contacts, b = {ds.attrs['fit_slope_ns_per_contact']:.0f} ns, "
        f"R$^2$ = {ds.attrs['fit_r2']:.4f}",
    )
    ax.set_xlabel("mean contacts")
    ax.set_ylabel("kernel time per step [s]")
    ax.set_title("cost grows linearly with contacts")
    ax.legend(fontsize=8)
    ax = axes[1]
    n = ds.n_body.values
    ax.semilogx(n, ds.ns_per_contact_step.values, "o-", label="per contact")
    ax.semilogx(n, ds.ns_per_body_step.values, "s--", label="per body")
    ax.set_ylim(0, None)
    ax.set_xlabel("free bodies")
    ax.set_ylabel("kernel ns per step")
    ax.set_title("ns per contact per step (flat = linear)")
    ax.legend(fontsize=8)
    ax = axes[2]
    ax.loglog(n, ds.all_pairs_seconds.values, "o-", label="all n(n-1)/2 pairs, AABB test")
    ax.loglog(n, ds.sweep_seconds.values, "s-", label="sort-and-sweep (find_candidate_pairs)")
    ref = ds.all_pairs_seconds.values[-1] * (n / n[-1]) ** 2
    ax.loglog(n, ref, ":", color="grey", label="~ n$^2$")
    ax.set_xlabel("free bodies")
    ax.set_ylabel("broad phase per call [s]")
    ax.set_title("broad phase: all pairs vs sweep")
    ax.legend(fontsize=8)
    fig.suptitle(
        f"{ds.attrs['source']}, {ds.attrs['machine']}, "
        f"NUMBA_NUM_THREADS={ds.attrs['numba_num_threads']}",
        fontsize=8,
    )
    fig.tight_layout()
    write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    plt.close(fig)
    return path


MAX_SIZES = 30  # sizes in one run
DURATION_RANGE = (0.0, 60.0)  # [s] simulated per timed run, lower end excluded
TARGET_RANGE = (0.0, 600.0)  # [s] kernel wall time per size, lower end excluded


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.contact_cost", __doc__)
    parser.add_argument(
        "--quick", action="store_true", help="sizes 1, 10, 100 and a tiny duration (CI)"
    )
    parser.add_argument(
        "--sizes",
        type=int,
        nargs="+",
        help=f"free bodies per scene, 1 to 999, each once, at most {MAX_SIZES} sizes "
        "(default 1 ... 990)",
    )
    parser.add_argument(
        "--duration",
        type=float,
        help=f"simulated seconds per timed run, > 0 and <= {DURATION_RANGE[1]:g} (default "
        f"{DURATION})",
    )
    parser.add_argument(
        "--target",
        type=float,
        help=f"kernel wall seconds aimed at per size, "
        f"repeating short runs, > 0 and <= {TARGET_RANGE[1]:g} (default {TARGET_SECONDS})",
    )
    parser.add_argument(
        "--model", choices=CONTACT_MODELS, default=MODEL, help=f"contact law (default {MODEL})"
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=ROOT / "results",
        help="results folder: writes OUT/bench/contact_cost.nc and OUT/figures/contact_cost.png",
    )
    return parser


def check_args(args):
    """(sizes, duration [s], target [s], nc path, png path), or an InputError before anything
    runs."""
    from benchmarks import options
    from stonedem.engine.scene import MAX_BODIES

    if args.sizes is not None:
        if not 1 <= len(args.sizes) <= MAX_SIZES:
            raise InputError("--sizes", f"{len(args.sizes)} sizes", f"give 1 to {MAX_SIZES} sizes")
        for n in args.sizes:
            options.number(
                n,
                "--sizes",
                lo=1,
                hi=MAX_BODIES - 1,
                whole=True,
                unit="free bodies (the base is one more)",
            )
        if len(set(args.sizes)) != len(args.sizes):
            raise InputError("--sizes", "a size is given twice", "give each size once")
    sizes = tuple(args.sizes or (QUICK_SIZES if args.quick else SIZES))
    duration = (
        (0.05 if args.quick else DURATION)
        if args.duration is None
        else options.number(
            args.duration,
            "--duration",
            lo=DURATION_RANGE[0],
            lo_open=True,
            hi=DURATION_RANGE[1],
            unit="s",
            example="1",
        )
    )
    target = (
        (0.05 if args.quick else TARGET_SECONDS)
        if args.target is None
        else options.number(
            args.target,
            "--target",
            lo=TARGET_RANGE[0],
            lo_open=True,
            hi=TARGET_RANGE[1],
            unit="s",
            example="1",
        )
    )
    out = options.output_folder(
        args.out, "--out", files=("bench/contact_cost.nc", "figures/contact_cost.png")
    )
    return (
        sizes,
        duration,
        target,
        out / "bench" / "contact_cost.nc",
        out / "figures" / "contact_cost.png",
    )


def main(argv=None) -> int:
    """Options and output paths checked first (one line, exit 2); then the benchmark."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        sizes, duration, target, nc_path, png_path = check_args(args)
        ds = run_benchmark(
            sizes,
            duration=duration,
            target_seconds=target,
            broad_min_seconds=0.02 if args.quick else 0.2,
            model=args.model,
        )
        from stonedem.io.netcdf import write_dataset

        nc = write_dataset(ds, nc_path)
        png = plot(ds, png_path)
        print_table(ds)
        print(f"wrote {nc}\nwrote {png}")
        return 0

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
