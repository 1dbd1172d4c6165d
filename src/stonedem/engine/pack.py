"""A scene packed into the arrays the compiled kernels read, once per run.

:func:`pack_scene` flattens the bodies into structure-of-arrays (:class:`SceneArrays`);
:func:`kernel_model` bundles them with the contact law's row (:mod:`stonedem.engine.laws`),
gravity and the base motions into :class:`stonedem.kernels.step.Model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stonedem.engine import measures
from stonedem.engine.geometry import following, rotate_about
from stonedem.engine.laws import LAWS
from stonedem.engine.links import link_arrays
from stonedem.engine.scene import Scene, initial_pose, posed_vertices
from stonedem.errors import InputError
from stonedem.kernels import step
from stonedem.kernels.overlap import FRAME_BOUNDARY, FRAME_THESIS

# "faces": the point law's own frame (stonedem.kernels.point_contact), which ignores frame_rule
FRAME_RULES = {"boundary": FRAME_BOUNDARY, "thesis": FRAME_THESIS, "faces": FRAME_BOUNDARY}


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
    group_theta_cr: np.ndarray  # atan(b/h) of each group at rest, upright (n_group,) [rad]
    # counter-clockwise rotation of each group's rest pose from upright (-lean) (n_group,) [rad]
    group_lean: np.ndarray
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
    group_lean = np.zeros(len(groups))
    for g in groups.values():
        members = np.flatnonzero(body_group == g)
        verts = np.vstack([bodies[i].vertices for i in members])
        leans = [bodies[i].lean for i in members]
        lean = leans[0] if len(set(leans)) == 1 else float(np.mean(leans))
        if lean != 0.0:  # a leaning group's slenderness is its upright one (structure.tilt)
            verts = rotate_about(verts, lean, (0.0, 0.0))
            group_lean[g] = -lean
        width, height = np.ptp(verts, axis=0)
        group_theta_cr[g] = math.atan2(width, height)  # thesis Eq. 6.2
    # a body fell once its centroid is half its height below where it rests; a body released
    # in the air rests where it lands, so its drop to there is no fall (landing_drops)
    fall_depth = np.array([0.5 * np.ptp(b.vertices[:, 1]) for b in bodies]) + landing_drops(scene)

    extent = np.ptp(np.vstack([b.vertices for b in bodies if not b.driven]), axis=0)
    free_sizes = np.array([np.ptp(b.vertices, axis=0).min() for b in bodies if not b.driven])
    return SceneArrays(
        vert_start=vert_start,
        local_x=np.concatenate(local_x),
        local_y=np.concatenate(local_y),
        body_mass=mass,
        body_inertia=inertia,
        body_driven=driven,
        body_radius=radius,
        ref_x=ref[:, 0].copy(),
        ref_y=ref[:, 1].copy(),
        ref_theta=ref[:, 2].copy(),
        pair_mu=np.ascontiguousarray(pair_mu),
        body_group=body_group,
        group_theta_cr=group_theta_cr,
        group_lean=group_lean,
        fall_depth=fall_depth,
        init_x=init[:, 0].copy(),
        init_y=init[:, 1].copy(),
        init_theta=init[:, 2].copy(),
        init_vx=init[:, 3].copy(),
        init_vy=init[:, 4].copy(),
        init_omega=init[:, 5].copy(),
        sweep_axis=int(extent[1] >= extent[0]),
        margin=0.1 * float(free_sizes.min()),
    )


def landing_drops(scene: Scene) -> np.ndarray:
    """How far each body drops straight down from its pose at t = 0 onto what will hold it [m].

    0 for driven bodies and for bodies resting on something that rests on a driven body
    (all of a stacked structure); the height of the gap below a body released in the air
    (plus the drop of what it lands on: an airborne stack falls together); inf for a thrown
    body (an initial velocity) with nothing under it, which may land anywhere, and for every
    free body of a weightless scene. Under a body, "driven" reaches as far as the base sways
    (its largest horizontal displacement). Refused with an InputError naming the body: a
    scene with gravity in which nothing is driven, or a body with nothing under it to land
    on: it would fall freely for ever, which the run would report as a collapse.
    """
    # preflight, the packing and the quiet plan each ask for the same scene's drops in a row
    if _LAST_DROPS and _LAST_DROPS[0] is scene:
        return _LAST_DROPS[1].copy()
    drops = _landing_drops(scene)
    _LAST_DROPS[:] = [scene, drops.copy()]
    return drops


_LAST_DROPS: list = []  # [scene, its landing_drops] of the last scene asked for


def _landing_drops(scene: Scene) -> np.ndarray:
    driven = np.array([b.driven for b in scene.bodies])
    drops = np.where(driven, 0.0, np.inf)
    if scene.gravity == 0.0:
        return drops
    if not driven.any():
        raise InputError(
            "bodies",
            "no body is driven, so nothing holds the others up: every body would fall "
            "freely (a free fall, not a collapse)",
            "add the ground under them as a driven body (driven: true, role: base), or build a "
            "structure: (its base is driven)",
        )
    posed = [posed_vertices(b) for b in scene.bodies]
    lo = np.array([p.min(axis=0) for p in posed])
    hi = np.array([p.max(axis=0) for p in posed])
    size = np.ptp(np.stack([lo, hi]), axis=0)
    # touching (bodies may overlap by a sliver at t = 0) and x ranges that share a length
    touch = 1e-3 * size[:, 1]
    share = 1e-9 * float(size.max())
    reach = None
    for i in np.argsort(lo[:, 1], kind="stable"):  # bottom up: what lies below is done first
        if driven[i]:
            continue
        width = np.minimum(hi[i, 0], hi[:, 0]) - np.maximum(lo[i, 0], lo[:, 0])
        under = (width > share) & np.isfinite(drops)
        under[i] = False
        best = np.inf
        # nearest first by a lower bound of the gap (the bounds'), until none can be nearer
        for j in sorted(np.flatnonzero(under), key=lambda j: lo[i, 1] - hi[j, 1] + drops[j]):
            if lo[i, 1] - hi[j, 1] + drops[j] >= best:
                break
            gap = _vertical_gap(
                posed[i], posed[j], max(lo[i, 0], lo[j, 0]), min(hi[i, 0], hi[j, 0])
            )
            if gap > -min(touch[i], touch[j]):  # else j reaches above body i's bottom: beside it
                best = min(best, max(gap, 0.0) + drops[j])
        if math.isinf(best):  # the base may sway under it
            if reach is None:
                grid = np.arange(0.0, scene.duration + 1e-3, 1e-3)
                reach = float(np.abs(scene.horizontal.evaluate(grid)[0]).max())
            near = (
                driven
                & (lo[:, 0] - reach < hi[i, 0] - share)
                & (hi[:, 0] + reach > lo[i, 0] + share)
                & (hi[:, 1] <= lo[i, 1] + touch[i])
            )
            if near.any():
                best = max(float(lo[i, 1] - hi[near, 1].max()), 0.0)
        if math.isinf(best) and scene.bodies[i].velocity is None:
            raise InputError(
                f"bodies[{i}] ({scene.bodies[i].name})",
                "nothing under it leads down to a driven "
                "body: it would fall freely (a free fall, not a collapse)",
                "place it above the base, or on a body that rests on it",
            )
        drops[i] = best
    return drops


def _vertical_gap(above: np.ndarray, below: np.ndarray, x_from: float, x_to: float) -> float:
    """Smallest vertical distance from the convex polygon ``above`` down to ``below`` over x
    in [x_from, x_to] [m] (it is piecewise linear: its least is at a vertex's x or an end);
    negative where ``below`` reaches higher (it is not below)."""
    xs = np.concatenate([above[:, 0], below[:, 0], [x_from, x_to]])
    xs = xs[(xs >= x_from) & (xs <= x_to)]
    return float((_span(above, xs)[0] - _span(below, xs)[1]).min())


def _span(vertices: np.ndarray, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lowest, highest) y of a convex polygon on the vertical lines at xs [m] (clipped into it)."""
    xs = np.clip(xs, vertices[:, 0].min(), vertices[:, 0].max())[:, None]
    x1, y1 = vertices[:, 0], vertices[:, 1]
    x2, y2 = following(x1), following(y1)
    crossing = (np.minimum(x1, x2) <= xs) & (xs <= np.maximum(x1, x2))
    slanted = x2 != x1
    y = np.where(slanted, y1 + (xs - x1) / np.where(slanted, x2 - x1, 1.0) * (y2 - y1), y1)
    # a vertical edge on the line spans from y1 to y2
    low = np.where(crossing, np.minimum(y, np.where(slanted, y, y2)), np.inf).min(axis=1)
    high = np.where(crossing, np.maximum(y, np.where(slanted, y, y2)), -np.inf).max(axis=1)
    return low, high


def kernel_model(scene: Scene, arrays: SceneArrays) -> step.Model:
    """The read-only bundle :func:`stonedem.kernels.step.run` reads: arrays, contact law, gravity,
    base motion."""
    law = scene.contact

    def excitation(motion):
        return step.Excitation(
            kind=int(motion.kind),
            params=motion.params,
            table_accel=motion.table_accel,
            table_vel=motion.table_vel,
            table_disp=motion.table_disp,
            table_dt=float(motion.table_dt),
        )

    return step.Model(
        vert_start=arrays.vert_start,
        local_x=arrays.local_x,
        local_y=arrays.local_y,
        body_mass=arrays.body_mass,
        body_inertia=arrays.body_inertia,
        body_driven=arrays.body_driven,
        body_radius=arrays.body_radius,
        ref_x=arrays.ref_x,
        ref_y=arrays.ref_y,
        ref_theta=arrays.ref_theta,
        pair_mu=arrays.pair_mu,
        body_group=arrays.body_group,
        group_theta_cr=arrays.group_theta_cr,
        group_lean=arrays.group_lean,
        fall_depth=arrays.fall_depth,
        margin=arrays.margin,
        sweep_axis=arrays.sweep_axis,
        gravity=scene.gravity,
        law=step.Law(
            kind=LAWS[law.model].code,
            k_n=law.k_n,
            k_t=law.k_t,
            c_t=law.c_t,
            frame_rule=FRAME_RULES[law.frame],
            params=np.array(LAWS[law.model].kernel_params(law.params), dtype=np.float64),
        ),
        horizontal=excitation(scene.horizontal),
        vertical=excitation(scene.vertical),
        watch=watch_arrays(scene, arrays),
        links=link_arrays(scene),
    )


def initial_poses(scene: Scene, arrays: SceneArrays) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, theta) (n_body,) at step 0 as the compiled loop has them: free bodies at their
    initial pose, driven ones at their reference shifted by the base displacement at t = 0."""
    d_h, _, _ = scene.horizontal.evaluate(np.array([0.0]))
    d_v, _, _ = scene.vertical.evaluate(np.array([0.0]))
    driven = arrays.body_driven
    return (
        np.where(driven, arrays.ref_x + d_h[0], arrays.init_x),
        np.where(driven, arrays.ref_y + d_v[0], arrays.init_y),
        np.where(driven, arrays.ref_theta, arrays.init_theta),
    )


def watch_arrays(scene: Scene, arrays: SceneArrays) -> step.Watch:
    """The response measures' definitions (:mod:`stonedem.engine.measures`) as
    :func:`stonedem.kernels.step.track` reads them to keep their peaks at every step."""
    n = len(scene.bodies)
    rocking = np.zeros(n)
    rocking[measures.rocking_bodies(scene).astype(np.int64)] = 1.0
    theta_cr = (
        measures.rocking_theta_cr(
            scene, arrays.body_group, arrays.group_theta_cr, arrays.group_lean
        )
        if rocking.any()
        else np.inf
    )
    support = np.array(measures.supports(scene), dtype=np.int64)
    x0, y0, theta0 = initial_poses(scene, arrays)
    frames = measures.sliding_frames(scene, list(support), x0, y0, theta0)
    epistyle = np.zeros(n)
    epistyle[measures.epistyle_bodies(scene)] = 1.0
    return step.Watch(
        rocking=rocking,
        n_rocking=float(rocking.sum()),
        onset_rocking=theta_cr * measures.ONSET_FRACTION,
        support=support,
        slide_x=frames.body_x,
        slide_y=frames.body_y,
        slide_support_x=frames.support_x,
        slide_support_y=frames.support_y,
        slide_offset=frames.offset,
        epistyle=epistyle,
        n_epistyle=float(epistyle.sum()),
        x0=x0,
    )
