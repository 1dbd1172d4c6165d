"""What a scene may ask of the machine (issue 43): free text is text of bounded length, the
memory a run needs is estimated before it starts and refused naming output.every and a
value that fits, and the quiet phases fill their samples in pieces of bounded memory."""

import dataclasses

import numpy as np
import pytest

import stonedem.engine.memory
import stonedem.engine.simulate
from stonedem.engine.memory import available_memory, memory_budget, run_bytes
from stonedem.engine.scene import MAX_TEXT, scene_from_dict
from stonedem.engine.simulate import MAX_STEPS, preflight
from stonedem.engine.structures import standalone_column
from stonedem.errors import InputError


def column(duration=1.0, every=0.01, **extra):
    return {
        "bodies": standalone_column(3, height=3.0, width=0.6),
        "friction": 0.6,
        "excitation": {"kind": "harmonic", "amplitude": 0.001, "frequency": 2.0},
        "solver": {"duration": duration},
        "output": {"every": every},
        **extra,
    }


@pytest.mark.parametrize(
    "field, value, message",
    [
        ("name", ["lol"] * 3, "name: expected text, got a list"),
        ("description", {"a": 1}, "description: expected text, got a mapping"),
        ("name", "x" * (MAX_TEXT + 1), "name: 1001 characters exceed the limit 1000"),
        ("description", "y" * 5000, "description: 5000 characters exceed the limit 1000"),
        ("name", "two\nlines", r"name: contains the control character '\\n'"),
    ],
)
def test_free_text_is_text_of_bounded_length(field, value, message):
    with pytest.raises(InputError, match=message):
        scene_from_dict(column(**{field: value}))


def test_free_text_within_the_limit_is_kept():
    scene = scene_from_dict(column(name="n" * MAX_TEXT, description="line one\nline two"))
    assert scene.spec["description"] == "line one\nline two" and len(scene.spec["name"]) == 1000


def test_the_memory_budget_is_a_share_of_what_the_process_may_take():
    total = available_memory()
    assert 0 < total and memory_budget() == min(stonedem.engine.memory.MAX_RUN_BYTES, 0.5 * total)
    # 8 bytes x (32 + 8 x 4 bodies) per sample, and 24 doubles per pair of bodies
    assert run_bytes(1000, 4) == 8.0 * (1000 * 64 + 24 * 16)


def test_a_run_too_big_for_the_memory_names_output_every_and_a_value_that_fits(monkeypatch):
    monkeypatch.setattr(stonedem.engine.simulate, "memory_budget", lambda: 50e6)
    scene = scene_from_dict(column(duration=3600.0, every=0.001))
    with pytest.raises(
        InputError,
        match=r"^output.every: 3.6e\+06 samples of 4 bodies need about 1.72 GiB, "
        r"over the 0.0466 GiB .*raise output.every to 0.037 s or more",
    ) as err:
        preflight(scene)
    assert "dt_safety" not in str(err.value)
    preflight(dataclasses.replace(scene, output_every=0.037))  # the value named fits
    with pytest.raises(InputError, match="output.every"):
        preflight(dataclasses.replace(scene, output_every=0.036))  # and is the smallest of 2 digits


def test_an_hour_sampled_every_10_us_is_refused_for_output_every_not_dt_safety():
    scene = scene_from_dict(column(duration=3600.0, every=1e-5))
    with pytest.raises(
        InputError,
        match=r"^output.every: 1e-05 s makes dt = 1e-05 s: 3.6e\+08 steps .*"
        r"over the limit 2e\+08; raise output.every to",
    ) as err:
        preflight(scene)
    assert "dt_safety" not in str(err.value)
    every = float(str(err.value).split("raise output.every to ")[1].split(" s")[0])
    dt, _, n_steps = preflight(dataclasses.replace(scene, output_every=every))
    assert n_steps <= MAX_STEPS


def test_the_quiet_scan_and_fill_in_pieces_are_the_same_run(monkeypatch):
    import math

    import stonedem.engine.quiet
    from stonedem.engine.quiet import quiet_steps
    from stonedem.engine.simulate import run_time_step, simulate
    from stonedem.validation.cases import block_scene

    # a block slides under a 0.5 s pulse, then rests on a quiet base: the tail is carried
    scene = scene_from_dict(
        block_scene(
            2.0,
            0.5,
            friction=0.2,
            k_n=1e8,
            c_n=math.sqrt(1e8 * 2.0 * 2700.0),
            excitation={"kind": "rect_pulse", "accel": 0.5 * 9.81, "duration": 0.5},
            duration=4.0,
            every=0.001,
            base_width=20.0,
        )
    )
    dt, _ = run_time_step(scene)
    whole, phases = simulate(scene), quiet_steps(scene, dt, 4000, 1)
    monkeypatch.setattr(stonedem.engine.quiet, "CHUNK", 37)
    pieces = simulate(scene)
    assert quiet_steps(scene, dt, 4000, 1) == phases
    assert 1.25 < whole.rest_time < 2.5  # the tail was carried, in 60-odd pieces
    for key in ("time", "x", "y", "theta", "energy", "n_contact"):
        assert np.array_equal(getattr(whole, key), getattr(pieces, key)), key


def test_provenance_is_measured_without_expanding_shared_parts():
    import json
    import time

    from stonedem.io.provenance import bounded_json, json_size_over

    laughs = "lol"
    for _ in range(9):
        laughs = [laughs] * 10  # 10^9 strings, 10 lists in memory
    start = time.perf_counter()
    with pytest.raises(InputError, match=r"^scene: is over 4000000 characters as JSON"):
        bounded_json({"description": laughs}, "scene")
    assert time.perf_counter() - start < 5.0  # measured 0.7 s; json.dumps never ends
    small = {"b": [1.5, "text"], "a": None}
    assert bounded_json(small, "scene") == json.dumps(small, sort_keys=True)
    text = json.dumps(small)
    assert not json_size_over(small, len(text)) and json_size_over(small, 10)
