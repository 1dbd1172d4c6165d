"""Base excitations: validated specs -> :class:`BaseMotion` the compiled loop evaluates.

Analytic motions (harmonic displacement, rectangular and one-sine acceleration pulses,
linear acceleration ramp; thesis 5.1.3, 5.1.5, 6.3) and recorded accelerograms share one
interface, so the engine never cares where motion comes from. Records are read from plain
text (two columns time, acceleration; or one column with ``dt``) or NetCDF (``acceleration``
on ``time``), checked, scaled by a factor or to a target PGA, and tabulated for exact
piecewise-linear integration (:mod:`stonedem.kernels.excitation`). Records are baseline
corrected by default (``baseline: false`` keeps them as recorded; :mod:`stonedem.motion.records`).
The engine reads a record linearly between samples, which is how it is upsampled to the
solver's step.
"""

from __future__ import annotations

import math
import os
import re
from array import array
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from stonedem.errors import InputError, check_number
from stonedem.kernels import excitation as kx
from stonedem.motion.records import (
    G_STANDARD,
    MAX_RECORD_PGA,
    _reason,
    check_dt,
    check_pga,
    check_record_file,
    check_samples,
    shown,
    text_lines,
)

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
    time, accel, meta = _corrected_record(path, field, units, dt, baseline, component)
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


# records read by this process: (path, size, mtime, units, dt, baseline) -> (time, accel, meta);
# a study job runs many cases of the same few records, each read and corrected once
_RECORD_MEMO: dict = {}
RECORD_MEMO_SIZE = 8


def _corrected_record(path: Path, field: str, units, dt, baseline: bool, component=None):
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
    if isinstance(name, Path):
        name = str(name)
    if not isinstance(name, str):
        raise InputError(
            field, f"expected a file name or path, got {shown(repr(name))}", "give a record file"
        )
    if not name.strip():
        raise InputError(
            field, "empty record name", "give a path or a record name, e.g. northridge_1994_mul009"
        )
    if "\0" in name or len(name) > MAX_NAME_CHARS:
        raise InputError(
            field,
            f"'{shown(name)}' is not a usable file name"
            + (" (a NUL character)" if "\0" in name else f" (over {MAX_NAME_CHARS} characters)"),
            "give a path or a record name",
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
    if dangling and not not_files:
        raise InputError(
            field,
            f"{shown(dangling[0])} is a symbolic link that cannot be followed (a loop, or "
            "to nothing)",
            "give the record file itself",
        )
    if not_files:
        raise InputError(
            field,
            f"{shown(not_files[0])} is not a record file"
            + (" (a folder)" if not_files[0].is_dir() else ""),
            "give a record file",
        )
    known = sorted({p.stem for folder in folders for p in folder.glob("*.nc")})
    where = " or ".join(str(f) for f in folders) or "records/ (none installed)"
    listing = f" ({', '.join(known[:8])}{', ...' if len(known) > 8 else ''})" if known else ""
    raise InputError(
        field, f"record '{shown(name)}' not found", f"give a path or a name in {where}{listing}"
    )


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
    if dt is not None:
        dt = check_dt(check_number(dt, dt_field, positive=True), dt_field, "time step")
    name = shown(path.name)
    meta: dict = {}
    suffix = path.suffix.lower()
    if suffix == ".at2":
        from stonedem.motion.records import read_at2

        rec = read_at2(path, field)
        if units is not None and UNIT_FACTORS[units] != G_STANDARD:
            raise InputError(
                units_field,
                f"{name} is a PEER .AT2 record in g, {units_label} gives '{units}'",
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
                raise InputError(
                    dt_field,
                    f"{name} declares dt = {header_dt:g} s, {dt_label} gives {dt:g} s",
                    "drop one of them",
                )
            step = dt if dt is not None else header_dt
            if step is None:
                raise InputError(
                    field,
                    f"{name} has one column and no time step",
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
        raise InputError(
            dt_field,
            f"{name} has a time step of {file_dt:g} s, {dt_label} gives {dt:g} s",
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

    name = shown(path.name)
    check_record_file(
        path, field, max_bytes=2**62
    )  # regular file; size is bounded per variable below
    fix = "store 'acceleration' [m s-2] on a 'time' coordinate [s] (see records/README.md)"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = xr.open_dataset(path, decode_times=False, decode_timedelta=False, cache=False)
    except Exception as err:  # netCDF4, h5netcdf and scipy raise many types on junk
        raise InputError(
            field,
            f"{name} is not a readable NetCDF file ({_reason(err)})",
            "give a NetCDF record, or a text or .AT2 record with its own suffix",
        ) from None
    with ds:
        if "acceleration" not in ds.variables:
            have = ", ".join(shown(v, 30) for v in list(ds.variables)[:6]) or "none"
            raise InputError(field, f"{name} has no variable 'acceleration' (it has: {have})", fix)
        var = ds.variables["acceleration"]
        if tuple(var.dims) != ("time",):
            raise InputError(
                field,
                f"{name}: 'acceleration' has dimensions {shown(tuple(var.dims))}, expected (time,)",
                fix,
            )
        if "time" not in ds.variables or tuple(ds.variables["time"].dims) != ("time",):
            raise InputError(field, f"{name} has no 'time' coordinate for 'acceleration'", fix)
        tvar = ds.variables["time"]
        check_samples(int(var.size), field, path.name)
        for label, v in (("acceleration", var), ("time", tvar)):
            if v.dtype.kind not in "iuf":
                raise InputError(
                    field, f"{name}: '{label}' holds {shown(v.dtype)}, not real numbers", fix
                )
        file_units = var.attrs.get("units")
        if file_units is not None:
            if not isinstance(file_units, str) or file_units.strip().lower() not in UNIT_FACTORS:
                raise InputError(
                    field,
                    f"{name}: unknown acceleration units {shown(repr(file_units))}",
                    f"use one of {', '.join(UNIT_FACTORS)}",
                )
            file_units = file_units.strip().lower()
            if units is not None and UNIT_FACTORS[units] != UNIT_FACTORS[file_units]:
                raise InputError(
                    units_field,
                    f"{name} declares its acceleration in '{shown(file_units)}', "
                    f"{units_field.rsplit('.', 1)[-1]} gives '{units}'",
                    "drop the units: a NetCDF record carries its own",
                )
        else:
            file_units = units or "m s-2"
        time_units = tvar.attrs.get("units", "s")
        if not isinstance(time_units, str) or time_units.strip().lower() not in TIME_UNITS:
            raise InputError(
                field,
                f"{name}: time units {shown(repr(time_units))}, expected s",
                "store time in seconds (units: s)",
            )
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                accel = np.asarray(var.values, dtype=float)
                time = np.asarray(tvar.values, dtype=float)
        except Exception as err:
            raise InputError(
                field, f"{name}: cannot read 'acceleration' ({_reason(err)})", fix
            ) from None
        meta = {
            k: shown(v, 200)
            for k, v in ds.attrs.items()
            if k in ("title", "event", "station", "component", "source")
        }
    return time, accel, file_units, meta


_DT_HEADER = re.compile(r"^#*\s*dt\s*[=:]\s*(\S*)", re.IGNORECASE)


def _read_text_record(path: Path, field: str):
    """(time or None, acceleration, dt from a header line or None) of a text record."""
    name = shown(path.name)
    values = array("d")
    header_dt, n_cols, n_rows = None, None, 0
    for number, line in text_lines(path, field):
        stripped = line.strip()
        header = _DT_HEADER.match(stripped)
        if header:
            try:
                value = float(header.group(1).rstrip(",;"))
            except ValueError:
                raise InputError(
                    field,
                    f"{name} line {number}: bad dt header '{shown(stripped, 40)}'",
                    "write dt = 0.01",
                ) from None
            if header_dt is not None and value != header_dt:
                raise InputError(
                    field,
                    f"{name} line {number}: a second dt header ({value:g} s after {header_dt:g} s)",
                    "keep one dt header",
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
            raise InputError(
                field,
                f"{name} line {number}: non-numeric value in '{shown(text, 40)}'",
                "give numbers only (comments start with #; a PEER record must end in .AT2)",
            ) from None
        if n_cols is None:
            n_cols = len(row)
            if n_cols not in (1, 2):
                raise InputError(
                    field,
                    f"{name} line {number}: {n_cols} columns",
                    "give time and acceleration, or acceleration alone with dt",
                )
        elif len(row) != n_cols:
            raise InputError(
                field, f"{name} line {number}: {len(row)} columns, expected {n_cols}", "fix the row"
            )
        n_rows += 1
        check_samples(n_rows, field, path.name)
        values.extend(row)
    if not n_rows:
        raise InputError(field, f"{name} holds no samples", "give at least two samples")
    data = np.frombuffer(values, dtype=float).reshape(n_rows, n_cols)
    if n_cols == 2:
        return data[:, 0].copy(), data[:, 1].copy(), header_dt
    return None, data[:, 0].copy(), header_dt


def _check_record(time, accel, field, path):
    name = shown(path.name)
    if len(accel) < 2:
        raise InputError(field, f"{name}: fewer than 2 samples", "give a longer record")
    check_samples(len(accel), field, path.name)
    bad = np.flatnonzero(~np.isfinite(accel) | ~np.isfinite(time))
    if len(bad):
        raise InputError(
            field, f"{name}: NaN or infinite value at sample {bad[0]}", "clean the record"
        )
    with np.errstate(over="ignore", invalid="ignore"):
        steps = np.diff(time)
    if not np.all(np.isfinite(steps)):
        raise InputError(
            field, f"{name}: time values too large to take differences", "give time in s from 0"
        )
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise InputError(
            field,
            f"{name}: time not increasing at sample {i + 1} (t = {time[i + 1]:g} s)",
            "sort the samples and remove duplicates",
        )
    h = float((time[-1] - time[0]) / (len(time) - 1))
    if np.ptp(steps) > 1e-6 * h:
        raise InputError(
            field,
            f"{name}: non-uniform time step ({steps.min():g} to {steps.max():g} s)",
            "resample to a uniform step first (not done here)",
        )
    check_dt(h, field, f"{name}: time step")
    check_pga(accel, field, path.name)


def record_to_table(time, accel):
    """Acceleration samples -> (accel, exact node velocity, exact node displacement, step [s])."""
    from stonedem.motion.records import integrate

    accel = np.ascontiguousarray(accel, dtype=float)
    h = float((time[-1] - time[0]) / (len(time) - 1))
    vel, disp = integrate(np.arange(len(accel)) * h, accel)
    return accel, vel, disp, h
