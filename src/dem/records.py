"""Recorded accelerograms: read, resample, baseline-correct, integrate, scale, characterise.

Thesis 6.4 drives the columns with recorded earthquakes of very different frequency content
(Table 6.1) and plots their 10 %-damped response spectra (Fig. 6.14). This module reads
PEER NGA ``.AT2`` files (our own parser: both header styles, point count checked, no
``eval``) and plain text, resamples without aliasing, removes baseline drift so the base
displacement returns to rest, integrates exactly (acceleration linear between samples),
scales to a target PGA, and computes the predominant frequency (peak of the Konno-Ohmachi
smoothed Fourier amplitude) and pseudo-acceleration response spectra at any damping
(exact piecewise-linear SDOF recurrence of Nigam and Jennings).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dem.errors import InputError

G_STANDARD = 9.80665  # [m s-2], PEER convention for records in g


@dataclass
class Record:
    """An accelerogram on a uniform time grid starting at 0."""

    time: np.ndarray  # [s]
    acceleration: np.ndarray  # [m s-2]
    meta: dict = field(default_factory=dict)

    @property
    def dt(self) -> float:
        return float(self.time[1] - self.time[0])

    @property
    def pga(self) -> float:
        return float(np.abs(self.acceleration).max())

    @property
    def duration(self) -> float:
        return float(self.time[-1])


# --- reading -----------------------------------------------------------------------------

_NPTS_NEW = re.compile(r"NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*([0-9.eE+-]+)", re.IGNORECASE)
_NPTS_OLD = re.compile(r"^\s*(\d+)\s+([0-9.eE+-]+)\s+NPTS\s*,?\s*DT", re.IGNORECASE)


def read_at2(path: str | Path, field_name: str = "file") -> Record:
    """Read a PEER NGA ``.AT2`` file: 4 header lines, then acceleration in g, 5 per line.

    Header line 3 must declare the units (``UNITS OF G``); line 4 gives the point count and
    step, new style ``NPTS=  5590, DT=   .0050 SEC`` or old style ``5590 0.0050 NPTS, DT``.
    The number of values read must equal NPTS.
    """
    path = Path(path)
    lines = path.read_text(errors="replace").splitlines()
    where = f"{field_name} ({path.name})"
    if len(lines) < 5:
        raise InputError(where, "an AT2 file needs 4 header lines and data", "check the file is a PEER .AT2")
    units_line = lines[2].upper()
    if "UNITS OF G" not in units_line and not re.search(r"\bG\b", units_line):
        raise InputError(where, f"header line 3 does not declare units of g: '{lines[2].strip()[:50]}'",
                         "PEER AT2 files hold acceleration in g")
    match = _NPTS_NEW.search(lines[3]) or _NPTS_OLD.search(lines[3])
    if match is None:
        raise InputError(where, f"header line 4 has no NPTS and DT: '{lines[3].strip()[:50]}'",
                         "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'")
    npts, dt = int(match.group(1)), float(match.group(2))
    if npts < 2 or not dt > 0:
        raise InputError(where, f"NPTS = {npts}, DT = {dt}", "need at least 2 points and DT > 0")
    values = []
    for number, line in enumerate(lines[4:], start=5):
        for token in line.split():
            try:
                values.append(float(token))
            except ValueError:
                raise InputError(where, f"line {number}: non-numeric value '{token[:20]}'",
                                 "the data block holds numbers only") from None
    if len(values) != npts:
        raise InputError(where, f"header declares NPTS = {npts} but {len(values)} values were read",
                         "the file is truncated or the header is wrong")
    accel = np.array(values) * G_STANDARD
    if not np.all(np.isfinite(accel)):
        raise InputError(where, "NaN or infinite value", "clean the record")
    title = lines[1].strip()
    return Record(np.arange(npts) * dt, accel,
                  {"source_file": path.name, "header": " | ".join(x.strip() for x in lines[:2]),
                   "title": title, "units_in_file": "g"})


# --- processing ----------------------------------------------------------------------------

def integrate(time, accel):
    """Velocity [m s-1] and displacement [m] of an acceleration linear between samples (exact).

    v_{i+1} = v_i + h (a_i + a_{i+1}) / 2 and d_{i+1} = d_i + h v_i + h^2 (2 a_i + a_{i+1}) / 6.
    """
    h = np.diff(time)
    vel = np.concatenate([[0.0], np.cumsum(0.5 * h * (accel[:-1] + accel[1:]))])
    disp = np.concatenate([[0.0], np.cumsum(h * vel[:-1] + h * h * (2.0 * accel[:-1] + accel[1:]) / 6.0)])
    return vel, disp


def baseline_correct(time, accel, degree: int = 6):
    """Acceleration whose displacement ends at rest: subtract the second derivative of a polynomial.

    The displacement d(t) of the record is fitted in least squares by a polynomial in t
    with terms t^2 ... t^degree (so the start stays at rest: no initial displacement or
    velocity is introduced), and its second derivative is taken from the acceleration.
    Then the remaining end velocity and displacement are removed by a smooth cubic
    correction over the last 10 % of the record, so the base ends at rest where it started.
    """
    t = np.asarray(time, dtype=float)
    a = np.asarray(accel, dtype=float) - np.mean(accel[: max(1, len(accel) // 100)])
    span = t[-1] - t[0]
    x = (t - t[0]) / span
    _, disp = integrate(t, a)
    powers = np.arange(2, degree + 1)
    basis = x[:, None] ** powers[None, :]
    coef, *_ = np.linalg.lstsq(basis, disp, rcond=None)
    second = (powers * (powers - 1))[None, :] * x[:, None] ** (powers - 2)[None, :]
    a = a - (second @ coef) / span**2
    # end at rest: over the last 10 % add c0 + c1 (t - t1), with c0, c1 solved so that the
    # (exactly integrated) velocity and displacement are zero at the end
    vel, disp = integrate(t, a)
    i1 = int(0.9 * (len(t) - 1))
    ramp = np.where(np.arange(len(t)) >= i1, 1.0, 0.0)
    basis0 = ramp
    basis1 = ramp * (t - t[i1])
    v0, d0 = integrate(t, basis0)
    v1, d1 = integrate(t, basis1)
    m = np.array([[v0[-1], v1[-1]], [d0[-1], d1[-1]]])
    c0, c1 = np.linalg.solve(m, [-vel[-1], -disp[-1]])
    return a + c0 * basis0 + c1 * basis1


def resample(time, accel, dt_new: float):
    """The record on a uniform grid of step dt_new [s], without aliasing.

    Coarser grids are low-passed first (zero-phase Butterworth at 0.8 x the new Nyquist
    frequency); finer grids interpolate linearly, which is also how the engine reads a
    record between samples.
    """
    from scipy.signal import butter, sosfiltfilt

    t = np.asarray(time, dtype=float)
    a = np.asarray(accel, dtype=float)
    dt_old = t[1] - t[0]
    if dt_new > dt_old * (1 + 1e-12):
        nyquist_new = 0.5 / dt_new
        sos = butter(8, 0.8 * nyquist_new, btype="low", fs=1.0 / dt_old, output="sos")
        a = sosfiltfilt(sos, a)
    t_new = np.arange(0.0, t[-1] + 1e-9 * dt_new, dt_new)
    return t_new, np.interp(t_new, t, a)


def scale_to_pga(accel, pga: float):
    """Acceleration scaled so its peak absolute value is ``pga`` [m s-2] (exactly)."""
    peak = np.abs(accel).max()
    if peak == 0:
        raise InputError("pga", "the record is all zeros", "use a record with motion")
    return accel * (pga / peak)


def fourier_amplitude(time, accel):
    """(frequency [Hz], |FFT| x dt [m s-1]) of the record."""
    dt = time[1] - time[0]
    amp = np.abs(np.fft.rfft(accel)) * dt
    return np.fft.rfftfreq(len(accel), dt), amp


def konno_ohmachi(freq, amp, centres, b: float = 20.0):
    """Konno-Ohmachi smoothing of a Fourier amplitude spectrum at the centre frequencies [Hz]."""
    out = np.empty(len(centres))
    f = freq[1:]
    a = amp[1:]
    for i, fc in enumerate(centres):
        with np.errstate(divide="ignore", invalid="ignore"):
            arg = b * np.log10(f / fc)
            w = np.where(np.abs(arg) < 1e-12, 1.0, (np.sin(arg) / arg) ** 4)
        out[i] = np.sum(w * a) / np.sum(w)
    return out


def predominant_frequency(time, accel, f_min=0.1, f_max=25.0, b=20.0) -> float:
    """Frequency [Hz] of the peak of the Konno-Ohmachi (b = 20) smoothed Fourier amplitude."""
    freq, amp = fourier_amplitude(time, accel)
    centres = np.geomspace(f_min, min(f_max, freq[-1]), 300)
    smooth = konno_ohmachi(freq, amp, centres, b)
    return float(centres[np.argmax(smooth)])


def response_spectrum(time, accel, periods, damping: float = 0.05):
    """Pseudo-acceleration spectrum PSA = omega^2 max|u| [m s-2] of a SDOF oscillator.

    u'' + 2 zeta omega u' + omega^2 u = -a_g(t), a_g linear between samples: the exact
    recurrence of Nigam and Jennings (1969), vectorised over the periods [s].
    """
    a = np.asarray(accel, dtype=float)
    dt = float(time[1] - time[0])
    w = 2.0 * np.pi / np.asarray(periods, dtype=float)
    z = damping
    wd = w * np.sqrt(1.0 - z * z)
    e = np.exp(-z * w * dt)
    s, c = np.sin(wd * dt), np.cos(wd * dt)
    # state transition of (u, v) for one step with a forcing linear over the step
    a11 = e * (z / np.sqrt(1 - z * z) * s + c)
    a12 = e / wd * s
    a21 = -w / np.sqrt(1 - z * z) * e * s
    a22 = e * (c - z / np.sqrt(1 - z * z) * s)
    t2 = 2 * z / (w**3 * dt)
    b11 = e * (((2 * z * z - 1) / (w * w * dt) + z / w) * s / wd + (2 * z / (w**3 * dt) + 1 / (w * w)) * c) - t2
    b12 = -e * ((2 * z * z - 1) / (w * w * dt) * s / wd + 2 * z / (w**3 * dt) * c) - 1 / (w * w) + t2
    b21 = (e * (((2 * z * z - 1) / (w * w * dt) + z / w) * (c - z / np.sqrt(1 - z * z) * s)
                - (2 * z / (w**3 * dt) + 1 / (w * w)) * (wd * s + z * w * c)) + 1 / (w * w * dt))
    b22 = (-e * ((2 * z * z - 1) / (w * w * dt) * (c - z / np.sqrt(1 - z * z) * s)
                 - 2 * z / (w**3 * dt) * (wd * s + z * w * c)) - 1 / (w * w * dt))
    u = np.zeros_like(w)
    v = np.zeros_like(w)
    peak = np.zeros_like(w)
    for i in range(len(a) - 1):
        p0, p1 = -a[i], -a[i + 1]
        u, v = (a11 * u + a12 * v + b11 * p0 + b12 * p1,
                a21 * u + a22 * v + b21 * p0 + b22 * p1)
        np.maximum(peak, np.abs(u), out=peak)
    return w * w * peak


SPECTRUM_PERIODS = np.round(np.geomspace(0.02, 5.0, 60), 4)  # [s]
SPECTRUM_DAMPING = (0.05, 0.10)  # thesis Fig. 6.14 uses 10 %


def record_dataset(record: Record, name: str, attrs: dict | None = None):
    """Self-describing dataset of a record: as-recorded acceleration, the baseline-corrected
    velocity and displacement, response spectra at 5 % and 10 % damping, PGA and
    predominant frequency."""
    import xarray as xr

    t, a = record.time, record.acceleration
    corrected = baseline_correct(t, a)
    vel, disp = integrate(t, corrected)
    _, raw_disp = integrate(t, a)
    psa = np.array([response_spectrum(t, a, SPECTRUM_PERIODS, z) for z in SPECTRUM_DAMPING])
    f_p = predominant_frequency(t, a)

    def v(dims, data, units, long_name):
        return (dims, data, {"units": units, "long_name": long_name})

    return xr.Dataset(
        {"acceleration": v("time", a, "m s-2", "horizontal ground acceleration, as recorded"),
         "acceleration_corrected": v("time", corrected, "m s-2", "ground acceleration, baseline corrected"),
         "velocity": v("time", vel, "m s-1", "ground velocity (baseline corrected)"),
         "displacement": v("time", disp, "m", "ground displacement (baseline corrected)"),
         "displacement_uncorrected": v("time", raw_disp, "m", "ground displacement integrated from the record as is"),
         "psa": v(("damping", "period"), psa, "m s-2", "pseudo-acceleration response spectrum")},
        coords={"time": v("time", t, "s", "time"),
                "period": v("period", SPECTRUM_PERIODS, "s", "oscillator period"),
                "damping": v("damping", np.array(SPECTRUM_DAMPING), "1", "damping ratio")},
        attrs={"name": name, **(attrs or {}), **record.meta,
               "pga": record.pga, "pga_units": "m s-2", "dt": record.dt, "duration": record.duration,
               "predominant_frequency": f_p, "predominant_frequency_units": "Hz",
               "predominant_frequency_method": "peak of the Konno-Ohmachi (b = 20) smoothed Fourier amplitude, 0.1-25 Hz",
               "baseline_correction": "polynomial t^2..t^6 fitted to displacement, then a linear end correction over the last 10 %"},
    )
