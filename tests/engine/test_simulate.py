"""End-to-end engine behaviour: determinism, dt refusal, energy, response measures."""

import numpy as np
import pytest

from stonedem.engine.run import run_scene
from stonedem.engine.scene import load_scene, scene_from_dict
from stonedem.engine.simulate import simulate

SCENE = "tests/data/scenes/rocking_block.yaml"


def test_same_scene_gives_bit_identical_histories():
    scene = load_scene(SCENE, overrides=["solver.duration=1.0"])
    a, b = simulate(scene), simulate(scene)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.theta, b.theta)
    assert np.array_equal(a.energy, b.energy)


def test_chunking_does_not_change_the_result():
    scene = load_scene(SCENE, overrides=["solver.duration=0.5"])
    a, b = simulate(scene, chunks=1), simulate(scene, chunks=7)
    assert np.array_equal(a.theta, b.theta), "progress chunks must not alter the run"


def test_block_at_rest_stays_at_rest():
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 4, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {"name": "drum", "box": {"width": 1, "height": 0.75, "center": [0, 0.375]}},
        ],
        "contact": {"k_n": 1e9, "c_n": 1e5},
        "friction": 0.5,
        "solver": {"duration": 2.0},
        "output": {"every": 0.01},
    }
    r = simulate(scene_from_dict(spec))
    assert np.abs(r.theta[:, 1]).max() < 1e-6, "no spurious rotation"
    assert np.abs(r.x[:, 1] - r.x[0, 1]).max() < 1e-6, "no spurious sliding"
    # settles at the static penetration m g / (k_n L)
    m = 2000.0 * 0.75
    assert r.y[-1, 1] == pytest.approx(0.375 - m * 9.81 / 1e9, abs=1e-7)


def test_eight_drum_column_stays_stable_without_excitation():
    scene = scene_from_dict(
        {
            "structure": {"kind": "column", "n_drums": 8, "height": 6.0, "width": 1.0},
            "contact": {"k_n": 1e9, "c_n": 1e4},
            "friction": 0.5,
            "solver": {"duration": 1.0},
            "output": {"every": 0.01},
        }
    )
    ds = run_scene(scene)
    assert int(ds.collapsed) == 0
    assert float(ds.max_rocking) < 1e-6 and float(ds.max_total_sliding) < 1e-6


def test_rocking_block_dataset_is_self_describing_and_balanced():
    from stonedem.io.schema import missing_metadata

    ds = run_scene(load_scene(SCENE, overrides=["solver.duration=2.0"]))
    assert missing_metadata(ds) == []
    assert ds.attrs["dt"] <= ds.attrs["dt_stability_limit"]
    # c_n = 0, mu = 10: the balance closes to 1 % of the rocking energy (28.7 J)
    assert np.abs(ds.energy_balance_error).max() < 0.01 * 28.7
    assert float(ds.rocking_onset_time) == 0.0, "released tilted: rocking from the start"


def test_vertical_base_motion_carries_the_block():
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 4, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {"name": "drum", "box": {"width": 1, "height": 0.75, "center": [0, 0.375]}},
        ],
        "contact": {"k_n": 1e9, "c_n": 1e5},
        "friction": 0.5,
        # 0.5 g peak vertical acceleration: the block never leaves the base
        "excitation": {
            "kind": "none",
            "vertical": {
                "kind": "harmonic",
                "frequency": 2.0,
                "amplitude": 0.5 * 9.81 / (4 * np.pi) ** 2,
            },
        },
        "solver": {"duration": 1.0},
        "output": {"every": 0.01},
    }
    ds = run_scene(scene_from_dict(spec))
    follow = ds.y.sel(body="drum") - ds.base_vertical_displacement
    assert float(np.ptp(follow.values)) < 1e-4, (
        "rides on the base (static penetration changes only)"
    )


def test_interface_friction_concentrates_sliding():
    spec = {
        "structure": {"kind": "column", "n_drums": 2, "height": 1.0, "width": 1.0},
        "interface_friction": [{"bodies": ["c0_d0", "c0_d1"], "mu": 0.1}],
        "friction": 0.8,
        "contact": {"k_n": 1e9, "c_n": 1e5},
        "excitation": {"kind": "rect_pulse", "accel": 0.3 * 9.81, "duration": 0.5},
        "solver": {"duration": 1.5, "stop_on_collapse": False},
        "output": {"every": 0.01},
    }
    ds = run_scene(scene_from_dict(spec))
    bottom = float(np.abs(ds.sliding.sel(body="c0_d0")).max())
    top = float(np.abs(ds.sliding.sel(body="c0_d1")).max())
    assert top > 0.1 and bottom < 0.01 * top, (
        f"thesis 6.5: only the low-friction interface slides ({bottom:.2e} vs {top:.3f} m)"
    )


def test_initial_velocity_is_used():
    spec = {
        "bodies": [
            {
                "name": "base",
                "box": {"width": 40, "height": 0.5, "center": [0, -0.25]},
                "driven": True,
            },
            {
                "name": "slab",
                "box": {"width": 2, "height": 0.5, "center": [0, 0.25]},
                "velocity": [2.0, 0.0, 0.0],
            },
        ],
        "contact": {"k_n": 1e9, "c_n": 1e5},
        "friction": 0.5,
        "solver": {"duration": 1.0},
        "output": {"every": 0.001},
    }
    ds = run_scene(scene_from_dict(spec))
    # Coulomb deceleration mu g: stops after v^2 / (2 mu g)
    travel = float(ds.x.sel(body="slab")[-1] - ds.x.sel(body="slab")[0])
    assert travel == pytest.approx(2.0**2 / (2 * 0.5 * 9.81), rel=0.01)


def test_stability_limit_from_broad_phase_pairs_equals_the_all_pairs_scan(monkeypatch):
    import itertools

    import stonedem.engine.simulate as sim
    from tests.scenes import drum_wall

    scene = scene_from_dict(drum_wall(6, 4))  # 24 drums in 6 columns, gaps between them
    fast = sim.stability_limit(scene)
    monkeypatch.setattr(
        sim, "box_pairs", lambda lo, hi, margin: list(itertools.combinations(range(len(lo)), 2))
    )
    assert sim.stability_limit(scene) == fast, "the broad phase must not miss a touching neighbour"


def _base():
    return {
        "name": "base",
        "box": {"width": 4, "height": 0.5, "center": [0, -0.25]},
        "driven": True,
    }


def _block(x=0.0, bottom=0.0, **extra):
    return {
        "name": "block",
        "box": {"width": 0.25, "height": 1.0, "center": [x, bottom + 0.5]},
        **extra,
    }


def test_a_scene_with_nothing_driven_is_refused_not_run_into_a_collapse():
    # `stonedem run` of this scene reported "stopped at collapse" at t = 0.32 s: the block
    # had fallen half its height with nothing under it
    from stonedem.engine.simulate import preflight
    from stonedem.errors import InputError

    spec = {"bodies": [_block()], "solver": {"duration": 1.0}, "output": {"every": 0.01}}
    for run in (preflight, simulate, run_scene):
        with pytest.raises(InputError, match="free fall") as err:
            run(scene_from_dict(spec))
        assert err.value.field == "bodies" and "driven" in err.value.fix
    # the base under it, out of reach beside it: the block still has nothing to land on
    spec["bodies"] = [_base(), _block(x=3.0)]
    with pytest.raises(InputError, match="free fall") as err:
        run_scene(scene_from_dict(spec))
    assert err.value.field == "bodies[1] (block)"
    # weightless, nothing falls: a scene of free bodies is fine
    spec.update(bodies=[_block(velocity=[0.1, 0.0, 0.0])], gravity=0.0)
    assert int(run_scene(scene_from_dict(spec)).collapsed) == 0


def test_a_block_released_above_the_base_lands_and_did_not_collapse():
    from stonedem.engine.pack import landing_drops

    # released 0.8 m above the base (more than half its height: the old fall test fired in
    # the air, "stopped at collapse"), area law damped near critical: it lands at 0.4 s and stands
    spec = {
        "bodies": [_base(), _block(bottom=0.8)],
        "friction": 0.5,
        "contact": {"model": "area", "k_n": 1e9, "c_n": 5e5},
        "solver": {"duration": 1.0},
        "output": {"every": 0.01},
    }
    scene = scene_from_dict(spec)
    assert landing_drops(scene) == pytest.approx([0.0, 0.8])
    ds = run_scene(scene)
    assert ds.attrs["status"] == "completed" and int(ds.collapsed) == 0
    assert float(ds.y.sel(body="block")[-1]) == pytest.approx(0.5, abs=1e-3), "at rest on the base"
    # a stack in the air falls together; a stacked structure drops nothing
    spec["bodies"].append(
        {"name": "top", "box": {"width": 0.25, "height": 0.5, "center": [0.05, 2.05]}}
    )
    assert landing_drops(scene_from_dict(spec)) == pytest.approx([0.0, 0.8, 0.8 + 0.0])
    spec["bodies"][-1]["box"]["center"] = [0.05, 2.25]
    assert landing_drops(scene_from_dict(spec)) == pytest.approx([0.0, 0.8, 0.8 + 0.2])
    for structure in (
        {"kind": "column", "n_drums": 4, "capital": {"height": 0.6, "width": 1.4}},
        {"kind": "colonnade", "n_columns": 3, "n_drums": 2, "taper": 1.5},
        {"kind": "two_tier_colonnade"},
    ):
        built = scene_from_dict({"structure": structure, "solver": {"duration": 1.0}})
        assert np.abs(landing_drops(built)).max() < 1e-9


def test_the_loop_is_compiled_apart_from_its_timed_stepping(monkeypatch):
    """compile_seconds apart from wall_seconds (issue 45): the loop is compiled, or loaded from the
    cache, before its first timed call, for the very specialisation that call uses; a compile
    that takes a while has its notice, then one line with its seconds."""
    import io
    import time
    from types import SimpleNamespace

    import stonedem.engine.simulate as simulate_module
    from stonedem.kernels import step

    ds = run_scene(load_scene(SCENE, overrides=["solver.duration=0.05"]))
    assert ds.attrs["compile_seconds"] >= 0.0 and ds.attrs["wall_seconds"] >= 0.0
    assert ds.attrs["compile_seconds_units"] == "s"
    loop = step.run_area if ds.attrs["contact_model"] == "area" else step.run_point
    loaded = len(loop.overloads)
    again = simulate(load_scene(SCENE, overrides=["solver.duration=0.05"]))
    assert again.compile_seconds == 0.0 and len(loop.overloads) == loaded
    monkeypatch.setattr(simulate_module.Progress, "COMPILE_NOTICE_SECONDS", 0.02)
    out = io.StringIO()
    slow = SimpleNamespace(overloads={}, compile=lambda signature: time.sleep(0.2))
    assert simulate_module.compile_for(slow, (1.0,), simulate_module.Progress(out)) >= 0.2
    lines = out.getvalue().splitlines()
    assert (
        len(lines) == 2
        and "compiling the time loop" in lines[0]
        and lines[1].startswith("  compiled the time loop in")
    )


def test_the_warm_compile_covers_every_loop_and_type_of_the_study(monkeypatch):
    """The workflow's compile_kernels jobs (stonedem.engine.run.WARM_SCENES) compile every loop a
    study case runs on, for its argument types, so the jobs that run the engine load the cache."""
    import dataclasses
    from pathlib import Path

    import numba

    import stonedem.engine.simulate as simulate_module
    from stonedem.engine.run import STUDY_LOOPS, WARM_SCENES
    from stonedem.study.grid import config_cases, load_config, search_case
    from stonedem.study.runner import case_scene

    seen = []
    real = simulate_module.compile_for

    def spy(dispatcher, args, progress=None):
        seen.append((dispatcher.py_func.__module__, tuple(numba.typeof(a) for a in args)))
        return real(dispatcher, args, progress)

    monkeypatch.setattr(simulate_module, "compile_for", spy)
    for loop in STUDY_LOOPS:
        simulate(scene_from_dict(WARM_SCENES[loop]))
    warm, seen[:] = set(seen), []
    assert {module for module, _ in warm} == {
        "stonedem.kernels.step",
        "stonedem.kernels.contact_graph",
    }
    root = Path(__file__).resolve().parents[2]
    config = load_config(
        root / "config" / "config.yaml", root / "tests" / "workflow" / "config.yaml"
    )
    for cases in config_cases(config).values():
        for case in cases:
            scene = case_scene(search_case(case, 1.0) if case.search else case, root / "records")
            simulate(dataclasses.replace(scene, duration=0.002))
    assert seen and set(seen) <= warm


def test_a_plan_reuses_what_depends_on_the_bodies_alone_while_the_bodies_are_the_same():
    """BodiesMemo (the stability limit, the contact graph): kept for a scene with the same
    bodies tuple and an equal law, computed again for other bodies or another k_n."""
    import dataclasses

    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import BodiesMemo, stability_limit

    spec = {
        "structure": {"kind": "column", "n_drums": 2, "height": 4.0, "width": 1.0},
        "contact": {"model": "point", "k_n": 1.0e9},
        "excitation": {"kind": "harmonic", "amplitude": 0.1, "frequency": 2.0},
        "solver": {"duration": 0.1},
    }
    scene = scene_from_dict(spec)
    calls = []
    memo = BodiesMemo(lambda s: calls.append(s) or stability_limit(s))
    louder = dataclasses.replace(
        scene,
        horizontal=scene_from_dict(
            {**spec, "excitation": {"kind": "harmonic", "amplitude": 0.3, "frequency": 2.0}}
        ).horizontal,
    )
    assert memo(scene) == memo(louder) == stability_limit(scene) and len(calls) == 1
    stiffer = dataclasses.replace(scene, contact=scene.contact.replace(k_n=4.0e9))
    assert memo(stiffer) == stability_limit(stiffer) < stability_limit(scene) and len(calls) == 2
    rebuilt = scene_from_dict(spec)  # equal bodies, another tuple: computed again
    assert memo(rebuilt) == stability_limit(scene) and len(calls) == 3
