"""Shear-link validations (issue 48): the engine against closed forms, default point law."""

import numpy as np
import pytest

from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic
from stonedem.units import GRAVITY as G
from stonedem.validation import cases, links
from stonedem.validation import plots as validation_plots


@pytest.fixture(scope="module", params=sorted(links.CHECKS))
def result(request):
    return links.CHECKS[request.param]()


def test_every_link_check_is_registered():
    assert set(links.CHECKS) <= set(cases.VALIDATIONS)
    assert set(links.CHECKS) <= set(validation_plots.DRAWERS)


def test_link_check_meets_its_closed_form(result):
    tol = result.dataset.attrs["tolerance"]
    assert tol == 0.01, result.name
    assert result.passed and result.error <= tol, f"{result.name}: {result.summary}"


def test_link_check_dataset_is_self_describing(result, tmp_path):
    assert missing_metadata(result.dataset) == [], result.name
    assert np.isfinite(result.error)
    assert validation_plots.plot(result, tmp_path / f"{result.name}.png").stat().st_size > 0


def test_ramp_threshold_is_friction_plus_link(result):
    if result.name != "links_ramp_threshold":
        pytest.skip("ramp only")
    ds = result.dataset
    exact = analytic.linked_yield_acceleration(ds.mu.values, ds.attrs["mass"], ds.capacity.values)
    np.testing.assert_allclose(ds.onset_exact, exact, rtol=1e-12)
    np.testing.assert_allclose(ds.onset_engine, exact, rtol=0.01, err_msg="onset, tol 1 %")
    # the link carried its capacity once the interface yielded, and the energy balances
    np.testing.assert_allclose(ds.link_peak_force, ds.capacity, rtol=1e-9)
    assert float(ds.energy_error.max()) < 1e-3


def test_newmark_pulse_link_yields_over_the_whole_slide(result):
    if result.name != "links_newmark_pulse":
        pytest.skip("newmark only")
    ds = result.dataset
    # the plastic slip is the sliding but for the elastic slip V / k (~5 um)
    np.testing.assert_allclose(np.abs(ds.link_plastic_slip), ds.u_max_engine, atol=1e-5)
    assert float(ds.energy_error.max()) < 1e-3
    assert np.all(ds.u_max_exact < analytic.newmark_pulse_max_sliding(ds.a_p_g * G, ds.t_p, ds.mu))


def test_rocking_far_from_the_link_is_unchanged(result):
    if result.name != "links_rocking_far_edge":
        pytest.skip("rocking only")
    ds = result.dataset
    assert np.all(ds.anchor_slip < ds.link_gap), "the tilt keeps the anchor within its clearance"
    assert np.all(ds.link_peak_force == 0.0)
    np.testing.assert_allclose(ds.period_linked, ds.period_exact, rtol=0.01)
    np.testing.assert_allclose(ds.period_linked, ds.period_unlinked, rtol=0.01)
