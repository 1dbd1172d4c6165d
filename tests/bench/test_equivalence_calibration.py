"""benchmarks/equivalence_calibration.py: the changes it measures the test's power against are
the changes they claim to be (base motion x 1.02 exactly, friction x 1.01 everywhere), a flips
draw flips exactly three verdicts the baseline never splits, the rates carry exact binomial
intervals, and an earlier draw is reused only when it is that draw."""

import importlib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stonedem.engine.scene import scene_from_dict

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def calibration():
    return importlib.import_module("benchmarks.equivalence_calibration")


def column(excitation, **extra):
    return scene_from_dict(
        {
            "structure": {"kind": "column", "n_drums": 2, "height": 6.0, "width": 1.0},
            "friction": 0.485,
            "excitation": excitation,
            "solver": {"duration": 6.0},
            **extra,
        },
        base_dir=ROOT,
    )


@pytest.mark.parametrize(
    "excitation",
    [
        {"kind": "harmonic", "frequency": 0.5, "amplitude": 0.25},
        {"kind": "ramp", "rate": 0.5},
        {"kind": "sine_pulse", "accel": 3.0, "frequency": 2.0},
        {"kind": "rect_pulse", "accel": 3.0, "duration": 0.4},
        {"kind": "record", "file": "athens_standin_kocaeli_arc000", "pga": 8.0},
    ],
)
def test_the_shift_scales_the_whole_base_motion_by_its_factor(calibration, excitation):
    scene = column(excitation)
    shifted = calibration.changed_scene(scene, {"motion": 1.02})
    t = np.linspace(0.0, 6.0, 601)
    for plain, moved in (
        (scene.horizontal, shifted.horizontal),
        (scene.vertical, shifted.vertical),
    ):
        for a, b in zip(
            plain.evaluate(t), moved.evaluate(t)
        ):  # displacement, velocity, acceleration
            np.testing.assert_allclose(b, 1.02 * a, rtol=1e-14, atol=1e-300)
    assert np.abs(shifted.horizontal.evaluate(t)[2]).max() > 0.1  # not a motion of zeros
    assert shifted.contact == scene.contact and shifted.bodies == scene.bodies


def test_the_friction_change_reaches_every_coefficient(calibration):
    scene = column(
        {"kind": "ramp", "rate": 0.5},
        interface_friction=[{"bodies": ["c0_d0", "c0_d1"], "mu": 0.3}],
    )
    assert scene.pair_friction  # the case this test is about: a pair of its own
    changed = calibration.changed_scene(scene, {"friction": 1.01})
    assert changed.friction == scene.friction * 1.01
    assert changed.pair_friction == {k: v * 1.01 for k, v in scene.pair_friction.items()}
    assert changed.horizontal is scene.horizontal


def test_the_change_hook_wraps_the_runners_member_scene_and_unwraps_it(calibration):
    from stonedem.study import ensemble

    plain = ensemble.member_scene
    scene = column({"kind": "ramp", "rate": 0.5})
    calibration.install_change(calibration.parse_change("motion=1.02"))
    try:
        moved = ensemble.member_scene(scene, 3)
        assert moved.horizontal.params[0] == 0.5 * 1.02
        assert moved.contact.k_n == scene.contact.k_n * (1 - 3 * 2.0**-52)  # the member, too
    finally:
        calibration.install_change({})
    assert ensemble.member_scene is plain
    with pytest.raises(calibration.InputError, match=calibration.CHANGE_VARIABLE):
        calibration.parse_change("gravity=2")


def ensemble_file(collapsed, members):
    collapsed = np.asarray(collapsed, dtype=np.int8)
    return xr.Dataset(
        {"collapsed": (("case", "member"), collapsed)},
        coords={"case": [f"s/c{i}" for i in range(collapsed.shape[0])], "member": members},
    )


def test_a_flips_draw_flips_three_cases_the_baseline_never_splits(calibration):
    baseline = ensemble_file(
        [[1] * 8, [0, 1] * 4, [0] * 8, [1] * 8, [0] * 8, [1, 1, 1, 1, 1, 1, 1, 0]], range(8)
    )
    candidate = ensemble_file(
        [[1] * 4, [0, 1, 1, 0], [0] * 4, [1] * 4, [0] * 4, [1] * 4], range(8, 12)
    )
    for seed in range(20):
        out, names = calibration.flipped(candidate, baseline, seed)
        changed = np.flatnonzero((out.collapsed.values != candidate.collapsed.values).any(axis=1))
        assert len(names) == 3 and [f"s/c{k}" for k in changed] == names
        assert set(changed) <= {0, 2, 3, 4}  # unanimous in the baseline
        for k in changed:  # every member, to the baseline's opposite
            assert (out.collapsed.values[k] == 1 - baseline.collapsed.values[k, 0]).all()
    with pytest.raises(calibration.InputError, match="--baseline"):
        calibration.flipped(candidate.isel(case=[1, 5]), baseline.isel(case=[1, 5]), 0)


def test_the_rates_carry_exact_binomial_intervals(calibration):
    low, high = calibration.binomial_interval(0, 10)
    assert low == 0.0 and high == pytest.approx(0.3085, abs=1e-4)  # 1 - 0.025^(1/10)
    low, high = calibration.binomial_interval(10, 10)
    assert high == 1.0 and low == pytest.approx(0.025**0.1, rel=1e-9)
    low, high = calibration.binomial_interval(7, 10)
    assert low == pytest.approx(0.3475, abs=1e-4) and high == pytest.approx(0.9333, abs=1e-4)


def test_an_earlier_draw_is_reused_only_when_it_is_that_draw(calibration, tmp_path):
    baseline = ensemble_file([[1] * 8], range(8)).assign_attrs(config_digest="abc")
    path = tmp_path / "candidate-null-01.nc"
    ds = ensemble_file([[1] * 4], [24, 25, 26, 27]).assign_attrs(
        calibration_kind="null",
        calibration_draw=1,
        calibration_baseline=calibration.baseline_key(baseline),
    )
    ds.to_netcdf(path)
    assert calibration.draw_members(20, 1) == [24, 25, 26, 27]
    assert calibration.usable_draw(path, "null", 1, [24, 25, 26, 27], baseline)
    assert not calibration.usable_draw(path, "shift", 1, [24, 25, 26, 27], baseline)
    assert not calibration.usable_draw(path, "null", 1, [28, 29, 30, 31], baseline)
    assert not calibration.usable_draw(
        path, "null", 1, [24, 25, 26, 27], baseline.assign_attrs(config_digest="x")
    )
    path.write_bytes(b"half a file")
    assert not calibration.usable_draw(path, "null", 1, [24, 25, 26, 27], baseline)


def synthetic_ensemble(rng, rates, members):
    """Members whose verdicts are independent draws at each case's collapse rate."""
    collapsed = (rng.random((len(rates), len(members))) < np.asarray(rates)[:, None]).astype(
        np.int8
    )
    return ensemble_file(collapsed, members)


def test_resampled_rates_hold_alpha_under_the_null_and_see_a_shift(calibration):
    rng = np.random.default_rng(7)
    rates = np.r_[
        np.linspace(0.2, 0.8, 20), np.zeros(10), np.ones(10)
    ]  # 20 split cases, 20 unanimous
    baseline = synthetic_ensemble(rng, rates, range(20))
    nulls = [synthetic_ensemble(rng, rates, range(20 + 4 * d, 24 + 4 * d)) for d in range(5)]
    shifted = np.clip(rates + 0.5, 0.0, 1.0)
    shifts = [synthetic_ensemble(rng, shifted, range(20 + 4 * d, 24 + 4 * d)) for d in range(3)]
    ds = calibration.resampled_rates(
        baseline, nulls, shifts, resamples=150, n_permutations=1000, seed=1
    )
    rate = dict(zip(ds.estimate.values, ds.resampled_rate.values))
    assert set(rate) == set(calibration.RESAMPLED)
    # alpha 0.005 per statistic: a valid test rejects about 1 % of null picks; 150 picks see
    # 5 or more with probability < 0.02 at 1 %
    assert rate["false_alarm"] <= 4 / 150 and rate["false_alarm_pooled"] <= 4 / 150
    assert rate["power_shift"] >= 0.9 and rate["power_flips"] >= 0.9
    assert dict(zip(ds.estimate.values, ds.resampled_pool.values)) == {
        "false_alarm": 20,
        "false_alarm_pooled": 40,
        "power_shift": 12,
        "power_flips": 20,
    }
    assert ds.resampled_p_v.attrs["units"] == "1" and ds.sizes["resample"] == 150
    # a pool of fewer runs than one candidate gives no estimate of its kind, not a wrong one
    few = calibration.resampled_rates(
        baseline, nulls, shifts[:0], resamples=10, n_permutations=1000, seed=1
    )
    assert "power_shift" not in set(few.estimate.values)
