"""Declared inputs: every key a user may write is one :class:`Field` row, and every input
kind (a scene, a contact law, an excitation, a structure, a study grid, a wall case, the
figure options) is a :class:`Spec` of them.

``check(spec, mapping, where)`` returns the checked values, defaults filled in, or raises
one :class:`~stonedem.errors.InputError` line that names the field and gives its own hint.
The same rows generate the copies that used to be typed twice: the study config's JSON
schema (:func:`json_schema`) and the key tables of the docs (:func:`key_table`).

Our own rather than pydantic or attrs/cattrs: the messages are one line with a fix, YAML 1.1
gives numbers as text (``1.0e9``), and an import must stay cheap (docs/notebook.md, issue 46).
"""

from __future__ import annotations

import math
import numbers
import re
import reprlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

from stonedem.errors import InputError, one_line

KINDS = ("number", "integer", "flag", "text", "choice", "numbers", "mapping", "list", "any")


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()  # a Field default: the key must be given

# a number written as text: YAML 1.1 reads 1.0e9 (no sign in the exponent) as a string
NUMERIC_TEXT = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")
YAML_NUMBER = "write it as a YAML number (YAML 1.1 reads 1.0e9 as text: write 1.0e+9)"
_RANGE = re.compile(r"^\s*([\[(])\s*([^,\s]*)\s*,\s*([^,\s]*)\s*([\])])\s*$")

_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxdict, _REPR.maxtuple, _REPR.maxset = 2, 3, 3, 3, 3
_REPR.maxstring, _REPR.maxother, _REPR.maxlong = 40, 40, 40


def plain_number(value):
    """A number of any kind Python or numpy has (``np.float32(0.6)``, ``np.int64(3)``, a 0-d
    array) as a Python int or float, so that checkers need know only those two; anything else,
    bools (``np.True_`` too) included, comes back unchanged for the checker to refuse."""
    if (
        getattr(value, "ndim", None) == 0
        and hasattr(value, "item")
        and not isinstance(value, (int, float))
    ):
        value = value.item()  # numpy scalars and 0-d arrays; np.bool_ gives a bool
    if type(value) in (bool, int, float):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    return value


def check_text(value, field: str, max_len: int, one_line: bool = True, describe=None) -> str:
    """Free text of at most ``max_len`` printable characters (``one_line=False``: line breaks
    and tabs too), or an InputError naming ``field``; ``describe(value)`` words a non-text
    value in the message (default: its type's name)."""
    if not isinstance(value, str):
        got = describe(value) if describe else type(value).__name__
        raise InputError(field, f"expected text, got {got}", "give text in quotes")
    if len(value) > max_len:
        raise InputError(field, f"{len(value)} characters exceed the limit {max_len}", "shorten it")
    bad = next((c for c in value if not c.isprintable() and (one_line or c not in "\n\t")), None)
    if bad is not None:
        raise InputError(
            field,
            f"contains the control character {bad!r}",
            "give printable text" + (" on one line" if one_line else ""),
        )
    return value


def show(value, limit: int = 40) -> str:
    """A short one-line repr of a user value for a message (bounded work: a YAML alias bomb
    of nested lists is not expanded)."""
    return one_line(_REPR.repr(value), limit)


def kind_name(value) -> str:
    """How a message names the kind of a user value: ``a list``, ``text``, ``nothing (null)``."""
    if value is None:
        return "nothing (null)"
    return {
        bool: "a boolean",
        int: "an integer",
        float: "a number",
        str: "text",
        list: "a list",
        dict: "a mapping",
    }.get(type(value), type(value).__name__)


def got(value) -> str:
    """``text 'abc'``: a value's kind and a short repr, for "expected ..., got ..."."""
    return kind_name(value) if value is None else f"{kind_name(value)} {show(value)}"


@dataclass(frozen=True)
class Derived:
    """A default computed from the fields checked before it: ``Derived("k_n x 1 m",
    lambda v: v["k_n"] * 1.0)``; ``text`` is how the docs show it."""

    text: str
    value: Callable[[dict], Any]


@lru_cache(maxsize=None)  # a field's range is read at every check of it
def parse_range(text: str) -> tuple:
    """``"(0, 1e16]"`` -> (0.0, 1e16, low_open, high_open); an empty bound is unbounded."""
    if not text:
        return (-math.inf, math.inf, False, False)
    m = _RANGE.match(text)
    if not m:
        raise ValueError(f"range {text!r} is not like '(0, inf)' or '[0, 1]'")
    lo = float(m.group(2)) if m.group(2) not in ("", "-inf") else -math.inf
    hi = float(m.group(3)) if m.group(3) not in ("", "inf") else math.inf
    return (lo, hi, m.group(1) == "(", m.group(4) == ")")


def range_words(text: str, units: str = "") -> str:
    """``"(0, 1e16]"`` -> ``"> 0 and <= 1e+16"``; "" when unbounded."""
    lo, hi, lo_open, hi_open = parse_range(text)
    parts = []
    if lo > -math.inf:
        parts.append(f"{'>' if lo_open else '>='} {lo:g}")
    if hi < math.inf:
        parts.append(f"{'<' if hi_open else '<='} {hi:g}")
    return " and ".join(parts) + (f" {units}" if parts and units not in ("", "1") else "")


@dataclass(frozen=True)
class Field:
    """One key a user may write.

    ``kind`` is one of :data:`KINDS`; ``range`` an interval such as ``"(0, 1e16]"`` (numbers
    and integers; for ``numbers``, each item); ``default`` a value, a :class:`Derived`, or
    :data:`REQUIRED`; ``hint`` is the fix a refusal gives, ``doc`` what the key is (the docs'
    meaning column; default the hint). ``auto``: ``auto`` or null stands for "choose for me"
    and checks to None. ``limit`` is the text length (``text``) or the item count (``list``,
    ``numbers`` takes exactly ``length`` items when set, and a list or a mapping at least
    ``min_items``); ``spec`` checks a ``mapping`` value, or each item of a ``list`` (a Spec for
    mappings, a Field for plain items). ``strict``: a number must be a number (no numeric
    text) and an integer an int (no whole float), for values a parser or script gives.
    """

    key: str
    kind: str = "number"
    units: str = ""
    range: str = ""
    default: Any = None
    hint: str = ""
    choices: tuple = ()
    auto: bool = False
    limit: int | None = None
    length: int | None = None
    spec: Spec | Field | None = None
    one_line: bool = True  # text: no line breaks
    min_items: int = 0
    strict: bool = False
    doc: str = ""  # what the key is, for the docs and the schema (default: the hint)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"field {self.key}: kind {self.kind!r} is not one of {KINDS}")
        parse_range(self.range)  # a typo in a declaration fails at import, not at a user

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def check(self, value, where: str = ""):
        """``value`` checked as this field (named ``where``, default the key)."""
        name = where or self.key
        if self.auto and (value is None or value == "auto"):
            return None
        check = _CHECKS[self.kind]
        return check(self, value, name)

    def default_for(self, values: dict):
        """The value of an absent key, given the values checked so far."""
        if isinstance(self.default, Derived):
            return self.default.value(values)
        if isinstance(self.default, (dict, list)):
            return type(self.default)(self.default)  # never share a mutable default
        return self.default

    # --- how the docs and the schema show it --------------------------------------------

    def shown_default(self) -> str:
        if self.required:
            return "required"
        if isinstance(self.default, Derived):
            return self.default.text
        if self.default is None:
            return "auto" if self.auto else "—"
        if isinstance(self.default, bool):
            return "true" if self.default else "false"
        if isinstance(self.default, float):
            return f"{self.default:g}"
        return str(self.default)

    def shown_kind(self) -> str:
        if self.kind == "choice":
            return " \\| ".join(str(c) for c in self.choices)
        if self.kind == "numbers":
            return f"[{self.length} numbers]" if self.length else "list of numbers"
        return {"flag": "true \\| false"}.get(self.kind, self.kind)


def _fail(f: Field, name: str, problem: str, fix: str = ""):
    raise InputError(name, problem, fix or f.hint)


def _number_value(f: Field, value, name: str, what: str = "a number"):
    value = plain_number(value)
    if isinstance(value, str) and NUMERIC_TEXT.fullmatch(value.strip()):
        if f.strict:
            _fail(f, name, f"expected {what}, got {got(value)}", YAML_NUMBER)
        value = float(value)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        units = f" in {f.units}" if f.units not in ("", "1") else ""
        _fail(f, name, f"expected {what}, got {got(value)}", f"give {what}{units}")
    if isinstance(value, int) and abs(value) > 1e300:
        _fail(f, name, f"{show(value)} is out of range", "give a number of sensible size")
    if isinstance(value, float) and not math.isfinite(value):
        _fail(f, name, f"{value} is not finite", "give a finite number")
    return value


def _in_range(f: Field, x, name: str):
    lo, hi, lo_open, hi_open = parse_range(f.range)
    if x < lo or x > hi or (lo_open and x == lo) or (hi_open and x == hi):
        units = f" {f.units}" if f.units not in ("", "1") else ""
        _fail(
            f,
            name,
            f"must be {range_words(f.range)}, got {_shown_number(x)}{units}",
            f.hint or f"give a value {range_words(f.range, f.units)}",
        )
    return x


def _shown_number(x) -> str:
    return show(x) if isinstance(x, int) else f"{x:g}"  # an int may be beyond float range


def _check_number(f: Field, value, name: str) -> float:
    return _in_range(f, float(_number_value(f, value, name)) + 0.0, name)  # -0.0 -> 0.0


def _check_integer(f: Field, value, name: str) -> int:
    x = plain_number(value)
    # a whole float (YAML 3.0) is a count; text ("3") and flags (true) are not
    if isinstance(x, float) and not f.strict and math.isfinite(x) and x == int(x):
        x = int(x)
    if isinstance(x, bool) or not isinstance(x, int):
        _fail(f, name, f"must be an integer, got {got(value)}", f.hint or "give a whole number")
    return _in_range(f, x, name)


def _check_flag(f: Field, value, name: str) -> bool:
    if not isinstance(value, (bool,)) and type(value).__name__ != "bool_":
        _fail(f, name, f"expected true or false, got {got(value)}", "write true or false")
    return bool(value)


def _check_text(f: Field, value, name: str) -> str:
    return check_text(value, name, f.limit or 1000, f.one_line, describe=got)


def _check_choice(f: Field, value, name: str) -> str:
    if not isinstance(value, (str, int)) or isinstance(value, bool) or value not in f.choices:
        fix = "use one of: " + ", ".join(str(c) for c in f.choices)
        _fail(f, name, f"unknown value {show(value)}", fix + (f" ({f.hint})" if f.hint else ""))
    return value


def _check_numbers(f: Field, value, name: str) -> list:
    value = plain_list(value)
    if not isinstance(value, list) or (f.length is not None and len(value) != f.length):
        shape = f"a list of {f.length} numbers" if f.length else "a list of numbers"
        _fail(f, name, f"expected {shape}, got {got(value)}")
    _count_items(f, value, name)
    return [_check_number(f, v, f"{name}[{i}]") for i, v in enumerate(value)]


def _count_items(f: Field, value, name: str) -> None:
    if f.limit is not None and len(value) > f.limit:
        _fail(f, name, f"{len(value)} items exceed the limit {f.limit}", f"give at most {f.limit}")
    if len(value) < f.min_items:
        few = "none given" if not value else f"{len(value)} given"
        _fail(f, name, f"{few}, at least {f.min_items} needed")


def _check_mapping(f: Field, value, name: str):
    if f.spec is not None:
        return f.spec.check(value, name)
    if not isinstance(value, Mapping):
        _fail(
            f,
            name,
            f"expected a mapping, got {got(value)}",
            f.hint or "write it as {key: value, ...}",
        )
    _count_items(f, value, name)
    return dict(value)


def _check_list(f: Field, value, name: str) -> list:
    value = plain_list(value)
    if not isinstance(value, list):
        _fail(f, name, f"expected a list, got {got(value)}", f.hint or "write it as [item, ...]")
    _count_items(f, value, name)
    if f.spec is None:
        return list(value)
    return [f.spec.check(item, f"{name}[{i}]") for i, item in enumerate(value)]


def _check_any(f: Field, value, name: str):
    return value


_CHECKS = {
    "number": _check_number,
    "integer": _check_integer,
    "flag": _check_flag,
    "text": _check_text,
    "choice": _check_choice,
    "numbers": _check_numbers,
    "mapping": _check_mapping,
    "list": _check_list,
    "any": _check_any,
}


def plain_list(value):
    """A tuple or a 1-d numpy array as a list (a script's values), anything else unchanged."""
    if isinstance(value, tuple) or (getattr(value, "ndim", None) == 1 and hasattr(value, "tolist")):
        return list(value)
    return value


# --- rules across fields ------------------------------------------------------------------


@dataclass(frozen=True)
class Rule:
    """A named rule across the keys of one mapping; ``test(given keys)`` is True when kept."""

    name: str
    keys: tuple
    problem: str
    fix: str

    def check(self, mapping: Mapping, where: str) -> None:
        given = [k for k in self.keys if k in mapping]
        if not _RULE_TESTS[self.name](len(given)):
            raise InputError(where or ", ".join(self.keys), self.problem, self.fix)

    def words(self) -> str:
        return self.problem


_RULE_TESTS = {
    "exactly_one": lambda n: n == 1,
    "not_both": lambda n: n <= 1,
    "at_least_one": lambda n: n >= 1,
}


def _keys_text(keys) -> str:
    return " or ".join(f"{k}:" for k in keys)


def exactly_one(*keys: str, fix: str = "") -> Rule:
    return Rule("exactly_one", keys, f"give exactly one of {_keys_text(keys)}", fix)


def not_both(a: str, b: str, fix: str = "remove one") -> Rule:
    return Rule("not_both", (a, b), f"give {a} or {b}, not both", fix)


def at_least_one(*keys: str, fix: str = "") -> Rule:
    return Rule("at_least_one", keys, f"give at least one of {_keys_text(keys)}", fix)


# --- a whole mapping ----------------------------------------------------------------------


@dataclass(frozen=True)
class Spec:
    """The keys of one input mapping, in the order the docs list them, and its rules."""

    fields: tuple
    rules: tuple = ()
    doc: str = ""
    by_key: dict = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        keys = [f.key for f in self.fields]
        if len(set(keys)) != len(keys):
            raise ValueError(f"a spec lists a key twice: {keys}")
        object.__setattr__(self, "by_key", {f.key: f for f in self.fields})

    @property
    def keys(self) -> tuple:
        return tuple(self.by_key)

    def __getitem__(self, key: str) -> Field:
        return self.by_key[key]

    def __contains__(self, key) -> bool:
        return key in self.by_key

    def check_keys(self, mapping, where: str = "") -> Mapping:
        """``mapping`` is a mapping of known keys only, or an InputError."""
        allowed = f"allowed keys: {', '.join(self.keys)}"
        if not isinstance(mapping, Mapping):
            raise InputError(where or "input", f"expected a mapping, got {got(mapping)}", allowed)
        for key in mapping:
            if key not in self.by_key:
                shown = one_line(key if isinstance(key, str) else repr(key), 60)
                raise InputError(f"{where}.{shown}" if where else shown, "unknown key", allowed)
        return mapping

    def check(self, mapping, where: str = "") -> dict:
        """The checked values of every field, absent ones defaulted (None for a null or an
        absent optional key), or the first refusal as an InputError."""
        mapping = {} if mapping is None else mapping
        self.check_keys(mapping, where)
        for rule in self.rules:
            rule.check(mapping, where)
        values: dict = {}
        for f in self.fields:
            name = f"{where}.{f.key}" if where else f.key
            if f.key not in mapping or (mapping[f.key] is None and not f.auto):
                if f.required:
                    raise InputError(name, "missing", f.hint or "add this field")
                if f.kind == "mapping" and f.spec is not None and f.default == {}:
                    # an absent section is an empty one: its own defaults and required keys
                    values[f.key] = f.spec.check({}, name)
                    continue
                values[f.key] = f.default_for(values)
            else:
                values[f.key] = f.check(mapping[f.key], name)
        return values

    def defaults(self) -> dict:
        """Every field's default (REQUIRED ones left out)."""
        out: dict = {}
        for f in self.fields:
            if not f.required:
                out[f.key] = f.default_for(out)
        return out

    def replace(self, *fields: Field, rules: Sequence | None = None) -> Spec:
        """This spec with some fields replaced (same key) or added at the end."""
        new = {f.key: f for f in self.fields}
        new.update({f.key: f for f in fields})
        return Spec(tuple(new.values()), tuple(self.rules if rules is None else rules), self.doc)


def check(spec: Spec, mapping, where: str = "") -> dict:
    """``spec.check(mapping, where)``: the checked values, or one InputError line."""
    return spec.check(mapping, where)


# --- generated copies: the config schema and the docs' key tables -----------------------


def json_schema(f: Field | Spec) -> dict:
    """The JSON schema (draft 7) of a field or of a whole spec, for a YAML schema file."""
    if isinstance(f, Spec):
        out = {
            "type": "object",
            "additionalProperties": False,
            "properties": {g.key: json_schema(g) for g in f.fields},
        }
        required = [g.key for g in f.fields if g.required]
        if required:
            out["required"] = required
        return out
    out: dict = {}
    if f.kind in ("number", "integer"):
        out["type"] = f.kind
        lo, hi, lo_open, hi_open = parse_range(f.range)
        if lo > -math.inf:
            out["exclusiveMinimum" if lo_open else "minimum"] = _plain(lo)
        if hi < math.inf:
            out["exclusiveMaximum" if hi_open else "maximum"] = _plain(hi)
    elif f.kind == "flag":
        out["type"] = "boolean"
    elif f.kind == "text":
        out["type"] = "string"
    elif f.kind == "choice":
        out["enum"] = list(f.choices)
    elif f.kind == "numbers":
        out = {"type": "array", "items": json_schema(Field(f.key, "number", range=f.range))}
        if f.length is not None:
            out["minItems"] = out["maxItems"] = f.length
    elif f.kind == "mapping":
        out = json_schema(f.spec) if f.spec is not None else {"type": "object"}
    elif f.kind == "list":
        out = {"type": "array"}
        if f.spec is not None:
            out["items"] = json_schema(f.spec)
    if f.auto:
        out = {"anyOf": [out, {"const": "auto"}, {"type": "null"}]}
    if f.doc or f.hint or f.units:
        units = f"[{f.units}]" if f.units not in ("", "1") else ""
        out["description"] = f"{f.doc or f.hint} {units}".strip()
    return out


def _plain(x: float):
    return int(x) if x == int(x) and abs(x) < 2**53 else x


def key_table(spec: Spec, prefix: str = "") -> list[str]:
    """A Markdown table of a spec's keys: key, kind, units, range, default, meaning; nested
    mappings' keys follow as ``parent.key``."""
    rows = ["| key | kind | units | range | default | meaning |", "|---|---|---|---|---|---|"]
    rows += _rows(spec, prefix)
    return rows


def _rows(spec: Spec, prefix: str) -> list[str]:
    out = []
    for f in spec.fields:
        key = f"{prefix}{f.key}"
        meaning = (f.doc or f.hint).replace("|", "\\|")
        units = f.units if f.units not in ("", "1") else ""
        out.append(
            f"| `{key}` | {f.shown_kind()} | {units} | {range_words(f.range)} "
            f"| {f.shown_default()} | {meaning} |"
        )
        if isinstance(f.spec, Spec):
            out += _rows(f.spec, f"{key}{'[]' if f.kind == 'list' else ''}.")
    for rule in spec.rules:
        where = f"`{prefix.rstrip('.')}`" if prefix else "(top)"
        out.append(f"| {where} | rule | | | | {rule.words()} |")
    return out
