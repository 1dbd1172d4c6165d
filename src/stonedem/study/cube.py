"""Datasets of threshold searches: one system's runs (a ``run`` dimension, sorted by the
searched value) with its bracket, and a study's systems combined into its cube.

In a search study's cube the searched parameter (e.g. ``pga``) is a coordinate on
(system parameters..., run), not a dimension: each system ran its own values.
"""

from __future__ import annotations

from contextlib import nullcontext
from dataclasses import asdict
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.schema import SEARCH_VARIABLES
from stonedem.study.grid import (MEMBER, PARAMETERS, collapse_fraction, Case, case_parameters, case_piece, described_like, on_parameter_dimensions, shared_case_attrs)
from stonedem.study.search import Run
from stonedem.io.netcdf import open_result

def _attrs(name: str, parameter: str) -> dict:
    units, long_name = SEARCH_VARIABLES[name]
    _, p_units, p_long, _ = PARAMETERS[parameter]
    attrs = {"long_name": long_name.replace("{p}", p_long)}
    if units:  # text variables carry no units (CF)
        attrs["units"] = p_units if units == "[u]" else units
    return attrs


def search_dataset(system: Case, runs: list[Run], cases: list[Path | str | xr.Dataset], result: dict) -> xr.Dataset:
    """One system's search: every run's measures and histories along ``run`` (sorted by
    value), its bracket and how the search went (stonedem.study.search.summary).

    ``cases``: each run's case file, or the case dataset that was written to it (the same
    search as from the file, without reading it back: ~40 ms a run in the IDA)."""
    parameter = system.search.parameter
    order = sorted(range(len(runs)), key=lambda i: runs[i].value)
    pieces, attrs = [], []
    for i in order:
        with (nullcontext(cases[i]) if isinstance(cases[i], xr.Dataset) else open_result(cases[i])) as ds:
            pieces.append(case_piece(ds))
            attrs.append(dict(ds.attrs))
    cube = xr.concat(pieces, dim="run", coords="different", compat="equals", join="outer",
                     combine_attrs="drop")
    cube = cube.assign_coords(run=np.arange(len(order)))
    for name in cube.variables:  # concat keeps no variable attributes: the cases' own
        if name in pieces[0].variables:
            cube[name].attrs = dict(pieces[0][name].attrs)
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
    for name, (dims, value) in values.items():
        cube[name] = xr.Variable(dims, value, _attrs(name, parameter))
    settings = {f"search_{k}": v for k, v in asdict(system.search).items()}
    cube.attrs = {**shared_case_attrs(attrs), **settings,
                  "search_method": "hunt and fill (Vamvatsikos & Cornell 2002), stonedem.study.search",
                  "resurrections": " ".join(f"{v:g}" for v in result["resurrections"]),
                  "title": f"stonedem threshold search: {system.study}/{system.id}", "case": system.id}
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
    merged = xr.merge(pieces, join="outer", compat="no_conflicts", combine_attrs="drop").set_coords(parameter)
    cube = described_like(merged, paths[0])
    settings = {k: v for k, v in attrs[0].items() if k.startswith("search_")}
    cube.attrs = {**shared_case_attrs(attrs), **settings,
                  "title": f"stonedem study cube (threshold searches): {attrs[0].get('study', '')}",
                  "n_systems": len(pieces), "n_cases": int(cube["n_runs"].sum()), "description": description}
    if stripes is not None:  # an ensemble study whose fills ran (none may have been needed)
        cube.attrs["stripe_fills"] = int(sum(piece.sizes.get("stripe_run", 0) for piece in stripes.values()))
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
