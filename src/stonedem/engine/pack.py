"""A scene packed into the arrays the compiled kernels read, once per run.

:func:`pack_scene` flattens the bodies into structure-of-arrays (:class:`SceneArrays`);
:func:`kernel_model` bundles them with the contact law's row (:mod:`stonedem.engine.laws`),
gravity and the base motions into :class:`stonedem.kernels.step.Model`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stonedem.engine.laws import LAWS
from stonedem.engine.scene import Scene, initial_pose
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
        law=step.Law(kind=LAWS[law.model].code, k_n=law.k_n, damping=LAWS[law.model].kernel_damping(law),
                     impact=law.impact == "plastic", k_t=law.k_t, c_t=law.c_t,
                     frame_rule=FRAME_RULES[law.frame]),
        horizontal=excitation(scene.horizontal), vertical=excitation(scene.vertical),
    )
