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
}
STUDY_KEYS = ("structure", "friction", "contact", "excitation", "solver", "output", "grid",
              "interface_friction")


@dataclass(frozen=True)
class Case:
    study: str
    id: str
    params: dict  # swept parameter values
    scene: dict  # the full scene mapping


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
    """All cases of one study: the Cartesian product of its grid over its base scene."""
    if not isinstance(study, dict):
        raise InputError(f"studies.{name}", "expected a mapping", "give structure:, excitation:, grid:")
    for key in study:
        if key not in STUDY_KEYS:
            raise InputError(f"studies.{name}.{key}", "unknown key", f"allowed keys: {', '.join(STUDY_KEYS)}")
    grid = study.get("grid") or {}
    for key, values in grid.items():
        if key not in PARAMETERS:
            raise InputError(f"studies.{name}.grid.{key}", "unknown parameter",
                             f"sweepable: {', '.join(PARAMETERS)}")
        if not isinstance(values, list) or not values:
            raise InputError(f"studies.{name}.grid.{key}", "expected a non-empty list", "write [v1, v2, ...]")
    base = {k: copy.deepcopy(v) for k, v in (defaults or {}).items()}
    for key in ("structure", "friction", "contact", "excitation", "solver", "output", "interface_friction"):
        if key in study:
            if isinstance(study[key], dict) and isinstance(base.get(key), dict):
                base[key] = {**base[key], **copy.deepcopy(study[key])}
            else:
                base[key] = copy.deepcopy(study[key])
    cases = []
    keys = list(grid)
    for combo in itertools.product(*(grid[k] for k in keys)):
        params = dict(zip(keys, combo))
        scene = copy.deepcopy(base)
        scene["name"] = f"{name}/{case_id(params)}"
        for k, v in params.items():
            _set(scene, PARAMETERS[k][0], v)
        cases.append(Case(name, case_id(params) or "base", params, scene))
    ids = [c.id for c in cases]
    if len(set(ids)) != len(ids):
        raise InputError(f"studies.{name}.grid", "two cases share an id", "remove duplicate grid values")
    return cases


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
SHARED_ATTRS = ("source", "study", "k_n", "c_n", "k_t", "c_t", "friction", "excitation", "contact_frame")
CUBE_VARIABLES = ("collapsed", "collapse_time", "max_rocking", "max_total_sliding",
                  "residual_total_sliding", "rocking_onset_time", "max_epistyle_displacement", "theta_cr")


def combine_cases(paths) -> xr.Dataset:
    """Study cube: the scalar measures of every case on dimensions named by the swept parameters."""
    pieces = []
    shared = None
    for path in paths:
        with xr.open_dataset(path) as ds:
            params = [k for k in PARAMETERS if k in ds.coords and ds[k].ndim == 0]
            small = ds[[v for v in CUBE_VARIABLES if v in ds]].load()
            small = small.reset_coords([c for c in small.coords if c not in params], drop=True)
            pieces.append(small.expand_dims(params))
            case_attrs = {k: ds.attrs[k] for k in SHARED_ATTRS if k in ds.attrs}
            shared = case_attrs if shared is None else {
                k: v for k, v in shared.items() if k in case_attrs and str(case_attrs[k]) == str(v)}
    attrs = shared or {}
    cube = xr.combine_by_coords(pieces, combine_attrs="drop_conflicts")
    for name in list(cube.coords):
        if name in PARAMETERS:
            _, units, long_name, _ = PARAMETERS[name]
            cube[name].attrs.update(units=units, long_name=long_name)
    # per-case settings (dt, status, ...) stay in the case files; the cube keeps the shared ones
    cube.attrs = {**attrs, "title": f"dem study cube: {attrs.get('study', '')}", "n_cases": len(pieces)}
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
