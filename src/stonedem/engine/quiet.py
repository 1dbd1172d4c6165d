"""The quiet phases of a run: what the compiled loop need not integrate.

A scene at rest in its reference pose moves rigidly with the base while the base is too
quiet to slide or rock anything (:func:`quiet_threshold`), and once everything is at rest
on a base that is quiet for good. :func:`quiet_steps` plans those phases before the run;
:func:`rigid_motion` and :func:`carry` fill their samples; :func:`settled_state` starts the
loop again from a settled state carried to the first loud instant.

A stretch carried at rest adds nothing to the running peaks of the response measures
(:func:`stonedem.kernels.step.track`): the bodies keep their rotations and their poses
relative to the base and to each other, so every measure keeps the value of the state the
loop left there, which it has already counted.
"""

from __future__ import annotations

import math

import numpy as np

from stonedem.engine.pack import SceneArrays, landing_drops
from stonedem.engine.scene import Scene, posed_vertices
from stonedem.entry import check_interrupt
from stonedem.kernels import step

# the base counts as quiet below half the smallest acceleration that could move a body
QUIET_MARGIN = 0.5
REST_SPEED = 1e-3  # [m s-1] a body slower than this relative to the base is at rest
REST_SECONDS = 0.5  # [s] ... for this long in a row, with the base quiet for good: the run ends
# times evaluated at once by the quiet scan and the carried fill: their memory stays a few
# MB whatever the run's length (a 3600 s scan at 10 us in one piece took 23 GB)
CHUNK = 1 << 16


def quiet_threshold(scene: Scene) -> float:
    """Base acceleration over gravity below which no body can slide or rock: a lower bound [1].

    A body slides only if a/g exceeds the smallest friction coefficient; an assembly above
    a joint rocks only if a/g exceeds (half the joint width) / (height of its centroid above
    the joint), which is at least (narrowest free body) / (2 x height of the free structure).
    Halved (QUIET_MARGIN), so the soft contacts' own vibration has no part in it either. A
    leaning body (structure.tilt) lowers both bounds to those toward its lean.
    """
    free = [posed_vertices(b) for b in scene.bodies if not b.driven]
    mu = [b.friction if b.friction is not None else scene.friction for b in scene.bodies]
    mu_min = min(min(mu), *scene.pair_friction.values()) if scene.pair_friction else min(mu)
    width = min(float(np.ptp(v[:, 0])) for v in free)
    height = float(np.ptp(np.vstack(free)[:, 1]))
    lean = max(abs(b.lean) for b in scene.bodies)
    if lean == 0.0:
        return QUIET_MARGIN * min(mu_min, width / (2.0 * height))
    # a leaning column (structure.tilt): toward its lean it slides at (mu - tan b)/(1 + mu tan b)
    # and rocks past an angle smaller by the lean
    t = math.tan(lean)
    slide = (mu_min - t) / (1.0 + mu_min * t)
    rock = math.tan(max(math.atan(width / (2.0 * height)) - lean, 0.0))
    return QUIET_MARGIN * max(min(slide, rock), 0.0)


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
    ratio = quiet_threshold(scene)
    # the grid of np.arange(0, duration + spacing, spacing), i x spacing, a chunk at a time
    n_grid = math.ceil((scene.duration + spacing) / spacing)
    first_loud = last_loud = None
    for start in range(0, n_grid, CHUNK):
        check_interrupt()
        grid = np.arange(start, min(start + CHUNK, n_grid)) * spacing
        _, _, a_h = h.evaluate(grid)
        _, _, a_v = v.evaluate(grid)
        loud = (np.abs(a_h) >= ratio * (scene.gravity - np.abs(a_v))) | (
            np.abs(a_v) >= 0.5 * scene.gravity
        )
        if loud.any():
            if first_loud is None:
                first_loud = grid[np.argmax(loud)]
            last_loud = grid[len(loud) - 1 - np.argmax(loud[::-1])]
    if first_loud is None:
        first_loud, last_loud = 0.0, 0.0  # nothing to skip but the settled rest at the end
    # released in the air, a body falls first (stonedem.engine.pack.landing_drops)
    at_rest = (
        all(b.driven or (b.tilt_angle == 0.0 and b.velocity is None) for b in scene.bodies)
        and not (landing_drops(scene) > 0.0).any()
    )
    n_first = 0
    if at_rest:
        n_first = max(0, int((first_loud - spacing) / dt)) // out_every * out_every
        n_first = min(n_first, n_steps // out_every * out_every)
    n_rest = max(n_first, int(math.ceil((last_loud + spacing) / dt)))
    return n_first, n_rest


def rigid_motion(
    scene: Scene, arrays: SceneArrays, times, t_from, x_from, y_from, theta_from, energy_from=None
):
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
    x = np.where(
        free, x_from[None, :] + (d_h - d_h0[0])[:, None], arrays.ref_x[None, :] + d_h[:, None]
    )
    y = np.where(
        free, y_from[None, :] + (d_v - d_v0[0])[:, None], arrays.ref_y[None, :] + d_v[:, None]
    )
    theta = np.where(free, theta_from[None, :], arrays.ref_theta[None, :])
    mass = np.where(free, arrays.body_mass, 0.0)
    energy = np.zeros((len(times), step.N_ENERGY))
    energy[:, step.ENERGY_KINETIC] = 0.5 * mass.sum() * (v_h**2 + v_v**2)
    energy[:, step.ENERGY_POTENTIAL] = scene.gravity * (y * mass[None, :]).sum(axis=1)
    if energy_from is not None:
        for col in (step.ENERGY_ELASTIC, step.ENERGY_DAMPING, step.ENERGY_TANGENTIAL):
            energy[:, col] = energy_from[col]
        gained = (
            energy[:, step.ENERGY_KINETIC]
            + energy[:, step.ENERGY_POTENTIAL]
            - energy_from[step.ENERGY_KINETIC]
            - energy_from[step.ENERGY_POTENTIAL]
        )
        energy[:, step.ENERGY_BASE_WORK] = energy_from[step.ENERGY_BASE_WORK] + gained
    return x, y, theta, energy


def carry(
    scene: Scene,
    arrays: SceneArrays,
    samples: "step.Samples",
    n_sample: int,
    n_to: int,
    dt: float,
    out_every: int,
    including: bool = False,
) -> tuple[int, int]:
    """Fill the samples after sample ``n_sample - 1`` every ``out_every`` steps up to step
    ``n_to`` (``including`` it), carried by the base; returns (samples now, last step run)."""
    k = n_sample - 1
    last = int(samples.step[k])
    steps = np.arange(last + out_every, n_to, out_every, dtype=np.int64)
    if including and n_to > last:
        steps = np.append(steps, np.int64(n_to))
    for start in range(0, len(steps), CHUNK):  # rows are independent: the same values in pieces
        check_interrupt()
        part = steps[start : start + CHUNK]
        fill = slice(k + 1 + start, k + 1 + start + len(part))
        samples.step[fill] = part
        filled = rigid_motion(
            scene,
            arrays,
            part * dt,
            last * dt,
            samples.x[k],
            samples.y[k],
            samples.theta[k],
            samples.energy[k],
        )
        samples.x[fill], samples.y[fill], samples.theta[fill], samples.energy[fill] = filled
        samples.n_contact[fill] = samples.n_contact[k]
    return n_sample + len(steps), last


def settled_state(
    scene: Scene,
    arrays: SceneArrays,
    samples: "step.Samples",
    k: int,
    last: int,
    state: "step.State",
    n_first: int,
    dt: float,
) -> None:
    """Move the state settled at step ``last`` (sample k) to step ``n_first``, shifted with the
    base and moving with it; the contacts' memory (in their own frames) and the dissipated
    energy are kept."""
    free = ~arrays.body_driven
    x, y, th, energy = rigid_motion(
        scene,
        arrays,
        np.array([n_first * dt]),
        last * dt,
        samples.x[k],
        samples.y[k],
        samples.theta[k],
        samples.energy[k],
    )
    state.body_x[free], state.body_y[free] = x[0, free], y[0, free]
    state.body_theta[free] = th[0, free]
    _, v_h, _ = scene.horizontal.evaluate(np.array([n_first * dt]))
    _, v_v, _ = scene.vertical.evaluate(np.array([n_first * dt]))
    state.body_vx[free], state.body_vy[free], state.body_omega[free] = v_h[0], v_v[0], 0.0
    # the accumulators are the accumulated energy columns (step.ENERGY_ACCUMULATED on)
    state.energy_acc[:] = energy[0, step.ENERGY_ACCUMULATED :]
