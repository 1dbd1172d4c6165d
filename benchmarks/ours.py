"""The canonical scenes (:mod:`benchmarks.canonical`) in our engine, for a contact law and dt.

Each scene function takes the scene's ``contact:`` mapping (:mod:`stonedem.engine.scene`; e.g.
``{"model": "point", "k_n": 1e10}``), builds the scene dict, runs
:func:`stonedem.engine.simulate.simulate` (the compiled loop, warm cache) and returns a
:class:`Trajectory` in the base's frame; ``wall_seconds`` is the compiled loop's own time
(:attr:`stonedem.engine.simulate.RunResult.wall_seconds`). ``dt = None`` takes the automatic step;
``dt_ratio`` instead asks for that fraction of the stability limit.

The benchmark compares three contact variants (:data:`VARIANTS`); :func:`rocking_contact`,
:func:`pulse_contact` and :func:`column_contact` give each one's mapping for scenes (a),
(b) and (c):

- ``area``: the thesis' overlap-area law (``model: area``). A soft contact has no impact
  law of its own, so for free rocking (a) the normal dashpot c_n is calibrated per block
  and k_n to Housner's first-impact energy ratio by :func:`calibrate_rocking_damping`
  (thesis 5.1.2: on a problem with a known solution); (b) c_n = 0.5 x critical, (c) 0.05 x
  critical of one drum on its bed joint.
- ``point_dashpot``: point contacts at the face ends (``model: point``) without the plastic
  landing (``impact: none``), so restitution again comes from a dashpot: for (a) the
  damping ratio zeta of each contact point is calibrated the same way; (b), (c) zeta = 0.05.
- ``point``: point contacts with Housner's plastic landing (``impact: plastic``) and
  zeta = 0.05 everywhere, the point law's scene defaults; nothing calibrated.
"""

from __future__ import annotations

import math
import warnings
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from benchmarks import canonical as cn
from benchmarks.canonical import Trajectory
from stonedem.engine.laws import LAWS
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import simulate, stability_limit
from stonedem.engine.structures import standalone_column
from stonedem.reference import analytic
from stonedem.validation.cases import block_scene

VARIANTS = ("area", "point_dashpot", "point")
VARIANT_TITLES = {
    "area": "overlap-area law (thesis), c_n calibrated to Housner's first impact",
    "point_dashpot": "point contacts, no plastic landing, zeta calibrated to Housner's first "
    "impact",
    "point": "point contacts with Housner's plastic landing, zeta 0.05 (the point law's scene "
    "defaults)",
}
POINT_DAMPING = 0.05  # zeta of the point law wherever it is not calibrated (its scene default)
PULSE_DAMPING = 0.5  # area law on (b): c_n / critical
COLUMN_DAMPING = 0.05  # area law on (c): c_n / critical of one drum on its bed joint
# Brent's bracket of the calibrated damping, as a fraction of critical (area) or zeta (point)
CALIBRATION_BRACKET = (1e-3, 3.0)


def _run(spec, dt, dt_ratio, n_free_from=1):
    """Simulate ``spec`` at dt (or dt_ratio x its stability limit); return (Trajectory, scene,
    result)."""
    if dt is None and dt_ratio is not None:
        dt = dt_ratio * stability_limit(scene_from_dict(spec))
    spec["solver"]["dt"] = "auto" if dt is None else float(dt)
    scene = scene_from_dict(spec)
    res = simulate(scene)
    d_base, _, _ = scene.horizontal.evaluate(res.time)
    free = slice(n_free_from, None)
    x = res.x[:, free] - res.x[0, free] - d_base[:, None]
    traj = Trajectory(
        time=res.time,
        theta=res.theta[:, free],
        x=x,
        wall_seconds=res.wall_seconds,
        steps=res.steps_run,
        status=int(res.status),
    )
    return traj, scene, res


def free_rocking(
    width, height, theta0, duration, *, contact, dt=None, dt_ratio=None, sample_every=1e-3
):
    """Free rocking of a block (density DENSITY) on a driven base from tilt theta0 [rad]."""
    spec = block_scene(
        width,
        height,
        density=cn.DENSITY,
        friction=cn.ROCKING_FRICTION,
        tilt=theta0,
        contact=contact,
        duration=duration,
        every=sample_every,
    )
    return _run(spec, dt, dt_ratio)[0]


def pulse_sliding(
    width,
    height,
    mu,
    accel,
    pulse_duration,
    duration,
    *,
    contact,
    dt=None,
    dt_ratio=None,
    sample_every=1e-3,
):
    """A block under a rectangular base-acceleration pulse; x is the sliding relative to the
    base."""
    spec = block_scene(
        width,
        height,
        density=cn.DENSITY,
        friction=mu,
        contact=contact,
        excitation={"kind": "rect_pulse", "accel": accel, "duration": pulse_duration},
        duration=duration,
        every=sample_every,
        base_width=2.0 * accel * pulse_duration * duration + 20.0,
    )
    return _run(spec, dt, dt_ratio)[0]


def column_scene_spec(duration, *, contact, pga, n_drums=cn.COLUMN_DRUMS, sample_every=1e-2):
    """Scene dict of scene (c): the 8-drum column on a driven base under the record at ``pga``."""
    bodies = standalone_column(
        n_drums, height=cn.COLUMN_HEIGHT, width=cn.COLUMN_WIDTH, density=cn.DENSITY
    )
    return {
        "bodies": bodies,
        "friction": cn.COLUMN_FRICTION,
        "contact": dict(contact),
        "excitation": {"kind": "record", "file": cn.COLUMN_RECORD, "pga": pga},
        "solver": {"duration": duration, "dt": "auto", "stop_on_collapse": False},
        "output": {"every": sample_every},
    }


def column_record(duration, *, contact, pga, dt=None, dt_ratio=None, sample_every=1e-2):
    """Scene (c) in our engine; also returns the (time, acceleration) table it applied."""
    traj, scene, _ = _run(
        column_scene_spec(duration, contact=contact, pga=pga, sample_every=sample_every),
        dt,
        dt_ratio,
    )
    h = scene.horizontal
    return traj, (np.arange(len(h.table_accel)) * h.table_dt, np.asarray(h.table_accel))


# --- contact laws of the variants ----------------------------------------------------------


def law_contact(model, k_n, damping, impact="plastic"):
    """``contact:`` mapping of one law: model area (damping = c_n [N s m-1]) or point
    (damping = zeta [1], impact plastic or none)."""
    if model not in LAWS:
        raise ValueError(f"unknown contact model {model!r}; use {' or '.join(LAWS)}")
    row = LAWS[model]
    return row.mapping(
        model,
        float(k_n),
        float(damping),
        **({"impact": impact} if "impact" in row.defaults else {}),
    )


def _check_variant(variant):
    if variant not in VARIANTS:
        raise ValueError(f"unknown contact variant {variant!r}; use one of {', '.join(VARIANTS)}")


def rocking_contact(variant, width, height, k_n):
    """Contact of scene (a) for a variant: its damping calibrated per block and k_n (area,
    point_dashpot) or zeta 0.05 with the plastic landing (point)."""
    _check_variant(variant)
    if variant == "point":
        return law_contact("point", k_n, POINT_DAMPING, "plastic")
    model = "area" if variant == "area" else "point"
    return law_contact(
        model, k_n, calibrate_rocking_damping(width, height, k_n, model=model), "none"
    )


def pulse_contact(variant, k_n):
    """Contact of scene (b): area c_n = 0.5 x critical of the pulse block; point zeta 0.05."""
    _check_variant(variant)
    if variant == "area":
        w, h = cn.PULSE_BLOCK
        mass = cn.DENSITY * w * h * cn.DEPTH
        return law_contact("area", k_n, PULSE_DAMPING * critical_damping(k_n, w, mass))
    return law_contact("point", k_n, POINT_DAMPING, "plastic" if variant == "point" else "none")


def column_contact(variant, k_n):
    """Contact of scene (c): area c_n = 0.05 x critical of one drum on its bed joint; point zeta
    0.05."""
    _check_variant(variant)
    if variant == "area":
        drum_mass = cn.DENSITY * cn.COLUMN_WIDTH * cn.COLUMN_HEIGHT / cn.COLUMN_DRUMS * cn.DEPTH
        return law_contact(
            "area", k_n, COLUMN_DAMPING * critical_damping(k_n, cn.COLUMN_WIDTH, drum_mass)
        )
    return law_contact("point", k_n, POINT_DAMPING, "plastic" if variant == "point" else "none")


def contact_damping(contact) -> tuple[float, float]:
    """(c_n [N s m-1], zeta [1]) of a contact mapping; the one the law does not use is NaN."""
    if contact["model"] == "area":
        return float(contact["c_n"]), math.nan
    return math.nan, float(contact["damping"])


def critical_damping(k_n, width, mass):
    """2 sqrt(k_n width m) [N s m-1]: critical dashpot of a block of mass m on a face of
    ``width``."""
    return 2.0 * math.sqrt(k_n * width * mass)


def first_impact_restitution(traj: Trajectory, width, height):
    """Energy ratio of the first impact from the first two peaks (exact energies, thesis Eq.
    5.2)."""
    _, peaks = cn.rocking_measures(traj.time, traj.theta[:, 0], n_impacts=1)
    theta0 = abs(traj.theta[0, 0])
    return float(analytic.restitution_from_peaks_exact(width, height, [theta0, peaks[0]])[0])


def calibrate_rocking_damping(width, height, k_n, dt_ratio=0.1, model="area"):
    """Damping of a law giving Housner's energy ratio at the first impact of free rocking:
    c_n [N s m-1] (model area) or zeta [1] (model point, ``impact: none``); see
    :func:`rocking_calibration`."""
    return rocking_calibration(width, height, k_n, dt_ratio, model)[0]


@lru_cache(maxsize=None)
def rocking_calibration(width, height, k_n, dt_ratio=0.1, model="area"):
    """(damping, first-impact energy ratio it gives, Housner's) of free rocking at k_n.

    model area: the normal dashpot c_n [N s m-1]; model point (without the plastic landing,
    ``impact: none``): the damping ratio zeta of each contact point [1]. The target is
    Housner's energy ratio r at the first impact of a block released from
    cn.rocking_theta0, measured from the first two peaks
    (:func:`first_impact_restitution`) at dt_ratio x the stability limit; the damping is
    used then at every dt of the sweep, so a run's error shows how well one calibrated
    dashpot carries over to the later, smaller impacts and other steps.

    The damping is searched on a log scale within CALIBRATION_BRACKET x critical (area;
    critical = :func:`critical_damping` of the block on its base) or within those zetas
    (point). Area: Brent's method on the whole bracket (r falls with c_n). Point: r(zeta)
    is not monotonic (measured: it has a minimum near zeta = 1 and rises again, so a stiff
    point contact can hardly lose Housner's share of energy through its dashpots), so the
    bracket is walked up by half decades to the first zeta that loses enough, and Brent's
    method runs between it and the one below; if none does, the zeta of least r (bounded
    scalar minimisation around the best point) is returned, with the r it reaches (above
    Housner's: the calibration missed; a warning says by how much). If even the lightest
    damping loses too much energy (the soft contact itself does), the lightest is returned.
    """
    if model not in ("area", "point"):
        raise ValueError(f"unknown contact model {model!r}; use area or point")
    target = analytic.housner_restitution(width, height)
    theta0 = cn.rocking_theta0(width, height)
    times, _ = cn.rocking_reference(width, height, n_impacts=1)
    duration = 1.6 * times[0] * 2.0
    mass = cn.DENSITY * width * height * cn.DEPTH
    scale = critical_damping(k_n, width, mass) if model == "area" else 1.0
    reached = {}

    def restitution(log_d):
        if log_d not in reached:
            contact = law_contact(model, k_n, math.exp(log_d), "none")
            traj = free_rocking(
                width,
                height,
                theta0,
                duration,
                contact=contact,
                dt_ratio=dt_ratio,
                sample_every=2e-4,
            )
            r = first_impact_restitution(traj, width, height)
            reached[log_d] = r if np.isfinite(r) else 0.0
        return reached[log_d]

    def miss(log_d):
        return restitution(log_d) - target

    def result(log_d):
        return math.exp(log_d), restitution(log_d), target

    lo, hi = (math.log(f * scale) for f in CALIBRATION_BRACKET)
    if miss(lo) < 0.0:
        return result(lo)
    if model == "area":
        return result(brentq(miss, lo, hi, xtol=1e-4))
    grid = np.arange(lo, hi + 1e-9, 0.5 * math.log(10.0))
    grid[-1] = hi
    for below, above in zip(grid[:-1], grid[1:]):
        if miss(above) < 0.0:
            return result(brentq(miss, below, above, xtol=1e-4))
    best = int(np.argmin([miss(g) for g in grid]))
    left, right = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
    low = minimize_scalar(miss, bounds=(left, right), method="bounded", options={"xatol": 1e-3})
    if low.fun < 0.0:
        return result(brentq(miss, left, low.x, xtol=1e-4))
    log_d = low.x if low.fun < miss(grid[best]) else grid[best]
    warnings.warn(
        f"point law at k_n = {k_n:g} N/m2 on a {width} x {height} m block: no zeta in "
        f"{CALIBRATION_BRACKET} loses Housner's share at the first impact; zeta = "
        f"{math.exp(log_d):.3g} comes closest, r = {restitution(log_d):.5f} against {target:.5f}",
        stacklevel=2,
    )
    return result(log_d)
