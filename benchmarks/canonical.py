"""The canonical benchmark scenes, their exact references and error measures (DESIGN §6).

(a) free rocking: a rectangular block released from rest at theta0 = 0.5 alpha, pivoting on
    a corner; reference: the rigid rocking equation with Housner's energy ratio per impact.
    Error: the times of the first three impacts and the peak angles after them.
(a1) free rocking to the first impact: the blocks of (a), released alike, run only until
    FIRST_IMPACT_MARGIN x the exact first impact time; error: that impact's time.
(b) pulse sliding: a squat block under a rectangular base-acceleration pulse; reference:
    Newmark's maximum sliding u_max (thesis Eq. 5.5).
(c) an 8-drum column under a record; reference: the same engine at 1/16 of the step.

Every engine gets the same geometry, mass and friction; every engine returns a
:class:`Trajectory` in the frame of the base (ground fixed, base acceleration applied as a
uniform inertial load where the engine cannot drive a body), sampled every ``sample_every``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from stonedem.reference import analytic
from stonedem.units import GRAVITY as G  # [m s-2]

DENSITY = 2700.0  # stone [kg m-3]; unit out-of-plane depth, so masses are per metre
DEPTH = 1.0  # [m]

# (a) width x height [m] of the free-rocking blocks; the error of a run is the worst of them
ROCKING_BLOCKS = ((0.25, 1.0), (1.0, 6.0))
ROCKING_RATIO = 0.5  # theta0 / alpha
ROCKING_FRICTION = 10.0  # no sliding: pure rocking
N_IMPACTS = 3
# (a1) run length / the exact rigid block's first impact time: a margin past the impact, so
# the sign change of theta that marks it is sampled even by a run whose impact comes late
FIRST_IMPACT_MARGIN = 1.2

# (b) a squat block (tan alpha = 4 > a_p / g: it slides, never rocks)
PULSE_BLOCK = (2.0, 0.5)  # width x height [m]
PULSE_ACCEL = 0.5 * G  # a_p [m s-2]
PULSE_DURATION = 0.5  # T_p [s]
PULSE_FRICTION = 0.2  # mu

# (c) a 6 m x 1 m column of 8 drums under a record
COLUMN_DRUMS = 8
COLUMN_WIDTH = 1.0
COLUMN_HEIGHT = 6.0
COLUMN_FRICTION = 0.5
COLUMN_RECORD = "athens_standin_kocaeli_arc000"
COLUMN_DURATION = 10.0  # [s] of the record, from its start
COLUMN_REFERENCE_REFINEMENT = 16  # reference run: the engine's own, at dt / 16


@dataclass
class Trajectory:
    """Sampled motion of the free bodies of a scene, in the base's frame.

    time: (n_sample,) [s]
    theta: (n_sample, n_free) rotation of each free body, counterclockwise positive [rad]
    x: (n_sample, n_free) horizontal displacement of each body's centroid relative to the
       base, from its start [m]
    wall_seconds: wall time of the stepping only (no set-up, no compile) [s]
    steps: number of time steps taken
    status: run status of our engine (:mod:`stonedem.kernels.step`: 0 ok, 2 non-finite); 0 for
       the other engines
    """

    time: np.ndarray
    theta: np.ndarray
    x: np.ndarray
    wall_seconds: float
    steps: int
    status: int = 0


# --- (a) free rocking ---------------------------------------------------------------------


def rocking_theta0(width, height):
    """Initial tilt theta0 = ROCKING_RATIO x alpha [rad]."""
    return ROCKING_RATIO * math.atan2(width, height)


def rocking_reference(width, height, n_impacts=N_IMPACTS):
    """(impact times [s], peak angles after each impact [rad]) of the exact rigid block.

    Released from rest at theta0; Housner's energy ratio r at every impact (thesis Eq. 5.2),
    the peak after an impact from the exact potential energy, m g R [cos(alpha - theta) -
    cos alpha] (the inverse of :func:`stonedem.reference.analytic.restitution_from_peaks_exact`),
    each half cycle the exact rigid period at its amplitude
    (:func:`stonedem.reference.analytic.rocking_period_exact`)."""
    alpha = math.atan2(width, height)
    r = analytic.housner_restitution(width, height)
    peaks = [rocking_theta0(width, height)]
    for _ in range(n_impacts):
        level = r * (math.cos(alpha - peaks[-1]) - math.cos(alpha))
        peaks.append(alpha - math.acos(level + math.cos(alpha)))
    quarters = analytic.rocking_period_exact(width, height, np.array(peaks[:n_impacts])) / 4.0
    # impact k ends a half cycle of amplitude peaks[k-1] (the first is a quarter cycle)
    times = np.cumsum(np.concatenate([[quarters[0]], 2.0 * quarters[1:]]))
    return times, np.array(peaks[1:])


def rocking_measures(time, theta, n_impacts=N_IMPACTS):
    """(impact times [s], |peak| after each impact [rad]) of a sampled rotation history.

    Impacts are the sign changes of theta (linear interpolation between samples); the peak
    of each half cycle is refined by a parabola through the largest sample and its
    neighbours. Missing impacts (the block stopped) are NaN.
    """
    time = np.asarray(time, dtype=float)
    theta = np.asarray(theta, dtype=float)
    s = np.sign(theta)
    i = np.flatnonzero(s[1:] * s[:-1] < 0)
    crossings = time[i] + (0.0 - theta[i]) / (theta[i + 1] - theta[i]) * (time[i + 1] - time[i])
    times = np.full(n_impacts, np.nan)
    peaks = np.full(n_impacts, np.nan)
    ends = list(i + 1) + [len(theta)]
    for k in range(min(n_impacts, len(i))):
        lo, hi = ends[k], ends[k + 1]
        times[k] = crossings[k]
        j = lo + int(np.argmax(np.abs(theta[lo:hi])))
        if j == len(theta) - 1:
            continue  # the run ended before this half cycle's peak
        peaks[k] = _parabola_peak(np.abs(theta[max(j - 1, 0) : j + 2]))
    return times, peaks


def _parabola_peak(three):
    """Peak of the parabola through three equally spaced samples (or the largest sample)."""
    if len(three) < 3:
        return float(three.max())
    y0, y1, y2 = three
    curve = y0 - 2.0 * y1 + y2
    if curve >= 0.0:
        return float(y1)
    return float(y1 - 0.125 * (y2 - y0) ** 2 / curve)


def rocking_errors(traj: Trajectory, width, height):
    """(impact-time error, peak error): worst |relative error| over the first N_IMPACTS [1]."""
    t_ref, p_ref = rocking_reference(width, height)
    times, peaks = rocking_measures(traj.time, traj.theta[:, 0])
    t_err = np.abs(times / t_ref - 1.0)
    p_err = np.abs(peaks / p_ref - 1.0)
    # a missing impact or peak is an error of 100 %
    return float(np.nan_to_num(t_err, nan=1.0).max()), float(np.nan_to_num(p_err, nan=1.0).max())


def rocking_duration(width, height, margin=0.25):
    """Run length [s] that holds the first N_IMPACTS impacts and the peak after the last."""
    times, peaks = rocking_reference(width, height)
    last_half = analytic.rocking_period_exact(width, height, peaks[-1]) / 2.0
    return float(times[-1] + (0.5 + margin) * last_half)


def first_impact_time(width, height):
    """Time [s] of the first impact of the exact rigid block released from rest at
    :func:`rocking_theta0`: a quarter of the exact rigid period at that amplitude (the first
    entry of :func:`rocking_reference`)."""
    times, _ = rocking_reference(width, height, n_impacts=1)
    return float(times[0])


def first_impact_duration(width, height, margin=FIRST_IMPACT_MARGIN):
    """Run length [s] of scene (a1): ``margin`` x the exact first impact time."""
    return float(margin * first_impact_time(width, height))


def first_impact_error(traj: Trajectory, width, height):
    """|t_1 / exact t_1 - 1| [1]: relative error of the first impact time of a run.

    t_1 is detected as scene (a) detects every impact (:func:`rocking_measures`: the first
    sign change of theta, linearly interpolated between samples); no sign change in the run
    (the block never landed) is an error of 100 %.
    """
    times, _ = rocking_measures(traj.time, traj.theta[:, 0], n_impacts=1)
    return float(np.nan_to_num(abs(times[0] / first_impact_time(width, height) - 1.0), nan=1.0))


# --- (b) pulse sliding ----------------------------------------------------------------------


def pulse_reference():
    """Newmark's maximum sliding u_max [m] of the pulse scene (thesis Eq. 5.5)."""
    return float(
        analytic.newmark_pulse_max_sliding(PULSE_ACCEL, PULSE_DURATION, PULSE_FRICTION, g=G)
    )


def pulse_run_duration(margin=0.3):
    """Run length [s]: the block is at rest again at T_p a_p / (mu g) (thesis 5.1.3)."""
    return PULSE_DURATION * PULSE_ACCEL / (PULSE_FRICTION * G) + margin


def pulse_error(traj: Trajectory):
    """|u_max / Eq. 5.5 - 1| [1]."""
    return float(abs(np.nanmax(np.abs(traj.x[:, 0])) / pulse_reference() - 1.0))


# --- (c) column under a record --------------------------------------------------------------


def history_errors(traj: Trajectory, reference: Trajectory):
    """(rotation error, sliding error) of a run against a finer run of the same engine [1].

    Each: max over drums and time of |run - reference|, over the reference's largest
    absolute value (over drums and time), on the reference's sample times (the run is
    interpolated linearly). Sliding is each drum's horizontal displacement relative to the
    drum below (the base for the first), so rocking and sliding are told apart.
    """

    def on_grid(values):
        return np.column_stack(
            [np.interp(reference.time, traj.time, values[:, k]) for k in range(values.shape[1])]
        )

    def relative_sliding(x):
        return np.diff(np.column_stack([np.zeros(len(x)), x]), axis=1)

    errs = []
    for run, ref in (
        (on_grid(traj.theta), reference.theta),
        (relative_sliding(on_grid(traj.x)), relative_sliding(reference.x)),
    ):
        scale = np.nanmax(np.abs(ref))
        errs.append(float(np.nanmax(np.abs(run - ref)) / scale) if scale > 0 else float("nan"))
    return errs[0], errs[1]


def column_record():
    """(time [s], base acceleration [m s-2]) of the record that drives scene (c), as stored."""
    from pathlib import Path

    import xarray as xr

    path = Path(__file__).resolve().parents[1] / "records" / f"{COLUMN_RECORD}.nc"
    with xr.open_dataset(path) as rec:
        return rec["time"].values.astype(float), rec["acceleration"].values.astype(float)
