"""Base excitations: validated specs -> :class:`BaseMotion` the compiled loop evaluates.

Analytic motions (harmonic displacement, rectangular and one-sine acceleration pulses,
linear acceleration ramp; thesis 5.1.3, 5.1.5, 6.3) and recorded accelerograms share one
interface, so the engine never cares where motion comes from. A record is read and checked
by :mod:`stonedem.motion.records` (:func:`~stonedem.motion.records.read_record`), baseline
corrected by default (``baseline: false`` keeps it as recorded), scaled here by a factor or to
a target PGA, and tabulated for exact piecewise-linear integration
(:mod:`stonedem.kernels.excitation`).
The engine reads a record linearly between samples, which is how it is upsampled to the
solver's step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from stonedem.errors import InputError, check_number
from stonedem.kernels import excitation as kx
from stonedem.motion.records import (
    G_STANDARD,
    MAX_RECORD_PGA,
    check_units,
    read_record,
    record_to_table,
    resolve_record,
    shown,
)


@dataclass(frozen=True)
class BaseMotion:
    """A base motion as the kernel sees it (:func:`stonedem.kernels.excitation.base_motion`)."""

    kind: int
    params: np.ndarray  # (4,)
    table_accel: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m s-2]
    table_vel: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m s-1]
    table_disp: np.ndarray = field(default_factory=lambda: np.zeros(1))  # [m]
    table_dt: float = 1.0  # [s]
    description: dict = field(default_factory=dict)  # "kind": its row of EXCITATIONS

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Displacement [m], velocity [m s-1], acceleration [m s-2] at times t [s]."""
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
        if self.kind == kx.KIND_NONE:  # at rest, as base_motion gives it, without the call
            out = np.zeros((3, t.shape[0]))
            return out[0], out[1], out[2]
        out = kx.base_motion_many(
            t,
            self.kind,
            self.params,
            self.table_accel,
            self.table_vel,
            self.table_disp,
            self.table_dt,
        )
        return out[0], out[1], out[2]

    @property
    def row(self) -> "Excitation":
        return EXCITATIONS[self.description.get("kind", "none")]

    @property
    def pga(self) -> float:
        """Peak absolute base acceleration [m s-2] (0 for none; a ramp has no peak)."""
        return float(self.row.pga(self))

    @property
    def duration(self) -> float | None:
        """Natural length of the motion [s] (pulse or record), None when unbounded."""
        return self.row.duration(self)

    @property
    def shortest_period(self) -> float:
        """Shortest time scale [s] the time step must resolve (inf: none)."""
        return float(self.row.period(self))

    @property
    def label(self) -> str:
        """E.g. 'harmonic 0.5 Hz x 0.25 m (PGA 2.47 m/s2)'."""
        return excitation_label(self.description)


@dataclass(frozen=True)
class Excitation:
    """One excitation kind: everything the Python side knows of it, in one row of EXCITATIONS.

    A new kind is its branch in :func:`stonedem.kernels.excitation.base_motion` (or an
    existing kernel kind, e.g. a table) and one row here; scene parsing, the time step, the
    quiet-base plan, dataset attributes and plot labels all read the row.
    """

    keys: dict  # key -> units of its scene mapping (besides "kind")
    build: Callable  # (spec, field, base_dir) -> BaseMotion, the spec's keys already checked
    describe: Callable  # description -> words for labels, e.g. "ramp 0.5 m/s2 per s"
    pga: Callable = lambda m: 0.0  # BaseMotion -> peak |a| [m s-2]
    duration: Callable = lambda m: None  # BaseMotion -> natural length [s] or None
    period: Callable = lambda m: math.inf  # BaseMotion -> shortest period to resolve [s]


def _num(spec, key, where, positive=False, required=True, default=None):
    if key not in spec:
        if required:
            units = EXCITATIONS[spec["kind"]].keys.get(key, "")  # a kind's build checks its keys
            raise InputError(f"{where}.{key}", "missing", f"give {key} [{units}]")
        return default
    return check_number(spec[key], f"{where}.{key}", positive=positive)


# a base motion faster than this is taken for a units mistake (kHz for Hz); the step must
# also resolve it (stonedem.engine.simulate.MIN_STEPS_PER_PERIOD)
MAX_EXCITATION_FREQUENCY = 1000.0  # [Hz]


def _frequency(spec: dict, field: str) -> float:
    f = _num(spec, "frequency", field, positive=True)
    if f > MAX_EXCITATION_FREQUENCY:
        raise InputError(
            f"{field}.frequency",
            f"{f:g} Hz is above the limit {MAX_EXCITATION_FREQUENCY:g} Hz",
            "give the frequency in Hz",
        )
    return f


def _none(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    return BaseMotion(kx.KIND_NONE, np.zeros(4), description={"kind": "none"})


def _harmonic(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    f = _frequency(spec, field)
    if ("amplitude" in spec) == ("pga" in spec):
        raise InputError(
            f"{field}.amplitude",
            "give exactly one of amplitude [m] and pga [m s-2]",
            "write amplitude: 0.25 or pga: 2.15",
        )
    if "pga" in spec:  # thesis 6.1 sweeps frequency at a fixed peak acceleration: A = PGA / w^2
        amp = _num(spec, "pga", field, positive=True) / (2 * math.pi * f) ** 2
    else:
        amp = _num(spec, "amplitude", field)
    cycles = _num(spec, "ramp_cycles", field, required=False, default=1.0)
    if cycles < 0:
        raise InputError(
            f"{field}.ramp_cycles", f"must be >= 0, got {cycles}", "give 0 (abrupt) or more"
        )
    if not math.isfinite(amp * (2 * math.pi * f) ** 2):
        raise InputError(
            f"{field}.amplitude",
            f"{amp:g} m at {f:g} Hz is not a finite acceleration",
            "give an amplitude in m",
        )
    params = np.array([amp, 2 * math.pi * f, cycles / f, 0.0])
    return BaseMotion(
        kx.KIND_HARMONIC,
        params,
        description={
            "kind": "harmonic",
            "frequency": f,
            "frequency_units": "Hz",
            "amplitude": amp,
            "amplitude_units": "m",
            "ramp_cycles": cycles,
            "pga": amp * (2 * math.pi * f) ** 2,
        },
    )


def _rect_pulse(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    a_p = _num(spec, "accel", field)
    t_p = _num(spec, "duration", field, positive=True)
    return BaseMotion(
        kx.KIND_RECT_PULSE,
        np.array([a_p, t_p, 0.0, 0.0]),
        description={
            "kind": "rect_pulse",
            "accel": a_p,
            "accel_units": "m s-2",
            "duration": t_p,
            "duration_units": "s",
        },
    )


def _sine_pulse(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    a_p = _num(spec, "accel", field)
    f = _frequency(spec, field)
    return BaseMotion(
        kx.KIND_SINE_PULSE,
        np.array([a_p, 2 * math.pi * f, 1.0 / f, 0.0]),
        description={
            "kind": "sine_pulse",
            "accel": a_p,
            "accel_units": "m s-2",
            "frequency": f,
            "frequency_units": "Hz",
        },
    )


def _ramp(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    rate = _num(spec, "rate", field)
    return BaseMotion(
        kx.KIND_RAMP,
        np.array([rate, 0.0, 0.0, 0.0]),
        description={"kind": "ramp", "rate": rate, "rate_units": "m s-3"},
    )


def _angular_period(m: BaseMotion) -> float:
    return 2.0 * math.pi / m.params[1] if m.params[1] > 0.0 else math.inf


def _table_pga(m: BaseMotion) -> float:
    return float(np.abs(m.table_accel).max())


def _table_duration(m: BaseMotion) -> float:
    return (len(m.table_accel) - 1) * m.table_dt


def _table_period(m: BaseMotion) -> float:
    return 2.0 * m.table_dt  # the Nyquist period of the record's sampling


EXCITATIONS: dict[str, Excitation] = {
    "none": Excitation({}, _none, lambda d: "no base motion"),
    "harmonic": Excitation(
        {"frequency": "Hz", "amplitude": "m", "pga": "m s-2", "ramp_cycles": "1"},
        _harmonic,
        lambda d: f"harmonic {d['frequency']:g} Hz x {d['amplitude']:g} m",
        pga=lambda m: abs(m.params[0]) * m.params[1] ** 2,
        period=_angular_period,
    ),
    "rect_pulse": Excitation(
        {"accel": "m s-2", "duration": "s"},
        _rect_pulse,
        lambda d: f"rectangular pulse {d['accel']:g} m/s2 x {d['duration']:g} s",
        pga=lambda m: abs(m.params[0]),
        duration=lambda m: float(m.params[1]),
        period=lambda m: float(m.params[1]),
    ),
    "sine_pulse": Excitation(
        {"accel": "m s-2", "frequency": "Hz"},
        _sine_pulse,
        lambda d: f"sine pulse {d['accel']:g} m/s2 at {d['frequency']:g} Hz",
        pga=lambda m: abs(m.params[0]),
        duration=lambda m: float(m.params[2]),
        period=_angular_period,
    ),
    "ramp": Excitation({"rate": "m s-3"}, _ramp, lambda d: f"ramp {d['rate']:g} m/s2 per s"),
    "record": Excitation(
        {
            "file": "",
            "component": "",
            "scale": "1",
            "pga": "m s-2",
            "units": "",
            "dt": "s",
            "baseline": "",
        },
        lambda spec, field, base_dir: _record_motion(spec, field, Path(base_dir)),
        lambda d: f"record {Path(str(d.get('file', '?'))).stem}",
        pga=_table_pga,
        duration=_table_duration,
        period=_table_period,
    ),
}


def excitation_label(desc: dict) -> str:
    """E.g. 'harmonic 0.5 Hz x 0.25 m (PGA 2.47 m/s2)' from an excitation description."""
    row = EXCITATIONS.get(desc.get("kind", "none"))
    if row is None or row.build is _none:
        return "no base motion"
    text = row.describe(desc)
    pga = desc.get("pga")
    return text + (f" (PGA {pga:.3g} m/s2)" if isinstance(pga, (int, float)) else "")


def excitation_pair(spec: dict | None, base_dir: Path = Path(".")) -> tuple[BaseMotion, BaseMotion]:
    """(horizontal, vertical) base motions of an ``excitation:`` mapping; vertical from its
    ``vertical:`` key."""
    spec = dict(spec or {"kind": "none"})
    vertical = spec.pop("vertical", None)
    horizontal = excitation_from_spec(spec, "excitation", base_dir)
    if vertical is not None and not isinstance(vertical, dict):
        raise InputError("excitation.vertical", "expected a mapping", "write vertical: {kind: ...}")
    return horizontal, excitation_from_spec(vertical, "excitation.vertical", base_dir)


def excitation_from_spec(
    spec: dict | None, field: str = "excitation", base_dir: Path = Path(".")
) -> BaseMotion:
    """Validate one excitation mapping and build its BaseMotion (its row of EXCITATIONS)."""
    if spec is None:
        spec = {"kind": "none"}
    if not isinstance(spec, dict):
        raise InputError(field, "expected a mapping", "write {kind: none | harmonic | ...}")
    kind = spec.get("kind")
    if not isinstance(kind, str) or kind not in EXCITATIONS:
        raise InputError(
            f"{field}.kind", f"unknown kind {kind!r}", f"use one of {', '.join(EXCITATIONS)}"
        )
    allowed = ("kind", *EXCITATIONS[kind].keys)
    for key in spec:
        if key not in allowed:
            raise InputError(
                f"{field}.{key}",
                f"unknown key for kind {kind}",
                f"allowed keys: {', '.join(allowed)}",
            )
    return EXCITATIONS[kind].build(spec, field, Path(base_dir))


def _record_motion(spec: dict, field: str, base_dir: Path) -> BaseMotion:
    if "file" not in spec and "component" in spec:  # a suite component names its suite (FF07a)
        from stonedem.motion.suites import SUITES, suite_of

        suite = suite_of(spec["component"])
        if suite is None:
            raise InputError(
                f"{field}.component",
                f"{shown(repr(spec['component']))} is not a FEMA P695 component name",
                f"write e.g. FF07a (prefixes {', '.join(p for _, p in SUITES.values())}"
                ", record number, a or b), or give file:",
            )
        spec = {**spec, "file": f"suites/{suite}"}
    if "file" not in spec:
        raise InputError(
            f"{field}.file", "missing", "give the record file (path or name in records/)"
        )
    if "scale" in spec and "pga" in spec:
        raise InputError(field, "give scale or pga, not both", "remove one of them")
    name = spec["file"]
    if isinstance(name, bool) or not isinstance(name, (str, int, Path)):
        raise InputError(
            f"{field}.file",
            f"expected a file name or path, got {shown(repr(name))}",
            "write file: northridge_1994_mul009 or file: path/to/record.AT2",
        )
    units = check_units(spec.get("units"), f"{field}.units")
    dt = _num(spec, "dt", field, positive=True, required=False)
    baseline = spec.get("baseline", True)
    if not isinstance(baseline, bool):
        raise InputError(f"{field}.baseline", "expected true or false", "write baseline: true")
    target = _num(spec, "pga", field, positive=True) if "pga" in spec else None
    if target is not None and target > MAX_RECORD_PGA:
        raise InputError(
            f"{field}.pga",
            f"{target:g} m/s2 is above the {MAX_RECORD_PGA / G_STANDARD:g} g limit",
            "give a ground acceleration in m/s2",
        )
    scale = _num(spec, "scale", field, required=False, default=1.0)
    component = spec.get("component")
    if component is not None:
        if not isinstance(component, str) or not component:
            raise InputError(
                f"{field}.component",
                f"expected a component name, got {shown(repr(component))}",
                "write component: FF07a (a record of a suite file, records/suites/)",
            )
        if units is not None or dt is not None:
            raise InputError(
                f"{field}.component",
                "a suite component carries its own units and dt",
                "drop units and dt",
            )
    path = resolve_record(str(name), f"{field}.file", base_dir)
    time, accel, meta = corrected_record(path, field, units, dt, baseline, component)
    pga_raw = float(np.abs(accel).max())
    if target is not None:
        if pga_raw == 0.0:
            raise InputError(
                f"{field}.pga",
                "the record is all zeros" + (" after baseline correction" if baseline else ""),
                "use a record with motion",
            )
        scale = target / pga_raw
    accel = accel * scale
    pga = float(np.abs(accel).max())
    if not pga <= MAX_RECORD_PGA:
        limit = f"{MAX_RECORD_PGA / G_STANDARD:g} g limit (stonedem.motion.records.MAX_RECORD_PGA)"
        if "scale" in spec:
            raise InputError(
                f"{field}.scale",
                f"the scaled record's peak {pga:.4g} m/s2 is above the {limit}",
                "give a smaller scale",
            )
        raise InputError(
            f"{field}.file",
            f"{shown(path.name)}: baseline correction raises the peak to "
            f"{pga:.4g} m/s2, above the {limit}",
            "give baseline: false, or a longer record",
        )
    table_a, table_v, table_d, h = record_to_table(time, accel)
    description = {
        "kind": "record",
        "file": str(path),
        "scale": scale,
        "baseline_corrected": int(baseline),
        "pga": pga,
        "pga_units": "m s-2",
        "record_pga": pga_raw,
        "record_dt": h,
        "record_duration": float(time[-1] - time[0]),
        **meta,
    }
    return BaseMotion(kx.KIND_TABLE, np.zeros(4), table_a, table_v, table_d, h, description)


# --- a record once per process: read, then baseline corrected (a suite's component read by
# stonedem.motion.suites, which itself reads through stonedem.motion.records) ------------

# records read by this process: (path, size, mtime, units, dt, baseline) -> (time, accel, meta);
# a study job runs many cases of the same few records, each read and corrected once
_RECORD_MEMO: dict = {}


RECORD_MEMO_SIZE = 8


def corrected_record(path: Path, field: str, units, dt, baseline: bool, component=None):
    """read_record (or one component of a suite file), then the baseline correction; once per
    file and settings per process."""
    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns, units, dt, baseline, component)
    if key not in _RECORD_MEMO:
        if component is None:
            time, accel, meta = read_record(
                path,
                f"{field}.file",
                units=units,
                dt=dt,
                units_field=f"{field}.units",
                dt_field=f"{field}.dt",
            )
        else:
            from stonedem.motion.suites import read_component

            time, accel, meta = read_component(path, component, field)
        if baseline:
            from stonedem.motion.records import baseline_correct

            accel = baseline_correct(time, accel)
        if len(_RECORD_MEMO) >= RECORD_MEMO_SIZE:
            _RECORD_MEMO.pop(next(iter(_RECORD_MEMO)))
        time.setflags(write=False)
        accel.setflags(write=False)
        _RECORD_MEMO[key] = (time, accel, meta)
    time, accel, meta = _RECORD_MEMO[key]
    return time, accel, dict(meta)
