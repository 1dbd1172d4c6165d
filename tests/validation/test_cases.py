"""Thesis 5.1 validations: the engine against analytic references, each with its tolerance."""

import math

import numpy as np
import pytest

from stonedem.engine.scene import scene_from_dict
from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic
from stonedem.validation import cases as validation
from stonedem.validation import plots as validation_plots

# Each validation runs once per module; the number tests and the figure tests share it.


@pytest.fixture(scope="module")
def housner():
    return validation.housner_period()


@pytest.fixture(scope="module")
def impact():
    return validation.impact_restitution()


@pytest.fixture(scope="module")
def newmark():
    return validation.newmark_pulse()


@pytest.fixture(scope="module")
def sliding():
    return validation.record_sliding()


@pytest.fixture(scope="module")
def rocking():
    return validation.record_rocking(scales=(validation.ROCKING_CASE_SCALE,), c_factors=())


@pytest.fixture(scope="module")
def two():
    return validation.two_blocks()


@pytest.fixture(scope="module")
def energy():
    return validation.energy_conservation()


@pytest.fixture(scope="module")
def pena():
    return validation.pena_block()


@pytest.fixture(scope="module")
def results(housner, impact, newmark, sliding, rocking, two, energy, pena):
    return {r.name: r for r in (housner, impact, newmark, sliding, rocking, two, energy, pena)}


def test_housner_free_rocking_period_three_geometries(housner):
    result = housner
    err = np.abs(result.dataset.relative_error.values)
    assert err.shape == (3, 9), "three geometries x theta0/alpha = 0.1 ... 0.9"
    assert err.max() <= 0.01, (
        f"thesis 5.1.1: period vs exact rigid block, worst {err.max():.4f}, tol 1 %"
    )
    # Eq. 5.1 is the slender approximation: closest for the slenderest block
    slender = (
        np.abs(result.dataset.period_eq_5_1 / result.dataset.period_exact - 1).max("ratio").values
    )
    assert slender[2] < slender[0]


def test_impact_energy_loss_calibrated_to_r_085(impact):
    result = impact
    err = np.abs(result.dataset.relative_error.values)
    assert len(err) == 7, "initial peak + six impacts"
    assert err.max() <= 0.02, f"thesis 5.1.2 Eq. 5.3: worst peak error {err.max():.4f}, tol 2 %"
    assert result.dataset.attrs["measured_r"] == pytest.approx(0.85, abs=1e-3)


def test_calibration_function_reaches_other_targets():
    w, h, m = 0.25, 1.0, 503.0
    theta0 = 0.6 * math.atan(w / h)
    c_n = validation.calibrate_restitution(0.9, w, h, m, theta0)
    _, r, _ = validation.measured_restitution(c_n, w, h, m, theta0)
    assert r == pytest.approx(0.9, abs=1e-3), "target restitution -> c_n"


def test_newmark_sliding_under_rectangular_pulses(newmark):
    result = newmark
    err = np.abs(result.dataset.relative_error.values)
    assert set(result.dataset.a_p_g.values) == {0.8, 0.5}, "both pulses of thesis 5.1.3"
    assert err.max() <= 0.01, f"thesis Eq. 5.5: worst u_max error {err.max():.2e}, tol 1 %"


def test_newmark_histories_for_fig_5_8(newmark):
    ds = newmark.dataset
    # the exact history peaks at Eq. 5.5 (a positive pulse drives u negative)
    assert np.allclose(-ds.sliding_exact.min("time"), ds.u_max_eq_5_5, rtol=1e-9)
    # the engine's history holds its u_max and follows the exact one to 1 % of the peak
    assert np.allclose(np.abs(ds.sliding_engine).max("time"), ds.u_max_engine, rtol=1e-3)
    gap = (np.abs(ds.sliding_engine - ds.sliding_exact).max("time") / ds.u_max_eq_5_5).values
    assert gap.max() <= 0.01, f"history error / u_max {gap.max():.2e}"
    assert np.allclose(ds.pi_1, ds.pi_1_eq_5_5, rtol=0.01), "thesis Fig. 5.7: Pi_1 on Eq. 5.5"


def test_sliding_under_northridge_against_exact_rigid_plastic_block(sliding):
    result = sliding
    assert result.summary["max_error_over_peak"] <= 0.02, (
        f"thesis 5.1.4: history error / peak {result.summary['max_error_over_peak']:.4f}, tol 2 %"
    )
    assert abs(result.summary["peak_error"]) <= 0.02
    # the Bouc-Wen form (Eq. 5.6-5.7) is a smoothed rigid-plastic block: same peak to 5 %
    ds = result.dataset
    assert float(np.abs(ds.sliding_bouc_wen).max()) == pytest.approx(
        float(np.abs(ds.sliding_exact).max()), rel=0.05
    )


def test_rocking_of_monolithic_column_under_northridge(rocking):
    result = rocking
    err = result.summary["peak_error"]
    assert abs(err) <= 0.05, (
        f"thesis 5.1.5: peak rotation vs rigid rocking equation {err:+.4f}, tol 5 %"
    )
    assert result.summary["peak_rigid"] < result.dataset.attrs["alpha"], (
        "a case that does not overturn"
    )
    band = (result.summary["rigid_peak_band_low"], result.summary["rigid_peak_band_high"])
    assert band[0] < -0.3 and band[1] > 0.3, (
        f"the dataset carries the rigid peak's band over scale +-1 %: {band}"
    )


def test_a_single_rocking_peak_near_scale_0_6_is_ill_posed():
    """The rigid block's own peak under MUL009 moves by -36 / +34 % when the record scale
    moves by 1 % around 0.6, by -1.3 / +0.8 % around 1.0 (README, Validation): a 5 % check
    of one peak at 0.6 asks more of an engine than the reference itself can give."""
    spec = validation.block_scene(
        1.0,
        6.0,
        excitation={"kind": "record", "file": str(validation.RECORD_NORTHRIDGE), "scale": 1.0},
        duration=1.0,
    )
    t, a = validation._engine_record(scene_from_dict(spec).horizontal)
    r = analytic.housner_restitution(1.0, 6.0)

    def band(scale):
        peak = np.nanmax(
            np.abs(analytic.rigid_rocking_response_compiled(t, scale * a, 1.0, 6.0, r).theta)
        )
        low, high = validation.rigid_peak_band(t, scale * a, 1.0, 6.0, r)
        return low / peak - 1.0, high / peak - 1.0

    low, high = band(0.6)
    assert low == pytest.approx(-0.357, abs=0.01) and high == pytest.approx(0.340, abs=0.01), (
        low,
        high,
    )
    low, high = band(1.0)
    assert low == pytest.approx(-0.013, abs=0.003) and high == pytest.approx(0.008, abs=0.003), (
        low,
        high,
    )


def test_two_blocks_rotation_histories_and_energy_balance(two):
    result = two
    ds = result.dataset
    assert ds.theta_lower.shape[0] == 2 and list(ds.theta0.values) == [0.10, 0.15]
    worst = float(ds.max_abs_balance_error.max())
    assert worst <= 0.01, (
        f"thesis 5.1.6: energy balance error {worst:.4f} of the initial energy, tol 1 %"
    )
    # both blocks rock: released at theta0, they pass through upright
    assert (ds.theta_lower.min("time") < 0).all() and (ds.theta_upper.min("time") < 0).all()


def test_energy_conserved_without_damping_or_slip(energy):
    result = energy
    assert result.summary["final_drift"] <= 0.005, (
        f"10 s of rocking, c_n = 0: drift {result.summary['final_drift']:.5f} of the rocking "
        "energy, tol 0.5 %"
    )


def test_rigid_plastic_reference_matches_eq_5_5():
    t = np.linspace(0.0, 10.0, 100001)
    a = np.where(t < 1.5, 0.8 * 9.81, 0.0)
    u = analytic.rigid_plastic_sliding(t, a, 0.3).u
    assert np.abs(u).max() == pytest.approx(
        analytic.newmark_pulse_max_sliding(0.8 * 9.81, 1.5, 0.3), rel=1e-3
    )


def test_rigid_rocking_reference_free_period():
    w, h = 0.25, 1.0
    alpha = math.atan(w / h)
    t = np.linspace(0, 3, 30001)
    res = analytic.rigid_rocking_response(t, np.zeros_like(t), w, h, 1.0, theta0=0.5 * alpha)
    crossings = res.impact_times
    period = crossings[2] - crossings[0]  # impacts at T/4, 3T/4, 5T/4
    assert period == pytest.approx(analytic.rocking_period_exact(w, h, 0.5 * alpha), rel=1e-5)


def test_pena_block_free_rocking_against_rigid_rocking_equation(pena):
    """Thesis 5.2.1 (Fig. 5.20): r from the engine's first impact, then the rigid rocking
    equation must give every later peak and half-cycle duration (peaks >= theta0 / 5) to 2 %."""
    ds = pena.dataset
    peak_err = np.abs(ds.peak_relative_error.values)
    half_err = np.abs(ds.half_cycle_relative_error.values)
    assert len(peak_err) >= 10 and len(half_err) >= 9, "ten half cycles above theta0 / 5"
    assert peak_err.max() <= 0.02, (
        f"peaks vs rigid rocking equation: worst {peak_err.max():.4f}, tol 2 %"
    )
    assert half_err.max() <= 0.02, (
        f"half cycles vs exact period at the peak: worst {half_err.max():.4f}, tol 2 %"
    )
    assert pena.passed and pena.error == pytest.approx(max(peak_err.max(), half_err.max()))
    # the engine at the thesis c_n loses energy at each impact, less than Housner's no-bounce bound
    assert 0.85 < ds.attrs["restitution_r"] < 0.95
    assert ds.peak_engine[0] == pytest.approx(validation.PENA_BLOCK["theta0"], rel=1e-6)


def test_pena_damping_sweep_for_fig_5_21(pena):
    ds = pena.dataset
    assert validation.PENA_C_N in ds.c_n.values, "the thesis c_n is in the sweep"
    r = ds.restitution_first_impact.values
    assert np.all(np.diff(r) < 0), f"more contact damping, more loss at impact: {r}"
    # with the thesis's k_n = 1e8 N/m2 the block is not Housner-like: it stops after two impacts
    soft = np.atleast_1d(ds.attrs["restitution_per_impact_k_n_thesis"])
    assert len(soft) <= 3 and soft[0] < 0.7


def test_pena_check_fails_when_contact_is_too_soft():
    """The check can fail: at k_n = 1e9 the energy ratio falls from impact to impact."""
    result = validation.pena_block(k_n=1e9, c_sweep=())
    assert not result.passed
    assert result.summary["peak_error"] > 0.05


def test_validation_datasets_are_self_describing(results):
    for name, result in results.items():
        assert missing_metadata(result.dataset) == [], name
        assert "tolerance" in result.dataset.attrs and np.isfinite(result.error), name


def test_every_thesis_figure_is_drawn(results, tmp_path):
    assert set(validation_plots.CAPTIONS) == set(validation_plots.THESIS_FIGURES)
    for name, (which, _) in validation_plots.THESIS_FIGURES.items():
        assert name.startswith("thesis_fig_5_") and which in validation.VALIDATIONS
        path = validation_plots.draw_thesis_figure(
            name, results[which].dataset, tmp_path / f"{name}.png"
        )
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000, name
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        f"{n}.png" for n in validation_plots.THESIS_FIGURES
    )


def test_run_all_writes_dataset_figures_and_summary(tmp_path):
    assert validation.run_all(tmp_path, names=["two_blocks"]) == []
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == [
        "summary.csv",
        "thesis_fig_5_15.png",
        "thesis_fig_5_17.png",
        "two_blocks.nc",
        "two_blocks.png",
    ]
    table = validation.summary_table([tmp_path / "two_blocks.nc"]).splitlines()
    assert table[0] == "name,error,tolerance,passed"
    name, error, tol, passed = table[1].split(",")
    assert (name, tol, passed) == ("two_blocks", "0.01", "1") and 0 < float(error) <= 0.01
