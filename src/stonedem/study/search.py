"""Collapse thresholds by hunt-and-fill search over an intensity measure.

Vamvatsikos & Cornell (2002), incremental dynamic analysis: *hunt* up in growing steps
until the structure collapses, *bisect* between the largest survivor below the first
collapse and that collapse until the bracket is narrow enough, then *fill* the widest
gaps left below it and, every second fill, above it, because collapse is not monotonic in
the intensity: a fill run below that collapses lowers the threshold (bisection resumes),
and every survivor above the smallest collapse is a "resurrection", reported, never hidden.

The search is a pure function of the runs so far (:func:`next_value`), so it does not care
what the intensity measure is (a record's PGA, its PGV, a scale factor): the caller runs a
case at the value and reports whether it collapsed.

A GPU wants many runs at once, not one after another. :func:`search_together` runs many
searches in rounds: each round runs, for every search not yet done, the values the rule
could ask for next under either outcome of the runs still unknown (the rule's decision
tree, breadth first, up to ``width`` values), so the runs the rule does ask for are known a
few levels ahead. Replayed on the known outcomes, the rule then makes exactly the runs
:func:`search` makes: the same brackets, fills and resurrections; the other runs are spent.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

from stonedem.errors import InputError
from stonedem.io.spec import Field, Spec

# search statuses (summary()["status"])
BRACKETED = "bracketed"  # smallest collapse within tolerance of the largest survivor below it
NO_COLLAPSE = "no collapse up to the maximum"
COLLAPSE_AT_MINIMUM = "collapse at the minimum"
BUDGET = "run budget exhausted"
# the rounding of the values stopped the bisection short of the tolerance (only a tolerance
# below FINEST_TOLERANCE, which a config cannot give)
ROUNDING = "bracketed as narrow as the rounding allows, wider than the tolerance"
SIGNIFICANT_DIGITS = 4  # values run are rounded to this (a 2 % bracket needs 3)
# the narrowest bracket every search reaches: one unit in the last digit at 1.000...
FINEST_TOLERANCE = 10.0 ** (1 - SIGNIFICANT_DIGITS)


# --- config values as the config's YAML schema types them (here: grid imports this module) ---
# The kit also reads numeric text ("1.0e9") as a number, a whole float (3.0) as a count and a
# null as an absent key, for scripts and YAML 1.1; a config value keeps its YAML type, as the
# case ids and the scenes have it, so typed and checked refuse those.
def typed(f: Field, value, where: str):
    """``f.check(value, where)`` as a strict field: a config number must be written as one
    (not as text), an integer as an integer (not 3.0)."""
    return dataclasses.replace(f, strict=True).check(value, where)


def checked(spec: Spec, mapping, where: str, nullable=()) -> dict:
    """``spec.check(mapping, where)`` (defaults filled in), each given value first checked by
    :func:`typed`; a null stands for an absent key only for the ``nullable`` keys."""
    spec.check_keys(mapping, where)
    for f in spec.fields:  # in the rows' order, as the kit checks them
        if f.key in mapping and (mapping[f.key] is not None or f.key not in nullable):
            typed(f, mapping[f.key], f"{where}.{f.key}" if where else f.key)
    return spec.check(mapping, where)


@dataclass(frozen=True)
class SearchSettings:
    """How to search one system (config ``search:`` of a study; units of the parameter)."""

    parameter: str = "pga"  # the swept intensity measure (a study parameter)
    start: float = 1.0  # first value of the hunt
    # hunt: each value this times the last (down when start collapses); 1.8 < 1.02**32, so
    # five bisections narrow a hunt step to a 2 % bracket (2.0 would need six)
    factor: float = 1.8
    # bracket: smallest collapse / largest survivor below it - 1 (>= FINEST_TOLERANCE)
    tolerance: float = 0.02
    minimum: float = 0.125  # a collapse at start hunts down, at most to here
    maximum: float = 64.0  # no collapse up to here: the threshold lies above it
    fill: int = 3  # runs filling the widest gaps: below the threshold, above, below, ...
    max_runs: int = 40  # the search stops here whatever it found
    # its file keeps the runs' histories (the cubes' figures draw them), else measures only
    histories: bool = True

    @classmethod
    def from_config(cls, spec, where: str, parameters=None) -> "SearchSettings":
        """From a study's ``search:`` mapping (:data:`SEARCH`; ``parameters``: those it may
        search, default :data:`SEARCH_PARAMETERS`); an InputError names the field and the fix."""
        rows = SEARCH
        if parameters is not None and tuple(parameters) != SEARCH_PARAMETERS:
            rows = SEARCH.replace(
                dataclasses.replace(SEARCH["parameter"], choices=tuple(parameters))
            )
        values = checked(rows, spec, where)
        # across the fields: the hunt, the bracket and the run budget must fit together
        problem = None
        if values["factor"] <= 1.0 + values["tolerance"]:
            key, problem = "factor", f"{values['factor']:g} must exceed 1 + tolerance"
            fix = SEARCH["factor"].hint
        elif not values["minimum"] <= values["start"] <= values["maximum"]:
            key, problem = (
                "start",
                (
                    f"{values['start']:g} outside minimum ... maximum "
                    f"({values['minimum']:g} ... {values['maximum']:g})"
                ),
            )
            fix = "start inside the range"
        elif values["max_runs"] < _runs_needed(values):
            key, problem = (
                "max_runs",
                (
                    f"{values['max_runs']} runs cannot hunt over "
                    f"{values['minimum']:g} ... {values['maximum']:g} and bisect to the tolerance"
                ),
            )
            fix = f"allow at least {_runs_needed(values)} runs"
        if problem:
            raise InputError(f"{where}.{key}", problem, fix)
        return cls(**values)


# parameters a threshold search may sweep: the intensity measures of the excitation
SEARCH_PARAMETERS = ("pga", "pga_scale", "amplitude")
_D = SearchSettings  # the defaults
# a study's search: (config ``search:``), one row per setting of SearchSettings
SEARCH = Spec(
    (
        Field(
            "parameter",
            "choice",
            choices=SEARCH_PARAMETERS,
            default=_D.parameter,
            doc="the searched parameter (default pga); not in the study's grid or cases",
        ),
        Field("start", range="(0, inf)", default=_D.start, doc="first value of the hunt"),
        Field(
            "factor",
            range="(1, inf)",
            default=_D.factor,
            hint="hunt in steps wider than the bracket, e.g. factor: 1.8",
            doc="hunt step: each value this times the last",
            units="1",
        ),
        Field(
            "tolerance",
            range=f"[{FINEST_TOLERANCE:g}, 1)",
            default=_D.tolerance,
            hint=f"give tolerance >= {FINEST_TOLERANCE:g}, the finest the search can do (values "
            f"run are rounded to {SIGNIFICANT_DIGITS} significant digits), and < 1, e.g. 0.02",
            doc="bracket width: smallest collapse / largest survivor below it - 1; at least "
            f"{FINEST_TOLERANCE:g}, the finest the search's {SIGNIFICANT_DIGITS}-digit values "
            "resolve (stonedem.study.search.FINEST_TOLERANCE)",
            units="1",
        ),
        Field("minimum", range="(0, inf)", default=_D.minimum, doc="lowest value the hunt tries"),
        Field("maximum", range="(0, inf)", default=_D.maximum, doc="highest value the hunt tries"),
        Field(
            "fill",
            "integer",
            range="[0, 100]",
            default=_D.fill,
            doc="runs filling the widest gaps below the threshold",
        ),
        Field("max_runs", "integer", range="[1, 1000]", default=_D.max_runs, doc="runs at most"),
        Field(
            "histories",
            "flag",
            default=_D.histories,
            hint="write histories: false to keep the runs' measures only",
            doc="keep the runs' histories in the search file",
        ),
    )
)
# search_together's runs per search and round
WIDTH = Field("width", "integer", range="[1, inf)", hint="give e.g. width=8")


def _runs_needed(v: dict) -> int:
    """Runs of the longest hunt plus a bisection down to the tolerance."""
    hunt = (
        math.ceil(
            math.log(max(v["maximum"] / v["start"], v["start"] / v["minimum"], 1.0))
            / math.log(v["factor"])
        )
        + 1
    )
    bisect = math.ceil(math.log2(max(math.log(v["factor"]) / math.log1p(v["tolerance"]), 1.0)))
    return hunt + bisect


@dataclass(frozen=True)
class Run:
    value: float
    collapsed: bool
    phase: str  # hunt, bisect or fill


def rounded(value: float) -> float:
    """A value to run: SIGNIFICANT_DIGITS significant digits (readable, stable case ids)."""
    return float(f"{value:.{SIGNIFICANT_DIGITS}g}")


def next_value(runs: list[Run], settings: SearchSettings) -> tuple[float, str] | None:
    """The next (value, phase) to run after ``runs``, or None when the search is done."""
    s = settings
    if len(runs) >= s.max_runs:
        return None
    if not runs:
        return s.start, "hunt"
    done = {r.value for r in runs}
    collapses = [r.value for r in runs if r.collapsed]
    if not collapses:
        top = max(done)
        return None if top >= s.maximum else (min(rounded(top * s.factor), s.maximum), "hunt")
    first = min(collapses)
    below = sorted(r.value for r in runs if not r.collapsed and r.value < first)
    if not below:
        bottom = min(done)
        return None if bottom <= s.minimum else (max(rounded(bottom / s.factor), s.minimum), "hunt")
    lower = below[-1]
    if first / lower - 1.0 > s.tolerance:
        middle = rounded(math.sqrt(lower * first))
        if middle in (lower, first):  # narrower than the rounding: as bracketed as it gets
            return None
        return middle, "bisect"
    n_fill = sum(r.phase == "fill" for r in runs)
    if n_fill >= s.fill:
        return None
    # fill the widest gap (ratio) below the threshold (a collapse there lowers it), and every
    # second fill the widest above it (a survival there is a resurrection); the higher gap on
    # a tie; a side without a gap wider than the tolerance gives way to the other
    above = sorted(v for v in done if v > first)
    sides = [_widest_gap(below, s.tolerance), _widest_gap([first] + above, s.tolerance)]
    if n_fill % 2:
        sides.reverse()
    gap = sides[0] or sides[1]
    return None if gap is None else (rounded(math.sqrt(gap[0] * gap[1])), "fill")


def _widest_gap(values: list[float], tolerance: float) -> tuple[float, float] | None:
    """(low, high) of the widest ratio between consecutive values, if wider than 1 + tolerance."""
    if len(values) < 2:
        return None
    ratio, high, low = max((b / a, b, a) for a, b in zip(values, values[1:]))
    return (low, high) if ratio - 1.0 > tolerance else None


def search(
    run: Callable[[float, str], bool], settings: SearchSettings, runs: list[Run] | None = None
) -> list[Run]:
    """Run the search: ``run(value, phase)`` simulates one case and returns whether it
    collapsed. ``runs``: runs already made (a resumed search). Returns every run, in order."""
    runs = list(runs or [])
    while (step := next_value(runs, settings)) is not None:
        value, phase = step
        runs.append(Run(value, bool(run(value, phase)), phase))
    return runs


def replay(
    outcomes: dict[float, bool], settings: SearchSettings
) -> tuple[list[Run], tuple[float, str] | None]:
    """The runs :func:`search` makes when each value's outcome is ``outcomes[value]``, as far
    as they are known, and the next (value, phase) it needs (None: the search is done)."""
    runs: list[Run] = []
    while (step := next_value(runs, settings)) is not None and step[0] in outcomes:
        runs.append(Run(step[0], outcomes[step[0]], step[1]))
    return runs, step


def speculative_values(
    outcomes: dict[float, bool], settings: SearchSettings, width: int
) -> list[tuple[float, str]]:
    """Up to ``width`` (value, phase) the search may need next: the rule's next value, then
    breadth first the values it would ask for after each outcome of those (known values take
    their known outcome). Empty when the search is done."""
    runs, step = replay(outcomes, settings)
    chosen: dict[float, str] = {}
    queue = [runs]
    while queue and len(chosen) < width:
        runs = queue.pop(0)
        step = next_value(runs, settings)
        if step is None:
            continue
        value, phase = step
        if value in outcomes:
            queue.append(runs + [Run(value, outcomes[value], phase)])
            continue
        chosen.setdefault(value, phase)
        queue += [runs + [Run(value, collapsed, phase)] for collapsed in (False, True)]
    return list(chosen.items())


def search_together(
    run_many: Callable[[list[tuple[int, float, str]]], list[bool]],
    settings: list[SearchSettings],
    width: int = 8,
) -> tuple[list[list[Run]], int]:
    """Many searches in rounds (:func:`speculative_values`, ``width`` runs per search and
    round): ``run_many([(search, value, phase), ...])`` simulates them all at once and returns
    whether each collapsed. Returns each search's runs, as :func:`search` makes them, and the
    number of rounds."""
    typed(WIDTH, width, "width")
    outcomes: list[dict[float, bool]] = [{} for _ in settings]
    rounds = 0
    while True:
        requests = [
            (i, value, phase)
            for i, s in enumerate(settings)
            for value, phase in speculative_values(outcomes[i], s, width)
        ]
        if not requests:
            break
        rounds += 1
        for (i, value, _), collapsed in zip(requests, run_many(requests)):
            outcomes[i][value] = bool(collapsed)
    return [replay(known, s)[0] for known, s in zip(outcomes, settings)], rounds


def bracket(runs: list[Run]) -> dict:
    """The threshold the runs bracket, whichever way they were chosen (a search, a grid).

    lower: largest survivor below the smallest collapse (NaN: none); upper: the smallest
    collapse (NaN: none); width: upper / lower - 1; resurrections: survivors above the
    smallest collapse (collapse not monotonic on the runs when any).
    """
    collapses = sorted(r.value for r in runs if r.collapsed)
    upper = collapses[0] if collapses else math.nan
    survivors = sorted(r.value for r in runs if not r.collapsed)
    below = [v for v in survivors if not v > upper] if collapses else survivors
    lower = below[-1] if below else math.nan
    resurrections = [v for v in survivors if v > upper]
    return {
        "lower": lower,
        "upper": upper,
        "width": upper / lower - 1.0 if below and collapses else math.nan,
        "resurrections": resurrections,
        "monotonic": not resurrections,
    }


def summary(runs: list[Run], settings: SearchSettings) -> dict:
    """:func:`bracket` of a search's runs, their number and how the search ended."""
    result = bracket(runs)
    if math.isnan(result["upper"]):
        status = (
            NO_COLLAPSE if max((r.value for r in runs), default=0.0) >= settings.maximum else BUDGET
        )
    elif math.isnan(result["lower"]):
        status = COLLAPSE_AT_MINIMUM if result["upper"] <= settings.minimum else BUDGET
    elif result["width"] <= settings.tolerance:
        status = BRACKETED
    elif next_value(runs, settings) is None and len(runs) < settings.max_runs:
        status = ROUNDING  # never "bracketed" wider than asked
    else:
        status = BUDGET
    return {**result, "n_runs": len(runs), "status": status}
