"""Leaning columns (structure.tilt, issue 48): the engine's uplift under a slow ramp against the
closed forms g tan(alpha -+ beta), under the default point law, at the stated 1 % tolerance."""

import math

import numpy as np
import pytest

from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.errors import InputError
from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic
from stonedem.validation import cases, tilt
from stonedem.validation import plots as validation_plots


@pytest.fixture(scope="module")
def results():
    return {name: check() for name, check in tilt.CHECKS.items()}


@pytest.mark.parametrize("name", list(tilt.CHECKS))
def test_uplift_of_a_leaning_column_is_the_closed_form(results, name):
    result = results[name]
    ds = result.dataset
    assert ds.attrs["tolerance"] == 0.01
    err = ds.uplift_accel.values / ds.uplift_accel_exact.values - 1.0
    # measured: within 0.05 % in every case
    assert np.all(np.abs(err) <= ds.attrs["tolerance"]), err
    assert result.passed and result.error == pytest.approx(np.abs(err).max())
    assert not missing_metadata(ds)


def test_toward_the_lean_falls_and_away_rises_with_tilt(results):
    toward = results["tilt_tipping_toward"].dataset
    away = results["tilt_tipping_away"].dataset
    level = analytic.leaning_tipping_acceleration(toward.width, toward.height, 0.0)
    assert np.all(toward.uplift_accel.values < level) and np.all(away.uplift_accel.values > level)
    drums = results["tilt_ramp_drums"].dataset
    for n in np.unique(drums.n_drums.values):
        accel = drums.uplift_accel.values[drums.n_drums.values == n]
        assert np.all(np.diff(accel) < 0)  # Fig. 6.10's threshold falls as the tilt grows


def test_the_checks_are_registered_and_drawn(results, tmp_path):
    assert set(tilt.CHECKS) <= set(cases.VALIDATIONS)
    for result in results.values():
        assert validation_plots.plot(result, tmp_path / f"{result.name}.png").stat().st_size > 0


def _column(tilt_angle, n_drums=3, **extra):
    return {
        "structure": {"kind": "column", "n_drums": n_drums, "tilt": tilt_angle},
        "friction": 0.6,
        "excitation": {"kind": "none"},
        "solver": {"duration": 0.5},
        **extra,
    }


def test_a_leaning_column_stands_still_and_its_theta_cr_is_toward_the_lean():
    scene = scene_from_dict(_column(0.05))
    base, drums = scene.bodies[0], scene.bodies[1:]
    assert base.driven and base.lean == 0.0 and all(b.lean == 0.05 for b in drums)
    top = max(v[0] for v in drums[-1].vertices)
    assert top == pytest.approx(0.5 * math.cos(0.05) + 6.0 * math.sin(0.05), rel=1e-12)
    run = simulate(scene)
    assert run.collapse_step < 0 and run.onset_step < 0
    assert np.abs(run.theta[:, 1:]).max() < 1e-5  # from the rest pose, not the upright one
    from stonedem.engine.measures import supports

    assert supports(scene) == [-1, 0, 1, 2]
    alpha = math.atan(1.0 / 6.0)
    assert run.arrays.group_theta_cr[0] == pytest.approx(alpha, rel=1e-12)
    assert run.arrays.group_lean[0] == -0.05


@pytest.mark.parametrize(
    "spec, field",
    [
        (_column(0.17), "structure.tilt"),  # past atan(1/6) = 0.165: it cannot stand
        (_column(0.1, friction=0.05), "structure.tilt"),  # tan(0.1) > mu: it slides off
        ({**_column(0.0), "structure": {"kind": "colonnade", "tilt": 0.01}}, "structure.tilt"),
        (_column("steep"), "structure.tilt"),
        (_column(2.0), "structure.tilt"),
    ],
)
def test_meaningless_tilts_are_refused_in_one_line(spec, field):
    with pytest.raises(InputError) as err:
        scene_from_dict(spec)
    assert err.value.field == field and "\n" not in str(err.value)


def test_a_level_column_is_built_as_before():
    level = scene_from_dict(_column(0.0)).bodies
    plain = scene_from_dict({**_column(0.0), "structure": {"kind": "column", "n_drums": 3}}).bodies
    assert all(
        np.array_equal(a.vertices, b.vertices) and a.lean == 0.0 for a, b in zip(level, plain)
    )
