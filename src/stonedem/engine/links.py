"""Shear links (dowels, empolia) between stacked bodies: the scene keys, their presets and
the geometry the kernel reads (:mod:`stonedem.kernels.links`, thesis 8.3).

A scene lists them as ``links: [{bodies: [lower, upper], kind: titanium, at: 0.0}, ...]``;
a built column takes ``structure.links: {kind: titanium, joints: [1, 2]}``, expanded here
into one link per drum-drum joint. A link sits on the lower body's top face, ``at`` metres
along it from the face's centre, as built (before any initial tilt).

The presets' numbers are illustrative orders of magnitude, not sourced measurements: a
titanium dowel as in the Acropolis restorations (a ~20 mm bar set in marble, grouted, with
~0.5 mm clearance; its shear capacity ~300 MPa x 3e-4 m2 ~ 90 kN, taken as 50 kN for the
bar's bending in its holes) and a wooden empolion (a cedar or olive block in square
sockets with a central pin: ~5 kN, soft, loose). Neither is bonded to the stone, so their
pull-out resistance is 0: the drum lifts off the link, which leaves its hole once the
opening exceeds the embedment. ``kind: custom`` gives every number explicitly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stonedem.errors import InputError
from stonedem.io.spec import REQUIRED, Derived, Field, Spec, show
from stonedem.kernels import step

# kind -> (stiffness [N m-1], capacity [N], ultimate_slip [m], gap [m], pullout [N],
# embedment [m]); illustrative (module docstring)
PRESETS = {
    "titanium": (5.0e7, 5.0e4, 0.02, 5.0e-4, 0.0, 0.1),
    "wood": (2.0e6, 5.0e3, 0.01, 2.0e-3, 0.0, 0.05),
}
KINDS = (*PRESETS, "custom")
NUMBERS = ("stiffness", "capacity", "ultimate_slip", "gap", "pullout", "embedment")


def _preset(key: str):
    index = NUMBERS.index(key)
    return lambda v: PRESETS[v["kind"]][index] if v["kind"] in PRESETS else None


def _number(key, units, range_, doc):
    return Field(
        key,
        "number",
        units,
        range_,
        Derived("the kind's preset (custom: required)", _preset(key)),
        f"give {key} in {units}, in {range_}",
        doc=doc,
    )


KIND = Field(
    "kind",
    "choice",
    choices=KINDS,
    default="titanium",
    hint=f"use one of {', '.join(KINDS)}",
    doc="preset of the numbers below (illustrative, stonedem.engine.links); custom: give them all",
)
AT = Field(
    "at",
    "number",
    "m",
    "(-inf, inf)",
    0.0,
    "give the offset in m, within half the face's width",
    doc="offset along the interface from the lower body's top-face centre",
)
LINK_NUMBERS = (
    _number("stiffness", "N m-1", "(0, 1e12]", "shear (and pull-out) stiffness"),
    _number("capacity", "N", "[0, 1e9]", "shear capacity: the force at which it yields"),
    _number("ultimate_slip", "m", "(0, 1]", "total slip at which it breaks for good"),
    _number("gap", "m", "[0, 0.1]", "clearance in the hole before the shear engages"),
    _number("pullout", "N", "[0, 1e9]", "axial (pull-out) resistance, 0: none"),
    _number("embedment", "m", "(0, 1]", "opening at which it is pulled out for good"),
)
LINK = Spec(
    (
        Field("bodies", "list", default=REQUIRED, hint="write bodies: [lower, upper]"),
        KIND,
        AT,
        *LINK_NUMBERS,
    )
)
STRUCTURE_LINKS = Spec(
    (
        Field(
            "kind",
            "choice",
            choices=("none", *KINDS),
            default=REQUIRED,
            hint=f"use one of none, {', '.join(KINDS)}",
            doc="links at the column's joints (none: no links)",
        ),
        AT,
        Field(
            "joints",
            "list",
            doc="joints linked, j between drum j-1 and drum j (default: every drum-drum joint)",
            hint="write joints: [1, 2]",
        ),
        *LINK_NUMBERS,
    )
)


@dataclass(frozen=True)
class Link:
    """One checked link: its bodies' indices and its numbers (SI units)."""

    lower: int
    upper: int
    kind: str
    at: float
    stiffness: float
    capacity: float
    ultimate_slip: float
    gap: float
    pullout: float
    embedment: float

    def description(self, names) -> dict:
        return {
            "bodies": [names[self.lower], names[self.upper]],
            "kind": self.kind,
            "at": self.at,
            **{key: getattr(self, key) for key in NUMBERS},
        }


def _checked_numbers(values: dict, where: str) -> dict:
    if values["kind"] == "custom":
        for key in NUMBERS:
            if values[key] is None:
                raise InputError(f"{where}.{key}", "missing", f"kind custom: give {key}")
    if values["ultimate_slip"] <= values["gap"]:
        raise InputError(
            f"{where}.ultimate_slip",
            f"{values['ultimate_slip']:g} m is not beyond the gap {values['gap']:g} m: "
            "it would break before it engages",
            "give an ultimate slip larger than the gap",
        )
    return values


def top_face(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(centre [m], unit tangent, length [m]) of a convex polygon's top face: the edge whose
    outward normal points most upward (counter-clockwise vertices: it runs right to left, the
    tangent is turned to run left to right)."""
    nxt = np.roll(vertices, -1, axis=0)
    edge = nxt - vertices
    length = np.hypot(edge[:, 0], edge[:, 1])
    up = -edge[:, 0] / np.maximum(length, 1e-300)  # outward normal's y of a ccw edge
    k = int(np.argmax(up))
    tangent = -edge[k] / length[k]
    return 0.5 * (vertices[k] + nxt[k]), tangent, float(length[k])


def check_link(values: dict, bodies, where: str) -> Link:
    """A :class:`Link` of checked ``values`` (:data:`LINK`) on the scene's bodies, or an
    InputError: unknown or equal bodies, a driven upper body, an anchor beyond the lower
    body's top face, an upper body that does not rest on that face at the anchor."""
    names = [b.name for b in bodies]
    pair = values["bodies"]
    if len(pair) != 2 or not all(isinstance(n, str) and n in names for n in pair):
        raise InputError(
            f"{where}.bodies",
            f"expected two body names [lower, upper], got {show(pair)}",
            f"known bodies: {', '.join(names[:8])}{', ...' if len(names) > 8 else ''}",
        )
    lower, upper = names.index(pair[0]), names.index(pair[1])
    if lower == upper:
        raise InputError(f"{where}.bodies", "links a body to itself", "name two stacked bodies")
    if bodies[upper].driven:
        raise InputError(
            f"{where}.bodies",
            f"the upper body {pair[1]} is driven",
            "list the lower body first: bodies: [lower, upper]",
        )
    centre, tangent, width = top_face(bodies[lower].vertices)
    if abs(values["at"]) > 0.5 * width:
        raise InputError(
            f"{where}.at",
            f"{values['at']:g} m is outside the face of {pair[0]} (half width {0.5 * width:g} m)",
            f"give |at| <= {0.5 * width:g} m",
        )
    point = centre + values["at"] * tangent
    if not _on_bottom(bodies[upper].vertices, point, tangent, width):
        raise InputError(
            f"{where}.bodies",
            f"{pair[1]} does not rest on the top face of {pair[0]} at the link "
            f"({point[0]:.4g}, {point[1]:.4g}) m: they are not stacked there",
            "link a body to the one it stands on, at a point of their common face",
        )
    return Link(lower, upper, values["kind"], values["at"], *(values[k] for k in NUMBERS))


def _on_bottom(vertices, point, tangent, width) -> bool:
    """Whether ``point`` lies on the polygon's bottom face, parallel to ``tangent``."""
    nxt = np.roll(vertices, -1, axis=0)
    tol = 1e-6 * max(width, float(np.ptp(vertices[:, 0])))
    normal = np.array([-tangent[1], tangent[0]])
    for p, q in zip(vertices, nxt):
        edge = q - p
        length = float(np.hypot(*edge))
        if length == 0.0 or abs(edge @ normal) > 1e-9 * length:
            continue  # not parallel to the face
        if abs((point - p) @ normal) > tol:
            continue
        along = (point - p) @ edge / length
        if -tol <= along <= length + tol:
            return True
    return False


def scene_links(items: list, structure_links, body_specs: list, bodies) -> tuple:
    """The scene's links: ``structure.links`` expanded over the built column's joints, then
    the ``links:`` list; each checked (:func:`check_link`)."""
    out = []
    if structure_links is not None:
        out += structure_link_values(structure_links, body_specs)
    for i, item in enumerate(items):
        where = f"links[{i}]"
        out.append((_checked_numbers(LINK.check(item, where), where), where))
    return tuple(check_link(values, bodies, where) for values, where in out)


def structure_link_values(spec, body_specs: list) -> list:
    """(values, where) of each link ``structure.links`` puts on a built structure: one per
    joint j of each column, between its drums j-1 and j."""
    where = "structure.links"
    values = STRUCTURE_LINKS.check(spec, where)
    if values["kind"] == "none":
        given = [k for k in ("joints", *NUMBERS) if spec.get(k) is not None]
        if given or spec.get("at") is not None:
            raise InputError(
                where,
                f"kind none takes no other keys, got {', '.join(given or ['at'])}",
                "remove them, or give a link kind",
            )
        return []
    values = _checked_numbers(values, where)
    names = [b.get("name") for b in body_specs]
    drums = [n for n, b in zip(names, body_specs) if b.get("role") == "drum"]
    columns: dict = {}
    for name in drums:
        stem, _, k = name.rpartition("_d")
        columns.setdefault(stem, []).append(int(k))
    n_drums = max((len(v) for v in columns.values()), default=0)
    joints = values["joints"]
    if joints is None:
        joints = list(range(1, n_drums))
    for i, j in enumerate(joints):
        if isinstance(j, bool) or not isinstance(j, int) or not 1 <= j < n_drums:
            raise InputError(
                f"{where}.joints[{i}]",
                f"{show(j)} is not a drum-drum joint of a {n_drums}-drum column",
                f"give joints between 1 and {n_drums - 1}" if n_drums > 1 else "use 2+ drums",
            )
    if not joints:
        raise InputError(where, "the column has no drum-drum joint", "use n_drums >= 2")
    out = []
    link = {k: values[k] for k in ("kind", "at", *NUMBERS)}
    for stem in columns:
        for j in joints:
            pair = [f"{stem}_d{j - 1}", f"{stem}_d{j}"]
            out.append(({**link, "bodies": pair}, f"{where} (joint {j}, {pair[1]})"))
    return out


def anchor_point(scene, link: Link) -> np.ndarray:
    """The link's point as built [m]: ``at`` along the lower body's top face from its centre."""
    centre, tangent, _ = top_face(scene.bodies[link.lower].vertices)
    return centre + link.at * tangent


def link_arrays(scene) -> step.Links:
    """The kernel's :class:`stonedem.kernels.step.Links` of a scene's links: anchors in each
    body's frame (relative to its centroid at rest), the tangent in the lower body's frame."""
    links = getattr(scene, "links", ())
    if not links:
        return step.no_links()
    rows = []
    for link in links:
        lower, upper = scene.bodies[link.lower], scene.bodies[link.upper]
        centre, tangent, _ = top_face(lower.vertices)
        point = centre + link.at * tangent
        pa, pb = point - lower.centroid, point - upper.centroid
        rows.append((*pa, *pb, *tangent, *(getattr(link, k) for k in NUMBERS)))
    table = np.array(rows, dtype=np.float64).T.copy()
    ends = [
        np.array([getattr(link, k) for link in links], dtype=np.int64) for k in ("lower", "upper")
    ]
    return step.Links(*ends, *(np.ascontiguousarray(row) for row in table))
