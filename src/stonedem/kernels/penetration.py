"""Penetration check over a run's samples: the deepest overlap of any two bodies.

A soft contact lets bodies overlap a little (the Winkler layer, or the point law's corner
depth); an overlap that is a sizeable share of a body's area means a contact too soft for
its load, or a sliver body, and the run's answer is not physical (``stonedem.engine.simulate``
reports it as its own status, never as collapse). Run once after the time loop, over the
sampled poses.

The overlap of two convex bodies lies inside the overlap of their bounding boxes, so a
sample whose boxes overlap by less than the deepest overlap found so far is not clipped:
the answer is the same, and a run whose bodies rest on each other (every sample a slight
overlap) clips only the samples that go deeper than all before them.
"""

import numpy as np
from numba import njit

from stonedem.kernels import JIT_OPTIONS
from stonedem.kernels.broad_phase import body_bounds
from stonedem.kernels.integrate import update_world_vertices
from stonedem.kernels.overlap import (
    MAX_OVERLAP_VERTICES,
    clip_convex_polygons,
    polygon_area_centroid,
)
from stonedem.kernels.scalar import isfinite

# a sample is clipped unless its boxes' overlap is below the deepest overlap by more than this
# share: the clipped area's rounding (~1e-16 of the coordinates squared) never decides
BOX_MARGIN = 1e-6


@njit(**JIT_OPTIONS)
def deepest_overlap(vert_start, local_x, local_y, body_area, x, y, theta):
    """(largest overlap area / the smaller body's area [1], its sample, body a, body b).

    vert_start, local_x, local_y: the bodies' vertices about their centroids (as packed for
    the time loop); body_area (n_body,) [m2]; x, y, theta (n_sample, n_body): sampled
    poses. Pairs whose bounding boxes are apart are skipped.
    """
    n_sample, n_body = x.shape
    n_vert = local_x.shape[0]
    wx = np.empty(n_vert)
    wy = np.empty(n_vert)
    lo_x = np.empty(n_body)
    hi_x = np.empty(n_body)
    lo_y = np.empty(n_body)
    hi_y = np.empty(n_body)
    out_x = np.empty(MAX_OVERLAP_VERTICES)
    out_y = np.empty(MAX_OVERLAP_VERTICES)
    tmp_x = np.empty(MAX_OVERLAP_VERTICES)
    tmp_y = np.empty(MAX_OVERLAP_VERTICES)
    cos_theta = np.empty(n_body)
    sin_theta = np.empty(n_body)
    worst = 0.0
    at = (-1, -1, -1)
    for s in range(n_sample):
        finite = True
        for b in range(n_body):
            finite = finite and isfinite(x[s, b]) and isfinite(y[s, b]) and isfinite(theta[s, b])
        if not finite:
            continue
        update_world_vertices(
            n_body, vert_start, local_x, local_y, x[s], y[s], theta[s], wx, wy, cos_theta, sin_theta
        )
        body_bounds(n_body, vert_start, wx, wy, lo_x, lo_y, hi_x, hi_y)
        for a in range(n_body):
            for b in range(a + 1, n_body):
                if lo_x[a] > hi_x[b] or lo_x[b] > hi_x[a] or lo_y[a] > hi_y[b] or lo_y[b] > hi_y[a]:
                    continue
                smaller = min(body_area[a], body_area[b])
                box = (min(hi_x[a], hi_x[b]) - max(lo_x[a], lo_x[b])) * (
                    min(hi_y[a], hi_y[b]) - max(lo_y[a], lo_y[b])
                )
                if box * (1.0 + BOX_MARGIN) < worst * smaller:
                    continue
                sa, ea = vert_start[a], vert_start[a + 1]
                sb, eb = vert_start[b], vert_start[b + 1]
                n = clip_convex_polygons(
                    wx[sa:ea], wy[sa:ea], wx[sb:eb], wy[sb:eb], out_x, out_y, tmp_x, tmp_y
                )
                if n < 3:
                    continue
                area, _, _ = polygon_area_centroid(out_x, out_y, n)
                share = area / smaller
                if share > worst:
                    worst = share
                    at = (s, a, b)
    return worst, at[0], at[1], at[2]
