"""The CPU ensemble (stonedem.engine.ensemble, issue 33): many scenes' compiled loops side by
side give every scene exactly the run simulate gives it."""

import numpy as np
import pytest

from stonedem.engine.ensemble import run_ensemble
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.errors import InputError
from stonedem.study.reference_scenes import SCENES

FIELDS = ("time", "x", "y", "theta", "energy", "n_contact", "peaks", "peak_theta")
SCALARS = (
    "status",
    "steps_run",
    "collapse_sample",
    "onset_step",
    "collapse_step",
    "quiet_lead",
    "n_steps",
    "dt",
)


def _members(record):
    """Every kind of run: a record with a quiet lead and tail, collapse stopping the run, a
    lone block, a colonnade under a harmonic, the area law; different structures side by side."""
    specs = [
        # settles, is carried through 1 s of silence, rocks, comes to rest on a quiet base
        {
            "structure": {"kind": "column", "n_drums": 1, "height": 3.0, "width": 0.6},
            "friction": 0.6,
            "contact": {"model": "area", "k_n": 1e9, "c_n": 1.2e6},
            "excitation": {"kind": "record", "file": str(record), "baseline": False},
            "solver": {"duration": 4.0},
            "output": {"every": 0.01},
        },
        # a 1 x 4 m block overturned by a 2 Hz, 0.4 m harmonic within 1.5 s
        {
            "structure": {"kind": "column", "n_drums": 1, "height": 4.0, "width": 1.0},
            "friction": 0.7,
            "contact": {"model": "point", "k_n": 1e9},
            "excitation": {"kind": "harmonic", "frequency": 2.0, "amplitude": 0.4},
            "solver": {"duration": 1.5, "stop_on_collapse": True},
            "output": {"every": 0.01},
        },
    ]
    for pga in (2.0, 16.0):
        spec = SCENES["column_8"][1](3.0)
        spec["excitation"]["pga"] = pga
        spec["solver"]["stop_on_collapse"] = True
        specs.append(spec)
    specs.append(SCENES["lone_block"][1](2.0))
    spec = SCENES["colonnade_3x3"][1](1.0)
    spec["excitation"] = {"kind": "harmonic", "pga": 6.0, "frequency": 2.0}
    specs.append(spec)
    spec = SCENES["column_1"][1](1.0)
    spec["contact"] = {"model": "area", "k_n": 1e9, "c_n": 1e4}
    spec["excitation"]["pga"] = 10.0
    specs.append(spec)
    return [scene_from_dict(s) for s in specs]


@pytest.mark.parametrize("threads", [None, 1])
def test_every_member_runs_bit_for_bit_as_simulate_runs_it(quiet_sine_record, threads):
    scenes = _members(quiet_sine_record)
    together = run_ensemble(scenes, threads=threads)
    kinds = set()
    for scene, got in zip(scenes, together):
        alone = simulate(scene)
        for name in FIELDS:
            assert np.array_equal(getattr(got, name), getattr(alone, name), equal_nan=True), name
        assert [getattr(got, k) for k in SCALARS] == [getattr(alone, k) for k in SCALARS]
        assert np.array_equal(got.rest_time, alone.rest_time, equal_nan=True)
        kinds.add((alone.collapse_step >= 0, alone.quiet_lead > 0, np.isfinite(alone.rest_time)))
    # the members cover a collapse, a settled quiet lead and a quiet tail
    assert any(k[0] for k in kinds) and any(k[1] for k in kinds) and any(k[2] for k in kinds), kinds


def test_no_members_and_bad_thread_counts(quiet_sine_record):
    assert run_ensemble([]) == []
    scene = _members(quiet_sine_record)[4]
    for bad in (0, -1, 10**6, 1.5, True, "2"):
        with pytest.raises(InputError, match="threads"):
            run_ensemble([scene], threads=bad)
    for bad in ([scene, {"structure": {}}], [None]):
        with pytest.raises(InputError, match=r"scenes\[\d\]: expected a Scene"):
            run_ensemble(bad)
