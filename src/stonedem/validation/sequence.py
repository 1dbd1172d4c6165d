"""Validation of earthquake sequences (issue 48, item 2): ``excitation: {kind: sequence}``.

Three checks under the engine's default contact law (point), each against a closed form or an
exact reference at a stated tolerance, registered in
:data:`stonedem.validation.cases.VALIDATIONS` through :data:`CHECKS`:

| name             | reference                                                   | tolerance  |
|------------------|-------------------------------------------------------------|------------|
| sequence_exact   | two separate runs, the second from the first's end state    | bit for bit|
| sequence_newmark | k u_max after pulse k (Eq. 5.5 and translation invariance)  | 1 %        |
| sequence_rocking | exact rigid block under each one-sine pulse, no residual    | 1 %        |

What is bitwise and what is not (``sequence_exact``): a sequence runs each part as a run of
its own (:func:`stonedem.engine.simulate.simulate_sequence`), so its first part is the single
run of that motion at the same step, sample for sample, and its second part the run started
from the first's end state (``simulate(scene, start=first.end)``), to the last bit: the
rotations, heights, energies, contact counts and running peaks; the horizontal positions to
the last bit once the base offset the first part left is added the same way. A *fresh* run of
the second motion is not the same computation: it starts from the reference pose on unloaded
contact springs (or settles on them through its quiet lead), where the second part starts
from the state the first left, springs loaded and contact memory set. When the first part
leaves no residual the two agree to a tolerance (:data:`FRESH_TOLERANCE`), not bitwise.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.motion.excitation import sequence_offsets
from stonedem.reference import analytic
from stonedem.units import GRAVITY as G
from stonedem.validation.blocks import POINT_CONTACT, block_scene
from stonedem.validation.result import ValidationResult
from stonedem.validation.result import attrs as _attrs

# the rocking block of sequence_exact and sequence_rocking: 0.5 m x 2 m, one-sine pulses
# a_p / (g tan alpha) and omega_p / p below overturning (rigid_one_sine_response: none)
ROCKING_BLOCK = (0.5, 2.0)  # width x height [m]
ROCKING_PULSES = ((2.0, 8.0), (1.3, 5.0), (1.2, 3.0))  # (a_p / (g tan alpha), omega_p / p)
ROCKING_REST = 6.0  # [s] the block is at rest 5-6 s after such a pulse (point law)
# a fresh run of the second pulse against the sequence's second part, when the first leaves
# no residual: they differ by the contact state the first leaves (see the module docstring)
FRESH_TOLERANCE = 0.01
# sliding cases (a_p / g, T_p [s], mu) of sequence_newmark: two identical pulses
NEWMARK_SEQUENCE_CASES = ((0.5, 1.0, 0.3), (0.8, 1.5, 0.5), (0.5, 1.0, 0.1))


def _one_sine(amplitude, ratio, width, height):
    """(pulse mapping, its length [s], block properties) of a one-sine pulse on the block."""
    blk = analytic.rectangle_rocking_properties(width, height, g=G)
    omega_p = ratio * blk.p
    pulse = {
        "kind": "sine_pulse",
        "accel": amplitude * G * math.tan(blk.alpha),
        "frequency": omega_p / (2.0 * math.pi),
    }
    return pulse, 2.0 * math.pi / omega_p, blk


def _rocking_spec(excitation, duration):
    width, height = ROCKING_BLOCK
    return block_scene(
        width,
        height,
        friction=10.0,
        excitation=excitation,
        duration=duration,
        base_width=6.0,
        contact=POINT_CONTACT,
    )


def _max_abs_difference(a, b) -> float:
    """Largest |a - b| (inf for a shape mismatch; NaN in the same places counts as equal)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return math.inf
    same_nan = np.isnan(a) & np.isnan(b)
    if np.any(np.isnan(a) != np.isnan(b)):
        return math.inf
    d = np.abs(np.where(same_nan, 0.0, a - b))
    return float(d.max(initial=0.0))


def sequence_exact(amplitude=2.0, ratio=8.0, rest=ROCKING_REST):
    """Two identical one-sine pulses with a rest vs two separate runs, bit for bit; point law."""
    width, height = ROCKING_BLOCK
    pulse, period, blk = _one_sine(amplitude, ratio, width, height)
    window = period + rest
    seq_scene = scene_from_dict(
        _rocking_spec({"kind": "sequence", "parts": [pulse, pulse], "rest": rest}, 2 * window)
    )
    seq = simulate(seq_scene)
    # the separate runs: the pulse alone over its window, then the same from its end state
    single = scene_from_dict(_rocking_spec(pulse, window))
    first = simulate(single, keep_end=True)
    second = simulate(single, start=first.end)
    fresh = simulate(single)  # a fresh run of the second pulse
    parts = seq.parts
    one = slice(parts["first_sample"][0], parts["last_sample"][0] + 1)
    two = slice(parts["first_sample"][1], parts["last_sample"][1] + 1)
    d0, v0 = sequence_offsets(seq_scene.horizontal)[1]
    local = second.time[1:]
    second_x = second.x[1:] + (d0 + v0 * local)[:, None]
    pairs = {
        "part_1_x": (seq.x[one], first.x),
        "part_1_y": (seq.y[one], first.y),
        "part_1_theta": (seq.theta[one], first.theta),
        "part_1_energy": (seq.energy[one], first.energy),
        "part_1_time": (seq.time[one], first.time),
        "part_1_peak_rocking": (parts["max_rocking"][0], first.max_rocking),
        "part_2_x": (seq.x[two], second_x),
        "part_2_y": (seq.y[two], second.y[1:]),
        "part_2_theta": (seq.theta[two], second.theta[1:]),
        "part_2_energy": (seq.energy[two], second.energy[1:]),
        "part_2_n_contact": (seq.n_contact[two], second.n_contact[1:]),
        "part_2_peak_rocking": (parts["max_rocking"][1], second.max_rocking),
        "part_2_peak_theta": (seq.peak_theta, np.maximum(first.peak_theta, second.peak_theta)),
    }
    names = list(pairs)
    diffs = np.array([_max_abs_difference(*pairs[n]) for n in names])
    bitwise = float(diffs.max())
    residual = float(abs(first.theta[-1, 1]))
    fresh_error = parts["max_rocking"][1] / fresh.max_rocking - 1.0
    no_residual = residual <= 1e-4 * blk.alpha
    passed = bitwise == 0.0 and no_residual and abs(fresh_error) <= FRESH_TOLERANCE
    ds = xr.Dataset(
        {
            "max_abs_difference": (
                "compared",
                diffs,
                _attrs("1", "largest |sequence - separate runs| (SI units of the quantity)"),
            ),
            "theta_sequence": (
                "time",
                seq.theta[:, 1],
                _attrs("rad", "block rotation, sequence of two pulses"),
            ),
            "theta_separate": (
                "time",
                np.concatenate([first.theta[:, 1], second.theta[1:, 1]]),
                _attrs(
                    "rad", "block rotation, two separate runs (the second from the first's end)"
                ),
            ),
            "residual_rotation_part_1": (
                (),
                residual,
                _attrs("rad", "|block rotation| at the end of the first part's rest"),
            ),
            "peak_rocking_part_2": (
                (),
                parts["max_rocking"][1],
                _attrs("rad", "peak rotation in the sequence's second part"),
            ),
            "peak_rocking_fresh": (
                (),
                fresh.max_rocking,
                _attrs("rad", "peak rotation of a fresh single run of the pulse"),
            ),
            "fresh_relative_error": (
                (),
                fresh_error,
                _attrs("1", "second part's peak / fresh single run's peak - 1"),
            ),
        },
        coords={
            "compared": ("compared", np.array(names, dtype=object), _attrs("1", "quantity")),
            "time": ("time", seq.time, _attrs("s", "time")),
        },
        attrs={
            "tolerance": 0.0,
            "tolerance_fresh": FRESH_TOLERANCE,
            "contact_model": "point",
            "amplitude": amplitude,
            "omega_ratio": ratio,
            "rest": rest,
            "rest_units": "s",
        },
    )
    return ValidationResult(
        "sequence_exact",
        ds,
        passed,
        {
            "max_abs_difference": bitwise,
            "residual_rotation": residual,
            "fresh_relative_error": float(fresh_error),
            "tolerance": 0.0,
        },
        error=bitwise,
    )


def sequence_newmark(cases=NEWMARK_SEQUENCE_CASES, rest=None):
    """Residual sliding after each of two rectangular pulses vs k u_max (Eq. 5.5); point law."""
    tol = 0.01
    rows = []
    for ap_g, tp, mu in cases:
        a_p = ap_g * G
        t_stop = tp * a_p / (mu * G)  # the block stops relative to the base (thesis 5.1.3)
        part_rest = (t_stop - tp + 1.0) if rest is None else rest
        pulse = {"kind": "rect_pulse", "accel": a_p, "duration": tp}
        exact = analytic.sequence_pulse_residual_sliding(a_p, tp, mu, 2, g=G)
        window = tp + part_rest
        # the base keeps the pulses' velocity: wide enough to carry the block to the end
        reach = a_p * tp * (2 * window) * 2 + exact[-1]
        spec = block_scene(
            2.0,
            0.5,
            friction=mu,
            excitation={"kind": "sequence", "parts": [pulse, pulse], "rest": part_rest},
            duration=2 * window,
            base_width=2.0 * reach + 10.0,
            contact=POINT_CONTACT,
        )
        scene = scene_from_dict(spec)
        run = simulate(scene)
        d_base, _, _ = scene.horizontal.evaluate(run.time)
        # the block lags the base: it slides backwards relative to it, by u_max a pulse
        rel = -(run.x[:, 1] - run.x[0, 1] - d_base)
        ends = run.parts["last_sample"]
        rows.append((ap_g, tp, mu, part_rest, rel[ends[0]], rel[ends[1]], *exact))
    arr = np.array(rows)
    engine, exact = arr[:, 4:6], arr[:, 6:8]
    err = engine / exact - 1.0
    worst = float(np.abs(err).max())
    ds = xr.Dataset(
        {
            "residual_engine": (
                ("case", "part"),
                engine,
                _attrs("m", "sliding of the block against the pulse at the end of the part's rest"),
            ),
            "residual_exact": (
                ("case", "part"),
                exact,
                _attrs("m", "k u_max after pulse k (Newmark Eq. 5.5, translation invariance)"),
            ),
            "relative_error": (("case", "part"), err, _attrs("1", "engine / exact - 1")),
        },
        coords={
            "case": ("case", np.arange(len(rows)), _attrs("1", "case")),
            "part": ("part", np.arange(2), _attrs("1", "part of the sequence")),
            "a_p_g": ("case", arr[:, 0], _attrs("1", "pulse amplitude / g")),
            "t_p": ("case", arr[:, 1], _attrs("s", "pulse duration")),
            "mu": ("case", arr[:, 2], _attrs("1", "friction coefficient")),
            "rest": ("case", arr[:, 3], _attrs("s", "rest after each pulse")),
        },
        attrs={"tolerance": tol, "contact_model": "point"},
    )
    return ValidationResult(
        "sequence_newmark",
        ds,
        worst <= tol,
        {"max_abs_error": worst, "tolerance": tol},
        error=worst,
    )


def sequence_rocking(pulses=ROCKING_PULSES, rest=ROCKING_REST):
    """Peak rotation in each of two sub-overturning one-sine pulses vs the exact rigid block,
    and no residual rotation between them; point law."""
    tol = 0.01
    width, height = ROCKING_BLOCK
    r = analytic.housner_restitution(width, height)  # the point law's landing is Housner's
    rows = []
    for amplitude, ratio in pulses:
        pulse, period, blk = _one_sine(amplitude, ratio, width, height)
        window = period + rest
        spec = _rocking_spec(
            {"kind": "sequence", "parts": [pulse, pulse], "rest": rest}, 2 * window
        )
        run = simulate(scene_from_dict(spec))
        ref = analytic.rigid_one_sine_response(
            pulse["accel"], ratio * blk.p, width, height, r, g=G, early_stop=False, free_time=rest
        )
        peaks = run.parts["max_rocking"] / blk.alpha
        residual = np.abs(run.theta[run.parts["last_sample"], 1]) / blk.alpha
        rows.append((amplitude, ratio, *peaks, ref.peak, *residual))
    arr = np.array(rows)
    err = arr[:, 2:4] / arr[:, 4:5] - 1.0
    # no residual: the rotation left after a rest, against the tolerance on the peak
    residual_error = arr[:, 5:7] / arr[:, 4:5]
    worst = float(max(np.abs(err).max(), residual_error.max()))
    ds = xr.Dataset(
        {
            "peak_engine": (
                ("case", "part"),
                arr[:, 2:4],
                _attrs("1", "max |theta| / alpha in the part, engine"),
            ),
            "peak_rigid": (
                "case",
                arr[:, 4],
                _attrs("1", "max |theta| / alpha, exact rigid block, same restitution"),
            ),
            "relative_error": (("case", "part"), err, _attrs("1", "engine / rigid - 1")),
            "residual_rotation": (
                ("case", "part"),
                arr[:, 5:7],
                _attrs("1", "|theta| / alpha at the end of the part's rest (rigid: 0)"),
            ),
        },
        coords={
            "case": ("case", np.arange(len(rows)), _attrs("1", "case")),
            "part": ("part", np.arange(2), _attrs("1", "part of the sequence")),
            "amplitude": ("case", arr[:, 0], _attrs("1", "a_p / (g tan alpha)")),
            "omega_ratio": ("case", arr[:, 1], _attrs("1", "omega_p / p")),
        },
        attrs={
            "tolerance": tol,
            "contact_model": "point",
            "restitution_r": r,
            "rest": rest,
            "rest_units": "s",
        },
    )
    return ValidationResult(
        "sequence_rocking",
        ds,
        worst <= tol,
        {"max_abs_error": worst, "tolerance": tol},
        error=worst,
    )


CHECKS = {
    "sequence_exact": sequence_exact,
    "sequence_newmark": sequence_newmark,
    "sequence_rocking": sequence_rocking,
}


def _draw_exact(ds, ax):
    ax.plot(ds.time, ds.theta_sequence, "-", lw=2, color="0.6", label="sequence")
    ax.plot(ds.time, ds.theta_separate, "--", color="C0", label="two separate runs")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("block rotation [rad]")
    ax.legend(fontsize=8)


def _draw_newmark(ds, ax):
    for k in ds.part.values:
        ax.plot(ds.mu, ds.residual_exact.sel(part=k), "-", label=f"after pulse {k + 1}: k u_max")
        ax.plot(ds.mu, ds.residual_engine.sel(part=k), "o", label=f"after pulse {k + 1}: engine")
    ax.set_xlabel("friction coefficient [1]")
    ax.set_ylabel("residual sliding [m]")
    ax.legend(fontsize=8)


def _draw_rocking(ds, ax):
    x = np.arange(len(ds.case))
    ax.plot(x, ds.peak_rigid, "s", label="exact rigid block")
    for k in ds.part.values:
        ax.plot(x + 0.1 * (k + 1), ds.peak_engine.sel(part=k), "o", label=f"engine, part {k + 1}")
    ax.set_xlabel("case")
    ax.set_ylabel("max |theta| / alpha [1]")
    ax.legend(fontsize=8)


# the check figure of each (stonedem.validation.plots.plot)
DRAWERS = {
    "sequence_exact": _draw_exact,
    "sequence_newmark": _draw_newmark,
    "sequence_rocking": _draw_rocking,
}
