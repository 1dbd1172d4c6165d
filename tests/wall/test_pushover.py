"""Classic checks: a free-standing dry wall overturns at lambda = s/H, slides at lambda = mu."""

import pytest

from dem.wall.case import case_from_dict
from dem.wall.pushover import pushover


def wall(mu=0.7, blocks=2, courses=8):
    return {"panel": {"block": {"a": 0.081, "b": 0.210, "s": 0.070}, "blocks_per_course": blocks,
                      "courses": courses, "unit_weight": 20000.0},
            "joints": {"kind": "dry", "mu": mu, "k_n": 2.4e9, "k_t": 1.0e9},
            "restraints": [{"edge": "base", "fix": "all"}],
            "load": {"kind": "proportional", "direction": "out_of_plane"}}


def test_free_standing_wall_overturns_at_s_over_H():
    case = case_from_dict(wall())
    r = pushover(case.model, case.settings)
    s_over_h = 0.070 / (8 * 0.081)
    assert r.lambda_max == pytest.approx(s_over_h, rel=0.02), f"lambda_max {r.lambda_max:.4f} vs s/H {s_over_h:.4f} (2 %)"


def test_free_standing_wall_slides_at_mu():
    case = case_from_dict(wall(mu=0.05))
    r = pushover(case.model, case.settings)
    assert r.lambda_max == pytest.approx(0.05, rel=0.02), f"lambda_max {r.lambda_max:.4f} vs mu = 0.05 (2 %)"
