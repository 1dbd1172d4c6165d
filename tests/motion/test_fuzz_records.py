"""Fuzz the ground-motion record readers and ``stonedem record info`` with hostile files.

Every generated file (random bytes; text records with junk tokens, wrong column counts,
NaN, huge values, bad dt headers, bad encodings; PEER .AT2 files with garbled or truncated
headers and wrong point counts; NetCDF files with wrong variables, dimensions, dtypes,
units and time coordinates, or cut short) must either raise one InputError whose message is
one printable line naming the field, or read to a sane record: at least 2 finite samples on
a uniform step within the limits of :mod:`stonedem.motion.records`, which the scene path then turns
into finite tables, spectra and a predominant frequency (NaN only for a constant record).

``ci`` profile (default): 100 examples per test; ``HYPOTHESIS_PROFILE=fuzz``: 10 000.
"""

from __future__ import annotations

import contextlib
import io
import itertools
import math
import shutil
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from stonedem.errors import InputError
from stonedem.motion import records
from stonedem.motion.excitation import excitation_from_spec
from stonedem.motion.records import UNIT_FACTORS, read_record

FIELD = "excitation.file"
FIELDS = (FIELD, "excitation.units", "excitation.dt")
HEALTH = settings(
    suppress_health_check=[
        HealthCheck.too_slow,
        HealthCheck.function_scoped_fixture,
        HealthCheck.data_too_large,
        HealthCheck.large_base_example,
    ]
)

_WORK = Path(tempfile.mkdtemp(prefix="stonedem-fuzz-records-"))


def one_line(message: str) -> bool:
    return bool(message) and all(ch.isprintable() for ch in message) and len(message) < 1000


def sane(time, accel) -> None:
    time, accel = np.asarray(time), np.asarray(accel)
    assert 2 <= len(time) == len(accel) <= records.MAX_RECORD_SAMPLES
    assert np.all(np.isfinite(time)) and np.all(np.isfinite(accel))
    assert time[0] == 0.0
    steps = np.diff(time)
    h = (time[-1] - time[0]) / (len(time) - 1)
    assert np.all(steps > 0) and np.ptp(steps) <= 1e-6 * h
    assert records.MIN_RECORD_DT <= h <= records.MAX_RECORD_DT
    assert np.abs(accel).max() <= records.MAX_RECORD_PGA


def check_file(path: Path, **kwargs):
    """Read ``path`` as a scene would; assert the outcome is a one-line error or a sane record."""
    try:
        time, accel, meta = read_record(path, FIELD, **kwargs)
    except InputError as err:
        assert one_line(str(err)), repr(str(err))
        assert err.field in FIELDS, str(err)
        return None
    sane(time, accel)
    for value in meta.values():
        assert one_line(str(value)) or value == "", repr(value)
    return time, accel


def check_downstream(path: Path, time, accel, **kwargs) -> None:
    """A sane record drives a scene, has finite spectra and a predominant frequency."""
    given = {k: v for k, v in kwargs.items() if v is not None}  # the scene's units: and dt:
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # an overflow or 0/0 anywhere is a bug
        for spec in ({}, {"baseline": False}, {"pga": 3.0}):
            try:
                motion = excitation_from_spec(
                    {"kind": "record", "file": str(path), **given, **spec}
                )
            except InputError as err:  # only what the record's processing can refuse
                assert (
                    "all zeros" in str(err) or "baseline correction raises the peak" in str(err)
                ) and one_line(str(err)), str(err)
                continue
            for table in (motion.table_accel, motion.table_vel, motion.table_disp):
                assert np.all(np.isfinite(table))
        psa = records.response_spectrum(time, accel, records.SPECTRUM_PERIODS[::10], 0.05)
        assert np.all(np.isfinite(psa))
        f_p = records.predominant_frequency(time, accel)
    assert (
        math.isnan(f_p) and (records.is_constant(accel) or len(time) < 4)
    ) or 0.1 <= f_p <= 25.0, f_p


_COUNTER = itertools.count()


def fresh_folder() -> Path:
    """A new folder per example (the previous one removed): HDF5 keeps a file it failed on
    open under its name, so a rewritten file of the same name could read as the old one."""
    for old in _WORK.glob("ex*"):
        shutil.rmtree(old, ignore_errors=True)
    folder = _WORK / f"ex{next(_COUNTER)}"
    folder.mkdir()
    return folder


def write(name: str, data: bytes) -> Path:
    folder = fresh_folder()
    path = folder / name
    path.write_bytes(data)
    return path


# --- strategies ------------------------------------------------------------------------------

JUNK_TOKENS = [
    "",
    "abc",
    "1e-",
    ".",
    "-",
    "+",
    "1,5",
    "0x10",
    "1_0",
    "\u0661",
    "nan",
    "-inf",
    "inf",
    "1e999",
    "-1e999",
    "1e-999",
    "1e308",
    "-1e308",
    "\x00",
    "\ufeff1",
    "\u00e9",
    "#",
    "dt",
    "dt=",
    "=",
    "NPTS",
    "\t",
    "\r",
    "\x0b",
    "1e5",
    "-1e5",
    "9" * 40,
]
numbers = st.one_of(
    st.floats(-50.0, 50.0).map(lambda v: f"{v:.6g}"),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**30), 10**30).map(str),
    st.sampled_from(JUNK_TOKENS),
    st.text(max_size=6),
)
separators = st.sampled_from([" ", "  ", "\t", ",", ", ", ";"])


@st.composite
def sane_series(draw, max_n=60):
    n = draw(st.integers(0, max_n))
    dt = draw(
        st.one_of(
            st.sampled_from([0.005, 0.01, 0.02, 1.0 / 3.0]),
            st.floats(1e-4, 1.0),
            st.floats(1e-6, 3.0),
        )
    )
    values = draw(st.lists(st.floats(-30.0, 30.0), min_size=n, max_size=n))
    shape = draw(st.sampled_from(["sine", "random", "zeros", "constant"]))
    if shape == "sine":
        values = [3.0 * math.sin(2 * math.pi * 2.0 * i * dt) for i in range(n)]
    elif shape == "zeros":
        values = [0.0] * n
    elif shape == "constant":
        values = [1.5] * n
    t0 = draw(st.sampled_from([0.0, 0.0, 1.0, -2.5, 1e6]))
    return t0, dt, values


@st.composite
def mutated_lines(draw, lines):
    """Apply 0-3 line mutations: replace, insert, delete, duplicate, swap."""
    lines = list(lines)
    for _ in range(draw(st.sampled_from([0, 0, 1, 2, 3]))):
        op = draw(st.sampled_from(["replace", "insert", "delete", "duplicate", "swap", "columns"]))
        junk_line = draw(st.lists(numbers, max_size=4).map(" ".join))
        i = draw(st.integers(0, max(0, len(lines) - 1)))
        if op == "insert" or not lines:
            lines.insert(i, junk_line)
        elif op == "replace":
            lines[i] = junk_line
        elif op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        elif op == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        else:
            lines[i] = lines[i] + draw(separators) + draw(numbers)
    return lines


@st.composite
def byte_mutations(draw, data: bytes) -> bytes:
    """Optionally truncate, splice random bytes, re-encode or change the line ends."""
    op = draw(st.sampled_from(["none"] * 5 + ["truncate", "splice", "latin1", "crlf", "cr", "bom"]))
    if op == "truncate":
        return data[: draw(st.integers(0, len(data)))]
    if op == "splice":
        at = draw(st.integers(0, len(data)))
        return data[:at] + draw(st.binary(min_size=1, max_size=8)) + data[at:]
    if op == "latin1":
        return data.replace(b"\n", " \xe9\xff\n".encode("latin-1"), 1)
    if op == "crlf":
        return data.replace(b"\n", b"\r\n")
    if op == "cr":
        return data.replace(b"\n", b"\r")
    if op == "bom":
        return b"\xef\xbb\xbf" + data
    return data


@st.composite
def text_records(draw) -> bytes:
    t0, dt, values = draw(sane_series())
    form = draw(st.sampled_from(["two", "one_header", "one_comment_header", "one_bare"]))
    sep = draw(separators)
    lines = [
        draw(st.sampled_from(["# time [s], acceleration [m/s2]", "# station X \u00e9", "", "#"]))
    ]
    if form == "two":
        lines += [f"{t0 + i * dt!r}{sep}{v!r}" for i, v in enumerate(values)]
    else:
        if form == "one_header":
            lines.append(f"dt = {dt!r}")
        elif form == "one_comment_header":
            lines.append(f"# dt: {dt!r} s")
        lines += [repr(v) for v in values]
    lines = draw(mutated_lines(lines))
    return draw(byte_mutations("\n".join(lines).encode("utf-8", "surrogatepass") + b"\n"))


@st.composite
def at2_records(draw) -> bytes:
    _, dt, values = draw(sane_series())
    npts = len(values)
    style = draw(st.sampled_from(["new", "old"]))
    header = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        draw(
            st.sampled_from(["Test event 2000, Station, 090", "Caf\u00e9 \x1b[31m red", "a\x0bb"])
        ),
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {npts:7d}, DT= {dt:.4f} SEC" if style == "new" else f"  {npts}  {dt:.4f}  NPTS, DT",
    ]
    if draw(st.sampled_from([False, False, True])):  # garble a header line
        i = draw(st.integers(0, 3))
        header[i] = draw(
            st.one_of(
                st.text(max_size=40),
                st.builds(lambda n, d: f"NPTS= {n}, DT= {d}", numbers, numbers),
                st.builds(lambda n, d: f"{n} {d} NPTS, DT", numbers, numbers),
                st.sampled_from(
                    ["UNITS OF CM/S/S", "UNITS OF g", "NPTS=, DT=", "NPTS= 5 DT= 1e-", ""]
                ),
            )
        )
    body = [" ".join(f"{v / 9.80665: .7E}" for v in values[i : i + 5]) for i in range(0, npts, 5)]
    lines = header + draw(mutated_lines(body))
    if draw(st.sampled_from([False] * 9 + [True])):  # cut short
        lines = lines[: draw(st.integers(0, len(lines)))]
    return draw(byte_mutations("\n".join(lines).encode("utf-8") + b"\n"))


ATTR_VALUES = st.one_of(
    st.sampled_from(
        [
            *UNIT_FACTORS,
            "M/S2",
            " g ",
            "furlong",
            "",
            "s",
            "seconds",
            "seconds since 2000-01-01",
            "ms",
            "days",
            "m/s",
        ]
    ),
    st.text(max_size=8),
    st.floats(allow_nan=True),
    st.integers(-5, 5),
    st.lists(st.floats(-1, 1), min_size=1, max_size=3),
)


@st.composite
def netcdf_records(draw) -> bytes | None:
    import xarray as xr

    t0, dt, values = draw(sane_series(max_n=40))
    n = len(values)
    name = draw(st.sampled_from(["acceleration"] * 6 + ["accel", "time", "Acceleration"]))
    dims = draw(st.sampled_from([("time",)] * 10 + [("t",), ("time", "component"), ()]))
    accel = np.asarray(values, dtype=float)
    if draw(st.sampled_from([False, False, False, True])):  # splice in arbitrary floats
        extra = draw(
            st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=n, max_size=n)
        )
        accel = (
            np.where(draw(st.lists(st.booleans(), min_size=n, max_size=n)), extra, accel)
            if n
            else accel
        )
    dtype = draw(st.sampled_from(["f8", "f8", "f4", "i4", "S"]))
    if dims == ("time", "component"):
        accel = np.stack([accel, accel], axis=1)
    elif dims == ():
        accel = np.asarray(accel[0] if n else 0.0)
    with np.errstate(all="ignore"):
        data = accel.astype(dtype) if dtype != "S" else accel.astype(str).astype("S")
    variables = {name: (dims, data)}
    attrs = {}
    units = draw(st.sampled_from(["m s-2", None, "g", "cm/s2", " G ", "junk", "junk"]))
    if units is not None:
        attrs["units"] = draw(ATTR_VALUES) if units == "junk" else units
    coords = {}
    time_form = draw(st.sampled_from(["uniform"] * 8 + ["none", "random", "constant", "reversed"]))
    dim_len = accel.shape[0] if accel.ndim else 0
    if time_form != "none" and dims and dims[0] == "time":
        if time_form == "uniform":
            tvals = t0 + np.arange(dim_len) * dt
        elif time_form == "random":
            tvals = np.asarray(
                draw(st.lists(st.floats(allow_nan=True), min_size=dim_len, max_size=dim_len))
            )
        elif time_form == "constant":
            tvals = np.full(dim_len, t0)
        else:
            tvals = (t0 + np.arange(dim_len) * dt)[::-1]
        time_units = draw(st.sampled_from([None, "s", "seconds", "junk"]))
        tattrs = (
            {}
            if time_units is None
            else {"units": draw(ATTR_VALUES) if time_units == "junk" else time_units}
        )
        coords["time"] = ("time", tvals, tattrs)
    title = draw(st.sampled_from(["Quake\nline two", "T\x1b[2J", "ok"]))
    path = _WORK / f"gen{next(_COUNTER)}.nc"
    try:
        xr.Dataset(
            {k: (d, v, attrs) for k, (d, v) in variables.items()},
            coords=coords,
            attrs={"title": title},
        ).to_netcdf(path)
        data = path.read_bytes()
    except Exception:  # a combination netCDF cannot store: not a reader test
        return None
    finally:
        path.unlink(missing_ok=True)
    if draw(st.sampled_from([False, False, False, True])):
        data = draw(byte_mutations(data))
    return data


# --- the fuzz tests ----------------------------------------------------------------------------


@HEALTH
@given(
    data=st.binary(max_size=400),
    suffix=st.sampled_from([".txt", ".AT2", ".nc", ".csv", ".dat", ".NC"]),
)
def test_fuzz_random_bytes(data, suffix):
    path = write(f"random{suffix}", data)
    got = check_file(path)
    if got is not None:
        check_downstream(path, *got)


@HEALTH
@given(
    data=text_records(),
    units=st.sampled_from([None, None, "g", "cm/s2", "m s-2"]),
    dt=st.sampled_from([None, None, 0.01, 1e-9]),
)
def test_fuzz_text_records(data, units, dt):
    path = write("record.txt", data)
    got = check_file(path, units=units, dt=dt)
    if got is not None:
        check_downstream(path, *got, units=units, dt=dt)


@HEALTH
@given(data=at2_records(), units=st.sampled_from([None, None, "g", "m/s2"]))
def test_fuzz_at2_records(data, units):
    path = write("record.AT2", data)
    got = check_file(path, units=units)
    if got is not None:
        check_downstream(path, *got, units=units)


@HEALTH
@given(
    data=netcdf_records(),
    units=st.sampled_from([None, None, "g", "m s-2"]),
    suffix=st.sampled_from([".nc"] * 5 + [".txt"]),
)
def test_fuzz_netcdf_records(data, units, suffix):
    assume(data is not None)  # a combination netCDF cannot store
    path = write(f"record{suffix}", data)
    got = check_file(path, units=units)
    if got is not None:
        check_downstream(path, *got, units=units)


def _run_info(argv):
    """(exit status, stdout, stderr) of ``stonedem record info`` run in-process under
    stonedem.entry.guarded."""
    from stonedem.entry import guarded
    from stonedem.motion.cli import build_parser

    args = build_parser().parse_args(["record", "info", *argv])
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = guarded(lambda: args.handler(args))
    return status, out.getvalue(), err.getvalue()


GOOD_TEXT = b"# time, acceleration\n" + b"".join(
    f"{i * 0.01:.2f} {math.sin(i / 3):.5f}\n".encode() for i in range(80)
)


@HEALTH
@given(
    source=st.sampled_from(
        ["good_txt"] * 3 + ["name", "zeros", "junk", "missing", "empty", "nul", "folder", "one_col"]
    ),
    units=st.sampled_from([None] * 4 + ["g", "cm/s2", "furlong", ""]),
    dt=st.sampled_from([None] * 5 + ["0.01", "abc", "nan", "-1", "1e-9", "inf"]),
    damping=st.sampled_from([None] * 3 + [["0.05"], ["1.5"], ["nan"], ["0"], ["x"], ["0.02"] * 11]),
    plot=st.sampled_from(
        ["ok.png"] * 3 + ["ok.svg", "ok.txt", "dir", "input", "under_file", "", "deep/new/ok.png"]
    ),
)
def test_fuzz_record_info_arguments(source, units, dt, damping, plot):
    work = fresh_folder()
    files = {
        "good_txt": ("good.txt", GOOD_TEXT),
        "junk": ("junk.txt", b"\x00\xff garbage\n"),
        "one_col": ("one.txt", b"0.1\n0.2\n0.3\n"),
        "zeros": ("zeros.txt", b"0 0\n0.01 0\n0.02 0\n"),
    }
    if source in files:
        name, content = files[source]
        (work / name).write_bytes(content)
        record = str(work / name)
    else:
        record = {
            "name": "northridge_1994_mul009",
            "missing": str(work / "nope.txt"),
            "empty": "",
            "nul": "a\x00b",
            "folder": str(work),
        }[source]
    (work / "a_file").write_bytes(b"")
    (work / "dir").mkdir()
    target = {
        "dir": str(work / "dir"),
        "input": record,
        "under_file": str(work / "a_file" / "x.png"),
        "": "",
    }.get(plot, str(work / plot))
    argv = [record, "--plot", target]
    if units is not None:
        argv += ["--units", units]
    if dt is not None:
        argv += ["--dt", dt]
    if damping is not None:
        argv += ["--damping", *damping]
    before = sorted(p.relative_to(work) for p in work.rglob("*"))
    status, out, err = _run_info(argv)
    assert status in (0, 2), (status, err)
    if status == 2:
        lines = err.splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: ") and one_line(lines[0]), err
        assert out == "", "nothing printed before the error"
        after = sorted(p.relative_to(work) for p in work.rglob("*") if p.is_file())
        assert after == sorted(p for p in before if (work / p).is_file()), "nothing written"
    else:
        assert err == "" and "predominant freq." in out
        assert Path(target).stat().st_size > 500
        if source == "zeros":
            assert "none (the record is all zeros)" in out


@pytest.fixture(scope="module", autouse=True)
def _cleanup():
    yield
    shutil.rmtree(_WORK, ignore_errors=True)
