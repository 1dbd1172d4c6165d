"""stonedem.study.stripe_fill: an ensemble study's searches grouped by system, the fills
that complete their stripes run (only those), and Table 7.1's a50 fitted over both."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stonedem.errors import InputError
from stonedem.study import stripe_fill
from stonedem.study.grid import config_cases, load_config
from stonedem.study.runner import CaseStore

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def systems():
    config = load_config(
        ROOT / "config" / "config.yaml", ROOT / "tests" / "workflow" / "config.yaml"
    )
    config["studies"] = {"standalone_records": config["studies"]["standalone_records"]}
    config["ensemble"] = {"members": 3}
    return config_cases(config)["standalone_records"]


def test_members_group_under_the_system_as_configured(systems):
    groups = stripe_fill.member_groups(systems)
    assert list(groups) == ["rec-mexico_standin_chichi_tcu102_drums-1"]
    assert [s.id for s in groups["rec-mexico_standin_chichi_tcu102_drums-1"]] == [
        f"rec-mexico_standin_chichi_tcu102_drums-1_m-{j}" for j in range(3)
    ]
    plain = [
        s.__class__(
            s.study, "x", {k: v for k, v in s.params.items() if k != "member"}, s.scene, s.search
        )
        for s in systems[:1]
    ]
    assert stripe_fill.member_groups(plain) == {}  # one member: no fills


def search_file(path, values, threshold, survived):
    xr.Dataset(
        {"collapse_threshold": ((), threshold), "survived_below_threshold": ((), survived)},
        coords={"pga": ("run", np.asarray(values, float), {"units": "m s-2"})},
        attrs={"search_parameter": "pga"},
    ).to_netcdf(path)
    return path


def test_the_fills_are_the_zone_values_a_member_has_not_run(systems, tmp_path):
    members = stripe_fill.member_groups(systems)["rec-mexico_standin_chichi_tcu102_drums-1"]
    # member 0 ran 2, 8 (bracket 2 .. 8); member 1 ran 2, 4, 8 (2 .. 4); member 2 ran 2, 3, 16 (3 ..
    # 16): zone [2, 16], values in it 2, 3, 4, 8, 16
    paths = [
        search_file(tmp_path / "m0.nc", [2, 8], 8.0, 2.0),
        search_file(tmp_path / "m1.nc", [2, 4, 8], 4.0, 2.0),
        search_file(tmp_path / "m2.nc", [2, 3, 16], 16.0, 3.0),
    ]
    store = CaseStore(None, ROOT / "records")
    table = stripe_fill.fill_stripes(
        members, paths, tmp_path / "runs", tmp_path / "fills.nc", store
    )
    got = sorted(zip(table.stripe_member.values.tolist(), table.stripe_value.values.tolist()))
    assert got == [(0, 3.0), (0, 4.0), (0, 16.0), (1, 3.0), (1, 16.0), (2, 4.0), (2, 8.0)]
    for system, value, collapsed in zip(
        table.stripe_system.values, table.stripe_value.values, table.stripe_collapsed.values
    ):
        with xr.open_dataset(tmp_path / "runs" / f"{system}_pga-{value:g}.nc") as run:
            assert int(float(run["collapsed"]) > 0) == int(
                collapsed
            )  # the fill's verdict is its run's
    assert len(list((tmp_path / "runs").glob("*.nc"))) == 7
    # without run files (search_runs: summary) the same fills and verdicts, and no folder
    slim = stripe_fill.fill_stripes(members, paths, None, tmp_path / "slim.nc", store)
    assert slim.identical(table) and sorted(p.name for p in tmp_path.iterdir()) == [
        "fills.nc",
        "m0.nc",
        "m1.nc",
        "m2.nc",
        "runs",
        "slim.nc",
    ]
    with xr.open_dataset(tmp_path / "fills.nc") as ds:
        assert ds.stripe_value.attrs["units"] == "m s-2" and int(ds.attrs["members"]) == 3
    pieces = stripe_fill.stripe_pieces([tmp_path / "fills.nc"])
    assert {k: v.sizes["stripe_run"] for k, v in pieces.items()} == {
        m.id: n for m, n in zip(members, (3, 2, 2))
    }
    with pytest.raises(InputError, match="searches"):
        stripe_fill.fill_stripes(
            members, paths[:2], tmp_path / "runs", tmp_path / "fills.nc", store
        )


def test_table_7_1_fits_a50_over_the_searches_and_the_fills():
    from stonedem.study.reduce import ensemble_columns

    # two members: 0 ran 4 (stands) and 8 (falls); 1 ran 6 (falls) only. Without fills the runs
    # are separable and no value was run by both; the fills run 0 at 6 and 1 at 4 and 8
    system = xr.Dataset(
        {
            "collapsed": (("member", "run"), [[0.0, 1.0], [1.0, np.nan]]),
            "collapse_threshold": ("member", [8.0, 6.0]),
            "stripe_value": (("member", "stripe_run"), [[6.0, np.nan], [4.0, 8.0]]),
            "stripe_collapsed": (("member", "stripe_run"), [[0.0, np.nan], [0.0, 1.0]]),
        },
        coords={"member": [0, 1], "pga": (("member", "run"), [[4.0, 8.0], [6.0, np.nan]])},
        attrs={"stripe_fills": 3},
    )
    filled = ensemble_columns(system)
    plain = ensemble_columns(
        system.drop_vars(["stripe_value", "stripe_collapsed"]).assign_attrs(stripe_fills=0)
    )
    assert (
        filled["stripes"] == "search runs and stripe fills"
        and plain["stripes"] == "search runs and stripe fills"
    )
    # filled, the stripes 4, 6, 8 hold 0, 1 and 2 of 2 collapses: a50 at 6, everyone falls from 8
    assert filled["a50_m_s2"] == pytest.approx(6.0, rel=1e-9)
    assert filled["a_first_m_s2"] == 6.0 and filled["a_all_m_s2"] == 8.0
    # the search runs alone never ran member 0 at 6, so "all collapse" looks like 6 and a50 4.9
    assert plain["a_all_m_s2"] == 6.0 and plain["a50_m_s2"] < 5.0
    unfilled = system.drop_vars(["stripe_value", "stripe_collapsed"])
    unfilled.attrs = {}
    assert ensemble_columns(unfilled)["stripes"] == "search runs"


def test_the_study_cube_keeps_the_fills_beside_each_members_runs(systems, tmp_path):
    import dataclasses

    from stonedem.study.cube import combine_searches
    from stonedem.study.reduce import ensemble_columns
    from stonedem.study.runner import run_search

    members = stripe_fill.member_groups(systems)["rec-mexico_standin_chichi_tcu102_drums-1"][:2]
    members[1] = dataclasses.replace(
        members[1], search=dataclasses.replace(members[1].search, start=3.0)
    )
    store = CaseStore(None, ROOT / "records")
    paths = []
    for system in members:  # the tiny config's searches: nothing collapses in 1 s up to 8 m/s2
        run_search(system, None, tmp_path / f"{system.id}.nc", store)
        paths.append(tmp_path / f"{system.id}.nc")
    # a fills table as fill_stripes writes it (its verdicts made up: only the merge is tested)
    xr.Dataset(
        {
            "stripe_system": (
                "stripe",
                np.array([members[1].id, members[0].id, members[1].id], dtype=object),
            ),
            "stripe_member": ("stripe", np.array([1, 0, 1], dtype=np.int32)),
            "stripe_value": ("stripe", [2.0, 3.0, 4.5], {"units": "m s-2"}),
            "stripe_collapsed": ("stripe", np.array([0, 0, 1], dtype=np.int8)),
        }
    ).to_netcdf(tmp_path / "fills.nc")
    cube = combine_searches(paths, "", stripe_fill.stripe_pieces([tmp_path / "fills.nc"]))
    assert cube.attrs["stripe_fills"] == 3 and cube.sizes["stripe_run"] == 2
    fills = cube.stripe_value.squeeze(drop=True).transpose("member", "stripe_run").values
    np.testing.assert_array_equal(
        fills, [[3.0, np.nan], [2.0, 4.5]]
    )  # each member's own, NaN-padded
    assert cube.collapse_threshold.dims[-1] == "member" and cube.sizes["member"] == 2
    row = ensemble_columns(cube.squeeze(drop=True))
    assert row["stripes"] == "search runs and stripe fills" and row["a_first_m_s2"] == 4.5
    assert (
        combine_searches(paths, "").attrs.get("stripe_fills") is None
    )  # one member's study: no fills
