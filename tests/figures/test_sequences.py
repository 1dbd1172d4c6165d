"""The sequence_records table (stonedem.figures.sequences): verdicts per event, residuals of
the members that survived the mainshock, with and without an ensemble's members."""

import numpy as np
import xarray as xr

from stonedem.figures.sequences import _sequence_figure, sequence_rows


def _cube(members: int | None):
    shape = (2, 1, members or 1, 2)  # mainshock, aftershock, member, part
    collapsed = np.zeros(shape, dtype=np.int8)
    ran = np.ones(shape, dtype=np.int8)
    collapsed[1, 0, 0, 0], ran[1, 0, 0, 1] = 1, 0  # member 0 falls in the big mainshock
    collapsed[1, 0, 1:, 1] = 1  # the others fall in the aftershock
    sliding = np.full(shape, 0.002)
    sliding[1, 0, :, 0] = [0.01, 0.003, 0.005][: shape[2]]
    dims = ("mainshock_pga", "aftershock_pga", "member", "part")
    data = {
        "part_collapsed": collapsed,
        "part_run": ran,
        "part_residual_total_sliding": sliding,
        "part_residual_rocking": np.zeros(shape),
        "part_max_rocking": np.full(shape, 0.05),
    }
    cube = xr.Dataset(
        {k: (dims, v) for k, v in data.items()},
        coords={"mainshock_pga": [0.5, 3.0], "aftershock_pga": [4.0], "part": [0, 1]},
    )
    return cube if members else cube.isel(member=0, drop=True)


def test_rows_of_an_ensemble_count_the_members_that_survived_the_mainshock():
    quiet, big = sequence_rows(_cube(3))
    assert quiet["members"] == 3 and quiet["aftershock_collapse_fraction"] == 0.0
    assert big["mainshock_collapse_fraction"] == 1 / 3
    assert big["aftershock_collapse_fraction"] == 1.0  # both members that survived it
    assert big["residual_sliding_after_mainshock"] == 0.004  # median of 0.003 and 0.005


def test_rows_without_members_and_the_figure(tmp_path):
    quiet, big = sequence_rows(_cube(None))
    assert big["mainshock_collapse_fraction"] == 1.0
    assert np.isnan(big["aftershock_collapse_fraction"])  # fell in the mainshock
    assert np.isnan(big["residual_sliding_after_mainshock"])
    path = tmp_path / "cube.nc"
    _cube(3).to_netcdf(path)
    assert _sequence_figure([str(path)], tmp_path / "fig.png").stat().st_size > 0
