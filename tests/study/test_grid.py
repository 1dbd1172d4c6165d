"""Study grids: case tables, stable ids, cubes and the Table 7.1 reduction."""

import numpy as np
import pytest
import xarray as xr

from stonedem.errors import InputError
from stonedem.study.cube import combine_cases
from stonedem.study.grid import case_id, case_table
from stonedem.study.reduce import table_7_1
from stonedem.study.runner import run_case

STUDY = {
    "structure": {"kind": "column", "height": 6.0, "width": 1.0},
    "friction": 0.5,
    "excitation": {"kind": "harmonic", "amplitude": 0.05},
    "solver": {"duration": 0.5},
    "grid": {"n_drums": [1, 2], "frequency": [0.5, 2.0]},
}


def test_case_table_is_the_grid_product_with_stable_ids():
    cases = case_table("s", STUDY, {"contact": {"k_n": 1e9}})
    assert [c.id for c in cases] == ["drums-1_f-0.5", "drums-1_f-2", "drums-2_f-0.5", "drums-2_f-2"]
    assert (
        cases[3].scene["structure"]["n_drums"] == 2
        and cases[3].scene["excitation"]["frequency"] == 2.0
    )
    assert cases[0].scene["contact"] == {"k_n": 1e9}, "defaults carried into every case"
    assert case_table("s", STUDY)[1].id == cases[1].id, "ids depend only on the parameters"
    assert case_id({"record": "athens_x", "pga": 2.5}) == "rec-athens_x_pga-2.5"


@pytest.mark.parametrize(
    "grid, field",
    [
        ({"bogus": [1]}, "grid.bogus"),
        ({"n_drums": []}, "grid.n_drums"),
        ({"n_drums": 3}, "grid.n_drums"),
    ],
)
def test_bad_grids_name_the_field(grid, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        case_table("s", {**STUDY, "grid": grid})


def test_cases_combine_into_a_cube_with_parameter_dimensions(tmp_path):
    from stonedem.io.netcdf import write_dataset

    paths = []
    for case in case_table("s", STUDY, {"contact": {"k_n": 1e9, "c_n": 1e4}}):
        ds = run_case(case)
        assert (
            float(ds["n_drums"]) == case.params["n_drums"]
            and ds["frequency"].attrs["units"] == "Hz"
        )
        paths.append(write_dataset(ds, tmp_path / f"{case.id}.nc"))
    cube = combine_cases(paths)
    assert dict(cube.sizes) == {"n_drums": 2, "frequency": 2, "time": 501}
    assert cube["max_rocking"].attrs["units"] == "rad" and cube["n_drums"].attrs["long_name"]
    assert np.all(np.isfinite(cube["max_rocking"].values))
    assert set(cube["rocking"].dims) == {"n_drums", "frequency", "time"}, (
        "histories keep the time axis"
    )
    for case, path in zip(case_table("s", STUDY), paths):
        with xr.open_dataset(path) as ds:
            along = cube["rocking"].sel(
                n_drums=case.params["n_drums"], frequency=case.params["frequency"]
            )
            assert np.array_equal(along.values[: ds.sizes["time"]], ds["rocking"].values), case.id


def test_listed_cases_and_weak_joint():
    study = {
        "structure": {"kind": "column", "n_drums": 4},
        "friction": 0.48,
        "excitation": {"kind": "harmonic", "frequency": 0.5, "amplitude": 0.3},
        "grid": {"weak_joint": [0, 2]},
        "weak_joint": {"mu": 0.05},
        "cases": [{"weak_joint": 3, "weak_joint_mu": 0.2}],
    }
    cases = case_table("fl", study)
    assert [c.id for c in cases] == ["joint-0", "joint-2", "joint-3_muj-0.2"]
    assert cases[0].scene["interface_friction"] == [{"bodies": ["base", "c0_d0"], "mu": 0.05}]
    assert cases[2].scene["interface_friction"] == [{"bodies": ["c0_d2", "c0_d3"], "mu": 0.2}]
    with pytest.raises(InputError, match="weak_joint.joint"):
        case_table("fl", {**study, "cases": [{"weak_joint": 4}]})
    with pytest.raises(InputError, match=r"cases\[0\]\.speed"):
        case_table("fl", {**study, "cases": [{"speed": 1}]})


def synthetic_cube(collapsed):
    pga = [1.0, 2.0, 4.0, 8.0]
    return xr.Dataset(
        {"collapsed": (("record", "n_drums", "pga"), np.array(collapsed, dtype=float))},
        coords={
            "record": ["mexico_x", "athens_y"],
            "n_drums": [1],
            "pga": ("pga", pga, {"units": "m s-2"}),
        },
    )


def test_table_7_1_rows_bracket_the_first_collapse_and_report_resurrections():
    # not monotonic: mexico collapses at 2, survives 4, collapses 8; athens never
    cube = synthetic_cube([[[0, 1, 0, 1]], [[0, 0, 0, 0]]])
    rows = table_7_1(cube, cube)
    mex = [r for r in rows if r["record"] == "mexico_x" and r["system"] == "single column"][0]
    assert mex["collapse_pga_m_s2"] == 2.0 and mex["survived_pga_m_s2"] == 1.0
    assert mex["resurrections_m_s2"] == "4" and mex["monotonic"] == 0
    assert mex["collapse_map"] == "1:. 2:X 4:. 8:X", "the whole collapse map is kept"
    assert mex["thesis_accel_to_failure_m_s2"] == 1.15
    ath = [r for r in rows if r["record"] == "athens_y" and r["system"] == "colonnade"][0]
    assert np.isnan(ath["collapse_pga_m_s2"]) and ath["survived_pga_m_s2"] == 8.0


def test_table_7_1_reads_a_search_cube_with_runs_padded_by_nan():
    # two systems: 3 runs and 4 runs, the searched pga a coordinate on (record, n_drums, run)
    pga = np.array([[[1.0, 1.8, 1.4, np.nan], [1.0, 1.8, 3.24, 2.4]]])
    collapsed = np.array([[[0, 1, 0, np.nan], [0, 0, 1, 1]]], dtype=float)
    cube = xr.Dataset(
        {"collapsed": (("record", "n_drums", "run"), collapsed)},
        coords={
            "record": ["mexico_x"],
            "n_drums": [1, 2],
            "run": np.arange(4),
            "pga": (("record", "n_drums", "run"), pga),
        },
    )
    rows = [r for r in table_7_1(cube, cube) if r["system"] == "colonnade"]
    assert [
        (r["n_drums"], r["survived_pga_m_s2"], r["collapse_pga_m_s2"], r["n_runs"]) for r in rows
    ] == [(1, 1.4, 1.8, 3), (2, 1.8, 2.4, 4)]
    assert rows[1]["collapse_map"] == "1:. 1.8:. 2.4:X 3.24:X"


def test_string_parameters_keep_their_full_names(tmp_path):
    from stonedem.io.netcdf import write_dataset

    paths = []
    for kind in ("a", "per_span"):
        ds = xr.Dataset(
            {"collapsed": ((), 0.0, {"units": "1", "long_name": "collapsed"})},
            coords={"epistyle_type": ((), kind, {"units": "1", "long_name": "epistyle type"})},
        )
        paths.append(write_dataset(ds, tmp_path / f"{kind}.nc"))
    cube = combine_cases(paths)
    assert sorted(cube["epistyle_type"].values) == ["a", "per_span"], cube["epistyle_type"].values


def test_histories_align_on_times_that_differ_by_rounding(tmp_path):
    from stonedem.io.netcdf import write_dataset

    paths = []
    for k, jitter in ((1, 0.0), (2, 3.5e-18)):
        time = np.arange(5) * 0.01 + jitter * np.arange(5)
        ds = xr.Dataset(
            {
                "collapsed": ((), 0.0, {"units": "1", "long_name": "collapsed"}),
                "rocking": (
                    ("time",),
                    np.full(5, float(k)),
                    {"units": "rad", "long_name": "rocking"},
                ),
            },
            coords={
                "time": ("time", time, {"units": "s", "long_name": "time"}),
                "n_drums": ((), k, {"units": "1", "long_name": "drums"}),
            },
        )
        paths.append(write_dataset(ds, tmp_path / f"{k}.nc"))
    cube = combine_cases(paths)
    assert cube.sizes["time"] == 5, f"{cube.sizes['time']} samples: the two time axes did not align"
    assert not np.isnan(cube["rocking"].values).any()


def test_load_config_merges_a_profile_key_by_key_as_snakemake_does(tmp_path):
    from stonedem.study.grid import config_cases, load_config

    base = tmp_path / "config.yaml"
    base.write_text(
        "defaults: {contact: {k_n: 1.0e10}}\n"
        "studies:\n  s: {structure: {kind: column, n_drums: 2}, friction: 0.5,\n"
        "      excitation: {kind: harmonic, amplitude: 0.1}, solver: {duration: 1.0},\n"
        "      grid: {frequency: [1.0, 2.0, 4.0]}}\n"
    )
    quick = tmp_path / "quick.yaml"
    quick.write_text("studies: {s: {grid: {frequency: [2.0]}}}\nbench_profile: quick\n")
    config = load_config(base, quick)
    assert config["studies"]["s"]["friction"] == 0.5, "keys the profile does not name are kept"
    assert config["studies"]["s"]["grid"] == {"frequency": [2.0]}, "lists are replaced"
    assert config["bench_profile"] == "quick"
    cases = config_cases(config)["s"]
    assert [c.params for c in cases] == [{"frequency": 2.0}]


def test_a_search_study_has_a_system_per_grid_case_and_refuses_its_searched_parameter():
    from stonedem.study.grid import search_case

    study = {
        "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
        "excitation": {"kind": "record"},
        "grid": {"record": ["a", "b"], "n_drums": [1, 2]},
        "search": {"parameter": "pga", "start": 2.0},
    }
    systems = case_table("s", study)
    assert [c.id for c in systems][:2] == ["rec-a_drums-1", "rec-a_drums-2"]
    assert all(c.search.start == 2.0 and c.scene["excitation"]["pga"] == 2.0 for c in systems)
    run = search_case(systems[1], 12.43)
    assert run.id == "rec-a_drums-2_pga-12.43" and run.scene["excitation"]["pga"] == 12.43
    assert run.params == {"record": "a", "n_drums": 2, "pga": 12.43} and run.search is None
    with pytest.raises(InputError, match=r"studies\.s\.grid\.pga: pga is the searched parameter"):
        case_table("s", {**study, "grid": {**study["grid"], "pga": [1.0]}})
    with pytest.raises(InputError, match=r"studies\.s\.search\.tolerance"):
        case_table("s", {**study, "search": {"tolerance": -0.1}})
