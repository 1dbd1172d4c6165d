"""The ensemble runner (stonedem.study.ensemble): member 0 is the study's own run bit for bit,
the stripe fills complete every member's stripes, a rounding file gives the same ensemble as a
direct run, and the command refuses bad options in one line before running."""

import io
import shutil
import sys
import types
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from benchmarks import rounding
from stonedem.study import ensemble
from stonedem.study.grid import config_cases, load_config
from stonedem.study.runner import run_case

ROOT = Path(__file__).resolve().parents[2]
# two cheap grid cases (ramps, ~0.1 s each) and one cheap search (5 runs to a 10 % bracket)
TINY = """studies:
  ramp_drums:
    grid: {n_drums: [1, 4]}
  standalone_records:
    grid: {record: [athens_standin_kocaeli_arc000], n_drums: [1]}
    search: {start: 8.0, tolerance: 0.1, fill: 0}
"""
STUDIES = ["ramp_drums", "standalone_records"]


@pytest.fixture
def tiny(tmp_path, monkeypatch):
    """(config path, grid cases, search systems) of the tiny config, run from the repository
    root."""
    monkeypatch.chdir(ROOT)  # the cases' records are found from the repository root
    folder = tmp_path / "config"
    folder.mkdir()
    shutil.copy(ROOT / "config/config.yaml", folder / "config.yaml")
    (folder / "tiny.yaml").write_text(TINY)
    groups = config_cases(load_config(folder / "config.yaml", folder / "tiny.yaml"), STUDIES)
    return folder / "tiny.yaml", groups["ramp_drums"], groups["standalone_records"]


@pytest.fixture
def direct(tiny):
    """The tiny config's ensemble of K = 2 members, run directly."""
    _, cases, systems = tiny
    return ensemble.run_members(cases, systems, [0, 1], jobs=1, log=io.StringIO())


def test_member_0_is_the_study_run_bit_for_bit(tiny, direct):
    _, cases, _ = tiny
    assert len(cases) == 2
    for case, row in zip(cases, direct.verdicts):
        plain = run_case(case, "records")
        assert row[0]["collapsed"] == int(float(plain["collapsed"]) > 0)
        assert row[0]["max_rocking"] == float(plain["max_rocking"].max())  # bit for bit
        assert row[0]["dt"] == plain.attrs["dt"]
    ds = ensemble.ensemble_dataset(*tiny[1:], direct)
    assert list(ds.member.values) == [0, 1] and ds.attrs["members"] == 2
    assert ds.collapsed.dtype == np.int8 and ds.sizes["case"] == 2 and ds.sizes["system"] == 1
    assert ds.threshold.values[0, 0] == direct.searches[0][0]["upper"]
    # the run table holds every search run, each in the search's own phases
    assert ds.sizes["run"] == sum(r["n_runs"] for r in direct.searches[0])
    assert set(ds.run_phase.values) <= {"hunt", "bisect", "fill"}
    for name in ds.variables:
        assert "long_name" in ds[name].attrs, name
        assert "units" in ds[name].attrs or ds[name].dtype.kind in "OSU", name


def test_the_stripe_fill_gives_every_member_every_value_inside_the_zone(tiny, direct):
    _, _, systems = tiny
    # member 1's search as if it had found another bracket (the two members of the tiny
    # config agree): 11.0 survived, 12.0 collapsed, so the zone is [lower of 0, 12.0]
    search = direct.searches[0][0]
    fake = {
        **search,
        "runs": [
            (8.0, False, "hunt"),
            (14.4, True, "hunt"),
            (11.0, False, "bisect"),
            (12.0, True, "bisect"),
        ],
        "lower": 11.0,
        "upper": 12.0,
        "n_runs": 4,
    }
    results = direct._replace(searches=[[search, fake]])
    filled = ensemble.run_stripes(results, systems, jobs=1, log=io.StringIO())
    ran = {0: {v for v, _, _ in search["runs"]}, 1: {v for v, _, _ in fake["runs"]}}
    for j, value, _ in filled.stripes[0]:
        assert value not in ran[j]  # nothing run twice
        ran[j].add(value)
    zone = (min(search["lower"], 11.0), max(search["upper"], 12.0))
    inside = {v for values in ran.values() for v in values if zone[0] <= v <= zone[1]}
    assert len(inside) >= 4 and len(filled.stripes[0]) >= 2
    for j in (0, 1):
        assert inside <= ran[j], j
    # a stripe run is the member's own run of that value
    j, value, collapsed = filled.stripes[0][0]
    assert collapsed == ensemble.member_value(systems[0], value, j)["collapsed"]
    ds = ensemble.ensemble_dataset(*tiny[1:], filled)
    assert int((ds.run_phase == ensemble.STRIPE).sum()) == len(filled.stripes[0])


def test_a_rounding_file_gives_what_a_direct_run_gives(tiny, direct, tmp_path):
    config, cases, systems = tiny
    code = rounding.main(
        [
            "--config",
            str(config),
            "--studies",
            *STUDIES,
            "--perturbations",
            "1",
            "--jobs",
            "1",
            "--out",
            str(tmp_path / "rounding"),
        ]
    )
    assert code == 0
    converted = ensemble.from_rounding(
        tmp_path / "rounding" / "rounding.nc", cases, systems, jobs=1, log=io.StringIO()
    )
    assert converted.members == direct.members == [0, 1]
    assert converted.verdicts == direct.verdicts
    assert (
        converted.searches == direct.searches
    )  # the same runs, values to the last bit, and phases
    assert converted.stripes == direct.stripes
    xr.testing.assert_identical(
        ensemble.ensemble_dataset(cases, systems, converted).drop_attrs(),
        ensemble.ensemble_dataset(cases, systems, direct).drop_attrs(),
    )


def test_a_rounding_file_of_other_cases_is_refused(tiny, tmp_path):
    config, cases, systems = tiny
    assert (
        rounding.main(
            [
                "--config",
                str(config),
                "--studies",
                "ramp_drums",
                "--perturbations",
                "1",
                "--jobs",
                "1",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    with pytest.raises(ensemble.InputError, match="--from-rounding: its cases differ"):
        ensemble.from_rounding(tmp_path / "rounding.nc", cases[:1], [])


def test_the_command_writes_the_file_and_its_summary(tiny, tmp_path, capsys, monkeypatch):
    config, _, _ = tiny
    # layers A and B come from stonedem.study.exact_checks: a stand-in of that layout here
    stub = types.SimpleNamespace(
        layer_a=lambda quick: xr.Dataset(
            {"check_value": ("check", [1.0], {"units": "1", "long_name": "value"})},
            coords={"check": ["housner_period"]},
        ),
        layer_b=lambda duration=0.5: xr.Dataset(
            {"floor_position": ("scene", [1e-12], {"units": "m", "long_name": "floor"})},
            coords={"scene": ["block"]},
        ),
    )
    monkeypatch.setitem(sys.modules, "stonedem.study.exact_checks", stub)
    monkeypatch.setattr("stonedem.study.exact_checks", stub, raising=False)
    out = tmp_path / "ensemble.nc"
    # two worker processes: the pool's path (the stand-in layers are read in this process)
    code = ensemble.main(
        [
            "--config",
            str(config),
            "--studies",
            *STUDIES,
            "--members",
            "2",
            "--first",
            "1",
            "--jobs",
            "2",
            "--checks",
            "quick",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert (
        "2 members" in text
        and "split cases" in text
        and "cells whose member thresholds differ" in text
    )
    with xr.open_dataset(out) as ds:
        assert list(ds.member.values) == [1, 2] and ds.attrs["first_member"] == 1
        assert ds.attrs["perturbation"] == "stiffness" and ds.attrs["checks"] == "quick"
        assert "check" in ds.dims and "scene" in ds.dims
        assert len(ds.attrs["config_digest"]) == 64 and "tiny.yaml" in ds.attrs["config"]
        assert ds.attrs["Conventions"].startswith("CF") and "stonedem" in ds.attrs["history"]


@pytest.mark.parametrize(
    "argv, field",
    [
        (["--members", "0"], "--members"),
        (["--first", "-1"], "--first"),
        (["--members", "5", "--first", "998"], "--members"),
        (["--perturbation", "wind"], "--perturbation"),
        (["--checks", "some"], "--checks"),
        (["--jobs", "0"], "--jobs"),
        (["--studies", "nope"], "--studies"),
        (["--from-rounding", "config/config.yaml"], "--from-rounding"),
    ],
)
def test_the_command_refuses_a_bad_option_in_one_line(tiny, tmp_path, capsys, argv, field):
    config, _, _ = tiny
    out = tmp_path / "ensemble.nc"
    assert ensemble.main(["--config", str(config), *argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"error: {field}") and "\n" not in err
    assert not out.exists()


def test_run_members_refuses_a_repeated_or_impossible_member(tiny):
    _, cases, _ = tiny
    with pytest.raises(ensemble.InputError, match="member index repeats"):
        ensemble.run_members(cases, [], [0, 0], jobs=1, log=io.StringIO())
    with pytest.raises(ensemble.InputError, match="member"):
        ensemble.run_members(cases, [], [-1], jobs=1, log=io.StringIO())
    with pytest.raises(ensemble.InputError, match="perturbation"):
        ensemble.run_members(cases, [], [0], jobs=1, perturbation="wind", log=io.StringIO())


def test_the_file_carries_a50_its_band_the_zone_and_the_thesis_value_per_search():
    """with_bands: a system whose members split between 10 and 12 m/s2 (stripes at 9, 10, 11,
    12, 13: 0, 1, 2, 3 and 4 of 4 members collapse) has a50 near 11 inside its band."""
    import xarray as xr

    from stonedem.study.ensemble import with_bands
    from stonedem.study.grid import Case

    values, members, collapsed = [], [], []
    for j in range(4):
        for value in (9.0, 10.0, 11.0, 12.0, 13.0):
            values.append(value)
            members.append(j)
            collapsed.append(int(value >= 13.0 - j))  # member j collapses from 13 - j
    thresholds = [
        min(v for v, m, c in zip(values, members, collapsed) if m == j and c) for j in range(4)
    ]
    ds = xr.Dataset(
        {
            "threshold": (("system", "member"), [thresholds], {"units": "m s-2"}),
            "run_system": ("run", np.zeros(len(values), dtype=np.int32)),
            "run_member": ("run", np.array(members, dtype=np.int32)),
            "run_value": ("run", np.array(values)),
            "run_collapsed": ("run", np.array(collapsed, dtype=np.int8)),
            "collapsed": (
                ("case", "member"),
                np.array([[0, 1, 1, 0], [1, 1, 1, 1]], dtype=np.int8),
            ),
        },
        coords={"member": [0, 1, 2, 3], "case": ["a/x", "a/y"], "case_study": ("case", ["a", "a"])},
    )
    system = Case(
        "standalone_records",
        "rec-athens_standin_kocaeli_arc000_drums-1",
        {"record": "athens_standin_kocaeli_arc000", "n_drums": 1},
        {},
    )
    out = with_bands(ds, [system])
    assert (
        out["thesis_threshold"].item() == 20.77
    )  # thesis Table 7.1, single column, 1 drum, Athens
    assert out["a_first"].item() == 10.0 and out["a_all"].item() == 13.0
    assert (
        10.5 < out["a50"].item() < 11.5
        and out["a50_low"].item() <= out["a50"].item() <= out["a50_high"].item()
    )
    assert out["threshold_member_0"].item() == thresholds[0] and out["threshold_min"].item() == 10.0
    np.testing.assert_array_equal(out["collapse_fraction"].values, [0.5, 1.0])
    np.testing.assert_array_equal(out["split"].values, [1, 0])
    assert (
        out["study_cases"].sel(study="a").item() == 2
        and out["study_split_cases"].sel(study="a").item() == 1
    )
    assert out["a50"].attrs["units"] == "m s-2" and out["fit_status"].item() == "fitted"
