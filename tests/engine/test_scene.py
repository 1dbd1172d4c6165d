"""Scene loading: mass properties from geometry, overrides, and one-line errors for bad input."""

import math

import numpy as np
import pytest
import yaml

from stonedem.engine.scene import initial_pose, load_scene, scene_from_dict
from stonedem.errors import InputError

SCENE = "tests/data/scenes/rocking_block.yaml"


def block_scene(**changes):
    spec = yaml.safe_load(open(SCENE))
    spec.update(changes)
    return spec


def test_example_scene_loads_with_mass_and_inertia_from_geometry():
    scene = load_scene(SCENE)
    block = scene.bodies[1]
    assert block.mass == 503.0
    # rectangle: I = m (b^2 + h^2) / 12
    assert block.inertia == pytest.approx(503.0 * (0.25**2 + 1.0**2) / 12.0, rel=1e-12)
    assert scene.contact.k_n == 1.0e9 and scene.contact.c_n == 0.0
    assert scene.dt is None and scene.duration == 4.0


def test_density_and_depth_give_mass():
    spec = block_scene(depth=0.5)
    spec["bodies"][1] = {
        "name": "block",
        "box": {"width": 0.25, "height": 1.0, "center": [0, 0.5]},
        "density": 2600.0,
    }
    scene = scene_from_dict(spec)
    assert scene.bodies[1].mass == pytest.approx(2600.0 * 0.25 * 1.0 * 0.5, rel=1e-12)


def test_tilt_about_bottom_right_leans_onto_that_corner():
    scene = load_scene(SCENE)
    x, y, theta = initial_pose(scene.bodies[1])
    assert theta == pytest.approx(-0.05236), "leaning right is a clockwise (negative) rotation"
    # the centroid turns about the corner (0.125, 0)
    r = math.hypot(0.125, 0.5)
    alpha = math.atan(0.125 / 0.5)
    assert x == pytest.approx(0.125 - r * math.sin(alpha - 0.05236), rel=1e-12)
    assert y == pytest.approx(r * math.cos(alpha - 0.05236), rel=1e-12)


def test_set_overrides_nested_fields_and_list_items_by_name():
    scene = load_scene(
        SCENE, overrides=["solver.duration=1.5", "contact.c_n=200", "bodies.block.mass=10"]
    )
    assert scene.duration == 1.5 and scene.contact.c_n == 200.0 and scene.bodies[1].mass == 10.0


def test_interface_friction_overrides_pair():
    spec = block_scene(interface_friction=[{"bodies": ["base", "block"], "mu": 0.2}])
    scene = scene_from_dict(spec)
    assert scene.pair_friction == {("base", "block"): 0.2}


@pytest.mark.parametrize(
    "mutate, field",
    [
        (lambda s: s.update(bogus=1), "bogus"),
        (lambda s: s["contact"].update(k_x=1), "contact.k_x"),
        (
            lambda s: (
                s["contact"].update(model="point", frame="thesis", k_n=1e10)
                or s["contact"].pop("c_n", None)
            ),
            "contact.frame",
        ),
        (lambda s: s["contact"].update(model="area", frame="faces"), "contact.frame"),
        (lambda s: s["bodies"][1].update(mass=-1.0), "mass"),
        (lambda s: s["bodies"][1].update(mass=0.0), "mass"),
        (lambda s: s.update(density=0.0), "density"),
        (
            lambda s: (
                s["bodies"][1].pop("box")
                and s["bodies"][1].update(
                    polygon={"vertices": [[0, 0], [1, 0], [0.2, 0.2], [0, 1]]}
                )
            ),
            "non-convex",
        ),
        (
            lambda s: (
                s["bodies"][1].pop("box")
                and s["bodies"][1].update(polygon={"vertices": [[0, 0], [1, 1], [1, 0], [0, 1]]})
            ),
            "self-intersecting",
        ),
        (lambda s: s["bodies"][1]["box"].update(center=[0.0, 0.4]), "overlap"),
        (lambda s: s["solver"].update(dt=0.5), "stability limit"),
        (lambda s: s["solver"].pop("duration"), "solver.duration"),
        (lambda s: s["bodies"][1]["box"].update(width="wide"), "box.width"),
        (lambda s: s["bodies"][1].update(tilt={"angle": 0.1, "about": "middle"}), "tilt.about"),
        # were "mass: 503 kg (inertia 0 kg m2) is outside ..." and, both bodies at x = 1e12, exit 0
        (
            lambda s: s["bodies"][1]["box"].update(center=[0.0, 1e300]),
            "(block).box: a corner lies 1e+300 m",
        ),
        (
            lambda s: [b["box"].update(center=[1e12, b["box"]["center"][1]]) for b in s["bodies"]],
            "past 100000 m",
        ),
        (
            lambda s: (
                s["bodies"][1].pop("box")
                and s["bodies"][1].update(polygon={"vertices": [[0, 0], [1e6, 0], [0, 1]]})
            ),
            "polygon.vertices: a corner lies 1e+06 m",
        ),
    ],
)
def test_bad_input_names_the_field(mutate, field):
    spec = block_scene()
    mutate(spec)
    with pytest.raises(InputError) as err:
        scene = scene_from_dict(spec)
        from stonedem.engine.simulate import choose_time_step

        choose_time_step(scene)
    message = str(err.value)
    assert field in message and "\n" not in message, message


def test_malformed_yaml_is_one_line(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("bodies: [\n  {name: a\n")
    with pytest.raises(InputError, match="not valid YAML"):
        load_scene(bad)


def test_unstable_dt_message_names_the_limit():
    spec = block_scene()
    spec["solver"]["dt"] = 0.01
    from stonedem.engine.simulate import choose_time_step, stability_limit

    scene = scene_from_dict(spec)
    limit = stability_limit(scene)
    with pytest.raises(InputError, match=f"{limit:.3g}"):
        choose_time_step(scene)
    assert 1e-5 < limit < 1e-2 and np.isfinite(limit)


def test_an_overlap_far_along_a_row_of_bodies_is_found():
    from stonedem.errors import InputError
    from tests.scenes import drum_wall

    spec = drum_wall(30, 2)
    last = spec["bodies"][-1]
    # the top drum of the last column sinks 1 cm into the one below
    last["box"]["center"][1] -= 0.01
    with pytest.raises(InputError, match="overlap"):
        scene_from_dict(spec)
