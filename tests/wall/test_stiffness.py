"""Interface stiffness of Eq. 5 and the sparse panel stiffness."""

import numpy as np
import pytest
import scipy.sparse as sp

from stonedem.wall.compatibility import panel_compatibility
from stonedem.wall.panel import KIND_BED, KIND_HEAD, build_panel
from stonedem.wall.stiffness import local_stiffness, panel_stiffness, sections, to_global_order


def test_eq5_areas_and_inertias():
    a, b, s = 0.081, 0.21, 0.07
    p = build_panel(a, b, s, 4, 4)
    sec = sections(p)
    bed, head = np.flatnonzero(p.kind == KIND_BED)[0], np.flatnonzero(p.kind == KIND_HEAD)[0]
    assert sec.area[bed] == pytest.approx(b * s / 2) and sec.area[head] == pytest.approx(a * s)
    assert sec.inertia[bed] == pytest.approx([b * s**3 / 24, b**3 * s / 96]), "I_h1, I_h3 of Eq. 5"
    assert sec.inertia[head] == pytest.approx([a * s**3 / 12, a**3 * s / 12]), "I_v2, I_v3 of Eq. 5"


def test_panel_stiffness_sparse_symmetric_with_six_rigid_modes():
    p = build_panel(0.081, 0.21, 0.07, 4, 6)
    sec = sections(p)
    kd = to_global_order(local_stiffness(sec, 2.4e9, 1e9), sec.perm).ravel()
    K = panel_stiffness(panel_compatibility(p), kd)
    assert sp.issparse(K) and K.nnz < 0.2 * K.shape[0] ** 2
    assert abs(K - K.T).max() < 1e-6 * abs(K).max()
    eig = np.linalg.eigvalsh(K.toarray())
    assert (np.abs(eig) < 1e-6 * eig.max()).sum() == 6, (
        "an unsupported panel has 6 rigid-body modes"
    )
