"""Scene files: YAML or dict -> validated, frozen :class:`Scene` -> read-only kernel arrays.

A scene lists rigid convex polygons (explicit ``box``/``polygon`` bodies and/or a
``structure`` built by :mod:`stonedem.engine.structures`), contact and friction parameters, the base
excitation, solver and output settings. Every field is checked once here, types strictly
(no coercion of a string to a flag or a count), sizes against MAX_BODIES and the mass
range; a bad one raises :class:`stonedem.errors.InputError` naming its dotted path. Defaults:
the point contact law, k_n = 1e11 N/m2 per unit contact length, 5 % of critical damping per
end and a plastic landing, stepped at the stability bound (docs/method/engine.md, "Contact laws");
with ``model: area`` the thesis' k_n = 1e8 N/m2 and c_n = 1e3 N s/m (thesis 3.8, 5.1.2); stone
density 2000 kg/m3 (thesis Fig. 4.6), unit out-of-plane depth.
"""

from __future__ import annotations

import contextvars
import copy
import dataclasses
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from stonedem.engine import geometry
from stonedem.engine.laws import DEFAULT_LAW, LAWS, ContactLaw
from stonedem.errors import InputError
from stonedem.io.spec import REQUIRED, Derived, Field, Spec, exactly_one, got, not_both, show
from stonedem.io.yaml_file import parse_yaml_text, read_yaml_mapping
from stonedem.motion.excitation import BaseMotion, excitation_pair
from stonedem.units import GRAVITY

ROLES = ("base", "drum", "capital", "epistyle", "block")
TILT_PIVOTS = ("bottom_left", "bottom_right", "centroid")
# auto: a point-law scene runs on its contact graph while that holds
# (stonedem.kernels.contact_graph), then on the general loop; general: the general loop from the
# start
KERNELS = ("auto", "general")
MAX_BODY_VERTICES = 24
# a scene of more bodies is refused: the contact memory is n^2 x 20 doubles (160 MB at 1000)
MAX_BODIES = 1000
# masses outside this range are taken for a units mistake (a 1 mm pebble of stone is 1e-6 kg
# per m of depth; 1e9 kg is a 400 000 m3 block); they would also make the step absurd
MIN_MASS = 1e-6
MAX_MASS = 1e9
# corners farther from the origin [m]: at 1e12 m float64 spacing (1e-4 m) outgrows the contact
# overlaps (a block there froze, "stopped at collapse", exit 0); at 1e7 m the run matched x = 0
MAX_COORDINATE = 1e5
# bodies may touch at t = 0 but not overlap by more than this share of the smaller area
INITIAL_OVERLAP_TOLERANCE = 1e-6
MAX_TEXT = 1000  # characters of the scene's name and description (stored in every output)

BOX = Spec(
    (
        Field("width", "number", "m", "(0, inf)", REQUIRED, "give the width in m"),
        Field("height", "number", "m", "(0, inf)", REQUIRED, "give the height in m"),
        Field("center", "numbers", "m", length=2, default=[0.0, 0.0], hint="write center: [x, y]"),
        Field("angle", "number", "rad", default=0.0, doc="rotation about the centre, ccw"),
    )
)
POLYGON = Spec(
    (
        Field(
            "vertices",
            "list",
            "m",
            default=REQUIRED,
            hint="list at least 3 [x, y] corners in order",
            doc=f"3 to {MAX_BODY_VERTICES} [x, y] corners of a convex polygon, in order",
        ),
    )
)
TILT = Spec(
    (
        Field("angle", "number", "rad", default=REQUIRED, hint="give the tilt angle in rad"),
        Field(
            "about",
            "any",
            default="centroid",
            doc="pivot: bottom_left or bottom_right (lean onto that corner), centroid or [x, y]",
        ),
    )
)
BODY = Spec(
    (
        Field("name", "text", limit=200, doc="body name, unique (default: body0, body1, ...)"),
        Field("box", "mapping", spec=BOX, doc="a rectangle"),
        Field("polygon", "mapping", spec=POLYGON, doc="a convex polygon"),
        Field("mass", "number", "kg", "(0, inf)", doc="mass (or density)"),
        Field("density", "number", "kg m-3", "(0, inf)", doc="density (default: the scene's)"),
        Field("driven", "flag", default=False, doc="moves with the base"),
        Field("tilt", "mapping", spec=TILT, doc="initial tilt"),
        Field(
            "lean",
            "number",
            "rad",
            "(-1.5, 1.5)",
            0.0,
            hint="give the lean in rad, positive toward +x",
            doc="the body as given leans by this angle from its upright frame, positive toward "
            "+x (structure.tilt sets it): its critical rotation and support are reckoned upright",
        ),
        Field(
            "velocity",
            "numbers",
            "m s-1, m s-1, rad s-1",
            length=3,
            hint="give [vx, vy, omega] in [m/s, m/s, rad/s]",
            doc="initial velocity",
        ),
        Field("friction", "number", "1", "[0, inf)", doc="friction with its supports"),
        Field(
            "role",
            "choice",
            choices=ROLES,
            default=Derived(
                "base if driven, else block", lambda v: "base" if v["driven"] else "block"
            ),
        ),
        Field("column", "integer", range="[-1, inf)", default=-1, doc="column index, -1: none"),
        Field("tier", "integer", range="[0, inf)", default=0, doc="tier of a two-tier colonnade"),
    ),
    rules=(
        exactly_one("box", "polygon", fix="describe the shape once"),
        not_both("mass", "density"),
    ),
)
INTERFACE = Spec(
    (
        Field("bodies", "list", default=REQUIRED, hint="write bodies: [a, b]"),
        Field("mu", "number", "1", "[0, inf)", REQUIRED, "give the friction coefficient mu"),
    )
)
SOLVER = Spec(
    (
        Field("duration", "number", "s", "(0, inf)", REQUIRED, "give the simulated time in s"),
        Field("dt", "number", "s", "(0, inf)", auto=True, doc="time step (auto: stable bound)"),
        Field(
            "dt_safety",
            "number",
            "1",
            "(0, 1]",
            auto=True,
            hint="use a fraction of the stability limit, e.g. 0.25",
            doc="share of the stability limit (auto: the law's)",
        ),
        Field("stop_on_collapse", "flag", default=True),
        Field("skip_quiet", "flag", default=True, doc="skip a base too quiet to move anything"),
        Field(
            "kernel",
            "choice",
            choices=KERNELS,
            default="auto",
            hint="auto: the contact graph where it holds",
        ),
    )
)
PIVOT = Field("about", "numbers", "m", length=2, hint="write about: [x, y]")
VERTEX = Field("vertex", "numbers", "m", length=2, hint="list numbers in pairs")
OUTPUT = Spec((Field("every", "number", "s", "(0, inf)", 0.001, doc="output interval"),))
SCENE = Spec(
    (
        Field("name", "text", limit=MAX_TEXT, doc="scene name"),
        Field("description", "text", limit=MAX_TEXT, one_line=False, doc="free text"),
        Field(
            "bodies",
            "list",
            default=[],
            hint="write bodies: [{name: block, box: {width: 1, height: 2}}, ...]",
            doc="the bodies (keys: bodies[])",
        ),
        Field("structure", "any", doc="a built structure (stonedem.engine.structures)"),
        Field("depth", "number", "m", "(0, inf)", 1.0, doc="out-of-plane depth"),
        Field("density", "number", "kg m-3", "(0, inf)", 2000.0, doc="default density"),
        Field("gravity", "number", "m s-2", "[0, inf)", GRAVITY, doc="acceleration of gravity"),
        Field("friction", "number", "1", "[0, inf)", 0.5, doc="default friction coefficient"),
        Field(
            "interface_friction",
            "list",
            spec=INTERFACE,
            default=[],
            hint="write interface_friction: [{bodies: [a, b], mu: 0.6}]",
            doc="friction of named pairs",
        ),
        Field(
            "links",
            "list",
            default=[],
            hint="write links: [{bodies: [lower, upper], kind: titanium}]",
            doc="shear links between stacked bodies (keys: links[], stonedem.engine.links)",
        ),
        Field("contact", "any", doc="the contact law: the keys of its row (stonedem.engine.laws)"),
        Field("excitation", "any", doc="the base motion (stonedem.motion.excitation)"),
        Field(
            "solver", "mapping", doc="time stepping (keys: solver., below)"
        ),  # its keys: after the bodies
        Field(
            "output", "mapping", doc="sampling of the histories (keys: output., below)"
        ),  # its keys: after the bodies
    )
)
# provenance: a scene's solver: and output: as given over these (auto stays "auto")
SOLVER_DEFAULTS = {f.key: "auto" if f.auto else f.default_for({}) for f in SOLVER.fields}
SOLVER_DEFAULTS["duration"] = None
OUTPUT_DEFAULTS = OUTPUT.defaults()


@dataclass(frozen=True)
class Body:
    """One rigid body at rest (before any tilt), with its derived mass properties."""

    name: str
    vertices: np.ndarray  # counter-clockwise, world coordinates at rest (n, 2) [m]
    mass: float  # [kg]
    inertia: float  # about the centroid [kg m2]
    driven: bool
    role: str
    column: int  # -1 when not part of a column
    tier: int
    friction: float | None
    tilt_angle: float  # counter-clockwise rotation applied at t = 0 [rad]
    tilt_pivot: np.ndarray  # [m]
    velocity: tuple | None  # (vx [m s-1], vy [m s-1], omega [rad s-1]) or None
    # the vertices as given lean by this angle from the body's upright frame, positive toward
    # +x (clockwise; structure.tilt) [rad]
    lean: float = 0.0

    @property
    def centroid(self) -> np.ndarray:
        return geometry.centroid(self.vertices)


@dataclass(frozen=True)
class Scene:
    """A validated scene: bodies, materials, excitation and settings, all in SI units."""

    bodies: tuple
    contact: ContactLaw
    friction: float
    pair_friction: dict  # {(name_a, name_b): mu}, names sorted
    gravity: float
    depth: float
    horizontal: BaseMotion
    vertical: BaseMotion
    duration: float
    dt: float | None  # None = choose automatically
    dt_safety: float
    stop_on_collapse: bool
    # skip where the base is too quiet to move anything (stonedem.engine.quiet.quiet_steps)
    skip_quiet: bool
    output_every: float
    spec: dict = field(repr=False)  # the fully defaulted input, for provenance
    kernel: str = "auto"  # solver.kernel: KERNELS
    links: tuple = ()  # shear links (stonedem.engine.links.Link)

    @property
    def body_names(self) -> list[str]:
        return [b.name for b in self.bodies]


def load_scene(path: str | Path, *, overrides=None, base_dir: str | Path | None = None) -> Scene:
    """Read a scene YAML file, apply overrides (:func:`apply_overrides`), validate; see
    :func:`scene_from_dict`. Records and other files are looked up from ``base_dir``, by
    default the scene file's folder."""
    path = Path(path)
    spec = read_scene_file(path)
    apply_overrides(spec, overrides)
    return scene_from_dict(spec, base_dir=path.parent if base_dir is None else base_dir)


MAX_SCENE_BYTES = 4_000_000  # ~40 000 bodies; the thesis' two-tier colonnade takes 3 kB


def read_scene_file(path: str | Path) -> dict:
    """The scene mapping of a YAML file, or an InputError naming the file and the fix
    (:func:`stonedem.io.yaml_file.read_yaml_mapping`: kind, size, encoding, nesting)."""
    return read_yaml_mapping(
        path, "a scene file", MAX_SCENE_BYTES, "start with keys such as bodies:, contact:, solver:"
    )


def apply_overrides(spec: dict, overrides) -> None:
    """Set fields of a scene mapping in place: ``overrides`` is a list of ``key=value``
    strings (``stonedem run --set``, values parsed as YAML, :func:`apply_override`) or a
    mapping {dotted key: value} (values used as given); None sets nothing."""
    if overrides is None:
        return
    if isinstance(overrides, Mapping):
        for key, value in overrides.items():
            if not isinstance(key, str) or not key.strip():
                raise InputError(
                    "overrides",
                    f"key {key!r} is not a dotted field name",
                    "write e.g. {'solver.duration': 2.0}",
                )
            set_field(spec, key, value, "overrides")
        return
    items = (
        None
        if isinstance(overrides, (str, bytes))
        else list(overrides)
        if isinstance(overrides, Iterable)
        else None
    )
    if items is None or not all(isinstance(item, str) for item in items):
        raise InputError(
            "overrides",
            f"expected a list of key=value strings or a mapping, got {overrides!r}",
            "write e.g. ['solver.duration=2'] or {'solver.duration': 2.0}",
        )
    for item in items:
        apply_override(spec, item)


def apply_override(spec: dict, item: str) -> None:
    """Set a dotted key from ``key=value`` (value parsed as YAML): ``solver.duration=2``."""
    if "=" not in item:
        raise InputError(
            "--set", f"'{item}' is not key=value", "write e.g. --set solver.duration=2"
        )
    key, _, text = item.partition("=")
    try:
        value = parse_yaml_text(text, "")
    except InputError as err:
        raise InputError(
            f"--set {key.strip()!r}",
            f"value is {err.problem}",
            "quote text values, e.g. --set name='my scene'",
        ) from None
    set_field(spec, key, value)


def set_field(spec: dict, key: str, value, label: str = "--set") -> None:
    """Set the dotted ``key`` of a scene mapping to ``value``: mappings are made on the way,
    list items are picked by index or body name; errors name ``label`` and the key."""
    parts = key.strip().split(".")
    node = spec
    for i, part in enumerate(parts[:-1]):
        if isinstance(node, list):
            node = node[_list_index(node, part, ".".join(parts[: i + 1]), label)]
            continue
        if part not in node or node[part] is None:
            node[part] = {}
        node = node[part]
        if not isinstance(node, (dict, list)):
            raise InputError(f"{label} {key}", f"'{part}' is not a mapping", "set a leaf key")
    last = parts[-1]
    if isinstance(node, list):
        node[_list_index(node, last, key, label)] = value
    else:
        node[last] = value


def _list_index(node: list, part: str, key: str, label: str = "--set") -> int:
    if part.isdigit() and int(part) < len(node):
        return int(part)
    names = [b.get("name") for b in node if isinstance(b, dict)]
    if part in names:
        return names.index(part)
    raise InputError(f"{label} {key}", f"no list item '{part}'", "use an index or a body name")


def contact_law(contact: dict) -> ContactLaw:
    """The scene's ``contact:`` mapping checked against its law's row (stonedem.engine.laws)."""
    contact = Field("contact", "mapping", hint=CONTACT_FIX).check(
        {} if contact is None else contact
    )
    # no model: point, unless c_n is given (a dashpot only the area law has: a scene written
    # for the thesis' law before the point law became the default keeps its meaning)
    model = contact.get("model", "area" if "c_n" in contact else DEFAULT_LAW)
    laws = Field(  # rows may be added at run time (a toy law in tests/test_registries.py)
        "model", "choice", choices=tuple(LAWS), hint=" or ".join(r.hint for r in LAWS.values())
    )
    row = LAWS[laws.check(model, "contact.model")]
    for key in contact:
        owner = next((name for name, r in LAWS.items() if key in r.own_keys), None)
        if owner is not None and key not in row.own_keys:
            raise InputError(
                f"contact.{key}",
                f"not used by the {model} model",
                f"drop it, or set contact.model: {owner}",
            )
    values = row.spec.check(contact, "contact")
    del values["model"]
    values["frame"] = row.frame or values["frame"]
    return ContactLaw(model, values)


CONTACT_FIX = "write contact: {model: point, k_n: 1.0e11}"


# Every coordinate of the scenes scene_from_dict builds, times this (1.0: as given). The
# equivalence test's last-bit floors (stonedem.study.exact_checks) run the validations, which
# build their own scenes, with 1 + j 2^-52: the rounding of the geometry, which k_n's last
# bits never move (stonedem.study.members, perturbation "geometry").
GEOMETRY_SCALE = contextvars.ContextVar("stonedem_geometry_scale", default=1.0)


def scaled_bodies(bodies, factor: float) -> tuple:
    """Every body with its vertices (and tilt pivot) times ``factor`` about the origin; mass
    and inertia kept (a factor 1 + j 2^-52 moves them by ~1e-16 relative, nothing physical)."""
    return tuple(
        dataclasses.replace(
            b, vertices=b.vertices * factor, tilt_pivot=np.asarray(b.tilt_pivot) * factor
        )
        for b in bodies
    )


def scene_from_dict(spec: dict, base_dir: Path | str = ".") -> Scene:
    """Validate a scene mapping (the YAML format of docs/guide/scenes.md) and build a Scene."""
    if not isinstance(spec, dict):
        raise InputError("scene", f"expected a mapping, got {got(spec)}", "start with bodies:")
    spec = copy.deepcopy(spec)
    top = SCENE.check(spec)  # solver: and output: come after the bodies (a scene lacking both
    # hears of its bodies first)
    body_specs = top["bodies"]
    structure_links = None
    if "structure" in spec:
        from stonedem.engine.structures import build_structure

        structure = spec["structure"]
        if isinstance(structure, dict) and "links" in structure:
            structure = {k: v for k, v in structure.items() if k != "links"}
            structure_links = spec["structure"]["links"]
        body_specs = build_structure(structure) + body_specs
    if not body_specs:
        raise InputError("bodies", "the scene has no bodies", "list bodies: or give a structure:")
    if len(body_specs) > MAX_BODIES:
        raise InputError(
            "bodies",
            f"{len(body_specs)} bodies exceed the limit {MAX_BODIES}",
            "split the scene; contact memory grows as the square of the body count",
        )
    bodies = tuple(_body(b, i, top["density"], top["depth"]) for i, b in enumerate(body_specs))
    if GEOMETRY_SCALE.get() != 1.0:
        bodies = scaled_bodies(bodies, GEOMETRY_SCALE.get())
    names = [b.name for b in bodies]
    for i, name in enumerate(names):
        if names.index(name) != i:
            raise InputError(
                f"bodies[{i}].name", f"duplicate body name '{name}'", "make names unique"
            )
    if all(b.driven for b in bodies):
        raise InputError("bodies", "every body is driven", "leave at least one body free")
    links = ()
    if top["links"] or structure_links is not None:
        from stonedem.engine.links import scene_links

        links = scene_links(top["links"], structure_links, body_specs, bodies)

    contact = contact_law(spec.get("contact"))
    pair_friction = {}
    for i, item in enumerate(top["interface_friction"]):
        pair = item["bodies"]
        if len(pair) != 2 or not all(isinstance(n, str) and n in names for n in pair):
            raise InputError(
                f"interface_friction[{i}].bodies",
                f"expected two body names, got {show(pair)}",
                f"known bodies: {', '.join(names)}",
            )
        pair_friction[tuple(sorted(pair))] = item["mu"]

    solver = SOLVER.check(spec.get("solver"), "solver")
    every = OUTPUT.check(spec.get("output"), "output")["every"]
    horizontal, vertical = base_motions(spec, base_dir)
    spec.update(
        depth=top["depth"],
        density=top["density"],
        gravity=top["gravity"],
        friction=top["friction"],
        contact={"model": contact.model, **contact.params},
        solver={**SOLVER_DEFAULTS, **(spec.get("solver") or {})},
        output={**OUTPUT_DEFAULTS, **(spec.get("output") or {})},
    )
    scene = Scene(
        bodies=bodies,
        contact=contact,
        friction=top["friction"],
        pair_friction=pair_friction,
        gravity=top["gravity"],
        depth=top["depth"],
        horizontal=horizontal,
        vertical=vertical,
        duration=solver["duration"],
        dt=solver["dt"],
        dt_safety=LAWS[contact.model].dt_safety
        if solver["dt_safety"] is None
        else solver["dt_safety"],
        stop_on_collapse=solver["stop_on_collapse"],
        skip_quiet=solver["skip_quiet"],
        output_every=every,
        spec=spec,
        kernel=solver["kernel"],
        links=links,
    )
    check_initial_overlaps(scene)
    check_lean_friction(scene)
    return scene


def check_lean_friction(scene: Scene) -> None:
    """Refuse leaning bodies (``lean``, structure.tilt) whose friction cannot hold them on
    their inclined seats: tan|lean| >= mu of a pair they touch at rest slides them off."""
    leaning = [i for i, b in enumerate(scene.bodies) if b.lean != 0.0]
    if not leaning:
        return
    steep = max(leaning, key=lambda i: abs(scene.bodies[i].lean))
    steepest = abs(scene.bodies[steep].lean)
    mus = [scene.friction if b.friction is None else b.friction for b in scene.bodies]
    names = scene.body_names
    # a pair's mu is the smaller of the two bodies' (stonedem.engine.pack), or its own
    grip = min(mus[i] for i, b in enumerate(scene.bodies) if i in leaning or b.driven)
    for pair, mu in scene.pair_friction.items():
        if any(names.index(n) in leaning for n in pair):
            grip = min(grip, mu)
    if math.tan(steepest) >= grip:
        built = isinstance(scene.spec.get("structure"), dict) and "tilt" in scene.spec["structure"]
        raise InputError(
            "structure.tilt" if built else f"bodies[{steep}] ({names[steep]}).lean",
            f"tan({steepest:g} rad) = {math.tan(steepest):.3g} reaches the friction {grip:g}: "
            "the drums slide down their inclined seats",
            f"give a lean < atan(friction) = {math.atan(grip):.4g} rad, or more friction",
        )


def base_motions(spec: dict, base_dir: Path | str) -> tuple[BaseMotion, BaseMotion]:
    """The (horizontal, vertical) base motion of a scene mapping's ``excitation``, checked by
    its kind's row (stonedem.motion.excitation.EXCITATIONS)."""
    return excitation_pair(spec.get("excitation"), Path(base_dir))


def scene_with_excitation(scene: Scene, spec: dict, base_dir: Path | str = ".") -> Scene:
    """:func:`scene_from_dict` of ``spec`` when it differs from ``scene.spec`` only in its
    ``excitation`` and ``name``: the scene's bodies, law and settings as they are (checked
    once, shared), its base motion built and checked from ``spec``. A threshold search's runs
    differ only so (stonedem.study.runner.SearchScenes); the bodies' identity lets the plan
    reuse what depends on them alone (stonedem.engine.simulate)."""
    own = {key: copy.deepcopy(spec[key]) for key in ("excitation", "name") if key in spec}
    horizontal, vertical = base_motions(own, base_dir)
    # the rest of the provenance is the scene's own (read-only: stonedem.api freezes it)
    full = {**{k: v for k, v in scene.spec.items() if k not in ("excitation", "name")}, **own}
    return dataclasses.replace(scene, horizontal=horizontal, vertical=vertical, spec=full)


def _body(spec: dict, index: int, density: float, depth: float) -> Body:
    name = spec.get("name", f"body{index}") if isinstance(spec, dict) else None
    if name is not None:
        name = BODY["name"].check(name, f"bodies[{index}].name")
        if not name:
            raise InputError(f"bodies[{index}].name", "is empty", "give a short text name")
    where = f"bodies[{index}] ({name})" if name else f"bodies[{index}]"
    body = BODY.check(spec, where)
    if body["box"] is not None:
        box = body["box"]
        vertices = geometry.box_vertices(box["width"], box["height"], box["center"], box["angle"])
    else:
        vertices = _polygon(body["polygon"]["vertices"], f"{where}.polygon")

    reach = float(np.max(np.abs(vertices)))
    if not reach <= MAX_COORDINATE:  # a width of 1e300 gave "mass: 503 kg (inertia nan) ..."
        raise InputError(
            f"{where}.{'box' if body['box'] is not None else 'polygon.vertices'}",
            f"a corner lies {reach:.3g} m from the origin, past {MAX_COORDINATE:g} m",
            "place the bodies near the origin, in metres",
        )

    area = geometry.signed_area(vertices) * depth  # volume [m3]
    polar = geometry.polar_moment_about_centroid(vertices) * depth
    mass = body["mass"] if body["mass"] is not None else (body["density"] or density) * area
    inertia = mass * polar / area if area > 0.0 else 0.0  # uniform distribution over the polygon
    if not (MIN_MASS <= mass <= MAX_MASS and inertia > 0.0 and np.isfinite(inertia)):
        raise InputError(
            f"{where}.mass",
            f"{mass:.3g} kg (inertia {inertia:.3g} kg m2) is outside {MIN_MASS:g}..{MAX_MASS:g} kg",
            "check mass, density, depth and the body's size (SI units)",
        )

    tilt_angle, tilt_pivot = 0.0, geometry.centroid(vertices)
    if body["tilt"] is not None:
        if body["driven"]:
            raise InputError(f"{where}.tilt", "a driven body cannot be tilted", "remove tilt:")
        tilt = body["tilt"]
        tilt_angle, tilt_pivot = _tilt(
            vertices, tilt["angle"], tilt["about"], f"{where}.tilt.about"
        )
    if body["lean"] != 0.0 and body["driven"]:
        raise InputError(
            f"{where}.lean", "a driven body has no critical rotation to reckon", "remove lean:"
        )
    velocity = body["velocity"]
    return Body(
        name=name if name is not None else f"body{index}",
        vertices=vertices,
        mass=mass,
        inertia=inertia,
        driven=body["driven"],
        role=body["role"],
        column=body["column"],
        tier=body["tier"],
        friction=body["friction"],
        tilt_angle=tilt_angle,
        tilt_pivot=tilt_pivot,
        velocity=None if velocity is None else tuple(velocity),
        lean=body["lean"],
    )


def _polygon(raw: list, where: str) -> np.ndarray:
    """The counter-clockwise corners of a ``polygon:`` body's vertices, or an InputError: 3 to
    MAX_BODY_VERTICES [x, y] pairs of finite numbers, a simple convex polygon with area."""
    field = f"{where}.vertices"
    if len(raw) < 3 or len(raw) > MAX_BODY_VERTICES:
        raise InputError(field, f"{len(raw)} vertices", f"give 3 to {MAX_BODY_VERTICES} [x, y]")
    vertices = np.array([VERTEX.check(v, f"{field}[{i}]") for i, v in enumerate(raw)])
    for bad, problem, fix in (
        (not geometry.is_simple(vertices), "self-intersecting", "order them around the boundary"),
        (abs(geometry.signed_area(vertices)) <= 1e-14, "zero area", "give a polygon with area"),
        (not geometry.is_convex(vertices), "non-convex polygon", "split it into convex bodies"),
    ):
        if bad:
            raise InputError(where, problem, fix)
    return vertices if geometry.signed_area(vertices) > 0.0 else vertices[::-1].copy()


def _tilt(vertices: np.ndarray, angle: float, about, where: str):
    """Tilt angle (counter-clockwise) and pivot for a ``tilt:`` entry.

    A named corner means "lean onto that corner by ``angle``": the opposite side rises, so
    about bottom_right the body turns clockwise. An explicit [x, y] pivot turns it
    counter-clockwise by ``angle``.
    """
    if isinstance(about, (list, tuple)):
        return angle, np.array(PIVOT.check(about, where))
    if about not in TILT_PIVOTS:
        raise InputError(
            where, f"unknown pivot {show(about)}", f"use one of {', '.join(TILT_PIVOTS)} or [x, y]"
        )
    if about == "centroid":
        return angle, geometry.centroid(vertices)
    # the outermost vertex among the lowest ones
    ys = vertices[:, 1]
    lowest = np.flatnonzero(ys <= ys.min() + 1e-9 * np.ptp(vertices).clip(min=1.0))
    xs = vertices[lowest, 0]
    right = about == "bottom_right"
    pivot = vertices[lowest[int(np.argmax(xs) if right else np.argmin(xs))]]
    return (-angle if right else angle), pivot


def initial_pose(body: Body) -> tuple[float, float, float]:
    """Centroid position [m] and rotation [rad] of a body at t = 0, after its tilt."""
    c = body.centroid
    if body.tilt_angle == 0.0:
        return float(c[0]), float(c[1]), 0.0
    moved = geometry.rotate_about(c[None, :], body.tilt_angle, body.tilt_pivot)[0]
    return float(moved[0]), float(moved[1]), body.tilt_angle


def posed_vertices(body: Body) -> np.ndarray:
    """World vertices of a body at t = 0 [m]."""
    if body.tilt_angle == 0.0:
        return body.vertices
    return geometry.rotate_about(body.vertices, body.tilt_angle, body.tilt_pivot)


def box_pairs(lo: np.ndarray, hi: np.ndarray, margin: float) -> list[tuple[int, int]]:
    """Pairs (i < j) whose bounds (n, 2) [m], inflated by ``margin``, overlap: the engine's
    sort-and-sweep (:func:`stonedem.kernels.broad_phase.find_candidate_pairs`), so set-up is
    O(N)."""
    from stonedem.kernels.broad_phase import find_candidate_pairs

    n = len(lo)
    axis = int(np.ptp(hi[:, 1]) + np.ptp(lo[:, 1]) >= np.ptp(hi[:, 0]) + np.ptp(lo[:, 0]))
    pa, pb = find_candidate_pairs(
        n,
        np.zeros(n, dtype=np.bool_),
        np.ascontiguousarray(lo[:, 0]),
        np.ascontiguousarray(lo[:, 1]),
        np.ascontiguousarray(hi[:, 0]),
        np.ascontiguousarray(hi[:, 1]),
        float(margin),
        axis,
    )
    return list(zip(pa.tolist(), pb.tolist()))


def check_initial_overlaps(scene: Scene) -> None:
    """Refuse bodies that overlap at t = 0 by more than a touching tolerance."""
    from stonedem.kernels.overlap import (
        MAX_OVERLAP_VERTICES,
        clip_convex_polygons,
        polygon_area_centroid,
    )

    posed = [posed_vertices(b) for b in scene.bodies]
    lo = np.array([p.min(axis=0) for p in posed])
    hi = np.array([p.max(axis=0) for p in posed])
    scratch = np.zeros((4, MAX_OVERLAP_VERTICES))
    for i, j in box_pairs(lo, hi, 0.0):
        a, b = posed[i], posed[j]
        n = clip_convex_polygons(
            a[:, 0].copy(),
            a[:, 1].copy(),
            b[:, 0].copy(),
            b[:, 1].copy(),
            scratch[0],
            scratch[1],
            scratch[2],
            scratch[3],
        )
        if n < 3:
            continue
        area = polygon_area_centroid(scratch[0], scratch[1], n)[0]
        smaller = min(geometry.signed_area(a), geometry.signed_area(b))
        if area > INITIAL_OVERLAP_TOLERANCE * smaller:
            bi, bj = scene.bodies[i].name, scene.bodies[j].name
            raise InputError(
                f"bodies ({bi}, {bj})",
                f"overlap by {area:.3g} m2 at t = 0",
                "place bodies so they touch without overlapping",
            )
