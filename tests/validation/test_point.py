"""The thesis 5.1 validations with the point contact law (stonedem.validation.cases.VALIDATIONS,
name_point)."""

import math

import numpy as np
import pytest

from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic
from stonedem.validation import cases as validation

POINT_VALIDATIONS = [name for name in validation.VALIDATIONS if name.endswith("_point")]
# one_sine_overturning_point (20-40 s) is checked at three pulses by
# tests/validation/test_one_sine.py; its full run is within 0.29 % everywhere (worst: omega_p/p = 8
# on 0.5 x 2 m; README)
FULL_RUNS = [name for name in POINT_VALIDATIONS if name != "one_sine_overturning_point"]
# measured with the engine's defaults (stonedem.validation.cases.POINT_CONTACT: k_n 1e11, dt_safety
# 1.0): the peak of the 1 x 6 m column under MUL009 x 0.6 is 39.9 % above the rigid rocking
# equation (k_n x 0.95: +11.9 %, x 1.05: +11.5 %; dt_safety 0.5: +6.9 %, 0.25: +15.0 %;
# at k_n 1e10 it was -11.6 %): multi-impact rocking near this scale is that sensitive. The
# other four scales are within 5 % at 1.0 (not 0.9 at 0.5 and 0.25: +81 %, +14 %); the
# area law with its calibrated dashpot is within 5 % at this scale only
KNOWN_MISSES = {
    "record_rocking_point": "peak +39.9 % against the rigid rocking equation (tolerance 5 %)"
}


@pytest.mark.parametrize(
    "name",
    [
        pytest.param(n, marks=pytest.mark.xfail(strict=True, reason=KNOWN_MISSES[n]))
        if n in KNOWN_MISSES
        else n
        for n in FULL_RUNS
    ],
)
def test_point_law_validation(name):
    result = validation.VALIDATIONS[name]()
    assert result.name == name
    assert result.dataset.attrs["contact_model"] == "point"
    assert missing_metadata(result.dataset) == []
    assert result.passed and result.error <= result.dataset.attrs["tolerance"], result.summary


def test_every_thesis_5_1_validation_has_a_point_variant():
    assert sorted(POINT_VALIDATIONS) == sorted(f"{name}_point" for name in validation.THESIS_5_1)


def test_point_impact_restitution_is_housners_without_calibration():
    result = validation.VALIDATIONS["impact_restitution_point"]()
    w, h = validation.IMPACT_BLOCK["width"], validation.IMPACT_BLOCK["height"]
    # the mean energy ratio over six impacts, from the peaks (Eq. 5.3), within 0.5 % of Housner's
    assert result.summary["measured_r"] == pytest.approx(
        analytic.housner_restitution(w, h), rel=5e-3
    )


def _ramp_overturning(contact, rate=0.5):
    spec = {
        "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
        "friction": 0.485,
        "contact": contact,
        "excitation": {"kind": "ramp", "rate": rate},
        "solver": {"duration": 7.0},
    }
    run = simulate(scene_from_dict(spec))
    assert run.collapse_sample >= 0
    return rate * run.time[run.collapse_sample]


def _rigid_ramp_overturning(rate=0.5):
    t = np.arange(0.0, 7.0, 1e-4)
    res = analytic.rigid_rocking_response_compiled(
        t, -rate * t, 1.0, 6.0, analytic.housner_restitution(1.0, 6.0)
    )
    over = np.abs(np.nan_to_num(res.theta, nan=10.0)) >= math.atan(1.0 / 6.0)
    return rate * t[np.argmax(over)]


def test_ramp_overturning_of_the_6_x_1_column_is_the_rigid_limit_with_point_contacts():
    rigid = _rigid_ramp_overturning()
    assert rigid == pytest.approx(2.5205, rel=1e-3)
    # measured (rigid 2.52045): point 2.5200 (-0.02 %) at k_n = 1e10 (the study's) and 2.5205
    # (+0.002 %) with the engine's defaults (1e11); area 2.395 (-5.0 %) at k_n = 1e10 N/m2
    assert _ramp_overturning({"model": "point", "k_n": 1e10}) == pytest.approx(rigid, rel=1e-3)
    assert _ramp_overturning({}) == pytest.approx(rigid, rel=1e-3)
    assert _ramp_overturning({"model": "area", "k_n": 1e10, "c_n": 1e4}) < 0.96 * rigid
