"""IDA over the record suites (stonedem.fragility.ida): config -> searches, limit states off the
runs, the cube, fits and the physics checks, on synthetic searches whose answers are known."""

import math

import numpy as np
import pytest
import xarray as xr

from stonedem.errors import InputError
from stonedem.fragility.checks import ordering_checks, pulse_check
from stonedem.fragility.fit import fragility_dataset, fragility_table
from stonedem.fragility.ida import (
    LIMIT_STATES,
    check_fragility,
    first_exceedance,
    fragility_comparisons,
    fragility_studies,
    ida_cube,
)
from stonedem.study.grid import config_cases

COLUMN = {
    "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
    "friction": 0.485,
}


def _config(**fragility):
    return {
        "records": {},
        "defaults": {"solver": {"stop_on_collapse": True}},
        "fragility": {"structures": {"col": COLUMN}, **fragility},
    }


def test_a_structure_becomes_a_search_study_over_its_suites_components():
    studies = fragility_studies(_config(suites=["near_field_pulse"], search={"tolerance": 0.1}))
    assert list(studies) == ["ida_col"]
    study = studies["ida_col"]
    assert len(study["grid"]["component"]) == 28 and study["grid"]["component"][0] == "NP01a"
    assert study["search"]["tolerance"] == 0.1 and study["search"]["parameter"] == "pga"
    cases = config_cases({"studies": studies, "defaults": {}})["ida_col"]
    assert cases[0].id == "rec-NP01a" and cases[0].scene["excitation"] == {
        "kind": "record",
        "component": "NP01a",
        "pga": 1.0,
    }


@pytest.mark.parametrize(
    "fragility, field",
    [
        ({"structures": {}}, "fragility.structures"),
        ({"suites": ["far"]}, "fragility.suites[0]"),
        ({"components": ["FF99z"]}, "fragility.components[0]"),
        ({"run_structures": ["nope"]}, "fragility.run_structures[0]"),
        ({"pulse_check": "nope"}, "fragility.pulse_check"),
        ({"job_seconds": -1}, "fragility.job_seconds"),
        ({"colour": 1}, "fragility.colour"),
        ({"search": {"tolerance": 2.0}}, "fragility.search.tolerance"),
        ({"search": {"tolerance": 1e-6, "max_runs": 1000}}, "fragility.search.tolerance"),
    ],
)
def test_bad_fragility_config_names_its_field(fragility, field):
    config = _config(components=["NP01a", "NP01b"])
    config["fragility"].update(fragility)
    with pytest.raises(InputError) as err:
        check_fragility(config)
    assert err.value.field == field


def test_compared_structures_are_checked_and_left_out_when_not_run():
    config = _config(compare={"pair": ["col", "col2"]})
    config["fragility"]["structures"]["col2"] = COLUMN
    assert fragility_comparisons(config) == {"pair": ["col", "col2"]}
    config["fragility"]["run_structures"] = ["col"]  # the quick profile's subset
    assert fragility_comparisons(config) == {}
    for compare, field in (
        ({"pair": ["col", "nope"]}, "fragility.compare.pair[1]"),
        ({"pair": ["col"]}, "fragility.compare.pair"),
        ({"pair": ["col", "col"]}, "fragility.compare.pair"),
        ({"a b": ["col", "col2"]}, "fragility.compare.a b"),
        ([["col", "col2"]], "fragility.compare"),
    ):
        config["fragility"]["compare"] = compare
        with pytest.raises(InputError) as err:
            fragility_comparisons(config)
        assert err.value.field == field


def test_a_structure_error_is_named_under_fragility_structures():
    config = _config(components=["NP01a"])
    config["fragility"]["structures"]["col"] = {**COLUMN, "friction": -1.0}
    with pytest.raises(InputError) as err:
        check_fragility(config)
    assert err.value.field == "fragility.structures.col.friction"


def test_first_exceedance_interpolates_the_ida_curve():
    # response ~ x^2: threshold 4 is reached at x = 2 exactly, between runs 1.5 and 3
    values, response = np.array([3.0, 1.0, 1.5, 6.0]), np.array([9.0, 1.0, 2.25, 36.0])
    est, lo, hi, cen = first_exceedance(values, response > 4.0, response, 4.0)
    assert (lo, hi, cen) == (1.5, 3.0, False) and est == pytest.approx(2.0, rel=1e-12)
    # an exceeding run without a usable response (a collapse): the geometric mean
    est, *_ = first_exceedance(
        values, response > 4.0, np.where(values == 3.0, np.nan, response), 4.0
    )
    assert est == pytest.approx(math.sqrt(1.5 * 3.0))
    # never exceeded: a lower bound at the largest run; exceeded at the first run: no lower end
    assert (
        first_exceedance(values, np.zeros(4, bool), response, 99.0) == (6.0, 6.0, math.nan, True)
        or first_exceedance(values, np.zeros(4, bool), response, 99.0)[3]
    )
    est, lo, hi, cen = first_exceedance(values, np.ones(4, bool), response, 0.5)
    assert est == 1.0 and math.isnan(lo) and not cen


def _search_file(path, structure, component, values, collapsed, rocking, sliding, theta_cr=0.2):
    """A search file as stonedem.study.cube writes it (the variables the cube reads)."""
    values = np.asarray(values, float)
    collapsed = np.asarray(collapsed, bool)
    hits = values[collapsed]
    upper = hits.min() if hits.size else math.nan
    below = values[~collapsed & (values < upper)] if hits.size else values[~collapsed]
    ds = xr.Dataset(
        {
            "collapsed": ("run", collapsed.astype(float)),
            "max_rocking": ("run", rocking),
            "residual_total_sliding": ("run", sliding),
            "theta_cr": ("run", np.full(values.size, theta_cr)),
            "collapse_threshold": ((), upper),
            "survived_below_threshold": ((), below.max()),
            "n_runs": ((), values.size),
            "monotonic": ((), 1),
        },
        coords={"pga": ("run", values), "component": ((), component)},
        attrs={"study": f"ida_{structure}", "search_tolerance": 0.05},
    )
    ds.to_netcdf(path)
    return path


def test_cube_and_fits_from_searches(tmp_path):
    # column a collapses at 4, 5 and 8 m/s2 under three far-field records; colonnade at twice that
    paths = []
    for structure, factor in (("col", 1.0), ("colonnade", 2.0)):
        for comp, pga_c in (("FF01a", 4.0), ("FF01b", 5.0), ("FF02a", 8.0)):
            values = np.array([1.0, 2.0, 3.0, 4.0, 6.0]) * pga_c / 4.0 * factor
            collapsed = values >= pga_c * factor
            rocking = np.where(collapsed, 0.2, 0.001 * values**2)  # theta_cr / 2 = 0.1 at x = 10
            sliding = np.zeros(values.size)
            paths.append(
                _search_file(
                    tmp_path / f"{structure}_{comp}.nc",
                    structure,
                    comp,
                    values,
                    collapsed,
                    rocking,
                    sliding,
                )
            )
    structures = {
        "col": COLUMN,
        "colonnade": {"structure": {"kind": "colonnade", "n_drums": 1, "width": 1.0}},
    }
    cube = ida_cube(paths, structures, ["far_field"])
    assert list(cube.limit_state.values) == list(LIMIT_STATES)
    col = cube.pga_at_limit.sel(structure="col")
    assert col.sel(limit_state="collapse", record=["FF01a", "FF01b", "FF02a"]).values.tolist() == [
        4.0,
        5.0,
        8.0,
    ]
    assert (
        int(cube.censored.sel(structure="col", record="FF03a", limit_state="collapse")) == -1
    )  # not run
    # residual sliding never exceeded before collapse: the collapse intensity
    assert col.sel(limit_state="residual_sliding", record="FF01a") == pytest.approx(
        math.sqrt(3.0 * 4.0)
    )
    # rocking onset theta_cr / 30 = 0.00667 at x = 2.58: interpolated between runs 2 and 3 (x^2
    # exact)
    assert float(col.sel(limit_state="rocking_onset", record="FF01a")) == pytest.approx(
        math.sqrt(6.667), rel=1e-3
    )
    ratio = float(cube.record_pgv.sel(record="FF02a") / cube.record_pga.sel(record="FF02a"))
    assert float(
        cube.pgv_at_limit.sel(structure="col", record="FF02a", limit_state="collapse")
    ) == pytest.approx(8.0 * ratio)
    assert (
        cube.pga_at_limit.attrs["units"] == "m s-2" and cube.pgv_at_limit.attrs["units"] == "m s-1"
    )

    fits = fragility_dataset(cube, samples=50)
    med = float(
        fits.median_pga.sel(structure="col", record_set="far_field", limit_state="collapse")
    )
    assert med == pytest.approx((4.0 * 5.0 * 8.0) ** (1 / 3))  # the MLE median: the geometric mean
    assert int(fits.n_records.sel(structure="col", record_set="all", limit_state="collapse")) == 3
    rows = fragility_table(fits)
    assert {r["structure"] for r in rows} == {"col", "colonnade"}
    checks = ordering_checks(cube, fits, structures)
    colonnade = [r for r in checks if r["check"] == "colonnade >= column"]
    assert colonnade and all(r["holds"] == "yes" for r in colonnade)
    order = [r for r in checks if r["check"] == "limit states in order"]
    assert order and all(r["holds"] == "yes" for r in order)
    # the two structures' collapse curves on one figure (fragility.compare)
    from stonedem.figures.fragility import comparison_figure

    comparison_figure(fits, ["col", "colonnade"], tmp_path / "compare.png")
    assert (tmp_path / "compare.png").stat().st_size > 10_000
    # one record a structure fits nothing: the figures say so instead of failing
    from stonedem.figures.fragility import medians_figure

    unfit = fits.copy(deep=True)
    for name in ("median_pga", "median_pga_band", "probability_pga", "probability_pga_band"):
        unfit[name].values[:] = np.nan
    medians_figure(unfit, None, tmp_path / "medians.png")
    comparison_figure(unfit, ["col", "colonnade"], tmp_path / "compare_unfit.png")
    assert (tmp_path / "medians.png").exists() and (tmp_path / "compare_unfit.png").exists()


def test_pulse_check_places_records_in_makris_vassiliou_coordinates(tmp_path):
    values = np.array([1.0, 2.0, 4.0])
    paths = [
        _search_file(
            tmp_path / "b.nc", "block", "NP01a", values, values >= 2.0, [0.001, 0.3, 0.3], [0, 0, 0]
        )
    ]
    cube = ida_cube(paths, {"block": COLUMN}, ["near_field_pulse"])
    check = pulse_check(cube, "block", COLUMN["structure"])
    rec = cube.sel(record="NP01a")
    omega = 2 * math.pi / float(rec.pulse_period)
    p = math.sqrt(3 * 9.81 / (4 * math.hypot(0.5, 3.0)))  # rectangle: p^2 = 3 g / (4 R)
    assert check.omega_ratio.item() == pytest.approx(omega / p, rel=1e-6)
    pgv = 2.0 * float(rec.record_pgv / rec.record_pga)
    assert check.collapse_ap_pgv.item() == pytest.approx(omega * pgv / 2 / (9.81 / 6.0), rel=1e-6)
    assert 1.0 < check.rigid_one_sine.item() < 10.0  # above the uplift level, a_p > g tan alpha
