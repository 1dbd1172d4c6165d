"""The time loop for a scene whose contacts are known: a fixed graph of face contacts.

A column is a stack: drum k touches only drums k - 1 and k + 1, on its bottom and top faces;
a colonnade is a fixed graph of drums, capitals and epistyles. :func:`run_steps` finds every
step what the general loop (:func:`stonedem.kernels.step.run_steps`) finds by a broad phase,
bounds, every body's edges and a separating-axis test over them: which pairs touch, and on
which faces. Here the pairs and faces are given (:class:`Graph`, built once per scene by
:func:`stonedem.engine.graph.contact_graph`), and each step computes only the two face edges
of each contact and their separations.

The law is the general loop's own (:func:`stonedem.kernels.point_contact.face_contact_forces`),
the pairs are visited in the same order (sorted by (a, b)) and every other stage is the same
function, so while the graph holds a run is the general loop's bit for bit. A guard checks
at every step, before anything is changed, that it holds:

- **the faces**: each contact's faces are still what the general law would choose. The
  separating axes are kept while they provably hold, as the general loop keeps them
  (:func:`stonedem.kernels.point_contact.faces_hold`), and found again over every edge of
  the pair when that proof lapses; and the two faces have not turned against each other
  by more than the graph's turn limit (then each is still the other body's edge most
  opposed to it, whichever is the reference face);
- **the pairs**: no other pair can touch. The broad phase runs as in the general loop
  (when some body has moved half the margin), and any candidate pair outside the graph
  breaks it.

When the guard fails, :func:`run_steps` returns STATUS_GENERAL with the step it stopped at,
whose state is untouched, and the run goes on in the general loop from that step.
"""

from typing import NamedTuple

import numpy as np
from numba import njit

from stonedem.kernels import INLINE_OPTIONS, JIT_OPTIONS, NO_ALLOC_OPTIONS
from stonedem.kernels.broad_phase import body_bounds, candidate_pairs_into
from stonedem.kernels.contact import MEM_ACTIVE, release_contact
from stonedem.kernels.excitation import base_motion
from stonedem.kernels.integrate import body_world_vertices, cos_sin, drive_bodies
from stonedem.kernels.point_contact import (
    FACE_A,
    FACE_B,
    FACE_SWITCH_TOLERANCE,
    N_FACE_CACHE,
    body_edge,
    body_edges,
    deepest_face,
    edge_separation,
    face_contact_forces,
    faces_hold,
    keep_faces,
)
from stonedem.kernels.step import (
    EVENT_COLLAPSE,
    STATUS_OK,
    allocate_work,
    clear_forces,
    collapsed,
    finish_step,
    first_pair_capacity,
    needs_resweep,
    smallest_theta_cr,
    track,
)

STATUS_GENERAL = 5  # the graph no longer holds: the general loop goes on from the step returned
# why it no longer holds (run's fifth value; its sixth names the pair a * n_body + b, or the
# contact)
HELD = 0
BROKEN_PAIR = 1  # a pair outside the graph came within the broad phase's margin
BROKEN_TURN = 2  # a contact's faces turned past its turn limit
BROKEN_FACES = 3  # a touching contact's edges of least overlap are no longer its faces


class Graph(NamedTuple):
    """A scene's face contacts, sorted by (a, b) as the general loop's broad phase sorts its
    pairs."""

    pair_a: np.ndarray  # bodies of each contact, a < b (n_contact,) int64
    pair_b: np.ndarray
    face_a: (
        np.ndarray
    )  # a's contact edge k -> k+1, counted from a's first vertex (n_contact,) int64
    face_b: np.ndarray  # b's
    turn_rest: (
        np.ndarray
    )  # angle from a's inward to b's outward face normal, less theta_b - theta_a [rad]
    turn_limit: (
        np.ndarray
    )  # the largest |angle| at which the faces are still each other's most opposed [rad]
    index: np.ndarray  # contact of pair (a, b), -1 for none (n_body, n_body) int64


@njit(**JIT_OPTIONS)
def run(
    model,
    settings,
    state,
    samples,
    graph,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """:func:`stonedem.kernels.step.run` for a scene with a contact graph: the same arguments
    plus ``graph`` (:class:`Graph`); returns (status, n_sample, collapse_sample, the step to
    go on from, why the graph broke, which pair or contact), which with STATUS_GENERAL is the
    step the general loop goes on from (BROKEN_*; else HELD, -1)."""
    n_contact = graph.pair_a.shape[0]
    work = allocate_work(model, max(first_pair_capacity(model.body_mass.shape[0]), n_contact))
    kept = np.full((n_contact, N_FACE_CACHE), -1.0)
    touching = np.zeros(n_contact, dtype=np.bool_)
    # a driven body keeps its reference angle, so its cos and sin are the same at every step
    n_body = model.body_mass.shape[0]
    ref_cos = np.empty(n_body)
    ref_sin = np.empty(n_body)
    for b in range(n_body):
        ref_cos[b], ref_sin[b] = cos_sin(model.ref_theta[b])
    return run_steps(
        model,
        settings,
        state,
        samples,
        graph,
        work,
        kept,
        touching,
        ref_cos,
        ref_sin,
        step_start,
        step_stop,
        step_first,
        rest_from_step,
        n_sample,
        collapse_sample,
    )


@njit(**INLINE_OPTIONS)
def place_graph(model, state, work, ref_cos, ref_sin, d_h, vel_h, d_v, vel_v):
    """Stage 1 of :func:`run_steps`: driven bodies at the base pose, then every body's world
    vertices and cos and sin of theta, as :func:`stonedem.kernels.integrate.update_world_vertices`
    computes them but for a driven body's cos and sin, which its fixed angle gives once."""
    n_body = model.body_mass.shape[0]
    vert_start, local_x, local_y, body_driven = (
        model.vert_start,
        model.local_x,
        model.local_y,
        model.body_driven,
    )
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    world_x, world_y, cos_theta, sin_theta = (
        work.world_x,
        work.world_y,
        work.cos_theta,
        work.sin_theta,
    )
    drive_bodies(
        n_body,
        body_driven,
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
    for b in range(n_body):
        if body_driven[b]:
            c = ref_cos[b]
            s = ref_sin[b]
        else:
            c, s = cos_sin(body_theta[b])
        body_world_vertices(
            b,
            c,
            s,
            vert_start,
            local_x,
            local_y,
            body_x,
            body_y,
            world_x,
            world_y,
            cos_theta,
            sin_theta,
        )


@njit(**INLINE_OPTIONS)
def graph_holds(model, state, work, graph, kept, touching):
    """The guard and narrow phase of one step: (BROKEN_TURN or BROKEN_FACES, contact) when a
    contact's faces are no longer the graph's; else (HELD, -1), and touching[g] tells whether
    contact g touches (no edge separates the pair).

    kept: each contact's separating axes, kept while they provably hold (rows as
    Work.face_cache's). Writes the face edges' lengths and normals into work.edge_*.
    """
    vert_start = model.vert_start
    body_x, body_y, body_theta, body_radius = (
        state.body_x,
        state.body_y,
        state.body_theta,
        model.body_radius,
    )
    world_x, world_y = work.world_x, work.world_y
    edge_len, edge_nx, edge_ny = work.edge_len, work.edge_nx, work.edge_ny
    pair_a, pair_b, face_a, face_b = graph.pair_a, graph.pair_b, graph.face_a, graph.face_b
    for g in range(pair_a.shape[0]):
        a = pair_a[g]
        b = pair_b[g]
        if abs(graph.turn_rest[g] + body_theta[b] - body_theta[a]) >= graph.turn_limit[g]:
            return BROKEN_TURN, g
        sa = vert_start[a]
        na = vert_start[a + 1] - sa
        sb = vert_start[b]
        nb = vert_start[b + 1] - sb
        ka = face_a[g]
        kb = face_b[g]
        body_edge(sa, na, ka, world_x, world_y, edge_len, edge_nx, edge_ny)
        body_edge(sb, nb, kb, world_x, world_y, edge_len, edge_nx, edge_ny)
        # the separating axes as the general law finds them: its edges of least overlap,
        # kept while they provably hold, else searched for over every edge of the pair
        sep_b = 0.0
        if kept[g, FACE_A] >= 0.0 and faces_hold(
            kept, g, a, b, body_x, body_y, body_theta, body_radius
        ):
            ref_a = int(kept[g, FACE_A])
            ref_b = int(kept[g, FACE_B])
            if ref_a != ka:
                body_edge(sa, na, ref_a, world_x, world_y, edge_len, edge_nx, edge_ny)
            if ref_b != kb:
                body_edge(sb, nb, ref_b, world_x, world_y, edge_len, edge_nx, edge_ny)
            sep_a = edge_separation(world_x, world_y, edge_nx, edge_ny, sa + ref_a, sb, nb)
            if sep_a < 0.0:
                sep_b = edge_separation(world_x, world_y, edge_nx, edge_ny, sb + ref_b, sa, na)
        else:
            kept[g, FACE_A] = -1.0
            body_edges(sa, na, world_x, world_y, edge_len, edge_nx, edge_ny)
            body_edges(sb, nb, world_x, world_y, edge_len, edge_nx, edge_ny)
            ref_b = kb
            sep_a, ref_a, next_a = deepest_face(
                world_x, world_y, edge_len, edge_nx, edge_ny, sa, na, sb, nb
            )
            if sep_a < 0.0:
                sep_b, ref_b, next_b = deepest_face(
                    world_x, world_y, edge_len, edge_nx, edge_ny, sb, nb, sa, na
                )
                if sep_b < 0.0:
                    keep_faces(
                        kept,
                        g,
                        a,
                        b,
                        ref_a,
                        ref_b,
                        sep_a - next_a,
                        sep_b - next_b,
                        body_x,
                        body_y,
                        body_theta,
                        body_radius,
                    )
        if sep_a < 0.0 and sep_b < 0.0 and (ref_a != ka or ref_b != kb):
            # the general law's reference face is the shallower of the two (b's only if
            # shallower by FACE_SWITCH_TOLERANCE of the larger body's size); the other face
            # follows from it (the turn limit), so the reference must be the graph's
            if sep_b > sep_a + FACE_SWITCH_TOLERANCE * pair_size(world_x, world_y, sa, na, sb, nb):
                if ref_b != kb:
                    return BROKEN_FACES, g
            elif ref_a != ka:
                return BROKEN_FACES, g
        touching[g] = sep_a < 0.0 and sep_b < 0.0
    return HELD, -1


@njit(**INLINE_OPTIONS)
def pair_size(world_x, world_y, sa, na, sb, nb):
    """The larger extent of the two bodies' bounds, along x or y [m] (what the general law
    weighs FACE_SWITCH_TOLERANCE by)."""
    size = 0.0
    for s, n in ((sa, na), (sb, nb)):
        lo_x = world_x[s]
        hi_x = world_x[s]
        lo_y = world_y[s]
        hi_y = world_y[s]
        for k in range(s + 1, s + n):
            lo_x = min(lo_x, world_x[k])
            hi_x = max(hi_x, world_x[k])
            lo_y = min(lo_y, world_y[k])
            hi_y = max(hi_y, world_y[k])
        size = max(size, max(hi_x - lo_x, hi_y - lo_y))
    return size


@njit(**NO_ALLOC_OPTIONS)
def pair_outside(graph, work, n_pair):
    """The first candidate pair of the last sweep that is no contact of the graph, as
    a * n_body + b; -1 for none."""
    n_body = graph.index.shape[0]
    for p in range(n_pair):
        if graph.index[work.pair_a[p], work.pair_b[p]] < 0:
            return work.pair_a[p] * n_body + work.pair_b[p]
    return -1


@njit(**NO_ALLOC_OPTIONS)
def run_steps(
    model,
    settings,
    state,
    samples,
    graph,
    work,
    kept,
    touching,
    ref_cos,
    ref_sin,
    step_start,
    step_stop,
    step_first,
    rest_from_step,
    n_sample,
    collapse_sample,
):
    """:func:`run` with its bundles; the stages of :func:`stonedem.kernels.step.run_steps`.
    ref_cos, ref_sin: cos and sin of each body's reference angle (a driven body's at every step)."""
    dt = settings.dt
    n_steps = settings.n_steps
    n_body = model.body_mass.shape[0]
    body_driven = model.body_driven
    body_x, body_y, body_theta = state.body_x, state.body_y, state.body_theta
    pair_ft, pair_memory, events = state.pair_ft, state.pair_memory, state.events
    sweep_x, sweep_y, sweep_theta = work.sweep_x, work.sweep_y, work.sweep_theta
    pair_a, pair_b, face_a, face_b = graph.pair_a, graph.pair_b, graph.face_a, graph.face_b
    n_contact_max = pair_a.shape[0]
    h, v = model.horizontal, model.vertical
    k_t = model.law.k_t
    out_every = settings.out_every

    tilt_alarm = smallest_theta_cr(model)
    need_sweep = True
    status = STATUS_OK
    # steps to the next multiple of out_every, counted down: no integer division a step
    to_sample = (out_every - step_start % out_every) % out_every
    for n in range(step_start, min(step_stop, n_steps + 1)):
        t = n * dt
        # 1. driven bodies at the base pose of t_n; world vertices (no bounds: no broad phase to
        # feed)
        d_h, vel_h, _ = base_motion(
            t, h.kind, h.params, h.table_accel, h.table_vel, h.table_disp, h.table_dt
        )
        d_v, vel_v, _ = base_motion(
            t, v.kind, v.params, v.table_accel, v.table_vel, v.table_disp, v.table_dt
        )
        place_graph(model, state, work, ref_cos, ref_sin, d_h, vel_h, d_v, vel_v)

        suspect = track(model, state, work, n, d_h, d_v, tilt_alarm)
        if suspect and events[EVENT_COLLAPSE] < 0 and collapsed(model, state, work, d_v):
            events[EVENT_COLLAPSE] = n
        stop = settings.stop_on_collapse and events[EVENT_COLLAPSE] == n

        # 2. the guard: no pair outside the graph within the margin (the general loop's
        # broad phase, at its steps), every contact on the graph's faces
        if need_sweep or needs_resweep(model, state, work):
            body_bounds(
                n_body,
                model.vert_start,
                work.world_x,
                work.world_y,
                work.lo_x,
                work.lo_y,
                work.hi_x,
                work.hi_y,
            )
            n_pair = candidate_pairs_into(
                n_body,
                body_driven,
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
            outside = pair_outside(graph, work, min(n_pair, work.pair_a.shape[0]))
            if outside >= 0 or n_pair > work.pair_a.shape[0]:
                return STATUS_GENERAL, n_sample, collapse_sample, n, BROKEN_PAIR, outside
            need_sweep = False
            for b in range(n_body):
                sweep_x[b] = body_x[b]
                sweep_y[b] = body_y[b]
                sweep_theta[b] = body_theta[b]
        broken, which = graph_holds(model, state, work, graph, kept, touching)
        if broken != HELD:
            return STATUS_GENERAL, n_sample, collapse_sample, n, broken, which

        # 3. contact forces from the velocities v_{n-1/2}, pair by pair in the general loop's order
        sample = to_sample == 0 or n == n_steps or stop
        to_sample = out_every - 1 if to_sample == 0 else to_sample - 1
        clear_forces(work)
        n_contact = 0
        elastic = 0.0
        for g in range(n_contact_max):
            a = pair_a[g]
            b = pair_b[g]
            if not touching[g]:
                if pair_memory[a, b, MEM_ACTIVE] != 0.0:
                    release_contact(a, b, pair_ft, pair_memory, k_t, state.energy_acc)
                continue
            n_contact += 1
            elastic = face_contact_forces(
                model, state, work, a, b, face_a[g], face_b[g], dt, sample, elastic
            )

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
            n_contact_max,
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
    return status, n_sample, collapse_sample, step_stop, HELD, -1
