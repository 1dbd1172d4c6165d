"""The declared-input kit: a field's checks, a spec's keys and rules, and the copies generated
from them (JSON schema, docs table)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from stonedem.errors import InputError
from stonedem.io.spec import (
    REQUIRED,
    Derived,
    Field,
    Spec,
    check,
    exactly_one,
    json_schema,
    key_table,
    not_both,
    parse_range,
)

CONTACT = Spec(
    (
        Field("k_n", "number", "N m-2", "(0, 1e16]", 1e11, "give k_n in N/m2"),
        Field("k_t", "number", "N m-1", "(0, 1e18]", Derived("k_n x 1 m", lambda v: v["k_n"])),
        Field("kernel", "choice", choices=("auto", "general"), default="auto"),
        Field("n", "integer", range="[1, 100]", default=1),
        Field("dt", "number", "s", "(0, inf)", auto=True),
        Field("center", "numbers", "m", length=2, default=[0.0, 0.0], hint="write [x, y]"),
        Field("on", "flag", default=True),
        Field("duration", "number", "s", "(0, 3600]", REQUIRED, "give the time in s"),
    ),
    rules=(not_both("k_n", "dt"),),
)


def test_values_are_checked_and_defaulted():
    values = check(CONTACT, {"k_n": "1.0e9", "duration": np.float32(2.0), "n": 3.0}, "contact")
    assert values == {
        "k_n": 1e9,
        "k_t": 1e9,
        "kernel": "auto",
        "n": 3,
        "dt": None,
        "center": [0.0, 0.0],
        "on": True,
        "duration": 2.0,
    }
    assert type(values["n"]) is int and CONTACT.check({"duration": 1, "dt": "auto"})["dt"] is None


@pytest.mark.parametrize(
    "given, message",
    [
        ({"k_n": -1.0}, "contact.k_n: must be > 0 and <= 1e+16, got -1 N m-2; give k_n in N/m2"),
        ({"k_n": "abc"}, "contact.k_n: expected a number, got text 'abc'; give a number in N m-2"),
        ({"k_t": float("nan")}, "contact.k_t: nan is not finite; give a finite number"),
        ({"zz": 1}, "contact.zz: unknown key; allowed keys: k_n, k_t, kernel, n, dt, center, on"),
        ({"kernel": "x"}, "contact.kernel: unknown value 'x'; use one of: auto, general"),
        ({"n": 2.5}, "contact.n: must be an integer, got a number 2.5; give a whole number"),
        ({"n": "3"}, "contact.n: must be an integer, got text '3'"),
        ({"n": True}, "contact.n: must be an integer, got a boolean True"),
        ({"n": 0}, "contact.n: must be >= 1 and <= 100, got 0; give a value >= 1 and <= 100"),
        ({"n": 10**400}, "contact.n: must be >= 1 and <= 100, got 100000000000000000..."),
        ({"center": [1]}, "contact.center: expected a list of 2 numbers, got a list [1]; write"),
        ({"center": [1, "a"]}, "contact.center[1]: expected a number"),
        ({"on": "yes"}, "contact.on: expected true or false, got text 'yes'"),
        ({"k_n": 1, "dt": 1}, "contact: give k_n or dt, not both; remove one"),
        ({}, "contact.duration: missing; give the time in s"),
    ],
)
def test_a_bad_value_is_one_line_naming_the_field(given, message):
    with pytest.raises(InputError) as err:
        CONTACT.check(
            {"duration": 1.0, **given} if "duration" not in given and given else given, "contact"
        )
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


def test_not_a_mapping_names_the_allowed_keys():
    with pytest.raises(
        InputError, match=r"^contact: expected a mapping, got a list \[1\]; allowed"
    ):
        CONTACT.check([1], "contact")
    with pytest.raises(InputError, match=r"^contact\.\\x1b\[31m: unknown key"):
        CONTACT.check({"\x1b[31m": 1}, "contact")


def test_nested_specs_and_rules():
    box = Spec((Field("width", "number", "m", "(0, inf)", REQUIRED),))
    body = Spec(
        (Field("box", "mapping", spec=box), Field("polygon", "list")),
        rules=(exactly_one("box", "polygon", fix="describe the shape once"),),
    )
    bodies = Spec((Field("bodies", "list", spec=body, limit=2, default=[]),))
    assert bodies.check({"bodies": [{"box": {"width": 1}}]})["bodies"][0]["box"] == {"width": 1.0}
    with pytest.raises(InputError, match=r"^bodies\[0\]\.box\.width: must be > 0"):
        bodies.check({"bodies": [{"box": {"width": 0}}]})
    with pytest.raises(InputError, match=r"^bodies\[1\]: give exactly one of box: or polygon:"):
        bodies.check({"bodies": [{"box": {"width": 1}}, {}]})
    with pytest.raises(InputError, match=r"^bodies: 3 items exceed the limit 2"):
        bodies.check({"bodies": [{}, {}, {}]})


def test_a_declaration_typo_fails_at_import():
    with pytest.raises(ValueError, match="range"):
        Field("x", range="0..1")
    with pytest.raises(ValueError, match="kind"):
        Field("x", "float")
    with pytest.raises(ValueError, match="twice"):
        Spec((Field("x"), Field("x")))
    assert parse_range("[0, inf)") == (0.0, float("inf"), False, True)


def test_the_schema_and_the_table_come_from_the_rows():
    schema = json_schema(CONTACT)
    assert schema["additionalProperties"] is False and schema["required"] == ["duration"]
    assert schema["properties"]["k_n"] == {
        "type": "number",
        "exclusiveMinimum": 0,
        "maximum": 1e16,
        "description": "give k_n in N/m2 [N m-2]",
    }
    assert schema["properties"]["dt"]["anyOf"][1] == {"const": "auto"}
    assert schema["properties"]["center"]["minItems"] == 2
    json.dumps(schema)  # plain JSON types only
    table = key_table(CONTACT)
    assert table[2] == "| `k_n` | number | N m-2 | > 0 and <= 1e+16 | 1e+11 | give k_n in N/m2 |"
    assert "| `k_t` | number | N m-1 | > 0 and <= 1e+18 | k_n x 1 m |  |" in table
    assert table[-1] == "| (top) | rule | | | | give k_n or dt, not both |"


def test_an_absent_section_is_checked_as_empty():
    solver = Spec((Field("duration", "number", "s", "(0, inf)", REQUIRED, "give it in s"),))
    top = Spec((Field("solver", "mapping", spec=solver, default={}),))
    with pytest.raises(InputError, match=r"^solver\.duration: missing; give it in s"):
        top.check({})
    output = Spec((Field("every", "number", "s", "(0, inf)", 0.001),))
    given = Spec((Field("output", "mapping", spec=output, default={}),)).check({})
    assert given == {"output": {"every": 0.001}}
    # an optional section (default None) stays absent
    assert Spec((Field("output", "mapping", spec=output),)).check({}) == {"output": None}


def test_strict_fields_take_plain_numbers_only():
    n = Field("n", "integer", range="[1, 10]", strict=True)
    x = Field("x", "number", "s", "(0, inf)", strict=True)
    assert n.check(3) == 3 and x.check(np.float64(2.0)) == 2.0
    with pytest.raises(InputError, match=r"^n: must be an integer, got a number 3\.0"):
        n.check(3.0)
    with pytest.raises(
        InputError, match=r"^x: expected a number, got text '1\.0e3'; write it as a"
    ):
        x.check("1.0e3")


def test_item_counts_and_plain_items():
    names = Field("names", "list", spec=Field("name", "choice", choices=("a", "b")), min_items=1)
    assert names.check(["a", "b"]) == ["a", "b"]
    with pytest.raises(InputError, match=r"^names: none given, at least 1 needed"):
        names.check([])
    with pytest.raises(InputError, match=r"^names\[1\]: unknown value 'c'; use one of: a, b"):
        names.check(["a", "c"])
    table = Field("t", "mapping", min_items=1, hint="write t: {a: 1}")
    with pytest.raises(InputError, match=r"^t: expected a mapping, got nothing \(null\); write t"):
        table.check(None)
    with pytest.raises(InputError, match=r"^t: none given, at least 1 needed; write t: \{a: 1\}"):
        table.check({})
