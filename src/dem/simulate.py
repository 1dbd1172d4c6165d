"""Run one scene: pack it into kernel arrays, choose or check dt, call the compiled loop, write.

Python sets up (:func:`pack_scene`, :func:`stability_limit`), Numba runs
(:func:`dem.kernels.step.run`, called in a few chunks so long runs can show progress), and
Python turns the samples into a self-describing dataset (:mod:`dem.dataset`).
"""

from __future__ import annotations

import math
import sys
import time as wallclock
from dataclasses import dataclass

import numpy as np

from dem import geometry
from dem.errors import InputError
from dem.kernels import step
from dem.kernels.contact import N_ENERGY_ACC, N_MEMORY
from dem.kernels.overlap import FRAME_BOUNDARY, FRAME_THESIS
from dem.scene import Scene, initial_pose, posed_vertices


FRAME_RULES = {"boundary": FRAME_BOUNDARY, "thesis": FRAME_THESIS}


@dataclass(frozen=True)
class SceneArrays:
    """Read-only structure-of-arrays description of a scene for the kernels."""

    vert_start: np.ndarray  # body b owns vertices vert_start[b]:vert_start[b+1] (n_body + 1,)
    local_x: np.ndarray  # vertex x in the body frame, relative to the centroid (n_vert,) [m]
    local_y: np.ndarray  # vertex y in the body frame (n_vert,) [m]
    body_mass: np.ndarray  # (n_body,) [kg]
    body_inertia: np.ndarray  # about the centroid (n_body,) [kg m2]
    body_driven: np.ndarray  # 1 = follows the base motion (n_body,) bool
    body_radius: np.ndarray  # bounding radius about the centroid (n_body,) [m]
    ref_x: np.ndarray  # centroid at rest; driven bodies move as ref + base displacement [m]
    ref_y: np.ndarray
    ref_theta: np.ndarray  # [rad]
    pair_mu: np.ndarray  # friction coefficient of every pair (n_body, n_body) [1]
    body_group: np.ndarray  # collapse group (column or single body), -1 for none (n_body,)
    group_theta_cr: np.ndarray  # atan(b/h) of each group at rest (n_group,) [rad]
    fall_depth: np.ndarray  # centroid drop meaning the body fell off (n_body,) [m]
    init_x: np.ndarray  # pose and velocity at t = 0 (n_body,)
    init_y: np.ndarray
    init_theta: np.ndarray
    init_vx: np.ndarray
    init_vy: np.ndarray
    init_omega: np.ndarray
    sweep_axis: int  # 0 = x, 1 = y
    margin: float  # broad-phase margin [m]


def pack_scene(scene: Scene) -> SceneArrays:
    """Flatten a scene into the arrays the kernels read."""
    bodies = scene.bodies
    n = len(bodies)
    vert_start = np.zeros(n + 1, dtype=np.int64)
    local_x, local_y = [], []
    mass = np.empty(n)
    inertia = np.empty(n)
    driven = np.zeros(n, dtype=np.bool_)
    radius = np.empty(n)
    ref = np.zeros((n, 3))
    init = np.zeros((n, 6))
    _, v_h0, _ = scene.horizontal.evaluate(np.array([0.0]))
    _, v_v0, _ = scene.vertical.evaluate(np.array([0.0]))
    for i, body in enumerate(bodies):
        c = body.centroid
        local = body.vertices - c
        local_x.append(local[:, 0])
        local_y.append(local[:, 1])
        vert_start[i + 1] = vert_start[i] + len(local)
        mass[i] = body.mass
        inertia[i] = body.inertia
        driven[i] = body.driven
        radius[i] = float(np.max(np.hypot(local[:, 0], local[:, 1])))
        ref[i] = (c[0], c[1], 0.0)
        x0, y0, th0 = initial_pose(body)
        # free bodies start moving with the base unless told otherwise, so the start is smooth
        vel = body.velocity if body.velocity is not None else (float(v_h0[0]), float(v_v0[0]), 0.0)
        init[i] = (x0, y0, th0, *vel)

    mu_body = np.array([b.friction if b.friction is not None else scene.friction for b in bodies])
    pair_mu = np.minimum.outer(mu_body, mu_body)  # thesis 3.8: the smaller of the two
    names = scene.body_names
    for (a, b), mu in scene.pair_friction.items():
        i, j = names.index(a), names.index(b)
        pair_mu[i, j] = pair_mu[j, i] = mu

    groups: dict = {}
    body_group = np.full(n, -1, dtype=np.int64)
    for i, body in enumerate(bodies):
        if body.driven:
            continue
        key = ("column", body.tier, body.column) if body.column >= 0 else ("body", i)
        body_group[i] = groups.setdefault(key, len(groups))
    group_theta_cr = np.empty(len(groups))
    for key, g in groups.items():
        members = np.flatnonzero(body_group == g)
        verts = np.vstack([bodies[i].vertices for i in members])
        width, height = np.ptp(verts, axis=0)
        group_theta_cr[g] = math.atan2(width, height)  # thesis Eq. 6.2
    fall_depth = np.array([0.5 * np.ptp(b.vertices[:, 1]) for b in bodies])

    extent = np.ptp(np.vstack([b.vertices for b in bodies if not b.driven]), axis=0)
    free_sizes = np.array([np.ptp(b.vertices, axis=0).min() for b in bodies if not b.driven])
    return SceneArrays(
        vert_start=vert_start, local_x=np.concatenate(local_x), local_y=np.concatenate(local_y),
        body_mass=mass, body_inertia=inertia, body_driven=driven, body_radius=radius,
        ref_x=ref[:, 0].copy(), ref_y=ref[:, 1].copy(), ref_theta=ref[:, 2].copy(),
        pair_mu=np.ascontiguousarray(pair_mu), body_group=body_group,
        group_theta_cr=group_theta_cr, fall_depth=fall_depth,
        init_x=init[:, 0].copy(), init_y=init[:, 1].copy(), init_theta=init[:, 2].copy(),
        init_vx=init[:, 3].copy(), init_vy=init[:, 4].copy(), init_omega=init[:, 5].copy(),
        sweep_axis=int(extent[1] >= extent[0]),
        margin=0.1 * float(free_sizes.min()),
    )


def stability_limit(scene: Scene) -> float:
    """Largest stable central-difference step [s]: min over bodies of 2/omega (sqrt(1+z^2) - z).

    omega^2 bounds the body's highest contact frequency (Gershgorin, factor 2 for moving
    neighbours): 2 (sum k_ij / m + sum k_ij (l^2/12 + d^2) / I) over the bodies it touches
    at rest, with k_ij = max(k_n l_ij, k_t), l_ij the shared length of their bounds and d_ij
    the distance from the centroid to the shared patch; z is the damping ratio of the
    dashpots on that stiffness (explicit-integration limit with damping).
    """
    law = scene.contact
    c = max(law.c_n, law.c_t)
    posed = [posed_vertices(b) for b in scene.bodies]
    lo = np.array([p.min(axis=0) for p in posed])
    hi = np.array([p.max(axis=0) for p in posed])
    size = np.maximum(hi - lo, 1e-12)
    limit = math.inf
    for i, body in enumerate(scene.bodies):
        if body.driven:
            continue
        k_trans = 0.0
        k_rot = 0.0
        n_touch = 0
        centre = geometry.centroid(posed[i])
        for j in range(len(posed)):
            if j == i:
                continue
            tol = 1e-3 * np.minimum(size[i], size[j])
            overlap = np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j])
            if np.any(overlap < -tol):
                continue
            length = float(max(overlap.max(), 0.0))
            patch = 0.5 * (np.maximum(lo[i], lo[j]) + np.minimum(hi[i], hi[j]))
            d2 = float(np.sum((patch - centre) ** 2))
            k_pair = max(law.k_n * length, law.k_t)
            k_trans += k_pair
            k_rot += k_pair * (length**2 / 12.0 + d2)
            n_touch += 1
        if n_touch == 0:
            # a body touching nothing at rest: bound by a contact as long as its own size
            length = float(size[i].max())
            k_trans = max(law.k_n * length, law.k_t)
            k_rot = k_trans * (length**2 / 12.0 + float(np.sum(size[i] ** 2)) / 4.0)
            n_touch = 1
        omega = math.sqrt(2.0 * (k_trans / body.mass + k_rot / body.inertia))
        zeta = n_touch * c / (2.0 * math.sqrt(k_trans * body.mass))
        limit = min(limit, 2.0 / omega * (math.sqrt(1.0 + zeta**2) - zeta))
    return limit


def choose_time_step(scene: Scene) -> tuple[float, float]:
    """(dt, stability limit) [s]: the given dt if stable, else dt_safety x the limit when auto."""
    limit = stability_limit(scene)
    if scene.dt is None:
        return scene.dt_safety * limit, limit
    if scene.dt > limit:
        raise InputError("solver.dt", f"{scene.dt:.3g} s exceeds the stability limit {limit:.3g} s "
                         "(2/omega of the stiffest contact on the lightest body)",
                         f"use dt <= {limit:.3g} s or dt: auto")
    return scene.dt, limit


@dataclass
class RunResult:
    """Raw samples of one run, before they become a dataset."""

    time: np.ndarray  # (n_sample,) [s]
    x: np.ndarray  # (n_sample, n_body) [m]
    y: np.ndarray
    theta: np.ndarray  # [rad]
    energy: np.ndarray  # (n_sample, N_ENERGY) [J], columns step.ENERGY_*
    n_contact: np.ndarray  # (n_sample,)
    status: int
    collapse_sample: int
    dt: float
    dt_limit: float
    out_every: int
    n_steps: int
    steps_run: int
    wall_seconds: float


def simulate(scene: Scene, progress: bool = False, chunks: int = 20) -> RunResult:
    """Run a scene to its duration (or its collapse) and return the samples."""
    dt, limit = choose_time_step(scene)
    if scene.dt is None:
        # round the automatic step down so samples fall exactly every output interval
        dt = scene.output_every / math.ceil(scene.output_every / dt - 1e-9)
    arrays = pack_scene(scene)
    n_steps = int(math.ceil(scene.duration / dt - 1e-9))
    out_every = max(1, int(round(scene.output_every / dt)))
    n_out = n_steps // out_every + 2
    n_body = len(scene.bodies)
    out_x = np.full((n_out, n_body), np.nan)
    out_y = np.full((n_out, n_body), np.nan)
    out_theta = np.full((n_out, n_body), np.nan)
    out_energy = np.full((n_out, step.N_ENERGY), np.nan)
    out_n_contact = np.zeros(n_out, dtype=np.int64)
    out_step = np.zeros(n_out, dtype=np.int64)
    bx, by, bth = arrays.init_x.copy(), arrays.init_y.copy(), arrays.init_theta.copy()
    bvx, bvy, bom = arrays.init_vx.copy(), arrays.init_vy.copy(), arrays.init_omega.copy()
    pair_ft = np.zeros((n_body, n_body))
    pair_memory = np.zeros((n_body, n_body, N_MEMORY))
    energy_acc = np.zeros(N_ENERGY_ACC)
    h, v = scene.horizontal, scene.vertical
    a = arrays
    n_sample, collapse_sample, status = 0, -1, step.STATUS_OK
    bounds = np.linspace(0, n_steps + 1, max(1, chunks) + 1).astype(np.int64)
    start = wallclock.perf_counter()
    for k in range(len(bounds) - 1):
        status, n_sample, collapse_sample = step.run(
            a.vert_start, a.local_x, a.local_y, a.body_mass, a.body_inertia, a.body_driven,
            a.body_radius, a.ref_x, a.ref_y, a.ref_theta, a.pair_mu,
            scene.contact.k_n, scene.contact.c_n, scene.contact.k_t, scene.contact.c_t,
            FRAME_RULES[scene.contact.frame], scene.gravity, a.body_group, a.group_theta_cr, a.fall_depth,
            h.kind, h.params, h.table_accel, h.table_vel, h.table_disp, h.table_dt,
            v.kind, v.params, v.table_accel, v.table_vel, v.table_disp, v.table_dt,
            dt, int(bounds[k]), int(bounds[k + 1]), n_steps, out_every, a.margin, a.sweep_axis,
            scene.stop_on_collapse, bx, by, bth, bvx, bvy, bom,
            pair_ft, pair_memory, energy_acc,
            out_step, out_x, out_y, out_theta, out_energy, out_n_contact, n_sample, collapse_sample,
        )
        if progress:
            done = (k + 1) / (len(bounds) - 1)
            print(f"\r  {100 * done:5.1f} %  t = {bounds[k + 1] * dt:8.3f} s  "
                  f"wall {wallclock.perf_counter() - start:7.1f} s", end="", file=sys.stderr)
        if status != step.STATUS_OK:
            break
    wall = wallclock.perf_counter() - start
    if progress:
        print(file=sys.stderr)
    steps_run = int(out_step[n_sample - 1]) if n_sample else 0
    return RunResult(
        time=out_step[:n_sample] * dt, x=out_x[:n_sample], y=out_y[:n_sample],
        theta=out_theta[:n_sample], energy=out_energy[:n_sample],
        n_contact=out_n_contact[:n_sample], status=int(status),
        collapse_sample=int(collapse_sample), dt=dt, dt_limit=limit, out_every=out_every,
        n_steps=n_steps, steps_run=int(steps_run), wall_seconds=wall,
    )


def run_scene(scene: Scene, progress: bool = False):
    """Simulate a scene and return its self-describing xarray Dataset (see :mod:`dem.dataset`)."""
    from dem.dataset import scene_dataset

    result = simulate(scene, progress=progress)
    if result.status == step.STATUS_NONFINITE:
        t = result.time[-1] if len(result.time) else 0.0
        raise InputError("solver.dt", f"the simulation diverged (NaN) near t = {t:.4g} s",
                         f"reduce dt below {result.dt:.3g} s or soften contact.k_n")
    return scene_dataset(scene, result)
