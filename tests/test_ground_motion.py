"""Excitation specs and record files: scaling, units, and one-line errors for bad records."""

import numpy as np
import pytest

from dem.errors import InputError
from dem.ground_motion import excitation_from_spec, excitation_pair, read_record

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
    h, v = excitation_pair({"kind": "harmonic", "frequency": 1.0, "amplitude": 0.1,
                            "vertical": {"kind": "sine_pulse", "accel": 2.0, "frequency": 2.0}})
    assert h.pga == pytest.approx(0.1 * (2 * np.pi) ** 2) and v.pga == 2.0


@pytest.mark.parametrize("content, message", [
    ("0 0.1\n0.01 nan\n0.02 0.3\n", "NaN or infinite"),
    ("0 0.1\n0.01 inf\n0.02 0.3\n", "NaN or infinite"),
    ("0 0.1\n0.02 0.2\n0.01 0.3\n", "time not increasing"),
    ("0 0.1\n0.01 0.2\n0.03 0.3\n", "non-uniform time step"),
    ("0 0.1\n0.01 abc\n", "non-numeric"),
    ("0 0.1 3\n0.01 0.2 4\n", "3 columns"),
    ("0 0.1\n0.01\n", "expected 2"),
    ("# nothing\n", "no samples"),
    ("0.1\n0.2\n0.3\n", "no time step"),
])
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


@pytest.mark.parametrize("spec, field", [
    ({"kind": "harmonic", "frequency": -1, "amplitude": 0.1}, "excitation.frequency"),
    ({"kind": "harmonic", "amplitude": 0.1}, "excitation.frequency"),
    ({"kind": "quake"}, "excitation.kind"),
    ({"kind": "ramp", "rate": 0.5, "speed": 2}, "excitation.speed"),
    ({"kind": "record", "file": "no_such_record"}, "excitation.file"),
    ({"kind": "record", "file": REC, "scale": 2, "pga": 3}, "excitation"),
])
def test_bad_excitation_specs(spec, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        excitation_from_spec(spec)
