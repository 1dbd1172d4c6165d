"""Thesis 5.1 validations: the engine against analytic references, each with its tolerance."""

import math

import numpy as np
import pytest

from dem import analytic, validation


def test_housner_free_rocking_period_three_geometries():
    result = validation.housner_period()
    err = np.abs(result.dataset.relative_error.values)
    assert err.shape == (3, 9), "three geometries x theta0/alpha = 0.1 ... 0.9"
    assert err.max() <= 0.01, f"thesis 5.1.1: period vs exact rigid block, worst {err.max():.4f}, tol 1 %"
    # Eq. 5.1 is the slender approximation: closest for the slenderest block
    slender = np.abs(result.dataset.period_eq_5_1 / result.dataset.period_exact - 1).max("ratio").values
    assert slender[2] < slender[0]


def test_impact_energy_loss_calibrated_to_r_085():
    result = validation.impact_restitution()
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


def test_newmark_sliding_under_rectangular_pulses():
    result = validation.newmark_pulse()
    err = np.abs(result.dataset.relative_error.values)
    assert set(result.dataset.a_p_g.values) == {0.8, 0.5}, "both pulses of thesis 5.1.3"
    assert err.max() <= 0.01, f"thesis Eq. 5.5: worst u_max error {err.max():.2e}, tol 1 %"


def test_sliding_under_northridge_against_exact_rigid_plastic_block():
    result = validation.record_sliding()
    assert result.summary["max_error_over_peak"] <= 0.02, \
        f"thesis 5.1.4: history error / peak {result.summary['max_error_over_peak']:.4f}, tol 2 %"
    assert abs(result.summary["peak_error"]) <= 0.02
    # the Bouc-Wen form (Eq. 5.6-5.7) is a smoothed rigid-plastic block: same peak to 5 %
    ds = result.dataset
    assert float(np.abs(ds.sliding_bouc_wen).max()) == pytest.approx(float(np.abs(ds.sliding_exact).max()), rel=0.05)


def test_rocking_of_monolithic_column_under_northridge():
    result = validation.record_rocking(scales=(validation.ROCKING_CASE_SCALE,), c_factors=())
    err = result.summary["peak_error"]
    assert abs(err) <= 0.05, f"thesis 5.1.5: peak rotation vs rigid rocking equation {err:+.4f}, tol 5 %"
    assert result.summary["peak_rigid"] < result.dataset.attrs["alpha"], "a case that does not overturn"


def test_two_blocks_rotation_histories_and_energy_balance():
    result = validation.two_blocks()
    ds = result.dataset
    assert ds.theta_lower.shape[0] == 2 and list(ds.theta0.values) == [0.10, 0.15]
    worst = float(ds.max_abs_balance_error.max())
    assert worst <= 0.01, f"thesis 5.1.6: energy balance error {worst:.4f} of the initial energy, tol 1 %"
    # both blocks rock: released at theta0, they pass through upright
    assert (ds.theta_lower.min("time") < 0).all() and (ds.theta_upper.min("time") < 0).all()


def test_energy_conserved_without_damping_or_slip():
    result = validation.energy_conservation()
    assert result.summary["final_drift"] <= 0.005, \
        f"10 s of rocking, c_n = 0: drift {result.summary['final_drift']:.5f} of the rocking energy, tol 0.5 %"


def test_rigid_plastic_reference_matches_eq_5_5():
    t = np.linspace(0.0, 10.0, 100001)
    a = np.where(t < 1.5, 0.8 * 9.81, 0.0)
    u = analytic.rigid_plastic_sliding(t, a, 0.3).u
    assert np.abs(u).max() == pytest.approx(analytic.newmark_pulse_max_sliding(0.8 * 9.81, 1.5, 0.3), rel=1e-3)


def test_rigid_rocking_reference_free_period():
    w, h = 0.25, 1.0
    alpha = math.atan(w / h)
    t = np.linspace(0, 3, 30001)
    res = analytic.rigid_rocking_response(t, np.zeros_like(t), w, h, 1.0, theta0=0.5 * alpha)
    crossings = res.impact_times
    period = crossings[2] - crossings[0]  # impacts at T/4, 3T/4, 5T/4
    assert period == pytest.approx(analytic.rocking_period_exact(w, h, 0.5 * alpha), rel=1e-5)
