"""Scene (a1) of the work-precision benchmark, free rocking to the first impact (issue 45), in
its reduced CI form: our point law and the other engines at one point each; no timing
assertions; each error against the measured value with a stated tolerance."""

import math

import numpy as np
import pytest

from benchmarks import canonical as cn
from benchmarks import ours, pymunk_engine, work_precision
from benchmarks.work_precision import QUICK, run_sweep, speedup_table
from stonedem.io.schema import missing_metadata
from stonedem.reference import analytic


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(QUICK, scenes=("a1",), contacts=("point",))


def row(ds, engine):
    return ds.isel(run=int(np.flatnonzero(ds.engine.values == engine)[0]))


def test_first_impact_time_is_a_quarter_of_the_exact_rigid_period():
    for w, h in cn.ROCKING_BLOCKS:
        quarter = float(analytic.rocking_period_exact(w, h, cn.rocking_theta0(w, h))) / 4.0
        assert cn.first_impact_time(w, h) == pytest.approx(quarter, rel=1e-12)
        assert cn.first_impact_time(w, h) == pytest.approx(
            cn.rocking_reference(w, h)[0][0], rel=1e-12
        )
        assert cn.first_impact_duration(w, h) == pytest.approx(
            cn.FIRST_IMPACT_MARGIN * quarter, rel=1e-12
        )
    # 0.349 s and 0.847 s
    assert [round(cn.first_impact_time(w, h), 3) for w, h in cn.ROCKING_BLOCKS] == [0.349, 0.847]


def test_first_impact_reference_agrees_with_an_impulse_engine_at_a_fine_step():
    # pymunk at dt = 1e-4 s, 1 ms samples: measured 1.9e-4 (0.25 x 1 m) and 7.0e-5 (1 x 6 m)
    for w, h in cn.ROCKING_BLOCKS:
        traj = pymunk_engine.free_rocking(
            w, h, cn.rocking_theta0(w, h), 1e-4, cn.first_impact_duration(w, h)
        )
        assert cn.first_impact_error(traj, w, h) < 3e-4, (w, h)


def test_a_run_without_an_impact_is_an_error_of_one():
    w, h = cn.ROCKING_BLOCKS[0]
    t = np.linspace(0.0, 0.3, 301)
    traj = cn.Trajectory(
        time=t,
        theta=-np.full((t.size, 1), 0.1),
        x=np.zeros((t.size, 1)),
        wall_seconds=1.0,
        steps=300,
    )
    assert cn.first_impact_error(traj, w, h) == 1.0


def test_quick_first_impact_sweep_is_self_describing(sweep):
    assert not missing_metadata(sweep)
    assert set(sweep.scene.values) == {"a1"}
    assert set(sweep.engine.values) == {"ours", "pymunk", "mujoco"}
    assert np.all(sweep.wall_per_sim_second > 0)
    assert np.all(sweep.status == 0)
    np.testing.assert_array_equal(sweep.error.values, sweep.error_impact_time.values)
    assert np.all(np.isnan(sweep.error_peak.values))
    # every engine ran each block for 1.2 x its exact first impact time
    pymunk = row(sweep, "pymunk")
    steps = sum(round(cn.first_impact_duration(w, h) / 1e-3) for w, h in cn.ROCKING_BLOCKS)
    assert int(pymunk.steps) == steps


def test_errors_at_the_quick_points(sweep):
    # measured at dt 1 ms: pymunk 1.46e-3, MuJoCo 1.14e-3 (both on the 0.25 x 1 m block)
    assert float(row(sweep, "pymunk").error) < 2e-3
    assert float(row(sweep, "mujoco").error) < 2e-3
    # ours, point law at k_n 1e10 and dt 0.5 x limit: measured 6.5e-5 (0.25 x 1 m block; the
    # 1 x 6 m block 2e-6), of which ~6e-5 is the 1 ms sampling across the impact's kink
    assert float(row(sweep, "ours").error) < 1.5e-4


def test_first_impact_error_is_against_the_exact_rigid_block(sweep):
    # the row's error is max over the blocks of |t_1 / exact - 1|, t_1 the first sign change of
    # theta of the same run (our engine is deterministic)
    errors = []
    for w, h in cn.ROCKING_BLOCKS:
        contact = ours.rocking_contact("point", w, h, 1e10)
        traj = ours.free_rocking(
            w,
            h,
            cn.rocking_theta0(w, h),
            cn.first_impact_duration(w, h),
            contact=contact,
            dt_ratio=0.5,
        )
        assert traj.time[-1] == pytest.approx(cn.first_impact_duration(w, h), abs=1e-3)
        s = np.sign(traj.theta[:, 0])
        i = int(np.flatnonzero(s[1:] * s[:-1] < 0)[0])
        t0, t1, y0, y1 = traj.time[i], traj.time[i + 1], traj.theta[i, 0], traj.theta[i + 1, 0]
        t_impact = t0 - y0 * (t1 - t0) / (y1 - y0)
        exact = float(analytic.rocking_period_exact(w, h, cn.rocking_theta0(w, h))) / 4.0
        errors.append(abs(t_impact / exact - 1.0))
    assert float(row(sweep, "ours").error) == pytest.approx(max(errors), rel=1e-9)


def test_speedup_table_has_the_first_impact_scene(sweep):
    table = speedup_table(sweep)
    assert list(table.scene.values) == ["a1"]
    assert list(table.contact.values) == ["best", "point"]
    # at 3e-3 every engine's quick point counts; at 1e-3 neither competitor's (1.1e-3, 1.5e-3)
    assert np.isfinite(float(table.sel(contact="best", scene="a1", error_level=3e-3)))
    assert math.isnan(float(table.sel(contact="best", scene="a1", error_level=1e-3)))
    assert sweep.attrs["speedup_a1_error_0.003"] == pytest.approx(
        float(table.sel(contact="best", scene="a1", error_level=3e-3))
    )


def test_quick_command_line_runs_the_first_impact_scene(tmp_path, capsys):
    out, figures = tmp_path / "bench", tmp_path / "figures"
    assert (
        work_precision.main(
            [
                "--quick",
                "--scenes",
                "a1",
                "--contacts",
                "point",
                "--out",
                str(out),
                "--figures",
                str(figures),
            ]
        )
        == 0
    )
    assert (out / "work_precision.nc").is_file()
    assert (figures / "work_precision_a1.png").is_file()
    assert "(a1)" in capsys.readouterr().out
