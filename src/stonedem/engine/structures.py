"""Scene builders: multi-drum columns, colonnades with epistyles, two-tier colonnades.

Plain Python returning body lists in the scene format (:mod:`stonedem.engine.scene`); nothing here
simulates. Bodies rest exactly touching: the base's top is at y = 0, each drum's bottom
is the previous drum's top. Geometry follows the thesis: 6 m x 1 m columns (chapter 6),
tapered drums at constant total mass (6.3.2), capitals and epistyles of the input file of
Fig. 4.6, the epistyle types a-d of Table 7.2 (chapter 7), and an upper row of columns on
the epistyle of a lower one (7.9).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

from stonedem.errors import InputError
from stonedem.io.spec import REQUIRED, Field, Spec, got

EPISTYLE_TYPES = ("a", "b", "c", "d", "per_span")
# a structure of more bodies is refused before it is built (stonedem.engine.scene.MAX_BODIES is the
# scene's limit; the pair memory grows as n^2)
MAX_COUNT = 1000


def _box(name, width, height, cx, y_bottom, density, **extra):
    return {
        "name": name,
        "box": {"width": width, "height": height, "center": [cx, y_bottom + height / 2]},
        "density": density,
        **extra,
    }


def base_body(width, height=0.5, center_x=0.0):
    """The driven base: a width x height box whose top face is at y = 0."""
    width, height = float(width), float(height)
    return {
        "name": "base",
        "box": {
            "width": width,
            "height": height,
            "center": [center_x, -height / 2],
        },
        "density": 2700.0,
        "driven": True,
        "role": "base",
    }


def shaft_widths(taper, width):
    """(bottom, top) width [m] of a shaft of mean width ``width`` and ratio W_b/W_t = taper.

    thesis 6.3.2: the total mass is that of the untapered column, so W_b + W_t = 2 width.
    """
    top = 2.0 * width / (1.0 + taper)
    return taper * top, top


def column(
    n_drums,
    height=6.0,
    width=1.0,
    density=2000.0,
    taper=1.0,
    capital=None,
    x=0.0,
    column_index=0,
    y0=0.0,
    prefix="",
):
    """The drums (and capital) of one column centred at x, standing on y = y0.

    height: shaft height, split into n_drums equal drums [m]; width: mean shaft width [m]
    taper: bottom / top width of the shaft (1 = rectangular drums); capital: None or
    {height, width} [m], a box on the top drum.
    """
    bottom, top = shaft_widths(taper, width)
    drum_h = height / n_drums
    bodies = []
    for k in range(n_drums):
        yb = y0 + k * drum_h
        wb = bottom + (top - bottom) * k / n_drums
        wt = bottom + (top - bottom) * (k + 1) / n_drums
        name = f"{prefix}c{column_index}_d{k}"
        extra = {"role": "drum", "column": column_index}
        if taper == 1.0:
            bodies.append(_box(name, width, drum_h, x, yb, density, **extra))
        else:
            vertices = [
                [x - wb / 2, yb],
                [x + wb / 2, yb],
                [x + wt / 2, yb + drum_h],
                [x - wt / 2, yb + drum_h],
            ]
            bodies.append(
                {"name": name, "polygon": {"vertices": vertices}, "density": density, **extra}
            )
    if capital is not None:
        ch, cw = capital.get("height", 0.6), capital.get("width", 1.4)
        bodies.append(
            _box(
                f"{prefix}c{column_index}_cap",
                cw,
                ch,
                x,
                y0 + height,
                density,
                role="capital",
                column=column_index,
            )
        )
    return bodies


def standalone_column(
    n_drums,
    height=6.0,
    width=1.0,
    density=2000.0,
    taper=1.0,
    capital=None,
    base_width=4.0,
    tilt=0.0,
):
    """Base + one column (thesis chapter 6), leaning by ``tilt`` [rad] toward +x with its seat.

    A leaning column stands square on the base's top face, which is inclined at ``tilt`` (a
    differential settlement of the foundation, or a base slope: for a lone column the same
    scene): every body turns clockwise by ``tilt`` about the centre of that face (:func:`lean`).
    """
    bodies = [base_body(base_width)] + column(n_drums, height, width, density, taper, capital)
    if tilt == 0.0:
        return bodies
    own = column_alpha(bodies[1:])
    if abs(tilt) >= own:
        raise InputError(
            "structure.tilt",
            f"|{tilt:g}| rad reaches the column's own {own:.4g} rad (atan(b/h) of a plain "
            "shaft): its centre of mass is past its toe and it cannot stand",
            f"give |tilt| < {own:.4g} rad",
        )
    return lean(bodies, tilt)


def column_alpha(bodies) -> float:
    """The angle [rad] an upright column (its bodies, standing on y = 0, centred on x = 0, of one
    density) leans to before its centre of mass passes its toe: atan((b_0 / 2) / y_c), b_0 the
    bottom width of its lowest body, y_c the height of its centre of mass. atan(b/h) (thesis
    Eq. 6.2) for a rectangular shaft; a capital raises y_c, a taper widens b_0."""
    area = moment = 0.0
    for body in bodies:
        v = _vertices(body)
        for (x0, y0), (x1, y1) in zip(v, v[1:] + v[:1]):
            cross = x0 * y1 - x1 * y0
            area += cross / 2.0
            moment += cross * (y0 + y1) / 6.0
    low = _vertices(bodies[0])
    bottom = min(y for _, y in low)
    xs = [x for x, y in low if y == bottom]
    return math.atan2((max(xs) - min(xs)) / 2.0, moment / area)


def lean(bodies, tilt, pivot=(0.0, 0.0)) -> list[dict]:
    """Bodies turned clockwise by ``tilt`` [rad] (leaning toward +x) about ``pivot`` [m], as
    polygons; the free ones carry ``lean: tilt`` (their upright frame, stonedem.engine.scene)."""
    c, s = math.cos(tilt), math.sin(tilt)
    px, py = pivot
    out = []
    for body in bodies:
        turned = {k: v for k, v in body.items() if k != "box"}
        turned["polygon"] = {
            "vertices": [
                [px + c * (x - px) + s * (y - py), py - s * (x - px) + c * (y - py)]
                for x, y in _vertices(body)
            ]
        }
        if not body.get("driven", False):
            turned["lean"] = tilt
        out.append(turned)
    return out


def _top(bodies):
    return max(max(v[1] for v in _vertices(b)) for b in bodies)


def _vertices(body):
    if "polygon" in body:
        return body["polygon"]["vertices"]
    w, h = body["box"]["width"], body["box"]["height"]
    cx, cy = body["box"]["center"]
    return [
        [cx - w / 2, cy - h / 2],
        [cx + w / 2, cy - h / 2],
        [cx + w / 2, cy + h / 2],
        [cx - w / 2, cy + h / 2],
    ]


def colonnade_row(
    n_columns=3,
    n_drums=1,
    height=6.0,
    width=1.0,
    clear_distance=2.0,
    epistyle_type="a",
    epistyle_height=0.8,
    epistyle_density=None,
    density=2000.0,
    taper=1.0,
    capital=None,
    y0=0.0,
    prefix="",
    column_offset=0,
    spacing=None,
):
    """Columns and epistyles of one row, centred on x = 0, standing on y = y0 (no base).

    Columns are spaced by the clear distance between shaft faces at their base plus the
    base width (``spacing`` overrides). Epistyle types (thesis Table 7.2):
    a: one epistyle over the full width of the external columns (outer edge to outer edge);
    b: two epistyles over that width, jointed over the centre line of the middle column
       (column n // 2);
    c: one epistyle from centre line to centre line of the external columns;
    d: two epistyles between those centre lines, jointed as in b;
    per_span: one epistyle per span, centre line to centre line (the input file of Fig. 4.6).
    """
    if n_columns * n_drums > MAX_COUNT:
        raise InputError(
            "structure.n_columns",
            f"{n_columns} columns x {n_drums} drums exceed {MAX_COUNT} bodies",
            "use fewer columns or drums",
        )
    epistyle_density = epistyle_density if epistyle_density is not None else density
    bottom, top = shaft_widths(taper, width)
    spacing = spacing if spacing is not None else bottom + clear_distance
    xs = [(k - (n_columns - 1) / 2.0) * spacing for k in range(n_columns)]
    bodies = []
    for k, x in enumerate(xs):
        bodies += column(
            n_drums, height, width, density, taper, capital, x, column_offset + k, y0, prefix
        )
    top_width = capital["width"] if capital else top
    y_top = y0 + height + (capital["height"] if capital else 0.0)
    outer = (xs[0] - top_width / 2, xs[-1] + top_width / 2)
    centres = (xs[0], xs[-1])
    joint = xs[n_columns // 2]
    if epistyle_type == "a":
        spans = [outer]
    elif epistyle_type == "c":
        spans = [centres]
    elif epistyle_type == "b":
        spans = [(outer[0], joint), (joint, outer[1])]
    elif epistyle_type == "d":
        spans = [(centres[0], joint), (joint, centres[1])]
    else:
        spans = list(zip(xs[:-1], xs[1:]))
    if n_columns == 1:
        spans = [outer]
    for i, (x0, x1) in enumerate(spans):
        if x1 - x0 <= 0:
            raise InputError(
                "structure.epistyle_type",
                f"type {epistyle_type} needs more columns",
                "use type a or c, or more columns",
            )
        bodies.append(
            _box(
                f"{prefix}e{i}",
                x1 - x0,
                epistyle_height,
                (x0 + x1) / 2,
                y_top,
                epistyle_density,
                role="epistyle",
            )
        )
    return bodies


def colonnade(
    n_columns=3,
    n_drums=1,
    height=6.0,
    width=1.0,
    clear_distance=2.0,
    epistyle_type="a",
    epistyle_height=0.8,
    epistyle_density=None,
    density=2000.0,
    taper=1.0,
    capital=None,
    base_margin=2.0,
):
    """Base + a row of columns with epistyles (thesis chapter 7)."""
    row = colonnade_row(
        n_columns,
        n_drums,
        height,
        width,
        clear_distance,
        epistyle_type,
        epistyle_height,
        epistyle_density,
        density,
        taper,
        capital,
    )
    xs = [x for b in row for x, _ in _vertices(b)]
    span = max(xs) - min(xs)
    return [base_body(span + 2 * base_margin)] + row


def two_tier_colonnade(lower=None, upper=None, base_margin=2.0):
    """Base + a lower row with a continuous epistyle carrying an upper row of smaller columns
    (thesis 7.9).

    lower, upper: colonnade keyword arguments of each row; the upper columns stand on the
    lower epistyle above the lower columns (same spacing) and carry their own epistyle.
    Defaults: lower 3 columns of 6 m x 1 m with a type a epistyle; upper 3 columns of
    3 m x 0.6 m with a type a epistyle of 0.4 m.
    """
    lower = {"n_columns": 3, "epistyle_type": "a", **(lower or {})}
    upper = {
        "n_columns": lower["n_columns"],
        "height": 3.0,
        "width": 0.6,
        "epistyle_height": 0.4,
        "epistyle_type": "a",
        **(upper or {}),
    }
    if upper["n_columns"] != lower["n_columns"]:
        raise InputError(
            "structure.upper.n_columns",
            "the upper row stands above the lower columns",
            "give the same n_columns for both rows",
        )
    if lower["epistyle_type"] not in ("a", "c"):
        raise InputError(
            "structure.lower.epistyle_type",
            "the upper row needs one continuous epistyle",
            "use type a or c for the lower row",
        )
    low = colonnade_row(**lower)
    low_cols = sorted(
        {
            b["box"]["center"][0] if "box" in b else _vertices(b)[0][0]
            for b in low
            if b.get("role") == "drum" and b["name"].endswith("_d0")
        }
    )
    spacing = (low_cols[1] - low_cols[0]) if len(low_cols) > 1 else 1.0
    upper.setdefault("clear_distance", max(spacing - upper.get("width", 0.6), 1e-3))
    up = colonnade_row(
        **upper, y0=_top(low), prefix="t1_", column_offset=lower["n_columns"], spacing=spacing
    )
    for body in up:
        body["tier"] = 1
    xs = [x for b in low + up for x, _ in _vertices(b)]
    return [base_body(max(xs) - min(xs) + 2 * base_margin)] + low + up


# the keys of a structure: what each builder takes, with units and ranges
N_DRUMS = Field("n_drums", "integer", "", f"[1, {MAX_COUNT}]", 1, doc="drums per column")
CAPITAL = Spec(
    (
        Field("height", "number", "m", "(0, inf)", 0.6, doc="capital height"),
        Field("width", "number", "m", "(0, inf)", 1.4, doc="capital width"),
    )
)
COLUMN_KEYS = (
    Field("height", "number", "m", "(0, inf)", 6.0, doc="shaft height, split into equal drums"),
    Field("width", "number", "m", "(0, inf)", 1.0, doc="mean shaft width"),
    Field("density", "number", "kg m-3", "(0, inf)", 2000.0, doc="stone density"),
    Field("taper", "number", "1", "(0, inf)", 1.0, doc="bottom / top shaft width"),
    Field("capital", "mapping", spec=CAPITAL, doc="a box on the top drum {height, width}"),
)
ROW_KEYS = (
    Field("n_columns", "integer", "", f"[1, {MAX_COUNT}]", 3, doc="columns in the row"),
    N_DRUMS,
    *COLUMN_KEYS[:2],
    Field("clear_distance", "number", "m", "(0, inf)", 2.0, doc="between shaft faces at the base"),
    Field(
        "epistyle_type",
        "choice",
        choices=EPISTYLE_TYPES,
        default="a",
        hint="thesis Table 7.2",
        doc="epistyle layout (thesis Table 7.2)",
    ),
    Field("epistyle_height", "number", "m", "(0, inf)", 0.8, doc="epistyle height"),
    Field("epistyle_density", "number", "kg m-3", "(0, inf)", doc="default: density"),
    *COLUMN_KEYS[2:],
)
BASE_MARGIN = Field("base_margin", "number", "m", "(0, inf)", 2.0, doc="base beyond the row")
TILT = Field(
    "tilt",
    "number",
    "rad",
    "(-1.5, 1.5)",
    0.0,
    hint="give the lean in rad, positive toward +x, below the column's atan(b/h)",
    doc="the column leans as a whole with its seat, the base's top face inclined at this "
    "angle (differential settlement; for a lone column the same as a base slope), positive "
    "toward +x; |tilt| < atan(b/h) and tan|tilt| < friction",
)
# a row of a two-tier colonnade: only the keys given (the builder has its own per-tier defaults)
TIER = Spec(tuple(dataclasses.replace(f, default=None) for f in ROW_KEYS))


@dataclass(frozen=True)
class Structure:
    """One kind of ``structure:``: its builder and the keys it takes."""

    build: Callable  # checked keys -> body list in the scene format
    spec: Spec
    doc: str


def _tiers(lower, upper, base_margin):
    given = {}
    for name, tier in (("lower", lower), ("upper", upper)):
        given[name] = {
            k: v for k, v in TIER.check(tier, f"structure.{name}").items() if v is not None
        }
    return two_tier_colonnade(given["lower"], given["upper"], base_margin)


BUILDERS = {
    "column": Structure(
        lambda v: standalone_column(**v),
        Spec(
            (
                Field(
                    "n_drums", "integer", "", f"[1, {MAX_COUNT}]", REQUIRED, "give e.g. n_drums: 4"
                ),
                *COLUMN_KEYS,
                Field("base_width", "number", "m", "(0, inf)", 4.0, doc="width of the driven base"),
                TILT,
            )
        ),
        "base + one column (thesis chapter 6)",
    ),
    "colonnade": Structure(
        lambda v: colonnade(**v),
        Spec((*ROW_KEYS, BASE_MARGIN)),
        "base + a row of columns with epistyles (thesis chapter 7)",
    ),
    "two_tier_colonnade": Structure(
        lambda v: _tiers(**v),
        Spec(
            (
                Field("lower", "mapping", spec=TIER, doc="the lower row's colonnade keys"),
                Field("upper", "mapping", spec=TIER, doc="the upper row's colonnade keys"),
                BASE_MARGIN,
            )
        ),
        "base + a lower row carrying an upper row (thesis 7.9)",
    ),
}
KIND = Field(
    "kind",
    "choice",
    choices=tuple(BUILDERS),
    default=REQUIRED,
    hint=f"use one of {', '.join(BUILDERS)}",
)


def build_structure(spec: dict) -> list[dict]:
    """Bodies of ``{kind: column | colonnade | two_tier_colonnade, ...its keys}``."""
    if not isinstance(spec, dict):
        raise InputError(
            "structure",
            f"expected a mapping, got {got(spec)}",
            "write structure: {kind: column, n_drums: 4}",
        )
    if "kind" not in spec:
        raise InputError("structure.kind", "missing", KIND.hint)
    row = BUILDERS[KIND.check(spec["kind"], "structure.kind")]
    if "tilt" in spec and "tilt" not in row.spec.keys:
        raise InputError(
            "structure.tilt",
            f"a {spec['kind']} does not lean as a whole here (its epistyles rest on every "
            "column; a settlement tilts them one by one)",
            "drop tilt:, or use kind: column",
        )
    values = Spec((KIND, *row.spec.fields)).check(spec, "structure")
    del values["kind"]
    return row.build(values)
