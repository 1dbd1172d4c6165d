"""The contact-graph loop (stonedem.kernels.contact_graph): the general loop's run bit for bit
while the graph holds, and handed over to the general loop, exactly, the step it breaks."""

import math

import numpy as np
import pytest

from stonedem.engine.graph import contact_graph
from stonedem.engine.pack import pack_scene
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate

BASE = {"name": "base", "box": {"width": 6, "height": 0.5, "center": [0, -0.25]}, "driven": True}


def both(spec):
    """The scene run on its contact graph (auto) and on the general loop alone."""
    auto = simulate(scene_from_dict(spec))
    general = simulate(scene_from_dict({**spec, "solver": {**spec["solver"], "kernel": "general"}}))
    return auto, general


def assert_same_run(a, b):
    for field in ("time", "x", "y", "theta", "energy", "n_contact", "peaks", "peak_theta"):
        assert np.array_equal(getattr(a, field), getattr(b, field), equal_nan=True), field
    assert (a.status, a.onset_step, a.collapse_step, a.steps_run) == (
        b.status,
        b.onset_step,
        b.collapse_step,
        b.steps_run,
    )


def test_a_column_runs_on_its_graph_as_the_general_loop_does():
    spec = {
        "structure": {"kind": "column", "n_drums": 3, "height": 3.0, "width": 0.6},
        "excitation": {"kind": "harmonic", "amplitude": 4.0, "frequency": 2.0},
        "solver": {"duration": 0.6},
        "output": {"every": 0.01},
    }
    auto, general = both(spec)
    assert auto.kernel == "contact_graph" and math.isnan(auto.handover_time)
    assert general.kernel == "general"
    assert np.abs(auto.theta).max() > 1e-3, "the column must rock for the test to mean anything"
    assert_same_run(auto, general)


def test_a_body_coming_near_hands_the_run_over_exactly():
    # a block slides along the base into another that it was apart from at t = 0
    spec = {
        "bodies": [
            BASE,
            {"name": "still", "box": {"width": 0.4, "height": 0.4, "center": [0, 0.2]}},
            {
                "name": "sliding",
                "box": {"width": 0.4, "height": 0.4, "center": [1.0, 0.2]},
                "velocity": [-3.0, 0.0, 0.0],
            },
        ],
        "friction": 0.2,
        "solver": {"duration": 0.5, "skip_quiet": False},
        "output": {"every": 0.005},
    }
    auto, general = both(spec)
    assert auto.kernel == "contact_graph"
    assert 0.0 < auto.handover_time < 0.5
    assert "still and sliding" in auto.handover_reason
    assert auto.x[-1, 1] < -0.01, "the blow must have pushed the still block (to -x)"
    assert_same_run(auto, general)


def test_faces_turning_past_their_limit_hand_the_run_over_exactly():
    # a slender block released past its tipping angle falls onto its side
    spec = {
        "bodies": [
            BASE,
            {
                "name": "slender",
                "box": {"width": 0.3, "height": 1.5, "center": [0, 0.75]},
                "tilt": {"angle": 0.3, "about": "bottom_right"},
            },
        ],
        "friction": 0.8,
        "solver": {"duration": 1.6, "stop_on_collapse": False},
        "output": {"every": 0.01},
    }
    auto, general = both(spec)
    assert auto.kernel == "contact_graph"
    assert not math.isnan(auto.handover_time)
    assert "turned" in auto.handover_reason and "slender" in auto.handover_reason
    assert_same_run(auto, general)


def test_a_column_graph_is_its_stack_of_faces():
    scene = scene_from_dict(
        {"structure": {"kind": "column", "n_drums": 3}, "solver": {"duration": 1.0}}
    )
    graph = contact_graph(pack_scene(scene))
    assert graph.pair_a.tolist() == [0, 1, 2] and graph.pair_b.tolist() == [1, 2, 3]
    # a's top edge (vertex 2 -> 3 of a box) on b's bottom edge (0 -> 1)
    assert graph.face_a.tolist() == [2, 2, 2] and graph.face_b.tolist() == [0, 0, 0]
    assert graph.turn_limit == pytest.approx(0.9 * math.pi / 4)
    assert graph.index[0, 1] == 0 and graph.index[0, 2] == -1


def test_an_unknown_kernel_is_refused_by_name():
    from stonedem.errors import InputError

    with pytest.raises(InputError, match="solver.kernel"):
        scene_from_dict(
            {
                "structure": {"kind": "column", "n_drums": 1},
                "solver": {"duration": 1.0, "kernel": "fast"},
            }
        )
