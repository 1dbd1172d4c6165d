"""Polygon properties used at set-up time: area, centroid, polar moment, convexity.

Plain NumPy (not in the time loop). A body is a convex polygon extruded over the scene's
out-of-plane depth; its mass and rotational inertia follow from the polygon and density
(or from a given mass with the same distribution).
"""

import numpy as np


def following(values: np.ndarray) -> np.ndarray:
    """Each vertex's successor's values, the last's the first's: np.roll(values, -1, axis=0)
    without its axis handling (~20 us a call, a few hundred calls per run's set-up)."""
    return np.concatenate((values[1:], values[:1]))


def signed_area(vertices: np.ndarray) -> float:
    """Signed area [m2] of a polygon (n, 2): positive when counter-clockwise (thesis Eq. 3.1)."""
    x, y = vertices[:, 0], vertices[:, 1]
    return 0.5 * float(np.sum(x * following(y) - following(x) * y))


def centroid(vertices: np.ndarray) -> np.ndarray:
    """Centroid [m] of a simple polygon (thesis Eq. 3.2-3.3)."""
    x, y = vertices[:, 0], vertices[:, 1]
    cross = x * following(y) - following(x) * y
    area6 = 3.0 * np.sum(cross)
    return np.array(
        [np.sum((x + following(x)) * cross) / area6, np.sum((y + following(y)) * cross) / area6]
    )


def polar_moment_about_centroid(vertices: np.ndarray) -> float:
    """Polar second moment of area about the centroid, J = int (x^2 + y^2) dA [m4]."""
    v = vertices - centroid(vertices)
    x, y = v[:, 0], v[:, 1]
    xn, yn = following(x), following(y)
    cross = x * yn - xn * y
    ixx = np.sum((y * y + y * yn + yn * yn) * cross) / 12.0
    iyy = np.sum((x * x + x * xn + xn * xn) * cross) / 12.0
    return float(abs(ixx + iyy))


def is_convex(vertices: np.ndarray, tol: float = 1e-12) -> bool:
    """True when the counter-clockwise polygon turns left (or goes straight) at every vertex."""
    d = following(vertices) - vertices
    turn = d[:, 0] * following(d[:, 1]) - d[:, 1] * following(d[:, 0])
    scale = np.max(np.abs(vertices)) ** 2 + 1.0
    return bool(np.all(turn >= -tol * scale))


def is_simple(vertices: np.ndarray) -> bool:
    """True when no two non-adjacent edges of the polygon intersect."""
    n = len(vertices)
    for i in range(n):
        p1, p2 = vertices[i], vertices[(i + 1) % n]
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            q1, q2 = vertices[j], vertices[(j + 1) % n]
            if _segments_intersect(p1, p2, q1, q2):
                return False
    return True


def _segments_intersect(p1, p2, q1, q2) -> bool:
    def orient(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    d1, d2 = orient(q1, q2, p1), orient(q1, q2, p2)
    d3, d4 = orient(p1, p2, q1), orient(p1, p2, q2)
    return (d1 * d2 < 0) and (d3 * d4 < 0)


def box_vertices(width: float, height: float, center=(0.0, 0.0), angle: float = 0.0) -> np.ndarray:
    """Counter-clockwise corners of a width x height rectangle rotated by angle [rad] about its
    centre."""
    hw, hh = 0.5 * width, 0.5 * height
    local = np.array([[-hw, -hh], [hw, -hh], [hw, hh], [-hw, hh]])
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    return local @ rot.T + np.asarray(center, dtype=float)


def rotate_about(vertices: np.ndarray, angle: float, pivot) -> np.ndarray:
    """Vertices rotated counter-clockwise by angle [rad] about the point pivot [m]."""
    c, s = np.cos(angle), np.sin(angle)
    rot = np.array([[c, -s], [s, c]])
    pivot = np.asarray(pivot, dtype=float)
    return (vertices - pivot) @ rot.T + pivot
