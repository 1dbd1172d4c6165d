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
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import REQUIRED, Field, Spec, exactly_one, got
from stonedem.kernels import excitation as kx
from stonedem.motion.records import (
    G_STANDARD,
    MAX_RECORD_PGA,
    RECORD_KEYS,
    check_units,
    first_key,
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
    # a sequence (KIND_SEQUENCE): its parts' motions and the start of each part's window [s]
    parts: tuple = ()
    starts: tuple = ()

    def evaluate(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Displacement [m], velocity [m s-1], acceleration [m s-2] at times t [s]."""
        t = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=float)))
        if self.kind == KIND_SEQUENCE:
            return _sequence_evaluate(self, t)
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
    quiet-base plan, dataset attributes and plot labels all read the row. Its ``spec``
    declares the keys of its scene mapping besides ``kind`` (:mod:`stonedem.io.spec`); they
    are checked before ``build`` runs, which gets the checked values.
    """

    spec: Spec  # the keys of its scene mapping besides "kind"
    build: Callable  # (checked values, field, base_dir) -> BaseMotion
    describe: Callable  # description -> words for labels, e.g. "ramp 0.5 m/s2 per s"
    pga: Callable = lambda m: 0.0  # BaseMotion -> peak |a| [m s-2]
    duration: Callable = lambda m: None  # BaseMotion -> natural length [s] or None
    period: Callable = lambda m: math.inf  # BaseMotion -> shortest period to resolve [s]
    keys: Spec = field(init=False, repr=False, compare=False)  # spec with "kind" first

    def __post_init__(self):
        kind = Field("kind", "any", default=REQUIRED, doc="the excitation kind (EXCITATIONS)")
        keys = Spec((kind, *self.spec.fields), self.spec.rules, self.spec.doc)
        object.__setattr__(self, "keys", keys)


# a base motion faster than this is taken for a units mistake (kHz for Hz); the step must
# also resolve it (stonedem.engine.simulate.MIN_STEPS_PER_PERIOD)
MAX_EXCITATION_FREQUENCY = 1000.0  # [Hz]

FREQUENCY = Field(
    "frequency",
    units="Hz",
    range=f"(0, {MAX_EXCITATION_FREQUENCY:g}]",
    default=REQUIRED,
    hint="give the frequency in Hz",
    doc="frequency of the motion",
)
ACCEL = Field(
    "accel",
    units="m s-2",
    default=REQUIRED,
    hint="give the peak acceleration in m/s2",
    doc="peak acceleration of the pulse",
)


def _none(v: dict, field: str, base_dir: Path) -> BaseMotion:
    return BaseMotion(kx.KIND_NONE, np.zeros(4), description={"kind": "none"})


def _harmonic(v: dict, field: str, base_dir: Path) -> BaseMotion:
    f = v["frequency"]
    if v["pga"] is not None:  # thesis 6.1 sweeps frequency at a fixed peak acceleration
        amp = v["pga"] / (2 * math.pi * f) ** 2  # A = PGA / w^2
    else:
        amp = v["amplitude"]
    cycles = v["ramp_cycles"]
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


def _rect_pulse(v: dict, field: str, base_dir: Path) -> BaseMotion:
    a_p, t_p = v["accel"], v["duration"]
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


def _sine_pulse(v: dict, field: str, base_dir: Path) -> BaseMotion:
    a_p, f = v["accel"], v["frequency"]
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


def _ramp(v: dict, field: str, base_dir: Path) -> BaseMotion:
    rate = v["rate"]
    return BaseMotion(
        kx.KIND_RAMP,
        np.array([rate, 0.0, 0.0, 0.0]),
        description={"kind": "ramp", "rate": rate, "rate_units": "m s-3"},
    )


# a sequence of base motions (one row below): Python runs each part as its own kernel motion
# (stonedem.engine.simulate.simulate_sequence), so the kernel never sees this kind
KIND_SEQUENCE = -1
MAX_SEQUENCE_PARTS = 20


def sequence_offsets(m: BaseMotion) -> list[tuple[float, float]]:
    """(displacement [m], velocity [m s-1]) of a sequence's base at the start of each part:
    what the parts before it left (a rectangular pulse leaves the base moving)."""
    out, d, v = [], 0.0, 0.0
    for k, part in enumerate(m.parts):
        out.append((d, v))
        if k + 1 < len(m.parts):
            length = m.starts[k + 1] - m.starts[k]
            d_e, v_e, _ = part.evaluate(np.array([length]))
            d, v = d + v * length + float(d_e[0]), v + float(v_e[0])
    return out


def _sequence_evaluate(m: BaseMotion, t: np.ndarray):
    """The composite motion of a sequence: part k from its start t_k on, added to the
    displacement and velocity the parts before it left (D_k + V_k (t - t_k))."""
    out = np.zeros((3, t.shape[0]))
    ends = (*m.starts[1:], math.inf)
    for k, (part, (d0, v0)) in enumerate(zip(m.parts, sequence_offsets(m))):
        inside = t < ends[k] if k == 0 else (t >= m.starts[k]) & (t < ends[k])
        if not inside.any():
            continue
        s = t[inside] - m.starts[k]
        d, v, a = part.evaluate(s)
        out[0, inside] = d0 + v0 * s + d
        out[1, inside] = v0 + v
        out[2, inside] = a
    return out[0], out[1], out[2]


def _sequence(v: dict, field: str, base_dir: Path) -> BaseMotion:
    rest, parts, starts, start = v["rest"], [], [], 0.0
    for i, item in enumerate(v["parts"]):
        where = f"{field}.parts[{i}]"
        if isinstance(item, Mapping) and item.get("kind") == "sequence":
            raise InputError(
                f"{where}.kind", "a sequence inside a sequence", "list its parts in the outer one"
            )
        if isinstance(item, Mapping) and "vertical" in item:
            raise InputError(
                f"{where}.vertical",
                "a sequence runs horizontal parts only",
                "remove vertical: from the part",
            )
        part = excitation_from_spec(item, where, base_dir)
        if part.duration is None:
            raise InputError(
                f"{where}.kind",
                f"{part.description.get('kind')} has no natural length to end a part",
                "use a record, rect_pulse or sine_pulse",
            )
        parts.append(part)
        starts.append(start)
        start += part.duration + rest
    description = {
        "kind": "sequence",
        "rest": rest,
        "rest_units": "s",
        "parts": [p.description for p in parts],
        "part_start": starts,
        "part_start_units": "s",
        "pga": max(p.pga for p in parts),
        "pga_units": "m s-2",
    }
    return BaseMotion(
        KIND_SEQUENCE,
        np.zeros(4),
        description=description,
        parts=tuple(parts),
        starts=tuple(starts),
    )


def _sequence_describe(d: dict) -> str:
    words = "; ".join(excitation_label(p) for p in d["parts"])
    return f"sequence of {len(d['parts'])} ({words}), rest {d['rest']:g} s"


def _angular_period(m: BaseMotion) -> float:
    return 2.0 * math.pi / m.params[1] if m.params[1] > 0.0 else math.inf


def _table_pga(m: BaseMotion) -> float:
    return float(np.abs(m.table_accel).max())


def _table_duration(m: BaseMotion) -> float:
    return (len(m.table_accel) - 1) * m.table_dt


def _table_period(m: BaseMotion) -> float:
    return 2.0 * m.table_dt  # the Nyquist period of the record's sampling


EXCITATIONS: dict[str, Excitation] = {
    "none": Excitation(Spec(()), _none, lambda d: "no base motion"),
    "harmonic": Excitation(
        Spec(
            (
                FREQUENCY,
                Field("amplitude", units="m", doc="displacement amplitude"),
                Field(
                    "pga",
                    units="m s-2",
                    range="(0, inf)",
                    hint="give the peak acceleration in m/s2",
                    doc="peak acceleration instead of amplitude: amplitude = pga / (2 pi f)^2",
                ),
                Field(
                    "ramp_cycles",
                    units="1",
                    range="[0, inf)",
                    default=1.0,
                    hint="give 0 (abrupt) or more",
                    doc="cycles over which the amplitude ramps up from 0",
                ),
            ),
            rules=(
                first_key(
                    exactly_one(
                        "amplitude", "pga", fix="write amplitude: 0.25 (m) or pga: 2.15 (m/s2)"
                    )
                ),
            ),
        ),
        _harmonic,
        lambda d: f"harmonic {d['frequency']:g} Hz x {d['amplitude']:g} m",
        pga=lambda m: abs(m.params[0]) * m.params[1] ** 2,
        period=_angular_period,
    ),
    "rect_pulse": Excitation(
        Spec(
            (
                ACCEL,
                Field(
                    "duration",
                    units="s",
                    range="(0, inf)",
                    default=REQUIRED,
                    hint="give the pulse length in s",
                    doc="length of the pulse",
                ),
            )
        ),
        _rect_pulse,
        lambda d: f"rectangular pulse {d['accel']:g} m/s2 x {d['duration']:g} s",
        pga=lambda m: abs(m.params[0]),
        duration=lambda m: float(m.params[1]),
        period=lambda m: float(m.params[1]),
    ),
    "sine_pulse": Excitation(
        Spec((ACCEL, FREQUENCY)),
        _sine_pulse,
        lambda d: f"sine pulse {d['accel']:g} m/s2 at {d['frequency']:g} Hz",
        pga=lambda m: abs(m.params[0]),
        duration=lambda m: float(m.params[2]),
        period=_angular_period,
    ),
    "ramp": Excitation(
        Spec(
            (
                Field(
                    "rate",
                    units="m s-3",
                    default=REQUIRED,
                    hint="give the rate in m/s2 per s",
                    doc="rate of the base acceleration",
                ),
            )
        ),
        _ramp,
        lambda d: f"ramp {d['rate']:g} m/s2 per s",
    ),
    "record": Excitation(
        RECORD_KEYS,
        lambda v, field, base_dir: _record_motion(v, field, Path(base_dir)),
        lambda d: f"record {Path(str(d.get('file', '?'))).stem}",
        pga=_table_pga,
        duration=_table_duration,
        period=_table_period,
    ),
    "sequence": Excitation(
        Spec(
            (
                Field(
                    "parts",
                    "list",
                    default=REQUIRED,
                    limit=MAX_SEQUENCE_PARTS,
                    min_items=1,
                    hint="write parts: [{kind: record, ...}, {kind: record, ...}]",
                    doc="the motions run back to back, each a record, rect_pulse or "
                    "sine_pulse mapping",
                ),
                Field(
                    "rest",
                    units="s",
                    range="[0, 3600]",
                    default=20.0,
                    hint="give the quiet time after each part in s, long enough to settle",
                    doc="quiet base after each part",
                ),
            )
        ),
        _sequence,
        _sequence_describe,
        pga=lambda m: max(p.pga for p in m.parts),
        duration=lambda m: m.starts[-1] + m.parts[-1].duration + m.description["rest"],
        period=lambda m: min(p.shortest_period for p in m.parts),
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
    spec = spec or {"kind": "none"}
    vertical = None
    if isinstance(spec, Mapping):
        spec = dict(spec)
        vertical = spec.pop("vertical", None)
    horizontal = excitation_from_spec(spec, "excitation", base_dir)
    if horizontal.kind == KIND_SEQUENCE and vertical is not None:
        raise InputError(
            "excitation.vertical",
            "a sequence runs horizontal parts only",
            "remove vertical: or run the parts as separate scenes",
        )
    return horizontal, excitation_from_spec(vertical, "excitation.vertical", base_dir)


def excitation_from_spec(
    spec: dict | None, field: str = "excitation", base_dir: Path = Path(".")
) -> BaseMotion:
    """Check one excitation mapping against its row of EXCITATIONS (its ``kind``, then the
    row's keys) and build its BaseMotion."""
    if spec is None:
        spec = {"kind": "none"}
    if not isinstance(spec, Mapping):  # the kit's mapping field gives no kind-specific fix
        raise InputError(
            field, f"expected a mapping, got {got(spec)}", "write {kind: none | harmonic | ...}"
        )
    kinds = Field("kind", "choice", choices=tuple(EXCITATIONS))  # rows may be added at run time
    row = EXCITATIONS[kinds.check(spec.get("kind"), f"{field}.kind")]
    return row.build(row.keys.check(spec, field), field, Path(base_dir))


def _record_motion(v: dict, field: str, base_dir: Path) -> BaseMotion:
    name, component, baseline = v["file"], v["component"], v["baseline"]
    if component is not None:  # a suite component names its suite (FF07a)
        from stonedem.motion.suites import SUITES, suite_of

        suite = suite_of(component)
        if suite is None:
            raise InputError(
                f"{field}.component",
                f"{shown(repr(component))} is not a FEMA P695 component name",
                f"write e.g. FF07a (prefixes {', '.join(p for _, p in SUITES.values())}"
                ", record number, a or b)" + (", or give file:" if name is None else ""),
            )
        name = f"suites/{suite}" if name is None else name
    units = check_units(v["units"], f"{field}.units")
    path = resolve_record(name, f"{field}.file", base_dir)
    time, accel, meta = corrected_record(path, field, units, v["dt"], baseline, component)
    pga_raw = float(np.abs(accel).max())
    scale = v["scale"]
    if v["pga"] is not None:
        if pga_raw == 0.0:
            raise InputError(
                f"{field}.pga",
                "the record is all zeros" + (" after baseline correction" if baseline else ""),
                "use a record with motion",
            )
        scale = v["pga"] / pga_raw
    accel = accel * scale
    pga = float(np.abs(accel).max())
    if not pga <= MAX_RECORD_PGA:
        limit = f"{MAX_RECORD_PGA / G_STANDARD:g} g limit (stonedem.motion.records.MAX_RECORD_PGA)"
        key, what, fix = (
            ("scale", "the scaled record's peak is", "give a smaller scale")
            if v["scale"] != 1.0  # else the baseline correction raised the peak
            else (
                "file",
                f"{shown(path.name)}: baseline correction raises the peak to",
                "give baseline: false, or a longer record",
            )
        )
        raise InputError(f"{field}.{key}", f"{what} {pga:.4g} m/s2, above the {limit}", fix)
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
