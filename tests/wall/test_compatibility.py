"""Compatibility matrices: general form equals manuscript Eq. A2-A3; rigid motions give d = 0."""

import numpy as np

from stonedem.wall.compatibility import block_blocks, interface_matrix, panel_compatibility
from stonedem.wall.panel import build_panel


def test_general_form_equals_eq_a2_a3_for_regular_interfaces():
    panel = build_panel(0.081, 0.21, 0.07, 4, 4)
    Hi, Hj = block_blocks(panel)
    compared = 0
    for k in range(panel.n_interfaces):
        i, j = panel.first[k], panel.second[k]
        mid = 0.5 * (panel.centre[i] + panel.centre[j])
        if np.allclose(mid, panel.centroid[k]):
            compared += 1
            dy = panel.centre[j] - panel.centre[i]
            H = interface_matrix(dy[0], dy[1])
            np.testing.assert_allclose(
                np.hstack([Hi[k], Hj[k]]),
                H,
                atol=1e-15,
                err_msg=f"interface {k}: H vs manuscript Eq. A2-A3",
            )
    # Eq. A2-A3 holds where the interface's centroid is midway between the block centres:
    # 28 of this panel's 38 interfaces (the others are the half-lapped bed joints)
    assert compared >= panel.n_interfaces // 2, (compared, panel.n_interfaces)


def test_rigid_body_motion_gives_no_relative_displacement():
    panel = build_panel(0.081, 0.21, 0.07, 3.5, 5)
    H = panel_compatibility(panel)
    rng = np.random.default_rng(1)
    u, w = rng.normal(size=3), rng.normal(size=3)
    q = np.concatenate([np.concatenate([u + np.cross(w, c), w]) for c in panel.centre])
    assert np.abs(H @ q).max() < 1e-12, (
        "a rigid motion of the whole panel must not strain interfaces"
    )
