"""Run one scene: pack it into kernel arrays, choose or check dt, call the compiled loop, check.

Python sets up (:func:`pack_scene`, :func:`stability_limit`, :func:`preflight`) and bundles
the kernel's inputs (:func:`kernel_model` and the other named tuples of
:mod:`stonedem.kernels.step`), Numba runs (:func:`stonedem.kernels.step.run`, called in a few chunks
so long runs can show progress), and Python checks the samples (:func:`run_checks`). The
computing side only: :mod:`stonedem.engine.run` (run_scene) turns the samples into a dataset, and
nothing here imports it or xarray.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import threading
import time as wallclock
from dataclasses import dataclass, field

import numba
import numpy as np
from numba._dispatcher import compute_fingerprint

from stonedem.engine import geometry
from stonedem.engine.graph import contact_graph as scene_graph
from stonedem.engine.graph import why_broken
from stonedem.engine.laws import LAWS, general_loop
from stonedem.engine.links import anchor_point
from stonedem.engine.memory import memory_budget, run_bytes
from stonedem.engine.pack import SceneArrays, kernel_model, landing_drops, pack_scene
from stonedem.engine.quiet import REST_SECONDS, REST_SPEED, carry, quiet_steps, settled_state
from stonedem.engine.scene import Scene, box_pairs, posed_vertices
from stonedem.entry import check_interrupt, deferred_signals, progress_print
from stonedem.errors import InputError
from stonedem.kernels import contact_graph, step
from stonedem.kernels import excitation as kx
from stonedem.kernels.contact import E_BASE_WORK, N_ENERGY_ACC, N_MEMORY
from stonedem.motion.excitation import KIND_SEQUENCE, sequence_offsets


class BodiesMemo:
    """The last value of ``function(scene, *args)``, a function of the scene's bodies and
    contact law alone, kept while the next scene has the same bodies (the same tuple, held
    here so its id is not reused) and an equal law: a run's preflight and plan ask twice, and a
    threshold search's runs share their bodies (stonedem.study.runner.SearchScenes)."""

    def __init__(self, function):
        self.function = function
        self.last: tuple | None = None  # (bodies, contact, value)

    def __call__(self, scene: Scene, *args):
        last = self.last
        if last is not None and last[0] is scene.bodies and last[1] == scene.contact:
            return last[2]
        value = self.function(scene, *args)
        self.last = (scene.bodies, scene.contact, value)
        return value


def stability_limit(scene: Scene) -> float:
    """Largest stable central-difference step [s]: min over bodies of 2/omega (sqrt(1+z^2) - z).

    omega^2 bounds the body's highest contact frequency (Gershgorin, factor 2 for moving
    neighbours): 2 (sum k_ij / m + sum k_ij (l^2/12 + d^2) / I) over the bodies it touches
    at rest, with k_ij = max(k_n l_ij, k_t), l_ij the shared length of their bounds and d_ij
    the distance from the centroid to the shared patch; z is the damping ratio of the
    dashpots on that stiffness (explicit-integration limit with damping).
    """
    law = scene.contact
    row = LAWS[law.model]
    # rotational stiffness of a face contact of length l about its middle: k l^2 / 12 for
    # the Winkler layer (area law), k l^2 / 4 for two end points (point law)
    arm2 = row.arm2
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
            c_sum += max(row.pair_dashpot(law, length, body.mass), law.c_t)
        if k_trans == 0.0:
            # a body touching nothing at rest: bound by a contact as long as its own size
            length = float(size[i].max())
            k_trans = max(law.k_n * length, law.k_t)
            k_rot = k_trans * (arm2 * length**2 + float(np.sum(size[i] ** 2)) / 4.0)
            c_sum = max(row.pair_dashpot(law, length, body.mass), law.c_t)
        for link in scene.links:  # a shear link is one more spring on the bodies it joins
            if i in (link.lower, link.upper):
                k_trans += link.stiffness
                k_rot += link.stiffness * float(np.sum((anchor_point(scene, link) - centre) ** 2))
        omega = math.sqrt(2.0 * (k_trans / body.mass + k_rot / body.inertia))
        zeta = c_sum / (2.0 * math.sqrt(k_trans * body.mass))
        limit = min(limit, 2.0 / omega * (math.sqrt(1.0 + zeta**2) - zeta))
    return limit


kept_stability_limit = BodiesMemo(stability_limit)
# the faces in contact at t = 0 of the packed bodies (graph.contact_graph reads only what the
# bodies give the packed arrays: shapes, poses, driven, margin)
body_graph = BodiesMemo(lambda scene, arrays: scene_graph(arrays))


def run_time_step(scene: Scene) -> tuple[float, float]:
    """(dt, stability limit) [s] of a run: :func:`choose_time_step`, sampled
    (:func:`sampled_step`)."""
    dt, limit = choose_time_step(scene)
    return sampled_step(scene, dt), limit


# an automatic step divides this clock, so it does not depend on output.every (which is a
# whole number of ticks in every scene we ship): the same scene sampled every 5 ms or every
# 0.25 s runs the same steps, and its peaks agree to the last bit
STEP_CLOCK = 1.0e-3


def sampled_step(scene: Scene, dt: float) -> float:
    """An automatic step rounded down to divide :data:`STEP_CLOCK` (and so the output
    interval, when that is a whole number of ticks; else the output interval itself), so
    samples fall exactly on steps."""
    if scene.dt is None:
        every = scene.output_every
        ticks = round(every / STEP_CLOCK)
        base = (
            STEP_CLOCK if ticks >= 1 and abs(ticks * STEP_CLOCK - every) <= 1e-9 * every else every
        )
        return base / max(1, math.ceil(base / dt - 1e-9))
    return dt


def choose_time_step(scene: Scene) -> tuple[float, float]:
    """(dt, stability limit) [s]: the given dt if stable, else dt_safety x the limit when
    auto, shortened where needed to resolve the excitation (MIN_STEPS_PER_PERIOD steps in
    its shortest period: a record sampled at 400 Hz asks for dt <= 0.25 ms)."""
    limit = kept_stability_limit(scene)
    if scene.dt is None:
        resolve = (
            min(m.shortest_period for m in (scene.horizontal, scene.vertical))
            / MIN_STEPS_PER_PERIOD
        )
        return min(scene.dt_safety * limit, resolve), limit
    if scene.dt > limit:
        raise InputError(
            "solver.dt",
            f"{scene.dt:.3g} s exceeds the stability limit {limit:.3g} s "
            "(2/omega of the stiffest contact on the lightest body)",
            f"use dt <= {limit:.3g} s or dt: auto",
        )
    return scene.dt, limit


# the compiled loop runs in chunks of about this much wall time: a signal is handled
# between chunks, and each call costs ~20 us of dispatch (0.01 % at 0.2 s)
CHUNK_SECONDS = 0.2
FIRST_CHUNK_STEPS = 2000


class Progress:
    """Progress of a run on stderr: a line redrawn twice a second on a terminal, else a log
    line after 1 s and then every LOG_SECONDS (nothing for a run shorter than 1 s); and a
    notice when compiling the time loop takes a while, with a line saying how long it took."""

    LOG_SECONDS = 5.0

    COMPILE_NOTICE_SECONDS = 2.0

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr
        self.tty = getattr(self.stream, "isatty", lambda: False)()
        self.last = 0.0
        self.drawn = False
        self.lock = threading.Lock()
        self.notice = None
        self.busy = False  # a compile is under way
        self.noticed = False  # and its notice was printed

    def compiling(self):
        """A compiled loop is being compiled (or loaded from the cache): a notice if that takes
        more than COMPILE_NOTICE_SECONDS, rather than sit silent."""
        with self.lock:
            self.busy, self.noticed = True, False
        self.notice = threading.Timer(self.COMPILE_NOTICE_SECONDS, self._compiling)
        self.notice.daemon = True
        self.notice.start()

    def _compiling(self):
        with self.lock:
            if self.busy:
                self.noticed = True
                # the times the message gives: docs/notebook.md, "Measurements moved out of the
                # code"
                self.stream = progress_print(
                    self.stream,
                    "  compiling the time loop (first run after install or an "
                    "edit: 20-35 s; cached after that)",
                )

    def compiled(self, seconds: float):
        """The compile ended after ``seconds``: one line saying so when its notice was printed."""
        with self.lock:
            self.busy = False
            if self.notice is not None:
                self.notice.cancel()
            if self.noticed:
                self.stream = progress_print(
                    self.stream, f"  compiled the time loop in {seconds:.1f} s"
                )

    def __call__(self, t, t_end, wall):
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
        if self.notice is not None:
            self.notice.cancel()
        if self.drawn:
            self.stream = progress_print(self.stream, "")


def compile_for(dispatcher, args, progress: Progress | None = None) -> float:
    """Compile a jitted ``dispatcher`` for the types of ``args`` (Numba's own typing of a call,
    so the call then finds that very specialisation), or load it from the cache, before a
    timed call; the seconds it took, 0.0 where it was loaded already in this process or runs
    as plain Python (NUMBA_DISABLE_JIT). ``progress``: its compile notice while it takes a while."""
    if not hasattr(dispatcher, "overloads"):
        return 0.0
    # Numba's own fingerprint of the arguments' types (what a call dispatches on): ~0.01 ms, where
    # typing them (numba.typeof) takes ~1 ms a run, a fifth of what a search's run may cost in
    # Python
    try:
        key = (id(dispatcher), tuple((type(arg), compute_fingerprint(arg)) for arg in args))
    except (
        NotImplementedError,
        ValueError,
        TypeError,
    ):  # a value Numba cannot fingerprint: typed below
        key = None
    if key is not None and key in _READY:
        return 0.0
    signature = tuple(numba.typeof(arg) for arg in args)
    if signature in dispatcher.overloads:
        if key is not None:
            _READY.add(key)
        return 0.0
    if progress is not None:
        progress.compiling()
    start = wallclock.perf_counter()
    try:
        dispatcher.compile(signature)
    finally:
        seconds = wallclock.perf_counter() - start
        if progress is not None:
            progress.compiled(seconds)
    if key is not None:
        _READY.add(key)
    return seconds


# (loop, its arguments' type fingerprints) compiled or loaded in this process (compile_for)
_READY: set = set()


@dataclass(frozen=True)
class Handover:
    """The end state of a run, the frame moved with its base so that the base is back at 0
    and at rest: poses and velocities of the bodies relative to the base, the contacts'
    memory (elastic tangential forces, contact state) and the energy accumulators. What
    :func:`simulate` starts a later run from (``start=``): a sequence's next part, or a
    second earthquake run by hand. A driven body is at its reference pose."""

    x: np.ndarray  # (n_body,) [m]
    y: np.ndarray
    theta: np.ndarray  # [rad]
    vx: np.ndarray  # [m s-1]
    vy: np.ndarray
    omega: np.ndarray  # [rad s-1]
    pair_ft: np.ndarray  # (n_body, n_body) [N]
    pair_memory: np.ndarray  # (n_body, n_body, N_MEMORY)
    energy_acc: np.ndarray  # (N_ENERGY_ACC,) [J]
    at_rest: bool  # the run ended at rest on a quiet base (its tail carried, not integrated)
    # shear links (stonedem.kernels.links): plastic slip [m], status LINK_*, peak |force| [N]
    # and stored energy [J] (n_link,): a broken or pulled-out link stays so
    link_slip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    link_status: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    link_peak: np.ndarray = field(default_factory=lambda: np.zeros(0))
    link_energy: np.ndarray = field(default_factory=lambda: np.zeros(0))


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
    # first sample at or after the collapse (the last one when it stopped the run), -1: none
    collapse_sample: int
    dt: float
    dt_limit: float
    out_every: int
    n_steps: int
    steps_run: int  # steps integrated (the quiet lead and tail are not)
    wall_seconds: float  # the compiled loop's stepping, its compile not included
    arrays: SceneArrays  # the packed scene (its checks and dataset reuse it)
    # [s] of the start carried by the base, not integrated (settled, base quiet)
    quiet_lead: float = 0.0
    # [s] at rest on a quiet base from here on (not integrated), NaN if never
    rest_time: float = math.nan
    # running maxima over every step run (stonedem.kernels.step.track; a stretch the base
    # carries at rest adds nothing to them), slots step.PEAK_*, and each body's max |theta|
    peaks: np.ndarray = None  # (N_PEAK,)
    peak_theta: np.ndarray = None  # (n_body,) [rad]
    onset_step: int = -1  # first step at which rocking exceeds theta_cr / 30, -1: never
    collapse_step: int = -1  # first step at which the structure collapsed, -1: never
    # [s] compiling the loop or loading it from the cache, before its first step
    compile_seconds: float = 0.0
    kernel: str = "general"  # the compiled loop it started on: contact_graph or general
    # [s] from which the general loop took over from the graph's, NaN: never
    handover_time: float = math.nan
    handover_reason: str = ""  # why (stonedem.engine.graph.why_broken)
    # the state at the end, in the frame of the base brought back to rest at 0: what a later
    # run starts from (simulate(scene, start=...)); None unless asked for
    end: Handover | None = None
    # a sequence's parts (simulate_sequence): per-part arrays, None for a single motion
    parts: dict | None = None
    # shear links at the end of the run (stonedem.kernels.links): plastic slip [m], status
    # LINK_*, peak |force| [N] (n_link,)
    link_slip: np.ndarray = None
    link_status: np.ndarray = None
    link_peak: np.ndarray = None

    @property
    def max_rocking(self) -> float:
        """Peak mean absolute rotation of the rocking bodies over every step [rad]."""
        return float(self.peaks[step.PEAK_ROCKING])

    @property
    def max_total_sliding(self) -> float:
        """Peak total sliding over every step [m]."""
        return float(self.peaks[step.PEAK_SLIDING])

    @property
    def max_epistyle_displacement(self) -> float:
        """Peak absolute value of the mean epistyle displacement relative to the base, over every
        step [m]."""
        return float(self.peaks[step.PEAK_EPISTYLE])

    @property
    def rocking_onset_time(self) -> float:
        """First time rocking exceeds theta_cr / 30 [s], found at every step; NaN if never."""
        return self.onset_step * self.dt if self.onset_step >= 0 else math.nan

    @property
    def collapse_time(self) -> float:
        """Time of collapse [s], found at every step; NaN if none."""
        return self.collapse_step * self.dt if self.collapse_step >= 0 else math.nan


@dataclass
class Cursor:
    """Where a run's samples stand: filled up to ``n_sample``, the collapse sample (-1: none),
    the compiled loop's wall time [s], the steps it integrated, and the time [s] its compile
    (or load from the cache) took before the first step, which ``wall`` leaves out."""

    samples: step.Samples
    n_sample: int = 0
    collapse: int = -1
    wall: float = 0.0
    steps: int = 0
    compile: float = 0.0

    def ran(self, start: int, stop: int, status: int, n_steps: int, wall: float) -> None:
        """Book a call of the loop over steps start..stop-1 that ended with ``status`` and took
        ``wall`` [s]; n_sample and collapse already hold what it returned."""
        self.wall += wall
        # steps integrated: up to the sample that stopped the run, else the chunk's end
        # (step n_steps is sampled, not integrated)
        end = (
            int(self.samples.step[self.n_sample - 1])
            if status != step.STATUS_OK
            else min(int(stop), n_steps)
        )
        self.steps += end - int(start)


def next_chunk(size: int, elapsed: float) -> int:
    """Steps in the next chunk: about CHUNK_SECONDS of work at the rate the last one ran."""
    rate = size / max(elapsed, 1e-6)
    return int(min(max(FIRST_CHUNK_STEPS, rate * CHUNK_SECONDS), 4 * size))


@dataclass
class CompiledLoop:
    """The compiled loop over one run's bundles, called in chunks of about CHUNK_SECONDS, so
    a signal (Ctrl-C) is handled within a second and progress can be shown."""

    model: step.Model
    settings: step.Settings
    state: step.State
    cursor: Cursor
    reporter: Progress | None
    loaded: list = dataclasses.field(
        default_factory=list
    )  # the compiled loops ready for this run's bundles
    # the scene's contact graph while it holds (stonedem.kernels.contact_graph), None: the general
    # loop
    graph: contact_graph.Graph | None = None
    # the step from which the general loop took over from the graph's, -1: none
    handover_step: int = -1
    started_on: str = ""  # the loop of the first call: contact_graph or general ("": not called)
    broken: tuple = ()  # why the graph stopped holding: (contact_graph.BROKEN_*, pair or contact)

    def steps(self, n: int, stop: int, step_first: int, rest_from: int) -> int:
        """One call of the compiled loop over steps n..stop-1: the contact graph's while it
        holds, then the general loop from the step it stopped holding; returns the status."""
        cursor = self.cursor
        if not self.started_on:
            self.started_on = "general" if self.graph is None else "contact_graph"
        bundles = (self.model, self.settings, self.state, cursor.samples)
        if self.graph is not None:
            args = (
                *bundles,
                self.graph,
                int(n),
                int(stop),
                step_first,
                rest_from,
                cursor.n_sample,
                cursor.collapse,
            )
            self.compiled(contact_graph.run, args)
            status, cursor.n_sample, cursor.collapse, n, broken, which = contact_graph.run(*args)
            if status != contact_graph.STATUS_GENERAL:
                return status
            self.broken = (int(broken), int(which), self.graph)
            self.graph, self.handover_step = None, int(n)
        args = (
            *bundles,
            int(n),
            int(stop),
            step_first,
            rest_from,
            cursor.n_sample,
            cursor.collapse,
        )
        # the general loop with the scene's law alone: the other law's code is never compiled
        loop = general_loop(self.model.law.kind)
        self.compiled(loop, args)
        status, cursor.n_sample, cursor.collapse = loop(*args)
        return status

    def compiled(self, loop, args) -> None:
        """Before the first call of a compiled ``loop`` in this run: compile it for ``args`` or load
        it from the cache (:func:`compile_for`), its time booked in cursor.compile, not as
        stepping."""
        if loop not in self.loaded:
            self.cursor.compile += compile_for(loop, args, self.reporter)
            self.loaded.append(loop)

    def run(self, n: int, n_stop: int, step_first: int, rest_from: int, n_chunks: int = 1) -> int:
        """Steps n..n_stop-1; returns the kernel's status. ``n_chunks`` > 1 forces at least
        that many chunks (tests compare chunkings)."""
        self.state.rest_count[0] = 0
        with deferred_signals():  # a signal is raised between chunks, never inside the kernel
            return self._chunks(n, n_stop, step_first, rest_from, n_chunks)

    def _chunks(self, n, n_stop, step_first, rest_from, n_chunks):
        cursor, n_steps, dt = self.cursor, self.settings.n_steps, self.settings.dt
        status = step.STATUS_OK
        size = max(1, (n_stop - n) // n_chunks) if n_chunks > 1 else FIRST_CHUNK_STEPS
        while n < n_stop:
            stop = min(n_stop, n + size)
            start, compiled = wallclock.perf_counter(), cursor.compile
            status = self.steps(n, stop, step_first, rest_from)
            # the chunk's stepping: a loop compiled (or loaded from the cache) before its first call
            # is not in it
            elapsed = wallclock.perf_counter() - start - (cursor.compile - compiled)
            cursor.ran(n, stop, status, n_steps, elapsed)
            n = stop
            if n_chunks <= 1:
                size = next_chunk(size, elapsed)
            if self.reporter is not None:
                self.reporter(n * dt, n_steps * dt, cursor.wall)
            if status != step.STATUS_OK:
                break
            check_interrupt()
        return status


def initial_state(arrays: SceneArrays, n_link: int = 0) -> step.State:
    """The kernel's state at t = 0: the packed initial poses and velocities, no contact memory,
    ``n_link`` shear links engaged and unloaded."""
    n_body = len(arrays.body_mass)
    return step.State(
        body_x=arrays.init_x.copy(),
        body_y=arrays.init_y.copy(),
        body_theta=arrays.init_theta.copy(),
        body_vx=arrays.init_vx.copy(),
        body_vy=arrays.init_vy.copy(),
        body_omega=arrays.init_omega.copy(),
        pair_ft=np.zeros((n_body, n_body)),
        pair_memory=np.zeros((n_body, n_body, N_MEMORY)),
        energy_acc=np.zeros(N_ENERGY_ACC),
        rest_count=np.zeros(1, dtype=np.int64),
        peaks=np.zeros(step.N_PEAK),
        peak_theta=np.zeros(n_body),
        events=np.full(step.N_EVENT, -1, dtype=np.int64),
        link_slip=np.zeros(n_link),
        link_status=np.zeros(n_link, dtype=np.int64),
        link_peak=np.zeros(n_link),
        link_energy=np.zeros(n_link),
    )


def empty_samples(n_out: int, n_body: int) -> step.Samples:
    return step.Samples(
        step=np.zeros(n_out, dtype=np.int64),
        x=np.full((n_out, n_body), np.nan),
        y=np.full((n_out, n_body), np.nan),
        theta=np.full((n_out, n_body), np.nan),
        energy=np.full((n_out, step.N_ENERGY), np.nan),
        n_contact=np.zeros(n_out, dtype=np.int64),
    )


@dataclass
class Plan:
    """One scene's run, phase by phase: what :func:`simulate` and
    :func:`stonedem.engine.ensemble.run_ensemble` hand the compiled loop, and where it stands."""

    scene: Scene
    arrays: SceneArrays  # the packed scene (its checks and dataset reuse it)
    loop: CompiledLoop
    dt: float
    limit: float
    n_first: int  # first step to integrate after the quiet lead (stonedem.engine.quiet.quiet_steps)
    n_rest: int  # step from which the base is quiet for good
    n_start: int = 0
    step_first: int = 0
    quiet_lead: float = 0.0
    status: int = step.STATUS_OK
    keep_end: bool = False  # finish_run hands the end state over (RunResult.end)


def uses_graph(scene: Scene) -> bool:
    """Whether the scene starts on the contact-graph loop (stonedem.kernels.contact_graph): under
    the point law, unless ``solver.kernel: general`` or the scene has shear links."""
    return (
        scene.kernel == "auto"
        and LAWS[scene.contact.model].code == step.CONTACT_POINT
        and not scene.links  # the graph's loop has no links: a linked scene runs the general one
    )


def plan_run(scene: Scene, progress: bool = False, start: Handover | None = None) -> Plan:
    """Time step, packed scene, bundles and quiet phases of one run; nothing integrated yet.
    ``start``: the state it starts from (:func:`start_state`), else the scene's at rest."""
    dt, limit = run_time_step(scene)
    arrays = pack_scene(scene)  # once per run: the checks and the dataset reuse it
    n_steps = int(math.ceil(scene.duration / dt - 1e-9))
    out_every = max(1, int(round(scene.output_every / dt)))
    settings = step.Settings(
        dt=dt,
        n_steps=n_steps,
        out_every=out_every,
        stop_on_collapse=scene.stop_on_collapse,
        rest_speed=REST_SPEED,
        rest_samples=max(1, int(math.ceil(REST_SECONDS / (out_every * dt)))),
    )
    cursor = Cursor(empty_samples(n_steps // out_every + 2, len(scene.bodies)))
    loop = CompiledLoop(
        kernel_model(scene, arrays),
        settings,
        initial_state(arrays, len(scene.links))
        if start is None
        else start_state(arrays, start, len(scene.links)),
        cursor,
        Progress() if progress else None,
        graph=body_graph(scene, arrays) if uses_graph(scene) else None,
    )
    n_first, n_rest = quiet_steps(scene, dt, n_steps, out_every)
    if start is not None:
        n_first, n_rest = 0, handed_rest_step(scene, dt, n_steps)
    return Plan(scene, arrays, loop, dt, limit, n_first, n_rest)


def handed_rest_step(scene: Scene, dt: float, n_steps: int) -> int:
    """Step from which the base is still for good, for a run started from a handed-over state:
    the end of its motions' natural lengths (the quiet threshold of
    :func:`stonedem.engine.quiet.quiet_steps` holds for the reference pose only, not a leaning
    or slid one); a motion without one never is."""
    lengths = [m.duration for m in (scene.horizontal, scene.vertical) if m.kind != kx.KIND_NONE]
    if not scene.skip_quiet or any(length is None for length in lengths):
        return n_steps + 1
    return min(n_steps + 1, int(math.ceil(max(lengths, default=0.0) / dt)) + 1)


def start_state(arrays: SceneArrays, start: Handover, n_link: int = 0) -> step.State:
    """The kernel's state at t = 0 from a handed-over end state (:class:`Handover`): the free
    bodies' poses and velocities, the contacts' memory, the shear links' state and the energy
    accumulators; the driven bodies at their reference poses. The running peaks and events
    start afresh, the links' peak forces carry on."""
    state = initial_state(arrays, n_link)
    if start.pair_ft.shape != state.pair_ft.shape:
        raise InputError(
            "start",
            f"a state of {len(start.x)} bodies for a scene of {len(state.body_x)}",
            "start from the end of a run of the same bodies",
        )
    if len(start.link_slip) != n_link:
        raise InputError(
            "start",
            f"a state of {len(start.link_slip)} shear links for a scene of {n_link}",
            "start from the end of a run of the same scene",
        )
    for name in ("link_slip", "link_status", "link_peak", "link_energy"):
        getattr(state, name)[:] = getattr(start, name)
    free = ~arrays.body_driven
    for name in ("x", "y", "theta", "vx", "vy", "omega"):
        getattr(state, f"body_{name}")[free] = getattr(start, name)[free]
    state.pair_ft[:] = start.pair_ft
    state.pair_memory[:] = start.pair_memory
    state.energy_acc[:] = start.energy_acc
    return state


def end_state(plan: Plan, settled: int, last: int) -> Handover:
    """The state at the run's end as a :class:`Handover`: a run at rest on a quiet base (from
    step ``last``, sample ``settled``) carried to its end first; then the frame moved with the
    base so that it is back at 0 and at rest (a rectangular pulse leaves it moving), the
    kinetic and potential energy that takes booked as base work so the balance goes on."""
    state, scene, arrays = plan.loop.state, plan.scene, plan.arrays
    state = step.State(*(np.array(a, copy=True) for a in state))
    samples, n = plan.loop.cursor.samples, plan.loop.cursor.n_sample
    n_end = int(samples.step[n - 1]) if n > 0 else 0
    at_rest = settled >= 0
    if at_rest:
        settled_state(scene, arrays, samples, settled, last, state, n_end, plan.dt)
    free = ~arrays.body_driven
    t_end = np.array([n_end * plan.dt])
    d_h, v_h, _ = scene.horizontal.evaluate(t_end)
    d_v, v_v, _ = scene.vertical.evaluate(t_end)
    x, y = state.body_x.copy(), state.body_y.copy()
    vx, vy = state.body_vx.copy(), state.body_vy.copy()
    x[free], y[free] = x[free] - d_h[0], y[free] - d_v[0]
    vx[free], vy[free] = vx[free] - v_h[0], vy[free] - v_v[0]
    x[~free], y[~free] = arrays.ref_x[~free], arrays.ref_y[~free]
    vx[~free], vy[~free] = 0.0, 0.0
    m = np.where(free, arrays.body_mass, 0.0)
    changed = 0.5 * np.sum(m * (vx**2 + vy**2 - state.body_vx**2 - state.body_vy**2))
    changed += scene.gravity * np.sum(m * (y - state.body_y))
    energy_acc = state.energy_acc.copy()
    energy_acc[E_BASE_WORK] += changed
    theta, omega = state.body_theta.copy(), state.body_omega.copy()
    theta[~free], omega[~free] = arrays.ref_theta[~free], 0.0
    return Handover(
        x,
        y,
        theta,
        vx,
        vy,
        omega,
        state.pair_ft,
        state.pair_memory,
        energy_acc,
        at_rest,
        state.link_slip,
        state.link_status,
        state.link_peak,
        state.link_energy,
    )


def settle_phase(plan: Plan) -> tuple[int, int, int, int] | None:
    """(start, stop, first, rest_from) of the settling from t = 0, at most until the first
    loud sample, or None when the run has no quiet lead."""
    return (0, plan.n_first, 0, 0) if plan.n_first > 0 else None


def after_settle(plan: Plan, status: int) -> None:
    """Settled: carried by the base to the first loud sample; still settling there: carry
    straight on; anything else ends the run with that status."""
    cursor, state = plan.loop.cursor, plan.loop.state
    settings = plan.loop.settings
    if status == step.STATUS_AT_REST:
        settled = cursor.n_sample - 1  # the last integrated sample
        cursor.n_sample, last = carry(
            plan.scene,
            plan.arrays,
            cursor.samples,
            cursor.n_sample,
            plan.n_first,
            plan.dt,
            settings.out_every,
        )
        settled_state(
            plan.scene, plan.arrays, cursor.samples, settled, last, state, plan.n_first, plan.dt
        )
        plan.n_start, plan.step_first, plan.quiet_lead = (
            plan.n_first,
            plan.n_first,
            (plan.n_first - last) * plan.dt,
        )
    elif status == step.STATUS_OK:
        plan.n_start = plan.n_first
    else:
        plan.status = status


def main_phase(plan: Plan) -> tuple[int, int, int, int] | None:
    """(start, stop, first, rest_from) of the run on from the settled state, or None if it ended."""
    if plan.status != step.STATUS_OK:
        return None
    return (
        plan.n_start,
        plan.loop.settings.n_steps + 1,
        plan.step_first,
        max(plan.n_rest, plan.n_start),
    )


def finish_run(plan: Plan) -> RunResult:
    """The run's result: the quiet tail's samples filled when it came to rest on a quiet base."""
    cursor, state, settings = plan.loop.cursor, plan.loop.state, plan.loop.settings
    dt, n_steps, status = plan.dt, settings.n_steps, plan.status
    rest_time = math.nan
    settled, last = -1, -1
    if status == step.STATUS_AT_REST:  # the quiet tail; the kernel samples the last step too
        settled = cursor.n_sample - 1
        cursor.n_sample, last = carry(
            plan.scene,
            plan.arrays,
            cursor.samples,
            cursor.n_sample,
            n_steps,
            dt,
            settings.out_every,
            including=True,
        )
        rest_time, status = last * dt, step.STATUS_OK
    end = end_state(plan, settled, last) if plan.keep_end else None
    n, samples = cursor.n_sample, cursor.samples
    return RunResult(
        time=samples.step[:n] * dt,
        x=samples.x[:n],
        y=samples.y[:n],
        theta=samples.theta[:n],
        energy=samples.energy[:n],
        n_contact=samples.n_contact[:n],
        status=int(status),
        collapse_sample=int(cursor.collapse),
        dt=dt,
        dt_limit=plan.limit,
        out_every=settings.out_every,
        n_steps=n_steps,
        steps_run=int(cursor.steps),
        wall_seconds=cursor.wall,
        compile_seconds=cursor.compile,
        quiet_lead=plan.quiet_lead,
        rest_time=rest_time,
        arrays=plan.arrays,
        peaks=state.peaks.copy(),
        peak_theta=state.peak_theta.copy(),
        onset_step=int(state.events[step.EVENT_ONSET]),
        collapse_step=int(state.events[step.EVENT_COLLAPSE]),
        kernel=plan.loop.started_on
        or "general",  # the ensemble runner's members run the general loop
        handover_time=plan.loop.handover_step * dt if plan.loop.handover_step >= 0 else math.nan,
        handover_reason=why_broken(*plan.loop.broken, plan.scene.body_names)
        if plan.loop.broken
        else "",
        end=end,
        link_slip=state.link_slip.copy(),
        link_status=state.link_status.copy(),
        link_peak=state.link_peak.copy(),
    )


def simulate(
    scene: Scene,
    progress: bool = False,
    chunks: int | None = None,
    start: Handover | None = None,
    keep_end: bool = False,
) -> RunResult:
    """Run a scene to its duration (or its collapse) and return the samples.

    With ``skip_quiet`` (:func:`stonedem.engine.quiet.quiet_steps`): the scene first settles
    on its contacts from t = 0 until at rest; the settled state is then carried rigidly by
    the base over the rest of the quiet lead (samples filled, nothing integrated) and
    integration resumes at the sample before the first loud instant; once the base is quiet
    for good and every body is at rest on it, the remaining samples are filled the same way.
    ``chunks``: calls of the compiled loop, for tests (default 1: chunks of CHUNK_SECONDS).
    ``start``: a state handed over by an earlier run (its ``end``, :class:`Handover`), the run
    integrated from t = 0 on (no quiet lead) and at rest once its motion has ended;
    ``keep_end``: the result's ``end`` is its end state, for a later run to start from. A
    sequence of motions (``excitation: {kind: sequence}``) runs part by part
    (:func:`simulate_sequence`).
    """
    if scene.horizontal.kind == KIND_SEQUENCE:
        if start is not None:
            raise InputError(
                "start", "a sequence starts at rest", "start each part's scene instead"
            )
        return simulate_sequence(scene, progress, chunks)
    plan = plan_run(scene, progress, start)
    plan.keep_end = keep_end
    try:
        phase = settle_phase(plan)
        if phase is not None:
            after_settle(plan, plan.loop.run(*phase))
        phase = main_phase(plan)
        if phase is not None:
            plan.status = plan.loop.run(*phase, chunks or 1)
    finally:
        if plan.loop.reporter is not None:
            plan.loop.reporter.finish()
    return finish_run(plan)


def simulate_sequence(scene: Scene, progress: bool = False, chunks: int | None = None) -> RunResult:
    """Run a sequence of motions (``excitation: {kind: sequence}``) part by part, each part
    a run of its own motion over its window (its natural length and the rest after it; the
    last part to the scene's duration), started from the state the part before it handed
    over (:class:`Handover`): residual sliding, rotation, open joints and contact memory
    carry over, the time loop stays compiled, and a rest at rest is carried, not integrated.
    Every part runs at the sequence's step (its shortest period and the scene's stability
    limit); a duration shorter than the sequence ends it early. The samples are joined on the
    sequence's clock, in the frame of its composite base motion
    (:func:`stonedem.motion.excitation.sequence_offsets`); a part that collapses (and stops)
    ends the sequence. ``RunResult.parts`` holds what each part did."""
    motion = scene.horizontal
    dt, _ = run_time_step(scene)
    results, start = [], None
    for k, part in enumerate(motion.parts):
        t0 = motion.starts[k]
        if k > 0 and t0 >= scene.duration:  # a shorter run than the sequence (preflight
            break  # refuses one; a test or a script may run its start)
        t1 = motion.starts[k + 1] if k + 1 < len(motion.parts) else scene.duration
        t1 = min(t1, scene.duration)
        part_scene = dataclasses.replace(scene, horizontal=part, duration=t1 - t0, dt=dt)
        result = simulate(part_scene, progress, chunks, start=start, keep_end=True)
        results.append(result)
        if result.status != step.STATUS_OK:
            break
        start = result.end
    return join_parts(scene, results)


def join_parts(scene: Scene, results: list[RunResult]) -> RunResult:
    """One RunResult of a sequence's part runs: samples on the sequence's clock (each part's
    first sample, the state handed over, left out), positions in the frame of the composite
    base motion, running peaks the largest of the parts', first events the first part's to
    have one (to the nearest step), and ``parts``: per-part arrays over every part of the
    sequence (NaN for parts not run after a collapse)."""
    motion = scene.horizontal
    offsets = sequence_offsets(motion)
    first, dt = results[0], results[0].dt
    n_part = len(motion.parts)
    pieces, n_sample, collapse_sample = [], 0, -1
    parts = {
        "start": np.array(motion.starts, dtype=float),
        "run": np.zeros(n_part, dtype=np.int8),
        "first_sample": np.full(n_part, -1, dtype=np.int64),
        "last_sample": np.full(n_part, -1, dtype=np.int64),
        "max_rocking": np.full(n_part, np.nan),
        "max_total_sliding": np.full(n_part, np.nan),
        "max_epistyle_displacement": np.full(n_part, np.nan),
        "collapsed": np.zeros(n_part, dtype=np.int8),
        "collapse_time": np.full(n_part, np.nan),
        "at_rest_from": np.full(n_part, np.nan),
    }
    onset_step = collapse_step = -1
    for k, r in enumerate(results):
        t0 = motion.starts[k]
        keep = slice(None) if k == 0 else slice(1, None)
        local = r.time[keep]
        shift = offsets[k][0] + offsets[k][1] * local
        pieces.append(
            (t0 + local, r.x[keep] + shift[:, None], r.y[keep], r.theta[keep])
            + (r.energy[keep], r.n_contact[keep])
        )
        if collapse_sample < 0 and r.collapse_sample >= 0:
            collapse_sample = n_sample + r.collapse_sample - (0 if k == 0 else 1)
        parts["run"][k] = 1
        parts["first_sample"][k] = n_sample
        n_sample += len(local)
        parts["last_sample"][k] = n_sample - 1
        parts["max_rocking"][k] = r.max_rocking
        parts["max_total_sliding"][k] = r.max_total_sliding
        parts["max_epistyle_displacement"][k] = r.max_epistyle_displacement
        parts["collapsed"][k] = int(r.collapse_step >= 0)
        parts["collapse_time"][k] = t0 + r.collapse_time
        parts["at_rest_from"][k] = t0 + r.rest_time
        if onset_step < 0 and r.onset_step >= 0:
            onset_step = int(round(t0 / dt)) + r.onset_step
        if collapse_step < 0 and r.collapse_step >= 0:
            collapse_step = int(round(t0 / dt)) + r.collapse_step
    time, x, y, theta, energy, n_contact = (np.concatenate(a) for a in zip(*pieces))
    last = results[-1]
    handover = next((r for r in results if r.handover_reason), None)
    return RunResult(
        time=time,
        x=x,
        y=y,
        theta=theta,
        energy=energy,
        n_contact=n_contact,
        status=last.status,
        collapse_sample=collapse_sample,
        dt=dt,
        dt_limit=first.dt_limit,
        out_every=first.out_every,
        n_steps=sum(r.n_steps for r in results),
        steps_run=sum(r.steps_run for r in results),
        wall_seconds=sum(r.wall_seconds for r in results),
        arrays=first.arrays,
        quiet_lead=first.quiet_lead,
        rest_time=motion.starts[len(results) - 1] + last.rest_time,
        peaks=np.max([r.peaks for r in results], axis=0),
        peak_theta=np.max([r.peak_theta for r in results], axis=0),
        onset_step=onset_step,
        collapse_step=collapse_step,
        compile_seconds=sum(r.compile_seconds for r in results),
        kernel=first.kernel,
        handover_time=math.nan
        if handover is None
        else motion.starts[results.index(handover)] + handover.handover_time,
        handover_reason="" if handover is None else handover.handover_reason,
        parts=parts,
        # the links' state carries from part to part: the last part's is the sequence's
        link_slip=last.link_slip,
        link_status=last.link_status,
        link_peak=last.link_peak,
    )


# a run whose energy balance drifts by more than this share of the energy it moves says so
# (status and stderr); measured: every run at dt <= the stability limit stays under it
# (docs/method/checks.md, "Stability"), so a larger drift flags a contact or step problem
ENERGY_TOLERANCE = 0.01
ENERGY_FLOOR = 1e-3  # smallest energy scale of energy_error, x initial kinetic + potential energy
# an overlap of two bodies beyond this share of the smaller one's area is not a contact
# but a body sinking into another (a contact too soft for its load, or a sliver body)
PENETRATION_LIMIT = 0.05


def energy_drift(result: RunResult) -> dict:
    """Drift of the energy balance from its start, relative to two energy scales [1].

    Balance = kinetic + potential + elastic + damping + tangential - base work; it stays
    constant in an exact integration, and a positive drift is energy created.
    energy_error: max abs(drift) / the energy the run moves around, max kinetic + max
    abs(change of potential) + max abs(base work), but at least ENERGY_FLOOR x the initial
    energy (a free-rocking block moves 2 % of its potential energy above the base, so the
    initial energy would hide large errors; a column settling before a record starts moves
    only a few J). energy_created: max drift on the same scale. energy_error_total: max
    abs(drift) / initial kinetic + potential energy (datum: the base's top). All NaN if not
    finite. A sequence's (``result.parts``): the largest of its parts', each measured as a run
    of its own from the state handed over (two records drift twice as far as one).
    """
    if result.parts is not None:
        return parts_drift(result)
    e = result.energy
    kinetic, potential = e[:, step.ENERGY_KINETIC], e[:, step.ENERGY_POTENTIAL]
    work = e[:, step.ENERGY_BASE_WORK]
    balance = (
        kinetic
        + potential
        + e[:, step.ENERGY_ELASTIC]
        + e[:, step.ENERGY_DAMPING]
        + e[:, step.ENERGY_TANGENTIAL]
        - work
    )
    if len(balance) == 0 or not np.all(np.isfinite(balance)):
        return {
            "energy_error": math.nan,
            "energy_created": math.nan,
            "energy_error_total": math.nan,
        }
    total = abs(kinetic[0]) + abs(potential[0])
    moved = kinetic.max() + np.abs(potential - potential[0]).max() + np.abs(work).max()
    moved = max(moved, ENERGY_FLOOR * total)
    drift = balance - balance[0]
    return {
        "energy_error": float(np.abs(drift).max() / moved),
        "energy_created": float(drift.max() / moved),
        "energy_error_total": float(np.abs(drift).max() / total),
    }


def parts_drift(result: RunResult) -> dict:
    """:func:`energy_drift` of each part of a sequence, from the sample handed over (base work
    counted from there), the largest of each figure (NaN if any is)."""
    worst: dict = {}
    first, last = result.parts["first_sample"], result.parts["last_sample"]
    for k, (a, b) in enumerate(zip(first, last)):
        if b < 0:
            continue
        e = result.energy[(a - 1 if k else 0) : b + 1].copy()
        e[:, step.ENERGY_BASE_WORK] -= e[0, step.ENERGY_BASE_WORK]
        drift = energy_drift(dataclasses.replace(result, energy=e, parts=None))
        for key, value in drift.items():
            worst[key] = value if math.isnan(value) else max(worst.get(key, value), value)
    return worst


def penetration(scene: Scene, result: RunResult) -> tuple[float, float, str, str]:
    """(deepest overlap / smaller body's area [1], its time [s], the two body names) over the
    samples."""
    from stonedem.kernels.penetration import deepest_overlap

    arrays = result.arrays
    areas = np.array([geometry.signed_area(b.vertices) for b in scene.bodies])
    share, s, a, b = deepest_overlap(
        arrays.vert_start,
        arrays.local_x,
        arrays.local_y,
        areas,
        np.ascontiguousarray(result.x),
        np.ascontiguousarray(result.y),
        np.ascontiguousarray(result.theta),
    )
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
        warnings.append(
            f"bodies {a} and {b} overlap by {100 * share:.3g} % of the smaller one's area at "
            f"t = {when:.4g} s (limit {100 * PENETRATION_LIMIT:g} %): the contact is too soft for "
            "the load or a body is a sliver; raise contact.k_n or thicken the body"
        )
    elif energy["energy_error"] > ENERGY_TOLERANCE:
        status = "energy balance error"
        warnings.append(
            f"the energy balance drifted by {100 * energy['energy_error']:.3g} % of the energy the "
            f"run moves (limit {100 * ENERGY_TOLERANCE:g} %); lower solver.dt_safety"
        )
    return {
        "status": status,
        "warnings": warnings,
        "penetration": share,
        "penetration_time": when,
        **energy,
    }


# resources a run may ask for; above them it is refused before computing (docs/guide/scenes.md, its
# table of limits)
MAX_STEPS = 2e8  # ~50x the study's longest case; 3-30 min of kernel time at 1-10 us/step
# the memory a run needs (samples, dataset, write) against a share of the machine's:
# stonedem.engine.memory.run_bytes and memory_budget
MAX_DURATION = 3600.0  # [s] simulated; the quiet-base scan holds ~8 doubles per ms of it
# the step must resolve the excitation: at least this many steps per period of its highest
# frequency (harmonic, one-sine pulse), per rectangular pulse and per record sample interval x 2
MIN_STEPS_PER_PERIOD = 20


def output_samples(scene: Scene, dt: float) -> float:
    """Output samples of a run at step ``dt`` (the samples simulate() allocates)."""
    return scene.duration / dt / max(1.0, round(scene.output_every / dt)) + 2


def _every_fix(scene: Scene, chosen: float, budget: float) -> str:
    """The fix of a run too long or too big for its output interval: the smallest
    output.every (2 significant digits, rounded up) at which its steps and memory fit,
    checked with the step that interval gives (:func:`sampled_step` of ``chosen``)."""
    n_body = len(scene.bodies)
    fixed = run_bytes(0, n_body)
    per_sample = run_bytes(1, n_body) - fixed
    room = budget - fixed - 2 * per_sample
    if room <= 0:
        return f"use fewer bodies: their contacts alone need {fixed / 2**30:.3g} GiB"
    every = max(scene.output_every, scene.duration / MAX_STEPS, scene.duration * per_sample / room)
    while every < scene.duration:
        scale = 10.0 ** (math.floor(math.log10(every)) - 1)
        every = math.ceil(every / scale * (1 - 1e-12)) * scale  # 2 significant digits, up
        trial = dataclasses.replace(scene, output_every=every)
        dt = sampled_step(trial, chosen)
        if (
            scene.duration / dt <= MAX_STEPS
            and run_bytes(output_samples(trial, dt), n_body) <= budget
        ):
            return f"raise output.every to {every:.2g} s or more, or shorten the run"
        every *= 1.05
    return "shorten the run or use fewer bodies"


def preflight(scene: Scene) -> tuple[float, float, int]:
    """(dt, stability limit [s], steps) of a scene, or an InputError before any computing.

    Refused: a scene whose bodies would fall freely (nothing driven, or a body with nothing
    under it to land on: :func:`stonedem.engine.pack.landing_drops`), a stability limit that is not
    a positive finite time, more than MAX_STEPS steps, more memory than the machine can give it
    (:func:`stonedem.engine.memory.run_bytes` against :func:`stonedem.engine.memory.memory_budget`),
    and a step that resolves the excitation's shortest period in fewer than MIN_STEPS_PER_PERIOD
    steps (it would read an 8 kHz harmonic at its zeros). When output.every is what makes a run too
    long or too big, the refusal names it and the smallest value that fits.
    """
    landing_drops(scene)
    motion = scene.horizontal
    if motion.kind == KIND_SEQUENCE and scene.duration < motion.duration * (1 - 1e-12):
        raise InputError(
            "solver.duration",
            f"{scene.duration:.6g} s ends before the sequence's last rest does "
            f"({motion.duration:.6g} s: its parts and their rests)",
            f"give solver.duration >= {motion.duration:.6g} s",
        )
    dt, limit = choose_time_step(scene)
    if not (math.isfinite(limit) and limit > 0.0 and dt > 0.0):
        raise InputError(
            "contact.k_n",
            f"the stability limit is {limit:.3g} s",
            "check masses and contact stiffness (SI units)",
        )
    chosen, dt = dt, sampled_step(scene, dt)  # as simulate()
    if scene.duration > MAX_DURATION:
        raise InputError(
            "solver.duration",
            f"{scene.duration:.3g} s is over the limit {MAX_DURATION:g} s",
            "simulate at most an hour; split a longer run",
        )
    budget = memory_budget()
    n_steps = scene.duration / dt
    if n_steps > MAX_STEPS:
        if (
            scene.output_every < chosen and scene.duration / chosen <= MAX_STEPS
        ):  # dt <= output.every
            raise InputError(
                "output.every",
                f"{scene.output_every:.3g} s makes dt = {dt:.3g} s: {n_steps:.3g} "
                f"steps over {scene.duration:.3g} s, over the limit {MAX_STEPS:.0e}",
                _every_fix(scene, chosen, budget),
            )
        raise InputError(
            "solver.duration",
            f"{scene.duration:.3g} s at dt = {dt:.3g} s is {n_steps:.3g} steps, "
            f"over the limit {MAX_STEPS:.0e}",
            f"shorten the run, raise solver.dt_safety (now {scene.dt_safety:g}) or soften "
            "contact.k_n",
        )
    n_out = output_samples(scene, dt)
    need = run_bytes(n_out, len(scene.bodies))
    if need > budget:
        raise InputError(
            "output.every",
            f"{n_out:.3g} samples of {len(scene.bodies)} bodies need about "
            f"{need / 2**30:.3g} GiB, over the {budget / 2**30:.3g} GiB a run may take here "
            "(stonedem.engine.memory.memory_budget)",
            _every_fix(scene, chosen, budget),
        )
    for name, motion in (("excitation", scene.horizontal), ("excitation.vertical", scene.vertical)):
        period = motion.shortest_period
        if period / dt < MIN_STEPS_PER_PERIOD:
            raise InputError(
                "solver.dt",
                f"dt = {dt:.3g} s resolves the {name}'s shortest period {period:.3g} s "
                f"in {period / dt:.3g} steps, fewer than {MIN_STEPS_PER_PERIOD}",
                f"use solver.dt <= {period / MIN_STEPS_PER_PERIOD:.3g} s, or a slower excitation",
            )
    return dt, limit, int(math.ceil(n_steps - 1e-9))
