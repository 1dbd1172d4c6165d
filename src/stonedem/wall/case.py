"""Wall case files (YAML): reading, strict validation, problem-size limits, and the model they
describe.

```yaml
panel: {block: {a: 0.081, b: 0.210, s: 0.070}, blocks_per_course: 3, courses: 13, unit_weight:
20000.0} joints: {kind: dry, mu: 0.7, k_n: 2.4e9, k_t: 1.0e9}   # mortar: add tensile_strength,
cohesion restraints: [{edge: base, fix: all}, {edge: left, fix: translations, at: edge}]
load: {kind: proportional, direction: out_of_plane}      # or {kind: pressure}
```

Three stages, each refusing bad input with an InputError naming the dotted field and the fix
(exit status 2):

- :func:`read_case`: the file (exists, a regular file, at most ``MAX_CASE_BYTES``, UTF-8, YAML
  without duplicate keys, a mapping);
- :func:`check_case`: every field type-checked strictly (a bool is a YAML bool, an integer an
  integer, a number finite and inside its range ``RANGES``; unknown keys refused with the
  known ones) and the problem size estimated (:func:`estimate_size`) and held to
  ``MAX_BLOCKS`` and ``MAX_MEMORY_BYTES`` -- nothing is built yet;
- :func:`build_case`: the panel, loads, restraints and the :class:`WallModel`.

Supports follow the geometry, and every block needs a load path to one
(:func:`check_load_paths`). A support joint or pin on an edge acts only on the blocks that touch
that edge of the panel (``base``: the blocks of the first course that are left; likewise top,
left, right), a restraint line only on the blocks it crosses; an opening that reaches an edge
leaves no support there, and the next block inward is not supported in its place. Blocks are
joined by the joints between the blocks that are left; a block, or a group of blocks, joined to
no support (an opening removing the first course: the wall hovers above its base; an opening over
all but the top course) is refused before anything is computed with an InputError naming the
opening that cuts it off (``panel.openings[k]``). The check is topological: a path to a support
that cannot carry the self-weight (a line holding only out of plane) is refused by the dead load.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import re
import reprlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stonedem.errors import InputError, check_text, plain_number
from stonedem.io.yaml_file import printable as _printable
from stonedem.io.yaml_file import read_yaml_mapping
from stonedem.wall.panel import EDGES, KIND_HEAD, KIND_SUPPORT, SUPPORT, build_panel
from stonedem.wall.settings import SolverSettings

if TYPE_CHECKING:
    from stonedem.wall.pushover import WallModel

# --- limits -------------------------------------------------------------------------------
# A case file is a few hundred bytes; anything above 1 MiB is not a case file.
MAX_CASE_BYTES = 1 << 20
# Blocks of the panel (estimated from the dimensions before building). The manuscript cases
# have 45-294 blocks. The sparse LU of a 5000-block panel (30 000 DOFs) takes ~0.8 s and
# ~90 MB on a 2-core machine; it is one uninterruptible compiled call, so this keeps Ctrl-C
# effective within about a second, and a pushover (hundreds of factorizations) within hours.
MAX_BLOCKS = 5000
# Estimated peak memory of a run: LU factors, the stored path (block displacements and
# interface states of every step up to solver.max_steps) and the dataset written from it.
MAX_MEMORY_BYTES = 2 << 30
MAX_OPENINGS = 100  # openings are tested against every block in Python
MAX_POINT_LOADS = 10_000  # load.extra_vertical[*].count: one Python pass over the top course each
MAX_TEXT = 2000  # characters of name / description / reference labels

TOP_KEYS = {"name", "description", "panel", "joints", "restraints", "load", "solver", "reference"}
PANEL_KEYS = {
    "block",
    "blocks_per_course",
    "courses",
    "unit_weight",
    "joint_thickness",
    "first_course_offset",
    "openings",
    "lintel_strength",
}
BLOCK_KEYS = {"a", "b", "s"}
JOINT_KEYS = {"kind", "mu", "k_n", "k_t", "tensile_strength", "cohesion", "alpha"}
# interface-law switches (the whole panel; not per support joint): manuscript Fig. 10 and Eq. 13
LAW_KEYS = {"torsion_under_bending": ("all", "no_tension"), "bending_release": ("own", "both")}
RESTRAINT_KEYS = {"edge", "fix", "support", "joint", "dead_load", "at", "offset", "hold"}
# where a block restraint acts: pins at the edge blocks' centres, or a straight line along the
# panel edge (at its mid-thickness), or parallel to it ``offset`` metres inside
RESTRAINT_AT = ("centre", "edge", "offset")
# what a restraint line holds: the displacement of its points out of plane, or all of it
LINE_COMPONENTS = {"out_of_plane": (2,), "translations": (0, 1, 2)}
LOAD_KEYS = {"kind", "direction", "extra_vertical", "extra_in_live_load"}
EXTRA_KEYS = {"count", "force", "edge"}
OPENING_KEYS = {"x", "y"}
SOLVER_KEYS = set(SolverSettings().as_dict()) | {"control_block"}
# manuscript reference values (free of effect on the run; the dataset carries them)
REFERENCE_NUMBERS = {
    "L",
    "H",
    "p_dem",
    "lambda_dem",
    "lambda_fem",
    "lambda_limit_analysis",
    "lambda_analytic",
}
REFERENCE_LISTS = {"p_experiment", "lambda_experiment"}  # a number or a list of numbers
REFERENCE_KEYS = REFERENCE_NUMBERS | REFERENCE_LISTS | {"table", "case", "n"}
FIX_DOFS = {
    "all": (0, 1, 2, 3, 4, 5),
    "translations": (0, 1, 2),
    "out_of_plane": (2,),
    "rotations": (3, 4, 5),
}
DIRECTIONS = {"out_of_plane": 2, "in_plane": 0}

# allowed ranges [lo, hi] (SI units); ``lo_open``: lo itself excluded. Wide enough for any
# masonry wall, narrow enough that the arithmetic stays finite and the run meaningful.
RANGES = {
    "length": (1e-3, 100.0, False),  # block sides a, b, s [m]
    "unit_weight": (1.0, 1e6, False),  # [N/m3] (brick ~18e3, steel 77e3)
    "coordinate": (0.0, 1e4, False),  # opening corners [m]
    "mu": (0.0, 10.0, True),
    "stiffness": (1e3, 1e16, False),  # k_n, k_t [N/m3]
    "alpha": (1.0, 10.0, False),  # Eq. 14 exponent (Table A1: 1.5-2.6); >= 1 keeps it convex
    "stress": (0.0, 1e10, False),  # tensile strength, cohesion, lintel strength [Pa]
    "force": (0.0, 1e10, False),  # point loads [N]
    "reference": (0.0, 1e12, True),
}
# solver settings: (kind, lo, hi, lo_open); "int" counts, "switch" 0/1 (or false/true)
SOLVER_RULES = {
    "tolerance": ("number", 1e-12, 0.1, False),  # finer: rounding (~1e-15) blamed the restraints
    "max_iterations": ("int", 2, 10_000),  # a Newton step converges at iteration 2 at the earliest
    "dead_load_iterations": ("int", 2, 100_000),
    "max_steps": ("int", 1, 1_000_000),
    "max_displacement": ("number", 0.0, 1e3, False),  # 0: the wall thickness s
    "first_step": ("number", 0.0, 1e3, False),  # 0: automatic
    "growth": ("number", 1.0, 10.0, False),
    "easy_iterations": ("int", 0, 10_000),
    "max_failures": ("int", 1, 1000),
    "accept_tolerance": ("number", 0.0, 1.0, True),
    "work_control": ("switch",),
    "consistent": ("switch",),
    "residual_stiffness": ("number", 0.0, 1.0, True),  # 0 would leave yielded DOFs singular
    "extrapolate": ("switch",),
    "reuse_ratio": ("number", 0.0, 1.0, False),
    "drop_ratio": ("number", 0.0, 1.0, False),
    "plateau_steps": ("int", 1, 1_000_000),
    "plateau_tolerance": ("number", 0.0, 1.0, False),
    "max_seconds": ("number", 0.0, 1e7, False),  # 0: no budget
    "secant": ("switch",),
    "load_step": ("number", 0.0, 1e12, False),  # 0: automatic
    "min_load_step": ("number", 0.0, 1.0, True),
    "singular_ratio": ("number", 1.0, 1e15, True),
    "secant_refresh": ("int", 0, 10_000),
    "control_block": ("int", 0, MAX_BLOCKS),
}
assert set(SOLVER_RULES) == SOLVER_KEYS, "every solver setting has a rule"
# [m] a set first_step: 0 (automatic) or at least this (1e-12 ran as 1e-5 did)
MIN_FIRST_STEP = 1e-12

# a number written as text: YAML 1.1 reads 1.0e9 (no exponent sign) as a string
_NUMERIC = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


# --- value checks -------------------------------------------------------------------------

_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxdict, _REPR.maxtuple, _REPR.maxset = 2, 3, 3, 3, 3
_REPR.maxstring, _REPR.maxother, _REPR.maxlong = 40, 40, 40


def _show(value, limit=40) -> str:
    """A short one-line repr of a user value for a message (bounded work: a YAML alias bomb
    of nested lists is not expanded)."""
    text = _printable(_REPR.repr(value))
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _kind_name(value) -> str:
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


def _mapping(value, field, allow_none=False):
    if value is None and allow_none:
        return {}
    if not isinstance(value, dict):
        raise InputError(
            field,
            f"expected a mapping, got {_kind_name(value)} {_show(value)}",
            "write it as {key: value, ...}",
        )
    return value


def _list(value, field, allow_none=False, max_items=None):
    if value is None and allow_none:
        return []
    if not isinstance(value, list):
        raise InputError(
            field,
            f"expected a list, got {_kind_name(value)} {_show(value)}",
            "write it as [item, ...] or as '- item' lines",
        )
    if max_items is not None and len(value) > max_items:
        raise InputError(
            field, f"{len(value)} items exceed the limit {max_items}", f"give at most {max_items}"
        )
    return value


def _keys(spec, allowed, field, required=()):
    _mapping(spec, field)
    for key in spec:
        if key not in allowed:
            key = _printable(key if isinstance(key, str) else repr(key))[:60]
            name = f"{field}.{key}" if field else key
            raise InputError(name, "unknown key", f"use one of: {', '.join(sorted(allowed))}")
    for key in required:
        if key not in spec:
            raise InputError(f"{field}.{key}" if field else key, "missing", "add this field")


def _choice(value, options, field):
    if not isinstance(value, str) or value not in options:
        raise InputError(
            field, f"unknown value {_show(value)}", f"use one of: {', '.join(options)}"
        )
    return value


def _bool(value, field):
    """A real YAML boolean (true/false); the string "false" or the number 0 is refused."""
    if not isinstance(value, bool):
        raise InputError(
            field,
            f"expected true or false, got {_kind_name(value)} {_show(value)}",
            "write true or false without quotes",
        )
    return value


def _as_number(value, field, what="a number"):
    value = plain_number(value)
    if isinstance(value, str) and _NUMERIC.fullmatch(value):
        value = float(value)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(
            field,
            f"expected {what}, got {_kind_name(value)} {_show(value)}",
            f"give {what} (SI units)",
        )
    if isinstance(value, int):
        if abs(value) > 1e300:
            raise InputError(
                field, f"{_show(value)} is out of range", "give a number of sensible size"
            )
        return value
    if not math.isfinite(value):
        raise InputError(field, f"{value} is not finite", "give a finite number")
    return value


def _range_text(lo, hi, lo_open):
    return f"{'>' if lo_open else '>='} {lo:g} and <= {hi:g}"


def _number(value, field, lo, hi, lo_open=False, units=""):
    """A finite float in [lo, hi] (``lo_open``: lo excluded)."""
    x = float(_as_number(value, field)) + 0.0  # -0.0 -> 0.0
    if x < lo or x > hi or (lo_open and x == lo):
        raise InputError(
            field,
            f"{x:g}{units} is out of range",
            f"give a value {_range_text(lo, hi, lo_open)}{units}",
        )
    return x


def _ranged(value, field, rule, units=""):
    lo, hi, lo_open = RANGES[rule]
    return _number(value, field, lo, hi, lo_open, units)


def _integer(value, field, lo, hi):
    """An integer in [lo, hi]; a float or numeric text must have an exact integral value."""
    x = _as_number(value, field, "an integer")
    if isinstance(x, float):
        if x != int(x):
            raise InputError(field, f"{x:g} is not a whole number", "give an integer")
        x = int(x)
    if x < lo or x > hi:
        raise InputError(field, f"{x} is out of range", f"give an integer >= {lo} and <= {hi}")
    return x


def _switch(value, field):
    """A 0/1 solver switch (or false/true)."""
    if isinstance(value, bool):
        return float(value)
    x = _as_number(value, field, "0 or 1")
    if x not in (0, 1):
        raise InputError(field, f"{_show(value)} is not 0 or 1", "give 0 (off) or 1 (on)")
    return float(x)


def _text(value, field, max_len=MAX_TEXT, one_line=True):
    return check_text(
        value, field, max_len, one_line, describe=lambda v: f"{_kind_name(v)} {_show(v)}"
    )


# --- reading ------------------------------------------------------------------------------


def read_case(path) -> dict:
    """The case mapping of a YAML file; an InputError naming the file when it cannot be one
    (:func:`stonedem.io.yaml_file.read_yaml_mapping`: kind, size, encoding, nesting, keys twice)."""
    return read_yaml_mapping(
        path,
        "a wall case file",
        MAX_CASE_BYTES,
        "give panel, joints, restraints and load as 'key: value' lines (see config/walls/)",
    )


# --- problem size -------------------------------------------------------------------------

# sparse LU fill of the panel stiffness, fitted on running-bond panels of 178-20 100 blocks
# (scipy splu, COLAMD): nonzeros ~ 100 nb^(4/3); seconds ~ 0.46 (nb / 3240)^1.26 on a
# 2-core machine
LU_FILL, LU_EXPONENT = 100.0, 4.0 / 3.0
LU_SECONDS, LU_SECONDS_BLOCKS, LU_SECONDS_EXPONENT = 0.46, 3240.0, 1.26
# compatibility matrix, sections, 6 x 6 return-map derivatives and their sparse assembly
MODEL_BYTES_PER_INTERFACE = 2400.0


@dataclass
class ProblemSize:
    """Estimated size of a case before anything is built (an upper bound when openings remove
    blocks)."""

    n_blocks: float
    n_interfaces: float
    n_dofs: float
    stiffness_nonzeros: float
    lu_bytes: float
    path_bytes: float  # the stored path: max_steps + 1 steps
    memory_bytes: float  # peak estimate: LU + path (twice: records and arrays) + dataset
    factor_seconds: float  # one sparse LU of the panel stiffness

    def describe(self, blocks: bool = True) -> str:
        text = (
            f"{self.n_interfaces:.3g} interfaces, {self.n_dofs:.3g} DOFs, "
            f"~{_bytes(self.memory_bytes)}, "
            f"~{self.factor_seconds:.2g} s per stiffness factorization"
        )
        return f"{self.n_blocks:.3g} blocks, {text}" if blocks else text


def _bytes(n: float) -> str:
    return f"{n / 2**30:.3g} GiB" if n >= 2**30 else f"{n / 2**20:.3g} MiB"


def estimate_size(
    blocks_per_course: float,
    courses: float,
    support_edges=(),
    max_steps: int = 1000,
    first_course_offset: bool = False,
) -> ProblemSize:
    """Blocks, interfaces, DOFs, memory and factorization time of a panel, from its dimensions
    alone (floats throughout, so absurd inputs give large numbers, not a hang)."""
    n_len, courses = float(blocks_per_course), float(courses)
    # courses alternate full and half-block starts: ceil(n) and ceil(n - 0.5) + 1 cells
    full, staggered = float(math.ceil(n_len - 1e-9)), float(math.ceil(n_len - 0.5 - 1e-9) + 1)
    first, second = (staggered, full) if first_course_offset else (full, staggered)
    nb = math.ceil(courses / 2) * first + math.floor(courses / 2) * second
    per_course = max(full, staggered)
    heads = courses * (per_course - 1)
    beds = max(courses - 1, 0) * (2 * per_course - 1)
    supports = sum(per_course if e in ("base", "top") else courses for e in set(support_edges))
    ni = heads + beds + supports
    nd = 6 * nb
    k_nnz = 36.0 * (nb + 2 * (heads + beds))
    lu_bytes = 12.0 * LU_FILL * nb**LU_EXPONENT  # value + row index per nonzero
    per_step = 8.0 * nd + 8.0 * ni + 8.0 * 8  # q, interface states, scalars
    path_bytes = (max_steps + 1) * per_step
    memory = (
        1.5 * lu_bytes + 2.0 * path_bytes + (max_steps + 1) * ni + MODEL_BYTES_PER_INTERFACE * ni
    )
    seconds = LU_SECONDS * (nb / LU_SECONDS_BLOCKS) ** LU_SECONDS_EXPONENT
    return ProblemSize(nb, ni, nd, k_nnz, lu_bytes, path_bytes, memory, seconds)


def check_size(size: ProblemSize, fix_steps: bool = True) -> ProblemSize:
    if size.n_blocks > MAX_BLOCKS:
        raise InputError(
            "panel",
            f"n_blocks {size.n_blocks:.3g} exceeds the limit {MAX_BLOCKS} "
            f"(estimated: {size.describe(blocks=False)})",
            "use fewer courses or blocks_per_course (stonedem.wall.case.MAX_BLOCKS)",
        )
    if size.memory_bytes > MAX_MEMORY_BYTES:
        where = "solver.max_steps" if fix_steps and size.path_bytes > size.lu_bytes else "panel"
        raise InputError(
            where,
            f"the run would need ~{_bytes(size.memory_bytes)}, over the limit "
            f"{_bytes(MAX_MEMORY_BYTES)} (estimated: {size.describe()})",
            "lower solver.max_steps or the panel size (stonedem.wall.case.MAX_MEMORY_BYTES)",
        )
    return size


# --- validation ---------------------------------------------------------------------------


@dataclass
class CaseInput:
    """A validated case, nothing built: every value checked, the problem size estimated."""

    spec: dict
    name: str
    a: float
    b: float
    s: float
    blocks_per_course: float
    courses: int
    unit_weight: float
    joint_thickness: float
    first_course_offset: bool
    openings: list
    lintel_strength: float
    joint_kind: str
    joint: dict
    law: dict
    support_edges: list
    support_joint: dict
    block_fix: dict
    dead_fix: set
    lines: list
    load_kind: str
    direction: str
    extras: list
    extra_live: bool
    settings: SolverSettings
    control_block: int | None
    size: ProblemSize = field(default=None)


def check_case(spec, name: str = "wall", where: str = "case") -> CaseInput:
    """Validate a case mapping (strict types, ranges, known keys, problem size) without building
    it."""
    spec = copy.deepcopy(_mapping(spec, where))
    _keys(spec, TOP_KEYS, "", required=("panel", "joints", "restraints", "load"))
    if "name" in spec:
        name = _text(spec["name"], "name", max_len=200)
    if "description" in spec:
        _text(spec["description"], "description", one_line=False)

    p = spec["panel"]
    _keys(p, PANEL_KEYS, "panel", required=("block", "blocks_per_course", "courses", "unit_weight"))
    _keys(p["block"], BLOCK_KEYS, "panel.block", required=("a", "b", "s"))
    a, b, s = (_ranged(p["block"][k], f"panel.block.{k}", "length", " m") for k in "abs")
    # the size limit (n_blocks, memory) is checked below, from the estimate
    n_len = _number(p["blocks_per_course"], "panel.blocks_per_course", 1.0, 1e12)
    if abs(2 * n_len - round(2 * n_len)) > 1e-9:
        raise InputError(
            "panel.blocks_per_course",
            f"{n_len:g} is not a multiple of 0.5",
            "give a whole or half number of blocks >= 1",
        )
    n_len = round(2 * n_len) / 2
    courses = _integer(p["courses"], "panel.courses", 1, 10**12)
    gamma = _ranged(p["unit_weight"], "panel.unit_weight", "unit_weight", " N/m3")
    e = _number(p.get("joint_thickness", 0.0), "panel.joint_thickness", 0.0, min(a, b), units=" m")
    offset = _bool(p.get("first_course_offset", False), "panel.first_course_offset")
    length, height = n_len * (b + e), courses * (a + e)
    openings = []
    for k, o in enumerate(
        _list(p.get("openings"), "panel.openings", allow_none=True, max_items=MAX_OPENINGS)
    ):
        f = f"panel.openings[{k}]"
        _keys(o, OPENING_KEYS, f, required=("x", "y"))
        box = {}
        for ax, extent in (("x", length), ("y", height)):
            v = o[ax]
            if not isinstance(v, list) or len(v) != 2:
                raise InputError(
                    f"{f}.{ax}",
                    f"expected [start, end] in metres, got {_show(v)}",
                    "give two numbers, e.g. [0.2, 0.5]",
                )
            lo, hi = (_ranged(x, f"{f}.{ax}", "coordinate", " m") for x in v)
            if hi <= lo:
                raise InputError(f"{f}.{ax}", f"end {hi:g} <= start {lo:g}", "give start < end")
            if lo >= extent:
                raise InputError(
                    f"{f}.{ax}",
                    f"starts at {lo:g} m, outside the panel (0 to {extent:.4g} m)",
                    "give the opening in metres from the panel's bottom left corner",
                )
            box[ax] = (lo, hi)
        openings.append(box)
    lintel = _ranged(p.get("lintel_strength", 0.0), "panel.lintel_strength", "stress", " Pa")
    if lintel and not openings:
        raise InputError(
            "panel.lintel_strength",
            "lintels act only over openings",
            "remove it or add panel.openings",
        )

    j = spec["joints"]
    _keys(j, JOINT_KEYS | set(LAW_KEYS), "joints", required=("kind", "mu", "k_n", "k_t"))
    kind = _choice(j["kind"], ("dry", "mortar"), "joints.kind")
    law = {
        key: _choice(j.get(key, options[0]), options, f"joints.{key}")
        for key, options in LAW_KEYS.items()
    }
    j = {key: val for key, val in j.items() if key not in LAW_KEYS}
    joint = _joint_props(j, kind, "joints")

    restraints = _list(spec["restraints"], "restraints", max_items=100)
    if not restraints:
        raise InputError("restraints", "expected a non-empty list", "e.g. [{edge: base, fix: all}]")
    support_edges, block_fix, support_joint, dead_fix, lines = [], {}, {}, set(), []
    for k, r in enumerate(restraints):
        f = f"restraints[{k}]"
        _keys(r, RESTRAINT_KEYS, f, required=("edge", "fix"))
        edge = _choice(r["edge"], EDGES, f"{f}.edge")
        fix = _choice(r["fix"], tuple(FIX_DOFS), f"{f}.fix")
        support = _choice(
            r.get("support", "joint" if edge == "base" else "block"),
            ("joint", "block"),
            f"{f}.support",
        )
        at = _choice(r.get("at", "centre"), RESTRAINT_AT, f"{f}.at")
        if "hold" in r and at == "centre":
            raise InputError(
                f"{f}.hold",
                "only for a restraint line (at: edge or offset)",
                "remove it or set at: edge",
            )
        if "offset" in r and at != "offset":
            raise InputError(
                f"{f}.offset",
                f"only for at: offset (this restraint is at: {at})",
                "remove it or set at: offset",
            )
        if support == "joint" and "at" in r:
            raise InputError(
                f"{f}.at",
                "a support joint is the whole edge interface",
                "remove it, or set support: block for a restraint line",
            )
        if support == "joint":
            if fix != "all":
                raise InputError(
                    f"{f}.fix",
                    f"{fix!r} with support: joint",
                    "a support joint is a fixed rigid support: use fix: all, or support: block",
                )
            if "dead_load" in r:
                raise InputError(
                    f"{f}.dead_load",
                    "only for support: block (a support joint always acts)",
                    "remove it or set support: block",
                )
            if edge in support_edges:
                raise InputError(
                    f"{f}.edge",
                    f"a second support joint on the {edge} edge",
                    "give each edge one support joint",
                )
            support_edges.append(edge)
            over = _mapping(r.get("joint"), f"{f}.joint", allow_none=True)
            _keys(over, JOINT_KEYS - {"kind"}, f"{f}.joint")
            support_joint[edge] = _joint_props({**j, **over}, kind, f"{f}.joint", given=over)
        else:
            if "joint" in r:
                raise InputError(
                    f"{f}.joint", "only for support: joint", "remove it or set support: joint"
                )
            # dead_load: true -> this restraint also acts while the self-weight is applied
            # (a base restraint always does: it carries the self-weight)
            dead = _bool(r.get("dead_load", False), f"{f}.dead_load")
            if at == "centre":
                block_fix.setdefault(edge, set()).update(FIX_DOFS[fix])
                if dead:
                    dead_fix.add(edge)
            else:
                if fix not in LINE_COMPONENTS:
                    raise InputError(
                        f"{f}.fix",
                        f"{fix!r} on a restraint line (at: {at}): a line holds "
                        "the displacement of its points, not rotations",
                        "use fix: out_of_plane or translations, or at: centre",
                    )
                distance = 0.0
                if at == "offset":
                    if "offset" not in r:
                        raise InputError(
                            f"{f}.offset",
                            "missing for at: offset",
                            "give the line's distance from the edge in metres",
                        )
                    extent = length if edge in ("left", "right") else height
                    distance = _number(r["offset"], f"{f}.offset", 0.0, extent, units=" m")
                    if distance >= extent:
                        raise InputError(
                            f"{f}.offset",
                            f"{distance:g} m is outside the panel ({extent:.4g} m across)",
                            "give a distance inside the panel",
                        )
                from stonedem.wall.restraints import LineRestraint

                hold = _choice(r.get("hold", "line"), ("line", "points"), f"{f}.hold")
                lines.append(
                    LineRestraint(
                        edge, LINE_COMPONENTS[fix], distance, dead or edge == "base", hold
                    )
                )

    ld = spec["load"]
    _keys(ld, LOAD_KEYS, "load", required=("kind",))
    load_kind = _choice(ld["kind"], ("proportional", "pressure"), "load.kind")
    direction = _choice(ld.get("direction", "out_of_plane"), tuple(DIRECTIONS), "load.direction")
    if load_kind == "pressure" and direction != "out_of_plane":
        raise InputError(
            "load.direction", "pressure acts out of plane", "use direction: out_of_plane"
        )
    extras = []
    for k, x in enumerate(
        _list(ld.get("extra_vertical"), "load.extra_vertical", allow_none=True, max_items=100)
    ):
        f = f"load.extra_vertical[{k}]"
        _keys(x, EXTRA_KEYS, f, required=("count", "force"))
        cnt = _integer(x["count"], f"{f}.count", 1, MAX_POINT_LOADS)
        force = _ranged(x["force"], f"{f}.force", "force", " N")
        extras.append((cnt, force, _choice(x.get("edge", "top"), ("top",), f"{f}.edge")))
    extra_live = _bool(ld.get("extra_in_live_load", False), "load.extra_in_live_load")

    sol = _mapping(spec.get("solver"), "solver", allow_none=True)
    _keys(sol, SOLVER_KEYS, "solver")
    settings = SolverSettings()
    control_block = None
    for key, val in sol.items():
        rule = SOLVER_RULES[key]
        f = f"solver.{key}"
        if rule[0] == "int":
            v = _integer(val, f, rule[1], rule[2])
        elif rule[0] == "switch":
            v = _switch(val, f)
        else:
            v = _number(val, f, *rule[1:])
        if (
            key == "first_step" and 0.0 < v < MIN_FIRST_STEP
        ):  # 1e-300 ran to lambda_max 4e-270, exit 0
            raise InputError(
                f,
                f"{v:g} m is below {MIN_FIRST_STEP:g} m, where rounding steers the path",
                f"give 0 (automatic) or a step >= {MIN_FIRST_STEP:g} m",
            )
        if key == "control_block":
            control_block = v
        else:
            # keep the type of the default (int counts; float otherwise, 0/1 switches included)
            setattr(settings, key, type(getattr(settings, key))(v))

    if "reference" in spec:
        _check_reference(spec["reference"])

    size = check_size(estimate_size(n_len, courses, support_edges, settings.max_steps, offset))
    if control_block is not None and control_block >= size.n_blocks:
        raise InputError(
            "solver.control_block",
            f"{control_block} >= {size.n_blocks:.0f} blocks",
            "give a block index of the panel",
        )
    return CaseInput(
        spec,
        name,
        a,
        b,
        s,
        n_len,
        courses,
        gamma,
        e,
        offset,
        openings,
        lintel,
        kind,
        joint,
        law,
        support_edges,
        support_joint,
        block_fix,
        dead_fix,
        lines,
        load_kind,
        direction,
        extras,
        extra_live,
        settings,
        control_block,
        size,
    )


def _check_reference(ref):
    _keys(ref, REFERENCE_KEYS, "reference")
    for key, val in ref.items():
        f = f"reference.{key}"
        if key in REFERENCE_NUMBERS:
            _ranged(val, f, "reference")
        elif key in REFERENCE_LISTS:
            if isinstance(val, list):
                _list(val, f, max_items=100)
            for k, x in enumerate(val if isinstance(val, list) else [val]):
                _ranged(x, f"{f}[{k}]" if isinstance(val, list) else f, "reference")
            if isinstance(val, list) and not val:
                raise InputError(f, "empty list", "give a number or a list of numbers")
        elif key in ("table", "n"):
            _integer(val, f, 1, 10_000)
        else:  # case label: text or an integer
            if isinstance(val, bool) or not isinstance(val, (str, int)):
                raise InputError(
                    f,
                    f"expected a label, got {_kind_name(val)} {_show(val)}",
                    "give text, e.g. S11",
                )
            if isinstance(val, str):
                _text(val, f, max_len=200)


def _joint_props(j, kind, field, given=None):
    """Joint properties of ``j``; ``given`` (support-joint overrides) names which keys the
    error should point at under ``field`` (the rest were checked under joints already)."""

    def name(key):
        return field if given is None or key in given else "joints"

    mu = _ranged(j["mu"], f"{name('mu')}.mu", "mu")
    k_n = _ranged(j["k_n"], f"{name('k_n')}.k_n", "stiffness", " N/m3")
    k_t = _ranged(j["k_t"], f"{name('k_t')}.k_t", "stiffness", " N/m3")
    alpha = _ranged(j.get("alpha", 1.5), f"{name('alpha')}.alpha", "alpha")
    if kind == "dry":
        for key in ("tensile_strength", "cohesion"):
            if key in j and _ranged(j[key], f"{name(key)}.{key}", "stress", " Pa") != 0.0:
                raise InputError(
                    f"{name(key)}.{key}",
                    "a dry joint has no tensile strength or cohesion",
                    "remove it or use kind: mortar",
                )
        sig_t, coh = 0.0, 0.0
    else:
        if "tensile_strength" not in j:
            raise InputError(
                f"{field}.tensile_strength", "missing for a mortar joint", "add it in Pa"
            )
        sig_t = _ranged(
            j["tensile_strength"], f"{name('tensile_strength')}.tensile_strength", "stress", " Pa"
        )
        # manuscript Eq. 10: shear strength mu (f_t - f_n), i.e. cohesion c = mu sigma_t
        if "cohesion" in j:
            coh = _ranged(j["cohesion"], f"{name('cohesion')}.cohesion", "stress", " Pa")
        else:
            coh = mu * sig_t
    return {
        "mu": mu,
        "k_n": k_n,
        "k_t": k_t,
        "alpha": alpha,
        "tensile_strength": sig_t,
        "cohesion": coh,
    }


# --- building -----------------------------------------------------------------------------


@dataclass
class WallCase:
    spec: dict
    name: str
    model: WallModel
    settings: SolverSettings
    control_block: int | None
    load_kind: str


def load_case(path) -> WallCase:
    path = Path(path)
    return build_case(check_case(read_case(path), name=path.stem, where=_printable(path)))


def case_from_dict(spec: dict, name: str = "wall") -> WallCase:
    return build_case(check_case(spec, name=name))


def build_case(ci: CaseInput) -> WallCase:
    """The panel, loads and restraints of a validated case (InputError for what only the built
    panel shows: openings removing every block or cutting blocks off from every support, a
    restrained control block, ...)."""
    from stonedem.wall.constitutive import (
        JointStrength,
    )  # numba and scipy: only once the case is valid
    from stonedem.wall.pushover import WallModel

    panel = build_panel(
        ci.a,
        ci.b,
        ci.s,
        ci.blocks_per_course,
        ci.courses,
        ci.joint_thickness,
        ci.openings,
        ci.first_course_offset,
        ci.support_edges,
    )
    if panel.n_blocks == 0:
        raise InputError("panel.openings", "the openings remove every block", "make them smaller")
    nb = panel.n_blocks
    ni = panel.n_interfaces
    if not ci.support_edges and not ci.block_fix and not ci.lines:
        raise InputError("restraints", "the wall is not supported", "add {edge: base, fix: all}")
    # pins on the blocks that touch their edge (an opening reaching the edge leaves none there)
    fixed = _pinned(panel, ci.block_fix)
    check_load_paths(ci, panel, fixed, ci.lines)
    if ni == 0:
        raise InputError(
            "panel",
            "a single block with no joints and no support joint",
            "give more blocks or a support joint (restraints: [{edge: base, fix: all}])",
        )
    props = {key: np.full(ni, ci.joint[key]) for key in ci.joint}
    for edge, jp in ci.support_joint.items():
        sel = (panel.kind == KIND_SUPPORT) & (panel.edge == edge)
        for key in jp:
            props[key][sel] = jp[key]
    # lintels: the head joints of the course just above each opening carry tension (a lintel
    # beam bearing on the jambs), otherwise a dry course over an opening cannot stand
    if ci.lintel_strength and ci.openings:
        for box in ci.openings:
            above = panel.centre[:, 1] - panel.size[:, 1] / 2 > box["y"][1] - 1e-9
            if not above.any():
                continue
            c_above = panel.course[above].min()
            x_lo = panel.centre[:, 0] - panel.size[:, 0] / 2
            x_hi = panel.centre[:, 0] + panel.size[:, 0] / 2
            beam = (
                (panel.course == c_above)
                & (x_hi > box["x"][0] + 1e-9)
                & (x_lo < box["x"][1] - 1e-9)
            )
            sel = (panel.kind == KIND_HEAD) & (panel.first >= 0) & (panel.second >= 0)
            sel &= np.isin(panel.first, np.flatnonzero(beam)) & np.isin(
                panel.second, np.flatnonzero(beam)
            )
            props["tensile_strength"][sel] = ci.lintel_strength
            props["cohesion"][sel] = props["mu"][sel] * ci.lintel_strength
    strength = JointStrength(
        props["mu"],
        props["tensile_strength"],
        props["cohesion"],
        props["alpha"],
        torsion_all_joints=ci.law["torsion_under_bending"] == "all",
        release_both_rotations=ci.law["bending_release"] == "both",
    )

    weight = ci.unit_weight * panel.volume
    dead = np.zeros((nb, 6))
    live = np.zeros((nb, 6))
    dead[:, 1] = -weight
    if ci.load_kind == "proportional":
        live[:, DIRECTIONS[ci.direction]] = weight
    else:
        live[:, 2] = panel.size[:, 0] * panel.size[:, 1]  # lambda = pressure [Pa]
    for count, force, edge in ci.extras:
        top = panel.edge_blocks(edge)
        lo = panel.centre[top, 0] - panel.size[top, 0] / 2
        hi = panel.centre[top, 0] + panel.size[top, 0] / 2
        for x in (np.arange(count) + 0.5) * panel.length / count:
            hit = top[np.flatnonzero((lo <= x) & (x < hi))]
            blk = hit[0] if len(hit) else top[np.argmin(np.abs(panel.centre[top, 0] - x))]
            dead[blk, 1] -= force
            if ci.extra_live and ci.load_kind == "proportional":
                live[blk, DIRECTIONS[ci.direction]] += force
    if not np.any((live.ravel() != 0) & ~fixed.ravel()):
        raise InputError(
            "restraints",
            "every block is held in the direction of the live load",
            "restrain only the edges (fewer restraints), or give a larger panel",
        )
    # restraints away from the base hold the wall after its self-weight has settled it
    fixed_dead = np.zeros_like(fixed)
    for blk in panel.touching("base"):
        fixed_dead[blk] = fixed[blk] if "base" in ci.block_fix else False
    for edge in ci.dead_fix:
        for blk in panel.touching(edge):
            fixed_dead[blk] |= fixed[blk]
    lines = ci.lines
    if not ci.support_edges and not fixed_dead.any() and not any(ln.dead_load for ln in lines):
        # nothing would carry the self-weight: every restraint acts from the start
        fixed_dead = fixed
        lines = [dataclasses.replace(ln, dead_load=True) for ln in lines]
    if ci.control_block is not None:
        if ci.control_block >= nb:
            raise InputError(
                "solver.control_block",
                f"{ci.control_block} >= {nb} blocks",
                "give a block index of the panel",
            )
        comp = DIRECTIONS[ci.direction] if ci.load_kind == "proportional" else 2
        if fixed[ci.control_block, comp]:
            raise InputError(
                "solver.control_block",
                f"block {ci.control_block} is restrained in the load direction",
                "give a free block, or remove control_block (the solver picks one)",
            )
    model = WallModel(
        panel,
        props["k_n"],
        props["k_t"],
        strength,
        dead.ravel(),
        live.ravel(),
        fixed.ravel(),
        fixed_dead.ravel(),
        lines,
    )
    return WallCase(ci.spec, ci.name, model, ci.settings, ci.control_block, ci.load_kind)


# --- load paths ---------------------------------------------------------------------------


def _pinned(panel, block_fix) -> np.ndarray:
    """(nb, 6) bool: the DOFs held by the pins of ``block_fix`` (edge -> DOFs), on the blocks
    that touch their edge."""
    fixed = np.zeros((panel.n_blocks, 6), dtype=bool)
    for edge, dofs in block_fix.items():
        fixed[np.ix_(panel.touching(edge), sorted(dofs))] = True
    return fixed


def _held(panel, fixed, lines) -> np.ndarray:
    """(nb,) bool: blocks a restraint acts on (a pinned DOF, a chord of a restraint line)."""
    held = np.asarray(fixed, dtype=bool).reshape(panel.n_blocks, 6).any(axis=1)
    for line in lines:
        held[np.array([blk for blk, _, _ in line.chords(panel)], dtype=int)] = True
    return held


def _cut_off(panel, held, present=None) -> np.ndarray:
    """(nb,) bool: blocks with no load path to a support. The interface graph: blocks are
    nodes, the joints between blocks (``present``: both present) edges, and the ground one more
    node, joined to by the support joints and to every ``held`` block."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    nb = panel.n_blocks
    present = np.ones(nb, dtype=bool) if present is None else present
    ends = np.stack([panel.first, panel.second]).reshape(2, -1)
    ends = np.where(ends == SUPPORT, nb, ends)
    ok = np.append(present, True)[ends].all(axis=0)
    pins = np.flatnonzero(held & present)
    rows = np.concatenate([ends[0, ok], pins])
    cols = np.concatenate([ends[1, ok], np.full(pins.size, nb)])
    graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(nb + 1, nb + 1))
    _, label = connected_components(graph, directed=False)
    return (label[:nb] != label[nb]) & present


def _ranges(values) -> str:
    """'0-3, 7, 9-10' for a set of integers."""
    values = sorted({int(v) for v in values})
    out, start = [], None
    for k, v in enumerate(values):
        if start is None:
            start = v
        if k + 1 == len(values) or values[k + 1] != v + 1:
            out.append(f"{start}" if start == v else f"{start}-{v}")
            start = None
    return ", ".join(out)


def _courses(course, courses) -> str:
    """'courses 2-8 of 8': course indices counted from 1 at the base, as in the case files."""
    course = np.unique(course) + 1
    return f"course{'s' if len(course) > 1 else ''} {_ranges(course)} of {courses}"


def _removed_text(full, removed, courses) -> str:
    """What a set of removed cells (``removed``: bool over the unholed panel) takes out."""
    whole = np.array(
        [c for c in np.unique(full.course[removed]) if removed[full.course == c].all()], dtype=int
    )
    part = removed & ~np.isin(full.course, whole)
    text = [f"every block of {_courses(whole, courses)}"] if whole.size else []
    if part.any():
        text.append(f"{int(part.sum())} blocks of {_courses(full.course[part], courses)}")
    return " and ".join(text)


def _blame(ci, panel, cut):
    """The openings that cut the ``cut`` blocks off from the supports and what they remove: those
    whose blocks, put back alone, give some of the blocks a load path (most first); else every
    opening that removes a block (only together do they cut the blocks off)."""
    every = list(range(len(ci.openings)))
    full = build_panel(
        ci.a,
        ci.b,
        ci.s,
        ci.blocks_per_course,
        ci.courses,
        ci.joint_thickness,
        (),
        ci.first_course_offset,
        ci.support_edges,
    )
    x, y = full.centre[:, 0], full.centre[:, 1]
    # the test build_panel removes a block by, on the same centres
    inside = np.array(
        [(o["x"][0] < x) & (x < o["x"][1]) & (o["y"][0] < y) & (y < o["y"][1]) for o in ci.openings]
    ).reshape(len(ci.openings), full.n_blocks)
    kept = ~inside.any(axis=0)
    if int(kept.sum()) != panel.n_blocks:  # not reached: the holed panel is the kept cells
        return every, "the blocks between them and the supports"
    cut_full = np.zeros(full.n_blocks, dtype=bool)
    cut_full[np.flatnonzero(kept)[cut]] = True
    held_full = _held(full, _pinned(full, ci.block_fix), ci.lines)
    joined = []
    for k in every:
        alone = inside[k] & (inside.sum(axis=0) == 1)
        if alone.any():
            n = int((cut_full & ~_cut_off(full, held_full, kept | alone)).sum())
            if n:
                joined.append((-n, k))
    order = [k for _, k in sorted(joined)] or [k for k in every if inside[k].any()] or every
    return order, _removed_text(full, inside[order].any(axis=0), ci.courses)


def check_load_paths(ci: CaseInput, panel, fixed, lines) -> None:
    """Refuse a panel with blocks that have no load path to a support, naming the opening that
    cuts them off (InputError). A support acts only on the blocks that touch its edge (support
    joint, pins) or lie on its line; a block, or a group of blocks joined by joints, that reaches
    none would hover: it has no limit load."""
    cut = _cut_off(panel, _held(panel, fixed, lines))
    if not cut.any():
        return
    nb, n = panel.n_blocks, int(cut.sum())
    who = (
        f"every block ({nb}, {_courses(panel.course, ci.courses)}) has"
        if n == nb
        else f"{n} of the {nb} blocks ({_courses(panel.course[cut], ci.courses)}) have"
    )
    edges = [e for e in EDGES if e in ci.support_edges or e in ci.block_fix]
    where = [f"the {' and '.join(edges)} edge{'s' if len(edges) > 1 else ''}"] if edges else []
    where += [
        f"the {ln.edge} line" + (f" {ln.distance:g} m inside" if ln.distance else "")
        for ln in lines
        if ln.edge not in edges or ln.distance
    ]
    why = f"a support acts only on the blocks on {' and '.join(where)}"
    fix = (
        "shrink or move the opening so that blocks join these to a support, or support an "
        "edge they touch"
    )
    if not ci.openings:  # not reached: a running-bond panel without openings is all joined
        raise InputError("restraints", f"{who} no load path to a support ({why})", fix)
    order, removed = _blame(ci, panel, cut)
    text = "the opening removes"
    if len(order) > 1:
        others = ", ".join(f"panel.openings[{k}]" for k in order[1:])
        text, fix = (
            f"with {others}, the opening removes",
            fix.replace("the opening", "the openings"),
        )
    raise InputError(
        f"panel.openings[{order[0]}]",
        f"{who} no load path to a support: {text} {removed}, and {why}",
        fix,
    )
