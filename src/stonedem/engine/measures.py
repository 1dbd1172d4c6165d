"""Response measures of columns and colonnades (thesis 6, 6.3.1) from sampled histories.

- total sliding: sum over bodies of the absolute sliding of each body along the top face of
  the body it rests on (its support at rest), in m (the thesis plots cm);
- rocking: mean absolute rotation of the drums (all free bodies when there are no drums);
- rocking onset: first time rocking exceeds theta_cr / 30, theta_cr = atan(b/h) (thesis Eq. 6.2);
  theta_cr is the smallest of the rocking bodies' groups (:func:`rocking_theta_cr`);
- collapse: the engine's flag (mean rotation beyond theta_cr or a body fallen off its support);
- displacement relative to the base: x(t) - x(0) - d_base(t), per body (epistyles in particular).

These functions read sampled histories (the dataset's time series). A peak or a first
time must not depend on how often the run is sampled, so the compiled loop tracks them at
every step (:func:`stonedem.kernels.step.track`) from the same definitions, which
:func:`stonedem.engine.pack.watch_arrays` takes from here (rocking bodies, supports,
sliding frames, epistyles).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from stonedem.engine.geometry import following, rotate_about
from stonedem.engine.scene import Scene, posed_vertices


def bottom_centre(vertices: np.ndarray) -> np.ndarray:
    """Middle of a polygon's lowest vertices (the centre of a drum's bottom face) [m]."""
    bottom = vertices[:, 1].min()
    low = vertices[vertices[:, 1] <= bottom + 1e-9 * max(1.0, np.ptp(vertices))]
    return np.array([0.5 * (low[:, 0].min() + low[:, 0].max()), bottom])


def supports(scene: Scene) -> list[int]:
    """Index of the body each body rests on at t = 0 (the one just below its bottom centre), or
    -1."""
    posed = [posed_vertices(b) for b in scene.bodies]
    out = []
    for i in range(len(posed)):
        if scene.bodies[i].driven:
            out.append(-1)
            continue
        probe = seat_point(scene.bodies[i], 1e-6)
        found = -1
        for j, other in enumerate(posed):
            if j != i and _contains(other, probe):
                found = j
                break
        out.append(found)
    return out


def seat_point(body, below: float = 0.0) -> np.ndarray:
    """The centre of a body's bottom face at t = 0, ``below`` [m] under it (a probe into its
    support) [m]. A leaning body (``lean``, structure.tilt) has its bottom face found upright
    and ``below`` taken square to that face: its lowest corner alone is no face, and straight
    under it may lie outside the inclined body it rests on."""
    if body.lean == 0.0:
        return bottom_centre(posed_vertices(body)) - [0.0, below]
    pivot = body.centroid
    upright = rotate_about(posed_vertices(body), body.lean, pivot)
    return rotate_about((bottom_centre(upright) - [0.0, below])[None, :], -body.lean, pivot)[0]


def _contains(vertices: np.ndarray, point: np.ndarray) -> bool:
    edges = following(vertices) - vertices
    rel = point - vertices
    return bool(np.all(edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0] >= 0.0))


def relative_sliding(scene: Scene, x, y, theta, support: list[int]) -> np.ndarray:
    """Sliding of each body along its support's top face since t = 0 (n_time, n_body) [m]; 0 without
    support.

    The bottom-centre point of the body and the material point of the support under it at
    t = 0 are followed; their separation along the support's rotated x axis is the sliding
    (:func:`sliding_frames`; the compiled loop tracks its peak at every step from the same frames).
    """
    n_time, n_body = x.shape
    out = np.zeros((n_time, n_body))
    frames = sliding_frames(scene, support, x[0], y[0], theta[0])
    for i, s in enumerate(support):
        if s < 0:
            continue
        sep = _separation(frames, i, s, x, y, theta)
        out[:, i] = sep - frames.offset[i]
    return out


class SlidingFrames(NamedTuple):
    """The material point each body's sliding follows (the bottom centre at t = 0), in the
    body's frame (body_x, body_y) and in its support's (support_x, support_y) [m], and their
    separation along the support's x axis at t = 0 (offset) [m]; (n_body,) each, 0 without
    support."""

    body_x: np.ndarray
    body_y: np.ndarray
    support_x: np.ndarray
    support_y: np.ndarray
    offset: np.ndarray


def sliding_frames(scene: Scene, support: list[int], x0, y0, theta0) -> SlidingFrames:
    """:class:`SlidingFrames` from the poses at t = 0 (x0, y0, theta0 (n_body,))."""
    n_body = len(support)
    frames = SlidingFrames(*(np.zeros(n_body) for _ in range(5)))
    for i, s in enumerate(support):
        if s < 0:
            continue
        point = seat_point(scene.bodies[i])
        frames.body_x[i], frames.body_y[i] = _local(point, x0[i], y0[i], theta0[i])
        frames.support_x[i], frames.support_y[i] = _local(point, x0[s], y0[s], theta0[s])
    for i, s in enumerate(support):
        if s >= 0:
            frames.offset[i] = _separation(
                frames, i, s, x0[[i]], y0[[i]], theta0[[i]], x0[[s]], y0[[s]], theta0[[s]]
            )[0]
    return frames


def _separation(frames: SlidingFrames, i, s, x, y, theta, xs=None, ys=None, thetas=None):
    """Separation of body i's followed point from its support s's along the support's x axis [m]:
    poses (n_time, n_body), or body i's (x, y, theta) and the support's (xs, ys, thetas)
    (n_time,)."""
    if xs is None:
        x, y, theta, xs, ys, thetas = x[:, i], y[:, i], theta[:, i], x[:, s], y[:, s], theta[:, s]
    p_i = _world(frames.body_x[i], frames.body_y[i], x, y, theta)
    p_s = _world(frames.support_x[i], frames.support_y[i], xs, ys, thetas)
    return (p_i[0] - p_s[0]) * np.cos(thetas) + (p_i[1] - p_s[1]) * np.sin(thetas)


def _local(point, x0, y0, theta0):
    """Coordinates in a body's frame of ``point`` [m], the body at (x0, y0, theta0)."""
    lx, ly = point[0] - x0, point[1] - y0
    c0, s0 = np.cos(-theta0), np.sin(-theta0)
    return c0 * lx - s0 * ly, s0 * lx + c0 * ly


def _world(lx, ly, x, y, theta):
    """World positions over time of the material point at (lx, ly) in a body's frame."""
    c, s = np.cos(theta), np.sin(theta)
    return x + c * lx - s * ly, y + s * lx + c * ly


def rocking_bodies(scene: Scene) -> np.ndarray:
    """Indices whose mean |theta| is the rocking measure: drums, else every free body."""
    drums = [i for i, b in enumerate(scene.bodies) if b.role == "drum"]
    if drums:
        return np.array(drums)
    return np.array(
        [i for i, b in enumerate(scene.bodies) if not b.driven and b.role != "epistyle"]
    )


def rocking_theta_cr(
    scene: Scene, body_group: np.ndarray, group_theta_cr: np.ndarray, group_lean=None
) -> float:
    """theta_cr [rad] of the rocking measure: the smallest of its bodies' collapse groups; a
    leaning group's toward its lean, theta_cr - |lean| (group_lean, structure.tilt)."""
    groups = np.unique(body_group[rocking_bodies(scene)])
    if group_lean is None or not np.any(group_lean[groups]):
        return float(group_theta_cr[groups].min())
    return float((group_theta_cr[groups] - np.abs(group_lean[groups])).min())


def epistyle_bodies(scene: Scene) -> list[int]:
    """Indices whose mean displacement relative to the base is the epistyle displacement."""
    return [i for i, b in enumerate(scene.bodies) if b.role == "epistyle"]


# rocking onset: mean rotation above this share of theta_cr (thesis 6.3.1)
ONSET_FRACTION = 1.0 / 30.0


def rocking_onset_time(time, rocking, theta_cr) -> float:
    """First time [s] of the samples at which the mean rotation exceeds theta_cr / 30 (thesis
    6.3.1); NaN if never. A run's own onset is found at every step (stonedem.kernels.step.track)."""
    above = np.flatnonzero(rocking > theta_cr * ONSET_FRACTION)
    return float(time[above[0]]) if len(above) else float("nan")
