"""Hypothesis strategies for hostile wall cases: single and multiple mutations of the manuscript
case files (wrong types, numeric strings, negative / zero / NaN / inf / huge values, missing and
unknown keys, container swaps), each with what the validator must do with it.

An example is ``(spec, expect)``: ``expect`` is ``("refuse", field)`` when the case must be
refused with an InputError naming exactly ``field``, or ``("any", None)`` when refusing (with
any field) and accepting are both fine (then the parsed case must be sane).
"""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import yaml
from hypothesis import strategies as st

CASES = Path(__file__).resolve().parents[2] / "config" / "walls"
BASE_NAMES = (
    "orduna_case1",
    "chee_liang_10_11",
    "s32",
    "s23",
)  # dry, mortar + pressure, point loads, openings
BASES = {name: yaml.safe_load((CASES / f"{name}.yaml").read_text()) for name in BASE_NAMES}

NUM, INT, BOOL, CHOICE, MAP, LIST, PAIR, TEXT, PROSE, SWITCH, LABEL, NUMS = (
    "number",
    "integer",
    "bool",
    "choice",
    "mapping",
    "list",
    "pair",
    "text",
    "prose",
    "switch",
    "label",
    "numbers",
)

JOINT = {"mu": NUM, "k_n": NUM, "k_t": NUM, "tensile_strength": NUM, "cohesion": NUM, "alpha": NUM}
SOLVER_INT = (
    "max_iterations",
    "dead_load_iterations",
    "max_steps",
    "easy_iterations",
    "max_failures",
    "plateau_steps",
    "secant_refresh",
    "control_block",
)
SOLVER_SWITCH = ("work_control", "consistent", "extrapolate", "secant")
SOLVER_NUM = (
    "tolerance",
    "max_displacement",
    "first_step",
    "growth",
    "accept_tolerance",
    "residual_stiffness",
    "reuse_ratio",
    "drop_ratio",
    "plateau_tolerance",
    "max_seconds",
    "load_step",
    "min_load_step",
    "singular_ratio",
)

# the kind of every field ([*]: any list item); an independent statement of the schema
SCHEMA = {
    "name": TEXT,
    "description": PROSE,  # a description may run over several lines
    "panel": MAP,
    "panel.block": MAP,
    "panel.block.a": NUM,
    "panel.block.b": NUM,
    "panel.block.s": NUM,
    "panel.blocks_per_course": NUM,
    "panel.courses": INT,
    "panel.unit_weight": NUM,
    "panel.joint_thickness": NUM,
    "panel.first_course_offset": BOOL,
    "panel.lintel_strength": NUM,
    "panel.openings": LIST,
    "panel.openings[*]": MAP,
    "panel.openings[*].x": PAIR,
    "panel.openings[*].y": PAIR,
    "joints": MAP,
    "joints.kind": CHOICE,
    **{f"joints.{k}": v for k, v in JOINT.items()},
    "restraints": LIST,
    "restraints[*]": MAP,
    "restraints[*].edge": CHOICE,
    "restraints[*].fix": CHOICE,
    "restraints[*].support": CHOICE,
    "restraints[*].joint": MAP,
    "restraints[*].dead_load": BOOL,
    "restraints[*].at": CHOICE,
    "restraints[*].hold": CHOICE,
    "restraints[*].offset": NUM,
    "joints.torsion_under_bending": CHOICE,
    "joints.bending_release": CHOICE,
    **{f"restraints[*].joint.{k}": v for k, v in JOINT.items()},
    "load": MAP,
    "load.kind": CHOICE,
    "load.direction": CHOICE,
    "load.extra_vertical": LIST,
    "load.extra_vertical[*]": MAP,
    "load.extra_vertical[*].count": INT,
    "load.extra_vertical[*].force": NUM,
    "load.extra_vertical[*].edge": CHOICE,
    "load.extra_in_live_load": BOOL,
    "solver": MAP,
    **{f"solver.{k}": INT for k in SOLVER_INT},
    **{f"solver.{k}": SWITCH for k in SOLVER_SWITCH},
    **{f"solver.{k}": NUM for k in SOLVER_NUM},
    "reference": MAP,
    "reference.table": INT,
    "reference.case": LABEL,
    "reference.n": INT,
    **{
        f"reference.{k}": NUM
        for k in (
            "L",
            "H",
            "p_dem",
            "lambda_dem",
            "lambda_fem",
            "lambda_limit_analysis",
            "lambda_analytic",
        )
    },
    "reference.p_experiment": NUMS,
    "reference.lambda_experiment": NUMS,
}
REQUIRED = {
    "panel",
    "joints",
    "restraints",
    "load",
    "panel.block",
    "panel.blocks_per_course",
    "panel.courses",
    "panel.unit_weight",
    "panel.block.a",
    "panel.block.b",
    "panel.block.s",
    "joints.kind",
    "joints.mu",
    "joints.k_n",
    "joints.k_t",
    "restraints[*].edge",
    "restraints[*].fix",
    "load.kind",
    "load.extra_vertical[*].count",
    "load.extra_vertical[*].force",
    "panel.openings[*].x",
    "panel.openings[*].y",
}
# optional containers: null stands for empty
NULLABLE = {"panel.openings", "load.extra_vertical", "solver", "restraints[*].joint", "reference"}

# values every field of the kind must refuse (the field's minimum is >= 0 for every number)
_NOT_NUMBERS = [
    "abc",
    "false",
    "1.0e9x",
    "",
    " 1",
    "nan",
    "inf",
    True,
    False,
    None,
    [1.0],
    {"v": 1},
    float("nan"),
    float("inf"),
    float("-inf"),
    -1.0,
    -1e-300,
    1e300,
    10**400,
]
BAD = {
    NUM: _NOT_NUMBERS,
    INT: _NOT_NUMBERS + [0.5, 2.5, "3.5", -1, 10**30],
    NUMS: ["abc", True, None, {"v": 1}, [], [float("nan")], ["x"], [-1.0], [True]],
    SWITCH: [0.5, 2, -1, "abc", None, float("nan"), [1], "true"],
    BOOL: ["false", "true", "no", "", 0, 1, 1.0, 0.0, None, [], {}, "yes"],
    CHOICE: [1, 0.5, True, None, [], {}, "zzz", "", "BASE", ["base"]],
    MAP: [1, 2.5, "x", True, [], [{}]],
    LIST: [1, 2.5, "x", True, {}, {"x": [0, 1]}],
    PAIR: [
        1,
        "x",
        None,
        [1.0],
        [0.1, 0.2, 0.3],
        ["a", 0.2],
        [0.3, 0.1],
        [0.1, float("nan")],
        {},
        [True, 0.2],
        [-0.1, 0.2],
    ],
    TEXT: [1, 2.5, True, [], {}, ["a"], "line\nbreak", "x" * 100_000, "bell\a"],
    PROSE: [1, 2.5, True, [], {}, ["a"], "x" * 100_000, "bell\a", None],
    LABEL: [2.5, True, None, [], {}, float("nan"), "line\nbreak"],
}
ANY_LEAF = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**6), 10**6),
    st.integers(),
    st.floats(),
    st.floats(-1e3, 1e3),
    st.floats(1e-9, 1.0),
    st.sampled_from(
        [
            0,
            0.0,
            -0.0,
            1,
            2,
            0.5,
            1e9,
            1e12,
            1e15,
            1e-12,
            "0.5",
            "1.0e9",
            "2.4e9",
            "1e4",
            "abc",
            "",
            "true",
            "base",
            "all",
            "mortar",
            "dry",
            "pressure",
        ]
    ),
    st.text(max_size=8),
)
ANY_VALUE = st.recursive(
    ANY_LEAF,
    lambda inner: st.one_of(
        st.lists(inner, max_size=3),
        st.dictionaries(st.sampled_from(["a", "x", "y", "kind", "edge", "mu"]), inner, max_size=3),
    ),
    max_leaves=6,
)
KEY = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1, max_size=12)


def schema_kind(path: str):
    return SCHEMA.get(re.sub(r"\[\d+\]", "[*]", path))


def _walk(node, prefix=""):
    """Every (path, value) of a spec, containers included."""
    if isinstance(node, dict):
        for key, value in node.items():
            path = f"{prefix}.{key}" if prefix else str(key)
            yield path, value
            yield from _walk(value, path)
    elif isinstance(node, list):
        for k, value in enumerate(node):
            path = f"{prefix}[{k}]"
            yield path, value
            yield from _walk(value, path)


def _steps(path):
    out = []
    for part in path.split("."):
        m = re.fullmatch(r"([^\[]+)((?:\[\d+\])*)", part)
        out.append(m.group(1))
        out.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    return out


def _set(spec, path, value):
    *head, last = _steps(path)
    node = spec
    for step in head:
        if isinstance(step, str) and step not in node:
            node[step] = {}
        node = node[step]
    node[last] = value


def _delete(spec, path):
    *head, last = _steps(path)
    node = spec
    for step in head:
        node = node[step]
    del node[last]


def addressable(spec):
    """Paths of the spec that are in the schema, plus known optional fields that can be added."""
    paths = [p for p, _ in _walk(spec) if schema_kind(p)] + ["name", "description"]
    for field in SCHEMA:
        if "[*]" not in field and field.count(".") >= 1 and field not in paths:
            parent = field.rsplit(".", 1)[0]
            if parent in paths or parent in ("solver", "reference"):
                paths.append(field)
    restraints = spec.get("restraints")
    for k, r in enumerate(restraints if isinstance(restraints, list) else []):
        if isinstance(r, dict):
            for key in ("support", "dead_load"):
                if key not in r:
                    paths.append(f"restraints[{k}].{key}")
    return sorted(set(paths))


def _mapping_paths(spec):
    return (
        [""]
        + [p for p, v in _walk(spec) if isinstance(v, dict) and schema_kind(p) == MAP]
        + ["solver"]
    )


@st.composite
def bad_value_case(draw):
    """One field gets a value its kind must refuse: the error names that field."""
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    path = draw(st.sampled_from(addressable(spec)))
    kind = schema_kind(path)
    value = draw(st.sampled_from(BAD[kind]))
    if value is None and (re.sub(r"\[\d+\]", "[*]", path) in NULLABLE):
        value = 7
    _set(spec, path, copy.deepcopy(value))
    return spec, ("refuse", path)


@st.composite
def unknown_key_case(draw):
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    where = draw(st.sampled_from(_mapping_paths(spec)))
    key = draw(KEY.filter(lambda k: schema_kind(f"{where}.{k}" if where else k) is None))
    _set(spec, f"{where}.{key}" if where else key, draw(ANY_LEAF))
    return spec, ("refuse", f"{where}.{key}" if where else key)


@st.composite
def missing_key_case(draw):
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    paths = [p for p, _ in _walk(spec) if schema_kind(p)]
    path = draw(st.sampled_from(paths))
    _delete(spec, path)
    pattern = re.sub(r"\[\d+\]", "[*]", path)
    required = pattern in REQUIRED or (
        path == "joints.tensile_strength" and spec["joints"]["kind"] == "mortar"
    )
    return spec, (("refuse", path) if required else ("any", None))


@st.composite
def any_value_case(draw):
    """One to three fields get arbitrary values (anything YAML can hold): refuse or parse sanely."""
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    for _ in range(draw(st.integers(1, 3))):
        paths = addressable(spec)
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        try:
            _set(spec, path, draw(ANY_VALUE))
        except (TypeError, KeyError, IndexError, AttributeError):
            pass  # an earlier mutation replaced a container on the way
    return spec, ("any", None)


@st.composite
def extreme_number_case(draw):
    """A number field gets an extreme or borderline value: refuse or parse sanely."""
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    paths = [p for p in addressable(spec) if schema_kind(p) in (NUM, INT, SWITCH)]
    path = draw(st.sampled_from(paths))
    value = draw(
        st.one_of(
            st.sampled_from(
                [
                    0,
                    0.0,
                    -0.0,
                    1,
                    1e-320,
                    5e-324,
                    1e-12,
                    1e6,
                    1e9,
                    1e15,
                    1e18,
                    2**31,
                    2**63,
                    10**5,
                    100_000,
                    1.5,
                    0.999999,
                    1.000001,
                    "1e4",
                    "1.0e+3",
                    "-0",
                ]
            ),
            st.floats(allow_nan=True, allow_infinity=True),
            st.integers(),
        )
    )
    _set(spec, path, value)
    return spec, ("any", None)


@st.composite
def size_case(draw):
    """Wall dimensions from tiny to absurd (100 000 courses): refuse above the limits or parse."""
    spec = copy.deepcopy(BASES[draw(st.sampled_from(BASE_NAMES))])
    spec["panel"]["courses"] = draw(
        st.one_of(st.integers(1, 200), st.integers(1, 10**7), st.sampled_from([100_000, 10**12]))
    )
    spec["panel"]["blocks_per_course"] = draw(
        st.one_of(
            st.integers(1, 100),
            st.integers(1, 10**6),
            st.sampled_from([0.5, 1.5, 2.5, 1e9, 10**20]),
        )
    )
    if draw(st.booleans()):
        spec.setdefault("solver", {})["max_steps"] = draw(
            st.sampled_from([1, 10, 1000, 10**5, 10**6])
        )
    return spec, ("any", None)


HOSTILE_CASES = st.one_of(
    bad_value_case(),
    unknown_key_case(),
    missing_key_case(),
    any_value_case(),
    extreme_number_case(),
    size_case(),
)


def is_finite_tree(value) -> bool:
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, dict):
        return all(is_finite_tree(v) for v in value.values())
    if isinstance(value, (list, tuple)):
        return all(is_finite_tree(v) for v in value)
    return True
