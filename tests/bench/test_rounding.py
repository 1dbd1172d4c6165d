"""The rounding-sensitivity benchmark (benchmarks.rounding): what it perturbs, what it
counts, and its command line."""

import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from benchmarks import rounding
from stonedem.engine.run import run_scene
from stonedem.study.grid import config_cases, load_config

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def ramp_case(monkeypatch):
    monkeypatch.chdir(ROOT)  # the cases' records are found from the repository root
    config = load_config(ROOT / "config/config.yaml", ROOT / "config/quick.yaml")
    return config_cases(config, ["ramp_drums"])["ramp_drums"][0]


def test_a_perturbation_changes_k_n_by_its_last_bits_and_nothing_else(ramp_case):
    base = rounding.perturbed_scene(ramp_case, 0)
    for j in (1, 3):
        scene = rounding.perturbed_scene(ramp_case, j)
        assert scene.contact.k_n == base.contact.k_n * (1.0 - j * 2.0**-52)
        assert 0 < base.contact.k_n - scene.contact.k_n <= 2 * j * math.ulp(base.contact.k_n)
        assert scene.contact.k_t == base.contact.k_t and scene.dt_safety == base.dt_safety
        assert (
            scene.duration == base.duration
            and scene.gravity == base.gravity
            and scene.dt == base.dt
        )
        for body, same in zip(scene.bodies, base.bodies, strict=True):
            assert np.array_equal(body.vertices, same.vertices) and body.mass == same.mass


def test_a_perturbed_run_keeps_its_step_and_moves_only_in_the_last_bits(ramp_case):
    # a ramp is not chaotic before it topples: the perturbed run follows the configured one
    runs = [run_scene(rounding.perturbed_scene(ramp_case, j)) for j in (0, 1)]
    assert runs[1].attrs["k_n"] != runs[0].attrs["k_n"]
    assert runs[1].attrs["dt"] == runs[0].attrs["dt"]
    assert int(runs[1]["collapsed"]) == int(runs[0]["collapsed"])
    theta = [ds["theta"].values for ds in runs]
    assert theta[0].shape == theta[1].shape
    assert np.max(np.abs(theta[1] - theta[0])) <= 1e-6 * np.max(np.abs(theta[0]))


def _synthetic():
    """Three cases of two studies, two search systems, K = 2, outcomes chosen by hand."""
    collapsed = np.array(
        [
            [1, 1, 0],  # a/x: perturbation 2 changes it
            [0, 1, 1],  # a/y: both change it
            [0, 0, 0],
        ],  # b/z: none
        dtype=np.int8,
    )
    upper = np.array(
        [
            [10.0, 10.0, 11.0],  # 10 % shift, bracket 2 %: 5 brackets
            [4.0, 3.9, 4.0],
        ]
    )  # 2.5 % shift, bracket 4 %
    lower = np.array(
        [[10.0 / 1.02, 10.0 / 1.02, 11.0 / 1.02], [4.0 / 1.04, 3.9 / 1.04, 4.0 / 1.04]]
    )
    ds = xr.Dataset(
        {
            "collapsed": (("case", "perturbation"), collapsed),
            "collapse_value": (("system", "perturbation"), upper, {"units": "m s-2"}),
            "survived_value": (("system", "perturbation"), lower, {"units": "m s-2"}),
        },
        coords={
            "perturbation": [0, 1, 2],
            "case": ["a/x", "a/y", "b/z"],
            "case_study": ("case", ["a", "a", "b"]),
            "system": ["s/1", "s/2"],
        },
    )
    return rounding.summarize(ds)


def test_summarize_counts_changed_verdicts_per_case_and_study():
    ds = _synthetic()
    assert list(ds.verdict_flips.values) == [1, 2, 0]
    assert list(ds.study.values) == ["a", "b"]
    assert list(ds.study_cases.values) == [2, 1]
    assert list(ds.study_cases_changed.values) == [2, 0]
    assert list(ds.study_verdicts_changed.values) == [2, 0]  # perturbation 2 changes both of a's
    assert list(ds.attrs["verdicts_changed_per_perturbation"]) == [1, 2]
    assert ds.attrs["cases_with_any_change"] == 2


def test_summarize_measures_threshold_shifts_in_brackets():
    ds = _synthetic()
    assert ds.threshold.values == pytest.approx([10.0, 4.0])
    assert ds.threshold_shift.values == pytest.approx([0.10, 0.025])
    assert ds.bracket_width.values == pytest.approx([0.02, 0.04])
    assert ds.shift_in_brackets.values == pytest.approx([5.0, 0.625])
    assert ds.threshold_spread.values == pytest.approx([0.10, 4.0 / 3.9 - 1.0])
    assert ds.attrs["systems_shifted_past_bracket"] == 1
    assert ds.threshold_min.attrs["units"] == "m s-2"


def test_the_command_writes_a_self_describing_dataset(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    code = rounding.main(
        [
            "--config",
            "config/quick.yaml",
            "--studies",
            "ramp_drums",
            "standalone_records",
            "--limit",
            "1",
            "--perturbations",
            "1",
            "--jobs",
            "1",
            "--out",
            str(tmp_path),
        ]
    )
    assert code == 0
    with xr.open_dataset(tmp_path / "rounding.nc") as ds:
        assert ds.sizes["perturbation"] == 2 and ds.sizes["case"] == 1 and ds.sizes["system"] == 1
        for name in ds.variables:
            assert "long_name" in ds[name].attrs, name
            assert "units" in ds[name].attrs or ds[name].dtype.kind in "OSU", (
                name
            )  # CF: no units on text
        assert ds.search_status.values[0, 0] == "bracketed"
    assert "largest shift" in capsys.readouterr().out


def test_the_command_refuses_a_bad_option_before_running(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    code = rounding.main(
        ["--config", "config/quick.yaml", "--perturbations", "0", "--out", str(tmp_path / "new")]
    )
    assert code == 2
    assert "--perturbations" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()
