"""Fuzz: malformed and extreme scenes give a one-line InputError naming a field, or a sane Scene.

Mutations of valid scenes (a block, a drum column, a colonnade, a two-tier colonnade, a
record-driven column): any leaf or container replaced by junk of another type, keys
deleted or added, numbers pushed to 0, negative, NaN, inf, huge and tiny. Nothing is
simulated: every example stops after the checks ``stonedem run`` makes before computing
(:func:`stonedem.engine.simulate.preflight`), which must refuse absurd sizes too.
"""

import copy
import math

import yaml
from hypothesis import given
from hypothesis import strategies as st

from stonedem.engine.scene import apply_override, scene_from_dict
from stonedem.engine.simulate import preflight
from stonedem.errors import InputError

BASES = [
    yaml.safe_load(open("tests/data/scenes/rocking_block.yaml")),
    {
        "structure": {"kind": "column", "n_drums": 4, "capital": {"height": 0.6, "width": 1.4}},
        "friction": 0.5,
        "excitation": {"kind": "harmonic", "amplitude": 3.0, "frequency": 2.0},
        "solver": {"duration": 1.0},
    },
    {
        "structure": {"kind": "colonnade", "n_columns": 2, "n_drums": 2, "epistyle_type": "b"},
        "excitation": {"kind": "one_sine", "amplitude": 4.0, "frequency": 1.5},
        "contact": {"model": "area", "k_n": 1e9, "c_n": 1e4},
        "solver": {"duration": 1.0},
    },
    {"structure": {"kind": "two_tier_colonnade"}, "solver": {"duration": 0.5}},
    {
        "structure": {"kind": "column", "n_drums": 3},
        "solver": {"duration": 2.0, "dt_safety": 0.25},
        "excitation": {"kind": "record", "file": "athens_standin_kocaeli_arc000", "pga": 3.0},
        "output": {"every": 0.01},
    },
    {  # an earthquake sequence (issue 48): a pulse, then a record, each with a rest
        "structure": {"kind": "column", "n_drums": 2},
        "excitation": {
            "kind": "sequence",
            "parts": [
                {"kind": "rect_pulse", "accel": 3.0, "duration": 0.2},
                {"kind": "record", "file": "athens_standin_kocaeli_arc000", "pga": 3.0},
            ],
            "rest": 2.0,
        },
        "solver": {"duration": 40.0},
        "output": {"every": 0.01},
    },
    # a leaning column (structure.tilt, issue 48) and a body that leans (lean)
    {
        "structure": {"kind": "column", "n_drums": 2, "tilt": -0.03, "base_width": 3.0},
        "friction": 0.6,
        "excitation": {"kind": "ramp", "rate": 0.5},
        "solver": {"duration": 0.5},
    },
    {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 2.0, "height": 0.2, "center": [0, -0.1]},
                "driven": True,
            },
            {
                "name": "block",
                "box": {"width": 0.3, "height": 1.0, "center": [0, 0.5]},
                "lean": 0.02,
            },
        ],
        "solver": {"duration": 0.5},
    },
    # shear links (issue 48): a listed link with every number, and a column's links
    {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 4.0, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {"name": "block", "box": {"width": 1.0, "height": 0.5, "center": [0, 0.25]}},
        ],
        "links": [
            {
                "bodies": ["base", "block"],
                "kind": "custom",
                "at": 0.2,
                "stiffness": 1.0e7,
                "capacity": 1.0e4,
                "ultimate_slip": 0.05,
                "gap": 0.001,
                "pullout": 100.0,
                "embedment": 0.05,
            }
        ],
        "excitation": {"kind": "rect_pulse", "accel": 5.0, "duration": 0.2},
        "solver": {"duration": 0.5},
    },
    {
        "structure": {
            "kind": "column",
            "n_drums": 3,
            "links": {"kind": "titanium", "joints": [1, 2], "at": 0.1, "gap": 0.002},
        },
        "excitation": {"kind": "harmonic", "amplitude": 0.1, "frequency": 1.0},
        "solver": {"duration": 1.0},
    },
]

JUNK = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**12), 10**12),
    st.sampled_from(
        [0, 0.0, -1.0, 1e-300, 1e-30, 1e30, 1e300, math.nan, math.inf, -math.inf, 0.5, 7]
    ),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    st.sampled_from(["auto", "high", "true", "false", "1e9", "abc", "", "harmonic"]),
    st.lists(st.integers(-3, 3), max_size=3),
    st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
)


def paths(node, prefix=()):
    """Every path into a nested dict/list, containers included."""
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from paths(v, prefix + (i,))


def mutate(spec, path, action, junk):
    spec = copy.deepcopy(spec)
    if not path:
        return junk if action == "replace" else spec
    parent = spec
    for p in path[:-1]:
        parent = parent[p]
    last = path[-1]
    if action == "replace":
        parent[last] = junk
    elif action == "delete":
        del parent[last]
    elif action == "add" and isinstance(parent, dict):
        parent[f"unknown_{last}"] = junk
    elif (
        action == "scale"
        and isinstance(parent[last], (int, float))
        and not isinstance(parent[last], bool)
    ):
        parent[last] = (
            parent[last] * junk
            if isinstance(junk, (int, float)) and not isinstance(junk, bool)
            else junk
        )
    return spec


def check(spec):
    try:
        scene = scene_from_dict(spec)
        preflight(scene)
    except InputError as err:
        text = str(err)
        assert "\n" not in text and ":" in text and len(text) < 400, text
        return None
    return scene


@given(
    st.integers(0, len(BASES) - 1),
    st.data(),
    st.sampled_from(["replace", "delete", "add", "scale"]),
    JUNK,
)
def test_fuzz_scene_mutation_gives_input_error_or_scene(base, data, action, junk):
    spec = BASES[base]
    path = data.draw(st.sampled_from(list(paths(spec))))
    scene = check(mutate(spec, path, action, junk))
    if scene is not None:
        assert scene.duration > 0 and all(b.mass > 0 and b.inertia > 0 for b in scene.bodies)


@given(st.integers(0, len(BASES) - 1), st.data(), st.lists(JUNK, min_size=2, max_size=4))
def test_fuzz_scene_several_mutations(base, data, junks):
    spec = BASES[base]
    for junk in junks:
        path = data.draw(st.sampled_from(list(paths(spec))))
        spec = mutate(spec, path, data.draw(st.sampled_from(["replace", "delete", "scale"])), junk)
    check(spec)


@given(st.text(max_size=30))
def test_fuzz_set_override_gives_input_error_or_scene(item):
    spec = copy.deepcopy(BASES[1])
    try:
        apply_override(spec, item)
    except InputError:
        return
    check(spec)
