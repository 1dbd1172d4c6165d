"""Wall case files (YAML): reading, strict validation, problem-size limits, and the model they
describe. A case file::

    panel: {block: {a: 0.081, b: 0.210, s: 0.070}, blocks_per_course: 3, courses: 13,
            unit_weight: 20000.0}
    joints: {kind: dry, mu: 0.7, k_n: 2.4e9, k_t: 1.0e9}  # mortar: add tensile_strength, cohesion
    restraints: [{edge: base, fix: all}, {edge: left, fix: translations, at: edge}]
    load: {kind: proportional, direction: out_of_plane}     # or {kind: pressure}

Every key is one row of :data:`CASE_SPEC` (units, range, default, meaning), checked with the
declared-input kit (:mod:`stonedem.io.spec`); ``key_table(CASE_SPEC)`` prints them. Three
stages, each refusing bad input with an InputError naming the dotted field and the fix (exit
status 2):

- :func:`read_case`: the file (exists, a regular file, at most ``MAX_CASE_BYTES``, UTF-8, YAML
  without duplicate keys, a mapping);
- :func:`check_case`: every field checked against :data:`CASE_SPEC` (a bool is a YAML bool, an
  integer an integer, a number finite and inside its range; unknown keys refused with the
  known ones), then the checks across fields and against the geometry, and the problem size
  estimated (:func:`estimate_size`) and held to ``MAX_BLOCKS`` and ``MAX_MEMORY_BYTES`` --
  nothing is built yet;
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
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import (
    NUMERIC_TEXT,
    REQUIRED,
    Derived,
    Field,
    Spec,
    got,
    plain_list,
    plain_number,
    show,
)
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

FIX_DOFS = {
    "all": (0, 1, 2, 3, 4, 5),
    "translations": (0, 1, 2),
    "out_of_plane": (2,),
    "rotations": (3, 4, 5),
}
DIRECTIONS = {"out_of_plane": 2, "in_plane": 0}
# where a block restraint acts: pins at the edge blocks' centres, or a straight line along the
# panel edge (at its mid-thickness), or parallel to it ``offset`` metres inside
RESTRAINT_AT = ("centre", "edge", "offset")
# what a restraint line holds: the displacement of its points out of plane, or all of it
LINE_COMPONENTS = {"out_of_plane": (2,), "translations": (0, 1, 2)}
# interface-law switches (the whole panel; not per support joint): manuscript Fig. 10 and Eq. 13
LAW_KEYS = ("torsion_under_bending", "bending_release")
# [m] a set first_step: 0 (automatic) or at least this (1e-12 ran as 1e-5 did)
MIN_FIRST_STEP = 1e-12


# --- kinds the kit lacks ------------------------------------------------------------------


@dataclass(frozen=True)
class _Own(Field):
    """A field of a kind the kit lacks, checked by ``own(field, value, name)`` -> (value, problem);
    a problem is refused with the field's hint as the fix. ``shown`` is its kind in the docs."""

    own: Callable | None = None
    shown: str = ""

    def check(self, value, where: str = ""):
        name = where or self.key
        value, problem = self.own(self, value, name)
        if problem:
            raise InputError(name, problem, self.hint)
        return value

    def shown_kind(self) -> str:
        return self.shown


def _zero_or_one(f: Field, value, name: str):
    """0 or 1 (false or true, or numeric text), as a float like the settings' switches."""
    x = plain_number(value)
    if isinstance(x, str) and NUMERIC_TEXT.fullmatch(x):
        x = float(x)
    if type(value) is not bool and (type(x) not in (int, float) or x not in (0, 1)):
        return value, f"expected 0 or 1, got {got(value)}"
    return float(x), ""


def _number_or_list(f: Field, value, name: str):
    """One number, or a non-empty list of them, each in the field's range."""
    if isinstance(plain_list(value), list):
        values = Field.check(f, value, name)  # the kit's list of numbers
        return values, "" if values else "empty list"
    return Field(f.key, "number", f.units, f.range).check(value, name), ""


def _label(f: Field, value, name: str):
    """Text (one line) or an integer, e.g. ``S11`` or ``1``."""
    if isinstance(value, int) and not isinstance(value, bool):
        return value, ""
    if isinstance(value, str):
        return Field.check(f, value, name), ""
    return value, f"expected a label, got {got(value)}"


# --- the case file, declared --------------------------------------------------------------

LENGTH = "[1e-3, 100]"  # [m] block sides: any masonry unit
STRESS = "[0, 1e10]"  # [Pa] tensile strength, cohesion, lintel strength
FORCE = "[0, 1e10]"  # [N] point loads
STIFFNESS = "[1e3, 1e16]"  # [N/m3] k_n, k_t
REFERENCE = "(0, 1e12]"  # manuscript reference values

BLOCK_SPEC = Spec(
    (
        Field("a", "number", "m", LENGTH, REQUIRED, doc="block height (one course)"),
        Field("b", "number", "m", LENGTH, REQUIRED, doc="block length along the course"),
        Field("s", "number", "m", LENGTH, REQUIRED, doc="block thickness (the wall's)"),
    ),
    doc="the block",
)
OPENING_SPEC = Spec(
    tuple(
        Field(
            axis,
            "numbers",
            "m",
            "[0, 1e4]",
            REQUIRED,
            length=2,
            hint=f"give [start, end] in metres from the panel's {corner}, e.g. [0.2, 0.5]",
            doc=f"{what} of the opening, from the panel's {corner}",
        )
        for axis, what, corner in (
            ("x", "horizontal extent [start, end]", "left edge"),
            ("y", "vertical extent [start, end]", "base"),
        )
    ),
    doc="a rectangular opening",
)
PANEL_SPEC = Spec(
    (
        Field("block", "mapping", default=REQUIRED, spec=BLOCK_SPEC, doc="the block: a, b and s"),
        Field(
            "blocks_per_course",
            "number",
            "",
            "[1, 1e12]",
            REQUIRED,
            doc="blocks along a course, a whole or half number (the courses are staggered)",
        ),
        Field("courses", "integer", "", "[1, 1e12]", REQUIRED, doc="courses, base to top"),
        Field(
            "unit_weight",
            "number",
            "N/m3",
            "[1, 1e6]",
            REQUIRED,
            doc="unit weight of the masonry (brick ~18e3, steel 77e3)",
        ),
        Field(
            "joint_thickness",
            "number",
            "m",
            "[0, 100]",
            0.0,
            doc="thickness of the joints between blocks, at most the block's a and b",
        ),
        Field(
            "first_course_offset",
            "flag",
            default=False,
            doc="start the first course with a half block (the second one otherwise)",
        ),
        Field(
            "openings",
            "list",
            limit=MAX_OPENINGS,
            default=[],
            spec=OPENING_SPEC,
            hint="give a list of {x: [start, end], y: [bottom, top]}",
            doc="rectangular openings: the blocks whose centres lie inside are left out",
        ),
        Field(
            "lintel_strength",
            "number",
            "Pa",
            STRESS,
            0.0,
            doc="tensile strength of the head joints of the course over each opening (a lintel)",
        ),
    ),
    doc="the panel: a running-bond wall of equal blocks",
)


def _cohesion(v: dict):
    # manuscript Eq. 10: shear strength mu (f_t - f_n), i.e. cohesion c = mu sigma_t
    return None if v["tensile_strength"] is None else v["mu"] * v["tensile_strength"]


JOINT_FIELDS = (
    Field("mu", "number", "", "(0, 10]", REQUIRED, doc="friction coefficient"),
    Field("k_n", "number", "N/m3", STIFFNESS, REQUIRED, doc="normal stiffness per unit area"),
    Field("k_t", "number", "N/m3", STIFFNESS, REQUIRED, doc="shear stiffness per unit area"),
    Field(
        "tensile_strength",
        "number",
        "Pa",
        STRESS,
        doc="tensile strength: required for a mortar joint, none (or 0) for a dry one",
    ),
    Field(
        "cohesion",
        "number",
        "Pa",
        STRESS,
        Derived("mu x tensile_strength", _cohesion),
        doc="cohesion of a mortar joint (manuscript Eq. 10)",
    ),
    Field(
        "alpha",
        "number",
        "",
        "[1, 10]",
        1.5,
        doc="exponent of the shear-torsion domain (Eq. 14; Table A1: 1.5-2.6); >= 1: convex",
    ),
)
JOINTS_SPEC = Spec(
    (
        Field("kind", "choice", default=REQUIRED, choices=("dry", "mortar"), doc="joint kind"),
        *JOINT_FIELDS,
        Field(
            "torsion_under_bending",
            "choice",
            default="all",
            choices=("all", "no_tension"),
            doc="which joints keep their torsion strength while they open in bending (Fig. 10)",
        ),
        Field(
            "bending_release",
            "choice",
            default="own",
            choices=("own", "both"),
            doc="a joint opening in bending releases its own rotation or both (Eq. 13)",
        ),
    ),
    doc="the joints of the whole panel (the support joints too, unless a restraint sets its own)",
)
# a support joint's own values: each absent one is the joints' (cohesion: mu x tensile_strength)
SUPPORT_JOINT_SPEC = Spec(
    tuple(
        dataclasses.replace(f, default=None, doc=f"{f.doc}; default: the joints'")
        for f in JOINT_FIELDS
    ),
    doc="a support joint's own law values",
)
RESTRAINT_SPEC = Spec(
    (
        Field("edge", "choice", default=REQUIRED, choices=EDGES, doc="the panel edge it holds"),
        Field(
            "fix",
            "choice",
            default=REQUIRED,
            choices=tuple(FIX_DOFS),
            doc="what it holds: all DOFs, the translations, the out-of-plane one or the rotations",
        ),
        Field(
            "support",
            "choice",
            default=Derived(
                "joint on the base, else block",
                lambda v: "joint" if v["edge"] == "base" else "block",
            ),
            choices=("joint", "block"),
            doc="joint: an interface to a rigid support along the edge (fix: all); block: the "
            "edge blocks are held",
        ),
        Field(
            "joint",
            "mapping",
            default={},
            spec=SUPPORT_JOINT_SPEC,
            doc="a support joint's own law values, in place of the joints' (support: joint)",
        ),
        Field(
            "dead_load",
            "flag",
            default=False,
            doc="also hold while the self-weight is applied (a base restraint always does)",
        ),
        Field(
            "at",
            "choice",
            default="centre",
            choices=RESTRAINT_AT,
            doc="where a block restraint acts: pins at the edge blocks' centres, a line along "
            "the edge (mid-thickness), or a line offset inside (support: block)",
        ),
        Field(
            "offset",
            "number",
            "m",
            "[0, inf)",
            doc="distance of the line from the edge (at: offset)",
        ),
        Field(
            "hold",
            "choice",
            default="line",
            choices=("line", "points"),
            doc="a restraint line holds every point of its chords, or the middle of each chord "
            "(a row of pins)",
        ),
    ),
    doc="one restraint of the panel",
)
EXTRA_SPEC = Spec(
    (
        Field(
            "count",
            "integer",
            "",
            f"[1, {MAX_POINT_LOADS}]",
            REQUIRED,
            doc="point loads, evenly spaced along the top course",
        ),
        Field("force", "number", "N", FORCE, REQUIRED, doc="downward force of each point load"),
        Field("edge", "choice", default="top", choices=("top",), doc="the edge they bear on"),
    ),
    doc="point loads on the top course",
)
LOAD_SPEC = Spec(
    (
        Field(
            "kind",
            "choice",
            default=REQUIRED,
            choices=("proportional", "pressure"),
            doc="the live load: lambda x the self-weight (proportional), or a pressure lambda "
            "[Pa] on the face",
        ),
        Field(
            "direction",
            "choice",
            default="out_of_plane",
            choices=tuple(DIRECTIONS),
            doc="direction of the live load (a pressure acts out of plane)",
        ),
        Field(
            "extra_vertical",
            "list",
            limit=100,
            default=[],
            spec=EXTRA_SPEC,
            hint="give a list of {count: n, force: N}",
            doc="point loads on the top course, added to the self-weight",
        ),
        Field(
            "extra_in_live_load",
            "flag",
            default=False,
            doc="the point loads also enter a proportional live load",
        ),
    ),
    doc="the loads: the self-weight first (dead load), then the live load lambda x ...",
)
_S = SolverSettings()


def _setting(key: str, kind: str, interval: str, doc: str, units: str = "") -> Field:
    """A solver setting, its default the settings' own."""
    return Field(key, kind, units, interval, getattr(_S, key), doc=doc)


def _switch(key: str, doc: str) -> Field:
    hint = "give 0 (off) or 1 (on)"
    return _Own(
        key, "any", default=getattr(_S, key), hint=hint, doc=doc, own=_zero_or_one, shown="0 \\| 1"
    )


SOLVER_SPEC = Spec(
    (
        # finer than 1e-12: rounding (~1e-15) was blamed on the restraints
        _setting(
            "tolerance",
            "number",
            "[1e-12, 0.1]",
            "residual norm / reference load norm at convergence",
        ),
        # a Newton step converges at iteration 2 at the earliest
        _setting("max_iterations", "integer", "[2, 10000]", "iterations before a step is halved"),
        _setting(
            "dead_load_iterations",
            "integer",
            "[2, 100000]",
            "iterations of the dead load (load control, secant matrix)",
        ),
        _setting("max_steps", "integer", "[1, 1e6]", "steps of the pushover at most"),
        _setting(
            "max_displacement",
            "number",
            "[0, 1e3]",
            "control displacement at which to stop; 0: the wall thickness s",
            "m",
        ),
        _setting(
            "first_step",
            "number",
            "[0, 1e3]",
            f"first control increment; 0: automatic, else at least {MIN_FIRST_STEP:g} m",
            "m",
        ),
        _setting("growth", "number", "[1, 10]", "step growth after an easy step"),
        _setting(
            "easy_iterations",
            "integer",
            "[0, 10000]",
            "a step is easy when it converged within this many iterations",
        ),
        _setting(
            "max_failures",
            "integer",
            "[1, 1000]",
            "consecutive failed (halved) steps before accepting or giving up",
        ),
        _setting("accept_tolerance", "number", "(0, 1]", "residual accepted after max_failures"),
        _switch("work_control", "1: step the load-weighted mean displacement, 0: the control DOF"),
        _switch("consistent", "1: consistent (return-map) tangent, 0: the secant of Eq. 13-14"),
        # 0 would leave yielded DOFs singular
        _setting(
            "residual_stiffness",
            "number",
            "(0, 1]",
            "fraction of the stiffness kept on yielded components (iteration matrix)",
        ),
        _switch(
            "extrapolate", "1: start a step from the last increment, scaled; 0: from the last state"
        ),
        _setting(
            "reuse_ratio",
            "number",
            "[0, 1]",
            "keep the LU while an iteration cuts the residual below this x; 0: refactor always",
        ),
        _setting(
            "drop_ratio", "number", "[0, 1]", "stop when lambda falls below this x lambda_max"
        ),
        _setting(
            "plateau_steps",
            "integer",
            "[1, 1e6]",
            "stop after this many steps (and twice the displacement) ...",
        ),
        _setting(
            "plateau_tolerance",
            "number",
            "[0, 1]",
            "... in which lambda rose by less than this fraction",
        ),
        _setting(
            "max_seconds",
            "number",
            "[0, 1e7]",
            "wall-clock budget of the live-load phase; 0: none",
            "s",
        ),
        _switch(
            "secant",
            "1: the manuscript's load-controlled secant scheme (2.3), 0: displacement control",
        ),
        _setting(
            "load_step",
            "number",
            "[0, 1e12]",
            "first load increment (secant scheme); 0: 1/50 of the elastic-limit estimate",
        ),
        _setting(
            "min_load_step",
            "number",
            "(0, 1]",
            "stop refining when the increment falls below this x the first one",
        ),
        _setting(
            "singular_ratio",
            "number",
            "(1, 1e15]",
            "unbounded: incremental flexibility over this x the initial one",
        ),
        _setting(
            "secant_refresh",
            "integer",
            "[0, 10000]",
            "> 0: also rebuild the secant matrix every this many iterations",
        ),
        Field(
            "control_block",
            "integer",
            "",
            f"[0, {MAX_BLOCKS}]",
            doc="block whose displacement controls the steps; default: the solver picks one",
        ),
    ),
    doc="the pushover solver's settings (stonedem.wall.settings.SolverSettings)",
)
assert set(SOLVER_SPEC.keys) == set(_S.as_dict()) | {"control_block"}, "every setting a row"
REFERENCE_SPEC = Spec(
    (
        Field("table", "integer", "", "[1, 10000]", doc="manuscript table of the case"),
        _Own(
            "case",
            "text",
            limit=200,
            hint="give text, e.g. S11, or an integer",
            doc="case label in that table",
            own=_label,
            shown="text \\| integer",
        ),
        Field(
            "n", "integer", "", "[1, 10000]", doc="the table's n: blocks per course of the specimen"
        ),
        *(
            Field(key, "number", "", REFERENCE, doc=doc)
            for key, doc in (
                ("L", "panel length [m]"),
                ("H", "panel height [m]"),
                ("p_dem", "limit pressure of the manuscript's DEM [Pa]"),
                ("lambda_dem", "limit load multiplier of the manuscript's DEM"),
                ("lambda_fem", "limit load multiplier of its FEM reference"),
                ("lambda_limit_analysis", "limit load multiplier of its limit analysis"),
                ("lambda_analytic", "closed-form limit load multiplier"),
            )
        ),
        *(
            _Own(
                key,
                "numbers",
                "",
                REFERENCE,
                limit=100,
                hint="give a number or a list of numbers",
                doc=doc,
                own=_number_or_list,
                shown="number \\| list of numbers",
            )
            for key, doc in (
                ("p_experiment", "experimental limit pressure(s) [Pa]"),
                ("lambda_experiment", "experimental limit load multiplier(s)"),
            )
        ),
    ),
    doc="manuscript reference values: no effect on the run; the dataset carries them",
)
CASE_SPEC = Spec(
    (
        Field("name", "text", limit=200, doc="case name (default: the file's stem)"),
        Field(
            "description",
            "text",
            limit=MAX_TEXT,
            one_line=False,
            doc="free text, may run over lines",
        ),
        Field(
            "panel",
            "mapping",
            default=REQUIRED,
            spec=PANEL_SPEC,
            doc="the panel: its block, size and openings",
        ),
        Field("joints", "mapping", default=REQUIRED, spec=JOINTS_SPEC, doc="the law of the joints"),
        Field(
            "restraints",
            "list",
            default=REQUIRED,
            limit=100,
            spec=RESTRAINT_SPEC,
            hint="give a list of restraints, e.g. [{edge: base, fix: all}]",
            doc="the supports of the panel",
        ),
        Field(
            "load",
            "mapping",
            default=REQUIRED,
            spec=LOAD_SPEC,
            doc="the self-weight and the live load",
        ),
        Field(
            "solver", "mapping", default={}, spec=SOLVER_SPEC, doc="the pushover solver's settings"
        ),
        Field("reference", "mapping", spec=REFERENCE_SPEC, doc="manuscript reference values"),
    ),
    doc="a wall case file",
)


# --- checks across fields (code: they depend on other values or on the geometry) ----------


@dataclass(frozen=True)
class Across:
    """A check across the checked values of one mapping: ``refused(values)`` is true when the
    value of ``key`` ("": the mapping itself) is refused; ``problem`` may name values
    (``{at}``, ``{fix!r}``)."""

    key: str
    refused: Callable[[dict], bool]
    problem: str
    fix: str


def _across(checks, values: dict, where: str) -> None:
    for c in checks:
        if c.refused(values):
            name = ".".join(part for part in (where, c.key) if part)
            raise InputError(name, c.problem.format(**values), c.fix)


def _within(value, name: str, interval: str, units: str = "", hint: str = "", kind="number"):
    """``value`` checked against a range known only from the geometry (a kit field made on
    the spot, ``interval`` like ``"[0, 0.63)"``)."""
    return Field(name, kind, units, interval, hint=hint).check(value, name)


TOP_CHECKS = (
    Across(
        "restraints",
        lambda v: not v["restraints"],
        "expected a non-empty list",
        "e.g. [{edge: base, fix: all}]",
    ),
)
PANEL_CHECKS = (
    Across(
        "blocks_per_course",
        lambda v: abs(2 * v["blocks_per_course"] - round(2 * v["blocks_per_course"])) > 1e-9,
        "{blocks_per_course:g} is not a multiple of 0.5",
        "give a whole or half number of blocks >= 1",
    ),
    Across(
        "lintel_strength",
        lambda v: v["lintel_strength"] and not v["openings"],
        "lintels act only over openings",
        "remove it or add panel.openings",
    ),
)
# one axis of an opening: {lo, hi, extent} (the panel's length or height)
OPENING_CHECKS = (
    Across("", lambda v: v["hi"] <= v["lo"], "end {hi:g} <= start {lo:g}", "give start < end"),
    Across(
        "",
        lambda v: v["lo"] >= v["extent"],
        "starts at {lo:g} m, outside the panel (0 to {extent:.4g} m)",
        "give the opening in metres from the panel's bottom left corner",
    ),
)
SUPPORT_JOINT_CHECKS = tuple(
    Across(
        key,
        lambda v, key=key: v["kind"] == "dry" and v.get(key),
        "a dry joint has no tensile strength or cohesion",
        "remove it or use kind: mortar",
    )
    for key in ("tensile_strength", "cohesion")
)
JOINT_CHECKS = (
    *SUPPORT_JOINT_CHECKS,
    Across(
        "tensile_strength",
        lambda v: v["kind"] == "mortar" and v["tensile_strength"] is None,
        "missing for a mortar joint",
        "add it in Pa",
    ),
)
# values: the restraint's, ``given`` (the keys written) and ``seen`` (the support joints' edges
# so far)
RESTRAINT_CHECKS = (
    Across(
        "hold",
        lambda v: "hold" in v["given"] and v["at"] == "centre",
        "only for a restraint line (at: edge or offset)",
        "remove it or set at: edge",
    ),
    Across(
        "offset",
        lambda v: "offset" in v["given"] and v["at"] != "offset",
        "only for at: offset (this restraint is at: {at})",
        "remove it or set at: offset",
    ),
    Across(
        "at",
        lambda v: v["support"] == "joint" and "at" in v["given"],
        "a support joint is the whole edge interface",
        "remove it, or set support: block for a restraint line",
    ),
    Across(
        "fix",
        lambda v: v["support"] == "joint" and v["fix"] != "all",
        "{fix!r} with support: joint",
        "a support joint is a fixed rigid support: use fix: all, or support: block",
    ),
    Across(
        "dead_load",
        lambda v: v["support"] == "joint" and "dead_load" in v["given"],
        "only for support: block (a support joint always acts)",
        "remove it or set support: block",
    ),
    Across(
        "edge",
        lambda v: v["support"] == "joint" and v["edge"] in v["seen"],
        "a second support joint on the {edge} edge",
        "give each edge one support joint",
    ),
    Across(
        "joint",
        lambda v: v["support"] == "block" and "joint" in v["given"],
        "only for support: joint",
        "remove it or set support: joint",
    ),
    Across(
        "fix",
        lambda v: (
            v["support"] == "block" and v["at"] != "centre" and v["fix"] not in LINE_COMPONENTS
        ),
        "{fix!r} on a restraint line (at: {at}): a line holds the displacement of its points, "
        "not rotations",
        "use fix: out_of_plane or translations, or at: centre",
    ),
    Across(
        "offset",
        lambda v: v["at"] == "offset" and "offset" not in v["given"],
        "missing for at: offset",
        "give the line's distance from the edge in metres",
    ),
)
LOAD_CHECKS = (
    Across(
        "direction",
        lambda v: v["kind"] == "pressure" and v["direction"] != "out_of_plane",
        "pressure acts out of plane",
        "use direction: out_of_plane",
    ),
)
SOLVER_CHECKS = (
    # 1e-300 ran to lambda_max 4e-270, exit 0
    Across(
        "first_step",
        lambda v: 0.0 < v["first_step"] < MIN_FIRST_STEP,
        f"{{first_step:g}} m is below {MIN_FIRST_STEP:g} m, where rounding steers the path",
        f"give 0 (automatic) or a step >= {MIN_FIRST_STEP:g} m",
    ),
)


def _loose(spec: Spec, mapping, where: str = "") -> None:
    """Refuse, before the kit checks ``mapping``, what the kit reads more loosely than a case
    file is written: a null where a value is due (the kit takes it for an absent key; a null
    is an empty list or mapping only where that is the default), numeric text with spaces
    around it (the kit strips them), and an integer past 1e300 (the kit cannot print it)."""
    if not isinstance(mapping, Mapping):
        return
    for key, value in mapping.items():
        f = spec.by_key.get(key)
        if f is None:
            continue  # an unknown key: the kit names it
        name = f"{where}.{key}" if where else key
        problem, fix = "", f.hint
        x = plain_number(value)
        items = plain_list(value) if isinstance(plain_list(value), list) else [value]
        padded = [t for t in items if isinstance(t, str) and t != t.strip()]
        if value is None and not isinstance(f.default, (list, dict)):
            if f.kind != "mapping":
                f.check(None, name)  # refused in the kit's (or the field's own) words
            problem, fix = f"expected a mapping, got {got(None)}", "write it as {key: value, ...}"
        elif f.kind in ("number", "numbers") and padded:
            problem, fix = f"expected a number, got {got(padded[0])}", "write the number alone"
        elif f.kind == "integer" and type(x) is int and abs(x) > 1e300:
            problem, fix = f"{show(value)} is out of range", "give a number of sensible size"
        if problem:
            raise InputError(name, problem, fix)
        if f.spec is not None and f.kind == "mapping":
            _loose(f.spec, value, name)
        elif f.spec is not None and isinstance(plain_list(value), list):
            for k, item in enumerate(plain_list(value)[: f.limit]):
                _loose(f.spec, item, f"{name}[{k}]")


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
    it: :data:`CASE_SPEC`, then the checks across fields and against the geometry."""
    Field(where, "mapping").check(spec, where)
    spec = copy.deepcopy(spec)
    _loose(CASE_SPEC, spec)
    v = CASE_SPEC.check(spec)
    _across(TOP_CHECKS, v, "")
    p, j, ld = v["panel"], v["joints"], v["load"]
    sol = v["solver"] or SOLVER_SPEC.defaults()
    name = name if v["name"] is None else v["name"]

    a, b, s = (p["block"][key] for key in "abs")
    _across(PANEL_CHECKS, p, "panel")
    # the size limit (n_blocks, memory) is checked below, from the estimate
    n_len = round(2 * p["blocks_per_course"]) / 2
    e = _within(p["joint_thickness"], "panel.joint_thickness", f"[0, {min(a, b)!r}]", "m")
    length, height = n_len * (b + e), p["courses"] * (a + e)
    openings = []
    for k, o in enumerate(p["openings"]):
        for ax, extent in (("x", length), ("y", height)):
            lo, hi = o[ax]
            _across(
                OPENING_CHECKS, {"lo": lo, "hi": hi, "extent": extent}, f"panel.openings[{k}].{ax}"
            )
        openings.append({ax: tuple(o[ax]) for ax in "xy"})

    kind = j["kind"]
    _across(JOINT_CHECKS, j, "joints")
    joint = _joint(j, kind)
    law = {key: j[key] for key in LAW_KEYS}

    support_edges, block_fix, support_joint, dead_fix, lines = [], {}, {}, set(), []
    for k, (given, r) in enumerate(zip(spec["restraints"], v["restraints"])):
        f = f"restraints[{k}]"
        _across(RESTRAINT_CHECKS, {**r, "given": given, "seen": support_edges}, f)
        edge, fix, at = r["edge"], r["fix"], r["at"]
        if r["support"] == "joint":
            support_edges.append(edge)
            own = {key: x for key, x in r["joint"].items() if x is not None}
            _across(SUPPORT_JOINT_CHECKS, {**own, "kind": kind}, f"{f}.joint")
            merged = {**j, **own}
            if "cohesion" not in own and "cohesion" not in spec["joints"]:
                merged["cohesion"] = _cohesion(merged)
            support_joint[edge] = _joint(merged, kind)
        elif at == "centre":
            block_fix.setdefault(edge, set()).update(FIX_DOFS[fix])
            if r["dead_load"]:
                dead_fix.add(edge)
        else:
            from stonedem.wall.restraints import LineRestraint  # scipy: only for a line

            distance = 0.0
            if at == "offset":
                extent = length if edge in ("left", "right") else height
                distance = _within(
                    r["offset"],
                    f"{f}.offset",
                    f"[0, {extent!r})",
                    "m",
                    "give a distance inside the panel",
                )
            base = r["dead_load"] or edge == "base"
            lines.append(LineRestraint(edge, LINE_COMPONENTS[fix], distance, base, r["hold"]))

    _across(LOAD_CHECKS, ld, "load")
    extras = [(x["count"], x["force"], x["edge"]) for x in ld["extra_vertical"]]

    _across(SOLVER_CHECKS, sol, "solver")
    settings = SolverSettings()
    for key, value in sol.items():
        if key != "control_block":
            # keep the type of the default (int counts; float otherwise, 0/1 switches included)
            setattr(settings, key, type(getattr(settings, key))(value))

    size = check_size(
        estimate_size(
            n_len, p["courses"], support_edges, settings.max_steps, p["first_course_offset"]
        )
    )
    control_block = sol["control_block"]
    if control_block is not None:
        control_block = _within(
            control_block,
            "solver.control_block",
            f"[0, {size.n_blocks!r})",
            hint="give a block index of the panel",
            kind="integer",
        )
    return CaseInput(
        spec,
        name,
        a,
        b,
        s,
        n_len,
        p["courses"],
        p["unit_weight"],
        e,
        p["first_course_offset"],
        openings,
        p["lintel_strength"],
        kind,
        joint,
        law,
        support_edges,
        support_joint,
        block_fix,
        dead_fix,
        lines,
        ld["kind"],
        ld["direction"],
        extras,
        ld["extra_in_live_load"],
        settings,
        control_block,
        size,
    )


def _joint(v: dict, kind: str) -> dict:
    """The law values of a joint, in the order :func:`build_case` reads them: a dry joint has
    neither tensile strength nor cohesion."""
    dry = kind == "dry"
    return {
        "mu": v["mu"],
        "k_n": v["k_n"],
        "k_t": v["k_t"],
        "alpha": v["alpha"],
        "tensile_strength": 0.0 if dry else v["tensile_strength"],
        "cohesion": 0.0 if dry else v["cohesion"],
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
