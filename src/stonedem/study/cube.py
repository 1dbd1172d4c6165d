"""Study cubes: a grid study's case files combined (:func:`combine_cases`), and the datasets of
threshold searches: one system's runs (a ``run`` dimension, sorted by the searched value) with
its bracket, and a study's systems combined into its cube.

In a search study's cube the searched parameter (e.g. ``pga``) is a coordinate on
(system parameters..., run), not a dimension: each system ran its own values.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.netcdf import open_result, schema_variables
from stonedem.io.schema import (
    CUBE_HISTORIES,
    CUBE_MEASURES,
    CUBE_PART_MEASURES,
    CUBE_SHARED_ATTRS,
    SEARCH_VARIABLES,
)
from stonedem.study.grid import CASE_PARAMETERS, MEMBER, PARAMETERS, Case
from stonedem.study.search import Run


def _attrs(name: str, parameter: str) -> dict:
    units, long_name = SEARCH_VARIABLES[name]
    _, p_units, p_long, _ = PARAMETERS[parameter]
    attrs = {"long_name": long_name.replace("{p}", p_long)}
    if units:  # text variables carry no units (CF)
        attrs["units"] = p_units if units == "[u]" else units
    return attrs


@dataclass
class RunPiece:
    """What a threshold search keeps of one run: the cube's measures and histories
    (CUBE_MEASURES, CUBE_HISTORIES) as numpy arrays, and the attributes a cube may share."""

    params: dict  # the case's swept parameters (the searched one included)
    time: (
        np.ndarray
    )  # output times [s], rounded to 1e-9 s (runs of different dt sample the same times)
    variables: dict  # name -> (dims, values), dims () or ("time",)
    attrs: dict  # CUBE_SHARED_ATTRS as the run's dataset states them
    collapsed: bool


def run_piece(case: Case, run, histories: bool = True) -> RunPiece:
    """The piece of a run (:class:`stonedem.engine.run.CheckedRun`) of ``case``, without
    building its dataset; ``histories`` False: its measures alone."""
    from stonedem.engine.run import contact_attrs, response_measures
    from stonedem.io.netcdf import code_version
    from stonedem.io.provenance import bounded_json

    response = response_measures(run.scene, run.result, run.checks, histories)
    attrs = {
        "source": code_version(),
        "study": case.study,
        **contact_attrs(run.scene),
        "excitation": bounded_json(run.scene.horizontal.description, "excitation"),
    }
    return RunPiece(
        dict(case.params),
        np.round(run.result.time, 9),
        {name: response[name] for name in CUBE_MEASURES + CUBE_HISTORIES if name in response},
        {k: attrs[k] for k in CUBE_SHARED_ATTRS if k in attrs},
        bool(response["collapsed"][1]),
    )


def dataset_piece(ds: xr.Dataset) -> RunPiece:
    """The piece of a run's case dataset (a file of a grid or a full search run)."""
    small = case_piece(ds)
    params = {name: small[name].values.item() for name in case_parameters(ds)}
    variables = {
        name: (small[name].dims, small[name].values)
        for name in small.data_vars
        if "part" not in small[name].dims  # a sequence's per-part measures: grid cubes only
    }
    time = small["time"].values if "time" in small.coords else np.zeros(0)
    return RunPiece(
        params,
        time,
        variables,
        {k: ds.attrs[k] for k in CUBE_SHARED_ATTRS if k in ds.attrs},
        bool(small["collapsed"] > 0),
    )


def search_dataset(system: Case, runs: list[Run], cases: list, result: dict) -> xr.Dataset:
    """One system's search: every run's measures and histories along ``run`` (sorted by
    value; histories padded with NaN to the longest run), its bracket and how the search
    went (stonedem.study.search.summary).

    ``cases``: each run's :class:`RunPiece`, case dataset or case file."""
    parameter = system.search.parameter
    order = sorted(range(len(runs)), key=lambda i: runs[i].value)
    pieces = []
    for i in order:
        if isinstance(cases[i], RunPiece):
            pieces.append(cases[i])
        elif isinstance(cases[i], xr.Dataset):
            pieces.append(dataset_piece(cases[i]))
        else:
            with open_result(cases[i]) as ds:
                pieces.append(dataset_piece(ds))
    time = np.unique(np.concatenate([piece.time for piece in pieces]))
    data = {}
    for name in dict.fromkeys(n for piece in pieces for n in piece.variables):
        dims = next(piece.variables[name][0] for piece in pieces if name in piece.variables)
        if dims != () and not system.search.histories:
            continue
        if dims == ():
            values = [
                piece.variables[name][1] if name in piece.variables else np.nan for piece in pieces
            ]
            data[name] = (("run",), np.array(values))
            continue
        history = np.full((len(pieces), len(time)), np.nan)
        for k, piece in enumerate(pieces):
            if name in piece.variables:
                history[k, np.searchsorted(time, piece.time)] = piece.variables[name][1]
        data[name] = (("run", "time"), history)
    cube = xr.Dataset(
        schema_variables(data),
        coords=schema_variables({"time": (("time",), time)} if system.search.histories else {}),
    )
    params = {}
    for name in pieces[0].params:
        values = [piece.params.get(name) for piece in pieces]
        _, units, long_name, _ = CASE_PARAMETERS[name]
        attrs = {"units": units, "long_name": long_name}
        same = all(v == values[0] for v in values)
        params[name] = (
            xr.Variable((), values[0], attrs)
            if same and name != parameter
            else xr.Variable(("run",), np.array(values), attrs)
        )
    cube = cube.assign_coords(params).assign_coords(run=np.arange(len(order)))
    cube["run"].attrs = {"units": "1", "long_name": f"run of the search, by increasing {parameter}"}
    values = {
        "search_order": (("run",), np.array(order, dtype=np.int32)),
        "search_phase": (("run",), np.array([runs[i].phase for i in order], dtype=object)),
        "collapse_threshold": ((), result["upper"]),
        "survived_below_threshold": ((), result["lower"]),
        "bracket_width": ((), result["width"]),
        "n_runs": ((), np.int32(result["n_runs"])),
        "monotonic": ((), np.int8(result["monotonic"])),
        "n_resurrections": ((), np.int32(len(result["resurrections"]))),
        "search_status": ((), result["status"]),
    }
    # in one update: each item assigned alone costs a merge (~0.7 ms a search run in all)
    cube = cube.assign(
        {
            name: xr.Variable(dims, value, _attrs(name, parameter))
            for name, (dims, value) in values.items()
        }
    )
    settings = {
        f"search_{k}": int(v) if isinstance(v, bool) else v
        for k, v in asdict(system.search).items()
    }
    cube.attrs = {
        **shared_case_attrs([piece.attrs for piece in pieces]),
        **settings,
        "search_method": "hunt and fill (Vamvatsikos & Cornell 2002), stonedem.study.search",
        "resurrections": " ".join(f"{v:g}" for v in result["resurrections"]),
        "title": f"stonedem threshold search: {system.study}/{system.id}",
        "case": system.id,
    }
    return cube


def combine_searches(paths, description: str = "", stripes: dict | None = None) -> xr.Dataset:
    """A search study's cube: each system's search (:func:`search_dataset`) on dimensions
    named by the system's parameters, runs padded with NaN to the longest search.

    ``stripes``: {system id: its stripe fills on ``stripe_run``} of an ensemble study
    (:func:`stonedem.study.stripe_fill.stripe_pieces`), kept beside that system's runs; their
    count goes to attrs ``stripe_fills`` (0: the fills ran and none was needed)."""
    pieces, attrs = [], []
    parameter = None
    for path in paths:
        with open_result(path) as ds:
            ds = ds.load()
        parameter = ds.attrs.get("search_parameter", parameter)
        if stripes and ds.attrs.get("case") in stripes:
            ds = xr.merge([ds, stripes[ds.attrs["case"]]], combine_attrs="override")
        # the searched values become a variable, expanded with the rest; a coordinate again after
        pieces.append(on_parameter_dimensions(ds.reset_coords([parameter]), case_parameters(ds)))
        attrs.append(dict(ds.attrs))
    if not pieces:
        raise InputError("searches", "no searches to combine", "run the study's searches first")
    merged = xr.merge(pieces, join="outer", compat="no_conflicts", combine_attrs="drop").set_coords(
        parameter
    )
    cube = described_like(merged, paths[0])
    settings = {k: v for k, v in attrs[0].items() if k.startswith("search_")}
    cube.attrs = {
        **shared_case_attrs(attrs),
        **settings,
        "title": f"stonedem study cube (threshold searches): {attrs[0].get('study', '')}",
        "n_systems": len(pieces),
        "n_cases": int(cube["n_runs"].sum()),
        "description": description,
    }
    if stripes is not None:  # an ensemble study whose fills ran (none may have been needed)
        cube.attrs["stripe_fills"] = int(
            sum(piece.sizes.get("stripe_run", 0) for piece in stripes.values())
        )
    return cube


def member_summary(cube: xr.Dataset) -> xr.Dataset:
    """A grid cube of an ensemble (a ``member`` dimension) as its figures and tables read it:
    ``collapsed`` the collapse fraction (0 or 1 where K = 1), the other measures their median
    over members, histories member 0's (the case as configured). A cube without members as it is."""
    if MEMBER not in cube.dims:
        return cube
    first = cube[MEMBER].values.min()
    out = cube.sel({MEMBER: first}, drop=True)
    if "run" in cube.dims:  # a search study's runs: member 0's searches (Table 7.1 reads them all)
        out.attrs = {**cube.attrs, "members": int(cube.sizes[MEMBER])}
        return out
    for name, var in cube.data_vars.items():
        if MEMBER in var.dims and "time" not in var.dims and var.dtype.kind in "fiu":
            out[name] = var.median(MEMBER).assign_attrs(var.attrs)
    out["collapsed"] = collapse_fraction(cube["collapsed"])
    out.attrs = {**cube.attrs, "members": int(cube.sizes[MEMBER])}
    return out


# --- a grid study's cube from its cases' files (moved from stonedem.study.grid) -------------


def case_piece(ds: xr.Dataset) -> xr.Dataset:
    """What a cube keeps of one case file: its measures and histories, its swept parameters
    as scalar coordinates, output times rounded (cases of different dt sample the same
    times to within rounding)."""
    params = case_parameters(ds)
    names = [v for v in CUBE_MEASURES + CUBE_HISTORIES + CUBE_PART_MEASURES if v in ds]
    small = ds[names].load()
    small = small.reset_coords(
        [c for c in small.coords if c not in params and c not in ("time", "part")], drop=True
    )
    if "time" in small.coords:
        small = small.assign_coords(
            time=("time", np.round(small["time"].values, 9), small["time"].attrs)
        )
    return small


def case_parameters(ds: xr.Dataset) -> list[str]:
    """The parameters of a case (or search) file: its scalar coordinates in CASE_PARAMETERS."""
    return [k for k in CASE_PARAMETERS if k in ds.coords and ds[k].ndim == 0]


def on_parameter_dimensions(piece: xr.Dataset, params: list[str]) -> xr.Dataset:
    """``piece`` with its scalar parameters as dimensions of length one, ready to merge;
    strings as objects (merging fixed-width unicode truncates 'per_span' to the width of 'a')."""
    piece = piece.expand_dims(params)
    return piece.assign_coords(
        {k: piece[k].astype(object) for k in params if piece[k].dtype.kind == "U"}
    )


def shared_case_attrs(attrs: list[dict]) -> dict:
    """The case attributes a cube keeps: those of CUBE_SHARED_ATTRS every case agrees on."""
    shared = None
    for case_attrs in attrs:
        case_attrs = {k: case_attrs[k] for k in CUBE_SHARED_ATTRS if k in case_attrs}
        shared = (
            case_attrs
            if shared is None
            else {
                k: v for k, v in shared.items() if k in case_attrs and str(case_attrs[k]) == str(v)
            }
        )
    return shared or {}


def described_like(cube: xr.Dataset, path) -> xr.Dataset:
    """``cube`` (merged, attributes dropped) with the variable attributes of the file it was
    combined from first, and each swept parameter's units and long name (PARAMETERS)."""
    with open_result(path) as first:
        for name in cube.variables:
            if name in first.variables and name not in CASE_PARAMETERS:
                cube[name].attrs = dict(first[name].attrs)
    for name in cube.coords:
        if name in CASE_PARAMETERS:
            _, units, long_name, _ = CASE_PARAMETERS[name]
            cube[name].attrs.update(units=units, long_name=long_name)
    return cube


def collapse_fraction(collapsed: xr.DataArray) -> xr.DataArray:
    """The share of an ensemble's members that collapsed, per case (NaN where none ran)."""
    return collapsed.mean(MEMBER).assign_attrs(
        units="1",
        long_name=f"collapse fraction over the ensemble's {collapsed.sizes[MEMBER]} members",
    )


def merged_pieces(pieces: list[xr.Dataset]) -> xr.Dataset:
    """The pieces merged by coordinates with an outer join, two at a time up a tree.

    One merge of every piece reindexes each to the whole cube first: 360 cases of a 5-member
    study made 360 copies of its 90 MB cube and were killed at 24 GB. Up a tree a piece is
    reindexed to its subtree's extent only, and each cell still comes from the one case that
    has it; the union of an index is sorted either way, so the cube is the same. An integer
    variable that a subtree padded with NaN gets its dtype back where the whole cube has none,
    as one merge leaves it."""
    dtypes = {name: var.dtype for name, var in pieces[0].data_vars.items()}
    while len(pieces) > 1:
        pieces = [
            xr.merge(pieces[i : i + 2], join="outer", compat="no_conflicts", combine_attrs="drop")
            for i in range(0, len(pieces), 2)
        ]
    cube = pieces[0]
    for name, dtype in dtypes.items():
        var = cube[name]
        if var.dtype != dtype and dtype.kind in "biu" and not var.isnull().any():
            cube[name] = var.astype(dtype)
    return cube


def combine_cases(paths, description: str = "") -> xr.Dataset:
    """Study cube: each case's measures and histories on dimensions named by the swept parameters.

    Cases are merged by coordinates with an outer join, so a study of listed cases (not a
    full grid) gives a cube with NaN where a combination was not run.
    """
    pieces, attrs = [], []
    for path in paths:
        with open_result(path) as ds:
            pieces.append(on_parameter_dimensions(case_piece(ds), case_parameters(ds)))
            attrs.append(dict(ds.attrs))
    if not pieces:
        raise InputError("cases", "no case files to combine", "run the study's cases first")
    cube = described_like(merged_pieces(pieces), paths[0])
    if (
        MEMBER in cube.dims
    ):  # an ensemble (issue 44): the verdicts stay per member, beside their share
        cube["collapse_fraction"] = collapse_fraction(cube["collapsed"])
    # per-case settings (dt, status, ...) stay in the case files; the cube keeps the shared ones
    shared = shared_case_attrs(attrs)
    cube.attrs = {
        **shared,
        "title": f"stonedem study cube: {shared.get('study', '')}",
        "n_cases": len(pieces),
        "description": description,
    }
    return cube
