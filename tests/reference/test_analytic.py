"""Reference solutions of thesis 5.1 (stonedem.reference.analytic) checked against closed forms and
fine ODE solves."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from stonedem.reference import analytic

G = 9.81
SLENDER = (0.25, 1.0)  # width x height [m], alpha = 0.245 rad


def _alpha(width, height):
    return analytic.rectangle_rocking_properties(width, height).alpha


# --- geometry ----------------------------------------------------------------------------


def test_rectangle_rocking_properties():
    blk = analytic.rectangle_rocking_properties(0.5, 2.0, mass=3.0)
    radius = math.hypot(0.25, 1.0)
    assert blk.alpha == pytest.approx(math.atan(0.25)), f"alpha {blk.alpha} vs atan(b/h), tol 1e-12"
    assert blk.radius == pytest.approx(radius), f"R {blk.radius} vs {radius}, tol 1e-12"
    assert blk.inertia_corner == pytest.approx(4.0 / 3.0 * 3.0 * radius**2), (
        "I_O = 4/3 m R^2, tol 1e-12"
    )
    assert blk.p == pytest.approx(math.sqrt(3.0 * G / (4.0 * radius))), "p = sqrt(3g/4R), tol 1e-12"
    with pytest.raises(ValueError):
        analytic.rectangle_rocking_properties(-1.0, 1.0)


# --- 5.1.1 -------------------------------------------------------------------------------


def test_housner_period_slender_eq51_scalar_and_array():
    w, h = SLENDER
    blk = analytic.rectangle_rocking_properties(w, h)
    ratios = np.array([0.1, 0.5, 0.9])
    periods = analytic.housner_period_slender(w, h, ratios * blk.alpha)
    ref = 4.0 / blk.p * np.arccosh(1.0 / (1.0 - ratios))
    assert periods.shape == (3,)
    np.testing.assert_allclose(periods, ref, rtol=1e-14, err_msg="Eq. 5.1, tol 1e-14")
    single = analytic.housner_period_slender(w, h, -0.5 * blk.alpha)
    assert np.ndim(single) == 0 and single == pytest.approx(ref[1], rel=1e-14), (
        "Eq. 5.1 is even in theta0"
    )
    assert analytic.housner_period_slender(w, h, blk.alpha) == np.inf, (
        "Eq. 5.1 at theta0 = alpha: inf"
    )


@pytest.mark.parametrize("width, height", [(0.25, 1.0), (1.0, 1.0), (1.0, 6.0)])
def test_rocking_period_exact_vs_ode_quarter_period(width, height):
    blk = analytic.rectangle_rocking_properties(width, height)
    ratios = np.array([0.05, 0.5, 0.95])
    periods = analytic.rocking_period_exact(width, height, ratios * blk.alpha)
    assert periods.shape == (3,)

    def reach_zero(t, y):
        return y[0]

    reach_zero.terminal = True
    for theta0, period in zip(ratios * blk.alpha, periods):
        sol = solve_ivp(
            lambda t, y: [y[1], -(blk.p**2) * math.sin(blk.alpha - y[0])],
            (0.0, 100.0),
            [theta0, 0.0],
            method="DOP853",
            events=reach_zero,
            rtol=1e-12,
            atol=1e-14,
        )
        quarter = sol.t_events[0][0]
        assert period == pytest.approx(4.0 * quarter, rel=1e-6), (
            f"exact period {period} vs 4 x ODE quarter period {4 * quarter}, tol 1e-6"
        )


def test_rocking_period_exact_tends_to_eq51_for_slender_blocks():
    ratios = np.array([0.01, 0.3, 0.6, 0.9])
    misfit = {}
    for width in (0.04, 0.02):  # alpha = 0.02, 0.01 rad
        alpha = _alpha(width, 2.0)
        exact = analytic.rocking_period_exact(width, 2.0, ratios * alpha)
        slender = analytic.housner_period_slender(width, 2.0, ratios * alpha)
        misfit[width] = np.abs(exact / slender - 1.0).max()
        assert misfit[width] < alpha**2 / 10.0, f"exact vs Eq. 5.1: {misfit[width]}, tol alpha^2/10"
    ratio = misfit[0.04] / misfit[0.02]
    assert 3.5 < ratio < 4.5, (
        f"exact vs Eq. 5.1 misfit should scale as alpha^2, ratio {ratio}, tol 4 +- 0.5"
    )
    assert analytic.rocking_period_exact(0.25, 1.0, 0.0) == 0.0


# --- 5.1.2 -------------------------------------------------------------------------------


def test_eq53_eq54_and_their_inverse_are_consistent():
    w, h = SLENDER
    alpha = _alpha(w, h)
    theta0, r = 0.6 * alpha, 0.85
    peaks = analytic.rocking_peak_angles_eq53(w, h, theta0, r, 6)
    assert peaks.shape == (7,) and peaks[0] == pytest.approx(theta0, rel=1e-14), "Eq. 5.3 at n = 0"
    assert np.all(np.diff(peaks) < 0.0), "Eq. 5.3 peaks must decrease"
    np.testing.assert_allclose(
        analytic.restitution_from_peaks(w, h, peaks),
        r,
        rtol=1e-12,
        err_msg="inverse of Eq. 5.3, tol 1e-12",
    )
    # Eq. 5.4: a half cycle of amplitude theta_n lasts half the Eq. 5.1 period at theta_n
    half = analytic.rocking_half_periods_eq54(w, h, theta0, r, 6)
    np.testing.assert_allclose(
        half,
        analytic.housner_period_slender(w, h, peaks) / 2.0,
        rtol=1e-12,
        err_msg="Eq. 5.4 vs Eq. 5.1 / 2 at the Eq. 5.3 peaks, tol 1e-12",
    )
    # the exact energy ratio of the Eq. 5.3 peaks is r up to the slender-block approximation
    exact_r = analytic.restitution_from_peaks_exact(w, h, peaks)
    assert np.abs(exact_r - r).max() < alpha**2 / 20.0, (
        f"exact energy ratio {exact_r} vs {r}, tol alpha^2/20"
    )


def test_housner_restitution():
    assert analytic.housner_restitution(1.0, 1.0) == pytest.approx(0.0625, rel=1e-12), (
        "square block: (1 - 3/2 * 1/2)^2, tol 1e-12"
    )
    alpha = _alpha(1.0, 6.0)
    ref = (1.0 - 1.5 * math.sin(alpha) ** 2) ** 2
    assert analytic.housner_restitution(1.0, 6.0) == pytest.approx(ref, rel=1e-14), (
        "Housner r, tol 1e-14"
    )


# --- 5.1.3 -------------------------------------------------------------------------------


def test_newmark_pulse_max_sliding_eq55_vectorised():
    mus = np.array([0.1, 0.5, 0.8, 1.0])
    u = analytic.newmark_pulse_max_sliding(0.8 * G, 1.5, mus)
    ref = 0.8 * G * 1.5**2 / 2.0 * (0.8 / mus - 1.0)
    np.testing.assert_allclose(u[:2], ref[:2], rtol=1e-14, err_msg="Eq. 5.5, tol 1e-14")
    assert np.all(u[2:] == 0.0), f"Eq. 5.5: no sliding when a_p <= mu g, got {u[2:]}"
    assert analytic.newmark_pulse_max_sliding(0.8 * G, 1.5, 0.0) == np.inf


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.5, 0.7])
def test_rigid_plastic_sliding_rectangular_pulse_eq55(mu):
    a_p, t_p = 0.8 * G, 1.5
    ref = analytic.newmark_pulse_max_sliding(a_p, t_p, mu)
    t_end = t_p * a_p / (mu * G) + 1.0
    # (a) a jump: repeated instants; (b) 1 ns linear ramps; (c) 1 ms samples
    jump = analytic.rigid_plastic_sliding(
        [0.0, 0.0, t_p, t_p, t_end], [0.0, a_p, a_p, 0.0, 0.0], mu
    )
    ramp = analytic.rigid_plastic_sliding(
        [0.0, 1e-9, t_p, t_p + 1e-9, t_end], [0.0, a_p, a_p, 0.0, 0.0], mu
    )
    assert np.abs(jump.u).max() == pytest.approx(ref, rel=1e-12), (
        f"Eq. 5.5: {np.abs(jump.u).max()} vs {ref}, tol 1e-12"
    )
    assert np.abs(ramp.u).max() == pytest.approx(ref, rel=1e-6), (
        f"Eq. 5.5: {np.abs(ramp.u).max()} vs {ref}, tol 1e-6"
    )
    assert jump.u[-1] < 0.0 and jump.v[-1] == 0.0, (
        "positive ground pulse drives u negative, block stops"
    )
    # velocity at the end of the pulse: -(a_p - mu g) T_p
    assert jump.v[2] == pytest.approx(-(a_p - mu * G) * t_p, rel=1e-12), (
        "v(T_p) closed form, tol 1e-12"
    )
    t = np.linspace(0.0, t_end, 3001)
    sampled = analytic.rigid_plastic_sliding(t, np.where(t <= t_p, a_p, 0.0), mu)
    tol = 2.0 * (t[1] - t[0]) / t_p  # one sample of ramp at each pulse edge
    assert np.abs(sampled.u).max() == pytest.approx(ref, rel=tol), f"Eq. 5.5 sampled, tol {tol}"


def test_rigid_plastic_sliding_stuck_below_friction_and_antisymmetric():
    t = np.linspace(0.0, 2.0, 2001)
    a = 0.29 * G * np.sin(2 * np.pi * 1.5 * t)
    stuck = analytic.rigid_plastic_sliding(t, a, 0.3)
    assert np.all(stuck.u == 0.0) and np.all(stuck.v == 0.0), "|a_g| < mu g: no sliding, exact zero"
    a = 0.6 * G * np.sin(2 * np.pi * 1.5 * t) + 0.1 * G * np.sin(2 * np.pi * 4.0 * t)
    plus = analytic.rigid_plastic_sliding(t, a, 0.3)
    minus = analytic.rigid_plastic_sliding(t, -a, 0.3)
    np.testing.assert_allclose(
        minus.u, -plus.u, rtol=0, atol=1e-14, err_msg="odd in a_g, tol 1e-14 m"
    )
    assert plus.u[100] < 0.0, "a_g > mu g first: u decreases"


def test_rigid_plastic_sliding_sine_vs_hand_solution_and_smoothed_ode():
    mu, amp, omega = 0.2, 0.5 * G, 2 * np.pi * 2.0
    t = np.linspace(0.0, 3.0, 30001)
    a = amp * np.sin(omega * t) * (t <= 2.0)
    res = analytic.rigid_plastic_sliding(t, a, mu)
    # by hand, first excursion: slip at t1 where amp sin(omega t1) = mu g, then
    # v = amp/omega (cos(omega t) - cos(omega t1)) + mu g (t - t1) until v(t2) = 0
    t1 = math.asin(mu * G / amp) / omega

    def v_hand(tt):
        return amp / omega * (math.cos(omega * tt) - math.cos(omega * t1)) + mu * G * (tt - t1)

    def u_hand(tt):
        return (
            amp / omega**2 * (math.sin(omega * tt) - math.sin(omega * t1))
            - amp / omega * math.cos(omega * t1) * (tt - t1)
            + 0.5 * mu * G * (tt - t1) ** 2
        )

    t2 = brentq(v_hand, t1 + 1e-6, 0.5 / 2.0 + 0.2)
    inside = (t > t1) & (t < t2)
    u_ref = np.array([u_hand(x) for x in t[inside]])
    scale = abs(u_hand(t2))
    err = np.abs(res.u[inside] - u_ref).max() / scale
    assert err < 1e-6, f"first excursion vs hand solution: {err}, tol 1e-6 of its size"
    assert np.all(res.u[t <= t1] == 0.0), "stuck before |a_g| = mu g"
    # whole history vs a fine solve_ivp with the friction sign smoothed by tanh(v / 1e-6 m/s)
    eps = 1e-6

    def rhs(tt, y):
        return [y[1], -amp * math.sin(omega * tt) * (tt <= 2.0) - mu * G * math.tanh(y[1] / eps)]

    sol = solve_ivp(
        rhs, (0.0, 3.0), [0.0, 0.0], method="LSODA", t_eval=t, rtol=1e-10, atol=1e-12, max_step=1e-3
    )
    peak = np.abs(res.u).max()
    err = np.abs(sol.y[0] - res.u).max() / peak
    assert err < 1e-3, f"rigid-plastic vs smoothed-sign ODE: {err} of peak, tol 1e-3"


def test_bouc_wen_sliding_close_to_rigid_plastic():
    mu = 0.3
    t = np.linspace(0.0, 3.0, 1501)
    a = (0.7 * G * np.sin(2 * np.pi * 2.0 * t) + 0.2 * G * np.sin(2 * np.pi * 5.0 * t)) * (t <= 2.0)
    exact = analytic.rigid_plastic_sliding(t, a, mu)
    bw = analytic.bouc_wen_sliding(t, a, mu)
    peak = np.abs(exact.u).max()
    err = np.abs(bw.u - exact.u).max() / peak
    assert peak > 0.01 and err < 0.02, (
        f"Eq. 5.6-5.7 vs rigid-plastic: {err} of peak {peak} m, tol 0.02"
    )


def test_compiled_bouc_wen_matches_lsoda():
    """The compiled BDF2 twin (used by record_sliding) against the LSODA reference; 2nd order."""
    mu = 0.3
    t = np.linspace(0.0, 3.0, 1501)
    a = (0.7 * G * np.sin(2 * np.pi * 2.0 * t) + 0.2 * G * np.sin(2 * np.pi * 5.0 * t)) * (t <= 2.0)
    ref = analytic.bouc_wen_sliding(t, a, mu)
    peak = np.abs(ref.u).max()
    u = {
        n: analytic.bouc_wen_sliding_compiled(t, a, mu, steps_per_period=n).u
        for n in (192, 768, 3072)
    }
    error = np.abs(u[768] - ref.u).max() / peak
    assert error < 1e-5, (
        f"history error {error:.2e} of the peak at the default, tol 1e-5 (LSODA's own: 2.6e-6)"
    )
    coarse, fine = (np.abs(u[n] - u[3072]).max() / peak for n in (192, 768))
    assert coarse / fine > 8.0, f"2nd order: 4x the steps, {coarse / fine:.1f}x smaller (16 ideal)"
    with pytest.raises(ValueError, match="steps_per_period"):
        analytic.bouc_wen_sliding_compiled(t, a, mu, steps_per_period=True)
    with pytest.raises(ValueError, match="u_y"):
        analytic.bouc_wen_sliding_compiled(t, a, mu, u_y=0.0)
    with pytest.raises(ValueError, match="mu"):
        analytic.bouc_wen_sliding_compiled(t, a, math.nan)


# --- 5.1.5 -------------------------------------------------------------------------------


def _peaks_from_energy(res, width, height):
    """Peak |theta| of each half cycle, from the free-rocking energy at the sample nearest the
    peak."""
    blk = analytic.rectangle_rocking_properties(width, height)
    th, om = res.theta, res.omega
    j = np.flatnonzero(np.sign(om[:-1]) * np.sign(om[1:]) < 0)  # theta' changes sign: a peak
    # free rocking: cos(alpha - theta_peak) = cos(alpha - |theta|) + theta'^2 / (2 p^2)
    level = np.cos(blk.alpha - np.abs(th[j])) + om[j] ** 2 / (2.0 * blk.p**2)
    return blk.alpha - np.arccos(level)


def test_rigid_rocking_free_period_matches_exact():
    w, h = SLENDER
    alpha = _alpha(w, h)
    t = np.arange(0.0, 6.0, 1e-3)
    res = analytic.rigid_rocking_response(t, np.zeros_like(t), w, h, 1.0, theta0=0.5 * alpha)
    period = analytic.rocking_period_exact(w, h, 0.5 * alpha)
    om, th = res.omega, res.theta
    i = np.flatnonzero((om[:-1] > 0.0) & (om[1:] <= 0.0) & (th[:-1] > 0.0))  # positive peaks
    t_peak = t[i] + om[i] / (om[i] - om[i + 1]) * (t[i + 1] - t[i])
    assert len(t_peak) >= 3
    err = np.abs(np.diff(t_peak) / period - 1.0).max()
    assert err < 1e-5, f"peak-to-peak vs rocking_period_exact {period} s: {err}, tol 1e-5"
    impacts = np.array(res.impact_times)
    np.testing.assert_allclose(
        impacts[2:] - impacts[:-2],
        period,
        rtol=1e-8,
        err_msg="impact-to-impact vs rocking_period_exact, tol 1e-8",
    )
    assert impacts[0] == pytest.approx(period / 4.0, rel=1e-8), "first impact at T/4, tol 1e-8"
    assert not res.overturned and np.nanmax(np.abs(th)) == pytest.approx(0.5 * alpha, rel=1e-9)


def test_rigid_rocking_impact_energy_ratio():
    w, h = SLENDER
    alpha = _alpha(w, h)
    t = np.arange(0.0, 6.0, 1e-3)
    res = analytic.rigid_rocking_response(t, np.zeros_like(t), w, h, 0.85, theta0=0.5 * alpha)
    peaks = _peaks_from_energy(res, w, h)
    assert len(peaks) >= 10
    r = analytic.restitution_from_peaks_exact(w, h, np.r_[0.5 * alpha, peaks])
    np.testing.assert_allclose(
        r, 0.85, rtol=0, atol=1e-6, err_msg="exact energy ratio per impact, tol 1e-6"
    )
    # Eq. 5.4 half periods hold up to the slender-block approximation
    half = analytic.rocking_half_periods_eq54(w, h, 0.5 * alpha, 0.85, 4)[1:]
    measured = np.diff(res.impact_times)[:4]
    err = np.abs(measured / half - 1.0).max()
    assert err < alpha**2 / 5.0, f"half periods vs Eq. 5.4: {err}, tol alpha^2/5"


def test_rigid_rocking_settles_after_chattering():
    w, h = SLENDER
    t = np.arange(0.0, 5.0, 1e-3)
    res = analytic.rigid_rocking_response(t, np.zeros_like(t), w, h, 0.6, theta0=0.5 * _alpha(w, h))
    assert res.impact_times[-1] < 4.0, "impacts accumulate in finite time"
    late = t > res.impact_times[-1]
    assert np.all(res.theta[late] == 0.0) and np.all(res.omega[late] == 0.0), (
        "block at rest after chattering"
    )


def test_rigid_rocking_constant_acceleration_below_uplift_stays_at_rest():
    w, h = SLENDER
    t = np.arange(0.0, 3.0, 1e-3)
    threshold = G * math.tan(_alpha(w, h))
    for sign in (1.0, -1.0):
        res = analytic.rigid_rocking_response(
            t, np.full_like(t, 0.99 * sign * threshold), w, h, 0.85
        )
        assert np.all(res.theta == 0.0) and np.all(res.omega == 0.0), (
            "|a_g| < g tan(alpha): theta = 0"
        )
        assert not res.overturned and res.impact_times == []


def test_rigid_rocking_constant_acceleration_above_uplift_overturns():
    w, h = SLENDER
    t = np.arange(0.0, 3.0, 1e-3)
    res = analytic.rigid_rocking_response(
        t, np.full_like(t, -1.01 * G * math.tan(_alpha(w, h))), w, h, 0.85
    )
    assert res.overturned, "a_g = -1.01 g tan(alpha) held: overturns"
    finite = np.isfinite(res.theta)
    assert np.all(res.theta[finite] >= 0.0), (
        "a_g < 0 tips the block onto its right corner (theta > 0)"
    )
    assert np.isnan(res.theta[-1]) and np.nanmax(res.theta) <= 0.5 * math.pi


def test_rigid_rocking_one_sine_pulse_sign():
    w, h = SLENDER
    alpha = _alpha(w, h)
    f, amp = 2.0, 3.0 * G * math.tan(alpha)
    t = np.arange(0.0, 3.0, 1e-3)
    a = np.where(t <= 1.0 / f, amp * np.sin(2 * np.pi * f * t), 0.0)
    res = analytic.rigid_rocking_response(t, a, w, h, 0.85)
    moving = np.flatnonzero(res.theta != 0.0)
    assert len(moving), "3 g tan(alpha) one-sine pulse must uplift the block"
    t_uplift = math.asin(1.0 / 3.0) / (2 * np.pi * f)  # a_g = g tan(alpha)
    assert t[moving[0] - 1] <= t_uplift < t[moving[0]], "uplift when a_g first exceeds g tan(alpha)"
    assert res.theta[moving[0]] < 0.0, (
        "positive a_g tips the block onto its left corner (theta < 0)"
    )
    mirror = analytic.rigid_rocking_response(t, -a, w, h, 0.85)
    np.testing.assert_allclose(
        mirror.theta,
        -res.theta,
        rtol=0,
        atol=1e-9,
        equal_nan=True,
        err_msg="rocking is odd in a_g, tol 1e-9 rad",
    )


def test_input_checks():
    with pytest.raises(ValueError):
        analytic.rigid_plastic_sliding([0.0, 1.0, 0.5], [0.0, 1.0, 0.0], 0.3)
    with pytest.raises(ValueError):
        analytic.rigid_rocking_response([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], 0.25, 1.0, 0.85)
    with pytest.raises(ValueError):
        analytic.rigid_rocking_response([0.0, 1.0], [0.0, 0.0], 0.25, 1.0, 1.5)


# --- 5.1.5 one-sine pulse overturning spectrum ---------------------------------------------

ISSUE_BLOCK = (0.5, 2.0)  # width x height [m], alpha = 0.245 rad, p = 2.672 rad/s


def _onset(width, height):
    return G * math.tan(_alpha(width, height))


def _sampled_one_sine(ratio, amplitude, width, height, r, per_period=200, free=14.0):
    """Brute force: the one-sine pulse sampled every T / per_period, rigid_rocking_response."""
    blk = analytic.rectangle_rocking_properties(width, height)
    omega = ratio * blk.p
    period = 2.0 * math.pi / omega
    dt = period / per_period
    # the pulse on [0, T] (a_g(T) = 0 exactly), then free rocking for ``free`` / p
    after = period + dt * np.arange(1, int(free / blk.p / dt))
    t = np.r_[np.linspace(0.0, period, per_period + 1), after]
    a = np.where(t < period, amplitude * _onset(width, height) * np.sin(omega * t), 0.0)
    a[per_period] = 0.0
    # rest_omega 1e-4: chattering to rest is cut short sooner (to keep the test fast); a block
    # at 1e-4 rad/s is 4 orders of magnitude below the p alpha it would need to overturn
    return analytic.rigid_rocking_response(t, a, width, height, r, rest_omega=1e-4)


def test_one_sine_below_uplift_and_mirror_image():
    w, h = ISSUE_BLOCK
    blk = analytic.rectangle_rocking_properties(w, h)
    r = analytic.housner_restitution(w, h)
    for a_p in (_onset(w, h), -0.5 * _onset(w, h)):
        assert analytic.rigid_one_sine_response(a_p, 2.0 * blk.p, w, h, r) == (False, "none", 0.0)
    for ratio, amp in ((2.0, 1.15), (2.0, 1.5), (3.0, 3.6), (3.0, 5.0)):
        up = analytic.rigid_one_sine_response(amp * _onset(w, h), ratio * blk.p, w, h, r)
        down = analytic.rigid_one_sine_response(-amp * _onset(w, h), ratio * blk.p, w, h, r)
        assert up[:2] == down[:2], "mirror image: same verdict"
        assert up.peak == pytest.approx(down.peak, rel=1e-9), "mirror image: same peak, tol 1e-9"


@pytest.mark.parametrize("ratio", [2.0, 5.0])
def test_one_sine_min_overturning_is_scale_free(ratio):
    # same alpha and omega_p / p, block 3 times larger: same a_p / (g tan alpha) (similarity)
    r = 0.85
    small = analytic.rigid_one_sine_min_overturning(ratio, 0.25, 1.0, r, rel_tol=1e-7, step=1.05)
    large = analytic.rigid_one_sine_min_overturning(ratio, 0.75, 3.0, r, rel_tol=1e-7, step=1.05)
    assert small.mode == large.mode == "impact"
    assert large.amplitude == pytest.approx(small.amplitude, rel=1e-6), "scale-free, tol 1e-6"


@pytest.mark.parametrize("ratio, grid", [(2.0, (1.15, 1.220, 1.225)), (4.0, (1.780, 1.785))])
def test_one_sine_min_overturning_vs_sampled_brute_force(ratio, grid):
    # brute force: rigid_rocking_response on the sampled pulse (dt = T/200, a_g error ~1e-4
    # relative) for amplitudes 0.005 apart around the threshold, and one well below it
    w, h = ISSUE_BLOCK
    r = analytic.housner_restitution(w, h)
    thr = analytic.rigid_one_sine_min_overturning(ratio, w, h, r, rel_tol=1e-6)
    brute = [_sampled_one_sine(ratio, amp, w, h, r) for amp in grid]
    falls = [res.overturned for res in brute]
    first = grid[falls.index(True)] if any(falls) else math.inf
    assert falls == [amp >= first for amp in grid], f"brute force overturns from {first}: {falls}"
    assert 0.0 <= first - thr.amplitude <= 0.005, (
        f"threshold {thr.amplitude:.5f} vs smallest overturning grid amplitude {first}, "
        "tol: grid spacing 0.005"
    )
    assert thr.mode == "impact", "overturns after an impact"
    assert all(len(res.impact_times) >= 1 for res in brute if res.overturned), "brute force too"


def test_one_sine_spectrum_safe_band_between_modes():
    # omega_p / p = 3 (issue block): overturning after an impact from 1.400, a safe band
    # (3.549 - 3.655), then overturning without impact; the threshold is the lower edge. In
    # the safe band the block passes the crest |theta| = alpha and the ground pulls it back
    # (peak 1.474 alpha at 3.6; rigid_rocking_response on the sampled pulse agrees)
    w, h = ISSUE_BLOCK
    r = analytic.housner_restitution(w, h)
    spec = analytic.rigid_one_sine_spectrum([3.0], w, h, r, [1.2, 2.0, 3.6, 5.0])
    modes = [analytic.ONE_SINE_MODES[m] for m in spec.mode[0]]
    assert modes == ["none", "impact", "none", "no_impact"], modes
    assert spec.overturned[0].tolist() == [False, True, False, True]
    assert spec.peak[0, 0] < 1.0, spec.peak[0]
    assert spec.peak[0, 2] == pytest.approx(1.4744, abs=1e-3), "past the crest, tol 1e-3"
    thr = analytic.rigid_one_sine_min_overturning(3.0, w, h, r)
    assert thr.mode == "impact" and 1.2 < thr.amplitude < 2.0


@pytest.mark.parametrize("ratio", [1e4, 1e6])
def test_one_sine_min_overturning_short_pulse_limit(ratio):
    # Derived, not published: for omega_p / p -> inf a one-sine pulse leaves the block almost
    # where it was (the ground velocity returns to 0) but, to second order in the small
    # rotation, moving back towards theta = 0 at theta' = 3 pi C^2 tan(alpha) sin^2(alpha)
    # omega_p, C = a_p / (g tan alpha) (p / omega_p)^2. It overturns after that impact iff
    # r theta'^2 / (2 p^2) > 1 - cos(alpha), so a_p / (g tan alpha) -> c* (omega_p / p)^1.5 with
    # c*^4 = 2 (1 - cos alpha) / (9 pi^2 r tan^2(alpha) sin^4(alpha)); the neglected terms
    # (rotation during the pulse) are O((omega_p / p)^-1/2).
    w, h = ISSUE_BLOCK
    alpha = _alpha(w, h)
    r = analytic.housner_restitution(w, h)
    c_star = (
        2.0
        * (1.0 - math.cos(alpha))
        / (9.0 * math.pi**2 * r * math.tan(alpha) ** 2 * math.sin(alpha) ** 4)
    ) ** 0.25
    thr = analytic.rigid_one_sine_min_overturning(ratio, w, h, r, rel_tol=1e-6, step=1.2, cap=1e12)
    q = thr.amplitude / (c_star * ratio**1.5)
    assert thr.mode == "impact"
    assert 0.0 < 1.0 - q < 2.0 / math.sqrt(ratio), f"A / (c* (w/p)^1.5) = {q}, tol 2 (w/p)^-1/2"


def test_one_sine_early_stop_matches_integrating_free_rocking():
    # the energy verdict after the pulse against integrating the free rocking to the end: 20
    # random pulses, and 4 within 0.2 % of the threshold (where the verdict is a knife edge)
    w, h = ISSUE_BLOCK
    blk = analytic.rectangle_rocking_properties(w, h)
    r = analytic.housner_restitution(w, h)
    rng = np.random.default_rng(5)
    ratios = np.r_[rng.uniform(1.0, 8.0, 20), 2.0, 2.0, 5.0, 5.0]
    amps = np.r_[
        np.exp(rng.uniform(0.0, math.log(20.0), 20)),
        1.2233 * np.array([0.998, 1.002]),
        2.8488 * np.array([0.998, 1.002]),
    ]
    signs = np.r_[rng.choice([-1.0, 1.0], 20), 1.0, -1.0, 1.0, -1.0]
    modes = set()
    for ratio, amp, sign in zip(ratios, amps, signs):
        a_p = sign * amp * _onset(w, h)
        fast = analytic.rigid_one_sine_response(a_p, ratio * blk.p, w, h, r)
        full = analytic.rigid_one_sine_response(a_p, ratio * blk.p, w, h, r, early_stop=False)
        assert fast[:2] == full[:2], f"omega_p/p {ratio:.3f}, A {sign * amp:.3f}: {fast} vs {full}"
        assert fast.peak == pytest.approx(full.peak, rel=1e-6), "same peak / alpha, tol 1e-6"
        modes.add(fast.mode)
    assert modes == {"none", "impact", "no_impact"}, f"all three outcomes among the cases: {modes}"
    near = [
        analytic.rigid_one_sine_response(s * a * _onset(w, h), x * blk.p, w, h, r).overturned
        for x, a, s in zip(ratios[20:], amps[20:], signs[20:])
    ]
    assert near == [False, True, False, True], "either side of the thresholds of the table"


def _overturn_instant(t, theta):
    """Instant |theta| reaches pi/2: a parabola through the last three finite samples."""
    k = np.flatnonzero(np.isfinite(theta))[-1]
    c2, c1, c0 = np.polyfit(t[k - 2 : k + 1] - t[k], np.abs(theta[k - 2 : k + 1]), 2)
    roots = np.roots([c2, c1, c0 - 0.5 * math.pi])
    roots = roots[np.isreal(roots)].real
    return t[k] + roots[roots > 0.0].min()


# reference accuracy (rigid_rocking_response: DOP853, rtol 1e-10, atol 1e-12) on MUL009, 1 x 6 m,
# measured against the compiled twin at 64 substeps (itself within 2e-9 rad and 1e-9 s of DOP853 at
# rtol 1e-13), the reference re-run at 0.7-1.4 x its rtol (a step sequence other rounding could
# give): theta off by up to 8.6e-7 rad (scale 1), impact instants by up to 3.7e-6 s, the peak of
# the block that stays up by 1.9e-7 relative; the block that falls (scale 3) rocks on one pivot
# for 4 s after its last impact, past the crest, and the reference's error grows there to 5.5e-6
# rad just before the fall, 3.0e-6 s of its theta' (the instant of overturning: 3.4e-6 s)
@pytest.mark.parametrize("scale", [1.0, 3.0])
def test_compiled_rigid_rocking_matches_the_scipy_integrator(scale):
    """The compiled twin (used by the record_rocking validation) against solve_ivp, Northridge.

    Only properties of the motion: the verdict, the impact instants, theta at every sample, its
    peak if the block stays up, and the instant it falls if it does (the last finite theta of a
    falling block is where the integration stopped, not a peak)."""
    import xarray as xr

    from stonedem.motion.records import RECORDS_DIR

    with xr.open_dataset(RECORDS_DIR / "northridge_1994_mul009.nc") as rec:
        a = scale * rec["acceleration"].values.astype(float)
        t = rec["time"].values.astype(float)
    w, h, r = 1.0, 6.0, analytic.housner_restitution(1.0, 6.0)
    exact = analytic.rigid_rocking_response(t, a, w, h, r)
    fast = analytic.rigid_rocking_response_compiled(t, a, w, h, r)
    assert fast.overturned == exact.overturned == (scale == 3.0), (
        f"scale {scale}: overturned {fast.overturned} vs {exact.overturned}"
    )
    assert len(fast.impact_times) == len(exact.impact_times) > 0, "same number of impacts"
    # reference accuracy: impact instants to 3.7e-6 s
    np.testing.assert_allclose(
        fast.impact_times,
        exact.impact_times,
        rtol=0,
        atol=1e-5,
        err_msg="impact instants within 1e-5 s",
    )
    falling = exact.overturned & (t > exact.impact_times[-1])  # falling: after its last impact
    # reference accuracy: theta to 8.6e-7 rad
    np.testing.assert_allclose(
        fast.theta[~falling],
        exact.theta[~falling],
        rtol=2e-6,
        atol=1e-6,
        err_msg="theta within 1e-6 rad + 2e-6 of itself at every sample",
    )
    if not exact.overturned:
        # reference accuracy: the peak to 1.9e-7 relative
        peak_fast, peak_exact = np.nanmax(np.abs(fast.theta)), np.nanmax(np.abs(exact.theta))
        assert peak_fast == pytest.approx(peak_exact, rel=1e-6), (
            f"peak {peak_fast} vs {peak_exact}, rel 1e-6"
        )
        return
    # reference accuracy: during the fall theta to 3.0e-6 s of its theta', the instant of
    # overturning to 3.4e-6 s, its impact instants to 3.7e-6 s: 1e-5 s for all three
    up = falling & np.isfinite(fast.theta) & np.isfinite(exact.theta)
    gap = np.abs(fast.theta[up] - exact.theta[up]) / (1e-6 + 1e-5 * np.abs(exact.omega[up]))
    assert up.sum() > 100 and gap.max() <= 1.0, (
        f"falling: theta within 1e-6 rad + |theta'| x 1e-5 s, worst {gap.max():.2f} of that"
    )
    fall_fast, fall_exact = _overturn_instant(t, fast.theta), _overturn_instant(t, exact.theta)
    assert fall_exact > exact.impact_times[-1], "falls after its last impact"
    assert fall_fast == pytest.approx(fall_exact, rel=0, abs=1e-5), (
        f"overturns at {fall_fast:.7f} s vs {fall_exact:.7f} s, tol 1e-5 s"
    )


def test_compiled_rigid_rocking_converges_in_its_substeps():
    """Runge-Kutta order 4: 4x the substeps takes the error down ~256x; 16 (the default) is within
    1e-9 rad of 64."""
    t = np.arange(0.0, 6.0, 0.01)
    w, h = SLENDER
    a = 1.5 * G * math.tan(_alpha(w, h)) * np.sin(2.0 * np.pi * 1.3 * t) * np.exp(-0.3 * t)
    runs = {
        m: analytic.rigid_rocking_response_compiled(t, a, w, h, 0.8, substeps=m)
        for m in (4, 16, 64)
    }
    coarse = np.nanmax(np.abs(runs[4].theta - runs[64].theta))
    default = np.nanmax(np.abs(runs[16].theta - runs[64].theta))
    assert default < 1e-9, f"substeps 16 vs 64: {default} rad, tol 1e-9"
    assert coarse > 50.0 * default, (
        f"4 -> 16 substeps cut the error {coarse / default:.0f}x (>= 50x for order 4)"
    )
    for bad in (0, 2.5, True):
        with pytest.raises(ValueError, match="substeps"):
            analytic.rigid_rocking_response_compiled(t, a, w, h, 0.8, substeps=bad)
    with pytest.raises(ValueError, match="finite"):
        analytic.rigid_rocking_response_compiled(t, np.where(t > 1.0, np.nan, a), w, h, 0.8)


def test_compiled_one_sine_matches_the_scipy_integrator():
    """The compiled twin (used by the thresholds and maps) against solve_ivp: 40 random pulses."""
    w, h = ISSUE_BLOCK
    blk = analytic.rectangle_rocking_properties(w, h)
    rng = np.random.default_rng(11)
    modes = set()
    for _ in range(40):
        ratio, amp = rng.uniform(0.7, 9.0), math.exp(rng.uniform(0.0, math.log(25.0)))
        a_p, r = rng.choice([-1.0, 1.0]) * amp * _onset(w, h), rng.uniform(0.4, 1.0)
        ref = analytic.rigid_one_sine_response(a_p, ratio * blk.p, w, h, r)
        fast = analytic.rigid_one_sine_response_compiled(a_p, ratio * blk.p, w, h, r)
        assert fast[:2] == ref[:2], (
            f"omega_p/p {ratio:.3f}, a_p {a_p:.3f}, r {r:.3f}: {fast} vs {ref}"
        )
        assert fast.peak == pytest.approx(ref.peak, abs=1e-8), "same peak / alpha, tol 1e-8"
        modes.add(fast.mode)
    assert modes == {"none", "impact", "no_impact"}, f"all three outcomes among the cases: {modes}"


@pytest.mark.parametrize("ratio", [2.0, 5.0])
def test_compiled_one_sine_threshold_matches_the_scipy_one(ratio):
    w, h = ISSUE_BLOCK
    r = analytic.housner_restitution(w, h)
    ref = analytic.rigid_one_sine_min_overturning(ratio, w, h, r, rel_tol=1e-7, compiled=False)
    fast = analytic.rigid_one_sine_min_overturning(ratio, w, h, r, rel_tol=1e-7)
    assert fast.mode == ref.mode
    assert fast.amplitude == pytest.approx(ref.amplitude, rel=2e-7), "same threshold, tol 2 rel_tol"


def test_compiled_one_sine_converges_at_fourth_order():
    # one impact during the pulse (1.5 g tan alpha at omega_p / p = 2): theta at the end of the
    # pulse from 250, 1000, 4000 steps per pulse against 16000; RK4 cuts the error 4^4 = 256x
    from stonedem.reference.rigid_rocking import PULSE_ENDED, one_sine_pulse

    w, h = ISSUE_BLOCK
    blk = analytic.rectangle_rocking_properties(w, h)
    r = analytic.housner_restitution(w, h)
    runs = [
        one_sine_pulse(
            1.5 * _onset(w, h), 2.0 * blk.p, blk.alpha, blk.p**2, 9.81, r, 1e-6 * blk.p, n
        )
        for n in (250, 1000, 4000, 16000)
    ]
    assert [run[0] for run in runs] == [PULSE_ENDED] * 4 and [run[4] for run in runs] == [1] * 4
    errors = [abs(run[1] - runs[-1][1]) for run in runs[:-1]]
    assert errors[0] / errors[1] > 150.0 and errors[0] < 1e-9, (
        f"theta errors vs 16000 steps: {errors}"
    )


def test_compiled_one_sine_refuses_bad_input():
    w, h = ISSUE_BLOCK
    for kwargs, match in (
        ({"steps": True}, "steps"),
        ({"steps": 0}, "steps"),
        ({"steps": 2.5}, "steps"),
    ):
        with pytest.raises(ValueError, match=match):
            analytic.rigid_one_sine_response_compiled(1.0, 1.0, w, h, 0.8, **kwargs)
    with pytest.raises(ValueError, match="r must be"):
        analytic.rigid_one_sine_response_compiled(1.0, 1.0, w, h, 1.5)
    with pytest.raises(ValueError, match="omega_p"):
        analytic.rigid_one_sine_response_compiled(math.nan, 1.0, w, h, 0.8)


def test_sequence_pulse_residual_sliding_adds_newmark_u_max():
    u = analytic.newmark_pulse_max_sliding(0.5 * G, 1.0, 0.3)
    res = analytic.sequence_pulse_residual_sliding(0.5 * G, 1.0, 0.3, 3)
    assert res.shape == (3,)
    assert np.allclose(res, [u, 2 * u, 3 * u], rtol=0, atol=1e-15)
    # below the sliding threshold nothing accumulates
    assert np.all(analytic.sequence_pulse_residual_sliding(0.2 * G, 1.0, 0.3, 2) == 0.0)


# --- leaning columns (issue 48) ----------------------------------------------------------


def _toe_moment(a, width, height, tilt, toward_lean):
    """Moment [per unit mass] about the toe the block turns on of gravity and the inertial
    force -a (x), the block leaning toward +x by tilt (turned clockwise about its bottom
    centre); positive: it uplifts."""
    c, s = math.cos(tilt), math.sin(tilt)
    # toe toward the lean: bottom right; away: bottom left (upright frame, from the centroid)
    toe = (width / 2 if toward_lean else -width / 2, -height / 2)
    tx, ty = c * toe[0] + s * toe[1], -s * toe[0] + c * toe[1]  # turned clockwise
    # force per unit mass: gravity (0, -g) and the inertial force; a pushes toward the toe's side
    fx = a if toward_lean else -a
    # moment of the force applied at the centroid about the toe: r x F with r = -toe
    moment = (-tx) * (-G) - (-ty) * fx
    return moment if toward_lean else -moment


@pytest.mark.parametrize("tilt", [0.0, 0.01, 0.05, 0.1])
@pytest.mark.parametrize("toward_lean", [True, False])
def test_leaning_tipping_acceleration_balances_moments_about_the_toe(tilt, toward_lean):
    width, height = 1.0, 6.0
    a = analytic.leaning_tipping_acceleration(width, height, tilt, toward_lean, g=G)
    root = brentq(_toe_moment, 0.0, 20.0, args=(width, height, tilt, toward_lean), xtol=1e-14)
    assert a == pytest.approx(root, rel=1e-10)
    level = analytic.leaning_tipping_acceleration(width, height, 0.0, g=G)
    assert level == pytest.approx(G / 6.0, rel=1e-12)
    assert (a <= level) if toward_lean else (a >= level)


def test_leaning_tipping_acceleration_refuses_a_column_that_cannot_stand():
    alpha = math.atan(1.0 / 6.0)
    assert math.isnan(analytic.leaning_tipping_acceleration(1.0, 6.0, alpha + 1e-9))
    out = analytic.leaning_tipping_acceleration(1.0, 6.0, np.array([0.0, 0.02]), toward_lean=False)
    assert out == pytest.approx(G * np.tan(alpha + np.array([0.0, 0.02])), rel=1e-12)


# --- shear links (issue 48) ----------------------------------------------------------------


def test_linked_yield_acceleration_adds_the_link_to_friction():
    a_y = analytic.linked_yield_acceleration(0.3, 2700.0, 5297.4, g=G)
    assert a_y == pytest.approx(0.3 * G + 5297.4 / 2700.0, rel=1e-15)
    assert analytic.linked_yield_acceleration(0.3, 2700.0, 0.0, g=G) == pytest.approx(0.3 * G)


@pytest.mark.parametrize("mu", [0.1, 0.3])
def test_linked_newmark_equals_the_rigid_plastic_block_with_the_added_resistance(mu):
    a_p, t_p, mass, capacity = 0.8 * G, 0.5, 2700.0, 0.2 * G * 2700.0
    u = analytic.linked_newmark_max_sliding(a_p, t_p, mu, mass, capacity, g=G)
    mu_eff = mu + capacity / (mass * G)
    t_end = t_p * a_p / (mu_eff * G) + 1.0
    jump = analytic.rigid_plastic_sliding(
        [0.0, 0.0, t_p, t_p, t_end], [0.0, a_p, a_p, 0.0, 0.0], mu_eff, g=G
    )
    assert u == pytest.approx(np.abs(jump.u).max(), rel=1e-12), "linked Eq. 5.5, tol 1e-12"
    assert analytic.linked_newmark_max_sliding(a_p, t_p, mu, mass, 0.0, g=G) == pytest.approx(
        analytic.newmark_pulse_max_sliding(a_p, t_p, mu, g=G), rel=1e-14
    )
    assert analytic.linked_newmark_max_sliding(0.2 * G, t_p, mu, mass, capacity, g=G) == 0.0
