"""Excitation specs and record files: scaling, units, and one-line errors for bad records."""

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.motion.excitation import excitation_from_spec, excitation_pair
from stonedem.motion.records import read_record

REC = "tests/data/records/synthetic_two_column.txt"


def test_harmonic_pga_and_description():
    m = excitation_from_spec({"kind": "harmonic", "frequency": 0.5, "amplitude": 0.25})
    assert m.pga == pytest.approx(0.25 * np.pi**2)
    assert m.description["frequency_units"] == "Hz"


def test_record_scaling_by_factor_and_to_pga_is_exact():
    raw = excitation_from_spec({"kind": "record", "file": REC})
    doubled = excitation_from_spec({"kind": "record", "file": REC, "scale": 2.0})
    target = excitation_from_spec({"kind": "record", "file": REC, "pga": 9.81})
    assert doubled.pga == pytest.approx(2.0 * raw.pga, rel=1e-15)
    assert target.pga == pytest.approx(9.81, rel=1e-15)
    in_g = excitation_from_spec({"kind": "record", "file": REC, "units": "g"})
    assert in_g.pga == pytest.approx(9.80665 * raw.pga, rel=1e-15)


def test_records_found_by_name_in_records_folder():
    m = excitation_from_spec({"kind": "record", "file": "northridge_1994_mul009"})
    assert m.pga == pytest.approx(4.077, rel=1e-3) and m.duration == pytest.approx(29.98)


def test_vertical_excitation_beside_horizontal():
    h, v = excitation_pair(
        {
            "kind": "harmonic",
            "frequency": 1.0,
            "amplitude": 0.1,
            "vertical": {"kind": "sine_pulse", "accel": 2.0, "frequency": 2.0},
        }
    )
    assert h.pga == pytest.approx(0.1 * (2 * np.pi) ** 2) and v.pga == 2.0


@pytest.mark.parametrize(
    "content, message",
    [
        ("0 0.1\n0.01 nan\n0.02 0.3\n", "NaN or infinite"),
        ("0 0.1\n0.01 inf\n0.02 0.3\n", "NaN or infinite"),
        ("0 0.1\n0.02 0.2\n0.01 0.3\n", "time not increasing"),
        ("0 0.1\n0.01 0.2\n0.03 0.3\n", "non-uniform time step"),
        ("0 0.1\n0.01 abc\n", "non-numeric"),
        ("0 0.1 3\n0.01 0.2 4\n", "3 columns"),
        ("0 0.1\n0.01\n", "expected 2"),
        ("# nothing\n", "no samples"),
        ("0.1\n0.2\n0.3\n", "no time step"),
    ],
)
def test_bad_records_give_one_line_naming_the_field(tmp_path, content, message):
    path = tmp_path / "bad.txt"
    path.write_text(content)
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": str(path)})
    text = str(err.value)
    assert text.startswith("excitation.file") and message in text and "\n" not in text, text


def test_one_column_record_with_dt_header(tmp_path):
    path = tmp_path / "one.txt"
    path.write_text("dt = 0.02\n0.0\n1.0\n0.5\n")
    t, a, _ = read_record(path, "f")
    assert t == pytest.approx([0, 0.02, 0.04]) and a == pytest.approx([0, 1.0, 0.5])


@pytest.mark.parametrize(
    "spec, field",
    [
        ({"kind": "harmonic", "frequency": -1, "amplitude": 0.1}, "excitation.frequency"),
        ({"kind": "harmonic", "amplitude": 0.1}, "excitation.frequency"),
        ({"kind": "quake"}, "excitation.kind"),
        ({"kind": "ramp", "rate": 0.5, "speed": 2}, "excitation.speed"),
        ({"kind": "record", "file": "no_such_record"}, "excitation.file"),
        ({"kind": "record", "file": REC, "scale": 2, "pga": 3}, "excitation"),
    ],
)
def test_bad_excitation_specs(spec, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        excitation_from_spec(spec)


# --- hostile record files (issue 13): one line naming the field, or a sane record ------------


def _refused(path, message, field="excitation.file", **spec):
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": str(path), **spec})
    text = str(err.value)
    assert err.value.field == field and message in text, text
    assert all(ch.isprintable() for ch in text), repr(text)
    return text


def _netcdf(
    path,
    accel=(0.0, 0.3, -0.2, 0.1),
    time=None,
    name="acceleration",
    dims=("time",),
    units="m s-2",
    time_units="s",
    **encoding,
):
    import xarray as xr

    accel = np.asarray(accel)
    time = np.arange(len(accel)) * 0.01 if time is None else np.asarray(time)
    attrs = {} if units is None else {"units": units}
    coords = (
        {"time": ("time", time, {} if time_units is None else {"units": time_units})}
        if "time" in dims
        else {}
    )
    xr.Dataset({name: (dims, accel, attrs)}, coords=coords).to_netcdf(
        path, encoding={name: encoding}
    )
    return path


@pytest.mark.parametrize(
    "content, message",
    [
        (b"\x00\x01\x02garbage\xff\n", "binary file"),
        (b"0 0.1\n0.01 0.2\xe9\n", "not UTF-8"),
        (b"0 0.1\n" + b"9" * 20000 + b"\n", "longer than"),
        (b"0 0.1\n", "fewer than 2 samples"),
        (b"dt = 1e-7\n0.1\n0.2\n", "outside [0.0001, 1] s"),
        (b"dt = 5\n0.1\n0.2\n", "outside [0.0001, 1] s"),
        (b"dt = abc\n0.1\n0.2\n", "bad dt header"),
        (b"0 0.1\n0.01 2000\n", "above the 100 g limit"),
        (b"0 0.1\n0.01 1e308\n", "above the 100 g limit"),
        (b"# dt = 0.01\n# dt = 0.02\n0.1\n0.2\n", "a second dt header"),
    ],
)
def test_hostile_text_records(tmp_path, content, message):
    path = tmp_path / "bad.txt"
    path.write_bytes(content)
    _refused(path, message)


def test_file_names_in_messages_are_one_line(tmp_path):
    path = tmp_path / "two\nlines\x1b[31m.txt"
    path.write_bytes(b"\xff\xfe")
    text = _refused(path, "not UTF-8")
    assert "two\\nlines\\x1b[31m.txt" in text


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda p: p.write_bytes(b"this is not netcdf"), "not a readable NetCDF file"),
        (lambda p: p.write_bytes(b""), "not a readable NetCDF file"),
        (lambda p: p.write_bytes(_netcdf(p).read_bytes()[:300]), "not a readable NetCDF file"),
        (lambda p: _netcdf(p, name="accel"), "no variable 'acceleration' (it has: accel, time)"),
        (lambda p: _netcdf(p, accel=np.zeros((4, 2)), dims=("time", "component")), "dimensions"),
        (lambda p: _netcdf(p, dims=("t",)), "dimensions"),
        (lambda p: _netcdf(p, accel=[0.1, np.nan, 0.2]), "NaN or infinite"),
        (lambda p: _netcdf(p, accel=[0.1, np.inf, 0.2]), "NaN or infinite"),
        (lambda p: _netcdf(p, time=[0.0, 0.02, 0.01, 0.03]), "time not increasing"),
        (lambda p: _netcdf(p, time=[0.0, 0.01, 0.03, 0.04]), "non-uniform time step"),
        (lambda p: _netcdf(p, accel=[0.3]), "fewer than 2 samples"),
        (lambda p: _netcdf(p, units="furlong/fortnight2"), "unknown acceleration units"),
        (lambda p: _netcdf(p, time_units="days"), "time units 'days'"),
        (lambda p: _netcdf(p, time_units="seconds since 2000-01-01"), "time units"),
        (lambda p: _netcdf(p, accel=np.array([b"a", b"b"])), "not real numbers"),
    ],
)
def test_hostile_netcdf_records(tmp_path, make, message):
    path = tmp_path / "bad.nc"
    make(path)
    _refused(path, message)


def test_netcdf_without_a_time_coordinate_is_refused(tmp_path):
    import xarray as xr

    path = tmp_path / "no_time.nc"
    xr.Dataset({"acceleration": ("time", np.array([0.1, 0.2, 0.3]))}).to_netcdf(path)
    _refused(path, "no 'time' coordinate")


def test_netcdf_units_are_its_own(tmp_path):
    path = _netcdf(tmp_path / "r.nc", units="m s-2")
    text = _refused(path, "carries its own", field="excitation.units", units="g")
    assert "declares its acceleration in 'm s-2'" in text
    same = excitation_from_spec(
        {"kind": "record", "file": str(path), "units": "m/s2", "baseline": False}
    )
    assert same.pga == pytest.approx(0.3)
    in_g = excitation_from_spec(
        {"kind": "record", "file": str(_netcdf(tmp_path / "g.nc", units="g")), "baseline": False}
    )
    assert in_g.pga == pytest.approx(0.3 * 9.80665)
    no_units = _netcdf(tmp_path / "plain.nc", units=None)  # no attribute: units: applies
    assert excitation_from_spec(
        {"kind": "record", "file": str(no_units), "units": "g", "baseline": False}
    ).pga == pytest.approx(0.3 * 9.80665)


def test_a_conflicting_dt_is_refused(tmp_path):
    _refused(REC, "dt gives 0.02 s", field="excitation.dt", dt=0.02)
    one = tmp_path / "one.txt"
    one.write_text("dt = 0.01\n0.1\n0.2\n0.3\n")
    _refused(one, "declares dt = 0.01 s, dt gives 0.02 s", field="excitation.dt", dt=0.02)
    assert excitation_from_spec(
        {"kind": "record", "file": str(one), "dt": 0.01}
    ).duration == pytest.approx(0.02)


@pytest.mark.parametrize(
    "value, message",
    [
        (None, "give at least one of file: or component:"),  # null is an absent key
        (["a"], "expected a file name or path"),
        (True, "expected a file name or path"),
        ("", "empty record name"),
        ("a\x00b", "NUL character"),
        ("x" * 5000, "over 4096 characters"),
    ],
)
def test_bad_record_names(value, message):
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": value})
    assert err.value.field == "excitation.file" and message in str(err.value), str(err.value)


def test_a_folder_is_not_a_record(tmp_path):
    _refused(tmp_path, "(a folder)")


@pytest.mark.parametrize(
    "spec, field, message",
    [
        ({"units": ["g"]}, "excitation.units", "unknown units"),
        ({"units": "furlong"}, "excitation.units", "unknown units"),
        ({"pga": 5000.0}, "excitation.pga", "above the 100 g limit"),
        ({"scale": 1e300}, "excitation.scale", "above the 100 g limit"),
        ({"dt": 0.02}, "excitation.dt", "has a time step of 0.01 s, dt gives 0.02 s"),
    ],
)
def test_bad_record_keys(spec, field, message):
    with pytest.raises(InputError) as err:
        excitation_from_spec({"kind": "record", "file": "northridge_1994_mul009", **spec})
    assert err.value.field == field and message in str(err.value), str(err.value)


def test_sample_limit_is_checked_before_reading(tmp_path, monkeypatch):
    from stonedem.motion import records

    big = _netcdf(tmp_path / "long.nc", accel=np.zeros(records.MAX_RECORD_SAMPLES + 1), zlib=True)
    _refused(big, f"more than {records.MAX_RECORD_SAMPLES} samples")
    monkeypatch.setattr(records, "MAX_RECORD_SAMPLES", 5)
    text = tmp_path / "t.txt"
    text.write_text("".join(f"{i * 0.01} 0.1\n" for i in range(6)))
    _refused(text, "more than 5 samples")


def test_file_size_limit(tmp_path):
    from stonedem.motion import records

    path = tmp_path / "huge.txt"
    with open(path, "wb") as f:  # sparse: instant, no disk used
        f.truncate(records.MAX_RECORD_BYTES + 1)
    _refused(path, "MB limit")


def test_a_special_file_is_not_a_record(tmp_path):
    import os

    fifo = tmp_path / "pipe.txt"
    os.mkfifo(fifo)
    _refused(fifo, "not a record file")


def test_records_resolve_from_the_installed_package_data(tmp_path, monkeypatch):
    import shutil

    from stonedem.motion import records as ground_motion

    installed = tmp_path / "site" / "stonedem" / "_records"
    installed.mkdir(parents=True)
    shutil.copy("records/northridge_1994_mul009.nc", installed)
    monkeypatch.setattr(ground_motion, "checkout_records_dir", lambda: None)
    monkeypatch.setattr(ground_motion, "packaged_records_dir", lambda: installed)
    monkeypatch.chdir(tmp_path)
    path = ground_motion.resolve_record("northridge_1994_mul009", "excitation.file", tmp_path)
    assert path == installed / "northridge_1994_mul009.nc"
    with pytest.raises(InputError) as err:
        ground_motion.resolve_record("nope", "excitation.file", tmp_path)
    assert str(installed) in str(err.value) and "northridge_1994_mul009" in str(err.value)


def test_the_package_ships_the_records():
    from pathlib import Path

    import tomllib

    config = tomllib.loads(Path("pyproject.toml").read_text())["tool"]["setuptools"]
    assert config["package-dir"] == {"": "src", "stonedem._records": "records"}
    assert "*.nc" in config["package-data"]["stonedem._records"]
    assert Path("src/stonedem/_records/__init__.py").is_file(), (
        "lets package discovery find stonedem._records"
    )
    assert len(list(Path("records").glob("*.nc"))) >= 4


def test_records_that_broke_the_baseline_correction(tmp_path):
    # found by tests/motion/test_fuzz_records.py: subnormal samples overflowed the baseline fit to
    # inf (it now works on acc / 2^k)
    tiny = tmp_path / "tiny.txt"
    tiny.write_text("0 0\n0.005 2.2e-313\n")
    motion = excitation_from_spec({"kind": "record", "file": str(tiny)})
    assert np.all(np.isfinite(motion.table_accel)) and np.all(np.isfinite(motion.table_disp))
    # a 9-sample, 30 g record: its correction is 3x its peak; named as the file's, not scale's
    short = tmp_path / "short.txt"
    short.write_text(
        "0.0 2.0\n0.005 0.0\n0.01 -13.0\n0.015 0.0\n0.02 30.0\n0.025 0\n0.03 0\n0.035 0\n0.04 0\n"
    )
    _refused(short, "baseline correction raises the peak to 987.3 m/s2", units="g")
    assert excitation_from_spec(
        {"kind": "record", "file": str(short), "units": "g", "baseline": False}
    ).pga == pytest.approx(30 * 9.80665)


def test_a_record_found_once_is_found_again_without_a_search_until_its_file_is_gone(
    tmp_path, monkeypatch
):
    import shutil

    from stonedem.motion import records as ground_motion

    shutil.copy("records/northridge_1994_mul009.nc", tmp_path / "quake.nc")
    monkeypatch.chdir(tmp_path)
    first = ground_motion.resolve_record("quake", "excitation.file", tmp_path)
    looked = []
    monkeypatch.setattr(
        ground_motion.Path, "is_file", lambda self: looked.append(self) or self.exists()
    )
    assert (
        ground_motion.resolve_record("quake", "excitation.file", tmp_path)
        == first
        == tmp_path / "quake.nc"
    )
    assert looked == [first]  # one check of the path found before, no search
    first.unlink()
    with pytest.raises(InputError, match="record 'quake' not found"):
        ground_motion.resolve_record("quake", "excitation.file", tmp_path)


# --- sequences (issue 48): parts back to back with a rest -----------------------------------

PULSE = {"kind": "rect_pulse", "accel": 3.0, "duration": 0.5}


def test_sequence_windows_labels_and_composite_motion():
    m = excitation_from_spec({"kind": "sequence", "parts": [PULSE, PULSE], "rest": 2.0})
    assert m.starts == (0.0, 2.5) and m.duration == pytest.approx(5.0)
    assert m.pga == 3.0 and m.shortest_period == 0.5
    assert "sequence of 2" in m.label and "rest 2 s" in m.label
    # the second pulse starts on the velocity and displacement the first left
    d, v, a = m.evaluate(np.array([0.25, 1.0, 2.5, 2.75, 10.0]))
    assert a.tolist() == [3.0, 0.0, 3.0, 3.0, 0.0]
    assert v[1] == pytest.approx(1.5) and v[3] == pytest.approx(1.5 + 0.75)
    assert v[4] == pytest.approx(3.0)
    d_end = 0.5 * 3.0 * 0.25 + 1.5 * 2.0  # first pulse, then coasting to t = 2.5
    assert d[2] == pytest.approx(d_end, rel=1e-15)
    assert d[3] == pytest.approx(d_end + 1.5 * 0.25 + 0.5 * 3.0 * 0.25**2, rel=1e-15)


@pytest.mark.parametrize(
    "spec, field, words",
    [
        ({"kind": "sequence"}, "excitation.parts", "missing"),
        ({"kind": "sequence", "parts": []}, "excitation.parts", "at least 1"),
        ({"kind": "sequence", "parts": PULSE}, "excitation.parts", "expected a list"),
        ({"kind": "sequence", "parts": [PULSE] * 21}, "excitation.parts", "limit 20"),
        ({"kind": "sequence", "parts": [PULSE], "rest": -1}, "excitation.rest", ""),
        ({"kind": "sequence", "parts": [PULSE], "rest": "long"}, "excitation.rest", ""),
        (
            {"kind": "sequence", "parts": [{"kind": "harmonic", "frequency": 1, "amplitude": 0.1}]},
            "excitation.parts[0].kind",
            "no natural length",
        ),
        (
            {"kind": "sequence", "parts": [PULSE, {"kind": "ramp", "rate": 1.0}]},
            "excitation.parts[1].kind",
            "no natural length",
        ),
        (
            {"kind": "sequence", "parts": [{"kind": "sequence", "parts": [PULSE]}]},
            "excitation.parts[0].kind",
            "inside a sequence",
        ),
        (
            {"kind": "sequence", "parts": [{**PULSE, "vertical": PULSE}]},
            "excitation.parts[0].vertical",
            "horizontal parts only",
        ),
        ({"kind": "sequence", "parts": [{**PULSE, "accel": "x"}]}, "excitation.parts[0].accel", ""),
        ({"kind": "sequence", "parts": [7]}, "excitation.parts[0]", "mapping"),
    ],
)
def test_bad_sequences_give_one_line_naming_the_key(spec, field, words):
    with pytest.raises(InputError) as err:
        excitation_from_spec(spec)
    assert err.value.field == field and words in str(err.value), str(err.value)
    assert "\n" not in str(err.value)


def test_sequence_refuses_a_vertical_motion():
    with pytest.raises(InputError) as err:
        excitation_pair({"kind": "sequence", "parts": [PULSE], "vertical": PULSE})
    assert err.value.field == "excitation.vertical"
