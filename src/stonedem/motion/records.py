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

import math
import re
from array import array
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

import numpy as np

from stonedem.errors import InputError
from stonedem.units import G_STANDARD  # [m s-2], PEER convention for records in g

# --- limits on record files (hostile or mistaken input; docs/guide/records.md) ----
# Spectra cost ~20 us per sample and damping on this machine, the predominant frequency
# ~25 us per sample: 500 000 samples (e.g. 500 s at 1 kHz, 40x the longest committed
# record) keep `stonedem record info` under a minute and a record's arrays under 10 MB each.
MAX_RECORD_SAMPLES = 500_000
MAX_RECORD_BYTES = 64 * 2**20  # [bytes] text and .AT2 files, checked before reading
MAX_LINE_CHARS = 10_000  # a text or .AT2 line; longer is binary or has no line ends
MIN_RECORD_DT = 1e-4  # [s] 10 kHz; below it the exact spectrum recurrence loses digits
MAX_RECORD_DT = 1.0  # [s] above it there is nothing left of an earthquake's 0.1-25 Hz band
MAX_RECORD_PGA = 100.0 * G_STANDARD  # [m s-2] 100 g: no ground motion; wrong units or junk


def shown(text, limit: int = 60) -> str:
    """``text`` fit for a one-line message: control characters escaped, at most ``limit`` chars."""
    text = str(text)
    cut = len(text) > limit
    out = "".join(
        ch if ch.isprintable() else ch.encode("unicode_escape", "backslashreplace").decode("ascii")
        for ch in text[:limit]
    )
    return out + "..." if cut else out


def check_record_file(path: Path, field: str, max_bytes: int | None = None) -> int:
    """Size [bytes] of a regular, readable record file, or an InputError naming ``field``.

    ``max_bytes`` defaults to :data:`MAX_RECORD_BYTES` (text and .AT2 records).
    """
    import os
    import stat

    max_bytes = MAX_RECORD_BYTES if max_bytes is None else max_bytes
    try:
        info = os.stat(path)
    except (OSError, ValueError) as err:
        raise InputError(
            field,
            f"{shown(path.name)}: cannot read ({_reason(err)})",
            "give a readable record file",
        ) from None
    if not stat.S_ISREG(info.st_mode):
        raise InputError(field, f"{shown(path.name)} is not a regular file", "give a record file")
    if info.st_size > max_bytes:
        raise InputError(
            field,
            f"{shown(path.name)} is {info.st_size / 2**20:.0f} MB, above the "
            f"{max_bytes / 2**20:.0f} MB limit for text records",
            f"give at most {MAX_RECORD_SAMPLES} samples (stonedem.motion.records.MAX_RECORD_BYTES)",
        )
    return info.st_size


def _reason(err: BaseException) -> str:
    """A short one-line reason from an exception."""
    text = getattr(err, "strerror", None) or str(err) or type(err).__name__
    return shown(text, 80)


def text_lines(path: Path, field: str) -> Iterator[tuple[int, str]]:
    """(line number, text without its line end) of a UTF-8 text record file, checked.

    Refused with an InputError naming ``field``: a file that is not a regular file or larger
    than :data:`MAX_RECORD_BYTES`, a NUL byte (a binary file), a line longer than
    :data:`MAX_LINE_CHARS`, bytes that are not UTF-8.
    """
    check_record_file(path, field)
    name = shown(path.name)
    try:
        handle = open(path, "rb")
    except OSError as err:
        raise InputError(
            field, f"{name}: cannot read ({_reason(err)})", "give a readable record file"
        ) from None
    chunk = MAX_LINE_CHARS * 4 + 2  # bytes: a UTF-8 character takes at most 4
    with handle:
        number = 0
        while True:
            try:
                raw = handle.readline(chunk)
            except OSError as err:
                raise InputError(
                    field, f"{name}: cannot read ({_reason(err)})", "give a readable record file"
                ) from None
            if not raw:
                return
            number += 1
            if b"\0" in raw:
                raise InputError(
                    field,
                    f"{name} line {number}: a NUL byte, this is a binary file",
                    "give a text record (or a NetCDF one named .nc)",
                )
            text = None
            if len(raw) < chunk or raw.endswith(b"\n"):
                try:
                    text = raw.decode("utf-8")
                except UnicodeDecodeError as err:
                    raise InputError(
                        field,
                        f"{name} line {number}: byte {err.start + 1} is not UTF-8 text",
                        "save the record as UTF-8 or ASCII text",
                    ) from None
            if text is None or len(text.rstrip("\r\n")) > MAX_LINE_CHARS:
                raise InputError(
                    field,
                    f"{name} line {number} is longer than {MAX_LINE_CHARS} characters",
                    "give one sample (or one .AT2 row) per line, ending in a line feed",
                )
            if number == 1 and text.startswith("\ufeff"):
                text = text[1:]  # a byte order mark
            yield number, text.rstrip("\r\n")


def check_samples(count: int, field: str, name: str) -> None:
    """An InputError naming ``field`` when a record has more than MAX_RECORD_SAMPLES samples."""
    if count > MAX_RECORD_SAMPLES:
        raise InputError(
            field,
            f"{shown(name)}: more than {MAX_RECORD_SAMPLES} samples "
            f"(the limit, stonedem.motion.records.MAX_RECORD_SAMPLES)",
            "cut or resample the record to a coarser step first",
        )


def check_dt(dt: float, field: str, what: str) -> float:
    """``dt`` [s] when finite and within [MIN_RECORD_DT, MAX_RECORD_DT], else an InputError."""
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise InputError(
            field, f"{what} {dt!r} s is not a positive finite time step", "give dt > 0 in s"
        )
    if not MIN_RECORD_DT <= dt <= MAX_RECORD_DT:
        raise InputError(
            field,
            f"{what} {dt:g} s is outside [{MIN_RECORD_DT:g}, {MAX_RECORD_DT:g}] s "
            "(stonedem.motion.records.MIN_RECORD_DT, MAX_RECORD_DT)",
            "give the record's real time step; resample records finer than 10 kHz",
        )
    return float(dt)


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

_NUMBER = r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?(?![0-9.eE+-])"
_NPTS_NEW = re.compile(
    rf"NPTS\s*=\s*([0-9]+)\s*,?\s*DT\s*=\s*({_NUMBER})", re.IGNORECASE | re.ASCII
)
_NPTS_OLD = re.compile(rf"^\s*([0-9]+)\s+({_NUMBER})\s+NPTS\s*,?\s*DT", re.IGNORECASE | re.ASCII)


def read_at2(path: str | Path, field_name: str = "file") -> Record:
    """Read a PEER NGA ``.AT2`` file: 4 header lines, then acceleration in g, 5 per line.

    Header line 3 must declare the units (``UNITS OF G``); line 4 gives the point count and
    step, new style ``NPTS=  5590, DT=   .0050 SEC`` or old style ``5590 0.0050 NPTS, DT``.
    The number of values read must equal NPTS. Every failure is a one-line InputError
    naming ``field_name`` and the file (limits: :data:`MAX_RECORD_SAMPLES`, the dt range,
    :data:`MAX_RECORD_PGA`; the file is read as UTF-8 text).
    """
    path = Path(path)
    name = shown(path.name)
    where = field_name
    header: list[str] = []
    values = array("d")
    count = 0
    npts = 0
    for number, line in text_lines(path, where):
        if number <= 4:
            header.append(line)
            if number == 3:
                units_line = line.upper()
                if "UNITS OF G" not in units_line and not re.search(r"\bG\b", units_line):
                    raise InputError(
                        where,
                        f"{name}: header line 3 does not declare units of g: "
                        f"'{shown(line.strip(), 50)}'",
                        "PEER AT2 files hold acceleration in g",
                    )
            if number == 4:
                match = _NPTS_NEW.search(line) or _NPTS_OLD.search(line)
                if match is None:
                    raise InputError(
                        where,
                        f"{name}: header line 4 has no NPTS and DT: '{shown(line.strip(), 50)}'",
                        "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'",
                    )
                npts, dt = int(match.group(1)), float(match.group(2))
                if npts < 2:
                    raise InputError(where, f"{name}: NPTS = {npts}", "need at least 2 points")
                check_samples(npts, where, path.name)
                check_dt(dt, where, f"{name}: header DT =")
            continue
        for token in line.split():
            try:
                value = float(token)
            except ValueError:
                raise InputError(
                    where,
                    f"{name} line {number}: non-numeric value '{shown(token, 20)}'",
                    "the data block holds numbers only",
                ) from None
            if count < npts:
                values.append(value)
            count += 1
    if len(header) < 4 or count == 0:
        raise InputError(
            where,
            f"{name}: an AT2 file needs 4 header lines and data",
            "check the file is a PEER .AT2",
        )
    if count != npts:
        raise InputError(
            where,
            f"{name}: header declares NPTS = {npts} but {count} values were read",
            "the file is truncated or the header is wrong",
        )
    with np.errstate(over="ignore"):  # 1e308 g is inf m/s2, refused just below
        accel = np.frombuffer(values, dtype=float) * G_STANDARD
    bad = np.flatnonzero(~np.isfinite(accel))
    if len(bad):
        raise InputError(
            where, f"{name}: NaN or infinite value at sample {bad[0]}", "clean the record"
        )
    check_pga(accel, where, path.name)
    title = shown(header[1].strip(), 200)
    return Record(
        np.arange(npts) * dt,
        accel,
        {
            "source_file": shown(path.name, 200),
            "header": shown(" | ".join(x.strip() for x in header[:2]), 400),
            "title": title,
            "units_in_file": "g",
        },
    )


def check_pga(accel, field: str, name: str) -> None:
    """An InputError naming ``field`` when a record's peak exceeds MAX_RECORD_PGA."""
    peak = float(np.abs(accel).max()) if len(accel) else 0.0
    if not peak <= MAX_RECORD_PGA:
        raise InputError(
            field,
            f"{shown(name)}: peak acceleration {peak:.4g} m/s2 ({peak / G_STANDARD:.3g} g) "
            f"is above the {MAX_RECORD_PGA / G_STANDARD:g} g limit "
            "(stonedem.motion.records.MAX_RECORD_PGA)",
            "check the units (units: g, cm/s2, m/s2) or the file's values",
        )


# --- processing ----------------------------------------------------------------------------


def integrate(time, accel):
    """Velocity [m s-1] and displacement [m] of an acceleration linear between samples (exact).

    v_{i+1} = v_i + h (a_i + a_{i+1}) / 2 and d_{i+1} = d_i + h v_i + h^2 (2 a_i + a_{i+1}) / 6.
    """
    h = np.diff(time)
    vel = np.concatenate([[0.0], np.cumsum(0.5 * h * (accel[:-1] + accel[1:]))])
    disp = np.concatenate(
        [[0.0], np.cumsum(h * vel[:-1] + h * h * (2.0 * accel[:-1] + accel[1:]) / 6.0)]
    )
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
    a = np.asarray(accel, dtype=float)
    peak = float(np.abs(a).max()) if len(a) else 0.0
    if peak == 0.0:
        return a.copy()  # all zeros: at rest already
    # work on a / 2^k ~ 1: exact (a power of two), so records of ordinary size give the same
    # bits, and a record of subnormal values (1e-314) does not overflow in the fit
    scale = math.ldexp(1.0, math.frexp(peak)[1])
    a = a / scale
    a = a - np.mean(a[: max(1, len(a) // 100)])
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
    return (a + c0 * basis0 + c1 * basis1) * scale


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
            out[i] = np.sum(w * a) / np.sum(w)  # NaN when no frequency lies near fc
    return out


def is_constant(accel) -> bool:
    """True when a record has no motion beyond rounding: its range is at most 1e-12 of its peak."""
    a = np.asarray(accel, dtype=float)
    return len(a) == 0 or bool(np.ptp(a) <= 1e-12 * np.abs(a).max())


def predominant_frequency(time, accel, f_min=0.1, f_max=25.0, b=20.0) -> float:
    """Frequency [Hz] of the peak of the Konno-Ohmachi (b = 20) smoothed Fourier amplitude.

    NaN when there is none: an all-zero or constant record (its spectrum is rounding noise
    outside 0 Hz), or a record whose Nyquist frequency is below ``f_min``.
    """
    freq, amp = fourier_amplitude(time, accel)
    if is_constant(accel) or len(freq) < 2 or freq[-1] <= f_min:
        return math.nan
    centres = np.geomspace(f_min, min(f_max, freq[-1]), 300)
    smooth = konno_ohmachi(freq, amp, centres, b)
    if not np.any(np.isfinite(smooth) & (smooth > 0)):
        return math.nan
    return float(centres[np.nanargmax(smooth)])


def response_spectrum(time, accel, periods, damping: float = 0.05):
    """Pseudo-acceleration spectrum PSA = omega^2 max|u| [m s-2] of a SDOF oscillator.

    u'' + 2 zeta omega u' + omega^2 u = -a_g(t), a_g linear between samples: the exact
    recurrence of Nigam and Jennings (1969), vectorised over the periods [s].
    """
    a = np.asarray(accel, dtype=float)
    dt = float(time[1] - time[0])
    periods = np.asarray(periods, dtype=float)
    if not (math.isfinite(damping) and 0.0 <= damping < 1.0):
        raise InputError(
            "damping", f"{damping!r} is not a damping ratio in [0, 1)", "give e.g. 0.05"
        )
    if not np.all(np.isfinite(periods) & (periods > 0)):
        raise InputError("periods", "periods must be finite and > 0 s", "give positive periods")
    w = 2.0 * np.pi / periods
    z = float(damping)
    wd = w * np.sqrt(1.0 - z * z)
    e = np.exp(-z * w * dt)
    s, c = np.sin(wd * dt), np.cos(wd * dt)
    # state transition of (u, v) for one step with a forcing linear over the step
    a11 = e * (z / np.sqrt(1 - z * z) * s + c)
    a12 = e / wd * s
    a21 = -w / np.sqrt(1 - z * z) * e * s
    a22 = e * (c - z / np.sqrt(1 - z * z) * s)
    t2 = 2 * z / (w**3 * dt)
    b11 = (
        e
        * (
            ((2 * z * z - 1) / (w * w * dt) + z / w) * s / wd
            + (2 * z / (w**3 * dt) + 1 / (w * w)) * c
        )
        - t2
    )
    b12 = (
        -e * ((2 * z * z - 1) / (w * w * dt) * s / wd + 2 * z / (w**3 * dt) * c) - 1 / (w * w) + t2
    )
    b21 = e * (
        ((2 * z * z - 1) / (w * w * dt) + z / w) * (c - z / np.sqrt(1 - z * z) * s)
        - (2 * z / (w**3 * dt) + 1 / (w * w)) * (wd * s + z * w * c)
    ) + 1 / (w * w * dt)
    b22 = -e * (
        (2 * z * z - 1) / (w * w * dt) * (c - z / np.sqrt(1 - z * z) * s)
        - 2 * z / (w**3 * dt) * (wd * s + z * w * c)
    ) - 1 / (w * w * dt)
    u = np.zeros_like(w)
    v = np.zeros_like(w)
    peak = np.zeros_like(w)
    for i in range(len(a) - 1):
        p0, p1 = -a[i], -a[i + 1]
        u, v = (a11 * u + a12 * v + b11 * p0 + b12 * p1, a21 * u + a22 * v + b21 * p0 + b22 * p1)
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
        {
            "acceleration": v("time", a, "m s-2", "horizontal ground acceleration, as recorded"),
            "acceleration_corrected": v(
                "time", corrected, "m s-2", "ground acceleration, baseline corrected"
            ),
            "velocity": v("time", vel, "m s-1", "ground velocity (baseline corrected)"),
            "displacement": v("time", disp, "m", "ground displacement (baseline corrected)"),
            "displacement_uncorrected": v(
                "time", raw_disp, "m", "ground displacement integrated from the record as is"
            ),
            "psa": v(("damping", "period"), psa, "m s-2", "pseudo-acceleration response spectrum"),
        },
        coords={
            "time": v("time", t, "s", "time"),
            "period": v("period", SPECTRUM_PERIODS, "s", "oscillator period"),
            "damping": v("damping", np.array(SPECTRUM_DAMPING), "1", "damping ratio"),
        },
        attrs={
            "name": name,
            **(attrs or {}),
            **record.meta,
            "pga": record.pga,
            "pga_units": "m s-2",
            "dt": record.dt,
            "duration": record.duration,
            "predominant_frequency": f_p,
            "predominant_frequency_units": "Hz",
            "predominant_frequency_method": "peak of the Konno-Ohmachi (b = 20) smoothed "
            "Fourier amplitude, 0.1-25 Hz",
            "baseline_correction": "polynomial t^2..t^6 fitted to displacement, then a linear "
            "end correction over the last 10 %",
        },
    )
