"""Validations of leaning columns (issue 48: ``structure.tilt``) against closed forms.

A column standing square on a seat inclined at beta (its base's top face) uplifts under a
horizontal base acceleration a = g tan(alpha - beta) toward its lean and a = g tan(alpha +
beta) away from it, alpha = atan(b/h) (:func:`stonedem.reference.analytic.
leaning_tipping_acceleration`). Each case runs the engine's default point law (friction 2,
nothing slides) under a slow ramp of the base acceleration (0.5 m/s2 per s, the rate of
thesis Fig. 6.10) toward +x: a column leaning toward -x (tilt < 0) then tips toward its lean,
one leaning toward +x away from it.

The measure is the uplift: the ramp's acceleration at the instant the mean rotation of the
column's bodies from their rest pose first exceeds THETA_UPLIFT (1e-3 rad, sampled every
1 ms and interpolated), less the ramp's rise over the time the rigid block takes to turn
that far after uplift (:func:`stonedem.reference.analytic.ramp_uplift_rotation`, the rocking
equation linearised about the toe; theta / alpha' <= 0.01 there). The raw first crossing is
kept beside it (raw_uplift_accel: 8-16 % late at this rate). Measured: the block cases
within 0.04 % of the closed forms, the drums within 0.05 % (the joints' elastic rotation
before uplift adds to the crossing); tolerance 1 %, the README's margin for the rigid limit.

| name                | reference                                             | tolerance |
|---------------------|-------------------------------------------------------|-----------|
| tilt_tipping_toward | block uplift toward its lean, g tan(alpha - beta)     | 1 %       |
| tilt_tipping_away   | block uplift away from its lean, g tan(alpha + beta)  | 1 %       |
| tilt_ramp_drums     | Fig. 6.10's column, 1-8 drums: g tan(alpha_col - beta) | 1 %      |
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from scipy.optimize import brentq

from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.reference import analytic
from stonedem.units import GRAVITY as G
from stonedem.validation.blocks import POINT_CONTACT
from stonedem.validation.result import ValidationResult
from stonedem.validation.result import attrs as _attrs

TOLERANCE = 0.01
RATE = 0.5  # [m s-3] thesis Fig. 6.10's ramp
THETA_UPLIFT = 1e-3  # [rad] mean rotation from rest that marks the uplift
FRICTION = 2.0  # tan(beta) << mu: nothing slides
# (width, height [m], tilt [rad]) of the block cases
BLOCKS = ((1.0, 6.0, 0.02), (1.0, 6.0, 0.05), (1.0, 6.0, 0.1), (0.5, 1.5, 0.05), (0.5, 1.5, 0.2))
RAMP_DRUMS = (1, 2, 4, 8)  # thesis Fig. 6.10 (1-8 drums)
RAMP_TILTS = (0.0, 0.02, 0.05)  # [rad]


def uplift_acceleration(width, height, n_drums, tilt, toward_lean, contact=None):
    """Engine uplift of a column under the ramp: (uplift acceleration [m s-2] with the rigid
    delay taken off, raw first crossing [m s-2], closed form [m s-2])."""
    reference = analytic.leaning_tipping_acceleration(width, height, tilt, toward_lean, g=G)
    lean = -tilt if toward_lean else tilt  # a +x ramp tips the column toward -x
    spec = {
        "structure": {
            "kind": "column",
            "n_drums": n_drums,
            "height": height,
            "width": width,
            "base_width": max(4.0, 4.0 * width),
            "tilt": lean,
        },
        "friction": FRICTION,
        "contact": dict(contact or POINT_CONTACT),
        "excitation": {"kind": "ramp", "rate": RATE},
        "solver": {"duration": reference / RATE + 1.0, "stop_on_collapse": True},
        "output": {"every": 1e-3},
    }
    run = simulate(scene_from_dict(spec))
    free = slice(1, None)  # the base is body 0
    turn = np.abs(run.theta[:, free].mean(axis=1) - run.theta[0, free].mean())
    i = int(np.argmax(turn > THETA_UPLIFT))
    if i == 0:
        return float("nan"), float("nan"), reference
    crossing = float(np.interp(THETA_UPLIFT, turn[i - 1 : i + 1], run.time[i - 1 : i + 1]))
    delay = brentq(
        lambda tau: (
            analytic.ramp_uplift_rotation(tau, width, height, tilt, RATE, toward_lean, g=G)
            - THETA_UPLIFT
        ),
        0.0,
        30.0,
        xtol=1e-9,
    )
    return RATE * (crossing - delay), RATE * crossing, reference


def _result(name, rows, dims, reference_name, contact):
    arr = np.array([r[-3:] for r in rows], dtype=float)
    err = arr[:, 0] / arr[:, 2] - 1.0
    coords = {
        "case": ("case", np.arange(len(rows)), _attrs("1", "case")),
        "width": ("case", [r[0] for r in rows], _attrs("m", "column width")),
        "height": ("case", [r[1] for r in rows], _attrs("m", "column height")),
        "n_drums": ("case", [r[2] for r in rows], _attrs("1", "drums")),
        "tilt": ("case", [r[3] for r in rows], _attrs("rad", "lean of the column and its seat")),
    }
    ds = xr.Dataset(
        {
            "uplift_accel": (
                "case",
                arr[:, 0],
                _attrs("m s-2", "uplift acceleration, engine (rigid ramp delay taken off)"),
            ),
            "raw_uplift_accel": (
                "case",
                arr[:, 1],
                _attrs("m s-2", f"ramp acceleration when the rotation first exceeds {dims}"),
            ),
            "uplift_accel_exact": ("case", arr[:, 2], _attrs("m s-2", reference_name)),
            "relative_error": ("case", err, _attrs("1", "engine / closed form - 1")),
        },
        coords=coords,
        attrs={
            "tolerance": TOLERANCE,
            "ramp_rate": RATE,
            "theta_uplift": THETA_UPLIFT,
            "friction": FRICTION,
            **{f"contact_{k}": v for k, v in (contact or POINT_CONTACT).items()},
        },
    )
    worst = float(np.nanmax(np.abs(err))) if np.isfinite(err).all() else float("inf")
    return ValidationResult(
        name, ds, worst <= TOLERANCE, {"max_abs_error": worst, "tolerance": TOLERANCE}, worst
    )


def tilt_tipping_toward(blocks=BLOCKS, contact=None):
    """Uplift of a block on a seat inclined at beta toward its lean: g tan(alpha - beta)."""
    rows = [(w, h, 1, b, *uplift_acceleration(w, h, 1, b, True, contact)) for w, h, b in blocks]
    return _result("tilt_tipping_toward", rows, "1e-3 rad", "g tan(alpha - beta)", contact)


def tilt_tipping_away(blocks=BLOCKS, contact=None):
    """Uplift of a block on a seat inclined at beta away from its lean: g tan(alpha + beta)."""
    rows = [(w, h, 1, b, *uplift_acceleration(w, h, 1, b, False, contact)) for w, h, b in blocks]
    return _result("tilt_tipping_away", rows, "1e-3 rad", "g tan(alpha + beta)", contact)


def tilt_ramp_drums(drums=RAMP_DRUMS, tilts=RAMP_TILTS, contact=None):
    """Fig. 6.10's ramp on the 6 m x 1 m column of 1-8 drums leaning by beta: uplift toward
    the lean at g tan(alpha_col - beta), alpha_col = atan(1/6) of the whole column."""
    rows = [
        (1.0, 6.0, n, b, *uplift_acceleration(1.0, 6.0, n, b, True, contact))
        for n in drums
        for b in tilts
    ]
    return _result(
        "tilt_ramp_drums", rows, "1e-3 rad", "g tan(alpha_col - beta), whole column", contact
    )


CHECKS = {
    "tilt_tipping_toward": tilt_tipping_toward,
    "tilt_tipping_away": tilt_tipping_away,
    "tilt_ramp_drums": tilt_ramp_drums,
}


def draw(ds, ax):
    """Uplift acceleration against tilt: engine (markers) and closed form (lines)."""
    groups = sorted(
        {
            (float(w), float(h), int(n))
            for w, h, n in zip(ds.width.values, ds.height.values, ds.n_drums.values)
        }
    )
    for w, h, n in groups:
        sel = (ds.width.values == w) & (ds.height.values == h) & (ds.n_drums.values == n)
        tilt = ds.tilt.values[sel]
        label = f"{w:g} x {h:g} m" + (f", {n} drums" if n > 1 or len(groups) > 2 else "")
        (line,) = ax.plot(tilt, ds.uplift_accel_exact.values[sel], "-", lw=1)
        ax.plot(tilt, ds.uplift_accel.values[sel], "o", color=line.get_color(), label=label)
    ax.set_xlabel("tilt beta [rad]")
    ax.set_ylabel("uplift acceleration [m/s2]")
    ax.legend(fontsize=7, title="engine (o), closed form (-)", title_fontsize=7)


DRAWERS = dict.fromkeys(CHECKS, draw)
