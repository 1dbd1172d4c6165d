"""The work-precision benchmark in its reduced CI form: a few points per engine and contact
variant, no timing assertions; each error at its point against the measured value with a
stated tolerance."""

import math

import numpy as np
import pytest

from benchmarks import canonical as cn
from benchmarks import ours, pymunk_engine
from benchmarks.work_precision import NO_VARIANT, QUICK, run_sweep, speedup_table
from stonedem.engine.scene import scene_from_dict
from stonedem.io.schema import missing_metadata


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(QUICK, scenes=("a", "b"))


def error(ds, engine, scene, contact=None):
    sel = (ds.engine == engine) & (ds.scene == scene)
    if contact is not None:
        sel = sel & (ds.contact == contact)
    return float(ds.error.where(sel, drop=True).max())


def test_reference_of_free_rocking_agrees_with_an_impulse_engine_at_a_fine_step():
    # pymunk at dt = 1e-4 s: a separate rigid solver; our exact reference must match it to 0.2 %
    w, h = cn.ROCKING_BLOCKS[0]
    traj = pymunk_engine.free_rocking(
        w, h, cn.rocking_theta0(w, h), 1e-4, cn.rocking_duration(w, h)
    )
    t_err, p_err = cn.rocking_errors(traj, w, h)
    assert t_err < 2e-3 and p_err < 2e-3


def test_quick_sweep_is_self_describing_and_has_every_engine_and_variant(sweep):
    assert not missing_metadata(sweep)
    assert set(sweep.engine.values) == {"ours", "pymunk", "mujoco"}
    mine = sweep.engine.values == "ours"
    assert set(sweep.contact.values[mine]) == set(ours.VARIANTS)
    assert set(sweep.contact.values[~mine]) == {NO_VARIANT}
    assert np.all(sweep.wall_per_sim_second > 0)
    assert np.all(sweep.status == 0)  # every run of ours stayed finite


def test_errors_at_the_quick_points(sweep):
    # measured at k_n 1e10, dt 0.5 x limit: (a) area 2.2e-2, point_dashpot 9.7e-3, point
    # 3.8e-3; (b) at k_n 1e8: 2.9e-5 (area, point_dashpot), 3.0e-5 (point)
    assert error(sweep, "ours", "a", "area") < 0.03
    assert error(sweep, "ours", "a", "point_dashpot") < 0.015
    assert error(sweep, "ours", "a", "point") < 0.006
    # the plastic landing needs no calibration and still beats both calibrated dashpots
    assert (
        error(sweep, "ours", "a", "point")
        < error(sweep, "ours", "a", "point_dashpot")
        < error(sweep, "ours", "a", "area")
    )
    for variant in ours.VARIANTS:
        assert error(sweep, "ours", "b", variant) < 1e-4, variant
    # pymunk 2.2e-2 and MuJoCo 2.8e-2 on (a) at dt 1 ms; (b) 1e-14 and 1.5e-4
    assert error(sweep, "pymunk", "a") < 0.03
    assert error(sweep, "mujoco", "a") < 0.04
    assert error(sweep, "pymunk", "b") < 1e-3
    assert error(sweep, "mujoco", "b") < 1e-3


def test_calibrated_damping_meets_housners_first_impact(sweep):
    a = sweep.where((sweep.scene == "a") & (sweep.engine == "ours"), drop=True)
    for variant in ("area", "point_dashpot"):
        run = a.where(a.contact == variant, drop=True)
        reached = run.rocking_restitution.values[0]
        # measured: within 1e-4 of Housner's ratio (0.8313, 0.9206) for both laws at 1e10
        np.testing.assert_allclose(reached, sweep.housner_restitution.values, atol=3e-4)
    zeta = a.rocking_zeta.where(a.contact == "point_dashpot", drop=True).values
    assert np.all((zeta > 0.05) & (zeta <= ours.CALIBRATION_BRACKET[1]))  # measured 0.59, 0.74
    assert np.all(np.isnan(a.rocking_c_n.where(a.contact != "area", drop=True).values))
    assert np.all(
        a.rocking_zeta.where(a.contact == "point", drop=True).values == ours.POINT_DAMPING
    )


def test_speedup_table_compares_at_equal_error(sweep):
    table = speedup_table(sweep)
    assert table.dims == ("contact", "scene", "error_level")
    assert list(table.contact.values) == ["best", *ours.VARIANTS]
    # the best of our variants is the fastest of them at every level: the largest ratio
    per_variant = table.sel(contact=list(ours.VARIANTS)).values
    best = table.sel(contact="best").values
    has = np.isfinite(per_variant).any(axis=0)
    np.testing.assert_allclose(best[has], np.nanmax(per_variant[:, has], axis=0))
    assert np.all(np.isnan(best[~has]))
    # at 1e-4 only ours and pymunk reach (b): a finite ratio
    assert np.isfinite(float(table.sel(contact="best", scene="b", error_level=1e-4)))
    # at 1e-2 on (a) only the point laws reach it, not the area law (2.2e-2)
    assert math.isnan(float(table.sel(contact="area", scene="a", error_level=1e-2)))
    assert sweep.attrs["speedup_b_error_0.0001"] == pytest.approx(
        float(table.sel(contact="best", scene="b", error_level=1e-4))
    )


@pytest.mark.parametrize("variant", ours.VARIANTS)
def test_contact_of_every_variant_is_a_valid_scene(variant):
    w, h = cn.PULSE_BLOCK
    law = scene_from_dict(ours.block_scene(w, h, contact=ours.pulse_contact(variant, 1e8))).contact
    column = scene_from_dict(
        ours.column_scene_spec(1.0, contact=ours.column_contact(variant, 1e9), pga=1.0)
    ).contact
    for contact in (law, column):
        assert contact.model == ("area" if variant == "area" else "point")
        if variant == "area":
            assert contact.c_n > 0
        else:
            assert contact.damping == ours.POINT_DAMPING
            assert contact.impact == ("plastic" if variant == "point" else "none")
    with pytest.raises(ValueError, match="unknown contact variant"):
        ours.pulse_contact("points", 1e8)
