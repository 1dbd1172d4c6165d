"""Running-bond builder: block counts, half blocks, interface widths, openings."""

import numpy as np
import pytest

from stonedem.wall.panel import KIND_BED, KIND_HEAD, KIND_SUPPORT, build_panel


def test_running_bond_3_by_13():
    p = build_panel(0.081, 0.21, 0.07, 3, 13, support_edges=["base"])
    assert p.n_blocks == 7 * 3 + 6 * 4, "odd courses: half + 2 full + half"
    assert p.length == pytest.approx(0.63) and p.height == pytest.approx(1.053)
    assert np.allclose(p.width[p.kind == KIND_BED], 0.105), "bed interfaces are half a block wide"
    assert np.allclose(p.width[p.kind == KIND_HEAD], 0.081)
    assert (p.kind == KIND_SUPPORT).sum() == 3
    assert p.volume.sum() == pytest.approx(0.63 * 1.053 * 0.07), "the blocks fill the wall"


def test_openings_remove_blocks():
    full = build_panel(0.081, 0.21, 0.07, 6, 10)
    holed = build_panel(
        0.081, 0.21, 0.07, 6, 10, openings=[{"x": (0.42, 0.84), "y": (0.243, 0.567)}]
    )
    assert full.n_blocks - holed.n_blocks == 8, "4 courses x 2 blocks removed"
