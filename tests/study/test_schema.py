"""The config schema's generated $defs (stonedem.study.schema) and the typed checks."""

import math
from pathlib import Path

import pytest
import yaml

from stonedem.errors import InputError
from stonedem.study.grid import PARAMETERS, SWEPT, check_value
from stonedem.study.schema import generated_defs, main, render
from stonedem.study.search import SEARCH

ROOT = Path(__file__).resolve().parents[2]
SCHEMA_FILE = ROOT / "workflow" / "schemas" / "config.schema.yaml"


def test_the_committed_schema_is_what_the_rows_generate():
    text = SCHEMA_FILE.read_text()
    assert render(text) == text, "run python -m stonedem.study.schema"
    assert main([str(SCHEMA_FILE), "--check"]) == 0


def test_the_command_refuses_in_one_line_and_writes_only_when_stale(tmp_path, capsys):
    stale = tmp_path / "config.schema.yaml"
    text = SCHEMA_FILE.read_text()
    stale.write_text(text.replace("$defs/pga", "$defs/nothing"))
    assert main([str(stale), "--check"]) == 1
    assert main([str(stale)]) == 0 and stale.read_text() == text
    for bad, message in (
        (tmp_path / "none.yaml", "the config schema not found"),
        (tmp_path, "is a folder, not the config schema"),
    ):
        assert main([str(bad)]) == 2
        assert message in capsys.readouterr().err
    other = tmp_path / "other.yaml"
    other.write_text("a: 1\n")
    assert main([str(other)]) == 2 and other.read_text() == "a: 1\n"
    assert "SCHEMA: has no generated block" in capsys.readouterr().err
    defs = yaml.safe_load(text)["$defs"]
    assert {key: defs[key] for key in generated_defs()} == generated_defs()
    assert set(defs["grid"]["properties"]) == set(PARAMETERS) == set(SWEPT.keys)
    assert set(defs["search"]["properties"]) == set(SEARCH.keys)


def test_a_new_parameter_row_reaches_the_schema(monkeypatch):
    from stonedem.io.spec import Field, Spec
    from stonedem.study import schema

    row = Field("duration_scale", units="1", range="(0, 2]", doc="time scale of the record")
    monkeypatch.setattr(schema, "SWEPT", Spec((*SWEPT.fields, row)))
    text = render(SCHEMA_FILE.read_text())
    defs = yaml.safe_load(text)["$defs"]
    assert defs["duration_scale"] == {
        "type": "number",
        "exclusiveMinimum": 0,
        "maximum": 2,
        "description": "time scale of the record",
    }
    assert defs["grid"]["properties"]["duration_scale"]["items"] == {
        "$ref": "#/$defs/duration_scale"
    }
    assert defs["case"]["properties"]["duration_scale"] == {"$ref": "#/$defs/duration_scale"}


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("pga", "1.0e9", "expected a number, got text '1.0e9'; write it as a YAML number"),
        ("pga", "high", "expected a number, got text 'high'; give a number in m s-2"),
        ("pga", -1, "must be > 0, got -1 m s-2"),
        ("pga", math.nan, "nan is not finite"),
        ("pga", None, "expected a number, got nothing (null)"),
        ("n_drums", 3.0, "must be an integer, got a number 3.0"),
        ("n_drums", 0, "must be >= 1 and <= 100, got 0; give an integer 1 ... 100"),
        ("weak_joint", 100, "must be >= 0 and <= 99, got 100"),
        ("friction", -0.1, "must be >= 0, got -0.1"),
        ("epistyle_type", "e", "unknown value 'e'; use one of: a, b, c, d, per_span"),
        ("record", "a/b", "expected a record name, got text 'a/b'; give a name listed"),
        ("component", "FF7a", "expected a component name, got text 'FF7a'; give e.g. FF07a"),
    ],
)
def test_a_bad_swept_value_is_refused_in_one_line(key, value, message):
    with pytest.raises(InputError) as error:
        check_value(f"studies.s.grid.{key}[0]", key, value)
    assert str(error.value).startswith(f"studies.s.grid.{key}[0]: {message}"), str(error.value)


@pytest.mark.parametrize(
    "key, value", [("pga", 3), ("friction", -0.0), ("n_drums", 2), ("component", "NN12a")]
)
def test_a_swept_value_is_kept_as_written(key, value):
    assert check_value("v", key, value) is value  # 3 stays an int, -0.0 keeps its sign
