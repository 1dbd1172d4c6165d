"""Wall case files (YAML): parsing, validation, and the model they describe.

```yaml
panel: {block: {a: 0.081, b: 0.210, s: 0.070}, blocks_per_course: 3, courses: 13, unit_weight: 20000.0}
joints: {kind: dry, mu: 0.7, k_n: 2.4e9, k_t: 1.0e9}   # mortar: add tensile_strength, cohesion
restraints: [{edge: base, fix: all}, {edge: left, fix: translations}]
load: {kind: proportional, direction: out_of_plane}      # or {kind: pressure}
```

Every error is an InputError naming the dotted field and the fix (exit status 2).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from dem.errors import InputError, check_number
from dem.wall.constitutive import JointStrength
from dem.wall.panel import EDGES, KIND_HEAD, KIND_SUPPORT, build_panel
from dem.wall.pushover import SolverSettings, WallModel

TOP_KEYS = {"name", "description", "panel", "joints", "restraints", "load", "solver", "reference"}
PANEL_KEYS = {"block", "blocks_per_course", "courses", "unit_weight", "joint_thickness",
              "first_course_offset", "openings", "lintel_strength"}
BLOCK_KEYS = {"a", "b", "s"}
JOINT_KEYS = {"kind", "mu", "k_n", "k_t", "tensile_strength", "cohesion", "alpha"}
RESTRAINT_KEYS = {"edge", "fix", "support", "joint", "dead_load"}
LOAD_KEYS = {"kind", "direction", "extra_vertical", "extra_in_live_load"}
EXTRA_KEYS = {"count", "force", "edge"}
SOLVER_KEYS = set(SolverSettings().as_dict()) | {"control_block"}
FIX_DOFS = {"all": (0, 1, 2, 3, 4, 5), "translations": (0, 1, 2), "out_of_plane": (2,),
            "rotations": (3, 4, 5)}
DIRECTIONS = {"out_of_plane": 2, "in_plane": 0}


def _mapping(value, field):
    if not isinstance(value, dict):
        raise InputError(field, f"expected a mapping, got {type(value).__name__}",
                         "write it as {key: value, ...}")
    return value


def _keys(spec, allowed, field, required=()):
    _mapping(spec, field)
    for key in spec:
        if key not in allowed:
            raise InputError(f"{field}.{key}" if field else key, "unknown key",
                             f"use one of: {', '.join(sorted(allowed))}")
    for key in required:
        if key not in spec:
            raise InputError(f"{field}.{key}" if field else key, "missing", "add this field")


def _choice(value, options, field):
    if value not in options:
        raise InputError(field, f"unknown value {value!r}", f"use one of: {', '.join(options)}")
    return value


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
    if not path.is_file():
        raise InputError(str(path), "case file not found", "give the path of a wall case YAML file")
    try:
        spec = yaml.safe_load(path.read_text())
    except yaml.YAMLError as err:
        raise InputError(str(path), f"not valid YAML ({str(err).splitlines()[0]})", "fix the YAML syntax")
    return case_from_dict(spec, name=path.stem)


def case_from_dict(spec: dict, name: str = "wall") -> WallCase:
    spec = copy.deepcopy(spec)
    _keys(spec, TOP_KEYS, "", required=("panel", "joints", "restraints", "load"))
    name = str(spec.get("name", name))

    p = spec["panel"]
    _keys(p, PANEL_KEYS, "panel", required=("block", "blocks_per_course", "courses", "unit_weight"))
    _keys(p["block"], BLOCK_KEYS, "panel.block", required=("a", "b", "s"))
    a, b, s = (check_number(p["block"][k], f"panel.block.{k}", positive=True) for k in "abs")
    n_len = check_number(p["blocks_per_course"], "panel.blocks_per_course", positive=True)
    if abs(2 * n_len - round(2 * n_len)) > 1e-9 or n_len < 1:
        raise InputError("panel.blocks_per_course", f"{n_len} is not a multiple of 0.5 >= 1",
                         "give a whole or half number of blocks")
    courses = check_number(p["courses"], "panel.courses", positive=True)
    if courses != int(courses):
        raise InputError("panel.courses", f"{courses} is not a whole number", "give an integer")
    gamma = check_number(p["unit_weight"], "panel.unit_weight", positive=True)
    e = check_number(p.get("joint_thickness", 0.0), "panel.joint_thickness", nonnegative=True)
    openings = []
    for k, o in enumerate(p.get("openings") or []):
        f = f"panel.openings[{k}]"
        _keys(o, {"x", "y"}, f, required=("x", "y"))
        box = {}
        for ax in ("x", "y"):
            v = o[ax]
            if not isinstance(v, (list, tuple)) or len(v) != 2:
                raise InputError(f"{f}.{ax}", "expected [start, end] in metres", "give two numbers")
            lo, hi = (check_number(x, f"{f}.{ax}", nonnegative=True) for x in v)
            if hi <= lo:
                raise InputError(f"{f}.{ax}", f"end {hi} <= start {lo}", "give start < end")
            box[ax] = (lo, hi)
        openings.append(box)

    j = spec["joints"]
    _keys(j, JOINT_KEYS, "joints", required=("kind", "mu", "k_n", "k_t"))
    kind = _choice(j["kind"], ("dry", "mortar"), "joints.kind")
    joint = _joint_props(j, kind, "joints")

    restraints = spec["restraints"]
    if not isinstance(restraints, list) or not restraints:
        raise InputError("restraints", "expected a non-empty list", "e.g. [{edge: base, fix: all}]")
    support_edges, block_fix, support_joint, dead_fix = [], {}, {}, set()
    for k, r in enumerate(restraints):
        f = f"restraints[{k}]"
        _keys(r, RESTRAINT_KEYS, f, required=("edge", "fix"))
        edge = _choice(r["edge"], EDGES, f"{f}.edge")
        fix = _choice(r["fix"], tuple(FIX_DOFS), f"{f}.fix")
        support = _choice(r.get("support", "joint" if edge == "base" else "block"), ("joint", "block"),
                          f"{f}.support")
        if support == "joint":
            if fix != "all":
                raise InputError(f"{f}.fix", f"{fix!r} with support: joint",
                                 "a support joint is a fixed rigid support: use fix: all, or support: block")
            support_edges.append(edge)
            over = r.get("joint") or {}
            _keys(over, JOINT_KEYS - {"kind"}, f"{f}.joint")
            support_joint[edge] = _joint_props({**j, **over}, kind, f"{f}.joint")
        else:
            if "joint" in r:
                raise InputError(f"{f}.joint", "only for support: joint", "remove it or set support: joint")
            block_fix.setdefault(edge, set()).update(FIX_DOFS[fix])
            # dead_load: true -> this restraint also acts while the self-weight is applied
            if r.get("dead_load", False):
                dead_fix.add(edge)

    ld = spec["load"]
    _keys(ld, LOAD_KEYS, "load", required=("kind",))
    load_kind = _choice(ld["kind"], ("proportional", "pressure"), "load.kind")
    direction = _choice(ld.get("direction", "out_of_plane"), tuple(DIRECTIONS), "load.direction")
    if load_kind == "pressure" and direction != "out_of_plane":
        raise InputError("load.direction", "pressure acts out of plane", "use direction: out_of_plane")
    extras = []
    for k, x in enumerate(ld.get("extra_vertical") or []):
        f = f"load.extra_vertical[{k}]"
        _keys(x, EXTRA_KEYS, f, required=("count", "force"))
        cnt = check_number(x["count"], f"{f}.count", positive=True)
        extras.append((int(cnt), check_number(x["force"], f"{f}.force", nonnegative=True),
                       _choice(x.get("edge", "top"), ("top",), f"{f}.edge")))
    extra_live = bool(ld.get("extra_in_live_load", False))

    sol = spec.get("solver") or {}
    _keys(sol, SOLVER_KEYS, "solver")
    settings = SolverSettings()
    for key, val in sol.items():
        if key == "control_block":
            continue
        conv = type(getattr(settings, key))   # int for counts, float otherwise (the defaults say which)
        setattr(settings, key, conv(check_number(val, f"solver.{key}", nonnegative=True)))
    control_block = sol.get("control_block")

    panel = build_panel(a, b, s, n_len, int(courses), e, openings,
                        bool(p.get("first_course_offset", False)), support_edges)
    if panel.n_blocks == 0:
        raise InputError("panel.openings", "the openings remove every block", "make them smaller")
    if control_block is not None:
        cb = check_number(control_block, "solver.control_block", nonnegative=True)
        if int(cb) >= panel.n_blocks:
            raise InputError("solver.control_block", f"{int(cb)} >= {panel.n_blocks} blocks",
                             "give a block index of the panel")
        control_block = int(cb)
    ni = panel.n_interfaces
    props = {key: np.full(ni, joint[key]) for key in joint}
    for edge, jp in support_joint.items():
        sel = (panel.kind == KIND_SUPPORT) & (panel.edge == edge)
        for key in jp:
            props[key][sel] = jp[key]
    # lintels: the head joints of the course just above each opening carry tension (a lintel
    # beam bearing on the jambs), otherwise a dry course over an opening cannot stand
    lintel = check_number(p.get("lintel_strength", 0.0), "panel.lintel_strength", nonnegative=True)
    if lintel and openings:
        for box in openings:
            above = panel.centre[:, 1] - panel.size[:, 1] / 2 > box["y"][1] - 1e-9
            if not above.any():
                continue
            c_above = panel.course[above].min()
            x_lo = panel.centre[:, 0] - panel.size[:, 0] / 2
            x_hi = panel.centre[:, 0] + panel.size[:, 0] / 2
            beam = (panel.course == c_above) & (x_hi > box["x"][0] + 1e-9) & (x_lo < box["x"][1] - 1e-9)
            sel = (panel.kind == KIND_HEAD) & (panel.first >= 0) & (panel.second >= 0)
            sel &= np.isin(panel.first, np.flatnonzero(beam)) & np.isin(panel.second, np.flatnonzero(beam))
            props["tensile_strength"][sel] = lintel
            props["cohesion"][sel] = props["mu"][sel] * lintel
    strength = JointStrength(props["mu"], props["tensile_strength"], props["cohesion"], props["alpha"])

    nb = panel.n_blocks
    weight = gamma * panel.volume
    dead = np.zeros((nb, 6))
    live = np.zeros((nb, 6))
    dead[:, 1] = -weight
    if load_kind == "proportional":
        live[:, DIRECTIONS[direction]] = weight
    else:
        live[:, 2] = panel.size[:, 0] * panel.size[:, 1]  # lambda = pressure [Pa]
    for count, force, edge in extras:
        top = panel.edge_blocks(edge)
        xs = (np.arange(count) + 0.5) * panel.length / count
        for x in xs:
            lo = panel.centre[top, 0] - panel.size[top, 0] / 2
            hi = panel.centre[top, 0] + panel.size[top, 0] / 2
            hit = top[np.flatnonzero((lo <= x) & (x < hi))]
            blk = hit[0] if len(hit) else top[np.argmin(np.abs(panel.centre[top, 0] - x))]
            dead[blk, 1] -= force
            if extra_live and load_kind == "proportional":
                live[blk, DIRECTIONS[direction]] += force
    fixed = np.zeros((nb, 6), dtype=bool)
    for edge, dofs in block_fix.items():
        for blk in panel.edge_blocks(edge):
            fixed[blk, list(dofs)] = True
    if not support_edges and not fixed.any():
        raise InputError("restraints", "the wall is not supported", "add {edge: base, fix: all}")
    # restraints away from the base hold the wall after its self-weight has settled it
    fixed_dead = np.zeros_like(fixed)
    for blk in panel.edge_blocks("base"):
        fixed_dead[blk] = fixed[blk] if "base" in block_fix else False
    for edge in dead_fix:
        for blk in panel.edge_blocks(edge):
            fixed_dead[blk] |= fixed[blk]
    if not support_edges and not fixed_dead.any():
        fixed_dead = fixed
    model = WallModel(panel, props["k_n"], props["k_t"], strength, dead.ravel(), live.ravel(),
                      fixed.ravel(), fixed_dead.ravel())
    return WallCase(spec, name, model, settings, control_block, load_kind)


def _joint_props(j, kind, field):
    mu = check_number(j["mu"], f"{field}.mu", positive=True)
    k_n = check_number(j["k_n"], f"{field}.k_n", positive=True)
    k_t = check_number(j["k_t"], f"{field}.k_t", positive=True)
    alpha = check_number(j.get("alpha", 1.5), f"{field}.alpha", positive=True)
    if kind == "dry":
        for key in ("tensile_strength", "cohesion"):
            if j.get(key):
                raise InputError(f"{field}.{key}", "a dry joint has no tensile strength or cohesion",
                                 "remove it or use kind: mortar")
        sig_t, coh = 0.0, 0.0
    else:
        if "tensile_strength" not in j:
            raise InputError(f"{field}.tensile_strength", "missing for a mortar joint", "add it in Pa")
        sig_t = check_number(j["tensile_strength"], f"{field}.tensile_strength", nonnegative=True)
        # manuscript Eq. 10: shear strength mu (f_t - f_n), i.e. cohesion c = mu sigma_t
        coh = check_number(j.get("cohesion", mu * sig_t), f"{field}.cohesion", nonnegative=True)
    return {"mu": mu, "k_n": k_n, "k_t": k_t, "alpha": alpha, "tensile_strength": sig_t,
            "cohesion": coh}
