"""Earthquake sequences (issue 48, item 2): the three checks of stonedem.validation.sequence
against their references at the stated tolerances, the dataset's per-part measures, and the
refusals of a run that cannot hold the sequence."""

import numpy as np
import pytest

from stonedem.engine.run import run_scene
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import preflight, simulate
from stonedem.errors import InputError
from stonedem.io.schema import missing_metadata
from stonedem.validation import cases, sequence


def test_the_checks_are_registered_with_the_validations():
    assert set(sequence.CHECKS) <= set(cases.VALIDATIONS)


def test_sequence_exact_is_bit_for_bit_and_a_fresh_run_within_tolerance():
    result = sequence.sequence_exact()
    ds = result.dataset
    assert (ds.max_abs_difference.values == 0.0).all(), ds.max_abs_difference.to_series()
    assert float(ds.residual_rotation_part_1) < 1e-6  # the first pulse leaves no residual
    assert abs(float(ds.fresh_relative_error)) <= sequence.FRESH_TOLERANCE
    assert result.passed and not missing_metadata(ds)


def test_sequence_newmark_residuals_are_k_u_max_within_1_percent():
    result = sequence.sequence_newmark()
    err = result.dataset.relative_error.values
    assert np.abs(err).max() <= 0.01 and result.passed, err
    assert not missing_metadata(result.dataset)


def test_sequence_rocking_peaks_are_the_rigid_blocks_within_1_percent():
    result = sequence.sequence_rocking()
    ds = result.dataset
    assert np.abs(ds.relative_error.values).max() <= 0.01, ds.relative_error.values
    assert ds.residual_rotation.values.max() <= 0.01
    assert result.passed and not missing_metadata(ds)


def _pulses(accel=4.0, rest=2.0, duration=None, stop=True):
    pulse = {"kind": "rect_pulse", "accel": accel, "duration": 0.5}
    spec = cases.block_scene(
        2.0,
        0.5,
        friction=0.3,
        excitation={"kind": "sequence", "parts": [pulse, pulse], "rest": rest},
        duration=duration or 2 * (0.5 + rest),
        base_width=60.0,
        contact=cases.POINT_CONTACT,
        stop_on_collapse=stop,
    )
    return scene_from_dict(spec)


def test_dataset_marks_each_part_and_reports_it():
    ds = run_scene(_pulses())
    assert ds.sizes["part"] == 2 and not missing_metadata(ds)
    assert ds.part_start.values.tolist() == [0.0, 2.5]
    assert set(np.unique(ds.sequence_part.values)) == {0, 1}
    assert ds.time.values[ds.sequence_part.values == 1][0] > 2.5
    assert (np.diff(ds.time.values) > 0).all()
    first, second = ds.part_residual_total_sliding.values
    assert second == pytest.approx(2 * first, rel=1e-3)
    assert float(ds.residual_total_sliding) == pytest.approx(second, rel=1e-12)
    assert ds.part_max_total_sliding.values[1] >= second
    assert ds.part_collapsed.values.tolist() == [0, 0]
    assert np.isfinite(ds.part_at_rest_from.values).all()  # each rest was carried at rest
    assert ds.attrs["status"] == "completed"
    # the joined histories follow the composite base: no jump at the part boundary
    rel = ds.displacement_relative_to_base.sel(body="block").values
    assert np.abs(np.diff(rel)).max() < 0.05


def test_a_duration_short_of_the_sequence_is_refused():
    with pytest.raises(InputError) as err:
        preflight(_pulses(duration=4.0))
    assert err.value.field == "solver.duration" and ">= 5" in str(err.value)


def test_a_run_started_from_an_end_state_of_other_bodies_is_refused():
    scene = _pulses()
    part = scene_from_dict(
        {
            "structure": {"kind": "column", "n_drums": 2},
            "excitation": {"kind": "rect_pulse", "accel": 1.0, "duration": 0.1},
            "solver": {"duration": 0.2},
        }
    )
    end = simulate(part, keep_end=True).end
    single = scene_from_dict(
        {**scene.spec, "excitation": {"kind": "rect_pulse", "accel": 1.0, "duration": 0.1}}
    )
    with pytest.raises(InputError) as err:
        simulate(single, start=end)
    assert err.value.field == "start"
