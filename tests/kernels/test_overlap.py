"""Overlap polygon, area, centroid and contact frame (thesis 3.6-3.7) against slow references."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from stonedem.engine import geometry
from stonedem.kernels.overlap import (
    FRAME_BOUNDARY,
    FRAME_THESIS,
    MAX_OVERLAP_VERTICES,
    clip_convex_polygons,
    contact_frame,
    polygon_area_centroid,
)
from tests import naive


def overlap(a, b):
    s = np.zeros((4, MAX_OVERLAP_VERTICES))
    n = clip_convex_polygons(
        a[:, 0].copy(), a[:, 1].copy(), b[:, 0].copy(), b[:, 1].copy(), s[0], s[1], s[2], s[3]
    )
    if n == 0:
        return 0.0, None, s, 0
    area, cx, cy = polygon_area_centroid(s[0], s[1], n)
    return area, np.array([cx, cy]), s, n


def frame(s, n, a, b, rule):
    return contact_frame(
        s[0],
        s[1],
        n,
        a[:, 0].copy(),
        a[:, 1].copy(),
        b[:, 0].copy(),
        b[:, 1].copy(),
        a[:, 0].mean(),
        a[:, 1].mean(),
        b[:, 0].mean(),
        b[:, 1].mean(),
        rule,
    )


def test_box_on_box_overlap_is_the_sliver():
    base = geometry.box_vertices(4.0, 0.5, (0.0, -0.25))
    block = geometry.box_vertices(0.25, 1.0, (0.3, 0.5 - 1e-4))
    area, c, s, n = overlap(base, block)
    assert area == pytest.approx(0.25 * 1e-4, rel=1e-9), "sliver 0.25 m x 0.1 mm"
    assert c == pytest.approx([0.3, -0.5e-4], abs=1e-12)
    nx, ny, tx, ty, chord = frame(s, n, base, block, FRAME_BOUNDARY)
    assert (nx, ny) == pytest.approx((0.0, 1.0), abs=1e-14), (
        "boundary rule: exactly the face normal"
    )
    assert chord == pytest.approx(0.25, rel=1e-9)
    assert (tx, ty) == pytest.approx((ny, -nx))
    # thesis 3.7: longest diagonal of the 0.25 x 1e-4 sliver, tilted by 1e-4 / 0.25
    nx, ny, *_ = frame(s, n, base, block, FRAME_THESIS)
    assert abs(nx) == pytest.approx(1e-4 / 0.25, rel=1e-3) and ny > 0


def test_flush_drums_normal_ignores_shared_sides():
    lower = geometry.box_vertices(1.0, 0.75, (0.0, 0.375))
    upper = geometry.box_vertices(1.0, 0.75, (0.0, 0.75 + 0.375 - 2e-5))
    area, c, s, n = overlap(lower, upper)
    nx, ny, *_ = frame(s, n, lower, upper, FRAME_BOUNDARY)
    assert (nx, ny) == pytest.approx((0.0, 1.0), abs=1e-12)


def test_corner_triangle_tangent_along_longest_side():
    base = geometry.box_vertices(4.0, 0.5, (0.0, -0.25))
    # block leaning on its right corner, corner 1 mm into the base
    block = geometry.rotate_about(geometry.box_vertices(0.25, 1.0, (0.0, 0.5)), -0.1, (0.125, 0.0))
    block[:, 1] -= 1e-3
    area, c, s, n = overlap(base, block)
    assert n == 3
    for rule in (FRAME_BOUNDARY, FRAME_THESIS):
        nx, ny, *_ = frame(s, n, base, block, rule)
        assert (nx, ny) == pytest.approx((0.0, 1.0), abs=1e-9), "tangent along the base face"


def test_separated_polygons_have_no_overlap():
    a = geometry.box_vertices(1.0, 1.0, (0.0, 0.0))
    b = geometry.box_vertices(1.0, 1.0, (1.5, 0.0))
    assert overlap(a, b)[0] == 0.0


convex = st.builds(
    lambda w, h, x, y, ang: geometry.box_vertices(w, h, (x, y), ang),
    st.floats(0.1, 2.0),
    st.floats(0.1, 2.0),
    st.floats(-1.0, 1.0),
    st.floats(-1.0, 1.0),
    st.floats(-3.2, 3.2),
)


@settings(max_examples=150, deadline=None)
@given(convex, convex)
def test_overlap_matches_plain_clipper_and_is_symmetric(a, b):
    area_ab, c_ab, *_ = overlap(a, b)
    area_ba, c_ba, *_ = overlap(b, a)
    ref = naive.half_plane_clip(a, b)
    ref_area = abs(geometry.signed_area(ref)) if len(ref) >= 3 else 0.0
    assert np.isfinite(area_ab) and area_ab >= 0.0
    assert area_ab == pytest.approx(ref_area, abs=1e-12), "kernel vs plain Sutherland-Hodgman"
    assert area_ab == pytest.approx(area_ba, abs=1e-12), "overlap(a, b) == overlap(b, a)"
    if area_ab > 1e-9:
        assert c_ab == pytest.approx(c_ba, abs=1e-9)


@pytest.mark.parametrize("shift", [0.0, 0.3, 0.77])
def test_area_against_grid_sampling(shift):
    a = geometry.box_vertices(1.0, 0.6, (0.0, 0.0), 0.3)
    b = geometry.box_vertices(0.8, 0.8, (0.4 + shift, 0.2), -0.5)
    area = overlap(a, b)[0]
    assert area == pytest.approx(naive.overlap_area_by_sampling(a, b), rel=2e-2, abs=1e-3), (
        "grid sampling with 400 x 400 points, 2 %"
    )
