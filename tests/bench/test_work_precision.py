"""The work-precision benchmark in its reduced CI form: a few points per engine, no timing
assertions; each engine's error at its point against the measured value with a stated tolerance."""

import numpy as np
import pytest

from dem.bench import canonical as cn
from dem.bench import pymunk_engine
from dem.bench.work_precision import QUICK, run_sweep, speedup_table
from dem.dataset import missing_metadata


@pytest.fixture(scope="module")
def sweep():
    return run_sweep(QUICK, scenes=("a", "b"))


def error(ds, engine, scene):
    sel = ds.where((ds.engine == engine) & (ds.scene == scene), drop=True)
    return float(sel.error.max())


def test_reference_of_free_rocking_agrees_with_an_impulse_engine_at_a_fine_step():
    # pymunk at dt = 1e-4 s: a separate rigid solver; our exact reference must match it to 0.2 %
    w, h = cn.ROCKING_BLOCKS[0]
    traj = pymunk_engine.free_rocking(w, h, cn.rocking_theta0(w, h), 1e-4, cn.rocking_duration(w, h))
    t_err, p_err = cn.rocking_errors(traj, w, h)
    assert t_err < 2e-3 and p_err < 2e-3


def test_quick_sweep_is_self_describing_and_has_every_engine(sweep):
    assert not missing_metadata(sweep)
    assert set(sweep.engine.values) == {"ours", "pymunk", "mujoco"}
    assert np.all(sweep.wall_per_sim_second > 0)


def test_errors_at_the_quick_points(sweep):
    # measured: ours (a) 2.2e-2 at k_n 1e10, dt 0.5 x limit; (b) 2.9e-5 at k_n 1e8
    assert error(sweep, "ours", "a") < 0.03
    assert error(sweep, "ours", "b") < 1e-4
    # pymunk 2.2e-2 and MuJoCo 2.8e-2 on (a) at dt 1 ms; (b) 1e-14 and 1.5e-4
    assert error(sweep, "pymunk", "a") < 0.03
    assert error(sweep, "mujoco", "a") < 0.04
    assert error(sweep, "pymunk", "b") < 1e-3
    assert error(sweep, "mujoco", "b") < 1e-3


def test_speedup_table_compares_at_equal_error(sweep):
    table = speedup_table(sweep)
    assert table.dims == ("scene", "error_level")
    # at 1e-4 only ours and pymunk reach (b): a finite ratio
    assert np.isfinite(float(table.sel(scene="b", error_level=1e-4)))
