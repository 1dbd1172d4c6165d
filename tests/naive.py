"""Slow, obviously correct references for the compiled kernels (tests only)."""

import numpy as np


def overlap_area_by_sampling(a: np.ndarray, b: np.ndarray, n: int = 400) -> float:
    """Overlap area of two convex CCW polygons by counting grid points inside both."""
    lo = np.maximum(a.min(axis=0), b.min(axis=0))
    hi = np.minimum(a.max(axis=0), b.max(axis=0))
    if np.any(hi <= lo):
        return 0.0
    xs = lo[0] + (np.arange(n) + 0.5) * (hi[0] - lo[0]) / n
    ys = lo[1] + (np.arange(n) + 0.5) * (hi[1] - lo[1]) / n
    gx, gy = np.meshgrid(xs, ys)
    pts = np.stack([gx.ravel(), gy.ravel()], axis=1)
    inside = inside_convex(a, pts) & inside_convex(b, pts)
    return float(inside.mean() * (hi[0] - lo[0]) * (hi[1] - lo[1]))


def inside_convex(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    ok = np.ones(len(pts), dtype=bool)
    for i in range(len(poly)):
        p, q = poly[i], poly[(i + 1) % len(poly)]
        ok &= (q[0] - p[0]) * (pts[:, 1] - p[1]) - (q[1] - p[1]) * (pts[:, 0] - p[0]) >= 0
    return ok


def half_plane_clip(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Overlap polygon by a plain-Python Sutherland-Hodgman, list based."""
    poly = [tuple(v) for v in a]
    for i in range(len(b)):
        p, q = b[i], b[(i + 1) % len(b)]

        def side(v, p=p, q=q):
            return (q[0] - p[0]) * (v[1] - p[1]) - (q[1] - p[1]) * (v[0] - p[0])

        new = []
        for k in range(len(poly)):
            s, f = poly[k], poly[(k + 1) % len(poly)]
            ss, sf = side(s), side(f)
            if ss >= 0:
                new.append(s)
            if (ss >= 0) != (sf >= 0):
                t = ss / (ss - sf)
                new.append((s[0] + t * (f[0] - s[0]), s[1] + t * (f[1] - s[1])))
        poly = new
        if not poly:
            break
    return np.array(poly) if poly else np.zeros((0, 2))
