"""A simulated scene as a self-describing dataset: run it and build its dataset.

:func:`run_scene` refuses absurd requests (:func:`stonedem.engine.simulate.preflight`), runs the
compiled loop (:func:`stonedem.engine.simulate.simulate`) and its checks, and turns the samples into
an xarray Dataset (:func:`scene_dataset`) with units and long names from :mod:`stonedem.io.schema`,
the full input as JSON in ``attrs["scene"]``, solver settings and the code version in
attrs; :func:`stonedem.io.netcdf.write_dataset` writes it.

Imports go one way: this module -> :mod:`stonedem.engine.simulate` -> :mod:`stonedem.kernels`; the
computing side never needs xarray.
"""

from __future__ import annotations

import dataclasses
import platform
import sys
from datetime import datetime, timezone

import numba
import numpy as np
import xarray as xr

from stonedem.engine import measures
from stonedem.engine.laws import LAWS
from stonedem.engine.scene import Scene
from stonedem.engine.simulate import (
    ENERGY_TOLERANCE,
    PENETRATION_LIMIT,
    RunResult,
    preflight,
    run_checks,
    simulate,
)
from stonedem.entry import check_interrupt
from stonedem.errors import InputError
from stonedem.io.netcdf import code_version, schema_variables
from stonedem.io.provenance import bounded_json
from stonedem.kernels import step
from stonedem.motion.excitation import KIND_SEQUENCE, excitation_label

# times an automatic step is halved for a run that diverges or drifts past the energy tolerance
ENERGY_RETRIES = 2


def _fits(scene: Scene) -> bool:
    """Whether a repeat of the scene stays within the engine's limits (steps, sample memory)."""
    try:
        preflight(scene)
    except InputError:
        return False
    return True


def run_scenes(
    scenes: list[Scene], device: str = "cpu", threads: int | None = None
) -> list[xr.Dataset]:
    """:func:`run_scene` of each scene, their first attempts run side by side
    (:func:`stonedem.engine.ensemble.run_ensemble` on ``device``); a retry at a halved step
    runs alone on the CPU. Each dataset's attrs say the device of its first attempt."""
    from stonedem.engine.ensemble import run_ensemble

    scenes = list(scenes)
    for scene in scenes:
        preflight(scene)
    # a sequence runs part by part (stonedem.engine.simulate.simulate_sequence), alone
    alone = [scene.horizontal.kind == KIND_SEQUENCE for scene in scenes]
    together = iter(
        run_ensemble([s for s, a in zip(scenes, alone) if not a], threads=threads, device=device)
    )
    results = [None if a else next(together) for a in alone]
    datasets = [run_scene(scene, first=result) for scene, result in zip(scenes, results)]
    for ds in datasets:
        ds.attrs["device"] = device
    return datasets


def run_scene(scene: Scene, progress: bool = False, first: RunResult | None = None) -> xr.Dataset:
    """Simulate a scene and return its self-describing xarray Dataset (:func:`scene_dataset`).
    ``first``: the first attempt, already run (:func:`run_scenes`).

    Refused before computing: :func:`stonedem.engine.simulate.preflight`. After it: a diverged run
    is an error; a penetration or energy drift past its limit is the dataset's ``status`` and a
    warning. With ``dt: auto`` a diverged run or an energy drift past its limit first halves
    dt_safety and runs again, up to ENERGY_RETRIES times (attrs ``dt_safety`` as run,
    ``dt_safety_requested``, ``dt_halvings``).
    """
    run = checked_run(scene, progress, first)
    ds = scene_dataset(run.scene, run.result, run.checks)
    ds.attrs["dt_safety_requested"] = scene.dt_safety
    ds.attrs["dt_halvings"] = run.halvings
    ds.attrs["compile_seconds"] = run.compile_seconds
    return ds


@dataclasses.dataclass
class CheckedRun:
    """A finished run and what it says of itself (:func:`checked_run`)."""

    scene: Scene  # as run: dt_safety halved ``halvings`` times from the scene asked for
    result: RunResult
    checks: dict  # stonedem.engine.simulate.run_checks
    halvings: int
    compile_seconds: float  # the loop's compile, whichever attempt waited for it [s]


def checked_run(scene: Scene, progress: bool = False, first: RunResult | None = None) -> CheckedRun:
    """Simulate a scene and check the run (:func:`run_scene` without the dataset): a diverged
    run is an InputError, a warning line for each check past its limit, and with ``dt: auto``
    a run that diverges or drifts past the energy tolerance repeated at half the step."""
    if first is None:  # run_scenes refused what it had to before running ``first``
        preflight(scene)
    compiled = 0.0
    for retry in range(ENERGY_RETRIES + 1):
        result = first if retry == 0 and first is not None else simulate(scene, progress=progress)
        compiled += result.compile_seconds
        diverged = result.status == step.STATUS_NONFINITE
        checks = None if diverged else run_checks(scene, result)
        # an automatic step whose run diverges or drifts past the energy tolerance is halved
        # and the run repeated (docs/method/engine.md, "Contact laws": the stable step is 1.4-2.9x
        # the bound)
        retry_worthy = diverged or checks["status"] == "energy balance error"
        halved = dataclasses.replace(scene, dt_safety=0.5 * scene.dt_safety)
        if scene.dt is not None or not retry_worthy or retry == ENERGY_RETRIES or not _fits(halved):
            break
        what = (
            "diverged (NaN)"
            if diverged
            else f"energy balance drifted {100 * checks['energy_error']:.3g} %"
        )
        scene = halved
        print(f"note: {what}; repeating at dt_safety {scene.dt_safety:g}", file=sys.stderr)
    if diverged:
        t = result.time[-1] if len(result.time) else 0.0
        raise InputError(
            "solver.dt",
            f"the simulation diverged (NaN) near t = {t:.4g} s",
            f"reduce dt below {result.dt:.3g} s or soften contact.k_n",
        )
    for line in checks["warnings"]:
        print(f"warning: {line}", file=sys.stderr)
    return CheckedRun(scene, result, checks, retry, compiled)


def response_measures(
    scene: Scene, result: RunResult, checks: dict, histories: bool = True
) -> dict[str, tuple[tuple, np.ndarray]]:
    """The response of a run as {name: (dims, values)}: the histories a study cube keeps
    (rocking, sliding, epistyle, base motion) and the measures (peaks, collapse, theta_cr;
    a penetrated run is never reported as a collapse). What :func:`scene_dataset` and a
    threshold search's file (:mod:`stonedem.study.cube`) hold of it. ``histories`` False:
    the measures alone (a search that keeps no histories), the same values."""
    time = result.time
    support = measures.supports(scene)
    free = np.array([not b.driven for b in scene.bodies])
    # the residual sliding needs only the last sample's (measured from the first's frames);
    # each sample's sliding is a row of its own
    rows = slice(None) if histories else [0, -1]
    sliding = measures.relative_sliding(
        scene, result.x[rows], result.y[rows], result.theta[rows], support
    )
    total_sliding = np.abs(sliding[:, free]).sum(axis=1)
    theta_cr = measures.rocking_theta_cr(
        scene, result.arrays.body_group, result.arrays.group_theta_cr, result.arrays.group_lean
    )
    epistyles = measures.epistyle_bodies(scene)
    collapsed = result.collapse_step >= 0 and checks["status"] != "penetrated"
    t = ("time",)
    response = {
        # peaks and first times over every step of the run, not the samples
        # (stonedem.kernels.step.track)
        "max_abs_theta": (("body",), result.peak_theta),
        "max_total_sliding": ((), result.max_total_sliding),
        "residual_total_sliding": ((), float(total_sliding[-1])),
        "max_rocking": ((), result.max_rocking),
        "theta_cr": ((), theta_cr),
        "rocking_onset_time": ((), result.rocking_onset_time),
        "collapsed": ((), np.int8(collapsed)),
        "collapse_time": ((), result.collapse_time if collapsed else float("nan")),
        "max_epistyle_displacement": (
            (),
            result.max_epistyle_displacement if epistyles else float("nan"),
        ),
    }
    if result.parts is not None:
        response.update(part_measures(scene, result, free))
    if not histories:
        return response
    d_h, v_h, a_h = scene.horizontal.evaluate(time)
    rocking = np.abs(result.theta[:, measures.rocking_bodies(scene)]).mean(axis=1)
    rel = result.x - result.x[0] - d_h[:, None]
    epi = rel[:, epistyles].mean(axis=1) if epistyles else np.full(len(time), np.nan)
    if result.parts is not None:
        part_of = np.full(len(time), -1, dtype=np.int32)
        for k, (a, b) in enumerate(zip(result.parts["first_sample"], result.parts["last_sample"])):
            part_of[a : b + 1] = k if a >= 0 else -1
        response["sequence_part"] = (t, part_of)
    return {
        "base_displacement": (t, d_h),
        "base_velocity": (t, v_h),
        "base_acceleration": (t, a_h),
        "displacement_relative_to_base": (("time", "body"), rel),
        "sliding": (("time", "body"), sliding),
        "total_sliding": (t, total_sliding),
        "rocking": (t, rocking),
        "epistyle_displacement": (t, epi),
        **response,
    }


def part_measures(scene: Scene, result: RunResult, free: np.ndarray) -> dict:
    """A sequence's measures per part (dimension ``part``): peaks over the part's window,
    residuals at its end (the end of its rest), the part it collapsed in. Sliding and
    rocking are measured from the sequence's start, so a residual carries into the next
    part's peak."""
    parts = result.parts
    ran = parts["last_sample"] >= 0
    rows = parts["last_sample"][ran]
    support = measures.supports(scene)
    sliding = measures.relative_sliding(
        scene,
        result.x[np.r_[0, rows]],
        result.y[np.r_[0, rows]],
        result.theta[np.r_[0, rows]],
        support,
    )[1:]
    residual_sliding = np.full(len(ran), np.nan)
    residual_sliding[ran] = np.abs(sliding[:, free]).sum(axis=1)
    residual_rocking = np.full(len(ran), np.nan)
    rocking = measures.rocking_bodies(scene)
    residual_rocking[ran] = np.abs(result.theta[rows][:, rocking]).mean(axis=1)
    p = ("part",)
    return {
        "part_max_rocking": (p, parts["max_rocking"]),
        "part_max_total_sliding": (p, parts["max_total_sliding"]),
        "part_max_epistyle_displacement": (p, parts["max_epistyle_displacement"]),
        "part_residual_total_sliding": (p, residual_sliding),
        "part_residual_rocking": (p, residual_rocking),
        "part_collapsed": (p, parts["collapsed"]),
        "part_collapse_time": (p, parts["collapse_time"]),
        "part_at_rest_from": (p, parts["at_rest_from"]),
        "part_run": (p, parts["run"]),
    }


def sequence_coords(scene: Scene, result: RunResult) -> dict:
    """The ``part`` coordinates of a sequence's dataset: index, start time, description."""
    motion = scene.horizontal
    labels = [excitation_label(p.description) for p in motion.parts]
    return {
        "part": (("part",), np.arange(len(motion.parts), dtype=np.int32)),
        "part_start": (("part",), np.asarray(result.parts["start"], dtype=float)),
        "part_description": (("part",), np.array(labels, dtype=object)),
    }


def scene_dataset(scene: Scene, result: RunResult, checks: dict | None = None) -> xr.Dataset:
    """Dataset of one simulated scene: histories, energies, response measures, provenance.

    ``checks``: :func:`stonedem.engine.simulate.run_checks` (computed here when not given); a
    penetrated run is never reported as a collapse."""
    time = result.time
    names = scene.body_names
    d_v, _, _ = scene.vertical.evaluate(time)
    e = result.energy
    kinetic = e[:, step.ENERGY_KINETIC]
    potential = e[:, step.ENERGY_POTENTIAL] - e[0, step.ENERGY_POTENTIAL]
    elastic = e[:, step.ENERGY_ELASTIC]
    diss_n = e[:, step.ENERGY_DAMPING]
    diss_t = e[:, step.ENERGY_TANGENTIAL]
    base_work = e[:, step.ENERGY_BASE_WORK]
    balance = kinetic + potential + elastic + diss_n + diss_t - base_work
    balance = balance - (kinetic[0] + elastic[0])
    if checks is None:
        checks = run_checks(scene, result)
    response = response_measures(scene, result, checks)

    tb = ("time", "body")
    data_vars = schema_variables(
        {
            "x": (tb, result.x),
            "y": (tb, result.y),
            "theta": (tb, result.theta),
            "base_vertical_displacement": (("time",), d_v),
            "energy_kinetic": (("time",), kinetic),
            "energy_potential": (("time",), potential),
            "energy_elastic": (("time",), elastic),
            "energy_dissipated": (("time",), diss_n + diss_t),
            "energy_dissipated_normal": (("time",), diss_n),
            "energy_dissipated_tangential": (("time",), diss_t),
            "energy_base_work": (("time",), base_work),
            "energy_balance_error": (("time",), balance),
            "n_contact": (("time",), result.n_contact.astype(np.int32)),
            **response,
        }
    )
    coords = schema_variables(
        {
            "time": (("time",), time),
            "body": (("body",), np.array(names, dtype=object)),
            "body_role": (("body",), np.array([b.role for b in scene.bodies], dtype=object)),
            "body_column": (("body",), np.array([b.column for b in scene.bodies], dtype=np.int32)),
            "body_mass": (("body",), np.array([b.mass for b in scene.bodies])),
            "body_inertia": (("body",), np.array([b.inertia for b in scene.bodies])),
            "body_support": (("body",), np.array(measures.supports(scene), dtype=np.int32)),
            **({} if result.parts is None else sequence_coords(scene, result)),
        }
    )
    attrs = {
        "title": f"stonedem rigid-block simulation: {scene.spec.get('name', 'scene')}",
        "source": code_version(),
        "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')} simulated by "
        "stonedem.engine.simulate",
        "platform": f"python {platform.python_version()}, numba {numba.__version__}",
        "scene": bounded_json(scene.spec, "scene", check=check_interrupt),
        "excitation": bounded_json(
            scene.horizontal.description, "excitation", check=check_interrupt
        ),
        "excitation_vertical": bounded_json(
            scene.vertical.description, "excitation.vertical", check=check_interrupt
        ),
        "dt": result.dt,
        "dt_units": "s",
        "dt_stability_limit": result.dt_limit,
        "dt_safety": scene.dt_safety if scene.dt is None else result.dt / result.dt_limit,
        "dt_mode": "auto" if scene.dt is None else "given",
        "output_interval": result.out_every * result.dt,
        **contact_attrs(scene),
        "gravity": scene.gravity,
        "depth": scene.depth,
        "duration": scene.duration,
        "n_steps": result.n_steps,
        "steps_run": result.steps_run,
        "stop_on_collapse": int(scene.stop_on_collapse),
        "skip_quiet": int(scene.skip_quiet),
        "quiet_lead_skipped": result.quiet_lead,
        "quiet_lead_skipped_units": "s",
        "at_rest_from": result.rest_time,
        "at_rest_from_units": "s",
        "status": checks["status"],
        "energy_error": checks["energy_error"],
        "energy_error_definition": "max |energy balance drift| / energy the run moves "
        "(stonedem.engine.simulate.energy_drift)",
        "energy_error_limit": float(ENERGY_TOLERANCE),
        "penetration": checks["penetration"],
        "penetration_definition": "largest overlap of two bodies over the samples / the "
        "smaller body's area",
        "penetration_limit": float(PENETRATION_LIMIT),
        "wall_seconds": result.wall_seconds,
        "compile_seconds": result.compile_seconds,
        "compile_seconds_units": "s",
        "compile_seconds_definition": "wall time to compile the time loop or load it from "
        "Numba's cache before its "
        "first step, not in wall_seconds (the stepping)",
        "kernel": result.kernel,
        "kernel_definition": "the compiled loop the run started on: contact_graph (the scene's "
        "face contacts, "
        "stonedem.kernels.contact_graph) or general (broad phase and separating axes)",
        "general_from": result.handover_time,
        "general_from_units": "s",
        "general_from_definition": "time from which the general loop went on where the contact "
        "graph stopped "
        "holding, NaN: never",
        "general_because": result.handover_reason,
        "integrator": "central difference (leapfrog form), thesis Eq. 3.7-3.16",
    }
    if scene.links:
        data_vars, coords, attrs = with_links(scene, result, data_vars, coords, attrs)
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def with_links(scene: Scene, result: RunResult, data_vars: dict, coords: dict, attrs: dict):
    """The dataset's variables, coordinates and attributes with the scene's shear links: each
    link's final status, peak force and plastic slip (stonedem.kernels.links)."""
    from stonedem.kernels.links import LINK_STATUS

    names = scene.body_names
    links = scene.links
    data_vars = {
        **data_vars,
        **schema_variables(
            {
                "link_status": (("link",), result.link_status.astype(np.int8)),
                "link_peak_force": (("link",), result.link_peak),
                "link_plastic_slip": (("link",), result.link_slip),
            }
        ),
    }
    data_vars["link_status"].attrs.update(
        flag_values=np.arange(len(LINK_STATUS), dtype=np.int8),
        flag_meanings=" ".join(LINK_STATUS),
    )
    coords = {
        **coords,
        **schema_variables(
            {
                "link": (("link",), np.arange(len(links), dtype=np.int32)),
                "link_lower": (("link",), np.array([names[k.lower] for k in links], dtype=object)),
                "link_upper": (("link",), np.array([names[k.upper] for k in links], dtype=object)),
                "link_kind": (("link",), np.array([k.kind for k in links], dtype=object)),
            }
        ),
    }
    attrs = {
        **attrs,
        "links": bounded_json([k.description(names) for k in links], "links"),
        "links_definition": "shear links (stonedem.engine.links): elastic-perfectly plastic "
        "shear with a clearance, broken beyond the ultimate slip; pull-out resistance up to "
        "the embedment, then pulled out; their stored energy is in energy_elastic and their "
        "losses in energy_dissipated_tangential",
        "links_units": "at, ultimate_slip, gap, embedment: m; stiffness: N m-1; capacity, "
        "pullout: N",
    }
    return data_vars, coords, attrs


def contact_attrs(scene: Scene) -> dict:
    """The contact law and friction of a scene, as a run's dataset states them in its attrs."""
    law = scene.contact
    return {
        "contact_model": law.model,
        "contact_law": LAWS[law.model].describe,
        "k_n": law.k_n,
        "k_n_units": "N m-2",
        "c_n": law.params.get("c_n", 0.0),
        "c_n_units": "N s m-1",
        "contact_damping": law.params.get("damping", 0.0),
        "contact_damping_units": "1",
        "contact_impact": law.params.get("impact", "none"),
        "k_t": law.k_t,
        "k_t_units": "N m-1",
        "c_t": law.c_t,
        "c_t_units": "N s m-1",
        "friction": scene.friction,
        "contact_frame": law.frame,
    }


# A tiny scene per compiled time loop whose run calls every compiled kernel a study run on that loop
# calls, with the argument types of every study run (one specialisation each;
# tests/engine/test_simulate.py checks them against the study's cases): the point law runs on its
# contact graph (stonedem.kernels.contact_graph), the area law on the general loop compiled with the
# area law alone (stonedem.kernels.step.run_area); general_point is the general loop with the point
# law alone (run_point), where a point-law run goes on when its graph stops holding.
WARM_SCENES = {
    loop: {
        "name": f"warm_compile_{loop}",
        "structure": {"kind": "column", "n_drums": 2, "height": 2.0, "width": 0.5},
        "contact": contact,
        "friction": 0.5,
        "excitation": {"kind": "harmonic", "amplitude": 0.01, "frequency": 1.0},
        "solver": {"duration": 0.01, "kernel": kernel},
        "output": {"every": 0.005},
    }
    for loop, contact, kernel in (
        ("contact_graph", {"model": "point", "k_n": 1.0e10}, "auto"),
        ("general", {"model": "area", "k_n": 1.0e9, "c_n": 5.0}, "auto"),
        ("general_point", {"model": "point", "k_n": 1.0e10}, "general"),
    )
}
# the loops the workflow compiles before its jobs fan out (workflow/rules/compile.smk): what the
# study's runs start on. None of them hands over to general_point; one that does compiles it there.
STUDY_LOOPS = ("contact_graph", "general")


def warm_compile(loops=None) -> dict[str, float]:
    """Compile the engine's compiled code, or load it from Numba's cache, by running the
    :data:`WARM_SCENES` of ``loops`` (default: all) through :func:`run_scene`, 0.01 s of
    simulated time each: the time loop and the kernels of a run's set-up and checks (broad
    phase, clipping, excitation, penetration), for the same argument types as any study run.
    The workflow's ``compile_kernels`` jobs, one per loop, call it before the jobs that run the
    engine start, so that those load the cache instead of compiling side by side. Returns
    {loop: seconds of its compile (attrs ``compile_seconds``)}: 22 s (contact_graph) and ~29 s
    (general, general_point) on 2 cores with an empty cache, 0.02 s each from a full one."""
    from stonedem.engine.scene import scene_from_dict

    return {
        loop: float(run_scene(scene_from_dict(WARM_SCENES[loop])).attrs["compile_seconds"])
        for loop in (WARM_SCENES if loops is None else loops)
    }
