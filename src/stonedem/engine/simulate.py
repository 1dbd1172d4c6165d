"""Run one scene: pack it into kernel arrays, choose or check dt, call the compiled loop, check.

Python sets up (:func:`pack_scene`, :func:`stability_limit`, :func:`preflight`) and bundles
the kernel's inputs (:func:`kernel_model` and the other named tuples of
:mod:`stonedem.kernels.step`), Numba runs (:func:`stonedem.kernels.step.run`, called in a few chunks
so long runs can show progress), and Python checks the samples (:func:`run_checks`). The
computing side only: :mod:`stonedem.engine.run` (run_scene) turns the samples into a dataset, and
nothing here imports it or xarray.
"""

from __future__ import annotations

import math
import sys
import time as wallclock
from dataclasses import dataclass

import numpy as np

from stonedem.engine import geometry
from stonedem.entry import check_interrupt, deferred_signals, progress_print
from stonedem.errors import InputError
from stonedem.kernels import excitation as kx
from stonedem.kernels import step
from stonedem.kernels.contact import N_ENERGY_ACC, N_MEMORY
from stonedem.kernels.overlap import FRAME_BOUNDARY, FRAME_THESIS
from stonedem.engine.scene import Scene, box_pairs, initial_pose, posed_vertices


# "faces": the point law's own frame (stonedem.kernels.point_contact), which ignores frame_rule
FRAME_RULES = {"boundary": FRAME_BOUNDARY, "thesis": FRAME_THESIS, "faces": FRAME_BOUNDARY}
CONTACT_MODELS = {"area": step.CONTACT_AREA, "point": step.CONTACT_POINT}


def contact_damping(law) -> float:
    """The kernel's damping argument: c_n [N s m-1] (area law) or zeta [1] (point law)."""
    return law.damping if law.model == "point" else law.c_n


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


def kernel_model(scene: Scene, arrays: SceneArrays) -> step.Model:
    """The read-only bundle :func:`stonedem.kernels.step.run` reads: arrays, contact law, gravity, base motion."""
    law = scene.contact

    def excitation(motion):
        return step.Excitation(kind=int(motion.kind), params=motion.params, table_accel=motion.table_accel,
                               table_vel=motion.table_vel, table_disp=motion.table_disp,
                               table_dt=float(motion.table_dt))

    return step.Model(
        vert_start=arrays.vert_start, local_x=arrays.local_x, local_y=arrays.local_y,
        body_mass=arrays.body_mass, body_inertia=arrays.body_inertia, body_driven=arrays.body_driven,
        body_radius=arrays.body_radius, ref_x=arrays.ref_x, ref_y=arrays.ref_y, ref_theta=arrays.ref_theta,
        pair_mu=arrays.pair_mu, body_group=arrays.body_group, group_theta_cr=arrays.group_theta_cr,
        fall_depth=arrays.fall_depth, margin=arrays.margin, sweep_axis=arrays.sweep_axis,
        gravity=scene.gravity,
        law=step.Law(kind=CONTACT_MODELS[law.model], k_n=law.k_n, damping=contact_damping(law),
                     impact=law.impact == "plastic", k_t=law.k_t, c_t=law.c_t,
                     frame_rule=FRAME_RULES[law.frame]),
        horizontal=excitation(scene.horizontal), vertical=excitation(scene.vertical),
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
    point = law.model == "point"
    # rotational stiffness of a face contact of length l about its middle: k l^2 / 12 for
    # the Winkler layer (area law), k l^2 / 4 for two end points (point law)
    arm2 = 0.25 if point else 1.0 / 12.0
    posed = [posed_vertices(b) for b in scene.bodies]
    lo = np.array([p.min(axis=0) for p in posed])
    hi = np.array([p.max(axis=0) for p in posed])
    size = np.maximum(hi - lo, 1e-12)
    # candidate neighbours from the broad phase (a superset of the touching ones), each
    # body's in ascending order as a full scan would visit them
    neighbours = [[] for _ in posed]
    for i, j in box_pairs(lo, hi, 0.5e-3 * float(size.max())):
        neighbours[i].append(j)
        neighbours[j].append(i)
    limit = math.inf
    for i, body in enumerate(scene.bodies):
        if body.driven:
            continue
        k_trans = 0.0
        k_rot = 0.0
        c_sum = 0.0
        centre = geometry.centroid(posed[i])
        for j in sorted(neighbours[i]):
            tol = 1e-3 * np.minimum(size[i], size[j])
            overlap = np.minimum(hi[i], hi[j]) - np.maximum(lo[i], lo[j])
            if np.any(overlap < -tol):
                continue
            length = float(max(overlap.max(), 0.0))
            patch = 0.5 * (np.maximum(lo[i], lo[j]) + np.minimum(hi[i], hi[j]))
            d2 = float(np.sum((patch - centre) ** 2))
            k_pair = max(law.k_n * length, law.k_t)
            k_trans += k_pair
            k_rot += k_pair * (arm2 * length**2 + d2)
            c_sum += max(_pair_dashpot(law, length, body.mass), law.c_t)
        if k_trans == 0.0:
            # a body touching nothing at rest: bound by a contact as long as its own size
            length = float(size[i].max())
            k_trans = max(law.k_n * length, law.k_t)
            k_rot = k_trans * (arm2 * length**2 + float(np.sum(size[i] ** 2)) / 4.0)
            c_sum = max(_pair_dashpot(law, length, body.mass), law.c_t)
        omega = math.sqrt(2.0 * (k_trans / body.mass + k_rot / body.inertia))
        zeta = c_sum / (2.0 * math.sqrt(k_trans * body.mass))
        limit = min(limit, 2.0 / omega * (math.sqrt(1.0 + zeta**2) - zeta))
    return limit


def _pair_dashpot(law, length: float, mass: float) -> float:
    """Normal dashpot [N s m-1] of a face contact of the given length on a body of this mass."""
    if law.model == "point":
        # two end points, each 2 zeta sqrt(K m) with K = k_n l / 2
        return 2.0 * 2.0 * law.damping * math.sqrt(0.5 * law.k_n * length * mass)
    return law.c_n


QUIET_MARGIN = 0.5  # the base counts as quiet below half the smallest acceleration that could move a body
REST_SPEED = 1e-3  # [m s-1] a body slower than this relative to the base is at rest
REST_SECONDS = 0.5  # [s] ... for this long in a row, with the base quiet for good: the run ends


def quiet_threshold(scene: Scene) -> float:
    """Base acceleration over gravity below which no body can slide or rock: a lower bound [1].

    A body slides only if a/g exceeds the smallest friction coefficient; an assembly above
    a joint rocks only if a/g exceeds (half the joint width) / (height of its centroid above
    the joint), which is at least (narrowest free body) / (2 x height of the free structure).
    Halved (QUIET_MARGIN), so the soft contacts' own vibration has no part in it either.
    """
    free = [posed_vertices(b) for b in scene.bodies if not b.driven]
    mu = [b.friction if b.friction is not None else scene.friction for b in scene.bodies]
    mu_min = min(min(mu), *scene.pair_friction.values()) if scene.pair_friction else min(mu)
    width = min(float(np.ptp(v[:, 0])) for v in free)
    height = float(np.ptp(np.vstack(free)[:, 1]))
    return QUIET_MARGIN * min(mu_min, width / (2.0 * height))


def quiet_steps(scene: Scene, dt: float, n_steps: int, out_every: int) -> tuple[int, int]:
    """(first step to integrate, step from which the base is quiet for good).

    Quiet: |a_h| < threshold x (g - |a_v|) and |a_v| < g / 2 (:func:`quiet_threshold`). A
    scene released at rest in its reference pose moves rigidly with the base through a
    quiet lead, so the run starts at the sample before the first loud instant; a scene with
    a tilt or an initial velocity starts at 0, and so does one whose base is never loud
    (it still settles on its contacts). Checked on a grid no coarser than the
    record's samples (between which a record is linear) or 1 ms.
    """
    if not scene.skip_quiet:
        return 0, n_steps + 1
    h, v = scene.horizontal, scene.vertical
    spacing = min(scene.output_every, 1e-3, *(m.table_dt for m in (h, v) if m.table_dt > 0))
    grid = np.arange(0.0, scene.duration + spacing, spacing)
    _, _, a_h = h.evaluate(grid)
    _, _, a_v = v.evaluate(grid)
    ratio = quiet_threshold(scene)
    loud = (np.abs(a_h) >= ratio * (scene.gravity - np.abs(a_v))) | (np.abs(a_v) >= 0.5 * scene.gravity)
    if not loud.any():
        first_loud, last_loud = 0.0, 0.0  # nothing to skip but the settled rest at the end
    else:
        first_loud, last_loud = grid[np.argmax(loud)], grid[len(loud) - 1 - np.argmax(loud[::-1])]
    at_rest = all(b.driven or (b.tilt_angle == 0.0 and b.velocity is None) for b in scene.bodies)
    n_first = 0
    if at_rest:
        n_first = max(0, int((first_loud - spacing) / dt)) // out_every * out_every
        n_first = min(n_first, n_steps // out_every * out_every)
    n_rest = max(n_first, int(math.ceil((last_loud + spacing) / dt)))
    return n_first, n_rest


def rigid_motion(scene: Scene, arrays: SceneArrays, times, t_from, x_from, y_from, theta_from,
                 energy_from=None):
    """(x, y, theta (n_time, n_body), energy (n_time, N_ENERGY)) of the scene carried by the base.

    From the poses at t_from [s], free bodies translate with the base displacement and keep
    their rotation; driven bodies follow the base. Stored and dissipated energies stay at
    energy_from's; the base's work is what changes the kinetic and potential energy. With
    energy_from None, the base work column is left 0 (the state at t_from is the origin).
    """
    h, v = scene.horizontal, scene.vertical
    times = np.asarray(times, dtype=float)
    d_h, v_h, _ = h.evaluate(times)
    d_v, v_v, _ = v.evaluate(times)
    d_h0, _, _ = h.evaluate(np.array([t_from]))
    d_v0, _, _ = v.evaluate(np.array([t_from]))
    free = ~arrays.body_driven
    x = np.where(free, x_from[None, :] + (d_h - d_h0[0])[:, None], arrays.ref_x[None, :] + d_h[:, None])
    y = np.where(free, y_from[None, :] + (d_v - d_v0[0])[:, None], arrays.ref_y[None, :] + d_v[:, None])
    theta = np.where(free, theta_from[None, :], arrays.ref_theta[None, :])
    mass = np.where(free, arrays.body_mass, 0.0)
    energy = np.zeros((len(times), step.N_ENERGY))
    energy[:, step.ENERGY_KINETIC] = 0.5 * mass.sum() * (v_h**2 + v_v**2)
    energy[:, step.ENERGY_POTENTIAL] = scene.gravity * (y * mass[None, :]).sum(axis=1)
    if energy_from is not None:
        for col in (step.ENERGY_ELASTIC, step.ENERGY_DAMPING, step.ENERGY_TANGENTIAL):
            energy[:, col] = energy_from[col]
        gained = (energy[:, step.ENERGY_KINETIC] + energy[:, step.ENERGY_POTENTIAL]
                  - energy_from[step.ENERGY_KINETIC] - energy_from[step.ENERGY_POTENTIAL])
        energy[:, step.ENERGY_BASE_WORK] = energy_from[step.ENERGY_BASE_WORK] + gained
    return x, y, theta, energy


def choose_time_step(scene: Scene) -> tuple[float, float]:
    """(dt, stability limit) [s]: the given dt if stable, else dt_safety x the limit when
    auto, shortened where needed to resolve the excitation (MIN_STEPS_PER_PERIOD steps in
    its shortest period: a record sampled at 400 Hz asks for dt <= 0.25 ms)."""
    limit = stability_limit(scene)
    if scene.dt is None:
        resolve = min(excitation_period(m) for m in (scene.horizontal, scene.vertical)) / MIN_STEPS_PER_PERIOD
        return min(scene.dt_safety * limit, resolve), limit
    if scene.dt > limit:
        raise InputError("solver.dt", f"{scene.dt:.3g} s exceeds the stability limit {limit:.3g} s "
                         "(2/omega of the stiffest contact on the lightest body)",
                         f"use dt <= {limit:.3g} s or dt: auto")
    return scene.dt, limit


# the compiled loop runs in chunks of about this much wall time: a signal is handled
# between chunks, and each call costs ~20 us of dispatch (0.01 % at 0.2 s)
CHUNK_SECONDS = 0.2
FIRST_CHUNK_STEPS = 2000


class Progress:
    """Progress of a run on stderr: a line redrawn twice a second on a terminal, else a log
    line after 1 s and then every LOG_SECONDS (nothing for a run shorter than 1 s)."""

    LOG_SECONDS = 5.0

    COMPILE_NOTICE_SECONDS = 2.0

    def __init__(self, stream=None):
        import threading

        self.stream = stream or sys.stderr
        self.tty = getattr(self.stream, "isatty", lambda: False)()
        self.last = 0.0
        self.drawn = False
        # the first call of the compiled loop compiles it (or loads it from the cache):
        # say so when that takes a while, rather than sit silent
        self.notice = threading.Timer(self.COMPILE_NOTICE_SECONDS, self._compiling)
        self.notice.daemon = True
        self.notice.start()

    def _compiling(self):
        self.stream = progress_print(self.stream, "  compiling the time loop (first run after install or an "
                                     "edit: about 1 min; cached after that)")

    def __call__(self, t, t_end, wall):
        self.notice.cancel()
        # a log gets its first line after 1 s (the run has started), then every LOG_SECONDS
        every = 0.5 if self.tty else (self.LOG_SECONDS if self.last > 0.0 else 1.0)
        if wall - self.last < every:
            return
        self.last = wall
        line = f"  t = {t:8.3f} s of {t_end:.3f} s  ({100 * t / t_end:3.0f} %)  wall {wall:7.1f} s"
        if self.tty:
            self.stream = progress_print(self.stream, "\r" + line, end="")
            self.drawn = True
        else:
            self.stream = progress_print(self.stream, line.strip())

    def finish(self):
        self.notice.cancel()
        if self.drawn:
            self.stream = progress_print(self.stream, "")


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
    steps_run: int  # steps integrated (the quiet lead and tail are not)
    wall_seconds: float
    quiet_lead: float = 0.0  # [s] of the start carried by the base, not integrated (settled, base quiet)
    rest_time: float = math.nan  # [s] at rest on a quiet base from here on (not integrated), NaN if never


def simulate(scene: Scene, progress: bool = False, chunks: int | None = None) -> RunResult:
    """Run a scene to its duration (or its collapse) and return the samples.

    With ``skip_quiet`` (:func:`quiet_steps`): the scene first settles on its contacts from
    t = 0 until at rest; the settled state is then carried rigidly by the base over the rest
    of the quiet lead (samples filled, nothing integrated) and integration resumes at the
    sample before the first loud instant; once the base is quiet for good and every body is
    at rest on it, the remaining samples are filled the same way. ``chunks``: calls of the
    compiled loop, for progress reports (default 20 with progress, else 1: each call costs
    ~20 us of dispatch, which a benchmark of short runs would see).
    """
    if chunks is None:
        chunks = 1
    dt, limit = choose_time_step(scene)
    if scene.dt is None:
        # round the automatic step down so samples fall exactly every output interval
        dt = scene.output_every / max(1, math.ceil(scene.output_every / dt - 1e-9))
    arrays = pack_scene(scene)
    n_steps = int(math.ceil(scene.duration / dt - 1e-9))
    out_every = max(1, int(round(scene.output_every / dt)))
    n_out = n_steps // out_every + 2
    n_body = len(scene.bodies)
    model = kernel_model(scene, arrays)
    settings = step.Settings(
        dt=dt, n_steps=n_steps, out_every=out_every, stop_on_collapse=scene.stop_on_collapse,
        rest_speed=REST_SPEED, rest_samples=max(1, int(math.ceil(REST_SECONDS / (out_every * dt)))),
    )
    state = step.State(
        body_x=arrays.init_x.copy(), body_y=arrays.init_y.copy(), body_theta=arrays.init_theta.copy(),
        body_vx=arrays.init_vx.copy(), body_vy=arrays.init_vy.copy(), body_omega=arrays.init_omega.copy(),
        pair_ft=np.zeros((n_body, n_body)), pair_memory=np.zeros((n_body, n_body, N_MEMORY)),
        energy_acc=np.zeros(N_ENERGY_ACC), rest_count=np.zeros(1, dtype=np.int64),
    )
    samples = step.Samples(
        step=np.zeros(n_out, dtype=np.int64), x=np.full((n_out, n_body), np.nan),
        y=np.full((n_out, n_body), np.nan), theta=np.full((n_out, n_body), np.nan),
        energy=np.full((n_out, step.N_ENERGY), np.nan), n_contact=np.zeros(n_out, dtype=np.int64),
    )
    n_first, n_rest = quiet_steps(scene, dt, n_steps, out_every)
    h, v = scene.horizontal, scene.vertical
    tally = {"n_sample": 0, "collapse": -1, "wall": 0.0, "steps": 0}

    def integrate(n_start, n_stop, step_first, rest_from, n_chunks):
        """Compiled loop over steps n_start..n_stop-1 in chunks; returns its status.

        Chunks are sized to take about CHUNK_SECONDS each, so a signal (Ctrl-C) is
        handled within a second and progress can be shown; ``n_chunks`` > 1 forces at
        least that many (tests compare chunkings)."""
        state.rest_count[0] = 0
        with deferred_signals():  # a signal is raised between chunks, never inside the kernel
            return chunked(n_start, n_stop, step_first, rest_from, n_chunks)

    def chunked(n, n_stop, step_first, rest_from, n_chunks):
        status = step.STATUS_OK
        size = max(1, (n_stop - n) // n_chunks) if n_chunks > 1 else FIRST_CHUNK_STEPS
        while n < n_stop:
            stop = min(n_stop, n + size)
            start = wallclock.perf_counter()
            status, tally["n_sample"], tally["collapse"] = step.run(
                model, settings, state, samples, int(n), int(stop),
                step_first, rest_from, tally["n_sample"], tally["collapse"],
            )
            elapsed = wallclock.perf_counter() - start
            tally["wall"] += elapsed
            # steps integrated: up to the sample that stopped the run, else the chunk's end
            # (step n_steps is sampled, not integrated)
            if status != step.STATUS_OK:
                end = int(samples.step[tally["n_sample"] - 1])
            else:
                end = min(int(stop), n_steps)
            tally["steps"] += end - int(n)
            n = stop
            if n_chunks <= 1:
                # next chunk: about CHUNK_SECONDS of work at the rate just measured
                rate = size / max(elapsed, 1e-6)
                size = int(min(max(FIRST_CHUNK_STEPS, rate * CHUNK_SECONDS), 4 * size))
            if reporter is not None:
                reporter(n * dt, n_steps * dt, tally["wall"])
            if status != step.STATUS_OK:
                break
            check_interrupt()
        return status

    def carry_to(n_to, including=False):
        """Fill the samples after the last one up to step n_to (``including`` it), carried by the base."""
        k = tally["n_sample"] - 1
        last = int(samples.step[k])
        steps = list(range(last + out_every, n_to, out_every)) + ([n_to] if including and n_to > last else [])
        if steps:
            fill = slice(k + 1, k + 1 + len(steps))
            samples.step[fill] = steps
            filled = rigid_motion(scene, arrays, np.array(steps) * dt, last * dt, samples.x[k], samples.y[k],
                                  samples.theta[k], samples.energy[k])
            samples.x[fill], samples.y[fill], samples.theta[fill], samples.energy[fill] = filled
            samples.n_contact[fill] = samples.n_contact[k]
            tally["n_sample"] += len(steps)
        return k, last

    reporter = Progress() if progress else None
    try:
        n_start, step_first, quiet_lead = 0, 0, 0.0
        status = step.STATUS_OK
        if n_first > 0:
            # settle from t = 0 (the contacts take up the weight), at most until the first loud sample
            status = integrate(0, n_first, 0, 0, 1)
            if status == step.STATUS_AT_REST:
                k, last = carry_to(n_first)
                # the settled state at n_first: shifted with the base, moving with it; the
                # contacts' memory (in their own frames) and the dissipated energy are kept
                free = ~arrays.body_driven
                x, y, th, energy = rigid_motion(scene, arrays, np.array([n_first * dt]), last * dt,
                                                samples.x[k], samples.y[k], samples.theta[k], samples.energy[k])
                state.body_x[free], state.body_y[free] = x[0, free], y[0, free]
                state.body_theta[free] = th[0, free]
                _, v_h, _ = h.evaluate(np.array([n_first * dt]))
                _, v_v, _ = v.evaluate(np.array([n_first * dt]))
                state.body_vx[free], state.body_vy[free], state.body_omega[free] = v_h[0], v_v[0], 0.0
                # the accumulators are the accumulated energy columns (step.ENERGY_ACCUMULATED on)
                state.energy_acc[:] = energy[0, step.ENERGY_ACCUMULATED:]
                n_start, step_first = n_first, n_first
                quiet_lead = (n_first - last) * dt
                status = step.STATUS_OK
            elif status == step.STATUS_OK:
                n_start = n_first  # still settling at the first loud sample: carry straight on
                step_first = 0
        if status == step.STATUS_OK:
            status = integrate(n_start, n_steps + 1, step_first, max(n_rest, n_start), chunks)
    finally:
        if reporter is not None:
            reporter.finish()
    rest_time = math.nan
    if status == step.STATUS_AT_REST:
        # the quiet tail: at rest on a base that can no longer move anything
        _, last = carry_to(n_steps, including=True)  # the kernel samples the last step too
        rest_time = last * dt
        status = step.STATUS_OK
    n_sample = tally["n_sample"]
    return RunResult(
        time=samples.step[:n_sample] * dt, x=samples.x[:n_sample], y=samples.y[:n_sample],
        theta=samples.theta[:n_sample], energy=samples.energy[:n_sample],
        n_contact=samples.n_contact[:n_sample], status=int(status),
        collapse_sample=int(tally["collapse"]), dt=dt, dt_limit=limit, out_every=out_every,
        n_steps=n_steps, steps_run=int(tally["steps"]), wall_seconds=tally["wall"],
        quiet_lead=quiet_lead, rest_time=rest_time,
    )


# a run whose energy balance drifts by more than this share of the energy it moves says so
# (status and stderr); measured: every run at dt <= the stability limit stays under it
# (README "Stability"), so a larger drift flags a contact or step problem
ENERGY_TOLERANCE = 0.01
ENERGY_FLOOR = 1e-3  # smallest energy scale of energy_error, x initial kinetic + potential energy
# an overlap of two bodies beyond this share of the smaller one's area is not a contact
# but a body sinking into another (a contact too soft for its load, or a sliver body)
PENETRATION_LIMIT = 0.05


def energy_drift(result: RunResult) -> dict:
    """Drift of the energy balance from its start, relative to two energy scales [1].

    Balance = kinetic + potential + elastic + damping + tangential - base work; it stays
    constant in an exact integration, and a positive drift is energy created.
    energy_error: max |drift| / the energy the run moves around, max kinetic + max |change
    of potential| + max |base work|, but at least ENERGY_FLOOR x the initial energy (a
    free-rocking block moves 2 % of its potential energy above the base, so the initial
    energy would hide large errors; a column settling before a record starts moves only a
    few J). energy_created: max drift on the same scale. energy_error_total: max |drift| /
    initial kinetic + potential energy (datum: the base's top). All NaN if not finite.
    """
    e = result.energy
    kinetic, potential = e[:, step.ENERGY_KINETIC], e[:, step.ENERGY_POTENTIAL]
    work = e[:, step.ENERGY_BASE_WORK]
    balance = (kinetic + potential + e[:, step.ENERGY_ELASTIC] + e[:, step.ENERGY_DAMPING]
               + e[:, step.ENERGY_TANGENTIAL] - work)
    if len(balance) == 0 or not np.all(np.isfinite(balance)):
        return {"energy_error": math.nan, "energy_created": math.nan, "energy_error_total": math.nan}
    total = abs(kinetic[0]) + abs(potential[0])
    moved = kinetic.max() + np.abs(potential - potential[0]).max() + np.abs(work).max()
    moved = max(moved, ENERGY_FLOOR * total)
    drift = balance - balance[0]
    return {"energy_error": float(np.abs(drift).max() / moved), "energy_created": float(drift.max() / moved),
            "energy_error_total": float(np.abs(drift).max() / total)}



def penetration(scene: Scene, result: RunResult) -> tuple[float, float, str, str]:
    """(deepest overlap / smaller body's area [1], its time [s], the two body names) over the samples."""
    from stonedem.kernels.penetration import deepest_overlap

    arrays = pack_scene(scene)
    areas = np.array([geometry.signed_area(b.vertices) for b in scene.bodies])
    share, s, a, b = deepest_overlap(arrays.vert_start, arrays.local_x, arrays.local_y, areas,
                                     np.ascontiguousarray(result.x), np.ascontiguousarray(result.y),
                                     np.ascontiguousarray(result.theta))
    if s < 0:
        return 0.0, math.nan, "", ""
    names = scene.body_names
    return float(share), float(result.time[s]), names[a], names[b]


def run_checks(scene: Scene, result: RunResult) -> dict:
    """What a finished run says of itself: energy drift and deepest penetration, and the
    status they give ("penetrated" > "energy balance error" > collapse or completed)."""
    energy = energy_drift(result)
    share, when, a, b = penetration(scene, result)
    status = ["completed", "stopped at collapse", "diverged"][result.status]
    warnings = []
    if share > PENETRATION_LIMIT:
        status = "penetrated"
        warnings.append(f"bodies {a} and {b} overlap by {100 * share:.3g} % of the smaller one's area at "
                        f"t = {when:.4g} s (limit {100 * PENETRATION_LIMIT:g} %): the contact is too soft for "
                        "the load or a body is a sliver; raise contact.k_n or thicken the body")
    elif energy["energy_error"] > ENERGY_TOLERANCE:
        status = "energy balance error"
        warnings.append(f"the energy balance drifted by {100 * energy['energy_error']:.3g} % of the energy the "
                        f"run moves (limit {100 * ENERGY_TOLERANCE:g} %); lower solver.dt_safety")
    return {"status": status, "warnings": warnings, "penetration": share, "penetration_time": when, **energy}


# resources a run may ask for; above them it is refused before computing (README "Limits")
MAX_STEPS = 2e8  # ~50x the study's longest case; 3-30 min of kernel time at 1-10 us/step
MAX_SAMPLE_BYTES = 2 * 2**30  # sampled positions and energies held in memory
MAX_DURATION = 3600.0  # [s] simulated; the quiet-base scan holds ~8 doubles per ms of it
# the step must resolve the excitation: at least this many steps per period of its highest
# frequency (harmonic, one-sine pulse), per rectangular pulse and per record sample interval x 2
MIN_STEPS_PER_PERIOD = 20


def excitation_period(motion) -> float:
    """Shortest time scale [s] the step must resolve in a base motion (inf: none)."""
    p = motion.params
    if motion.kind in (kx.KIND_HARMONIC, kx.KIND_SINE_PULSE) and p[1] > 0.0:
        return 2.0 * math.pi / p[1]
    if motion.kind == kx.KIND_RECT_PULSE:
        return float(p[1])
    if motion.kind == kx.KIND_TABLE:
        return 2.0 * motion.table_dt  # the Nyquist period of the record's sampling
    return math.inf


def preflight(scene: Scene) -> tuple[float, float, int]:
    """(dt, stability limit [s], steps) of a scene, or an InputError before any computing.

    Refused: a stability limit that is not a positive finite time, more than MAX_STEPS
    steps, more than MAX_SAMPLE_BYTES of samples, and a step that resolves the excitation's
    shortest period in fewer than MIN_STEPS_PER_PERIOD steps (it would read an 8 kHz
    harmonic at its zeros).
    """
    dt, limit = choose_time_step(scene)
    if not (math.isfinite(limit) and limit > 0.0 and dt > 0.0):
        raise InputError("contact.k_n", f"the stability limit is {limit:.3g} s",
                         "check masses and contact stiffness (SI units)")
    if scene.dt is None:  # as simulate(): rounded down so samples fall on the output times
        dt = scene.output_every / max(1, math.ceil(scene.output_every / dt - 1e-9))
    if scene.duration > MAX_DURATION:
        raise InputError("solver.duration", f"{scene.duration:.3g} s is over the limit {MAX_DURATION:g} s",
                         "simulate at most an hour; split a longer run")
    n_steps = scene.duration / dt
    if n_steps > MAX_STEPS:
        raise InputError("solver.duration", f"{scene.duration:.3g} s at dt = {dt:.3g} s is {n_steps:.3g} steps, "
                         f"over the limit {MAX_STEPS:.0e}",
                         f"shorten the run, raise solver.dt_safety (now {scene.dt_safety:g}) or soften contact.k_n")
    n_out = n_steps / max(1.0, round(scene.output_every / dt)) + 2
    sample_bytes = 8.0 * n_out * (3 * len(scene.bodies) + step.N_ENERGY + 2)
    if sample_bytes > MAX_SAMPLE_BYTES:
        raise InputError("output.every", f"{n_out:.3g} samples of {len(scene.bodies)} bodies need "
                         f"{sample_bytes / 2**30:.3g} GiB, over the limit {MAX_SAMPLE_BYTES / 2**30:g} GiB",
                         "sample less often (a larger output.every) or shorten the run")
    for name, motion in (("excitation", scene.horizontal), ("excitation.vertical", scene.vertical)):
        period = excitation_period(motion)
        if period / dt < MIN_STEPS_PER_PERIOD:
            raise InputError(
                "solver.dt", f"dt = {dt:.3g} s resolves the {name}'s shortest period {period:.3g} s "
                f"in {period / dt:.3g} steps, fewer than {MIN_STEPS_PER_PERIOD}",
                f"use solver.dt <= {period / MIN_STEPS_PER_PERIOD:.3g} s, or a slower excitation")
    return dt, limit, int(math.ceil(n_steps - 1e-9))
