"""Inside the step: nanoseconds per step and per contact-step of the compiled loop, stage by
stage, beside the parent commit (``snakemake bench_kernel``; issue 32).

For each scene of :data:`SCENES` (a lone rocking block, columns of 1, 8 and 30 drums, a
3 x 3 colonnade and a row of ten 3-drum columns under one epistyle) the benchmark reports:

- **ns per step** of :func:`stonedem.kernels.step.run` (the compiled loop's own wall time,
  :attr:`stonedem.engine.simulate.RunResult.wall_seconds`, over the steps it integrated), best
  of ``--repeats``, and per contact-step (over the mean number of touching pairs);
- the same for the **parent commit**, checked out from a git worktree into the user's cache
  (kept, so its compiled kernels are cached too), each engine timed in its own process with
  its kernels loaded from Numba's cache, the runs interleaved current / parent, and their
  ratio (an engine compiled in the measuring process ran 1.2-1.7x slower than the same code
  loaded from the cache, so the two are never timed in one process);
- the **share of each stage** of the staged step (:mod:`stonedem.kernels.step`): each
  stage's kernels are timed alone in a compiled loop over the scene's state half-way through
  the run, with the arrays unpacked as the time loop does; ``rest`` is what the loop costs
  beyond them (branches, the sample decision, the at-rest and collapse checks);
- the Python around the loop per step (set-up, chunks, signals): the wall time of
  :func:`stonedem.engine.simulate.simulate` minus the loop's.

Writes results/bench/kernel.nc (and .csv) and results/figures/kernel_cost.png (ns per step
against bodies). One thread; timings want a quiet machine.

    python -m benchmarks.kernel [--quick] [--parent REV|none] [--out results/bench] [--figure
    PNG]
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

from stonedem.kernels import NO_ALLOC_OPTIONS
from stonedem.kernels import step as kstep
from stonedem.kernels.contact import contact_power
from stonedem.kernels.integrate import central_difference_step
from stonedem.study.reference_scenes import RECORD, SCENES  # noqa: F401 - the benchmark's scenes

ROOT = Path(__file__).resolve().parents[1]
STAGES = (
    "place",
    "watch",
    "broad_phase",
    "contact_forces",
    "velocities_power",
    "sampling",
    "integrate",
    "rest",
)
STAGE_TITLES = {
    "place": "base motion, driven bodies, world vertices, bounds",
    "watch": "running peaks and the collapse check (track, collapsed)",
    "broad_phase": "the Verlet-list check (needs_resweep; a sweep is rare)",
    "contact_forces": "clear forces and the contact law",
    "velocities_power": "velocities at t_n and the contact power booking",
    "sampling": "a sample (sample_state) over the steps between samples",
    "integrate": "energy booking and the central-difference step",
    "rest": "the loop beyond the stages: branches, the sample decision, rest checks",
}


# --- the stages, each alone in a compiled loop ------------------------------------------
# The arrays are unpacked once and compiled without Numba's runtime, as
# stonedem.kernels.step.run_steps is, so a stage costs here what it costs there. Each returns
# a number that depends on the work, so nothing is optimised away.


@njit(**NO_ALLOC_OPTIONS)
def _place(model, state, work, t, n_rep):
    acc = 0.0
    for _r in range(n_rep):
        d_h, vel_h, d_v, vel_v = kstep.place_bodies(model, state, work, t)
        acc += work.hi_x[0] + d_h
    return acc


@njit(**NO_ALLOC_OPTIONS)
def _watch(model, state, work, n, d_h, d_v, n_rep):
    tilt_alarm = kstep.smallest_theta_cr(model)
    count = 0
    for _r in range(n_rep):
        if kstep.track(model, state, work, n, d_h, d_v, tilt_alarm) and kstep.collapsed(
            model, state, work, d_v
        ):
            count += 1
    return count


@njit(**NO_ALLOC_OPTIONS)
def _broad_phase(model, state, work, n_rep):
    count = 0
    for _r in range(n_rep):
        if kstep.needs_resweep(model, state, work):
            count += 1
    return count


@njit(**NO_ALLOC_OPTIONS)
def _contact_forces(model, state, work, n_pair, dt, n_rep, want_energy, point_law):
    total = 0
    for _r in range(n_rep):
        n_contact, elastic = kstep.contact_forces(
            model, state, work, n_pair, dt, want_energy, point_law
        )
        total += n_contact
    return total


@njit(**NO_ALLOC_OPTIONS)
def _velocities_power(model, state, work, n_pair, dt, n_rep):
    pair_a, pair_b, pair_memory = work.pair_a, work.pair_b, state.pair_memory
    body_x, body_y = state.body_x, state.body_y
    vel_x, vel_y, vel_om = work.vel_x, work.vel_y, work.vel_om
    acc = 0.0
    for _r in range(n_rep):
        kstep.velocities_at_step(model, state, work, 0.5 * dt)
        p_damp, p_tan = contact_power(
            pair_a, pair_b, n_pair, pair_memory, body_x, body_y, vel_x, vel_y, vel_om
        )
        kstep.book_power(work, p_damp, p_tan, 0.0, 0.0)
        acc += p_damp
    return acc


@njit(**NO_ALLOC_OPTIONS)
def _sampling(model, state, work, samples, dt, n_rep):
    count = 0
    for r in range(n_rep):
        if kstep.sample_state(r, 0, model, state, work, samples, 1, 0.0, 0.5 * dt):
            count += 1
    return count


@njit(**NO_ALLOC_OPTIONS)
def _integrate(model, state, work, n_rep):
    body_driven, inv_mass, inv_inertia = model.body_driven, work.inv_mass, work.inv_inertia
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    body_vx, body_vy, body_omega = state.body_vx, state.body_vy, state.body_omega
    n_body = body_x.shape[0]
    for _r in range(n_rep):
        # kick and drift of zero: the same arithmetic, and the state does not wander off
        kstep.book_energy(state, work, 0.0)
        central_difference_step(
            n_body,
            body_driven,
            inv_mass,
            inv_inertia,
            model.gravity,
            0.0,
            0.0,
            force_x,
            force_y,
            torque,
            body_x,
            body_y,
            body_theta,
            body_vx,
            body_vy,
            body_omega,
        )
    return body_x[0]


def _best_ns(function, n_rep, repeats=3):
    """Best-of-``repeats`` wall time of ``function(n_rep)`` per repetition [ns]."""
    function(1)  # compile
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        function(n_rep)
        best = min(best, time.perf_counter() - start)
    return 1e9 * best / n_rep


def stage_costs(spec: dict, n_rep: int = 20000, repeats: int = 3) -> dict:
    """ns per step of each stage of :data:`STAGES` but ``rest``, on the scene's state half-way
    through its run (the loop run to there first, so contacts, memory and pairs are live)."""
    from stonedem.engine.pack import kernel_model, pack_scene
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import REST_SPEED, empty_samples, initial_state, run_time_step

    scene = scene_from_dict(spec)
    dt, _ = run_time_step(scene)
    arrays = pack_scene(scene)
    n_steps = int(np.ceil(scene.duration / dt - 1e-9))
    out_every = max(1, int(round(scene.output_every / dt)))
    settings = kstep.Settings(
        dt=dt,
        n_steps=n_steps,
        out_every=out_every,
        stop_on_collapse=False,
        rest_speed=REST_SPEED,
        rest_samples=10**9,
    )
    model = kernel_model(scene, arrays)
    state = initial_state(arrays)
    samples = empty_samples(n_steps // out_every + 2, len(scene.bodies))
    n_mid = n_steps // 2
    kstep.run(model, settings, state, samples, 0, n_mid, 0, n_steps + 1, 0, -1)
    n_body = len(scene.bodies)
    work = kstep.allocate_work(model, max(1, n_body * (n_body - 1) // 2))
    t = n_mid * dt
    _place(model, state, work, t, 1)
    n_pair = kstep.sweep(model, state, work)
    one = empty_samples(1, len(scene.bodies))
    # the scene's law alone, as run_steps
    point_law = True if model.law.kind == kstep.CONTACT_POINT else None
    contact_ns = _best_ns(
        lambda n: _contact_forces(model, state, work, n_pair, dt, n, False, point_law),
        n_rep,
        repeats,
    )
    with_energy_ns = _best_ns(
        lambda n: _contact_forces(model, state, work, n_pair, dt, n, True, point_law),
        n_rep,
        repeats,
    )
    costs = {
        "place": _best_ns(lambda n: _place(model, state, work, t, n), n_rep, repeats),
        "watch": _best_ns(lambda n: _watch(model, state, work, n_mid, 0.0, 0.0, n), n_rep, repeats),
        "broad_phase": _best_ns(lambda n: _broad_phase(model, state, work, n), n_rep, repeats),
        "contact_forces": contact_ns,
        "velocities_power": _best_ns(
            lambda n: _velocities_power(model, state, work, n_pair, dt, n), n_rep, repeats
        ),
        # a sample's cost spread over the steps between samples, with the stored energy the
        # contact law then evaluates too
        "sampling": (
            _best_ns(lambda n: _sampling(model, state, work, one, dt, n), n_rep, repeats)
            + max(0.0, with_energy_ns - contact_ns)
        )
        / out_every,
        "integrate": _best_ns(lambda n: _integrate(model, state, work, n), n_rep, repeats),
    }
    return costs


# --- the parent commit, run beside this one ------------------------------------------------

# Each engine runs in its own Python process, both with their kernels loaded from Numba's
# cache. Not in one process: the engine compiled in the running process was measured 1.2-1.7x
# slower than the same machine code loaded from the cache (identical commits, 2026-11-26),
# which would have credited the newer commit with the difference.
WORKER = """
import json, sys, time
args = json.loads(sys.argv[1])
sys.path.insert(0, args["src"])
import numpy as np
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
out = {}
for name, spec in args["scenes"].items():
    short = json.loads(json.dumps(spec))
    short["solver"]["duration"] = 0.05
    simulate(scene_from_dict(short))  # the kernels loaded (or compiled) before the clock starts
    scene = scene_from_dict(spec)
    start = time.perf_counter()
    result = simulate(scene)
    total = time.perf_counter() - start
    steps = max(result.steps_run, 1)
    out[name] = [1e9 * result.wall_seconds / steps, 1e9 * (total - result.wall_seconds) / steps,
                 result.steps_run, float(np.mean(result.n_contact)), result.dt]
print(json.dumps(out))
"""


class ParentUnavailable(Exception):
    """The parent commit cannot be run here (no git checkout, no such commit)."""


def resolve_commit(rev: str, root: Path = ROOT) -> str:
    """The full hash of commit ``rev`` of the checkout at ``root`` (default: this package's),
    or ParentUnavailable saying why."""
    try:
        return subprocess.run(
            ["git", "-C", str(root), "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}"],
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        ).stdout.strip()
    except FileNotFoundError:
        raise ParentUnavailable("git is not installed") from None
    except (OSError, subprocess.SubprocessError):
        raise ParentUnavailable(
            f"no commit {rev!r} in {root} (not a git checkout, a shallow clone, or no such commit)"
        ) from None


KEPT_PARENTS = 4  # parent checkouts kept in the cache, the most recently used


def prune_parents(folder: Path, keep: int = KEPT_PARENTS) -> list[Path]:
    """Remove all but the ``keep`` most recently used checkouts in ``folder`` (each one's
    folder time is set when it is used); returns those removed."""
    if not folder.is_dir():
        return []
    checkouts = sorted(
        (p for p in folder.iterdir() if p.is_dir() and not p.name.endswith(".part")),
        key=lambda p: p.stat().st_mtime,
        reverse=True,
    )
    for old in checkouts[keep:]:
        shutil.rmtree(old, ignore_errors=True)
    return checkouts[keep:]


def parent_source(commit: str) -> Path:
    """The ``src`` folder of ``commit``, checked out once (:func:`check_out_parent`) into a
    folder of the user's cache that is kept, so its compiled kernels stay cached too; only the
    :data:`KEPT_PARENTS` most recently used checkouts stay there."""
    root = (
        Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
        / "stonedem"
        / "parents"
        / commit
    )
    source = root / "src"
    if not (source / "stonedem" / "__init__.py").is_file():
        check_out_parent(commit, root)
    os.utime(root)  # used now: prune_parents keeps it
    prune_parents(root.parent)
    return source


def check_out_parent(commit: str, root: Path) -> None:
    """``commit``'s src folder into root/src: a git worktree, copied through a ``.part``
    folder (so a copy cut short is never taken for a checkout) and removed."""
    with tempfile.TemporaryDirectory(prefix="stonedem-parent-") as workdir:
        tree = Path(workdir) / "worktree"
        try:
            subprocess.run(
                [
                    "git",
                    "-C",
                    str(ROOT),
                    "worktree",
                    "add",
                    "--detach",
                    "--quiet",
                    str(tree),
                    commit,
                ],
                capture_output=True,
                text=True,
                check=True,
            )
        except subprocess.CalledProcessError as exc:
            raise ParentUnavailable(f"git worktree add failed: {exc.stderr.strip()}") from exc
        try:
            if not (tree / "src" / "stonedem").is_dir():
                raise ParentUnavailable(f"commit {commit[:10]} has no src/stonedem")
            staging = root.with_name(root.name + ".part")
            shutil.rmtree(staging, ignore_errors=True)
            shutil.copytree(tree / "src", staging / "src")
            shutil.rmtree(root, ignore_errors=True)
            staging.rename(root)
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(tree)],
                capture_output=True,
            )


def time_engines(source: Path, specs: dict) -> dict:
    """{scene: (ns per step of the loop, ns per step of the Python around it, steps, mean
    contacts, dt)} of the engine in ``source`` (a ``src`` folder), one run each, in a fresh
    process."""
    done = subprocess.run(
        [sys.executable, "-c", WORKER, json.dumps({"src": str(source), "scenes": specs})],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=dict(os.environ, NUMBA_NUM_THREADS="1"),
    )
    if done.returncode != 0:
        tail = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise RuntimeError(f"the engine in {source} failed: {tail}")
    return {
        name: tuple(row) for name, row in json.loads(done.stdout.strip().splitlines()[-1]).items()
    }


# --- the benchmark ------------------------------------------------------------------------


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.kernel", __doc__)
    parser.add_argument(
        "--quick", action="store_true", help="2 simulated seconds per scene, not 10 (CI)"
    )
    parser.add_argument(
        "--parent",
        default=None,
        help="the commit to compare against, or none (default HEAD~1, if this is a git "
        "checkout that has it)",
    )
    parser.add_argument(
        "--repeats", type=int, default=3, help="interleaved runs per engine and scene; best kept"
    )
    parser.add_argument(
        "--out", type=options.path_arg, default=Path("results/bench"), help="folder of kernel.nc"
    )
    parser.add_argument(
        "--figure",
        type=options.path_arg,
        default=None,
        help="the figure (default: <out>/../figures/kernel_cost.png)",
    )
    return parser


# issue 32's targets: (the measure, its bound [ns]); the dataset says which are met
TARGETS = {
    "lone_block": ("ns_per_step", 150.0),
    "column_8": ("ns_per_contact_step", 70.0),
    "colonnade_3x3": ("ns_per_contact_step", 70.0),
}


def kernel_dataset(rows, stages, parent_commit, parent_note, quick):
    import xarray as xr

    from stonedem.io.netcdf import code_version

    names = list(SCENES)
    versions = ["current", "parent"]

    def grid(key):
        return xr.DataArray(
            np.array([[rows[s][v][key] for v in versions] for s in names], dtype=float),
            dims=("scene", "version"),
            coords={"scene": names, "version": versions},
        )

    ns_step = grid("ns_per_step")
    contacts = grid("contacts")
    ds = xr.Dataset(
        coords={
            "stage": (
                "stage",
                list(STAGES),
                {"long_name": "stage of the compiled step (stonedem.kernels.step)"},
            ),
        }
    )
    ds["n_body"] = (
        "scene",
        [rows[s]["n_body"] for s in names],
        {"long_name": "bodies, driven base included", "units": "1"},
    )
    ds["ns_per_step"] = ns_step.assign_attrs(
        long_name="wall time of the compiled loop per step, best of the repeats", units="ns"
    )
    ds["ns_per_contact_step"] = (ns_step / contacts.where(contacts > 0)).assign_attrs(
        long_name="wall time of the compiled loop per step and touching pair", units="ns"
    )
    ds["python_ns_per_step"] = grid("python_ns_per_step").assign_attrs(
        long_name="wall time of simulate() outside the compiled loop (set-up, chunks, signals) "
        "per step",
        units="ns",
    )
    ds["contacts"] = contacts.assign_attrs(
        long_name="mean number of touching pairs over the samples", units="1"
    )
    ds["steps"] = grid("steps").assign_attrs(long_name="steps integrated", units="1")
    ds["dt"] = grid("dt").assign_attrs(long_name="time step", units="s")
    ds["speedup"] = (ns_step.sel(version="parent") / ns_step.sel(version="current")).assign_attrs(
        long_name="parent's ns per step over this commit's", units="1"
    )
    ds["stage_ns_per_step"] = (
        ("scene", "stage"),
        np.array([[stages[s][k] for k in STAGES] for s in names]),
        {
            "long_name": "wall time of each stage per step, this commit (rest: the loop "
            "beyond the stages)",
            "units": "ns",
        },
    )
    ds["stage_share"] = (
        ds["stage_ns_per_step"] / ds["ns_per_step"].sel(version="current")
    ).assign_attrs(long_name="share of the loop's time per stage, this commit", units="1")
    ds["scene_title"] = ("scene", [SCENES[s][0] for s in names], {"long_name": "what the scene is"})
    bound = [TARGETS[s][1] if s in TARGETS else np.nan for s in names]
    ds["target_ns"] = (
        "scene",
        bound,
        {
            "long_name": "issue 32's target: ns per step (lone block) or per "
            "contact-step (8-drum column, colonnade), this commit",
            "units": "ns",
        },
    )
    met = [
        int(float(ds[TARGETS[s][0]].sel(scene=s, version="current")) <= TARGETS[s][1])
        if s in TARGETS
        else -1
        for s in names
    ]
    ds["target_met"] = (
        "scene",
        np.array(met, dtype=np.int8),
        {
            "long_name": "whether this commit meets issue 32's target",
            "units": "1",
            "flag_values": np.array([-1, 0, 1], dtype=np.int8),
            "flag_meanings": "no_target missed met",
        },
    )
    # the DataArrays assigned above bring their own (bare) scene and version coordinates
    ds["scene"].attrs = {"long_name": "benchmark scene"}
    ds["version"].attrs = {"long_name": "engine: this commit or its parent"}
    ds.attrs.update(
        {
            "title": "ns per step of the compiled rigid-block loop, stage by stage, beside the "
            "parent commit",
            "settings": "point law, k_n 1e10 N/m2, dt auto (dt_safety 1), output every 0.01 s, "
            "one thread, "
            f"{2.0 if quick else 10.0} simulated s per scene (skipped quiet stretches not counted)",
            "profile": "quick" if quick else "full",
            "parent_commit": parent_commit or "",
            "parent_note": parent_note,
            "stages": "; ".join(f"{k}: {v}" for k, v in STAGE_TITLES.items()),
            "code_version": code_version(),
            "machine": f"{os.cpu_count()} cores, {sys.platform}",
        }
    )
    return ds


def figure(ds, path: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from benchmarks.options import save_figure

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    order = np.argsort(ds["n_body"].values)
    bodies = ds["n_body"].values[order]
    for version, style in (("parent", "s--"), ("current", "o-")):
        values = ds["ns_per_step"].sel(version=version).values[order]
        if np.isfinite(values).any():
            label = (
                "this commit"
                if version == "current"
                else f"parent {ds.attrs['parent_commit'][:10]}"
            )
            ax.plot(bodies, values, style, label=label)
    for name, n, value in zip(
        ds["scene"].values[order], bodies, ds["ns_per_step"].sel(version="current").values[order]
    ):
        ax.annotate(str(name), (n, value), textcoords="offset points", xytext=(4, -10), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("bodies (driven base included)")
    ax.set_ylabel("ns per step of the compiled loop")
    ax.set_title("Cost of one step against scene size (one thread)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    save_figure(fig, path, dpi=120)
    plt.close(fig)


def main(argv=None) -> int:
    from benchmarks import options
    from stonedem.errors import InputError

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.engine.scene import scene_from_dict
        from stonedem.io.netcdf import write_dataset

        repeats = options.number(args.repeats, "--repeats", lo=1, hi=50, whole=True, example="3")
        path = (
            options.output_folder(args.out, "--out", files=("kernel.nc", "kernel.csv"))
            / "kernel.nc"
        )
        figure_path = options.output_file(
            args.figure or args.out.parent / "figures" / "kernel_cost.png",
            "--figure",
            suffixes=(".png",),
        )
        parent_commit, parent_note = None, "compared"
        if args.parent is None:  # the default: compared where the checkout has it
            try:
                parent_commit = resolve_commit("HEAD~1")
            except ParentUnavailable as exc:
                parent_note = f"parent not compared: {exc}"
                print(f"warning: {parent_note}", file=sys.stderr)
        elif args.parent.strip().lower() == "none":
            parent_note = "parent not compared: --parent none"
        else:
            try:
                parent_commit = resolve_commit(args.parent)
            except ParentUnavailable as exc:
                raise InputError(
                    "--parent",
                    str(exc),
                    "give a commit of this checkout's history, such as HEAD~1, or none",
                ) from None
        duration = 2.0 if args.quick else 10.0
        start = time.perf_counter()
        specs = {name: build(duration) for name, (_, build) in SCENES.items()}
        sources = {"current": ROOT / "src"}
        if parent_commit is not None:
            try:
                sources["parent"] = parent_source(parent_commit)
            except ParentUnavailable as exc:
                parent_commit, parent_note = None, f"parent not compared: {exc}"
                print(f"warning: {parent_note}", file=sys.stderr)
        for version, source in list(sources.items()):  # compile into the cache (once per source)
            try:
                time_engines(
                    source,
                    {
                        name: dict(spec, solver=dict(spec["solver"], duration=0.1))
                        for name, spec in specs.items()
                    },
                )
            except RuntimeError as exc:
                if version == "current":
                    raise
                del sources[version]
                parent_commit, parent_note = None, f"parent not compared: {exc}"
                print(f"warning: {parent_note}", file=sys.stderr)
        best = {version: {} for version in sources}
        for rep in range(repeats):  # interleaved, so drifts of the machine hit both
            for version, source in sources.items():
                for name, timing in time_engines(source, specs).items():
                    if name not in best[version] or timing[0] < best[version][name][0]:
                        best[version][name] = timing
            print(f"  run {rep + 1} of {repeats} done", file=sys.stderr, flush=True)
        rows, stages = {}, {}
        for name, spec in specs.items():
            n_body = len(scene_from_dict(spec).bodies)
            rows[name] = {"n_body": n_body}
            for version in ("current", "parent"):
                ns, py_ns, steps, contacts, dt = best.get(version, {}).get(name, (np.nan,) * 5)
                rows[name][version] = {
                    "ns_per_step": ns,
                    "python_ns_per_step": py_ns,
                    "steps": steps,
                    "contacts": contacts,
                    "dt": dt,
                }
            costs = stage_costs(spec, n_rep=5000 if args.quick else 20000, repeats=3)
            current = rows[name]["current"]["ns_per_step"]
            costs["rest"] = max(0.0, current - sum(costs.values()))
            stages[name] = costs
            parent_ns = rows[name]["parent"]["ns_per_step"]
            print(
                f"  {name:15s} {n_body:4d} bodies  {current:8.0f} ns/step  parent {parent_ns:8.0f}"
                f"  x{parent_ns / current:5.2f}  "
                + " ".join(f"{k} {v:.0f}" for k, v in costs.items()),
                file=sys.stderr,
                flush=True,
            )
        ds = kernel_dataset(rows, stages, parent_commit, parent_note, args.quick)
        write_dataset(ds, path)
        step, contact = ds["ns_per_step"], ds["ns_per_contact_step"]
        options.write_csv(
            path.with_suffix(".csv"),
            [
                {
                    "scene": name,
                    "version": version,
                    "n_body": int(ds["n_body"].sel(scene=name)),
                    "ns_per_step": f"{float(step.sel(scene=name, version=version)):.1f}",
                    "ns_per_contact_step": f"{float(contact.sel(scene=name, version=version)):.1f}",
                }
                for name in SCENES
                for version in ("current", "parent")
            ],
        )
        figure(ds, figure_path)
        for name in SCENES:
            cur = float(ds["ns_per_step"].sel(scene=name, version="current"))
            print(
                f"{name}: {cur:.0f} ns/step, "
                f"{float(ds['ns_per_contact_step'].sel(scene=name, version='current')):.0f}"
                f" ns/contact-step, x{float(ds['speedup'].sel(scene=name)):.2f} on the parent"
            )
        print(f"wrote {path} and {figure_path} in {time.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
