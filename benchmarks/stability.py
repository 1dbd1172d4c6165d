"""Numerical stability of the engine: dt x stiffness x damping x geometry (DESIGN §6).

:func:`stability_map` runs short simulations of a few scene kinds at dt = ratio x
:func:`stonedem.engine.simulate.stability_limit`, from well inside the limit to past it, and records
whether each run stays stable: finite, and the energy balance (kinetic + potential +
elastic + dissipated - base work) drifting by less than :data:`ENERGY_TOLERANCE` of the
scene's initial energy. :func:`auto_dt_margin` measures, for one scene of every study in
``config/config.yaml``, how far the automatic step sits below the step where runs go
unstable. ``python -m benchmarks.stability`` writes both to ``results/bench/`` and draws
``results/figures/stability_map.png``.

The contact law is the point law, point contacts at the face ends with Housner's plastic
landing (``contact.model: point``, ``impact: plastic``), whose damping is the damping ratio zeta of
each contact point, so the map's damping levels are zeta itself. ``model="area"`` (``--model
area``) maps the thesis' overlap-area law instead, with c_n = damping x critical
(:func:`critical_damping`).

The normal path (:func:`stonedem.engine.simulate.choose_time_step`) refuses dt > limit, so probes
past the limit ask for it as an "automatic" step of ``dt_safety = ratio`` on a copy of the
scene (scene validation, which caps dt_safety at 1, is not rerun on a copy); the sample
interval is a whole number of steps, so simulate's rounding keeps dt exactly.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import sys
import time as wallclock
from pathlib import Path

import numpy as np
import xarray as xr

from benchmarks.ours import critical_damping as critical_damping_of
from stonedem.engine.laws import LAWS
from stonedem.engine.scene import Scene, box_pairs, scene_from_dict
from stonedem.engine.simulate import RunResult, choose_time_step, simulate, stability_limit
from stonedem.io.netcdf import code_version, write_dataset
from stonedem.kernels import step
from stonedem.kernels.overlap import MAX_OVERLAP_VERTICES, clip_convex_polygons
from stonedem.validation.cases import block_scene

ROOT = Path(__file__).resolve().parents[1]
K_N_VALUES = (1e7, 1e8, 1e9, 1e10)  # [N m-2]
DT_RATIOS = (0.1, 0.25, 0.5, 0.75, 0.9, 1.0, 1.1, 1.25, 1.5, 2.0)  # dt / stability limit
# point law: zeta of each contact point; area law: c_n / (2 sqrt(k_n width m)) of the lightest free
# body
DAMPING_FRACTIONS = (0.0, 0.05, 0.5)
CONTACT_MODELS = tuple(LAWS)
SCENE_KINDS = ("block", "column", "colonnade")
DURATION = 0.5  # [s] of each run of the map
SAMPLE_EVERY = 1e-3  # [s] between samples (energy and overlap are checked on samples)
# Stable = finite and |energy balance drift| < this share of the energy the run moves
# (:func:`energy_drift`). Measured on the default map with the area law: every run at
# dt <= limit stays below 6.1e-3 (error ~ dt^2: ~1e-4 at 0.25 x limit); runs that go
# unstable jump to 2e-2 ... 9.
from stonedem.engine.simulate import ENERGY_FLOOR, ENERGY_TOLERANCE, energy_drift  # noqa: E402  (shared with every run)

HARMONIC = {"kind": "harmonic", "frequency": 2.0, "amplitude": 0.1}  # PGA 15.8 m s-2


def contact_spec(model: str, k_n: float, damping: float = 0.0) -> dict:
    """``contact:`` mapping of the map: point law with zeta = damping [1] (plastic landing,
    its scene default) or area law with c_n = c_t = damping [N s m-1]."""
    if model in LAWS:
        return LAWS[model].mapping(model, k_n, damping)
    raise ValueError(f"unknown contact model {model!r}; use one of {CONTACT_MODELS}")


def scene_spec(
    kind: str, k_n: float, damping: float = 0.0, duration: float = DURATION, model: str = "point"
) -> dict:
    """Scene mapping of one map scene kind (block, column, colonnade); damping as in
    :func:`contact_spec`."""
    contact = contact_spec(model, k_n, damping)
    solver = {"duration": duration, "stop_on_collapse": False}
    if kind == "block":
        # free rocking of a 0.25 x 1 m block released at half its slenderness angle
        spec = block_scene(
            0.25,
            1.0,
            tilt=0.5 * math.atan(0.25 / 1.0),
            contact=contact,
            duration=duration,
            every=SAMPLE_EVERY,
        )
        spec["solver"]["stop_on_collapse"] = False
        return spec
    if kind == "column":
        structure = {"kind": "column", "n_drums": 8, "height": 6.0, "width": 1.0}
    elif kind == "colonnade":
        structure = {
            "kind": "colonnade",
            "n_columns": 3,
            "n_drums": 2,
            "height": 6.0,
            "width": 1.0,
            "clear_distance": 2.0,
            "epistyle_type": "a",
        }
    else:
        raise ValueError(f"unknown scene kind {kind!r}; use one of {SCENE_KINDS}")
    return {
        "structure": structure,
        "friction": 0.5,
        "contact": contact,
        "excitation": dict(HARMONIC),
        "solver": solver,
        "output": {"every": SAMPLE_EVERY},
    }


def critical_damping(scene: Scene) -> float:
    """2 sqrt(k_n width m) [N s m-1] of the lightest free body (width: its horizontal extent)."""
    free = [b for b in scene.bodies if not b.driven]
    body = min(free, key=lambda b: b.mass)
    return critical_damping_of(scene.contact.k_n, float(np.ptp(body.vertices[:, 0])), body.mass)


def map_scene(
    kind: str, k_n: float, damping: float, duration: float = DURATION, model: str = "point"
) -> Scene:
    """Scene of the map: point law with zeta = ``damping``, or area law with c_n (and c_t) at
    ``damping`` x critical."""
    if model == "point":
        return scene_from_dict(scene_spec(kind, k_n, damping, duration, model))
    undamped = scene_from_dict(scene_spec(kind, k_n, 0.0, duration, model))
    return scene_from_dict(
        scene_spec(kind, k_n, damping * critical_damping(undamped), duration, model)
    )


def damping_long_name(model: str) -> str:
    """What the map's damping coordinate means for a contact model."""
    if model == "point":
        return "damping ratio zeta of each contact point (point law), fraction of critical"
    return "c_n / critical 2 sqrt(k_n width m) of the lightest free body (area law)"


def run_at_ratio(scene: Scene, ratio: float, sample_every: float = SAMPLE_EVERY) -> RunResult:
    """Simulate ``scene`` at dt = ratio x stability limit, past the limit too (see module doc)."""
    dt = ratio * stability_limit(scene)
    every = max(1, round(sample_every / dt)) * dt
    probe = dataclasses.replace(
        scene, dt=None, dt_safety=ratio, output_every=every, stop_on_collapse=False
    )
    return simulate(probe)


def min_width(x: np.ndarray, y: np.ndarray) -> float:
    """Smallest width of a convex polygon [m]: its thickness, i.e. the depth of an overlap
    sliver."""
    ex, ey = np.roll(x, -1) - x, np.roll(y, -1) - y
    length = np.hypot(ex, ey)
    keep = length > 1e-12
    if not keep.any():
        return 0.0
    nx, ny = -ey[keep] / length[keep], ex[keep] / length[keep]
    proj = np.outer(x, nx) + np.outer(y, ny)
    return float((proj.max(axis=0) - proj.min(axis=0)).min())


def overlap_depths(scene: Scene, result: RunResult) -> np.ndarray:
    """Deepest overlap between any two bodies at each sample (n_sample,) [m]."""
    local = [b.vertices - b.centroid for b in scene.bodies]
    n = len(local)
    scratch = np.zeros((4, MAX_OVERLAP_VERTICES))
    depth = np.zeros(len(result.time))
    for s in range(len(result.time)):
        world = []
        for b in range(n):
            c, si = math.cos(result.theta[s, b]), math.sin(result.theta[s, b])
            lx, ly = local[b][:, 0], local[b][:, 1]
            world.append((result.x[s, b] + c * lx - si * ly, result.y[s, b] + si * lx + c * ly))
        if not all(np.all(np.isfinite(w[0])) and np.all(np.isfinite(w[1])) for w in world):
            depth[s] = np.nan
            continue
        lo = np.array([[w[0].min(), w[1].min()] for w in world])
        hi = np.array([[w[0].max(), w[1].max()] for w in world])
        for i, j in box_pairs(lo, hi, 0.0):
            k = clip_convex_polygons(
                world[i][0],
                world[i][1],
                world[j][0],
                world[j][1],
                scratch[0],
                scratch[1],
                scratch[2],
                scratch[3],
            )
            if k >= 3:
                depth[s] = max(depth[s], min_width(scratch[0, :k].copy(), scratch[1, :k].copy()))
    return depth


def assess(scene: Scene, result: RunResult, tolerance: float = ENERGY_TOLERANCE) -> dict:
    """Stability measures of one run."""
    finite = result.status != step.STATUS_NONFINITE and np.all(np.isfinite(result.energy))
    energy = energy_drift(result)
    depths = overlap_depths(scene, result)
    return {
        "stable": bool(finite and energy["energy_error"] < tolerance),
        "finite": bool(finite),
        **energy,
        "max_overlap_depth": float(np.nanmax(depths)) if np.isfinite(depths).any() else math.nan,
        "dt": result.dt,
        "dt_limit": result.dt_limit,
        "wall_seconds": result.wall_seconds,
    }


VARIABLES = {  # name: (units, long name)
    "stable": ("1", "run stable: finite and |energy balance drift| < energy_tolerance (1 = yes)"),
    "finite": ("1", "every sampled pose and energy finite (1 = yes)"),
    "energy_error": (
        "1",
        "max |energy balance drift| / (max kinetic + max |potential change| + max |base work|)",
    ),
    "energy_created": (
        "1",
        "max energy balance drift (positive = energy created), same scale as energy_error",
    ),
    "energy_error_total": (
        "1",
        "max |energy balance drift| / initial kinetic + potential energy (datum: base top)",
    ),
    "max_overlap_depth": (
        "m",
        "deepest overlap between two bodies over the samples (overlap polygon's smallest width)",
    ),
    "dt": ("s", "time step of the run"),
    "wall_seconds": ("s", "wall time of the stepping"),
}


def stability_map(
    k_n_values=K_N_VALUES,
    dt_ratios=DT_RATIOS,
    scenes=SCENE_KINDS,
    duration=DURATION,
    damping_fractions=DAMPING_FRACTIONS,
    progress: bool = True,
    model: str = "point",
) -> xr.Dataset:
    """Stability of short runs over k_n x dt/limit x damping x scene kind (see module doc)."""
    shape = (len(k_n_values), len(dt_ratios), len(damping_fractions), len(scenes))
    data = {name: np.full(shape, np.nan) for name in VARIABLES}
    limit = np.full((shape[0], shape[2], shape[3]), np.nan)
    law_damping = np.full_like(limit, np.nan)
    total, done, start = int(np.prod(shape)), 0, wallclock.perf_counter()
    for i, k_n in enumerate(k_n_values):
        for d, frac in enumerate(damping_fractions):
            for s, kind in enumerate(scenes):
                scene = map_scene(kind, k_n, frac, duration, model)
                limit[i, d, s] = stability_limit(scene)
                law_damping[i, d, s] = (
                    scene.contact.c_n if model == "area" else scene.contact.damping
                )
                for r, ratio in enumerate(dt_ratios):
                    m = assess(scene, run_at_ratio(scene, ratio))
                    for name in VARIABLES:
                        data[name][i, r, d, s] = float(m[name])
                    done += 1
                    if progress:
                        print(
                            f"\r  stability map {done}/{total}  {model} {kind} k_n {k_n:.0e} "
                            f"damping {frac:g} "
                            f"dt {ratio:g} x limit: {'stable' if m['stable'] else 'UNSTABLE'} "
                            f"(err {m['energy_error']:.1e})   wall "
                            f"{wallclock.perf_counter() - start:6.1f} s",
                            end="",
                            file=sys.stderr,
                        )
    if progress:
        print(file=sys.stderr)

    def var(dims, values, units, long_name):
        return (dims, values, {"units": units, "long_name": long_name})

    dims = ("k_n", "dt_ratio", "damping", "scene")
    per_scene = ("k_n", "damping", "scene")
    ds = xr.Dataset(
        {name: var(dims, data[name], *meta) for name, meta in VARIABLES.items()},
        coords={
            "k_n": var(
                "k_n",
                np.array(k_n_values, float),
                "N m-2",
                "normal contact stiffness per unit "
                + ("contact length (point law)" if model == "point" else "overlap area (area law)"),
            ),
            "dt_ratio": var(
                "dt_ratio",
                np.array(dt_ratios, float),
                "1",
                "time step / stability limit (stonedem.engine.simulate.stability_limit)",
            ),
            "damping": var(
                "damping", np.array(damping_fractions, float), "1", damping_long_name(model)
            ),
            "scene": var(
                "scene",
                list(scenes),
                "1",
                "scene kind: block 0.25 x 1 m free rocking from 0.5 atan(b/h); column of "
                "8 drums 6 x 1 m; colonnade of 3 columns of 2 drums + epistyle (both harmonic)",
            ),
        },
        attrs={
            "source": code_version(),
            "contact_model": model,
            "contact_impact": "plastic (Housner's landing)" if model == "point" else "none",
            "energy_tolerance": ENERGY_TOLERANCE,
            "energy_floor": ENERGY_FLOOR,
            "duration": duration,
            "sample_every": SAMPLE_EVERY,
            "harmonic": str(HARMONIC),
            "description": "short runs at dt = dt_ratio x stability limit; stable = finite and "
            "energy_error < energy_tolerance (benchmarks.stability.energy_drift)",
        },
    )
    ds["dt_limit"] = var(
        per_scene, limit, "s", "stability limit (stonedem.engine.simulate.stability_limit)"
    )
    if model == "point":
        ds["zeta"] = var(
            per_scene, law_damping, "1", "damping ratio of each contact point (contact.damping)"
        )
    else:
        ds["c_n"] = var(
            per_scene, law_damping, "N s m-1", "normal (and tangential) contact dashpot"
        )
    ds["auto_dt_ratio"] = var(
        (), 0.25, "1", "automatic dt / stability limit (solver.dt_safety default)"
    )
    for name in ("stable", "finite"):
        ds[name] = ds[name].astype(np.int8)
    return ds


def study_scenes(config_path=ROOT / "config" / "config.yaml", duration: float = DURATION) -> dict:
    """{study: Scene}: the first case of every study in the config, shortened to ``duration``."""
    from stonedem.study.grid import config_cases, load_config, scene_without_member

    scenes = {}
    for name, cases in config_cases(load_config(config_path)).items():
        # member 0 of a study with its own ensemble is the case as configured
        spec, _ = scene_without_member(copy.deepcopy(cases[0].scene))
        spec.setdefault("solver", {}).update(duration=duration, stop_on_collapse=False)
        spec["solver"].pop("dt", None)  # the automatic step is what is measured
        spec.pop("name", None)
        scenes[name] = scene_from_dict(spec, base_dir=ROOT / "records")
    return scenes


def critical_ratio(
    scene: Scene, lo: float = 0.25, hi: float = 4.0, n_bisect: int = 6
) -> tuple[float, int]:
    """(smallest dt/limit found unstable, runs) by bisection on log(ratio) between lo and hi.

    hi doubles (up to 16) until a run there is unstable. Returns lo if the run at lo is
    already unstable, inf if none up to 16 is.
    """
    runs = 0

    def unstable(ratio):
        nonlocal runs
        runs += 1
        return not assess(scene, run_at_ratio(scene, ratio))["stable"]

    if unstable(lo):
        return lo, runs
    while not unstable(hi):
        if hi >= 16.0:
            return math.inf, runs
        lo, hi = hi, 2.0 * hi
    for _ in range(n_bisect):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if unstable(mid) else (mid, hi)
    return hi, runs


def auto_dt_margin(scenes: dict | None = None, progress: bool = True) -> xr.Dataset:
    """Automatic dt, stability limit and measured critical dt of one scene per study."""
    scenes = study_scenes() if scenes is None else scenes
    names = list(scenes)
    rows = {
        k: np.full(len(names), np.nan)
        for k in ("dt_auto", "dt_limit", "dt_critical", "margin", "k_n", "c_n", "zeta")
    }
    for i, name in enumerate(names):
        scene = scenes[name]
        dt, limit = choose_time_step(scene)
        ratio, runs = critical_ratio(scene, lo=scene.dt_safety)
        rows["dt_auto"][i], rows["dt_limit"][i] = dt, limit
        rows["dt_critical"][i] = ratio * limit
        rows["margin"][i] = ratio * limit / dt
        law = scene.contact
        rows["k_n"][i] = law.k_n
        rows["c_n" if law.model == "area" else "zeta"][i] = (
            law.c_n if law.model == "area" else law.damping
        )
        if progress:
            print(
                f"  auto dt {i + 1}/{len(names)} {name}: auto {dt:.3g} s, limit {limit:.3g} s, "
                f"critical {ratio * limit:.3g} s ({runs} runs)",
                file=sys.stderr,
            )
    meta = {
        "dt_auto": ("s", "automatic time step (stonedem.engine.simulate.choose_time_step)"),
        "dt_limit": ("s", "stability limit (stonedem.engine.simulate.stability_limit)"),
        "dt_critical": (
            "s",
            "smallest measured dt whose short run is unstable (bisection on dt / limit)",
        ),
        "margin": ("1", "dt_critical / dt_auto"),
        "k_n": ("N m-2", "normal contact stiffness"),
        "c_n": ("N s m-1", "normal contact dashpot (area law; NaN: point law)"),
        "zeta": ("1", "damping ratio of each contact point (point law; NaN: area law)"),
    }
    models = [scenes[name].contact.model for name in names]
    return xr.Dataset(
        {
            **{
                k: ("study", v, {"units": meta[k][0], "long_name": meta[k][1]})
                for k, v in rows.items()
            },
            "contact_model": (
                "study",
                models,
                {"units": "1", "long_name": "contact law of the study (point or area)"},
            ),
        },
        coords={
            "study": (
                "study",
                names,
                {"units": "1", "long_name": "study of config/config.yaml (its first case)"},
            )
        },
        attrs={
            "source": code_version(),
            "energy_tolerance": ENERGY_TOLERANCE,
            "duration": DURATION,
            "description": "unstable = non-finite or energy_error >= energy_tolerance in a short "
            "run (benchmarks.stability.energy_drift)",
        },
    )


def plot_stability_map(ds: xr.Dataset, path) -> Path:
    """Stable (o) / unstable (x) runs in (k_n, dt / limit), one panel per scene, every damping."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = list(ds.scene.values)
    fig, axes = plt.subplots(
        1, len(scenes), figsize=(4.2 * len(scenes), 3.8), sharey=True, squeeze=False
    )
    n_d = ds.sizes["damping"]
    for ax, scene in zip(axes[0], scenes):
        for d, frac in enumerate(ds.damping.values):
            shift = 10 ** (0.12 * (d - (n_d - 1) / 2))  # spread the damping levels side by side
            sub = ds.sel(scene=scene, damping=frac)
            kn, ratio = np.meshgrid(ds.k_n.values * shift, ds.dt_ratio.values, indexing="ij")
            ok = sub.stable.values.astype(bool)
            color = f"C{d}"
            what = "zeta" if ds.attrs.get("contact_model", "area") == "point" else "c / crit"
            ax.scatter(
                kn[ok],
                ratio[ok],
                marker="o",
                facecolors="none",
                edgecolors=color,
                s=22,
                label=f"stable, {what} = {frac:g}",
            )
            ax.scatter(
                kn[~ok],
                ratio[~ok],
                marker="x",
                color=color,
                s=22,
                label=f"unstable, {what} = {frac:g}",
            )
        ax.axhline(float(ds.auto_dt_ratio), color="k", ls="--", lw=1, label="automatic dt")
        ax.axhline(1.0, color="0.5", ls=":", lw=1, label="stability limit")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("k_n [N m-2]")
        ax.set_title(f"{scene} ({ds.attrs.get('contact_model', 'area')} law)")
    axes[0][0].set_ylabel("dt / stability limit")
    axes[0][-1].legend(fontsize=6, loc="lower right", ncol=1)
    fig.tight_layout()
    from benchmarks.options import save_figure

    path = save_figure(fig, path, dpi=120)
    plt.close(fig)
    return path


def table(ds: xr.Dataset) -> str:
    """Readable table: per scene, damping and k_n, the first unstable ratio and the worst stable
    error."""
    lines = [
        f"{'scene':10s} {'damping':>7s} {'k_n':>8s} {'limit [s]':>10s} {'unstable from':>13s} "
        f"{'max err (stable)':>16s} {'max overlap [m]':>15s}"
    ]
    for scene in ds.scene.values:
        for frac in ds.damping.values:
            for k_n in ds.k_n.values:
                sub = ds.sel(scene=scene, damping=frac, k_n=k_n)
                bad = sub.dt_ratio.values[sub.stable.values == 0]
                good = sub.stable.values == 1
                first = f"{bad.min():g} x" if len(bad) else "-"
                err = np.nanmax(sub.energy_error.values[good]) if good.any() else np.nan
                ov = np.nanmax(sub.max_overlap_depth.values[good]) if good.any() else np.nan
                lines.append(
                    f"{scene:10s} {frac:7g} {k_n:8.0e} {float(sub.dt_limit):10.3g} {first:>13s} "
                    f"{err:16.2e} {ov:15.2e}"
                )
    return "\n".join(lines)


DURATION_RANGE = (0.0, 60.0)  # [s] of each run of the map, lower end excluded


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.stability", __doc__)
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=str(ROOT / "results" / "bench"),
        help="output folder (writes stability_map.nc and auto_dt_margin.nc)",
    )
    parser.add_argument(
        "--figure",
        type=options.path_arg,
        default=str(ROOT / "results" / "figures" / "stability_map.png"),
        help="output figure (.png)",
    )
    parser.add_argument(
        "--duration",
        type=float,
        default=DURATION,
        help=f"simulated seconds of each run of the map, > 0 and <= {DURATION_RANGE[1]:g} "
        f"(default {DURATION}; --quick: 0.2)",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="two stiffnesses, three step ratios, no damping sweep, three studies (CI)",
    )
    parser.add_argument(
        "--model",
        choices=CONTACT_MODELS,
        default="point",
        help="contact law of the map (default: point; the "
        "auto-dt margins use each study's own law)",
    )
    return parser


def check_args(args):
    """(duration [s], folder, figure path, the studies' scenes), or an InputError before anything
    runs."""
    from benchmarks import options

    duration = options.number(
        args.duration,
        "--duration",
        lo=DURATION_RANGE[0],
        lo_open=True,
        hi=DURATION_RANGE[1],
        unit="s",
        example="0.5",
    )
    out = options.output_folder(args.out, "--out", files=("stability_map.nc", "auto_dt_margin.nc"))
    figure = options.output_file(args.figure, "--figure", suffixes=(".png",))
    # the studies' scenes of the auto-dt margins, built now: a bad config or a missing record
    # is refused before the map runs
    scenes = dict(list(study_scenes(duration=0.2).items())[:3]) if args.quick else study_scenes()
    return duration, Path(out), figure, scenes


def main(argv=None) -> int:
    """Options and output paths checked first (one line, exit 2); then the map and the margins."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        duration, out, figure, scenes = check_args(args)
        if args.quick:
            ds = stability_map(
                k_n_values=(1e8, 1e10),
                dt_ratios=(0.25, 1.0, 2.0),
                damping_fractions=(0.05,),
                duration=0.2,
                model=args.model,
            )
        else:
            ds = stability_map(duration=duration, model=args.model)
        write_dataset(ds, out / "stability_map.nc")
        print(table(ds))
        plot_stability_map(ds, figure)
        margin = auto_dt_margin(scenes)
        write_dataset(margin, out / "auto_dt_margin.nc")
        print(
            f"\n{'study':30s} {'auto dt [s]':>11s} {'limit [s]':>10s} {'critical [s]':>12s} "
            f"{'margin':>7s}"
        )
        for i, name in enumerate(margin.study.values):
            r = margin.isel(study=i)
            print(
                f"{name:30s} {float(r.dt_auto):11.3g} {float(r.dt_limit):10.3g} "
                f"{float(r.dt_critical):12.3g} "
                f"{float(r.margin):7.2f}"
            )
        return 0

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
