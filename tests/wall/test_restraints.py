"""Restraints eliminated exactly (stonedem.wall.restraints): pins and straight restraint lines."""

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.wall.case import case_from_dict
from stonedem.wall.panel import build_panel
from stonedem.wall.pushover import pushover
from stonedem.wall.restraints import LineRestraint, point_rows, reduction_matrix, restrained_dofs

RNG = np.random.default_rng(15)


def _panel():
    # running bond, 3.5 blocks long: courses alternate full and half blocks at the edges
    return build_panel(0.1, 0.2, 0.08, 3.5, 4, joint_thickness=0.01)


def _point_w(panel, q, blk, point):
    return point_rows(panel.centre[blk], point, (0, 1, 2)) @ q.reshape(-1, 6)[blk]


def test_pins_reduce_to_the_free_dofs():
    panel = _panel()
    fixed = np.zeros(6 * panel.n_blocks, dtype=bool)
    fixed[[0, 1, 2, 14, 20]] = True
    T = reduction_matrix(panel, fixed, [])
    assert T.shape == (6 * panel.n_blocks, 6 * panel.n_blocks - 5)
    assert np.array_equal(restrained_dofs(T), fixed)
    assert np.allclose((T.T @ T).toarray(), np.eye(T.shape[1]))


@pytest.mark.parametrize("edge", ["left", "right", "base", "top"])
def test_a_line_holds_every_point_of_its_chords_and_lets_blocks_turn_about_it(edge):
    panel = _panel()
    line = LineRestraint(edge, (2,))
    T = reduction_matrix(panel, np.zeros(6 * panel.n_blocks, dtype=bool), [line])
    chords = line.chords(panel)
    # every course (or every block of the edge course) is crossed once
    assert len(chords) == (
        panel.course.max() + 1
        if edge in ("left", "right")
        else np.sum(panel.course == (0 if edge == "base" else panel.course.max()))
    )
    q = T @ RNG.standard_normal(T.shape[1])
    for blk, a, b in chords:
        for t in (0.0, 0.3, 1.0):
            assert abs(_point_w(panel, q, blk, a + t * (b - a))[2]) < 1e-12
    # 2 constraints per crossed block: it keeps 4 DOFs, among them the turn about the line
    assert T.shape[1] == 6 * panel.n_blocks - 2 * len(chords)
    blk, a, b = chords[0]
    axis = (b - a) / np.linalg.norm(b - a)
    turn = np.zeros(6 * panel.n_blocks)
    turn[6 * blk + 3 : 6 * blk + 6] = axis
    turn[6 * blk : 6 * blk + 3] = np.cross(axis, panel.centre[blk] - a)  # rotation about the line
    v = np.linalg.lstsq(T.toarray(), turn, rcond=None)[0]
    assert np.allclose(T @ v, turn, atol=1e-12)


def test_the_left_edge_line_passes_the_panel_edge_not_the_block_centres():
    panel = _panel()
    for blk, a, b in LineRestraint("left", (2,)).chords(panel):
        assert a[0] == b[0] == 0.0
        assert panel.centre[blk, 0] - panel.size[blk, 0] / 2 == pytest.approx(0.0)
    offset = LineRestraint("left", (2,), distance=0.15)
    for blk, _a, _b in offset.chords(panel):
        lo, hi = (
            panel.centre[blk, 0] - panel.size[blk, 0] / 2,
            panel.centre[blk, 0] + panel.size[blk, 0] / 2,
        )
        assert lo <= 0.15 < hi


def test_points_hold_only_the_middle_of_each_chord():
    panel = _panel()
    line = LineRestraint("left", (2,), hold="points")
    T = reduction_matrix(panel, np.zeros(6 * panel.n_blocks, dtype=bool), [line])
    chords = LineRestraint("left", (2,)).chords(panel)
    assert T.shape[1] == 6 * panel.n_blocks - len(chords)
    q = T @ RNG.standard_normal(T.shape[1])
    blk, a, b = chords[0]
    assert abs(_point_w(panel, q, blk, 0.5 * (a + b))[2]) < 1e-12
    assert abs(_point_w(panel, q, blk, a)[2]) > 1e-6  # the block may turn about its pin


def _strip(top):
    """A dry strip one block wide, 10 courses of 0.1 x 0.2 x 0.1 m on a support joint."""
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


def test_a_strip_held_at_the_top_line_collapses_at_the_hinge_below_its_top_course():
    # free standing: rocking on the base joint, lambda = s/H (0.1). With the top edge held out of
    # plane on a line, the lower part turns about the base face, the top course about the line:
    # virtual work (w s H/2 at the base + w s H/2 at the hinge) / (lambda w y H/2) gives
    # lambda = 2 s / y, least at the highest bed joint y = H - a: 2 x 0.1 / 0.9 = 0.2222
    free = case_from_dict(_strip(None))
    r = pushover(free.model, free.settings)
    assert r.lambda_max == pytest.approx(0.1, rel=0.01)
    held = case_from_dict(_strip({"edge": "top", "fix": "out_of_plane", "at": "edge"}))
    r = pushover(held.model, held.settings)
    assert r.lambda_max == pytest.approx(2 * 0.1 / 0.9, rel=0.01)


@pytest.mark.parametrize(
    "restraint, field, problem",
    [
        ({"edge": "left", "fix": "all", "at": "edge"}, "restraints[1].fix", "not rotations"),
        (
            {"edge": "left", "fix": "out_of_plane", "hold": "points"},
            "restraints[1].hold",
            "only for a restraint line",
        ),
        (
            {"edge": "left", "fix": "out_of_plane", "offset": 0.1},
            "restraints[1].offset",
            "only for at: offset",
        ),
        (
            {"edge": "left", "fix": "out_of_plane", "at": "offset"},
            "restraints[1].offset",
            "missing",
        ),
        (
            {"edge": "left", "fix": "out_of_plane", "at": "offset", "offset": 5.0},
            "restraints[1].offset",
            "must be >= 0 and < ",
        ),
        (
            {"edge": "left", "fix": "out_of_plane", "at": "middle"},
            "restraints[1].at",
            "unknown value",
        ),
        (
            {"edge": "left", "fix": "out_of_plane", "at": "edge", "hold": "some"},
            "restraints[1].hold",
            "unknown value",
        ),
    ],
)
def test_bad_restraint_lines_are_refused_naming_the_field(restraint, field, problem):
    spec = _strip(None)
    spec["restraints"].append(restraint)
    with pytest.raises(InputError) as err:
        case_from_dict(spec)
    assert err.value.field == field and problem in str(err.value)
