"""Limit analysis by LP (stonedem.wall.limit_analysis): the supporting planes, answers known in
closed form, and the errors. The oracle over every table case is in test_tables.py."""

from pathlib import Path

import numpy as np
import pytest

from stonedem.wall.case import case_from_dict, load_case
from stonedem.wall.limit_analysis import (
    LimitAnalysisError,
    limit_multiplier,
    radial_boundary_points,
    tangent_normals,
)
from stonedem.wall.pushover import dead_load_state

CASES = Path(__file__).resolve().parents[2] / "config" / "walls"
RNG = np.random.default_rng(16)


@pytest.mark.parametrize("alpha", [1.0, 1.43, 2.56])
def test_supporting_planes_touch_the_domain_and_hold_all_of_it(alpha):
    """Eq. 14 domain v^alpha + u^2 <= 1: the radial point is on the boundary and the tangent
    plane there has the whole boundary on its inner side (the domain is convex)."""
    u, v = RNG.uniform(0, 3, 400), RNG.uniform(0, 3, 400)
    outside = v**alpha + u**2 > 1  # where the LP asks for a plane
    u, v = u[outside][:200], v[outside][:200]
    ub, vb = radial_boundary_points(u, v, np.full(200, alpha))
    np.testing.assert_allclose(vb**alpha + ub**2, 1.0, atol=1e-9)
    np.testing.assert_allclose(vb * u, ub * v, atol=1e-12)  # on the ray
    n_u, n_v = tangent_normals(ub, vb, np.full(200, alpha))
    b = n_u * ub + n_v * vb
    t = np.linspace(0, 1, 401)
    curve_u, curve_v = t, (1 - t**2) ** (1 / alpha)
    assert np.all(np.outer(n_u, curve_u) + np.outer(n_v, curve_v) <= b[:, None] + 1e-9)


def test_free_standing_wall_matches_its_closed_form():
    """A dry wall on its support joint rocks as one body: lambda = s / H (case file reference)."""
    case = load_case(CASES / "free_standing.yaml")
    r = limit_multiplier(case.model, dead_load_state(case.model, case.settings))
    assert r.converged, r.status
    assert r.lambda_limit == pytest.approx(case.spec["reference"]["lambda_analytic"], rel=1e-3)


def _strip(top):
    """A dry strip one block wide, 10 courses of 0.1 x 0.2 x 0.1 m (as
    tests/wall/test_restraints.py)."""
    return {
        "panel": {
            "block": {"a": 0.1, "b": 0.2, "s": 0.1},
            "blocks_per_course": 1,
            "courses": 10,
            "unit_weight": 20000.0,
        },
        "joints": {"kind": "dry", "mu": 0.7, "k_n": 1e9, "k_t": 1e9},
        "restraints": [{"edge": "base", "fix": "all"}] + ([top] if top else []),
        "load": {"kind": "proportional", "direction": "out_of_plane"},
    }


def test_a_strip_held_at_the_top_line_collapses_at_the_virtual_work_load():
    # lambda = 2 s / (H - a) = 0.2222 (virtual work; derivation in test_restraints.py)
    held = case_from_dict(_strip({"edge": "top", "fix": "out_of_plane", "at": "edge"}))
    r = limit_multiplier(held.model, dead_load_state(held.model, held.settings))
    assert r.lambda_limit == pytest.approx(2 * 0.1 / 0.9, rel=1e-3)


def test_a_wall_with_no_mechanism_is_refused():
    # the case builder refuses it first; the LP says so on its own too
    case = case_from_dict(_strip(None))
    case.model.fixed = np.ones_like(case.model.fixed)
    case.model.T_live = None
    with pytest.raises(LimitAnalysisError, match="no mechanism"):
        limit_multiplier(case.model, dead_load_state(case.model, case.settings))
