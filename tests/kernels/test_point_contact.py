"""Point contacts at the contact face's end vertices (stonedem.kernels.point_contact)."""

import math

import numpy as np
import pytest

from stonedem.kernels import step
from stonedem.kernels.contact import E_BASE_WORK, E_DAMPING, N_ENERGY_ACC
from stonedem.kernels.point_contact import (
    FACE_A,
    N_FACE_CACHE,
    deepest_face,
    edge_separation,
    faces_hold,
    keep_faces,
    plastic_impulse,
    point_contact_forces,
    world_edges,
)
from tests.kernels.bundles import law_bundles

K_N = 1e9


def box(cx, cy, w, h, angle=0.0):
    c, s = math.cos(angle), math.sin(angle)
    local = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
    return local @ np.array([[c, s], [-s, c]]) + [cx, cy]


def forces(base, block, mass=100.0, damping=0.0, vel=(0.0, 0.0, 0.0), impact=False, memory=None):
    """(force_x, force_y, torque, n_contact, stored, memory) of a driven base (body 0) and a block
    (body 1)."""
    verts = np.vstack([base, block])
    law = step.Law(
        kind=step.CONTACT_POINT,
        k_n=K_N,
        k_t=K_N,
        c_t=0.0,
        frame_rule=0,
        params=np.array([damping, 1.0 if impact else 0.0]),
    )
    model, state, work = law_bundles(
        verts,
        [0, 4, 8],
        [base.mean(0), block.mean(0)],
        law,
        mass=[1e9, mass],
        inertia=[1e9, mass / 6.0],
        driven=[True, False],
        vel=[(0.0, 0.0, 0.0), vel],
        mu=10.0,
        memory=memory,
    )
    n, stored = point_contact_forces(model, state, work, 1, 1e-4, True)
    return work.force_x, work.force_y, work.torque, n, stored, state.pair_memory


def test_flat_block_is_carried_by_its_two_corners_like_a_face():
    depth = 1e-5
    fx, fy, tq, n, stored, _ = forces(box(0, -0.25, 4, 0.5), box(0, 0.5 - depth, 1.0, 1.0))
    # two ends, each k_n (L/2) depth: the face's k_n L depth in all, no moment, no double count
    assert n == 1 and fy[1] == pytest.approx(K_N * 1.0 * depth, rel=1e-9)
    assert abs(fx[1]) < 1e-9 * fy[1] and abs(tq[1]) < 1e-9 * fy[1]
    assert stored == pytest.approx(2 * 0.5 * (K_N * 0.5) * depth**2, rel=1e-9)


def test_flush_drums_of_equal_width_share_their_corners_once():
    depth = 1e-5
    fx, fy, tq, n, _, _ = forces(box(0, -0.5, 1.0, 1.0), box(0, 0.5 - depth, 1.0, 1.0))
    assert fy[1] == pytest.approx(K_N * 1.0 * depth, rel=1e-9) and abs(tq[1]) < 1e-6


def test_pivoting_block_is_pushed_at_its_corner_whatever_the_stiffness():
    # a 1 x 1 block tilted onto its right corner, sunk 0.1 mm: the reaction acts at the corner
    theta, sink = 0.05, 1e-4
    block = box(0, 0, 1.0, 1.0, angle=theta)
    corner = block[np.argmin(block[:, 1])]
    block = block - [0.0, corner[1] + sink]
    corner = block[np.argmin(block[:, 1])]
    fx, fy, tq, n, _, _ = forces(box(0, -0.25, 4, 0.5), block)
    centre = block.mean(0)
    # moment about the centroid equals that of the force at the corner: lever = corner - centroid
    assert fy[1] > 0 and tq[1] == pytest.approx(
        (corner[0] - centre[0]) * fy[1] - (corner[1] - centre[1]) * fx[1], rel=1e-9
    )


def test_plastic_impulse_stops_the_landing_corner_and_books_the_loss():
    bx, by = np.array([0.0, 0.0]), np.array([-0.25, 0.5])
    vx, vy, om = np.array([0.0, 0.0]), np.array([0.0, -0.2]), np.array([0.0, 1.0])
    mass, inertia = np.array([1e9, 100.0]), np.array([1e9, 100.0 / 6.0])
    driven = np.array([True, False])
    acc = np.zeros(N_ENERGY_ACC)
    ke0 = 0.5 * mass[1] * (vx[1] ** 2 + vy[1] ** 2) + 0.5 * inertia[1] * om[1] ** 2
    px, py = -0.5, 0.0  # the landing corner
    plastic_impulse(0, 1, px, py, 0.0, 1.0, 10.0, bx, by, vx, vy, om, mass, inertia, driven, acc)
    v_corner = (vx[1] - om[1] * (py - by[1]), vy[1] + om[1] * (px - bx[1]))
    assert np.allclose(v_corner, 0.0, atol=1e-12)  # sticks: no bounce, no slip (Housner)
    ke1 = 0.5 * mass[1] * (vx[1] ** 2 + vy[1] ** 2) + 0.5 * inertia[1] * om[1] ** 2
    assert acc[E_DAMPING] == pytest.approx(ke0 - ke1, rel=1e-12) and acc[E_BASE_WORK] == 0.0

    # angular momentum about the landing corner is conserved (Housner 1963)
    def h_corner(v_x, v_y, w):
        return inertia[1] * w + mass[1] * ((bx[1] - px) * v_y - (by[1] - py) * v_x)

    assert h_corner(vx[1], vy[1], om[1]) == pytest.approx(h_corner(0.0, -0.2, 1.0), rel=1e-12)


def square(cx, cy, half=0.5, angle=0.0):
    """Counter-clockwise vertices (x, y) of a square of side 2 half centred at (cx, cy)."""
    c, s = math.cos(angle), math.sin(angle)
    local = [(-half, -half), (half, -half), (half, half), (-half, half)]
    return (
        np.array([cx + c * x - s * y for x, y in local]),
        np.array([cy + s * x + c * y for x, y in local]),
    )


def edges(xs, ys):
    """(length, nx, ny) of every edge of one polygon (world_edges on one body)."""
    out = [np.zeros(len(xs)) for _ in range(3)]
    world_edges(1, np.array([0, len(xs)]), xs, ys, *out)
    return out


def depth_of(ax, ay, bx, by):
    """deepest_face of b against a's edges, the two polygons one after the other in the world
    arrays."""
    length, nx, ny = edges(ax, ay)
    pad = np.zeros(len(bx))
    sep, k, _ = deepest_face(
        np.concatenate([ax, bx]),
        np.concatenate([ay, by]),
        np.concatenate([length, pad]),
        np.concatenate([nx, pad]),
        np.concatenate([ny, pad]),
        0,
        len(ax),
        len(ax),
        len(bx),
    )
    return sep, k


def test_deepest_face_finds_the_overlap_depth_and_the_separating_axis():
    ax, ay = square(0.0, 0.0)
    # b sits 0.1 m into a's top face (edge 2: (0.5, 0.5) -> (-0.5, 0.5), outward normal +y)
    bx, by = square(0.0, 0.9)
    sep, k = depth_of(ax, ay, bx, by)
    assert k == 2 and sep == pytest.approx(-0.1, abs=1e-12)
    # ... and a sits 0.1 m into b's bottom face (edge 0)
    sep, k = depth_of(bx, by, ax, ay)
    assert k == 0 and sep == pytest.approx(-0.1, abs=1e-12)
    # 0.2 m apart sideways: a's right face (edge 1) separates them by 0.2
    bx, by = square(1.2, 0.0)
    sep, k = depth_of(ax, ay, bx, by)
    assert k == 1 and sep == pytest.approx(0.2, abs=1e-12)
    # a corner of a tilted b dips 1 mm into a's top face
    tilt = 0.05
    dip = 0.5 * math.sqrt(2.0) * math.cos(math.pi / 4 - tilt)  # centre to lowest corner, vertically
    bx, by = square(0.3, 0.5 + dip - 1e-3, angle=tilt)
    sep, k = depth_of(ax, ay, bx, by)
    assert k == 2 and sep == pytest.approx(-1e-3, abs=1e-12)


def test_deepest_face_also_gives_the_next_largest_separation():
    ax, ay = square(0.0, 0.0)
    bx, by = square(0.0, 0.9)  # 0.1 m into a's top face; a's sides see b's far side 1 m away
    length, nx, ny = edges(ax, ay)
    pad = np.zeros(4)
    sep, k, following = deepest_face(
        np.concatenate([ax, bx]),
        np.concatenate([ay, by]),
        np.concatenate([length, pad]),
        np.concatenate([nx, pad]),
        np.concatenate([ny, pad]),
        0,
        4,
        4,
        4,
    )
    assert (
        k == 2
        and sep == pytest.approx(-0.1, abs=1e-12)
        and following == pytest.approx(-1.0, abs=1e-12)
    )


def _pair_world(poses, sizes):
    """World vertices and edges of two boxes (x, y, theta), (w, h), as the time loop has them."""
    verts = np.vstack([box(x, y, w, h, t) for (x, y, t), (w, h) in zip(poses, sizes)])
    wx, wy = verts[:, 0].copy(), verts[:, 1].copy()
    out = [np.zeros(8) for _ in range(3)]
    world_edges(2, np.array([0, 4, 8]), wx, wy, *out)
    return wx, wy, out


def test_kept_faces_hold_only_while_they_are_still_the_least_overlap():
    """faces_hold's bound, tried on random pairs of boxes, one resting on the other, moved
    and turned by up to 0.5 m and 0.5 rad: wherever it says the kept faces hold, the full
    separating-axis test picks those faces with the same separations, bit for bit; and
    for small moves it does hold (so the time loop skips most of the test)."""
    rng = np.random.default_rng(7)
    held = {}
    for trial in range(3000):
        sizes = [
            (rng.uniform(0.5, 3.0), rng.uniform(0.2, 1.5)),
            (rng.uniform(0.3, 1.5), rng.uniform(0.3, 2.0)),
        ]
        ta, tb = rng.uniform(-0.05, 0.05), rng.uniform(-0.2, 0.2)
        xa, ya = rng.uniform(-20, 20), rng.uniform(-1, 1)
        # b's lowest corner 1 mm into a's top face, b shifted along it
        lift = 0.5 * (sizes[1][0] * abs(math.sin(tb - ta)) + sizes[1][1] * math.cos(tb - ta))
        along = rng.uniform(-0.3, 0.3) * sizes[0][0]
        poses = [
            (xa, ya, ta),
            (
                xa + along * math.cos(ta) - (sizes[0][1] / 2 + lift - 1e-3) * math.sin(ta),
                ya + along * math.sin(ta) + (sizes[0][1] / 2 + lift - 1e-3) * math.cos(ta),
                tb,
            ),
        ]
        body_x, body_y, body_theta = (np.array([p[i] for p in poses]) for i in range(3))
        radius = np.array([0.5 * math.hypot(w, h) for w, h in sizes])
        wx, wy, (length, nx, ny) = _pair_world(poses, sizes)
        sep_a, k_a, next_a = deepest_face(wx, wy, length, nx, ny, 0, 4, 4, 4)
        sep_b, k_b, next_b = deepest_face(wx, wy, length, nx, ny, 4, 4, 0, 4)
        if sep_a >= 0.0 or sep_b >= 0.0:  # b's dipping corner beyond a's face
            continue
        cache = np.full((1, N_FACE_CACHE), -1.0)
        keep_faces(
            cache,
            0,
            0,
            1,
            k_a,
            k_b,
            sep_a - next_a,
            sep_b - next_b,
            body_x,
            body_y,
            body_theta,
            radius,
        )
        if cache[0, FACE_A] < 0.0:
            continue
        scale = [1e-4, 1e-2, 0.1, 0.5][trial % 4]
        moved = [
            (
                x + rng.uniform(-scale, scale),
                y + rng.uniform(-scale, scale),
                t + rng.uniform(-scale, scale),
            )
            for x, y, t in poses
        ]
        body_x, body_y, body_theta = (np.array([p[i] for p in moved]) for i in range(3))
        holds = faces_hold(cache, 0, 0, 1, body_x, body_y, body_theta, radius)
        held.setdefault(scale, []).append(holds)
        if not holds:
            continue
        wx, wy, (length, nx, ny) = _pair_world(moved, sizes)
        sep, k, _ = deepest_face(wx, wy, length, nx, ny, 0, 4, 4, 4)
        kept = edge_separation(wx, wy, nx, ny, int(cache[0, FACE_A]), 4, 4)
        if sep >= 0.0:  # separated: the kept face must say so too (it is the only use)
            assert kept >= 0.0
            continue
        assert k == cache[0, FACE_A] and kept == sep
        sep, k, _ = deepest_face(wx, wy, length, nx, ny, 4, 4, 0, 4)
        kept = edge_separation(wx, wy, nx, ny, 4 + int(cache[0, 1]), 0, 4)
        assert (kept >= 0.0) if sep >= 0.0 else (k == cache[0, 1] and kept == sep)
    assert all(held[1e-4]) and len(held[1e-4]) > 500
    assert np.mean(held[0.5]) < 0.5  # large turns are re-tested
