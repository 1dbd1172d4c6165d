"""The time loop of the 2D rigid-block engine, compiled whole (thesis 3.10, Fig. 3.14).

:func:`run` takes four bundles, named tuples of arrays and numbers that
:mod:`stonedem.engine.simulate` builds in plain Python: :class:`Model` (the scene, read only),
:class:`Settings` (time step, sampling, stopping rules), :class:`State` (poses, velocities, contact
memory, energy accumulators: carried from one call to the next) and :class:`Samples` (output
buffers). Each call allocates a :class:`Work` bundle (world vertices, bounds, forces, velocities at
t_n, candidate pairs).

Stages of one step at time t_n = n dt, numbered as in :func:`run_steps`:

1. place the bodies   place_bodies: base_motion, drive_bodies, update_world_vertices, body_bounds
   watch              track: running peaks of the response measures at t_n; collapsed
                      (every step, so neither depends on the sampling; a collapse with
                      stop_on_collapse is sampled at its own step and ends the run)
2. candidate pairs    needs_resweep; sweep when some body has moved half the margin
3. contact forces     contact_forces: clear_forces, then the scene's law from the velocities
                      v_{n-1/2} (area_contact_forces or point_contact_forces, inlined)
   shear links        link_forces (stonedem.kernels.links), only in a scene with links
4. velocities at t_n  velocities_at_step: half a kick on from v_{n-1/2}
5. power booking      contact_power and book_power: the powers at t_n, by accumulator slot
6. sampling           every ``out_every`` steps, at the last and at a collapse that stops
                      the run: sample_state, then at_rest may end the run
7. integrate          book_energy, central_difference_step: v_{n+1/2} = v_{n-1/2} + dt a_n
                      (first step: a half kick), x_{n+1} = x_n + dt v_{n+1/2}

Python never sees a single step: :func:`run` is called once per simulation phase, or in a
few chunks for progress reports. It allocates the :class:`Work` bundle and hands over to
:func:`run_steps`, the loop itself.

Performance (``snakemake bench_kernel``, its dataset kernel.nc; issue 32). Nothing the loop
calls allocates, so :func:`run_steps` and every kernel it calls are compiled without Numba's
runtime (``NO_ALLOC_OPTIONS``): with it, a compiled function handed arrays paid an atomic
increment and decrement on each of them at every call, ~40 % of a lone block's step. The
stage functions, the small kernels and both contact laws are inlined by LLVM
(``INLINE_OPTIONS``: it declined the larger ones unless told, and a call that hands over 41
arrays costs ~85 ns), so taking the bundles costs nothing and a new law is an inlined function of
(model, state, work, n_pair, dt, want_energy) and one more branch in the loop. The pair
list lives in Work's buffers (the broad phase sorts in place), the point law computes
every body's edge normals once a step, not once per pair and direction, and keeps each
touching pair's separating axes while they provably hold (Work.face_cache). Lone block: ~0.8 us
a step before, ~0.24 after; per contact, the arithmetic of the law dominates.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from stonedem.kernels import INLINE_OPTIONS, JIT_OPTIONS, NO_ALLOC_OPTIONS
from stonedem.kernels.broad_phase import body_bounds, candidate_pairs_into
from stonedem.kernels.contact import (
    E_BASE_WORK,
    E_DAMPING,
    E_TANGENTIAL,
    N_ENERGY_ACC,
    area_contact_forces,
    contact_power,
)
from stonedem.kernels.excitation import base_motion
from stonedem.kernels.integrate import central_difference_step, drive_bodies, update_world_vertices
from stonedem.kernels.links import link_forces
from stonedem.kernels.overlap import MAX_OVERLAP_VERTICES
from stonedem.kernels.point_contact import FACE_A, N_FACE_CACHE, point_contact_forces
from stonedem.kernels.scalar import isfinite

STATUS_OK = 0
STATUS_COLLAPSED = 1  # stopped early: the structure collapsed
STATUS_NONFINITE = 2  # a position or velocity became NaN or infinite
STATUS_AT_REST = 3  # stopped early: the base is quiet from here on and every body rests on it
# run_steps only: more candidate pairs than Work holds; run grows it and goes on
STATUS_PAIRS_FULL = 4

CONTACT_AREA = 0  # thesis overlap-area law (stonedem.kernels.contact)
CONTACT_POINT = 1  # point contacts at the face ends (stonedem.kernels.point_contact)

# Columns of the sampled energy array [J]: three state functions at the sample's instant,
# then the running sums of the contact accumulators (stonedem.kernels.contact E_*), slot k in
# column ENERGY_ACCUMULATED + k; the time loop adds what this step's power (book_power)
# contributes up to t_n.
ENERGY_KINETIC = 0
ENERGY_POTENTIAL = 1  # m g y of the free bodies
ENERGY_ELASTIC = 2  # stored in the contact springs
ENERGY_ACCUMULATED = 3
ENERGY_DAMPING = ENERGY_ACCUMULATED + E_DAMPING  # dissipated by the normal dashpots
ENERGY_TANGENTIAL = ENERGY_ACCUMULATED + E_TANGENTIAL  # dissipated by slip and tangential dashpots
ENERGY_BASE_WORK = ENERGY_ACCUMULATED + E_BASE_WORK  # work done by the driven bodies
N_ENERGY = ENERGY_ACCUMULATED + N_ENERGY_ACC

# Slots of State.peaks: running maxima over every step of the run (:func:`track`), with the
# definitions of stonedem.engine.measures (thesis 6.3.1) [rad], [m], [m]
PEAK_ROCKING = 0  # mean |theta| of the rocking bodies (Watch.rocking)
PEAK_SLIDING = 1  # total sliding: sum over bodies of |sliding along the support's top face|
PEAK_EPISTYLE = 2  # |mean displacement of the epistyles relative to the base|
N_PEAK = 3
# Slots of State.events: the step at which something first happened, -1 while it has not
EVENT_ONSET = 0  # rocking first exceeds Watch.onset_rocking (theta_cr / 30)
EVENT_COLLAPSE = 1  # :func:`collapsed` first true
N_EVENT = 2


class Law(NamedTuple):
    """The contact law of a scene (:mod:`stonedem.kernels.contact`,
    :mod:`stonedem.kernels.point_contact`): what every law reads, then the law's own values
    as one array, in the order of its row's own fields (:mod:`stonedem.engine.laws`)."""

    kind: int  # CONTACT_AREA or CONTACT_POINT
    k_n: float  # normal stiffness: per unit overlap area (area) or contact length (point) [N m-2]
    k_t: float  # tangential stiffness [N m-1]
    c_t: float  # tangential dashpot [N s m-1]
    frame_rule: int  # FRAME_BOUNDARY or FRAME_THESIS (stonedem.kernels.overlap)
    # area: (c_n [N s m-1],); point: (zeta [1], 1.0 when a landing end stops plastically)
    params: np.ndarray


class Excitation(NamedTuple):
    """One direction of base motion, as :func:`stonedem.kernels.excitation.base_motion` reads it."""

    kind: int  # KIND_* of stonedem.kernels.excitation
    params: np.ndarray  # (4,)
    table_accel: np.ndarray  # recorded motion sampled every table_dt (empty unless KIND_TABLE)
    table_vel: np.ndarray
    table_disp: np.ndarray
    table_dt: float  # [s]


class Watch(NamedTuple):
    """What :func:`track` measures at every step: the response measures' definitions
    (:func:`stonedem.engine.pack.watch_arrays`, from :mod:`stonedem.engine.measures`)."""

    rocking: np.ndarray  # 1.0 where the body counts in the rocking measure, else 0.0 (n_body,)
    n_rocking: float  # how many do (0: rocking not tracked)
    onset_rocking: float  # rocking above this is its onset, theta_cr / 30 [rad]
    support: np.ndarray  # body whose top face the body slides on, -1 for none (n_body,) int64
    slide_x: np.ndarray  # material point followed for sliding (the bottom centre at t = 0), in
    slide_y: np.ndarray  # the body's frame (n_body,) [m]
    slide_support_x: np.ndarray  # the same point in the support's frame at t = 0 (n_body,) [m]
    slide_support_y: np.ndarray
    slide_offset: np.ndarray  # their separation along the support's x axis at t = 0 (n_body,) [m]
    epistyle: (
        np.ndarray
    )  # 1.0 where the body counts in the epistyle displacement, else 0.0 (n_body,)
    n_epistyle: float
    x0: np.ndarray  # centroid x at t = 0 (n_body,) [m]


class Links(NamedTuple):
    """Shear links between bodies (:mod:`stonedem.kernels.links`; empty arrays: none), each
    from the scene's ``links:`` (:func:`stonedem.engine.pack.link_arrays`)."""

    a: np.ndarray  # lower body (n_link,) int64
    b: np.ndarray  # upper body (n_link,) int64
    a_x: np.ndarray  # anchor in a's frame (n_link,) [m]
    a_y: np.ndarray
    b_x: np.ndarray  # the same point as built, in b's frame (n_link,) [m]
    b_y: np.ndarray
    t_x: np.ndarray  # unit tangent of the interface in a's frame (n_link,) [1]
    t_y: np.ndarray
    stiffness: np.ndarray  # shear and axial stiffness (n_link,) [N m-1]
    capacity: np.ndarray  # shear capacity (n_link,) [N]
    ultimate_slip: np.ndarray  # total slip that breaks it (n_link,) [m]
    gap: np.ndarray  # clearance before the shear engages (n_link,) [m]
    pullout: np.ndarray  # pull-out resistance (n_link,) [N]
    embedment: np.ndarray  # opening at which it is pulled out (n_link,) [m]


def no_links() -> Links:
    """The :class:`Links` of a scene without links (plain Python)."""
    empty = np.zeros(0)
    ends = np.zeros(0, dtype=np.int64)
    return Links(ends, ends.copy(), *(empty.copy() for _ in Links._fields[2:]))


class Model(NamedTuple):
    """The scene, read only: :class:`stonedem.engine.pack.SceneArrays` but the initial state, plus
    contact law, gravity and base motion (:func:`stonedem.engine.pack.kernel_model`)."""

    vert_start: np.ndarray  # body b owns vertices vert_start[b]:vert_start[b+1] (n_body + 1,)
    local_x: np.ndarray  # vertices in the body frame (n_vert,) [m]
    local_y: np.ndarray
    body_mass: np.ndarray  # (n_body,) [kg]
    body_inertia: np.ndarray  # (n_body,) [kg m2]
    body_driven: np.ndarray  # follows the base motion (n_body,) bool
    body_radius: np.ndarray  # bounding radius about the centroid (n_body,) [m]
    ref_x: np.ndarray  # pose at rest, which driven bodies keep shifted by the base (n_body,)
    ref_y: np.ndarray
    ref_theta: np.ndarray
    pair_mu: np.ndarray  # friction coefficient of every pair (n_body, n_body) [1]
    body_group: np.ndarray  # collapse group of each body, -1 for none (n_body,)
    group_theta_cr: np.ndarray  # critical mean rotation of each group (n_group,) [rad]
    # rotation of each group's rest pose from upright (a leaning column), added to its bodies'
    # theta in the collapse check: toward the lean it collapses at theta_cr - |lean| (n_group,)
    group_lean: np.ndarray
    fall_depth: np.ndarray  # centroid drop that means a body fell (n_body,) [m]
    margin: float  # broad-phase margin [m]
    sweep_axis: int  # 0 = x, 1 = y
    gravity: float  # [m s-2], along -y
    law: Law
    horizontal: Excitation
    vertical: Excitation
    watch: Watch
    links: Links


class Settings(NamedTuple):
    """Time step, sampling and stopping rules of a run."""

    dt: float  # [s]
    n_steps: int  # the run ends at step n_steps (t = n_steps dt), which is sampled
    out_every: int  # steps between samples
    stop_on_collapse: bool
    rest_speed: float  # [m s-1] a free body slower than this relative to the base is at rest
    rest_samples: int  # ... for this many samples in a row (from rest_from_step on): the run ends


class State(NamedTuple):
    """What a run reads and writes, so it can be split into calls."""

    body_x: np.ndarray  # centroid (n_body,) [m]
    body_y: np.ndarray
    body_theta: np.ndarray  # [rad]
    body_vx: np.ndarray  # velocities at t = 0 before step 0, at mid-steps after (n_body,)
    body_vy: np.ndarray
    body_omega: np.ndarray
    pair_ft: np.ndarray  # elastic tangential force of each pair (n_body, n_body) [N]
    pair_memory: (
        np.ndarray
    )  # contact memory, slots MEM_* of stonedem.kernels.contact (n_body, n_body, N_MEMORY)
    energy_acc: (
        np.ndarray
    )  # energy accumulators, slots E_* of stonedem.kernels.contact (N_ENERGY_ACC,) [J]
    rest_count: np.ndarray  # samples at rest in a row so far (1,) int64
    peaks: np.ndarray  # running maxima over the steps run so far, slots PEAK_* (N_PEAK,)
    peak_theta: np.ndarray  # running maximum of each body's |theta| (n_body,) [rad]
    events: np.ndarray  # step of each first event, slots EVENT_*, -1: not yet (N_EVENT,) int64
    link_slip: np.ndarray  # plastic slip of each link (n_link,) [m]
    link_status: np.ndarray  # LINK_* of stonedem.kernels.links (n_link,) int64
    link_peak: np.ndarray  # running maximum of each link's |force| (n_link,) [N]
    link_energy: np.ndarray  # energy each link stored at its last step (n_link,) [J]


class Samples(NamedTuple):
    """Preallocated output: one row per sample."""

    step: np.ndarray  # step number of each sample (n_out,) int64
    x: np.ndarray  # (n_out, n_body) [m]
    y: np.ndarray
    theta: np.ndarray  # [rad]
    energy: np.ndarray  # (n_out, N_ENERGY), columns ENERGY_* [J]
    n_contact: np.ndarray  # (n_out,) int64


class Work(NamedTuple):
    """Arrays one run allocates and every step overwrites (:func:`allocate_work`)."""

    world_x: np.ndarray  # world vertices (n_vert,) [m]
    world_y: np.ndarray
    edge_len: np.ndarray  # point law: length and outward unit normal of each body's edge k -> k+1
    edge_nx: np.ndarray  # (n_vert,) [m], [1] (stonedem.kernels.point_contact.world_edges)
    edge_ny: np.ndarray
    cos_theta: np.ndarray  # cos and sin of each body's theta at t_n (n_body,)
    sin_theta: np.ndarray
    lo_x: np.ndarray  # bounds of each body (n_body,) [m]
    lo_y: np.ndarray
    hi_x: np.ndarray
    hi_y: np.ndarray
    inv_mass: np.ndarray  # 1 / mass and 1 / moment of inertia of each free body, 0 for a driven one
    inv_inertia: (
        np.ndarray
    )  # (n_body,) [kg-1], [kg-1 m-2] (the integrator multiplies: no division a step)
    force_x: np.ndarray  # contact force and torque on each body (n_body,) [N], [N m]
    force_y: np.ndarray
    torque: np.ndarray
    base_force_x: np.ndarray  # part of it exerted by driven bodies (n_body,) [N]
    base_force_y: np.ndarray
    vel_x: np.ndarray  # velocities at t_n (n_body,), 0 spin for driven bodies
    vel_y: np.ndarray
    vel_om: np.ndarray
    power: (
        np.ndarray
    )  # this step's power into each energy accumulator, slots E_* (N_ENERGY_ACC,) [W]
    sweep_x: np.ndarray  # poses at the last broad-phase sweep (n_body,)
    sweep_y: np.ndarray
    sweep_theta: np.ndarray
    scratch: np.ndarray  # overlap polygons (4, MAX_OVERLAP_VERTICES)
    pair_a: (
        np.ndarray
    )  # candidate pairs of the last sweep in their first n_pair entries (capacity,)
    pair_b: np.ndarray
    pair_key: (
        np.ndarray
    )  # the broad phase's sort buffers (capacity,) (broad_phase.candidate_pairs_into)
    pair_order: np.ndarray
    face_cache: (
        np.ndarray
    )  # point law: each pair slot's kept separating axes (capacity, N_FACE_CACHE), columns
    # of stonedem.kernels.point_contact (FACE_A < 0: nothing kept; a sweep forgets them all)
    order: np.ndarray  # bodies sorted along the sweep axis at the last sweep (n_body,)
    group_sum: np.ndarray  # sum of |theta| over each collapse group (n_group,) [rad]
    group_count: np.ndarray  # bodies in each collapse group (n_group,)


@njit(**INLINE_OPTIONS)
def first_pair_capacity(n_body):
    """Candidate pairs a Work bundle holds at first: every pair of a small scene, ~4 per body
    of a large one (the bundle doubles when they outgrow it)."""
    return min(max(1, n_body * (n_body - 1) // 2), 4 * n_body + 16)


@njit(**JIT_OPTIONS)
def allocate_work(model, capacity):
    """A :class:`Work` bundle for the model's bodies and vertices, with room for ``capacity``
    pairs."""
    n_body = model.body_mass.shape[0]
    n_vert = model.local_x.shape[0]
    n_group = model.group_theta_cr.shape[0]
    inv_mass = np.zeros(n_body)
    inv_inertia = np.zeros(n_body)
    for b in range(n_body):
        if not model.body_driven[b]:
            inv_mass[b] = 1.0 / model.body_mass[b]
            inv_inertia[b] = 1.0 / model.body_inertia[b]
    return Work(
        world_x=np.empty(n_vert),
        world_y=np.empty(n_vert),
        edge_len=np.zeros(n_vert),
        edge_nx=np.zeros(n_vert),
        edge_ny=np.zeros(n_vert),
        cos_theta=np.empty(n_body),
        sin_theta=np.empty(n_body),
        inv_mass=inv_mass,
        inv_inertia=inv_inertia,
        lo_x=np.empty(n_body),
        lo_y=np.empty(n_body),
        hi_x=np.empty(n_body),
        hi_y=np.empty(n_body),
        force_x=np.zeros(n_body),
        force_y=np.zeros(n_body),
        torque=np.zeros(n_body),
        base_force_x=np.zeros(n_body),
        base_force_y=np.zeros(n_body),
        vel_x=np.zeros(n_body),
        vel_y=np.zeros(n_body),
        vel_om=np.zeros(n_body),
        power=np.zeros(N_ENERGY_ACC),
        sweep_x=np.empty(n_body),
        sweep_y=np.empty(n_body),
        sweep_theta=np.empty(n_body),
        scratch=np.zeros((4, MAX_OVERLAP_VERTICES)),
        pair_a=np.zeros(capacity, dtype=np.int64),
        pair_b=np.zeros(capacity, dtype=np.int64),
        pair_key=np.zeros(capacity, dtype=np.int64),
        pair_order=np.zeros(capacity, dtype=np.int64),
        face_cache=np.full((capacity, N_FACE_CACHE), -1.0),
        order=np.arange(n_body),
        group_sum=np.zeros(n_group),
        group_count=np.zeros(n_group),
    )


@njit(**NO_ALLOC_OPTIONS)
def needs_resweep(model, state, work):
    """True once some body has moved (translation + radius x rotation) half the margin since the
    sweep."""
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    sweep_x, sweep_y, sweep_theta = work.sweep_x, work.sweep_y, work.sweep_theta
    body_radius = model.body_radius
    for b in range(body_x.shape[0]):
        moved = (
            abs(body_x[b] - sweep_x[b])
            + abs(body_y[b] - sweep_y[b])
            + body_radius[b] * abs(body_theta[b] - sweep_theta[b])
        )
        if moved > 0.5 * model.margin:
            return True
    return False


@njit(**NO_ALLOC_OPTIONS)
def sweep(model, state, work):
    """Candidate pairs from the current bounds into work.pair_a, pair_b; returns their number,
    which exceeds the buffers' length when they are too short. The poses are kept for
    needs_resweep."""
    n_pair = candidate_pairs_into(
        model.body_mass.shape[0],
        model.body_driven,
        work.lo_x,
        work.lo_y,
        work.hi_x,
        work.hi_y,
        model.margin,
        model.sweep_axis,
        work.order,
        work.pair_a,
        work.pair_b,
        work.pair_key,
        work.pair_order,
    )
    sweep_x, sweep_y, sweep_theta = work.sweep_x, work.sweep_y, work.sweep_theta
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    for p in range(min(n_pair, work.face_cache.shape[0])):  # the slots hold other pairs now
        work.face_cache[p, FACE_A] = -1.0
    for b in range(body_x.shape[0]):
        sweep_x[b] = body_x[b]
        sweep_y[b] = body_y[b]
        sweep_theta[b] = body_theta[b]
    return n_pair


@njit(**INLINE_OPTIONS)
def place_bodies(model, state, work, t):
    """Stage 1: driven bodies at the base pose of time t [s], then every body's world vertices
    (and the cos and sin of its theta) and bounds into work. Returns the base's (d_h, v_h,
    d_v, v_v): displacement [m] and velocity [m s-1], horizontal and vertical."""
    h, v = model.horizontal, model.vertical
    vert_start = model.vert_start
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    world_x, world_y = work.world_x, work.world_y
    n_body = body_x.shape[0]
    d_h, vel_h, _ = base_motion(
        t, h.kind, h.params, h.table_accel, h.table_vel, h.table_disp, h.table_dt
    )
    d_v, vel_v, _ = base_motion(
        t, v.kind, v.params, v.table_accel, v.table_vel, v.table_disp, v.table_dt
    )
    drive_bodies(
        n_body,
        model.body_driven,
        model.ref_x,
        model.ref_y,
        model.ref_theta,
        d_h,
        vel_h,
        d_v,
        vel_v,
        body_x,
        body_y,
        body_theta,
        state.body_vx,
        state.body_vy,
        state.body_omega,
    )
    update_world_vertices(
        n_body,
        vert_start,
        model.local_x,
        model.local_y,
        body_x,
        body_y,
        body_theta,
        world_x,
        world_y,
        work.cos_theta,
        work.sin_theta,
    )
    body_bounds(n_body, vert_start, world_x, world_y, work.lo_x, work.lo_y, work.hi_x, work.hi_y)
    return d_h, vel_h, d_v, vel_v


@njit(**INLINE_OPTIONS)
def smallest_theta_cr(model):
    """The smallest critical rotation of a collapse group [rad], inf without groups: below it
    no group can have collapsed by rotation (:func:`track`'s tilt alarm)."""
    smallest = np.inf
    for g in range(model.group_theta_cr.shape[0]):
        smallest = min(smallest, model.group_theta_cr[g] - abs(model.group_lean[g]))
    return smallest


@njit(**NO_ALLOC_OPTIONS)
def clear_forces(work):
    """Zero the force, torque and base-force accumulators before a contact law adds to them."""
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    base_force_x, base_force_y = work.base_force_x, work.base_force_y
    for b in range(force_x.shape[0]):
        force_x[b] = 0.0
        force_y[b] = 0.0
        torque[b] = 0.0
        base_force_x[b] = 0.0
        base_force_y[b] = 0.0


@njit(**INLINE_OPTIONS)
def contact_forces(model, state, work, n_pair, dt, want_energy, point_law):
    """Stage 3: clear work's force accumulators, then add every candidate pair's forces by the
    scene's law (a new law is an inlined function of these arguments and a branch here).
    ``point_law``: None under the overlap-area law, True under the point law, as an argument
    of the compiled loop, so Numba prunes the other law's branch and never compiles it.
    Returns (n_contact, stored elastic energy [J], evaluated only when want_energy)."""
    clear_forces(work)
    if point_law is None:
        return area_contact_forces(model, state, work, n_pair, dt, want_energy)
    return point_contact_forces(model, state, work, n_pair, dt, want_energy)


@njit(**NO_ALLOC_OPTIONS)
def velocities_at_step(model, state, work, half):
    """work.vel_*: velocities at t_n, half [s] of a kick on from v_{n-1/2}.

    half is 0 at the step a run starts from, whose state holds the velocities at t_n itself.
    """
    body_driven, inv_mass, inv_inertia = model.body_driven, work.inv_mass, work.inv_inertia
    body_vx, body_vy, body_omega = state.body_vx, state.body_vy, state.body_omega
    force_x, force_y, torque = work.force_x, work.force_y, work.torque
    vel_x, vel_y, vel_om = work.vel_x, work.vel_y, work.vel_om
    for b in range(body_driven.shape[0]):
        if body_driven[b]:
            vel_x[b] = body_vx[b]
            vel_y[b] = body_vy[b]
            vel_om[b] = 0.0
        else:
            vel_x[b] = body_vx[b] + half * force_x[b] * inv_mass[b]
            vel_y[b] = body_vy[b] + half * (force_y[b] * inv_mass[b] - model.gravity)
            vel_om[b] = body_omega[b] + half * torque[b] * inv_inertia[b]


@njit(**NO_ALLOC_OPTIONS)
def book_power(work, p_damp, p_tan, vel_h, vel_v):
    """work.power: this step's powers at t_n [W] by accumulator slot; the base's from
    work.base_force_*.

    p_damp, p_tan: dashpot power and tangential work rate
    (:func:`stonedem.kernels.contact.contact_power`) vel_h, vel_v: base velocity at t_n [m s-1]
    Each power covers [t_n - dt/2, t_n + dt/2] (the first step only its second half): the
    sample at t_n takes its first half, the accumulators all of it (:func:`book_energy`).
    """
    base_force_x, base_force_y = work.base_force_x, work.base_force_y
    p_base = 0.0
    for b in range(base_force_x.shape[0]):
        p_base += base_force_x[b] * vel_h + base_force_y[b] * vel_v
    work.power[E_DAMPING] = p_damp
    work.power[E_TANGENTIAL] = p_tan
    work.power[E_BASE_WORK] = p_base


@njit(**NO_ALLOC_OPTIONS)
def book_energy(state, work, kick):
    """Add kick [s] x this step's powers to the energy accumulators."""
    energy_acc, power = state.energy_acc, work.power
    for slot in range(N_ENERGY_ACC):
        energy_acc[slot] += kick * power[slot]


@njit(**NO_ALLOC_OPTIONS)
def sample_state(n, k, model, state, work, samples, n_contact, elastic, half):
    """Write sample k of step n: poses, energies at t_n, contact count. True if all of it is finite.

    elastic: stored contact energy [J]; half [s]: the time from v_{n-1/2} to t_n, over which
    the accumulators get the first half of this step's power.
    """
    body_mass, body_inertia, body_driven = model.body_mass, model.body_inertia, model.body_driven
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    vel_x, vel_y, vel_om = work.vel_x, work.vel_y, work.vel_om
    out_x, out_y, out_theta = samples.x, samples.y, samples.theta
    samples.step[k] = n
    kinetic = 0.0
    potential = 0.0
    finite = True
    for b in range(body_mass.shape[0]):
        out_x[k, b] = body_x[b]
        out_y[k, b] = body_y[b]
        out_theta[k, b] = body_theta[b]
        if body_driven[b]:
            continue
        vx = vel_x[b]
        vy = vel_y[b]
        om = vel_om[b]
        kinetic += 0.5 * body_mass[b] * (vx * vx + vy * vy)
        kinetic += 0.5 * body_inertia[b] * om * om
        potential += body_mass[b] * model.gravity * body_y[b]
        if not (
            isfinite(body_x[b]) and isfinite(body_y[b]) and isfinite(body_theta[b]) and isfinite(om)
        ):
            finite = False
    energy, energy_acc, power = samples.energy, state.energy_acc, work.power
    energy[k, ENERGY_KINETIC] = kinetic
    energy[k, ENERGY_POTENTIAL] = potential
    energy[k, ENERGY_ELASTIC] = elastic
    for slot in range(N_ENERGY_ACC):
        energy[k, ENERGY_ACCUMULATED + slot] = energy_acc[slot] + half * power[slot]
    samples.n_contact[k] = n_contact
    return finite


@njit(**NO_ALLOC_OPTIONS)
def at_rest(model, work, vel_h, vel_v, rest_speed):
    """True when every free body moves slower than rest_speed [m s-1] relative to the base.

    Speed: |v_x - v_h| + |v_y - v_v| + bounding radius x |omega|, at t_n (work.vel_*).
    """
    body_driven, body_radius = model.body_driven, model.body_radius
    vel_x, vel_y, vel_om = work.vel_x, work.vel_y, work.vel_om
    for b in range(body_driven.shape[0]):
        if body_driven[b]:
            continue
        speed = abs(vel_x[b] - vel_h) + abs(vel_y[b] - vel_v) + body_radius[b] * abs(vel_om[b])
        if speed > rest_speed:
            return False
    return True


@njit(**NO_ALLOC_OPTIONS)
def collapsed(model, state, work, d_v):
    """True when a group's mean |theta + lean| exceeds its theta_cr, or a body dropped below its
    support (lean: model.group_lean, 0 but for a leaning column).

    A body fell when its centroid, relative to the base (vertical displacement d_v [m]), is
    more than model.fall_depth below its reference; groups are model.body_group (column,
    epistyle, block), with critical mean rotation model.group_theta_cr = atan(b/h).
    """
    body_driven, body_group, group_theta_cr, group_lean = (
        model.body_driven,
        model.body_group,
        model.group_theta_cr,
        model.group_lean,
    )
    ref_y, fall_depth = model.ref_y, model.fall_depth
    body_y, body_theta = state.body_y, state.body_theta
    sums, counts = work.group_sum, work.group_count
    for g in range(group_theta_cr.shape[0]):
        sums[g] = 0.0
        counts[g] = 0.0
    for b in range(body_driven.shape[0]):
        if body_driven[b]:
            continue
        if ref_y[b] - (body_y[b] - d_v) > fall_depth[b]:
            return True
        g = body_group[b]
        if g >= 0:
            sums[g] += abs(body_theta[b] + group_lean[g])
            counts[g] += 1.0
    for g in range(group_theta_cr.shape[0]):
        if counts[g] > 0.0 and sums[g] / counts[g] > group_theta_cr[g]:
            return True
    return False


@njit(**NO_ALLOC_OPTIONS)
def track(model, state, work, n, d_h, d_v, tilt_alarm):
    """Fold the response measures at t_n (step n) into the running peaks and first events;
    True if the state may have collapsed (:func:`collapsed` can be true only then).

    The definitions of :mod:`stonedem.engine.measures`, as model.watch holds them: rocking,
    the mean |theta| of the rocking bodies; total sliding, the sum over bodies of the
    sliding of the followed material point along the support's rotated x axis since t = 0;
    the epistyles' mean x - x(0) - d_h (d_h, d_v: base displacement at t_n [m]); each body's
    |theta|. State.peaks, peak_theta and events[EVENT_ONSET] take them. A few flops a body:
    the cos and sin of theta are the ones update_world_vertices left in work, and the
    collapse check's group means are left to :func:`collapsed`, needed only once some body
    has fallen or turned past tilt_alarm (the smallest theta_cr of a group) [rad].
    """
    watch = model.watch
    rocking, support, epistyle, x0 = watch.rocking, watch.support, watch.epistyle, watch.x0
    slide_x, slide_y, slide_support_x, slide_support_y = (
        watch.slide_x,
        watch.slide_y,
        watch.slide_support_x,
        watch.slide_support_y,
    )
    slide_offset = watch.slide_offset
    ref_y, fall_depth = model.ref_y, model.fall_depth
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    cos_theta, sin_theta = work.cos_theta, work.sin_theta
    peaks, peak_theta, events = state.peaks, state.peak_theta, state.events
    rock_sum = 0.0
    slide_sum = 0.0
    epistyle_sum = 0.0
    suspect = False
    for b in range(body_theta.shape[0]):
        a = abs(body_theta[b])
        if a > peak_theta[b]:
            peak_theta[b] = a
        # driven bodies never turn or drop relative to the base
        if a > tilt_alarm or ref_y[b] - (body_y[b] - d_v) > fall_depth[b]:
            suspect = True
        rock_sum += rocking[b] * a
        epistyle_sum += epistyle[b] * (body_x[b] - x0[b] - d_h)
        s = support[b]
        if s >= 0:
            c_b = cos_theta[b]
            s_b = sin_theta[b]
            c_s = cos_theta[s]
            s_s = sin_theta[s]
            dx = (body_x[b] + c_b * slide_x[b] - s_b * slide_y[b]) - (
                body_x[s] + c_s * slide_support_x[b] - s_s * slide_support_y[b]
            )
            dy = (body_y[b] + s_b * slide_x[b] + c_b * slide_y[b]) - (
                body_y[s] + s_s * slide_support_x[b] + c_s * slide_support_y[b]
            )
            slide_sum += abs(dx * c_s + dy * s_s - slide_offset[b])
    if watch.n_rocking > 0.0:
        rock = rock_sum / watch.n_rocking
        if rock > peaks[PEAK_ROCKING]:
            peaks[PEAK_ROCKING] = rock
        if events[EVENT_ONSET] < 0 and rock > watch.onset_rocking:
            events[EVENT_ONSET] = n
    if slide_sum > peaks[PEAK_SLIDING]:
        peaks[PEAK_SLIDING] = slide_sum
    if watch.n_epistyle > 0.0:
        epi = abs(epistyle_sum / watch.n_epistyle)
        if epi > peaks[PEAK_EPISTYLE]:
            peaks[PEAK_EPISTYLE] = epi
    return suspect


@njit(**INLINE_OPTIONS)
def sample_step(
    n,
    model,
    settings,
    state,
    work,
    samples,
    n_sample,
    collapse_sample,
    n_contact,
    elastic,
    half,
    stop,
    rest_from_step,
    vel_h,
    vel_v,
):
    """Stage 6 of step n: write its sample (:func:`sample_state`); returns (status, n_sample,
    collapse_sample), the status STATUS_OK to go on, else the one that ends the run: non-finite
    values, the collapse that stops it (``stop``), or rest on a quiet base (from rest_from_step
    on, settings.rest_samples samples in a row, counted in state.rest_count)."""
    finite = sample_state(n, n_sample, model, state, work, samples, n_contact, elastic, half)
    n_sample += 1
    if not finite:
        return STATUS_NONFINITE, n_sample, collapse_sample
    if collapse_sample < 0 and state.events[EVENT_COLLAPSE] >= 0:
        collapse_sample = n_sample - 1
    if stop:
        return STATUS_COLLAPSED, n_sample, collapse_sample
    rest_count = state.rest_count
    if n >= rest_from_step and at_rest(model, work, vel_h, vel_v, settings.rest_speed):
        rest_count[0] += 1
        if rest_count[0] >= settings.rest_samples:
            return STATUS_AT_REST, n_sample, collapse_sample
    else:
        rest_count[0] = 0
    return STATUS_OK, n_sample, collapse_sample


@njit(**INLINE_OPTIONS)
def integrate_step(model, state, work, kick, dt):
    """Stage 7: book this step's powers over ``kick`` [s] and move the free bodies on
    (:func:`stonedem.kernels.integrate.central_difference_step`)."""
    book_energy(state, work, kick)
    central_difference_step(
        model.body_mass.shape[0],
        model.body_driven,
        work.inv_mass,
        work.inv_inertia,
        model.gravity,
        kick,
        dt,
        work.force_x,
        work.force_y,
        work.torque,
        state.body_x,
        state.body_y,
        state.body_theta,
        state.body_vx,
        state.body_vy,
        state.body_omega,
    )


@njit(**INLINE_OPTIONS)
def finish_step(
    n,
    model,
    settings,
    state,
    work,
    samples,
    pair_a,
    pair_b,
    n_pair,
    n_sample,
    collapse_sample,
    n_contact,
    elastic,
    stop,
    sample,
    step_first,
    rest_from_step,
    vel_h,
    vel_v,
):
    """Stages 4 to 7 of step n, once its contact forces are in work: the velocities and powers
    at t_n (the contact power over pairs pair_a, pair_b[:n_pair]), its sample if ``sample``
    (:func:`sample_step`), then, unless that ended the run or n is the last step, the step to
    t_{n+1} (:func:`integrate_step`; the first kick is a half step, so velocities sit at
    t + dt/2 from then on). Returns (status, n_sample, collapse_sample, whether the run ends
    here)."""
    # 4. velocities at t_n; 5. powers at t_n
    half = 0.0 if n == step_first else 0.5 * settings.dt
    velocities_at_step(model, state, work, half)
    p_damp, p_tan = contact_power(
        pair_a,
        pair_b,
        n_pair,
        state.pair_memory,
        state.body_x,
        state.body_y,
        work.vel_x,
        work.vel_y,
        work.vel_om,
    )
    book_power(work, p_damp, p_tan, vel_h, vel_v)
    # 6. a sample, which may end the run; 7. integrate
    status = STATUS_OK
    if sample:
        status, n_sample, collapse_sample = sample_step(
            n,
            model,
            settings,
            state,
            work,
            samples,
            n_sample,
            collapse_sample,
            n_contact,
            elastic,
            half,
            stop,
            rest_from_step,
            vel_h,
            vel_v,
        )
        if status != STATUS_OK:
            return status, n_sample, collapse_sample, True
    if n == settings.n_steps:
        return status, n_sample, collapse_sample, True
    dt = settings.dt
    integrate_step(model, state, work, 0.5 * dt if n == step_first else dt, dt)
    return status, n_sample, collapse_sample, False


@njit(**JIT_OPTIONS)
def run(
    model,
    settings,
    state,
    samples,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """Run steps step_start..step_stop-1 (of 0..n_steps); return (status, n_sample,
    collapse_sample).

    model, settings, state, samples: :class:`Model`, :class:`Settings`, :class:`State`,
    :class:`Samples`. Samples are written from index n_sample on; collapse_sample is the
    first sample at or after the collapse (state.events[EVENT_COLLAPSE], checked at every
    step; with settings.stop_on_collapse the collapse step is sampled and ends the run with
    STATUS_COLLAPSED), or -1. Every step also folds into the running peaks and first events
    of state (:func:`track`). step_first: the step the run starts from (its kick is a
    half step; state holds the velocities at that instant). From step rest_from_step on
    (the base motion is quiet for good), settings.rest_samples samples in a row at which
    every free body is at rest (:func:`at_rest`) end the run with STATUS_AT_REST;
    state.rest_count carries the count from one call to the next.

    The only part that allocates: a :class:`Work` bundle, then :func:`run_steps` (compiled
    without Numba's runtime, so no array it hands on costs reference counting). When the
    candidate pairs outgrow the bundle, run_steps stops before that step's forces and the
    bundle is made twice as large (every field of Work is rebuilt at each step).
    Both laws are compiled in and the scene's is chosen at run time; :func:`run_point` and
    :func:`run_area` compile one law's loop alone (what a single run calls).
    """
    if model.law.kind == CONTACT_POINT:
        return run_under_law(
            model,
            settings,
            state,
            samples,
            step_start,
            step_stop,
            step_first,
            rest_from_step,
            n_sample,
            collapse_sample,
            True,
        )
    return run_under_law(
        model,
        settings,
        state,
        samples,
        step_start,
        step_stop,
        step_first,
        rest_from_step,
        n_sample,
        collapse_sample,
        None,
    )


@njit(**JIT_OPTIONS)
def run_point(
    model,
    settings,
    state,
    samples,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """:func:`run` of a point-law scene, with the point law's code alone."""
    return run_under_law(
        model,
        settings,
        state,
        samples,
        step_start,
        step_stop,
        step_first,
        rest_from_step,
        n_sample,
        collapse_sample,
        True,
    )


@njit(**JIT_OPTIONS)
def run_area(
    model,
    settings,
    state,
    samples,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """:func:`run` of an overlap-area-law scene, with the area law's code alone (a cold compile
    of the general loop is ~16 s shorter without the point law)."""
    return run_under_law(
        model,
        settings,
        state,
        samples,
        step_start,
        step_stop,
        step_first,
        rest_from_step,
        n_sample,
        collapse_sample,
        None,
    )


@njit(**{**JIT_OPTIONS, "inline": "always"})
def run_under_law(
    model,
    settings,
    state,
    samples,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
    point_law,
):
    """:func:`run` under one law (``point_law``: None or True, :func:`contact_forces`)."""
    capacity = first_pair_capacity(model.body_mass.shape[0])
    n = step_start
    while True:
        work = allocate_work(model, capacity)
        status, n_sample, collapse_sample, n = steps_under_law(
            model,
            settings,
            state,
            samples,
            work,
            n,
            step_stop,
            step_first,
            rest_from_step,
            n_sample,
            collapse_sample,
            point_law,
        )
        if status != STATUS_PAIRS_FULL:
            return status, n_sample, collapse_sample
        capacity *= 2


@njit(**NO_ALLOC_OPTIONS)
def run_steps(
    model,
    settings,
    state,
    samples,
    work,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """:func:`run` with its :class:`Work` bundle; returns (status, n_sample, collapse_sample,
    the step to go on from). STATUS_PAIRS_FULL: the pairs do not fit in work; that step's
    forces are not computed yet and :func:`run` calls again from it with a larger bundle.
    Both laws compiled into one loop, the scene's chosen at run time: ``point_law`` is an
    optional here, which Numba cannot prune (the GPU's kernel, one loop for its members; two
    loops of one law each took numba-cuda 3.4x as long to compile)."""
    point_law = True
    if model.law.kind != CONTACT_POINT:
        point_law = None
    return steps_under_law(
        model,
        settings,
        state,
        samples,
        work,
        step_start,
        step_stop,
        step_first,
        rest_from_step,
        n_sample,
        collapse_sample,
        point_law,
    )


@njit(**NO_ALLOC_OPTIONS)
def steps_under_law(
    model,
    settings,
    state,
    samples,
    work,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
    point_law,
):
    """:func:`run_steps` under one law (``point_law``: None or True, :func:`contact_forces`)."""
    dt = settings.dt
    n_steps = settings.n_steps
    events = state.events

    tilt_alarm = smallest_theta_cr(model)
    pair_a, pair_b = work.pair_a, work.pair_b
    n_pair = 0
    need_sweep = True  # the pair list does not outlive a call
    status = STATUS_OK
    for n in range(step_start, min(step_stop, n_steps + 1)):
        t = n * dt
        # 1. driven bodies at the base pose of t_n; world vertices and bounds
        d_h, vel_h, d_v, vel_v = place_bodies(model, state, work, t)

        # the measures at t_n, at every step: peaks and events do not depend on the sampling;
        # a collapse that stops the run is sampled at its step
        suspect = track(model, state, work, n, d_h, d_v, tilt_alarm)
        if suspect and events[EVENT_COLLAPSE] < 0 and collapsed(model, state, work, d_v):
            events[EVENT_COLLAPSE] = n
        # (so also when run_steps is called again from this step)
        stop = settings.stop_on_collapse and events[EVENT_COLLAPSE] == n

        # 2. candidate pairs, found again once some body has moved half the margin
        if need_sweep or needs_resweep(model, state, work):
            n_pair = sweep(model, state, work)
            need_sweep = False
            if n_pair > pair_a.shape[0]:
                return STATUS_PAIRS_FULL, n_sample, collapse_sample, n

        # 3. contact forces from the velocities v_{n-1/2}, by the scene's law
        sample = n % settings.out_every == 0 or n == n_steps or stop
        n_contact, elastic = contact_forces(model, state, work, n_pair, dt, sample, point_law)
        if model.links.a.shape[0] > 0:  # 3b. shear links (a scene without them: nothing)
            elastic += link_forces(model, state, work)

        # 4.-7. velocities and powers at t_n, a sample, the step to t_{n+1}
        status, n_sample, collapse_sample, done = finish_step(
            n,
            model,
            settings,
            state,
            work,
            samples,
            pair_a,
            pair_b,
            n_pair,
            n_sample,
            collapse_sample,
            n_contact,
            elastic,
            stop,
            sample,
            step_first,
            rest_from_step,
            vel_h,
            vel_v,
        )
        if done:
            break
    return status, n_sample, collapse_sample, step_stop
