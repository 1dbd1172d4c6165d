"""A fuzz of the Python API (issue 43): hypothesis draws every argument of every public
function of :mod:`stonedem.api` from values of every kind (None, bools, numpy scalars and
arrays, text, paths missing, a folder, a symlink loop, a file of the wrong kind, mappings,
huge, negative and NaN numbers).

The oracle is the command line's: a result, or one clear exception, InputError or TypeError,
whose message is one line naming the argument or the field; never a library's exception.
Cheap at the ``ci`` profile: scenes last 0.02 s, walls are 2 x 3 blocks.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import stonedem
from stonedem.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
SHORT_SCENE = {
    "bodies": [
        {
            "name": "base",
            "box": {"width": 2.0, "height": 0.2, "center": [0.0, -0.1]},
            "driven": True,
        },
        {"name": "block", "box": {"width": 0.2, "height": 1.0, "center": [0.0, 0.5]}},
    ],
    "solver": {"duration": 0.02},
}
SMALL_WALL = {
    "panel": {
        "block": {"a": 0.081, "b": 0.210, "s": 0.070},
        "blocks_per_course": 2,
        "courses": 3,
        "unit_weight": 20000.0,
    },
    "joints": {"kind": "dry", "mu": 0.7, "k_n": 2.4e9, "k_t": 1.0e9},
    "restraints": [{"edge": "base", "fix": "all"}],
    "load": {"kind": "proportional", "direction": "out_of_plane"},
}
NUMBERS = [
    0,
    -1,
    1e309,
    float("nan"),
    float("-inf"),
    1e300,
    -0.0,
    2**70,
    np.float32(0.6),
    np.int64(3),
    np.array(0.5),
    np.array([1.0, 2.0]),
    np.True_,
    True,
    False,
    np.nan,
]


@pytest.fixture(scope="module")
def arena(tmp_path_factory):
    root = tmp_path_factory.mktemp("api")
    scene = root / "scene.yaml"
    scene.write_text(
        (ROOT / "tests/data/scenes/rocking_block.yaml")
        .read_text()
        .replace("duration: 4.0", "duration: 0.02")
    )
    (root / "loop").symlink_to("loop")
    (root / "folder").mkdir()
    (root / "text.nc").write_text("not netcdf\n")
    result = stonedem.write_dataset(stonedem.run_scene(scene), root / "result.nc")
    paths = {
        "scene": scene,
        "loop": root / "loop",
        "folder": root / "folder",
        "text": root / "text.nc",
        "result": result,
        "missing": root / "missing.yaml",
        "loop_in": root / "loop" / "x.nc",
    }
    return root, paths


def values(paths, *good):
    """Any kind of value, with the good ones for the argument among them."""
    path_values = (
        [p for p in paths.values()] + [str(p) for p in paths.values()] + [b"scene.yaml", ""]
    )
    return st.one_of(
        st.sampled_from(list(good) if good else [None]),
        st.sampled_from(NUMBERS),
        st.sampled_from(path_values),
        st.sampled_from([None, "", "x" * 300, "a\nb", {}, [], {"a": 1}, [None], (1, 2), object()]),
    )


def perturbed_scene(draw):
    """The short scene with one field set to any kind of value."""
    spec = {
        "bodies": [dict(b, box=dict(b["box"])) for b in SHORT_SCENE["bodies"]],
        "solver": dict(SHORT_SCENE["solver"]),
    }
    where = draw(
        st.sampled_from(
            [
                "friction",
                "gravity",
                "mass",
                "width",
                "duration",
                "name",
                "none",
                "sequence_parts",
                "sequence_rest",
            ]
        )
    )
    value = draw(
        st.one_of(st.sampled_from(NUMBERS), st.sampled_from([None, "abc", [1, 2], {"a": 1}]))
    )
    if where in ("friction", "gravity", "name"):
        spec[where] = value
    elif where == "mass":
        spec["bodies"][1]["mass"] = value
    elif where == "width":
        spec["bodies"][1]["box"]["width"] = value
    elif where.startswith("sequence_"):  # an excitation sequence (issue 48) within 0.02 s
        pulse = {"kind": "rect_pulse", "accel": 2.0, "duration": 0.005}
        spec["excitation"] = {"kind": "sequence", "parts": [pulse, pulse], "rest": 0.004}
        spec["excitation"][where.removeprefix("sequence_")] = value
    elif where == "duration":
        spec["solver"]["duration"] = (
            value if not isinstance(value, (int, float)) or abs(value) < 0.05 else 0.02
        )
    return spec


def check(call):
    try:
        result = call()
    except (InputError, TypeError) as err:
        event(type(err).__name__)
        message = str(err)
        assert message and "\n" not in message, repr(message)
        assert ":" in message, f"names no argument or field: {message!r}"
        return None
    event("result")
    return result


FUNCTIONS = [
    "load_scene",
    "run_scene",
    "run_scenes",
    "run_wall",
    "write_dataset",
    "open_cube",
    "open_search",
    "open_ida",
    "open_fragility",
]


@pytest.mark.parametrize("function", FUNCTIONS)
@settings(
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture], deadline=None
)
@given(data=st.data())
def test_fuzz_every_argument_of_the_api(arena, function, data):
    root, paths = arena
    draw = data.draw
    scene_like = st.one_of(
        values(paths, paths["scene"], str(paths["scene"])),
        st.builds(lambda: None).flatmap(lambda _: st.just(perturbed_scene(draw))),
    )
    if function == "load_scene":
        overrides = values(
            paths,
            None,
            ["solver.duration=0.01"],
            {"friction": 0.3},
            ["name=[1, 2]"],
            {"solver.duration": np.float32(0.01)},
            ["x=[[["],
        )
        check(
            lambda: stonedem.load_scene(
                draw(scene_like),
                base_dir=draw(values(paths, None, root)),
                overrides=draw(overrides),
            )
        )
    elif function == "run_scene":
        check(
            lambda: stonedem.run_scene(
                draw(scene_like), progress=draw(values(paths, False, np.False_))
            )
        )
    elif function == "run_scenes":
        many = st.one_of(scene_like, st.lists(scene_like, max_size=2))
        check(
            lambda: stonedem.run_scenes(
                draw(many),
                device=draw(values(paths, "cpu", "abacus")),
                threads=draw(values(paths, None, 1, np.int64(1), 0, -3)),
            )
        )
    elif function == "run_wall":
        wall = st.one_of(
            values(paths, SMALL_WALL),
            st.just(
                {
                    **SMALL_WALL,
                    "joints": {**SMALL_WALL["joints"], "mu": draw(st.sampled_from(NUMBERS))},
                }
            ),
        )
        check(
            lambda: stonedem.run_wall(
                draw(wall),
                limit_analysis=draw(values(paths, False)),
                progress=draw(values(paths, False)),
            )
        )
    elif function == "write_dataset":
        ds = st.one_of(
            values(paths, xr.Dataset({"x": ((), 1.0)})),
            st.sampled_from(
                [
                    xr.Dataset({"z": (("t",), np.array([1 + 1j]))}),
                    xr.Dataset({"x": ((), 1.0)}, attrs={"a": None}),
                    xr.Dataset({"x": (("t",), np.array([1, "a"], dtype=object))}),
                    xr.DataArray([1.0]),
                ]
            ),
        )
        out = st.one_of(
            values(paths, root / "out" / "o.nc"),
            st.sampled_from([root / "o.nc", str(root / "o2.nc")]),
        )
        kept = [paths["scene"], paths["text"], paths["result"]]
        before = [p.read_bytes() for p in kept]
        overwrite = draw(values(paths, False, True))
        check(
            lambda: stonedem.write_dataset(
                draw(ds), draw(out), encoding=draw(values(paths, None, {})), overwrite=overwrite
            )
        )
        after = [p.read_bytes() for p in kept]
        if overwrite is not True:
            assert after[:2] == before[:2], "a file stonedem did not write was replaced"
        for p, data in zip(kept, before):  # the next example sees the same arena
            p.write_bytes(data)
    else:
        check(lambda: getattr(stonedem, function)(draw(values(paths, paths["result"]))))
