"""Response measures of columns and colonnades (thesis 6, 6.3.1) from sampled histories.

- total sliding: sum over bodies of the absolute sliding of each body along the top face of
  the body it rests on (its support at rest), in m (the thesis plots cm);
- rocking: mean absolute rotation of the drums (all free bodies when there are no drums);
- rocking onset: first time rocking exceeds theta_cr / 30, theta_cr = atan(b/h) (thesis Eq. 6.2);
- collapse: the engine's flag (mean rotation beyond theta_cr or a body fallen off its support);
- displacement relative to the base: x(t) - x(0) - d_base(t), per body (epistyles in particular).
"""

from __future__ import annotations

import numpy as np

from stonedem.engine.scene import Scene, posed_vertices


def bottom_centre(vertices: np.ndarray) -> np.ndarray:
    """Middle of a polygon's lowest vertices (the centre of a drum's bottom face) [m]."""
    bottom = vertices[:, 1].min()
    low = vertices[vertices[:, 1] <= bottom + 1e-9 * max(1.0, np.ptp(vertices))]
    return np.array([0.5 * (low[:, 0].min() + low[:, 0].max()), bottom])


def supports(scene: Scene) -> list[int]:
    """Index of the body each body rests on at t = 0 (the one just below its bottom centre), or -1."""
    posed = [posed_vertices(b) for b in scene.bodies]
    out = []
    for i, verts in enumerate(posed):
        if scene.bodies[i].driven:
            out.append(-1)
            continue
        probe = bottom_centre(verts) - [0.0, 1e-6]
        found = -1
        for j, other in enumerate(posed):
            if j != i and _contains(other, probe):
                found = j
                break
        out.append(found)
    return out


def _contains(vertices: np.ndarray, point: np.ndarray) -> bool:
    edges = np.roll(vertices, -1, axis=0) - vertices
    rel = point - vertices
    return bool(np.all(edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0] >= 0.0))


def relative_sliding(scene: Scene, x, y, theta, support: list[int]) -> np.ndarray:
    """Sliding of each body along its support's top face since t = 0 (n_time, n_body) [m]; 0 without support.

    The bottom-centre point of the body and the material point of the support under it at
    t = 0 are followed; their separation along the support's rotated x axis is the sliding.
    """
    n_time, n_body = x.shape
    out = np.zeros((n_time, n_body))
    for i, s in enumerate(support):
        if s < 0:
            continue
        point = bottom_centre(posed_vertices(scene.bodies[i]))
        p_i = _follow(point, x[:, i], y[:, i], theta[:, i])
        p_s = _follow(point, x[:, s], y[:, s], theta[:, s])
        tangent = np.stack([np.cos(theta[:, s]), np.sin(theta[:, s])], axis=1)
        sep = np.sum((p_i - p_s) * tangent, axis=1)
        out[:, i] = sep - sep[0]
    return out


def _follow(point, x, y, theta):
    """World positions over time of the material point that is at ``point`` at t = 0."""
    local = point - np.array([x[0], y[0]])
    c0, s0 = np.cos(-theta[0]), np.sin(-theta[0])
    lx, ly = c0 * local[0] - s0 * local[1], s0 * local[0] + c0 * local[1]
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([x + c * lx - s * ly, y + s * lx + c * ly], axis=1)


def rocking_bodies(scene: Scene) -> np.ndarray:
    """Indices whose mean |theta| is the rocking measure: drums, else every free body."""
    drums = [i for i, b in enumerate(scene.bodies) if b.role == "drum"]
    if drums:
        return np.array(drums)
    return np.array([i for i, b in enumerate(scene.bodies) if not b.driven and b.role != "epistyle"])


def rocking_onset_time(time, rocking, theta_cr) -> float:
    """First time [s] the mean rotation exceeds theta_cr / 30 (thesis 6.3.1); NaN if never."""
    above = np.flatnonzero(rocking > theta_cr / 30.0)
    return float(time[above[0]]) if len(above) else float("nan")
