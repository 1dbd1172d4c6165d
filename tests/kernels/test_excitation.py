"""Base motion kernel: d, v, a mutually consistent for every kind; table integration exact."""

import numpy as np
import pytest

from stonedem.kernels import excitation as kx

H = 1e-6


NO_TABLE = (np.zeros(1), np.zeros(1), np.zeros(1), 1.0)


def motion(kind, params, t, table=NO_TABLE):
    return np.array(kx.base_motion(t, kind, np.asarray(params, float), *table))


@pytest.mark.parametrize(
    "kind, params",
    [
        (kx.KIND_HARMONIC, [0.25, 2 * np.pi * 0.5, 0, 0]),
        (kx.KIND_RECT_PULSE, [7.848, 1.5, 0, 0]),
        (kx.KIND_SINE_PULSE, [3.0, 2 * np.pi * 2.0, 0.5, 0]),
        (kx.KIND_RAMP, [0.5, 0, 0, 0]),
    ],
)
def test_velocity_and_acceleration_are_derivatives(kind, params):
    for t in (0.1, 0.37, 0.9, 1.2, 2.3):
        d0, v0, a0 = motion(kind, params, t)
        d1, v1, _ = motion(kind, params, t + H)
        dm, vm, _ = motion(kind, params, t - H)
        assert (d1 - dm) / (2 * H) == pytest.approx(v0, abs=1e-6), "v = d'"
        assert (v1 - vm) / (2 * H) == pytest.approx(a0, abs=1e-4), "a = v'"


def test_pulses_are_continuous_at_their_end_and_rest_before_zero():
    for kind, params, end in [
        (kx.KIND_RECT_PULSE, [7.848, 1.5, 0, 0], 1.5),
        (kx.KIND_SINE_PULSE, [3.0, 2 * np.pi * 2.0, 0.5, 0], 0.5),
    ]:
        before = motion(kind, params, end - 1e-12)
        after = motion(kind, params, end + 1e-12)
        assert before[:2] == pytest.approx(after[:2], abs=1e-9), "d and v continuous"
        assert list(motion(kind, params, -0.1)) == [0.0, 0.0, 0.0]
    assert motion(kx.KIND_SINE_PULSE, [3.0, 2 * np.pi * 2.0, 0.5, 0], 0.7)[1] == pytest.approx(
        0.0, abs=1e-12
    )


def test_table_integrates_piecewise_linear_acceleration_exactly():
    from stonedem.motion.records import record_to_table

    t = np.arange(0, 2.0001, 0.01)
    a = np.sin(3 * t) + 0.5 * (t > 1.0)
    table = record_to_table(t, a)
    # compare with a very fine trapezoid integration of the same piecewise-linear signal
    fine = np.linspace(0, 2.0, 200001)
    af = np.interp(fine, t, a)
    vf = np.concatenate([[0], np.cumsum(0.5 * (af[1:] + af[:-1]) * np.diff(fine))])
    df = np.concatenate([[0], np.cumsum(0.5 * (vf[1:] + vf[:-1]) * np.diff(fine))])
    for x in (0.333, 1.0049, 1.777, 2.0):
        d, v, acc = motion(kx.KIND_TABLE, np.zeros(4), x, table)
        i = np.searchsorted(fine, x)
        assert acc == pytest.approx(np.interp(x, t, a), abs=1e-12)
        assert v == pytest.approx(vf[i], abs=1e-8) and d == pytest.approx(df[i], abs=1e-8)
    # past the end: a = 0 and the base coasts
    d, v, acc = motion(kx.KIND_TABLE, np.zeros(4), 3.0, table)
    d_end, v_end, _ = motion(kx.KIND_TABLE, np.zeros(4), 2.0, table)
    assert acc == 0.0 and v == v_end and d == pytest.approx(d_end + v_end, rel=1e-12)
