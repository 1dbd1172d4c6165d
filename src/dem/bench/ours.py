"""The canonical scenes (:mod:`dem.bench.canonical`) in our engine, at a given k_n, c_n and dt.

Each function builds the scene dict, runs :func:`dem.simulate.simulate` (the compiled loop,
warm cache) and returns a :class:`Trajectory` in the base's frame; ``wall_seconds`` is the
compiled loop's own time (:attr:`dem.simulate.RunResult.wall_seconds`). ``dt = None`` takes
the automatic step; ``dt_ratio`` instead asks for that fraction of the stability limit.
The restitution of free rocking comes from the normal dashpot c_n, calibrated per block
and k_n by :func:`calibrate_rocking_damping` (thesis 5.1.2: on a problem with a known
solution), since a soft contact has no impact law of its own.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

from dem import analytic
from dem.bench import canonical as cn
from dem.bench.canonical import Trajectory
from dem.scene import scene_from_dict
from dem.simulate import simulate, stability_limit
from dem.structures import standalone_column
from dem.validation import block_scene


def _run(spec, dt, dt_ratio, n_free_from=1):
    """Simulate ``spec`` at dt (or dt_ratio x its stability limit); return (Trajectory, scene, result)."""
    if dt is None and dt_ratio is not None:
        dt = dt_ratio * stability_limit(scene_from_dict(spec))
    spec["solver"]["dt"] = "auto" if dt is None else float(dt)
    scene = scene_from_dict(spec)
    res = simulate(scene)
    d_base, _, _ = scene.horizontal.evaluate(res.time)
    free = slice(n_free_from, None)
    x = res.x[:, free] - res.x[0, free] - d_base[:, None]
    traj = Trajectory(time=res.time, theta=res.theta[:, free], x=x,
                      wall_seconds=res.wall_seconds, steps=res.steps_run)
    return traj, scene, res


def free_rocking(width, height, theta0, duration, *, k_n, c_n, dt=None, dt_ratio=None,
                 sample_every=1e-3):
    """Free rocking of a block (density DENSITY) on a driven base from tilt theta0 [rad]."""
    spec = block_scene(width, height, density=cn.DENSITY, friction=cn.ROCKING_FRICTION,
                       tilt=theta0, k_n=k_n, c_n=c_n, duration=duration, every=sample_every)
    return _run(spec, dt, dt_ratio)[0]


def pulse_sliding(width, height, mu, accel, pulse_duration, duration, *, k_n, c_n, dt=None,
                  dt_ratio=None, sample_every=1e-3):
    """A block under a rectangular base-acceleration pulse; x is the sliding relative to the base."""
    spec = block_scene(width, height, density=cn.DENSITY, friction=mu, k_n=k_n, c_n=c_n,
                       excitation={"kind": "rect_pulse", "accel": accel, "duration": pulse_duration},
                       duration=duration, every=sample_every,
                       base_width=2.0 * accel * pulse_duration * duration + 20.0)
    return _run(spec, dt, dt_ratio)[0]


def column_scene_spec(duration, *, k_n, c_n, pga, n_drums=cn.COLUMN_DRUMS, sample_every=1e-2):
    """Scene dict of scene (c): the 8-drum column on a driven base under the record at ``pga``."""
    bodies = standalone_column(n_drums, height=cn.COLUMN_HEIGHT, width=cn.COLUMN_WIDTH,
                               density=cn.DENSITY)
    return {
        "bodies": bodies, "friction": cn.COLUMN_FRICTION,
        "contact": {"k_n": k_n, "c_n": c_n},
        "excitation": {"kind": "record", "file": cn.COLUMN_RECORD, "pga": pga},
        "solver": {"duration": duration, "dt": "auto", "stop_on_collapse": False},
        "output": {"every": sample_every},
    }


def column_record(duration, *, k_n, c_n, pga, dt=None, dt_ratio=None, sample_every=1e-2):
    """Scene (c) in our engine; also returns the (time, acceleration) table it applied."""
    traj, scene, _ = _run(column_scene_spec(duration, k_n=k_n, c_n=c_n, pga=pga,
                                            sample_every=sample_every), dt, dt_ratio)
    h = scene.horizontal
    return traj, (np.arange(len(h.table_accel)) * h.table_dt, np.asarray(h.table_accel))


def critical_damping(k_n, width, mass):
    """2 sqrt(k_n width m) [N s m-1]: critical dashpot of a block of mass m on a face of ``width``."""
    return 2.0 * math.sqrt(k_n * width * mass)


def first_impact_restitution(traj: Trajectory, width, height):
    """Energy ratio of the first impact from the first two peaks (exact energies, thesis Eq. 5.2)."""
    _, peaks = cn.rocking_measures(traj.time, traj.theta[:, 0], n_impacts=1)
    theta0 = abs(traj.theta[0, 0])
    return float(analytic.restitution_from_peaks_exact(width, height, [theta0, peaks[0]])[0])


@lru_cache(maxsize=None)
def calibrate_rocking_damping(width, height, k_n, dt_ratio=0.1):
    """c_n [N s m-1] giving Housner's energy ratio at the first impact of free rocking.

    Found by Brent's method on log c_n between 1e-3 and 3 x critical, at dt_ratio x the
    stability limit; used then at every dt of the sweep, so a run's peak error shows how
    well one calibrated dashpot carries over to the later, smaller impacts and other steps.
    """
    target = analytic.housner_restitution(width, height)
    theta0 = cn.rocking_theta0(width, height)
    times, _ = cn.rocking_reference(width, height, n_impacts=1)
    duration = 1.6 * times[0] * 2.0
    mass = cn.DENSITY * width * height * cn.DEPTH
    crit = critical_damping(k_n, width, mass)

    def miss(log_c):
        traj = free_rocking(width, height, theta0, duration, k_n=k_n, c_n=math.exp(log_c),
                            dt_ratio=dt_ratio, sample_every=2e-4)
        r = first_impact_restitution(traj, width, height)
        return (r if np.isfinite(r) else 0.0) - target

    lo, hi = math.log(1e-3 * crit), math.log(3.0 * crit)
    if miss(lo) < 0.0:
        return 1e-3 * crit  # even the lightest dashpot loses too much: the soft contact itself does
    return math.exp(brentq(miss, lo, hi, xtol=1e-4))
