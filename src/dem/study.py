"""Parametric studies: config grid -> case table (stable, readable ids) -> one scene per case.

A study in ``config/config.yaml`` names a base scene (structure, friction, contact,
excitation, solver) and a grid of swept parameters; the case table is the Cartesian product
of the grid. Each parameter maps to one field of the scene (``PARAMETERS``), carries units
and a long name, and becomes a scalar coordinate of the case dataset and a dimension of the
study cube (:func:`combine_cases`). Case ids are built from the parameter values, so a case
is fully described by its id and Snakemake reruns exactly what changed.
"""

from __future__ import annotations

import copy
import itertools
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from dem.errors import InputError

# name: (scene field, units, long name, id label)
PARAMETERS = {
    "record": ("excitation.file", "1", "ground-motion record", "rec"),
    "pga": ("excitation.pga", "m s-2", "peak ground acceleration of the scaled record", "pga"),
    "pga_scale": ("excitation.scale", "1", "record scale factor", "x"),
    "frequency": ("excitation.frequency", "Hz", "harmonic excitation frequency", "f"),
    "amplitude": ("excitation.amplitude", "m", "harmonic displacement amplitude", "A"),
    "n_drums": ("structure.n_drums", "1", "number of drums per column", "drums"),
    "n_columns": ("structure.n_columns", "1", "number of columns", "cols"),
    "clear_distance": ("structure.clear_distance", "m", "clear distance between columns", "gap"),
    "epistyle_type": ("structure.epistyle_type", "1", "epistyle type (thesis Table 7.2)", "epi"),
    "epistyle_density": ("structure.epistyle_density", "kg m-3", "epistyle density", "rhoe"),
    "taper": ("structure.taper", "1", "base / top width of the shaft", "taper"),
    "friction": ("friction", "1", "friction coefficient", "mu"),
    # thesis 6.5: one joint of a standalone column with a lower friction coefficient
    "weak_joint": ("weak_joint.joint", "1", "joint with the lower friction, from the base (0: base / drum 0)", "joint"),
    "weak_joint_mu": ("weak_joint.mu", "1", "friction coefficient at the weak joint", "muj"),
}
STUDY_KEYS = ("structure", "friction", "contact", "excitation", "solver", "output", "grid",
              "interface_friction", "weak_joint", "cases", "description")
SCENE_KEYS = ("structure", "friction", "contact", "excitation", "solver", "output", "interface_friction",
              "weak_joint")


@dataclass(frozen=True)
class Case:
    study: str
    id: str
    params: dict  # swept parameter values
    scene: dict  # the full scene mapping


def load_config(*paths) -> dict:
    """A workflow config from YAML files, each merged into the ones before key by key
    (nested mappings merged, lists replaced), as ``snakemake --configfile`` merges a
    profile such as config/quick.yaml into config/config.yaml."""
    import yaml

    def merge(base: dict, extra: dict) -> dict:
        for key, value in extra.items():
            if isinstance(value, dict) and isinstance(base.get(key), dict):
                merge(base[key], value)
            else:
                base[key] = copy.deepcopy(value)
        return base

    config: dict = {}
    for path in paths:
        merge(config, yaml.safe_load(Path(path).read_text()) or {})
    return config


def config_cases(config: dict, studies=None) -> dict[str, list[Case]]:
    """{study: its case table} for the named studies of a config (all when None)."""
    names = list(config.get("studies") or {}) if studies is None else studies
    return {name: case_table(name, config["studies"][name], config.get("defaults")) for name in names}


def _label(value) -> str:
    if isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = str(value)
    return text.replace("/", "-").replace(" ", "")


def case_id(params: dict) -> str:
    """Readable, stable id from parameter values in grid order: ``rec-athens_pga-2_drums-3``."""
    return "_".join(f"{PARAMETERS[k][3]}-{_label(v)}" for k, v in params.items())


def _set(spec: dict, dotted: str, value) -> None:
    node = spec
    parts = dotted.split(".")
    for part in parts[:-1]:
        node = node.setdefault(part, {})
    node[parts[-1]] = value


def case_table(name: str, study: dict, defaults: dict | None = None) -> list[Case]:
    """All cases of one study: the Cartesian product of its ``grid`` plus its listed ``cases``.

    ``cases:`` is a list of parameter mappings for studies that are not a full grid (e.g. one
    PGA per record for the snapshot figures); a study may have both.
    """
    if not isinstance(study, dict):
        raise InputError(f"studies.{name}", "expected a mapping", "give structure:, excitation:, grid:")
    for key in study:
        if key not in STUDY_KEYS:
            raise InputError(f"studies.{name}.{key}", "unknown key", f"allowed keys: {', '.join(STUDY_KEYS)}")
    grid = study.get("grid") or {}
    listed = study.get("cases") or []
    if not grid and not listed:
        raise InputError(f"studies.{name}", "no cases", "give grid: {parameter: [values]} or cases: [{...}]")
    for key, values in grid.items():
        _check_parameter(f"studies.{name}.grid.{key}", key)
        if not isinstance(values, list) or not values:
            raise InputError(f"studies.{name}.grid.{key}", "expected a non-empty list", "write [v1, v2, ...]")
    if not isinstance(listed, list):
        raise InputError(f"studies.{name}.cases", "expected a list", "write cases: [{record: ..., pga: ...}]")
    for i, params in enumerate(listed):
        if not isinstance(params, dict) or not params:
            raise InputError(f"studies.{name}.cases[{i}]", "expected a mapping of parameters",
                             "write {record: ..., pga: ...}")
        for key in params:
            _check_parameter(f"studies.{name}.cases[{i}].{key}", key)
    base = {k: copy.deepcopy(v) for k, v in (defaults or {}).items()}
    for key in SCENE_KEYS:
        if key in study:
            if isinstance(study[key], dict) and isinstance(base.get(key), dict):
                base[key] = {**base[key], **copy.deepcopy(study[key])}
            else:
                base[key] = copy.deepcopy(study[key])
    keys = list(grid)
    combos = [dict(zip(keys, combo)) for combo in itertools.product(*(grid[k] for k in keys))] if grid else []
    cases = [_case(name, base, params) for params in combos + [dict(p) for p in listed]]
    ids = [c.id for c in cases]
    if len(set(ids)) != len(ids):
        raise InputError(f"studies.{name}", "two cases share an id", "remove duplicate grid values or cases")
    return cases


def _check_parameter(field: str, key: str) -> None:
    if key not in PARAMETERS:
        raise InputError(field, "unknown parameter", f"sweepable: {', '.join(PARAMETERS)}")


def _case(study: str, base: dict, params: dict) -> Case:
    scene = copy.deepcopy(base)
    scene["name"] = f"{study}/{case_id(params)}"
    for k, v in params.items():
        _set(scene, PARAMETERS[k][0], v)
    _apply_weak_joint(scene, f"studies.{study}")
    return Case(study, case_id(params) or "base", params, scene)


def _apply_weak_joint(scene: dict, where: str) -> None:
    """``weak_joint: {joint: j, mu: m}`` -> the per-interface friction of joint j of column 0 (thesis 6.5).

    Joint 0 is between the base and the bottom drum, joint j between drums j-1 and j.
    """
    weak = scene.pop("weak_joint", None)
    if weak is None:
        return
    if not isinstance(weak, dict) or set(weak) != {"joint", "mu"}:
        raise InputError(f"{where}.weak_joint", "expected {joint, mu}", "write weak_joint: {joint: 0, mu: 0.05}")
    joint = weak["joint"]
    n_drums = int((scene.get("structure") or {}).get("n_drums", 1))
    if not isinstance(joint, int) or not 0 <= joint < n_drums:
        raise InputError(f"{where}.weak_joint.joint", f"{joint!r} is not a joint of a {n_drums}-drum column",
                         f"give an integer 0 ... {n_drums - 1}")
    lower = "base" if joint == 0 else f"c0_d{joint - 1}"
    scene.setdefault("interface_friction", []).append({"bodies": [lower, f"c0_d{joint}"], "mu": weak["mu"]})


def run_case(case: Case, base_dir: Path | str = ".") -> xr.Dataset:
    """Simulate one case: the scene's dataset with the swept parameters as scalar coordinates."""
    from dem.scene import scene_from_dict
    from dem.simulate import run_scene

    scene_spec = copy.deepcopy(case.scene)
    solver = scene_spec.setdefault("solver", {})
    if solver.get("duration") is None:
        solver["duration"] = _natural_duration(scene_spec, base_dir)
    ds = run_scene(scene_from_dict(scene_spec, base_dir=base_dir))
    for key, value in case.params.items():
        _, units, long_name, _ = PARAMETERS[key]
        ds = ds.assign_coords({key: xr.Variable((), value, {"units": units, "long_name": long_name})})
    ds.attrs.update(study=case.study, case=case.id)
    return ds


def _natural_duration(scene_spec: dict, base_dir) -> float:
    """A record's own length, plus 2 s for the structure to come to rest, when none is given."""
    from dem.ground_motion import excitation_pair

    horizontal, _ = excitation_pair(scene_spec.get("excitation"), Path(base_dir))
    if horizontal.duration is None:
        raise InputError("solver.duration", "missing and the excitation has no natural length",
                         "give solver: {duration: ...} in the study")
    return horizontal.duration + 2.0


# case attributes a cube keeps when every case agrees on them
SHARED_ATTRS = ("source", "study", "contact_model", "contact_law", "k_n", "c_n", "contact_damping",
                "contact_impact", "k_t", "c_t", "friction", "excitation", "contact_frame")
CUBE_VARIABLES = ("collapsed", "collapse_time", "max_rocking", "max_total_sliding",
                  "residual_total_sliding", "rocking_onset_time", "max_epistyle_displacement", "theta_cr")
# time histories a cube keeps (NaN after a case stopped at collapse or ended)
HISTORY_VARIABLES = ("rocking", "total_sliding", "epistyle_displacement", "base_displacement",
                     "base_acceleration")


def combine_cases(paths, description: str = "") -> xr.Dataset:
    """Study cube: each case's measures and histories on dimensions named by the swept parameters.

    Cases are merged by coordinates with an outer join, so a study of listed cases (not a
    full grid) gives a cube with NaN where a combination was not run.
    """
    pieces = []
    shared = None
    for path in paths:
        with xr.open_dataset(path) as ds:
            params = [k for k in PARAMETERS if k in ds.coords and ds[k].ndim == 0]
            names = [v for v in CUBE_VARIABLES + HISTORY_VARIABLES if v in ds]
            small = ds[names].load()
            small = small.reset_coords([c for c in small.coords if c not in params and c != "time"], drop=True)
            # cases of different dt sample the same output times to within rounding: align them
            if "time" in small.coords:
                small = small.assign_coords(time=np.round(small["time"].values, 9))
            small = small.expand_dims(params)
            # strings as objects: merging fixed-width unicode truncates 'per_span' to the width of 'a'
            small = small.assign_coords({k: small[k].astype(object) for k in params if small[k].dtype.kind == "U"})
            pieces.append(small)
            case_attrs = {k: ds.attrs[k] for k in SHARED_ATTRS if k in ds.attrs}
            shared = case_attrs if shared is None else {
                k: v for k, v in shared.items() if k in case_attrs and str(case_attrs[k]) == str(v)}
    if not pieces:
        raise InputError("cases", "no case files to combine", "run the study's cases first")
    attrs = shared or {}
    cube = xr.merge(pieces, join="outer", compat="no_conflicts", combine_attrs="drop")
    for name in list(cube.coords):
        if name in PARAMETERS:
            _, units, long_name, _ = PARAMETERS[name]
            cube[name].attrs.update(units=units, long_name=long_name)
    with xr.open_dataset(paths[0]) as first:
        for name in cube.variables:
            if name in first.variables and name not in PARAMETERS:
                cube[name].attrs = dict(first[name].attrs)
    # per-case settings (dt, status, ...) stay in the case files; the cube keeps the shared ones
    cube.attrs = {**attrs, "title": f"dem study cube: {attrs.get('study', '')}", "n_cases": len(pieces),
                  "description": description}
    return cube


def minimum_collapse(cube: xr.Dataset, along: str = "pga") -> xr.DataArray:
    """Smallest value of ``along`` at which the case collapsed (NaN: never), per other parameters.

    Collapse is not monotonic in the excitation level, so the cube's ``collapsed`` map is
    kept beside this summary.
    """
    collapsed = cube["collapsed"].fillna(0) > 0
    values = cube[along].broadcast_like(collapsed)
    first = values.where(collapsed).min(along)
    first.attrs = {"units": cube[along].attrs.get("units", ""),
                   "long_name": f"smallest {cube[along].attrs.get('long_name', along)} that collapses"}
    return first
