"""Validation of the shear links (issue 48, thesis 8.3) against closed forms, under the engine's
default point contact law.

| name                    | reference                                                  | tolerance |
|-------------------------|------------------------------------------------------------|-----------|
| links_ramp_threshold    | sliding onset under a slow ramp at (mu N + V) / m          | 1 %       |
| links_newmark_pulse     | u_max of Eq. 5.5 with a_y = mu g + V / m                   | 1 %       |
| links_rocking_far_edge  | exact rigid rocking period, and the unlinked block's       | 1 %       |

The link of the first two sits at the block's centre with no clearance, stiff, and breaks
only beyond 1 m of slip: the interface resists sliding with friction and the link's
capacity V in parallel. The third rocks a block about the corner far from a preset link
(titanium, wood) from a tilt small enough that the slip its anchor sees, d (1 - cos theta0),
stays within the clearance: the drum lifts off the link (no pull-out resistance), which
then exerts nothing, so the period to the first impact is the unlinked block's.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from stonedem.engine.links import PRESETS
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import run_checks, simulate
from stonedem.reference import analytic
from stonedem.units import GRAVITY as G
from stonedem.validation.blocks import (
    POINT_CONTACT,
    block_scene,
    contact_attrs,
    first_crossing_time,
)
from stonedem.validation.result import ValidationResult
from stonedem.validation.result import attrs as _attrs

WIDTH, HEIGHT, DENSITY = 2.0, 0.5, 2700.0  # squat sliding block: tan(alpha) = 4, it cannot rock
MASS = WIDTH * HEIGHT * DENSITY  # [kg] per m of depth


def _sliding_link(capacity, stiffness):
    """A link at the block's centre: no clearance, no pull-out, broken only beyond 1 m."""
    return {
        "bodies": ["base", "block"],
        "kind": "custom",
        "at": 0.0,
        "stiffness": stiffness,
        "capacity": capacity,
        "ultimate_slip": 1.0,
        "gap": 0.0,
        "pullout": 0.0,
        "embedment": 0.1,
    }


def _sliding_block(mu, capacity, stiffness, excitation, duration, base_width=8.0):
    spec = block_scene(
        WIDTH,
        HEIGHT,
        density=DENSITY,
        friction=mu,
        excitation=excitation,
        duration=duration,
        every=1e-3,
        base_width=base_width,
        contact=POINT_CONTACT,
    )
    spec["links"] = [_sliding_link(capacity, stiffness)]
    return scene_from_dict(spec)


# (mu, V / (m g)): the onset at a_y / g = 0.5 and 0.6
RAMP_CASES = ((0.3, 0.2), (0.5, 0.1))
RAMP_RATE = 1.0  # [m s-3]
RAMP_STIFFNESS = 5.0e7  # [N m-1]
ONSET_SPEEDS = (2e-3, 2e-2)  # [m s-1] the relative speeds the onset is read from


def ramp_onset(time, rel_velocity, rate, speeds=ONSET_SPEEDS):
    """Onset time [s] of gross sliding under a ramp a = rate t: once the interface yields at
    t0 the block slides rigid-plastically, |v_rel| = rate (t - t0)^2 / 2, so each sample with
    |v_rel| in ``speeds`` gives t0 = t - sqrt(2 |v_rel| / rate); their median (NaN: none)."""
    speed = np.abs(rel_velocity)
    first = np.flatnonzero(speed >= speeds[0])
    if len(first) == 0:
        return math.nan
    rows = np.arange(first[0], len(speed))
    rows = rows[speed[rows] <= speeds[1]]
    return float(np.median(time[rows] - np.sqrt(2.0 * speed[rows] / rate)))


def links_ramp_threshold(cases=RAMP_CASES, rate=RAMP_RATE):
    """Sliding onset of a linked block under a slow ramp vs (mu N + V) / m; point law."""
    tol = 0.01
    rows = []
    for mu, ratio in cases:
        capacity = ratio * MASS * G
        a_ref = float(analytic.linked_yield_acceleration(mu, MASS, capacity, g=G))
        t_ref = a_ref / rate
        scene = _sliding_block(
            mu, capacity, RAMP_STIFFNESS, {"kind": "ramp", "rate": rate}, t_ref + 0.5
        )
        r = simulate(scene)
        _, v_base, _ = scene.horizontal.evaluate(r.time)
        v_block = np.gradient(r.x[:, 1], r.time)
        t0 = ramp_onset(r.time, v_block - v_base, rate)
        checks = run_checks(scene, r)
        rows.append((mu, ratio, capacity, rate * t0, a_ref, float(r.link_peak[0]), checks))
    err = np.array([row[3] / row[4] - 1.0 for row in rows])
    ds = xr.Dataset(
        {
            "onset_engine": (
                "case",
                [row[3] for row in rows],
                _attrs("m s-2", "base acceleration at the onset of gross sliding, engine"),
            ),
            "onset_exact": (
                "case",
                [row[4] for row in rows],
                _attrs("m s-2", "(mu m g + V) / m, friction and link in parallel"),
            ),
            "relative_error": ("case", err, _attrs("1", "engine / closed form - 1")),
            "link_peak_force": (
                "case",
                [row[5] for row in rows],
                _attrs("N", "peak link force, engine (its capacity once yielded)"),
            ),
            "energy_error": (
                "case",
                [row[6]["energy_error"] for row in rows],
                _attrs("1", "energy balance drift / energy moved (run_checks)"),
            ),
        },
        coords={
            "case": ("case", np.arange(len(rows)), _attrs("1", "case")),
            "mu": ("case", [row[0] for row in rows], _attrs("1", "friction coefficient")),
            "capacity_ratio": (
                "case",
                [row[1] for row in rows],
                _attrs("1", "link capacity / block weight V / (m g)"),
            ),
            "capacity": ("case", [row[2] for row in rows], _attrs("N", "link capacity V")),
        },
        attrs={
            "tolerance": tol,
            **contact_attrs(POINT_CONTACT),
            "ramp_rate": rate,
            "ramp_rate_units": "m s-3",
            "mass": MASS,
            "link_stiffness": RAMP_STIFFNESS,
            "onset_definition": "t0 = t - sqrt(2 |v_rel| / rate) over the samples with "
            f"{ONSET_SPEEDS[0]:g} <= |v_rel| <= {ONSET_SPEEDS[1]:g} m/s (median): rigid-plastic "
            "sliding after the onset",
        },
    )
    worst = float(np.nanmax(np.abs(err))) if np.all(np.isfinite(err)) else math.inf
    return ValidationResult(
        "links_ramp_threshold",
        ds,
        worst <= tol,
        {"max_abs_error": worst, "tolerance": tol},
        error=worst,
    )


# (a_p / g, T_p [s], mu, V / (m g))
NEWMARK_CASES = ((0.8, 0.3, 0.2, 0.2), (0.8, 0.3, 0.3, 0.2), (0.5, 0.5, 0.1, 0.2))
NEWMARK_STIFFNESS = 1.0e9  # [N m-1]: elastic slip V / k ~ 5 um, rigid for Eq. 5.5


def links_newmark_pulse(cases=NEWMARK_CASES):
    """Maximum sliding of a linked block under rectangular pulses vs Eq. 5.5 with
    a_y = mu g + V / m; point law."""
    tol = 0.01
    rows = []
    for ap_g, t_p, mu, ratio in cases:
        a_p = ap_g * G
        capacity = ratio * MASS * G
        u_ref = float(analytic.linked_newmark_max_sliding(a_p, t_p, mu, MASS, capacity, g=G))
        a_y = float(analytic.linked_yield_acceleration(mu, MASS, capacity, g=G))
        t_stop = t_p * a_p / a_y
        scene = _sliding_block(
            mu,
            capacity,
            NEWMARK_STIFFNESS,
            {"kind": "rect_pulse", "accel": a_p, "duration": t_p},
            t_stop + 0.3,
            base_width=2.0 * (u_ref + a_p * t_p * (t_stop + 0.3)) + 10.0,
        )
        r = simulate(scene)
        d_base, _, _ = scene.horizontal.evaluate(r.time)
        rel = r.x[:, 1] - r.x[0, 1] - d_base
        checks = run_checks(scene, r)
        rows.append(
            (ap_g, t_p, mu, ratio, float(np.abs(rel).max()), u_ref, float(r.link_slip[0]), checks)
        )
    arr = np.array([row[:7] for row in rows])
    err = arr[:, 4] / arr[:, 5] - 1.0
    ds = xr.Dataset(
        {
            "u_max_engine": ("case", arr[:, 4], _attrs("m", "maximum sliding, engine")),
            "u_max_exact": (
                "case",
                arr[:, 5],
                _attrs("m", "maximum sliding, Eq. 5.5 with a_y = mu g + V / m"),
            ),
            "relative_error": ("case", err, _attrs("1", "engine / closed form - 1")),
            "link_plastic_slip": (
                "case",
                arr[:, 6],
                _attrs("m", "plastic slip of the link at the end, engine"),
            ),
            "energy_error": (
                "case",
                [row[7]["energy_error"] for row in rows],
                _attrs("1", "energy balance drift / energy moved (run_checks)"),
            ),
        },
        coords={
            "case": ("case", np.arange(len(rows)), _attrs("1", "case")),
            "a_p_g": ("case", arr[:, 0], _attrs("1", "pulse amplitude / g")),
            "t_p": ("case", arr[:, 1], _attrs("s", "pulse duration")),
            "mu": ("case", arr[:, 2], _attrs("1", "friction coefficient")),
            "capacity_ratio": ("case", arr[:, 3], _attrs("1", "link capacity / block weight")),
        },
        attrs={
            "tolerance": tol,
            **contact_attrs(POINT_CONTACT),
            "mass": MASS,
            "link_stiffness": NEWMARK_STIFFNESS,
        },
    )
    worst = float(np.abs(err).max())
    return ValidationResult(
        "links_newmark_pulse",
        ds,
        worst <= tol,
        {"max_abs_error": worst, "tolerance": tol},
        error=worst,
    )


# (preset, tilt theta0 [rad], link offset at [m]) of a 0.5 m x 2 m block rocking about its
# right corner: the link's anchor is d = 0.25 - at from it and sees a slip d (1 - cos theta0)
# within the preset's clearance (titanium 0.36 of 0.5 mm, wood 1.4 of 2 mm)
ROCKING_BLOCK = (0.5, 2.0)
ROCKING_CASES = (("titanium", 0.04, -0.2), ("wood", 0.08, -0.2))


def _rocking_period(theta0, link, contact):
    width, height = ROCKING_BLOCK
    quarter = float(analytic.rocking_period_exact(width, height, theta0, g=G)) / 4.0
    spec = block_scene(
        width,
        height,
        tilt=theta0,
        excitation=None,
        duration=1.3 * quarter,
        every=quarter / 2000.0,
        contact=contact,
    )
    if link is not None:
        spec["links"] = [link]
    scene = scene_from_dict(spec)
    r = simulate(scene)
    peak = float(r.link_peak[0]) if link is not None else 0.0
    return 4.0 * first_crossing_time(r.time, r.theta[:, 1]), peak


def links_rocking_far_edge(cases=ROCKING_CASES):
    """Rocking about the corner far from a link: period to the first impact vs the exact rigid
    block and the unlinked block; point law."""
    tol = 0.01
    width, height = ROCKING_BLOCK
    rows = []
    for kind, theta0, at in cases:
        link = {"bodies": ["base", "block"], "kind": kind, "at": at}
        t_exact = float(analytic.rocking_period_exact(width, height, theta0, g=G))
        t_link, peak = _rocking_period(theta0, link, POINT_CONTACT)
        t_free, _ = _rocking_period(theta0, None, POINT_CONTACT)
        d = 0.5 * width - at
        rows.append((theta0, at, t_link, t_free, t_exact, peak, d * (1.0 - math.cos(theta0))))
    arr = np.array(rows)
    err_exact = arr[:, 2] / arr[:, 4] - 1.0
    err_free = arr[:, 2] / arr[:, 3] - 1.0
    ds = xr.Dataset(
        {
            "period_linked": (
                "case",
                arr[:, 2],
                _attrs("s", "rocking period with the link, engine (4 x release to impact)"),
            ),
            "period_unlinked": (
                "case",
                arr[:, 3],
                _attrs("s", "rocking period without the link, engine"),
            ),
            "period_exact": ("case", arr[:, 4], _attrs("s", "exact rigid rocking period")),
            "relative_error": ("case", err_exact, _attrs("1", "linked / exact - 1")),
            "relative_change": ("case", err_free, _attrs("1", "linked / unlinked - 1")),
            "link_peak_force": ("case", arr[:, 5], _attrs("N", "peak link force, engine")),
            "anchor_slip": (
                "case",
                arr[:, 6],
                _attrs("m", "slip the link's anchor sees at the tilt, d (1 - cos theta0)"),
            ),
            "link_gap": (
                "case",
                [PRESETS[kind][3] for kind, _, _ in cases],
                _attrs("m", "the preset's clearance"),
            ),
        },
        coords={
            "case": ("case", [kind for kind, _, _ in cases], _attrs("1", "link preset")),
            "theta0": ("case", arr[:, 0], _attrs("rad", "initial tilt about the right corner")),
            "at": ("case", arr[:, 1], _attrs("m", "link offset from the base's face centre")),
        },
        attrs={
            "tolerance": tol,
            **contact_attrs(POINT_CONTACT),
            "block_width": width,
            "block_height": height,
        },
    )
    worst = float(max(np.abs(err_exact).max(), np.abs(err_free).max()))
    return ValidationResult(
        "links_rocking_far_edge",
        ds,
        worst <= tol,
        {
            "max_abs_error": float(np.abs(err_exact).max()),
            "max_abs_change": float(np.abs(err_free).max()),
            "tolerance": tol,
        },
        error=worst,
    )


CHECKS = {
    "links_ramp_threshold": links_ramp_threshold,
    "links_newmark_pulse": links_newmark_pulse,
    "links_rocking_far_edge": links_rocking_far_edge,
}


def _engine_vs_exact(engine, exact, ylabel):
    def draw(ds, ax):
        x = np.arange(ds.sizes["case"])
        ax.plot(x, ds[exact], "s", mfc="none", ms=10, label=ds[exact].attrs["long_name"])
        ax.plot(x, ds[engine], "o", label=ds[engine].attrs["long_name"])
        ax.set_xticks(x)
        ax.set_xticklabels([_case_label(ds, i) for i in x], fontsize=7)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)

    return draw


def _case_label(ds, i):
    if "mu" in ds.coords:
        return f"mu {float(ds.mu[i]):g}, V/W {float(ds.capacity_ratio[i]):g}"
    return f"{ds.case.values[i]}, theta0 {float(ds.theta0[i]):g}"


def _rocking(ds, ax):
    x = np.arange(ds.sizes["case"])
    ax.plot(x, ds.period_exact, "s", mfc="none", ms=10, label="exact rigid block")
    ax.plot(x, ds.period_unlinked, "x", ms=9, label="engine, no link")
    ax.plot(x, ds.period_linked, "o", label="engine, linked")
    ax.set_xticks(x)
    ax.set_xticklabels([_case_label(ds, i) for i in x], fontsize=7)
    ax.set_ylabel("rocking period T [s]")
    ax.legend(fontsize=7)


# figures of stonedem validate (stonedem.validation.plots.DRAWERS)
DRAWERS = {
    "links_ramp_threshold": _engine_vs_exact(
        "onset_engine", "onset_exact", "base acceleration at sliding onset [m s-2]"
    ),
    "links_newmark_pulse": _engine_vs_exact("u_max_engine", "u_max_exact", "maximum sliding [m]"),
    "links_rocking_far_edge": _rocking,
}
