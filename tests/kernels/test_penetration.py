"""The penetration scan skips samples by their bounding boxes and still finds what clipping
every sample finds: the same deepest overlap, at the same sample, of the same pair."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from stonedem.kernels.overlap import (
    MAX_OVERLAP_VERTICES,
    clip_convex_polygons,
    polygon_area_centroid,
)
from stonedem.kernels.penetration import deepest_overlap

# a base slab, a block resting on it and a second block beside that one (vertices about centroids)
BOXES = [(2.0, 0.5), (0.4, 1.2), (0.5, 0.8)]


def packed():
    local_x, local_y, start = [], [], [0]
    for w, h in BOXES:
        local_x += [-w / 2, w / 2, w / 2, -w / 2]
        local_y += [-h / 2, -h / 2, h / 2, h / 2]
        start.append(len(local_x))
    areas = np.array([w * h for w, h in BOXES])
    return np.array(start, dtype=np.int64), np.array(local_x), np.array(local_y), areas


def every_sample_clipped(start, local_x, local_y, areas, x, y, theta):
    """(share, sample, a, b): the deepest overlap, clipping every pair at every sample."""
    worst, at = 0.0, (-1, -1, -1)
    out = [np.empty(MAX_OVERLAP_VERTICES) for _ in range(4)]
    for s in range(x.shape[0]):
        c, sn = np.cos(theta[s]), np.sin(theta[s])
        spans = [slice(start[b], start[b + 1]) for b in range(len(areas))]
        wx = [x[s, b] + c[b] * local_x[p] - sn[b] * local_y[p] for b, p in enumerate(spans)]
        wy = [y[s, b] + sn[b] * local_x[p] + c[b] * local_y[p] for b, p in enumerate(spans)]
        for a in range(len(areas)):
            for b in range(a + 1, len(areas)):
                n = clip_convex_polygons(wx[a], wy[a], wx[b], wy[b], *out)
                if n >= 3:
                    share = polygon_area_centroid(out[0], out[1], n)[0] / min(areas[a], areas[b])
                    if share > worst:
                        worst, at = share, (s, a, b)
    return worst, *at


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_skipping_by_boxes_finds_what_clipping_all_finds(seed):
    rng = np.random.default_rng(seed)
    start, local_x, local_y, areas = packed()
    n_sample = int(rng.integers(1, 60))
    # resting with a small random overlap, rocking a little, the neighbour sometimes pressed in
    x = np.column_stack(
        [np.zeros(n_sample), rng.normal(0.0, 0.05, n_sample), 0.5 + rng.normal(0.0, 0.05, n_sample)]
    )
    y = np.column_stack(
        [
            np.zeros(n_sample),
            0.85 - rng.uniform(0.0, 0.02, n_sample),
            0.65 - rng.uniform(0.0, 0.02, n_sample),
        ]
    )
    theta = np.column_stack(
        [np.zeros(n_sample), rng.normal(0.0, 0.02, n_sample), rng.normal(0.0, 0.02, n_sample)]
    )
    found = deepest_overlap(start, local_x, local_y, areas, x, y, theta)
    expected = every_sample_clipped(start, local_x, local_y, areas, x, y, theta)
    assert found[0] == expected[0] and found[1:] == expected[1:]
    assert found[0] > 0.0  # the block rests in the slab at every sample
