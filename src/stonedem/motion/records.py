"""Recorded accelerograms: read, resample, baseline-correct, integrate, scale, characterise.

Thesis 6.4 drives the columns with recorded earthquakes of very different frequency content
(Table 6.1) and plots their 10 %-damped response spectra (Fig. 6.14). This module reads
PEER NGA ``.AT2`` files (our own parser: both header styles, point count checked, no
``eval``) and plain text, resamples without aliasing, removes baseline drift so the base
displacement returns to rest, integrates exactly (acceleration linear between samples),
scales to a target PGA, and computes the predominant frequency (peak of the Konno-Ohmachi
smoothed Fourier amplitude) and pseudo-acceleration response spectra at any damping
(exact piecewise-linear SDOF recurrence of Nigam and Jennings).

A scene's record is found by name or path (:func:`resolve_record`: the checkout's
``records/``, then the records installed with the package) and read from plain text (two
columns time, acceleration; or one column with ``dt``), ``.AT2`` or NetCDF (``acceleration``
on ``time``) with every check of :func:`read_record`; :mod:`stonedem.motion.excitation` reads
each once per file and settings a process and makes a base motion of it.
"""

from __future__ import annotations

import math
import os
import re
from array import array
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, NoReturn

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import Field, Rule, Spec, at_least_one, not_both
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
DT_FIX = "give the record's real time step; resample records finer than 10 kHz"


def shown(text, limit: int = 60) -> str:
    """``text`` fit for a one-line message: control characters escaped, at most ``limit`` chars."""
    text = str(text)
    cut = len(text) > limit
    out = "".join(
        ch if ch.isprintable() else ch.encode("unicode_escape", "backslashreplace").decode("ascii")
        for ch in text[:limit]
    )
    return out + "..." if cut else out


def file_error(field: str, name, problem: str, fix: str, line: int | None = None) -> NoReturn:
    """Raise the one-line InputError of a record file's content, naming ``field``:
    ``<file name>[ line N]: <problem>; <fix>`` (every refusal of a file's content has this
    shape)."""
    at = f" line {line}" if line is not None else ""
    raise InputError(field, f"{shown(name)}{at}: {problem}", fix) from None


UNREADABLE = "give a readable record file"


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
        file_error(field, path.name, f"cannot read ({_reason(err)})", UNREADABLE)
    if not stat.S_ISREG(info.st_mode):
        file_error(field, path.name, "not a regular file", "give a record file")
    if info.st_size > max_bytes:
        file_error(
            field,
            path.name,
            f"{info.st_size / 2**20:.0f} MB, above the {max_bytes / 2**20:.0f} MB limit for "
            "text records",
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
    try:
        handle = open(path, "rb")
    except OSError as err:
        file_error(field, path.name, f"cannot read ({_reason(err)})", UNREADABLE)
    chunk = MAX_LINE_CHARS * 4 + 2  # bytes: a UTF-8 character takes at most 4
    with handle:
        number = 0
        while True:
            try:
                raw = handle.readline(chunk)
            except OSError as err:
                file_error(field, path.name, f"cannot read ({_reason(err)})", UNREADABLE)
            if not raw:
                return
            number += 1
            if b"\0" in raw:
                file_error(
                    field,
                    path.name,
                    "a NUL byte, this is a binary file",
                    "give a text record (or a NetCDF one named .nc)",
                    number,
                )
            text = None
            if len(raw) < chunk or raw.endswith(b"\n"):
                try:
                    text = raw.decode("utf-8")
                except UnicodeDecodeError as err:
                    file_error(
                        field,
                        path.name,
                        f"byte {err.start + 1} is not UTF-8 text",
                        "save the record as UTF-8 or ASCII text",
                        number,
                    )
            if text is None or len(text.rstrip("\r\n")) > MAX_LINE_CHARS:
                file_error(
                    field,
                    path.name,
                    f"longer than {MAX_LINE_CHARS} characters",
                    "give one sample (or one .AT2 row) per line, ending in a line feed",
                    number,
                )
            if number == 1 and text.startswith("\ufeff"):
                text = text[1:]  # a byte order mark
            yield number, text.rstrip("\r\n")


def check_samples(count: int, field: str, name: str) -> None:
    """An InputError naming ``field`` when a record has more than MAX_RECORD_SAMPLES samples."""
    if count > MAX_RECORD_SAMPLES:
        file_error(
            field,
            name,
            f"more than {MAX_RECORD_SAMPLES} samples "
            f"(the limit, stonedem.motion.records.MAX_RECORD_SAMPLES)",
            "cut or resample the record to a coarser step first",
        )


def check_dt(dt: float, field: str, what: str) -> float:
    """``dt`` [s] of a record file (its header or its time column) when within
    [MIN_RECORD_DT, MAX_RECORD_DT], else an InputError; ``what`` says where it was read. A dt
    key or option is the field RECORD_KEYS["dt"], the same range."""
    if not (isinstance(dt, (int, float)) and MIN_RECORD_DT <= dt <= MAX_RECORD_DT):  # NaN too
        raise InputError(
            field,
            f"{what} {dt:g} s is outside [{MIN_RECORD_DT:g}, {MAX_RECORD_DT:g}] s "
            "(stonedem.motion.records.MIN_RECORD_DT, MAX_RECORD_DT)",
            DT_FIX,
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
                    file_error(
                        where,
                        path.name,
                        f"header line 3 does not declare units of g: '{shown(line.strip(), 50)}'",
                        "PEER AT2 files hold acceleration in g",
                    )
            if number == 4:
                match = _NPTS_NEW.search(line) or _NPTS_OLD.search(line)
                if match is None:
                    file_error(
                        where,
                        path.name,
                        f"header line 4 has no NPTS and DT: '{shown(line.strip(), 50)}'",
                        "expected 'NPTS= n, DT= dt SEC' or 'n dt NPTS, DT'",
                    )
                npts, dt = int(match.group(1)), float(match.group(2))
                if npts < 2:
                    file_error(where, path.name, f"NPTS = {npts}", "need at least 2 points")
                check_samples(npts, where, path.name)
                check_dt(dt, where, f"{name}: header DT =")
            continue
        for token in line.split():
            try:
                value = float(token)
            except ValueError:
                file_error(
                    where,
                    path.name,
                    f"non-numeric value '{shown(token, 20)}'",
                    "the data block holds numbers only",
                    number,
                )
            if count < npts:
                values.append(value)
            count += 1
    if len(header) < 4 or count == 0:
        file_error(
            where,
            path.name,
            "an AT2 file needs 4 header lines and data",
            "check the file is a PEER .AT2",
        )
    if count != npts:
        file_error(
            where,
            path.name,
            f"header declares NPTS = {npts} but {count} values were read",
            "the file is truncated or the header is wrong",
        )
    with np.errstate(over="ignore"):  # 1e308 g is inf m/s2, refused just below
        accel = np.frombuffer(values, dtype=float) * G_STANDARD
    _check_finite(where, path.name, accel)
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


def _check_finite(field: str, name: str, *arrays) -> None:
    """An InputError at the first sample where one of ``arrays`` is NaN or infinite."""
    bad = np.flatnonzero(~np.logical_and.reduce([np.isfinite(a) for a in arrays]))
    if len(bad):
        file_error(field, name, f"NaN or infinite value at sample {bad[0]}", "clean the record")


def check_pga(accel, field: str, name: str) -> None:
    """An InputError naming ``field`` when a record's peak exceeds MAX_RECORD_PGA."""
    peak = float(np.abs(accel).max()) if len(accel) else 0.0
    if not peak <= MAX_RECORD_PGA:
        file_error(
            field,
            name,
            f"peak acceleration {peak:.4g} m/s2 ({peak / G_STANDARD:.3g} g) "
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


# the arguments of response_spectrum (stonedem record info's --damping is checked the same)
SPECTRUM_KEYS = Spec(
    (
        Field("periods", "numbers", "s", "(0, inf)", hint="give positive periods"),
        Field("damping", "number", "1", "[0, 1)", hint="give a damping ratio, e.g. 0.05"),
    )
)


def response_spectrum(time, accel, periods, damping: float = 0.05):
    """Pseudo-acceleration spectrum PSA = omega^2 max|u| [m s-2] of a SDOF oscillator.

    u'' + 2 zeta omega u' + omega^2 u = -a_g(t), a_g linear between samples: the exact
    recurrence of Nigam and Jennings (1969), vectorised over the periods [s].
    """
    a = np.asarray(accel, dtype=float)
    dt = float(time[1] - time[0])
    periods = np.asarray(periods, dtype=float)
    SPECTRUM_KEYS["periods"].check(periods.ravel())
    z = SPECTRUM_KEYS["damping"].check(damping)
    w = 2.0 * np.pi / periods
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


# --- reading a record file: by name or path, text or NetCDF, checked (stonedem.motion.excitation
# builds a base motion of it) -------------------------------------------------------------

UNIT_FACTORS = {
    "m/s2": 1.0,
    "m s-2": 1.0,
    "m/s^2": 1.0,
    "g": G_STANDARD,
    "cm/s2": 0.01,
    "cm s-2": 0.01,
    "gal": 0.01,
}
RECORD_SUFFIXES = (".nc", ".AT2", ".at2", ".txt", ".csv", ".dat")
TIME_UNITS = ("s", "sec", "second", "seconds")  # accepted units of a NetCDF record's time


class KeyRule(Rule):
    """A rule of the kit whose refusal names its first key (``excitation.file``, as the scene's
    messages always have), and that takes a null value for an absent key, as a field does."""

    def check(self, mapping, where: str) -> None:
        given = {k: v for k, v in mapping.items() if v is not None}
        super().check(given, f"{where}.{self.keys[0]}" if where else self.keys[0])


def first_key(rule: Rule) -> KeyRule:
    """``rule`` (exactly_one, not_both, ...) refused as :class:`KeyRule`."""
    return KeyRule(rule.name, rule.keys, rule.problem, rule.fix)


_SUITE_UNITS = "drop {}: a suite component carries its own units and dt"

# the keys of a ``kind: record`` excitation (stonedem.motion.excitation); the file, its units
# and the dt are checked against the file itself by read_record
RECORD_KEYS = Spec(
    (
        Field(
            "file",
            "any",
            hint="give the record file: a path, or a name in records/",
            doc="the record: a path (from the scene's folder) or a name in records/ "
            "(.nc, .AT2, text)",
        ),
        Field(
            "component",
            "any",  # its name is checked by stonedem.motion.suites.suite_of
            doc="a FEMA P695 component (FF07a); without file, read from its suite file",
        ),
        Field("scale", units="1", default=1.0, doc="factor on the record's acceleration"),
        Field(
            "pga",
            units="m s-2",
            range=f"(0, {MAX_RECORD_PGA!r}]",
            hint="give a peak ground acceleration in m/s2 (above the "
            f"{MAX_RECORD_PGA / G_STANDARD:g} g limit it is a units mistake)",
            doc="the record scaled to this peak ground acceleration",
        ),
        Field(
            "units",
            "any",
            hint=f"use one of {', '.join(UNIT_FACTORS)}",
            doc="acceleration units of a text record: m/s2 (default), g, cm/s2 (.AT2 and "
            "NetCDF records carry their own)",
        ),
        Field(
            "dt",
            units="s",
            range=f"[{MIN_RECORD_DT!r}, {MAX_RECORD_DT!r}]",
            hint=DT_FIX,
            doc="time step of a one-column text record",
        ),
        Field(
            "baseline",
            "flag",
            default=True,
            doc="baseline correction, so the base ends at rest (false: as recorded)",
        ),
    ),
    rules=(
        first_key(
            at_least_one(
                "file",
                "component",
                fix="give the record file (path or name in records/), or a suite component",
            )
        ),
        not_both("scale", "pga", fix="remove one of them"),
        first_key(not_both("component", "units", fix=_SUITE_UNITS.format("units"))),
        first_key(not_both("component", "dt", fix=_SUITE_UNITS.format("dt"))),
    ),
)


def checkout_records_dir() -> Path | None:
    """The top-level ``records/`` of a source checkout this module runs from (editable install)."""
    here = Path(__file__).resolve()
    root = here.parents[3]
    if (
        here.parents[2].name == "src"
        and (root / "pyproject.toml").is_file()
        and (root / "records").is_dir()
    ):
        return root / "records"
    return None


def packaged_records_dir() -> Path | None:
    """The records installed as package data ``stonedem._records`` (``pip install .``), if any.

    pyproject.toml maps the package ``stonedem._records`` onto the top-level ``records/`` folder
    and ships its ``*.nc``; found through the import system (importlib), so it is wherever
    ``stonedem`` was installed. None in a checkout (there ``stonedem._records`` is a placeholder).
    """
    import importlib.util

    try:
        spec = importlib.util.find_spec("stonedem._records")
    except (ImportError, ValueError):
        return None
    for location in (spec.submodule_search_locations or []) if spec else []:
        folder = Path(location)
        if folder.is_dir() and any(folder.glob("*.nc")):
            return folder
    return None


def record_folders() -> list[Path]:
    """Where record names are looked up: the checkout's records/, then the installed records."""
    folders = []
    for folder in (checkout_records_dir(), packaged_records_dir()):
        if folder is not None and folder not in folders:
            folders.append(folder)
    return folders


_folders = record_folders()
RECORDS_DIR = _folders[0] if _folders else Path(__file__).resolve().parents[3] / "records"


MAX_NAME_CHARS = 4096


# (name, base_dir, working folder, the records folders' finders) -> the record file found for
# it: the lookup stats up to a dozen paths (0.65 ms), now once a process while the file is there
_RESOLVED: dict = {}


def resolve_record(name: str, field: str, base_dir: Path) -> Path:
    """A record path: as given, relative to the scene, or by name in a records folder.

    Names are looked up (with or without a suffix of :data:`RECORD_SUFFIXES`) in the
    checkout's ``records/`` and in the records installed with the package
    (:func:`record_folders`), so ``athens_standin_kocaeli_arc000`` works from any install.
    The path must be a regular file; anything else is a one-line InputError naming ``field``.
    """
    if isinstance(name, (Path, int)) and not isinstance(name, bool):
        name = str(name)  # a path from a script; a number from YAML (file: 2024)
    problem = _unusable_name(name)
    if problem:
        raise InputError(
            field, problem, "give a record file's path or name, e.g. northridge_1994_mul009"
        )
    key = (name, str(base_dir), os.getcwd(), checkout_records_dir, packaged_records_dir)
    found = _RESOLVED.get(key)
    if found is not None and found.is_file():  # a search resolves its record once a run
        return found
    folders = record_folders()
    candidates = [Path(name), Path(base_dir) / name, *(folder / name for folder in folders)]
    for folder in (Path(base_dir), *folders):
        for ext in RECORD_SUFFIXES:
            candidates.append(folder / f"{name}{ext}")
    not_files, dangling = [], []
    for path in candidates:
        try:
            if path.is_file():
                if len(_RESOLVED) >= 256:
                    _RESOLVED.clear()
                _RESOLVED[key] = path
                return path
            if path.exists():
                not_files.append(path)
            elif path.is_symlink():  # a link to nothing, or a symlink loop
                dangling.append(path)
        except (OSError, ValueError):
            continue
    if not_files:
        folder = " (a folder)" if not_files[0].is_dir() else ""
        file_error(field, not_files[0], f"not a record file{folder}", "give a record file")
    if dangling:
        file_error(
            field,
            dangling[0],
            "a symbolic link that cannot be followed (a loop, or to nothing)",
            "give the record file itself",
        )
    known = sorted({p.stem for folder in folders for p in folder.glob("*.nc")})
    where = " or ".join(str(f) for f in folders) or "records/ (none installed)"
    listing = f" ({', '.join(known[:8])}{', ...' if len(known) > 8 else ''})" if known else ""
    raise InputError(
        field, f"record '{shown(name)}' not found", f"give a path or a name in {where}{listing}"
    )


def _unusable_name(name) -> str:
    """What is wrong with a record name, "" when nothing."""
    if not isinstance(name, str):
        return f"expected a file name or path, got {shown(repr(name))}"
    if not name.strip():
        return "empty record name"
    if "\0" in name or len(name) > MAX_NAME_CHARS:
        why = "a NUL character" if "\0" in name else f"over {MAX_NAME_CHARS} characters"
        return f"'{shown(name)}' is not a usable file name ({why})"
    return ""


def check_units(units, field: str) -> str | None:
    """The units name (stripped, lower case) when known, None when not given, else an InputError."""
    if units is None:
        return None
    if not isinstance(units, str) or units.strip().lower() not in UNIT_FACTORS:
        raise InputError(
            field, f"unknown units {shown(repr(units))}", f"use one of {', '.join(UNIT_FACTORS)}"
        )
    return units.strip().lower()


def read_record(
    path: Path,
    field: str,
    units: str | None = None,
    dt: float | None = None,
    *,
    units_field: str | None = None,
    dt_field: str | None = None,
):
    """(time [s] from 0, acceleration [m s-2], metadata) of a NetCDF, .AT2 or text record, checked.

    ``units`` and ``dt`` are for records that do not carry them (text); a NetCDF record with
    a ``units`` attribute and an .AT2 (in g, DT in its header) carry their own, and a
    conflicting ``units`` or ``dt`` is refused naming ``units_field`` / ``dt_field``
    (default: the scene's keys beside ``field``). Limits: :mod:`stonedem.motion.records`
    ``MAX_RECORD_*``."""
    path = Path(path)
    base = field.rsplit(".", 1)[0] + "." if "." in field else ""
    units_field = units_field or f"{base}units"
    dt_field = dt_field or f"{base}dt"
    units_label, dt_label = (
        units_field.rsplit(".", 1)[-1],
        dt_field.rsplit(".", 1)[-1],
    )  # key or --option
    units = check_units(units, units_field)
    dt = RECORD_KEYS["dt"].check(dt, dt_field) if dt is not None else None
    name = shown(path.name)
    meta: dict = {}
    suffix = path.suffix.lower()
    if suffix == ".at2":
        from stonedem.motion.records import read_at2

        rec = read_at2(path, field)
        if units is not None and UNIT_FACTORS[units] != G_STANDARD:
            file_error(
                units_field,
                path.name,
                f"a PEER .AT2 record in g, {units_label} gives '{units}'",
                "drop the units: an .AT2 record carries its own",
            )
        time, accel, file_units = rec.time, rec.acceleration, "m/s2"
        meta = {"title": rec.meta.get("title", "")}
    elif suffix == ".nc":
        time, accel, file_units, meta = _read_netcdf(path, field, units, units_field)
    else:
        time, accel, header_dt = _read_text_record(path, field)
        if time is None:
            if dt is not None and header_dt is not None and not _same_step(dt, header_dt):
                file_error(
                    dt_field,
                    path.name,
                    f"declares dt = {header_dt:g} s, {dt_label} gives {dt:g} s",
                    "drop one of them",
                )
            step = dt if dt is not None else header_dt
            if step is None:
                file_error(
                    field,
                    path.name,
                    "one column and no time step",
                    "add a header line 'dt = 0.01' or the key dt:",
                )
            check_dt(step, dt_field if dt is not None else field, f"{name}: dt =")
            time = np.arange(len(accel)) * step
            dt = None  # used
        file_units = units or "m/s2"
    with np.errstate(over="ignore", invalid="ignore"):
        accel = accel * UNIT_FACTORS[file_units]
    _check_record(time, accel, field, path)
    file_dt = float((time[-1] - time[0]) / (len(time) - 1))
    if dt is not None and not _same_step(dt, file_dt):
        file_error(
            dt_field,
            path.name,
            f"has a time step of {file_dt:g} s, {dt_label} gives {dt:g} s",
            "drop dt: it is only for one-column text records",
        )
    if time[0] != 0.0:
        meta["time_shift"] = float(-time[0])
        time = time - time[0]
    return time, accel, meta


def _same_step(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-6 * max(abs(a), abs(b))


def _read_netcdf(path: Path, field: str, units: str | None, units_field: str):
    """(time, acceleration, units name, meta) of a NetCDF record, every failure an InputError."""
    import warnings

    import xarray as xr

    name = path.name
    check_record_file(
        path, field, max_bytes=2**62
    )  # regular file; size is bounded per variable below
    fix = "store 'acceleration' [m s-2] on a 'time' coordinate [s] (see records/README.md)"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = xr.open_dataset(path, decode_times=False, decode_timedelta=False, cache=False)
    except Exception as err:  # netCDF4, h5netcdf and scipy raise many types on junk
        file_error(
            field,
            name,
            f"not a readable NetCDF file ({_reason(err)})",
            "give a NetCDF record, or a text or .AT2 record with its own suffix",
        )
    with ds:
        if "acceleration" not in ds.variables:
            have = ", ".join(shown(v, 30) for v in list(ds.variables)[:6]) or "none"
            file_error(field, name, f"no variable 'acceleration' (it has: {have})", fix)
        var = ds.variables["acceleration"]
        if tuple(var.dims) != ("time",):
            dims = shown(tuple(var.dims))
            file_error(field, name, f"'acceleration' has dimensions {dims}, expected (time,)", fix)
        if "time" not in ds.variables or tuple(ds.variables["time"].dims) != ("time",):
            file_error(field, name, "no 'time' coordinate for 'acceleration'", fix)
        tvar = ds.variables["time"]
        check_samples(int(var.size), field, name)
        for label, v in (("acceleration", var), ("time", tvar)):
            if v.dtype.kind not in "iuf":
                file_error(field, name, f"'{label}' holds {shown(v.dtype)}, not real numbers", fix)
        file_units = var.attrs.get("units")
        if file_units is not None:
            if not isinstance(file_units, str) or file_units.strip().lower() not in UNIT_FACTORS:
                file_error(
                    field,
                    name,
                    f"unknown acceleration units {shown(repr(file_units))}",
                    f"use one of {', '.join(UNIT_FACTORS)}",
                )
            file_units = file_units.strip().lower()
            if units is not None and UNIT_FACTORS[units] != UNIT_FACTORS[file_units]:
                file_error(
                    units_field,
                    name,
                    f"declares its acceleration in '{shown(file_units)}', "
                    f"{units_field.rsplit('.', 1)[-1]} gives '{units}'",
                    "drop the units: a NetCDF record carries its own",
                )
        else:
            file_units = units or "m s-2"
        time_units = tvar.attrs.get("units", "s")
        if not isinstance(time_units, str) or time_units.strip().lower() not in TIME_UNITS:
            file_error(
                field,
                name,
                f"time units {shown(repr(time_units))}, expected s",
                "store time in seconds (units: s)",
            )
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                accel = np.asarray(var.values, dtype=float)
                time = np.asarray(tvar.values, dtype=float)
        except Exception as err:
            file_error(field, name, f"cannot read 'acceleration' ({_reason(err)})", fix)
        meta = {
            k: shown(v, 200)
            for k, v in ds.attrs.items()
            if k in ("title", "event", "station", "component", "source")
        }
    return time, accel, file_units, meta


_DT_HEADER = re.compile(r"^#*\s*dt\s*[=:]\s*(\S*)", re.IGNORECASE)


def _read_text_record(path: Path, field: str):
    """(time or None, acceleration, dt from a header line or None) of a text record."""
    name = path.name
    values = array("d")
    header_dt, n_cols, n_rows = None, None, 0
    for number, line in text_lines(path, field):
        stripped = line.strip()
        header = _DT_HEADER.match(stripped)
        if header:
            try:
                value = float(header.group(1).rstrip(",;"))
            except ValueError:
                file_error(
                    field,
                    name,
                    f"bad dt header '{shown(stripped, 40)}'",
                    "write dt = 0.01",
                    number,
                )
            if header_dt is not None and value != header_dt:
                file_error(
                    field,
                    name,
                    f"a second dt header ({value:g} s after {header_dt:g} s)",
                    "keep one dt header",
                    number,
                )
            header_dt = value
            continue
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        parts = text.replace(",", " ").replace(";", " ").split()
        try:
            row = [float(p) for p in parts]
        except ValueError:
            file_error(
                field,
                name,
                f"non-numeric value in '{shown(text, 40)}'",
                "give numbers only (comments start with #; a PEER record must end in .AT2)",
                number,
            )
        if n_cols is None:
            n_cols = len(row)
            if n_cols not in (1, 2):
                file_error(
                    field,
                    name,
                    f"{n_cols} columns",
                    "give time and acceleration, or acceleration alone with dt",
                    number,
                )
        elif len(row) != n_cols:
            file_error(field, name, f"{len(row)} columns, expected {n_cols}", "fix the row", number)
        n_rows += 1
        check_samples(n_rows, field, name)
        values.extend(row)
    if not n_rows:
        file_error(field, name, "no samples", "give at least two samples")
    data = np.frombuffer(values, dtype=float).reshape(n_rows, n_cols)
    if n_cols == 2:
        return data[:, 0].copy(), data[:, 1].copy(), header_dt
    return None, data[:, 0].copy(), header_dt


def _check_record(time, accel, field, path):
    name = path.name
    if len(accel) < 2:
        file_error(field, name, "fewer than 2 samples", "give a longer record")
    check_samples(len(accel), field, name)
    _check_finite(field, name, accel, time)
    with np.errstate(over="ignore", invalid="ignore"):
        steps = np.diff(time)
    if not np.all(np.isfinite(steps)):
        file_error(
            field, name, "time values too large to take differences", "give time in s from 0"
        )
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        file_error(
            field,
            name,
            f"time not increasing at sample {i + 1} (t = {time[i + 1]:g} s)",
            "sort the samples and remove duplicates",
        )
    h = float((time[-1] - time[0]) / (len(time) - 1))
    if np.ptp(steps) > 1e-6 * h:
        file_error(
            field,
            name,
            f"non-uniform time step ({steps.min():g} to {steps.max():g} s)",
            "resample to a uniform step first (not done here)",
        )
    check_dt(h, field, f"{shown(name)}: time step")
    check_pga(accel, field, name)


def record_to_table(time, accel):
    """Acceleration samples -> (accel, exact node velocity, exact node displacement, step [s])."""
    from stonedem.motion.records import integrate

    accel = np.ascontiguousarray(accel, dtype=float)
    h = float((time[-1] - time[0]) / (len(time) - 1))
    vel, disp = integrate(np.arange(len(accel)) * h, accel)
    return accel, vel, disp, h
