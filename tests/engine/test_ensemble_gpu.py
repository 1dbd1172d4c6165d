"""The GPU ensemble (issue 33), under Numba's CUDA simulator: stacking, launches, chunking,
pair-buffer growth and copies back give every member the run simulate gives it.

The simulator runs each thread's loop compiled for the CPU (stonedem.kernels.gpu), so this
checks everything but the GPU's own code generation (tests/kernels/test_cuda_compile.py) and
its rounding, which only a GPU shows. Each check runs in a child process: the simulator is
chosen when numba.cuda is first imported.
"""

import importlib.util
import json
import os
import subprocess
import sys
import textwrap

import pytest

from stonedem.engine.ensemble import run_ensemble
from stonedem.errors import InputError

# agreement asked of the GPU over a short horizon (issue 33), on positions and rotations
TOLERANCE = 1e-9

CHILD = textwrap.dedent("""
    import json, sys
    import numpy as np
    from stonedem.study.reference_scenes import SCENES
    from stonedem.engine import ensemble
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import simulate

    record = sys.argv[1]
    def spec(name, duration, **changes):
        s = SCENES[name][1](duration)
        for key, value in changes.items():  # merged, unless it names another kind
            s[key] = value if "kind" in value else {**s.get(key, {}), **value}
        return s
    groups = {
        # a record with a quiet lead (settling, then carried), two lengths of record
        "record": [{"structure": {"kind": "column", "n_drums": 1, "height": 3.0, "width": 0.6},
                    "friction": 0.6, "contact": {"model": "point", "k_n": 1e9},
                    "excitation": {"kind": "record", "file": record, "baseline": False,
                                   "scale": scale},
                    "solver": {"duration": duration}, "output": {"every": 0.01}}
                   for scale, duration in ((1.0, 3.0), (2.5, 2.0), (4.0, 3.0))],
        # a 1 x 4 m block under a 2 Hz harmonic: rocks at 0.05 m, overturns within 1.5 s at 0.4 m
        "collapse": [{"structure": {"kind": "column", "n_drums": 1, "height": 4.0, "width": 1.0},
                      "friction": 0.7, "contact": {"model": "point", "k_n": 1e9},
                      "excitation": {"kind": "harmonic", "frequency": 2.0, "amplitude": amplitude},
                      "solver": {"duration": 1.5, "stop_on_collapse": True},
                      "output": {"every": 0.01}}
                     for amplitude in (0.05, 0.4)],
        "column_8": [spec("column_8", 0.5, excitation={"pga": pga}) for pga in (2.0, 8.0)],
        "colonnade": [spec("colonnade_3x3", 0.3,
                           excitation={"kind": "harmonic", "pga": pga, "frequency": 2.0})
                      for pga in (3.0, 6.0)],
        "lone_block": [spec("lone_block", 0.5)],
        "area_law": [spec("column_1", 0.5, contact={"model": "area", "k_n": 1e9, "c_n": 1e4},
                          excitation={"pga": pga}) for pga in (6.0, 10.0)],
    }

    def run(groups):
        out = {}
        for name, specs in groups.items():
            scenes = [scene_from_dict(s) for s in specs]
            rows = []
            for scene, gpu in zip(scenes, ensemble.run_ensemble(scenes, device="gpu")):
                cpu = simulate(scene)
                same_shape = cpu.theta.shape == gpu.theta.shape
                rows.append({
                    "status": [cpu.status, gpu.status], "steps": [cpu.steps_run, gpu.steps_run],
                    "collapse": [cpu.collapse_step, gpu.collapse_step],
                    "onset": [cpu.onset_step, gpu.onset_step],
                    "samples": [len(cpu.time), len(gpu.time)],
                    "position": float(max(np.max(np.abs(cpu.x - gpu.x)),
                                          np.max(np.abs(cpu.y - gpu.y))))
                    if same_shape else None,
                    "theta": float(np.max(np.abs(cpu.theta - gpu.theta))) if same_shape else None,
                    "peaks": float(np.max(np.abs(cpu.peaks - gpu.peaks))),
                })
            out[name] = rows
        return out

    # each new type of the members' loop compiled on this thread before the launch: in a
    # simulator thread it had half the GIL, the simulator's own thread polling the others
    import numba
    from stonedem.kernels import gpu
    simulated = gpu.member_kernel()

    class CompiledFirst:
        def __getitem__(self, grid):
            def launch(leaves, lengths, *rest):
                host = [numba.typeof(gpu._host_array(a)) for a in (lengths, *rest)]
                stacked = numba.typeof(tuple(gpu._host_array(a) for a in leaves))
                gpu.run_member.compile((stacked, host[0], numba.int64, *host[1:]))
                return simulated[grid](leaves, lengths, *rest)
            return launch
    gpu.member_kernel = CompiledFirst

    # the modes one after the other in this one process, so the simulator's loop compiles once
    out = {"plain": run(groups)}
    capacity = ensemble.pair_capacity
    ensemble.pair_capacity = lambda model: 1  # one pair of room at first: the buffers must grow
    out["small_pairs"] = run({"colonnade": groups["colonnade"]})
    ensemble.pair_capacity = capacity
    gpu.MEMBER_FASTEST = True  # the coalescing layout (stonedem.kernels.members.stack)
    # the record group's runs (a quiet lead, two lengths of record) on column_8's eight drums:
    # the two groups' stacked leaves then have one type, so run_member compiles once for the
    # layout (the lone drum's stack typed apart: a second ~150 s compile under the simulator)
    eight_drums = spec("column_8", 0.5)["structure"]
    on_eight = [{**s, "structure": eight_drums} for s in groups["record"]]
    out["member_fastest"] = run({"record": on_eight, "column_8": groups["column_8"]})
    gpu.MEMBER_FASTEST = False
    print(json.dumps(out))
""")


@pytest.fixture(scope="module")
def simulated(quiet_sine_record) -> dict:
    """{mode: {group: rows}} of one child process under the simulator (every mode in it)."""
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    done = subprocess.run(
        [sys.executable, "-c", CHILD, str(quiet_sine_record)],
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.splitlines()[-1])


# the simulator numba-cuda ships (numba's own is deprecated); the [gpu] extra installs it, and
# CI's GPU step runs this file with it (compiling the simulated loop takes ~3 min cold)
@pytest.mark.skipif(
    importlib.util.find_spec("numba_cuda") is None,
    reason="numba-cuda is not installed (pip install -e '.[gpu]')",
)
@pytest.mark.parametrize("mode", ["plain", "small_pairs", "member_fastest"])
def test_simulated_gpu_members_run_as_simulate_runs_them(simulated, mode):
    groups = simulated[mode]
    assert groups
    for name, rows in groups.items():
        for i, row in enumerate(rows):
            where = f"{name}[{i}]"
            for key in ("status", "steps", "collapse", "onset", "samples"):
                assert row[key][0] == row[key][1], (
                    f"{where}: {key} cpu {row[key][0]}, gpu {row[key][1]}"
                )
            assert row["position"] <= TOLERANCE and row["theta"] <= TOLERANCE, where
            assert row["peaks"] <= TOLERANCE, where
    if mode == "plain":  # the groups do what they are there for
        assert groups["collapse"][1]["collapse"][0] >= 0
        assert groups["collapse"][0]["collapse"][0] < 0
        assert len({row["samples"][0] for row in groups["record"]}) > 1  # records of two lengths


def test_unknown_device_is_refused_in_one_line():
    with pytest.raises(InputError, match="device"):
        run_ensemble([], device="tpu")


def test_gpu_without_one_says_why(monkeypatch):
    from stonedem.engine.scene import scene_from_dict
    from stonedem.kernels import gpu
    from stonedem.study.reference_scenes import SCENES

    monkeypatch.setattr(gpu, "gpu_available", lambda: (False, "no CUDA GPU or driver found"))
    with pytest.raises(RuntimeError, match="^device gpu: no CUDA GPU"):
        run_ensemble([scene_from_dict(SCENES["lone_block"][1](0.1))], device="gpu")
