"""Output datasets: self-describing, round trip, atomic writes."""

import os

import numpy as np
import pytest
import xarray as xr

from stonedem.engine.run import run_scene
from stonedem.engine.scene import load_scene
from stonedem.errors import InputError
from stonedem.io import schema
from stonedem.io.netcdf import write_dataset
from stonedem.io.schema import missing_metadata


@pytest.fixture(scope="module")
def rocking_dataset():
    return run_scene(
        load_scene("tests/data/scenes/rocking_block.yaml", overrides=["solver.duration=0.5"])
    )


def test_every_variable_and_coordinate_has_units_and_long_name(rocking_dataset):
    assert missing_metadata(rocking_dataset) == []
    for key in ("dt", "k_n", "c_n", "source", "scene", "excitation", "status"):
        assert key in rocking_dataset.attrs


def test_schema_names_every_variable_a_run_writes(rocking_dataset):
    written = list(rocking_dataset.data_vars) + list(rocking_dataset.coords)
    assert {name: rocking_dataset[name].attrs for name in written} == {
        name: schema.attrs_for(name) for name in written
    }
    assert set(schema.CUBE_MEASURES + schema.CUBE_HISTORIES) <= set(written)
    assert not schema.SCENE_VARIABLES.keys() & schema.WALL_VARIABLES.keys(), (
        "attrs_for serves both solvers"
    )


def test_round_trip_through_netcdf(tmp_path, rocking_dataset):
    path = write_dataset(rocking_dataset, tmp_path / "a.nc")
    with xr.open_dataset(path) as back:
        assert np.array_equal(back.theta.values, rocking_dataset.theta.values)
        assert back.theta.attrs["units"] == "rad"
        assert list(back.body.values) == ["base", "block"]


def test_failed_write_leaves_no_file(tmp_path, rocking_dataset):
    bad = rocking_dataset.copy()
    bad.attrs["not_serialisable"] = {"a": object()}
    target = tmp_path / "b.nc"
    with pytest.raises(InputError, match="not_serialisable"):
        write_dataset(bad, target)
    assert not target.exists() and list(tmp_path.iterdir()) == []


# a study-like case (8 drums, 20 Hz x 0.2 m) whose energy balance drifts 0.038 % at dt_safety 1.0:
# no shipped scene drifts past the 1 % tolerance any more (the 20 Hz x 0.25 m case that drifted
# 1.7 % runs at 0.003 % since the automatic step divides the 1 ms clock), so the mechanism is
# tested against a tolerance of 0.01 %, patched in by the fixture below
HARMONIC_8_DRUMS = {
    "name": "drift",
    "structure": {"kind": "column", "n_drums": 8, "height": 6.0, "width": 1.0},
    "density": 2000.0,
    "friction": 0.48,
    "contact": {"model": "point", "k_n": 1.0e10},
    "excitation": {"kind": "harmonic", "frequency": 20.0, "amplitude": 0.2},
    "solver": {"duration": 10.0, "dt": "auto", "dt_safety": 1.0, "stop_on_collapse": False},
    "output": {"every": 0.01},
}
TIGHT_TOLERANCE = 1.0e-4


@pytest.fixture
def tight_energy_tolerance(monkeypatch):
    import stonedem.engine.run
    import stonedem.engine.simulate

    monkeypatch.setattr(stonedem.engine.simulate, "ENERGY_TOLERANCE", TIGHT_TOLERANCE)
    monkeypatch.setattr(stonedem.engine.run, "ENERGY_TOLERANCE", TIGHT_TOLERANCE)


def test_auto_step_is_halved_when_the_energy_balance_drifts(tight_energy_tolerance):
    from stonedem.engine.scene import scene_from_dict

    ds = run_scene(scene_from_dict(HARMONIC_8_DRUMS))
    assert ds.attrs["dt_safety_requested"] == 1.0
    assert (
        ds.attrs["dt_halvings"] >= 1 and ds.attrs["dt_safety"] == 1.0 / 2 ** ds.attrs["dt_halvings"]
    )
    assert ds.attrs["status"] != "energy balance error"
    assert ds.attrs["energy_error"] <= ds.attrs["energy_error_limit"] == TIGHT_TOLERANCE


def test_a_given_step_is_never_changed(tight_energy_tolerance):
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import simulate

    dt = simulate(scene_from_dict(HARMONIC_8_DRUMS)).dt  # the automatic step at dt_safety 1.0
    spec = {**HARMONIC_8_DRUMS, "solver": {**HARMONIC_8_DRUMS["solver"], "dt": dt}}
    ds = run_scene(scene_from_dict(spec))
    assert ds.attrs["dt_halvings"] == 0 and ds.attrs["dt"] == dt
    assert ds.attrs["status"] == "energy balance error"  # reported, not hidden


def test_no_repeat_beyond_the_engines_step_limit(monkeypatch, tight_energy_tolerance):
    import stonedem.engine.simulate
    from stonedem.engine.scene import scene_from_dict

    monkeypatch.setattr(
        stonedem.engine.simulate, "MAX_STEPS", 61000
    )  # the run takes 60,000 steps, its repeat 120,000
    ds = run_scene(scene_from_dict(HARMONIC_8_DRUMS))
    assert ds.attrs["dt_halvings"] == 0 and ds.attrs["dt_safety"] == 1.0
    assert ds.attrs["status"] == "energy balance error"


ROCKING_BLOCK = {  # a 1 x 6 m block tipped by a ramp; the engine's defaults otherwise
    "name": "tip",
    "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
    "friction": 0.485,
    "excitation": {"kind": "ramp", "rate": 0.5},
    "solver": {"duration": 1.0},
}


def _diverging_first(monkeypatch, n_diverged):
    """stonedem.engine.run.simulate whose first n_diverged runs report NaN (the engine's status),
    then run."""
    import dataclasses

    import stonedem.engine.run
    from stonedem.kernels import step

    real, calls = stonedem.engine.run.simulate, []

    def simulate(scene, progress=False):
        calls.append(scene.dt_safety)
        result = real(scene, progress=progress)
        return (
            dataclasses.replace(result, status=step.STATUS_NONFINITE)
            if len(calls) <= n_diverged
            else result
        )

    monkeypatch.setattr(stonedem.engine.run, "simulate", simulate)
    return calls


def test_a_diverged_auto_step_is_halved(monkeypatch):
    from stonedem.engine.scene import scene_from_dict

    calls = _diverging_first(monkeypatch, 1)
    ds = run_scene(scene_from_dict(ROCKING_BLOCK))
    assert calls == [1.0, 0.5] and ds.attrs["dt_halvings"] == 1 and ds.attrs["dt_safety"] == 0.5


def test_a_run_that_diverges_at_every_step_tried_is_an_error(monkeypatch):
    from stonedem.engine.scene import scene_from_dict
    from stonedem.errors import InputError

    calls = _diverging_first(monkeypatch, 3)
    with pytest.raises(InputError, match="diverged"):
        run_scene(scene_from_dict(ROCKING_BLOCK))
    assert calls == [1.0, 0.5, 0.25]
    calls.clear()
    given = {**ROCKING_BLOCK, "solver": {"duration": 1.0, "dt": 1e-5}}
    with pytest.raises(InputError, match="diverged"):
        run_scene(scene_from_dict(given))
    assert calls == [1.0]  # a given dt is run once (its dt_safety is not used)


def test_a_full_disk_is_one_line_and_leaves_nothing(tmp_path, rocking_dataset):
    """A write that fails half-way (ENOSPC from write(2), as a full disk, a quota or a
    file-size limit gives it) is a WriteFailed naming the path and the cause; the temporary
    file and the folders made for it are gone."""
    import errno

    from stonedem.io.atomic import WriteFailed, write_atomically

    def fill(tmp):
        with open(tmp, "wb") as handle:
            handle.write(b"x" * 1000)
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    target = tmp_path / "new" / "deeper" / "b.nc"
    with pytest.raises(
        WriteFailed, match=r"b\.nc: cannot write the file \(No space left on device\)"
    ):
        write_atomically(target, fill)
    assert list(tmp_path.iterdir()) == []


def test_a_file_size_limit_while_writing_netcdf_is_one_line(tmp_path):
    """RLIMIT_FSIZE (SIGXFSZ ignored, as under a quota): netCDF4 says only 'HDF error'."""
    import subprocess
    import sys

    code = (
        "import resource, signal; signal.signal(signal.SIGXFSZ, signal.SIG_IGN); "
        "resource.setrlimit(resource.RLIMIT_FSIZE, (20000, 20000)); "
        "import sys; from stonedem.cli import main; sys.exit(main(sys.argv[1:]))"
    )
    out = tmp_path / "sub" / "full.nc"
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            code,
            "run",
            "tests/data/scenes/rocking_block.yaml",
            "-o",
            str(out),
            "-q",
            "--set",
            "solver.duration=0.2",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {out}: cannot write the file"), (
        proc.stderr
    )
    assert list(tmp_path.iterdir()) == []
