"""Contact force law (thesis Eq. 3.4-3.6) on hand-computed cases."""

import numpy as np
import pytest

from stonedem.engine import geometry
from stonedem.kernels import step
from stonedem.kernels.contact import area_contact_forces as contact_forces
from stonedem.kernels.contact import winkler_integral
from tests.kernels.bundles import law_bundles


def two_boxes(depth, shift_x=0.0):
    """Base 4 x 0.5 (top at 0) and a 1 x 1 block pushed ``depth`` into it."""
    base = geometry.box_vertices(4.0, 0.5, (0.0, -0.25))
    block = geometry.box_vertices(1.0, 1.0, (shift_x, 0.5 - depth))
    verts = np.vstack([base, block])
    return verts, np.array([0, 4, 8]), np.array([[0.0, -0.25], [shift_x, 0.5 - depth]])


def call(
    depth, vel_block=(0.0, 0.0, 0.0), mu=0.5, k_n=1e8, c_n=0.0, k_t=1e8, c_t=0.0, ft=0.0, dt=1e-4
):
    verts, start, centres = two_boxes(depth)
    pair_ft = np.zeros((2, 2))
    pair_ft[0, 1] = ft
    law = step.Law(
        kind=step.CONTACT_AREA, k_n=k_n, k_t=k_t, c_t=c_t, frame_rule=0, params=np.array([c_n])
    )
    # masses do not enter the area law
    model, state, work = law_bundles(
        verts,
        start,
        centres,
        law,
        mass=[1.0, 1.0],
        inertia=[1.0, 1.0],
        driven=[True, False],
        vel=[(0.0, 0.0, 0.0), vel_block],
        mu=mu,
        pair_ft=pair_ft,
    )
    n = contact_forces(model, state, work, 1, dt, True)
    return n[0], work.force_x, work.force_y, work.torque, state.pair_ft, state.pair_memory


def test_normal_force_is_stiffness_times_overlap_area():
    n, fx, fy, tq, *_ = call(1e-4)
    assert n == 1
    # the 0.1 mm sliver is computed from coordinates of order 1 m: ~1e-8 relative rounding
    assert fy[1] == pytest.approx(1e8 * 1.0 * 1e-4, rel=1e-7), "thesis Eq. 3.4: k_n A"
    assert fy[0] == pytest.approx(-fy[1]), "equal and opposite"
    assert tq[1] == pytest.approx(0.0, abs=1e-6), "centred overlap, no moment"


def test_normal_damping_adds_and_never_pulls():
    _, _, fy, *_ = call(1e-4, vel_block=(0.0, -0.1, 0.0), c_n=1e4)
    assert fy[1] == pytest.approx(1e4 + 1e4 * 0.1, rel=1e-7), "k_n A + c_n v_N"
    _, _, fy, *_ = call(1e-6, vel_block=(0.0, 1.0, 0.0), c_n=1e6)
    assert fy[1] == 0.0, "separating fast: no tension"


def test_tangential_spring_increments_and_coulomb_cap():
    # block moving right at 0.01 m/s: F_T,el grows by k_t v dt and opposes the motion
    _, fx, _, _, pair_ft, _ = call(1e-4, vel_block=(0.01, 0.0, 0.0), k_t=1e6, mu=10.0)
    assert pair_ft[0, 1] == pytest.approx(1e6 * 0.01 * 1e-4)
    assert fx[1] == pytest.approx(-1.0, rel=1e-9)
    # the cap: mu F_N
    _, fx, fy, _, pair_ft, _ = call(1e-4, vel_block=(1.0, 0.0, 0.0), k_t=1e8, mu=0.3)
    assert abs(fx[1]) == pytest.approx(0.3 * fy[1], rel=1e-12), "thesis Eq. 3.6"
    assert pair_ft[0, 1] == pytest.approx(0.3 * fy[1]), "on slip the spring sits at the cap"


def test_forces_conserve_angular_momentum_for_a_corner_contact():
    # block tilted onto its right corner: forces act at the overlap centroid, off both centroids
    base = geometry.box_vertices(4.0, 0.5, (0.0, -0.25))
    block = geometry.rotate_about(geometry.box_vertices(1.0, 1.0, (0.0, 0.5)), -0.2, (0.5, 0.0))
    block[:, 1] -= 1e-3
    verts = np.vstack([base, block])
    start = np.array([0, 4, 8])
    centres = np.array([[0.0, -0.25], block.mean(axis=0)])
    law = step.Law(
        kind=step.CONTACT_AREA, k_n=1e8, k_t=1e8, c_t=1e3, frame_rule=0, params=np.array([1e4])
    )
    model, state, work = law_bundles(
        verts,
        start,
        centres,
        law,
        mass=[1.0, 1.0],
        inertia=[1.0, 1.0],
        driven=[True, False],
        vel=[(0.0, 0.0, 0.0), (0.3, -0.2, 0.5)],
        mu=0.4,
    )
    n = contact_forces(model, state, work, 1, 1e-4, False)
    fx, fy, tq = work.force_x, work.force_y, work.torque
    assert n[0] == 1 and tq[1] != 0.0
    moment = tq.sum() + np.sum(centres[:, 0] * fy - centres[:, 1] * fx)
    assert moment == pytest.approx(0.0, abs=1e-9 * abs(fy[1])), "no net moment about the origin"
    assert fx.sum() == pytest.approx(0.0, abs=1e-9) and fy.sum() == pytest.approx(0.0, abs=1e-9)


def test_no_overlap_no_force_and_memory_released():
    n, fx, fy, tq, pair_ft, _ = call(-1e-3, ft=5.0)
    assert n == 0 and fy[1] == 0.0


def test_winkler_integral_of_a_triangle_and_a_sliver():
    # depth rising linearly from 0 to D over L: int d^2 ds = D^2 L / 3
    x = np.array([0.0, 2.0, 2.0])
    y = np.array([0.0, 0.0, 0.3])
    assert winkler_integral(x, y, 3, 1.0, 0.0, 0.0, 1.0) == pytest.approx(
        0.3**2 * 2.0 / 3.0, rel=1e-12
    )
    x = np.array([0.0, 1.0, 1.0, 0.0])
    y = np.array([0.0, 0.0, 1e-4, 1e-4])
    assert winkler_integral(x, y, 4, 1.0, 0.0, 0.0, 1.0) == pytest.approx(1e-8, rel=1e-9)
