"""one_sine_overturning: the engine's smallest overturning one-sine pulse vs the exact rigid
block."""

import math

import numpy as np
import pytest

from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic
from stonedem.validation import cases as validation
from stonedem.validation import plots as validation_plots

BLOCK = (0.5, 2.0)
MAP_RATIOS = (2.0, 5.0)
MAP_AMPLITUDES = (1.1, 1.6, 4.0, 20.0)  # each cell away from a mode boundary of the exact map


@pytest.fixture(scope="module")
def point():
    """The point law (Housner's impact), 0.5 x 2 m, omega_p / p = 2 and 3, and a 2 x 4 map."""
    return validation.one_sine_overturning(
        omega_ratios=(2.0, 3.0),
        blocks=(BLOCK,),
        contact=validation.POINT_CONTACT,
        map_ratios=MAP_RATIOS,
        map_amplitudes=MAP_AMPLITUDES,
    )


def test_point_law_threshold_within_1_percent_of_the_exact_rigid_block(point):
    ds = point.dataset
    assert point.name == "one_sine_overturning_point" and ds.attrs["contact_model"] == "point"
    # the same restitution: Housner's r for the reference, and the engine's own within 0.1 %
    r = analytic.housner_restitution(*BLOCK)
    assert float(ds.restitution[0]) == r
    assert float(ds.restitution_engine[0]) == pytest.approx(r, rel=1e-3)
    exact = [analytic.rigid_one_sine_min_overturning(x, *BLOCK, r).amplitude for x in (2.0, 3.0)]
    np.testing.assert_allclose(ds.threshold_exact[0], exact)
    # measured: -0.025 % and -0.087 % (the engine's bracket is 0.1 % wide)
    assert np.all(np.abs(ds.relative_error) <= 0.01), ds.relative_error.values
    assert point.passed and point.error <= ds.attrs["tolerance"] == 0.01
    assert np.all(ds.threshold_engine > 1.0)  # overturning needs uplift: a_p > g tan(alpha)
    assert (ds.mode_engine == ds.mode_exact).all()
    assert [analytic.ONE_SINE_MODES[m] for m in ds.mode_exact.values[0]] == ["impact", "impact"]


def test_dataset_is_self_describing(point):
    ds = point.dataset
    assert missing_metadata(ds) == []
    for name in ("threshold_engine", "threshold_exact", "relative_error"):
        assert ds[name].attrs["units"] == "1"
    for name in ("alpha", "p", "calibrated_c_n"):
        assert ds[name].attrs["units"] not in ("", "1")
    assert {"tolerance", "restitution_reference", "map_block", "map_agreement"} <= set(ds.attrs)


def test_map_codes_are_the_analytic_modes(point):
    ds = point.dataset
    for name in ("map_engine", "map_exact", "mode_engine", "mode_exact"):
        assert ds[name].attrs["flag_meanings"].split() == list(analytic.ONE_SINE_MODES)
        assert list(ds[name].attrs["flag_values"]) == list(range(len(analytic.ONE_SINE_MODES)))
        assert set(np.unique(ds[name])) <= set(range(len(analytic.ONE_SINE_MODES)))
    spectrum = analytic.rigid_one_sine_spectrum(
        MAP_RATIOS, *BLOCK, analytic.housner_restitution(*BLOCK), MAP_AMPLITUDES
    )
    np.testing.assert_array_equal(ds.map_exact, spectrum.mode)
    # every mode occurs, and away from the boundaries the engine agrees cell by cell
    assert set(np.unique(ds.map_exact)) == {0, 1, 2}
    np.testing.assert_array_equal(ds.map_engine, ds.map_exact)
    assert ds.attrs["map_agreement"] == 1.0


def test_figure_is_drawn(point, tmp_path):
    assert {"one_sine_overturning", "one_sine_overturning_point"} <= set(validation.VALIDATIONS)
    assert {"one_sine_overturning", "one_sine_overturning_point"} <= set(validation_plots.DRAWERS)
    path = validation_plots.plot(point, tmp_path / "one_sine.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000


def test_classify_impact_modes_and_the_energy_verdict():
    alpha, p = math.atan(0.25), 2.67
    t = np.linspace(0.0, 2.0, 2001)
    # rocks to one side, changes side (an impact), then falls
    fall_after = np.where(t < 1.0, 0.5 * alpha * np.sin(2 * np.pi * t), -2.0 * (t - 1.0))
    assert validation.one_sine_classify(t, fall_after, alpha, p, 0.5) == (True, "impact", 1)
    assert validation.one_sine_classify(t, 2.0 * t, alpha, p, 0.5) == (True, "no_impact", 0)
    # after the pulse, at rest (energy below the crest): safe, whatever came before
    at_rest = np.where(t < 1.0, 0.5 * alpha * np.sin(2 * np.pi * t), 0.0)
    assert validation.one_sine_classify(t, at_rest, alpha, p, 0.5) == (False, "none", 1)
    # still inside the pulse at the end, or near the crest: undecided
    assert validation.one_sine_classify(t, at_rest, alpha, p, 2.5)[0] is None
    assert validation.one_sine_classify(t, np.full_like(t, alpha), alpha, p, 0.5)[0] is None
    # beyond the crest, moving outwards or too slow to come back: falls
    beyond = np.full_like(t, 1.2 * alpha) + 1e-4 * t
    assert validation.one_sine_classify(t, beyond, alpha, p, 0.5)[0] is True
    assert validation.side_changes([0.0, 1e-4, -1e-4, 0.1, -0.1, 0.1], 1e-3) == 2


def test_hunt_and_bisection_find_a_known_step():
    calls = []

    def overturns(a):
        calls.append(a)
        return a >= 1.237, "impact"

    for guess in (1.0, 1.237, 1.5, 3.0):  # from below, at, above and far above
        amplitude, mode, _ = validation.engine_min_overturning(overturns, guess, rel_tol=1e-4)
        assert (
            amplitude == pytest.approx(1.237, rel=1e-4) and amplitude >= 1.237 and mode == "impact"
        )
    assert validation.engine_min_overturning(lambda a: (False, "none"), 1.2, cap=3.0)[:2] == (
        math.inf,
        "none",
    )


def _overturns_at(factor, block, ratio, contact):
    """(exact rigid block, engine) overturned under factor x the exact threshold pulse."""
    r = analytic.housner_restitution(*block)
    exact = analytic.rigid_one_sine_min_overturning(ratio, *block, r)
    rigid = analytic.rigid_one_sine_response(
        factor * exact.amplitude * analytic.G * block[0] / block[1],
        ratio * analytic.rectangle_rocking_properties(*block).p,
        *block,
        r,
    ).overturned
    engine, _ = validation.one_sine_engine_outcome(
        factor * exact.amplitude, ratio, *block, contact=contact
    )
    return rigid, engine


@pytest.mark.parametrize("block", [BLOCK, (1.0, 6.0)])
def test_default_point_law_at_omega_ratio_8_is_within_1_percent_of_the_exact_threshold(block):
    """The 1 % target at omega_p / p = 8 with the engine's defaults (k_n 1e11, dt_safety 1.0), both
    sides.

    Measured thresholds: +0.29 % (0.5 x 2 m, 10.292 vs 10.263) and +0.16 % (1 x 6 m, 7.942 vs
    7.930), both overturning after an impact as the rigid block does.
    """
    assert _overturns_at(1.01, block, 8.0, validation.POINT_CONTACT) == (True, True)
    assert _overturns_at(0.99, block, 8.0, validation.POINT_CONTACT) == (False, False)


@pytest.mark.xfail(
    strict=True,
    reason=(
        "the study's k_n = 1e10 N/m2, 0.5 x 2 m at omega_p / p = 8: measured +50.3 %: engine 15.42 "
        "(overturning without impact), exact 10.26 (after an impact): under a pulse of ~2.5 g the "
        "compliant pivot leaves the block about 4 % of alpha short of the crest after its "
        "impact, so "
        "it misses the narrow band of overturning after an impact (exact 10.26 - 11.9)"
    ),
)
def test_study_stiffness_at_omega_ratio_8_overturns_within_1_percent_above_the_exact_threshold():
    assert _overturns_at(1.01, BLOCK, 8.0, {**validation.POINT_CONTACT, "k_n": 1.0e10})[1]


@pytest.mark.xfail(
    strict=True,
    reason=(
        "area law (k_n = 1e10 N/m2, c_n calibrated to Housner's r), 0.5 x 2 m at omega_p / p = 2: "
        "measured -6.9 % (engine 1.139, exact 1.223 with the engine's r): the overlap's Winkler "
        "resultant sits inside the corner, so the block uplifts and overturns early"
    ),
)
def test_area_law_threshold_within_1_percent():
    result = validation.one_sine_overturning(omega_ratios=(2.0,), blocks=(BLOCK,), map_block=None)
    assert abs(float(result.dataset.relative_error[0, 0])) <= 0.01
