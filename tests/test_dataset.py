"""Output datasets: self-describing, round trip, atomic writes."""

import numpy as np
import pytest
import xarray as xr

from dem.dataset import run_scene, write_dataset
from dem.scene import load_scene
from dem import schema
from dem.schema import missing_metadata


@pytest.fixture(scope="module")
def rocking_dataset():
    return run_scene(load_scene("tests/data/scenes/rocking_block.yaml", ["solver.duration=0.5"]))


def test_every_variable_and_coordinate_has_units_and_long_name(rocking_dataset):
    assert missing_metadata(rocking_dataset) == []
    for key in ("dt", "k_n", "c_n", "source", "scene", "excitation", "status"):
        assert key in rocking_dataset.attrs


def test_schema_names_every_variable_a_run_writes(rocking_dataset):
    written = list(rocking_dataset.data_vars) + list(rocking_dataset.coords)
    assert {name: rocking_dataset[name].attrs for name in written} == {name: schema.attrs_for(name) for name in written}
    assert set(schema.CUBE_MEASURES + schema.CUBE_HISTORIES) <= set(written)
    assert not schema.SCENE_VARIABLES.keys() & schema.WALL_VARIABLES.keys(), "attrs_for serves both solvers"


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
    with pytest.raises(Exception):
        write_dataset(bad, target)
    assert not target.exists() and list(tmp_path.iterdir()) == []
