"""Base excitations: validated specs -> :class:`BaseMotion` the compiled loop evaluates.

Analytic motions (harmonic displacement, rectangular and one-sine acceleration pulses,
linear acceleration ramp; thesis 5.1.3, 5.1.5, 6.3) and recorded accelerograms share one
interface, so the engine never cares where motion comes from. Records are read from plain
text (two columns time, acceleration; or one column with ``dt``) or NetCDF (``acceleration``
on ``time``), checked, scaled by a factor or to a target PGA, and tabulated for exact
piecewise-linear integration (:mod:`dem.kernels.excitation`). Records are baseline
corrected by default (``baseline: false`` keeps them as recorded; :mod:`dem.records`).
The engine reads a record linearly between samples, which is how it is upsampled to the
solver's step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dem.errors import InputError, check_number
from dem.kernels import excitation as kx
from dem.records import G_STANDARD

RECORDS_DIR = Path(__file__).resolve().parents[2] / "records"
UNIT_FACTORS = {"m/s2": 1.0, "m s-2": 1.0, "m/s^2": 1.0, "g": G_STANDARD, "cm/s2": 0.01,
                "cm s-2": 0.01, "gal": 0.01}
KIND_KEYS = {
    "none": {},
    "harmonic": {"frequency": "Hz", "amplitude": "m", "pga": "m s-2", "ramp_cycles": "1"},
    "rect_pulse": {"accel": "m s-2", "duration": "s"},
    "sine_pulse": {"accel": "m s-2", "frequency": "Hz"},
    "ramp": {"rate": "m s-3"},
    "record": {"file": "", "scale": "1", "pga": "m s-2", "units": "", "dt": "s", "baseline": ""},
}


@dataclass(frozen=True)
class BaseMotion:
    """A base motion as the kernel sees it (:func:`dem.kernels.excitation.base_motion`)."""

    kind: int
    params: np.ndarray  # (4,)
    table_accel: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m s-2]
    table_vel: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m s-1]
    table_disp: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m]
    table_dt: float = 1.0  # [s]
    description: dict = field(default_factory=dict)

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Displacement [m], velocity [m s-1], acceleration [m s-2] at times t [s]."""
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
        out = kx.base_motion_many(t, self.kind, self.params, self.table_accel,
                                  self.table_vel, self.table_disp, self.table_dt)
        return out[0], out[1], out[2]

    @property
    def pga(self) -> float:
        """Peak absolute base acceleration [m s-2]."""
        p = self.params
        if self.kind == kx.KIND_HARMONIC:
            return abs(p[0]) * p[1] ** 2
        if self.kind in (kx.KIND_RECT_PULSE, kx.KIND_SINE_PULSE):
            return abs(p[0])
        if self.kind == kx.KIND_TABLE:
            return float(np.abs(self.table_accel).max())
        return 0.0  # none; a ramp has no peak

    @property
    def duration(self) -> float | None:
        """Natural length of the motion [s] (pulse or record), None when unbounded."""
        if self.kind in (kx.KIND_RECT_PULSE,):
            return float(self.params[1])
        if self.kind == kx.KIND_SINE_PULSE:
            return float(self.params[2])
        if self.kind == kx.KIND_TABLE:
            return (len(self.table_accel) - 1) * self.table_dt
        return None


def _num(spec, key, where, positive=False, required=True, default=None):
    if key not in spec:
        if required:
            raise InputError(f"{where}.{key}", "missing", f"give {key} [{KIND_KEYS_UNITS.get(key, '')}]")
        return default
    return check_number(spec[key], f"{where}.{key}", positive=positive)


KIND_KEYS_UNITS = {k: u for keys in KIND_KEYS.values() for k, u in keys.items()}


def excitation_pair(spec: dict | None, base_dir: Path = Path(".")) -> tuple[BaseMotion, BaseMotion]:
    """(horizontal, vertical) base motions of an ``excitation:`` mapping; vertical from its ``vertical:`` key."""
    spec = dict(spec or {"kind": "none"})
    vertical = spec.pop("vertical", None)
    horizontal = excitation_from_spec(spec, "excitation", base_dir)
    if vertical is not None and not isinstance(vertical, dict):
        raise InputError("excitation.vertical", "expected a mapping", "write vertical: {kind: ...}")
    return horizontal, excitation_from_spec(vertical, "excitation.vertical", base_dir)


def excitation_from_spec(spec: dict | None, field: str = "excitation", base_dir: Path = Path(".")) -> BaseMotion:
    """Validate one excitation mapping and build its BaseMotion (forms: README)."""
    if spec is None:
        spec = {"kind": "none"}
    if not isinstance(spec, dict):
        raise InputError(field, "expected a mapping", "write {kind: none | harmonic | ...}")
    kind = spec.get("kind")
    if kind not in KIND_KEYS:
        raise InputError(f"{field}.kind", f"unknown kind {kind!r}", f"use one of {', '.join(KIND_KEYS)}")
    allowed = ("kind", *KIND_KEYS[kind])
    for key in spec:
        if key not in allowed:
            raise InputError(f"{field}.{key}", f"unknown key for kind {kind}", f"allowed keys: {', '.join(allowed)}")
    params = np.zeros(4)
    description = {"kind": kind}
    if kind == "none":
        return BaseMotion(kx.KIND_NONE, params, description=description)
    if kind == "harmonic":
        f = _num(spec, "frequency", field, positive=True)
        if ("amplitude" in spec) == ("pga" in spec):
            raise InputError(f"{field}.amplitude", "give exactly one of amplitude [m] and pga [m s-2]",
                             "write amplitude: 0.25 or pga: 2.15")
        if "pga" in spec:  # thesis 6.1 sweeps frequency at a fixed peak acceleration: A = PGA / w^2
            amp = _num(spec, "pga", field, positive=True) / (2 * math.pi * f) ** 2
        else:
            amp = _num(spec, "amplitude", field)
        cycles = _num(spec, "ramp_cycles", field, required=False, default=1.0)
        if cycles < 0:
            raise InputError(f"{field}.ramp_cycles", f"must be >= 0, got {cycles}", "give 0 (abrupt) or more")
        params[:3] = amp, 2 * math.pi * f, cycles / f
        description.update(frequency=f, frequency_units="Hz", amplitude=amp, amplitude_units="m",
                           ramp_cycles=cycles, pga=amp * (2 * math.pi * f) ** 2)
        return BaseMotion(kx.KIND_HARMONIC, params, description=description)
    if kind == "rect_pulse":
        a_p = _num(spec, "accel", field)
        t_p = _num(spec, "duration", field, positive=True)
        params[:2] = a_p, t_p
        description.update(accel=a_p, accel_units="m s-2", duration=t_p, duration_units="s")
        return BaseMotion(kx.KIND_RECT_PULSE, params, description=description)
    if kind == "sine_pulse":
        a_p = _num(spec, "accel", field)
        f = _num(spec, "frequency", field, positive=True)
        params[:3] = a_p, 2 * math.pi * f, 1.0 / f
        description.update(accel=a_p, accel_units="m s-2", frequency=f, frequency_units="Hz")
        return BaseMotion(kx.KIND_SINE_PULSE, params, description=description)
    if kind == "ramp":
        rate = _num(spec, "rate", field)
        params[0] = rate
        description.update(rate=rate, rate_units="m s-3")
        return BaseMotion(kx.KIND_RAMP, params, description=description)
    return _record_motion(spec, field, Path(base_dir))


def _record_motion(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    if "file" not in spec:
        raise InputError(f"{field}.file", "missing", "give the record file (path or name in records/)")
    if "scale" in spec and "pga" in spec:
        raise InputError(field, "give scale or pga, not both", "remove one of them")
    path = resolve_record(str(spec["file"]), f"{field}.file", base_dir)
    units = spec.get("units")
    if units is not None and units not in UNIT_FACTORS:
        raise InputError(f"{field}.units", f"unknown units {units!r}", f"use one of {', '.join(UNIT_FACTORS)}")
    dt = _num(spec, "dt", field, positive=True, required=False)
    baseline = spec.get("baseline", True)
    if not isinstance(baseline, bool):
        raise InputError(f"{field}.baseline", "expected true or false", "write baseline: true")
    time, accel, meta = read_record(path, f"{field}.file", units=units, dt=dt)
    if baseline:
        from dem.records import baseline_correct

        accel = baseline_correct(time, accel)
    pga_raw = float(np.abs(accel).max())
    if "pga" in spec:
        target = _num(spec, "pga", field, positive=True)
        if pga_raw == 0.0:
            raise InputError(f"{field}.pga", "the record is all zeros", "use a record with motion")
        scale = target / pga_raw
    else:
        scale = _num(spec, "scale", field, required=False, default=1.0)
    accel = accel * scale
    table_a, table_v, table_d, h = record_to_table(time, accel)
    description = {"kind": "record", "file": str(path), "scale": scale, "baseline_corrected": int(baseline),
                   "pga": float(np.abs(accel).max()),
                   "pga_units": "m s-2", "record_pga": pga_raw, "record_dt": h,
                   "record_duration": float(time[-1] - time[0]), **meta}
    return BaseMotion(kx.KIND_TABLE, np.zeros(4), table_a, table_v, table_d, h, description)


def resolve_record(name: str, field: str, base_dir: Path) -> Path:
    """A record path: as given, relative to the scene, or by name in the repository's records/."""
    candidates = [Path(name), base_dir / name, RECORDS_DIR / name]
    for folder in (base_dir, RECORDS_DIR):
        for ext in (".nc", ".AT2", ".at2", ".txt", ".csv", ".dat"):
            candidates.append(folder / f"{name}{ext}")
    for path in candidates:
        if path.is_file():
            return path
    raise InputError(field, f"record '{name}' not found", f"give a path or a name in {RECORDS_DIR}")


def read_record(path: Path, field: str, units: str | None = None, dt: float | None = None):
    """(time [s] from 0, acceleration [m s-2], metadata) of a NetCDF or text record, checked."""
    meta: dict = {}
    if path.suffix.lower() == ".at2":
        from dem.records import read_at2

        rec = read_at2(path, field)
        time, accel, units = rec.time, rec.acceleration, "m/s2"
        meta = {"title": rec.meta.get("title", "")}
    elif path.suffix == ".nc":
        import xarray as xr

        with xr.open_dataset(path) as ds:
            if "acceleration" not in ds:
                raise InputError(field, f"{path.name} has no variable 'acceleration'", "store acceleration on time")
            accel = ds["acceleration"].values.astype(float)
            time = ds["acceleration"]["time"].values.astype(float)
            units = units or ds["acceleration"].attrs.get("units", "m s-2")
            meta = {k: str(v) for k, v in ds.attrs.items() if k in ("title", "event", "station", "component", "source")}
            if units not in UNIT_FACTORS:
                raise InputError(field, f"{path.name}: unknown acceleration units {units!r}",
                                 f"use one of {', '.join(UNIT_FACTORS)}")
    else:
        time, accel, header_dt = _read_text_record(path, field)
        dt = dt or header_dt
        if time is None:
            if dt is None:
                raise InputError(field, f"{path.name} has one column and no time step",
                                 "add a header line 'dt = 0.01' or the key dt:")
            time = np.arange(len(accel)) * dt
        units = units or "m/s2"
    accel = accel * UNIT_FACTORS[units]
    _check_record(time, accel, field, path)
    if time[0] != 0.0:
        meta["time_shift"] = float(-time[0])
        time = time - time[0]
    return time, accel, meta


def _read_text_record(path: Path, field: str):
    rows, header_dt, n_cols = [], None, None
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        text = line.split("#", 1)[0].strip()
        if line.lstrip().startswith("#") and "dt" in line and "=" in line:
            try:
                header_dt = float(line.split("=", 1)[1].split()[0])
            except (ValueError, IndexError):
                pass
        if not text:
            continue
        if text.lower().startswith("dt") and "=" in text:
            try:
                header_dt = float(text.split("=", 1)[1].split()[0])
            except (ValueError, IndexError):
                raise InputError(field, f"{path.name} line {number}: bad dt header", "write dt = 0.01") from None
            continue
        parts = text.replace(",", " ").split()
        try:
            values = [float(p) for p in parts]
        except ValueError:
            raise InputError(field, f"{path.name} line {number}: non-numeric value in '{text[:40]}'",
                             "give numbers only (comments start with #)") from None
        if n_cols is None:
            n_cols = len(values)
            if n_cols not in (1, 2):
                raise InputError(field, f"{path.name} line {number}: {n_cols} columns",
                                 "give time and acceleration, or acceleration alone with dt")
        elif len(values) != n_cols:
            raise InputError(field, f"{path.name} line {number}: {len(values)} columns, expected {n_cols}",
                             "fix the row")
        rows.append(values)
    if not rows:
        raise InputError(field, f"{path.name} holds no samples", "give at least two samples")
    data = np.array(rows)
    if n_cols == 2:
        return data[:, 0], data[:, 1], header_dt
    return None, data[:, 0], header_dt


def _check_record(time, accel, field, path):
    if len(accel) < 2:
        raise InputError(field, f"{path.name}: fewer than 2 samples", "give a longer record")
    bad = np.flatnonzero(~np.isfinite(accel) | ~np.isfinite(time))
    if len(bad):
        raise InputError(field, f"{path.name}: NaN or infinite value at sample {bad[0]}", "clean the record")
    steps = np.diff(time)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise InputError(field, f"{path.name}: time not increasing at sample {i + 1} (t = {time[i + 1]:g} s)",
                         "sort the samples and remove duplicates")
    h = float(np.mean(steps))
    if np.ptp(steps) > 1e-6 * h:
        raise InputError(field, f"{path.name}: non-uniform time step ({steps.min():g} to {steps.max():g} s)",
                         "resample to a uniform step first (not done here)")


def record_to_table(time, accel):
    """Acceleration samples -> (accel, exact node velocity, exact node displacement, step [s])."""
    from dem.records import integrate

    accel = np.ascontiguousarray(accel, dtype=float)
    h = float((time[-1] - time[0]) / (len(time) - 1))
    vel, disp = integrate(np.arange(len(accel)) * h, accel)
    return accel, vel, disp, h
