"""Shear links between stacked bodies (stonedem.engine.links, stonedem.kernels.links; issue 48):
scene keys and refusals, the column's expansion, forces, energy booking and the dataset."""

import numpy as np
import pytest

from stonedem.engine.ensemble import run_ensemble
from stonedem.engine.links import PRESETS
from stonedem.engine.run import run_scene
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import run_checks, simulate, uses_graph
from stonedem.errors import InputError
from stonedem.io.schema import missing_metadata
from stonedem.kernels.links import LINK_BROKEN, LINK_ENGAGED, LINK_PULLED_OUT

CUSTOM = {
    "kind": "custom",
    "stiffness": 1.0e7,
    "capacity": 1.0e4,
    "ultimate_slip": 0.5,
    "gap": 0.0,
    "pullout": 0.0,
    "embedment": 0.1,
}


def block(link=None, excitation=None, duration=1.0, tilt=None, kernel="auto", width=2.0):
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 8.0, "height": 0.5, "center": [0.0, -0.25]},
                "driven": True,
            },
            {
                "name": "block",
                "box": {"width": width, "height": 0.5, "center": [0.0, 0.25]},
                "density": 2700.0,
                **({"tilt": tilt} if tilt else {}),
            },
        ],
        "friction": 0.3,
        "excitation": excitation or {"kind": "rect_pulse", "accel": 8.0, "duration": 0.3},
        "solver": {"duration": duration, "kernel": kernel},
        "output": {"every": 0.005},
    }
    if link is not None:
        spec["links"] = [{"bodies": ["base", "block"], **link}]
    return spec


def test_presets_fill_the_numbers_and_explicit_keys_override():
    scene = scene_from_dict(block({"kind": "titanium", "gap": 0.001}))
    (link,) = scene.links
    stiffness, capacity, ultimate, _, pullout, embedment = PRESETS["titanium"]
    assert (link.stiffness, link.capacity, link.ultimate_slip) == (stiffness, capacity, ultimate)
    assert (link.gap, link.pullout, link.embedment) == (0.001, pullout, embedment)
    assert not uses_graph(scene), "a linked scene runs the general loop"
    assert uses_graph(scene_from_dict(block()))


@pytest.mark.parametrize(
    "link, field, words",
    [
        ({"kind": "custom", "stiffness": 1e7}, "links[0].capacity", "missing"),
        ({"kind": "wood", "at": 4.5}, "links[0].at", "outside the face"),
        ({"kind": "wood", "capacity": -1.0}, "links[0].capacity", ""),
        ({"kind": "wood", "gap": 0.02, "ultimate_slip": 0.01}, "links[0].ultimate_slip", "gap"),
        ({"kind": "steel"}, "links[0].kind", ""),
        ({"kind": "wood", "bodies": ["block", "base"]}, "links[0].bodies", "driven"),
        ({"kind": "wood", "bodies": ["base", "base"]}, "links[0].bodies", "itself"),
        ({"kind": "wood", "bodies": ["base", "nothing"]}, "links[0].bodies", "known bodies"),
        ({"kind": "wood", "colour": "red"}, "links[0].colour", "unknown key"),
    ],
)
def test_meaningless_links_are_refused_in_one_line(link, field, words):
    spec = block()
    spec["links"] = [{"bodies": ["base", "block"], **link}]
    with pytest.raises(InputError) as err:
        scene_from_dict(spec)
    text = str(err.value)
    assert text.startswith(field) and words in text and "\n" not in text, text


def test_bodies_that_are_not_stacked_are_refused():
    spec = block({"kind": "wood"})
    spec["bodies"][1]["box"]["center"] = [0.0, 0.35]  # 0.1 m above the base
    spec["bodies"][1]["velocity"] = [0.0, 0.0, 0.0]
    with pytest.raises(InputError, match="does not rest on the top face"):
        scene_from_dict(spec)
    spec = block({"kind": "wood", "at": 3.5})  # on the base's face, beside the block
    with pytest.raises(InputError, match="not stacked"):
        scene_from_dict(spec)


def test_structure_links_go_on_every_drum_joint_or_the_listed_ones():
    column = {"kind": "column", "n_drums": 4, "capital": {"height": 0.6, "width": 1.4}}
    spec = {"structure": {**column, "links": {"kind": "wood"}}, "solver": {"duration": 1.0}}
    scene = scene_from_dict(spec)
    names = scene.body_names
    pairs = [(names[k.lower], names[k.upper]) for k in scene.links]
    assert pairs == [("c0_d0", "c0_d1"), ("c0_d1", "c0_d2"), ("c0_d2", "c0_d3")]
    spec["structure"]["links"] = {"kind": "titanium", "joints": [2], "at": 0.2}
    (link,) = scene_from_dict(spec).links
    assert (link.kind, link.at, names[link.upper]) == ("titanium", 0.2, "c0_d2")
    colonnade = {"kind": "colonnade", "n_columns": 2, "n_drums": 2, "links": {"kind": "wood"}}
    assert len(scene_from_dict({"structure": colonnade, "solver": {"duration": 1}}).links) == 2
    assert scene_from_dict({**spec, "structure": {**column, "links": {"kind": "none"}}}).links == ()
    for links, field in (
        ({"kind": "none", "joints": [1]}, "structure.links"),
        ({"kind": "wood", "joints": [4]}, "structure.links.joints[0]"),
        ({"kind": "wood", "joints": [0]}, "structure.links.joints[0]"),
    ):
        with pytest.raises(InputError) as err:
            scene_from_dict({**spec, "structure": {**column, "links": links}})
        assert str(err.value).startswith(field), str(err.value)
    with pytest.raises(InputError, match="no drum-drum joint"):
        one = {"kind": "column", "n_drums": 1, "links": {"kind": "wood"}}
        scene_from_dict({"structure": one, "solver": {"duration": 1.0}})


def test_a_link_without_capacity_changes_nothing_to_the_last_bit():
    free = simulate(scene_from_dict(block(kernel="general")))
    nothing = {**CUSTOM, "capacity": 0.0}
    linked = simulate(scene_from_dict(block(nothing, kernel="general")))
    for name in ("x", "y", "theta", "energy"):
        assert np.array_equal(getattr(free, name), getattr(linked, name)), name


def test_the_link_yields_and_its_losses_balance_the_energy():
    scene = scene_from_dict(block(CUSTOM))
    r = simulate(scene)
    free = simulate(scene_from_dict(block()))

    def slide(run):
        return abs((run.x[-1, 1] - run.x[-1, 0]) - (run.x[0, 1] - run.x[0, 0]))

    assert r.link_status[0] == LINK_ENGAGED and r.link_peak[0] == pytest.approx(1.0e4)
    assert slide(r) == pytest.approx(abs(r.link_slip[0]), abs=1e-3)  # plastic, elastic <= V / k
    assert 0.01 < slide(r) < slide(free)
    checks = run_checks(scene, r)
    assert checks["status"] == "completed" and checks["energy_error"] < 1e-4, checks


def test_a_link_breaks_beyond_its_ultimate_slip_and_stays_broken():
    scene = scene_from_dict(block({**CUSTOM, "ultimate_slip": 0.02}))
    r = simulate(scene)
    assert r.link_status[0] == LINK_BROKEN
    assert abs(r.link_slip[0]) < 0.02 and r.link_peak[0] == pytest.approx(1.0e4)
    checks = run_checks(scene, r)
    assert checks["status"] == "completed" and checks["energy_error"] < 1e-4, checks


def test_uplift_beyond_the_embedment_pulls_the_link_out():
    # a slender block rocks onto its right corner; the link near its left edge opens
    pull = {**CUSTOM, "at": -0.2, "pullout": 500.0, "embedment": 0.01, "gap": 0.005}
    spec = block(
        pull,
        excitation={"kind": "rect_pulse", "accel": -6.0, "duration": 0.3},
        width=0.5,
        duration=1.5,
    )
    spec["bodies"][1]["box"].update(height=2.0, center=[0.0, 1.0])
    spec["friction"] = 2.0
    scene = scene_from_dict(spec)
    r = simulate(scene)
    assert r.link_status[0] == LINK_PULLED_OUT and r.link_peak[0] == pytest.approx(500.0)
    checks = run_checks(scene, r)
    assert checks["energy_error"] < 1e-3, checks


def test_the_dataset_describes_each_link():
    ds = run_scene(scene_from_dict(block(CUSTOM, duration=0.5)))
    assert missing_metadata(ds) == []
    assert ds.link_status.dims == ("link",) and int(ds.link_status[0]) == LINK_ENGAGED
    assert ds.link_status.attrs["flag_meanings"] == "engaged broken pulled_out"
    assert ds.link_peak_force.attrs["units"] == "N" and ds.link_plastic_slip.attrs["units"] == "m"
    assert list(ds.link_lower.values) == ["base"] and "links" in ds.attrs
    assert "link" not in run_scene(scene_from_dict(block(duration=0.2))).dims


def test_linked_members_run_in_an_ensemble_as_alone():
    scenes = [scene_from_dict(block(CUSTOM)), scene_from_dict(block({**CUSTOM, "at": 0.5}))]
    for scene, got in zip(scenes, run_ensemble(scenes, threads=1)):
        alone = simulate(scene)
        for name in ("x", "y", "theta", "energy", "link_slip", "link_peak", "link_status"):
            assert np.array_equal(getattr(got, name), getattr(alone, name)), name
