"""The output schema: units and long name of every variable and coordinate the solvers write,
what a study cube keeps of a case, and the CF layout of every file.

Every file carries ``units`` and ``long_name`` on every variable and coordinate (xarray
turns them into plot labels). Plain data: this module imports no xarray, so the computing
side can read it without paying for it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import xarray as xr

# the 2D rigid-block engine (stonedem.engine.run.scene_dataset); name: (units, long_name)
SCENE_VARIABLES = {
    "time": ("s", "time"),
    "body": ("1", "body name"),
    "body_role": ("1", "body role (base, drum, capital, epistyle, block)"),
    "body_column": ("1", "column index of the body, -1 when none"),
    "body_mass": ("kg", "body mass"),
    "body_inertia": ("kg m2", "rotational inertia about the centroid"),
    "body_support": ("1", "index of the body it rests on at t = 0, -1 when none"),
    "x": ("m", "horizontal position of the body centroid"),
    "y": ("m", "vertical position of the body centroid"),
    "theta": ("rad", "body rotation, counter-clockwise positive"),
    "base_displacement": ("m", "horizontal base displacement"),
    "base_velocity": ("m s-1", "horizontal base velocity"),
    "base_acceleration": ("m s-2", "horizontal base acceleration"),
    "base_vertical_displacement": ("m", "vertical base displacement"),
    "displacement_relative_to_base": (
        "m",
        "horizontal displacement of the body relative to the base",
    ),
    "sliding": ("m", "sliding of the body along the face of its support since t = 0"),
    "total_sliding": ("m", "total sliding: sum over bodies of absolute sliding (thesis 6)"),
    "rocking": ("rad", "rocking: mean absolute rotation of the drums (thesis 6)"),
    "epistyle_displacement": ("m", "mean horizontal epistyle displacement relative to the base"),
    "energy_kinetic": ("J", "kinetic energy of the free bodies"),
    "energy_potential": ("J", "gravitational potential energy relative to t = 0"),
    "energy_elastic": (
        "J",
        "elastic energy stored in the contacts (Winkler layer + tangential springs)",
    ),
    "energy_dissipated": ("J", "energy dissipated by dashpots and friction since t = 0"),
    "energy_dissipated_normal": ("J", "energy dissipated by the normal dashpots"),
    "energy_dissipated_tangential": (
        "J",
        "energy dissipated by friction slip and tangential dashpots",
    ),
    "energy_base_work": ("J", "work done by the driven base on the free bodies since t = 0"),
    "energy_balance_error": (
        "J",
        "kinetic + potential + elastic + dissipated - base work - initial energy",
    ),
    "n_contact": ("1", "number of contacts"),
    "max_total_sliding": ("m", "maximum total sliding"),
    "residual_total_sliding": ("m", "total sliding at the end of the run"),
    "max_rocking": ("rad", "maximum mean absolute drum rotation"),
    "rocking_onset_time": ("s", "first time rocking exceeds theta_cr / 30 (NaN: never)"),
    "theta_cr": ("rad", "critical angle atan(b/h) of the column (thesis Eq. 6.2)"),
    "collapsed": ("1", "1 when the structure collapsed"),
    "collapse_time": ("s", "time of collapse (NaN: no collapse)"),
    "max_epistyle_displacement": (
        "m",
        "maximum absolute epistyle displacement relative to the base (NaN: no epistyle)",
    ),
    "max_abs_theta": ("rad", "maximum absolute rotation of each body"),
    # an excitation sequence (stonedem.engine.run.part_measures): one row per part
    "part": ("1", "part of the excitation sequence"),
    "part_start": ("s", "start time of the part's window (its motion, then its rest)"),
    "part_description": ("1", "the part's motion"),
    "sequence_part": ("1", "part of the excitation sequence the sample belongs to"),
    "part_max_rocking": ("rad", "maximum rocking over the part's window"),
    "part_max_total_sliding": (
        "m",
        "maximum total sliding (since the sequence's start) over the part's window",
    ),
    "part_max_epistyle_displacement": (
        "m",
        "maximum absolute epistyle displacement relative to the base over the part's window",
    ),
    "part_residual_total_sliding": (
        "m",
        "total sliding since the sequence's start at the end of the part's rest",
    ),
    "part_residual_rocking": ("rad", "mean absolute drum rotation at the end of the part's rest"),
    "part_collapsed": ("1", "1 when the structure collapsed in the part's window"),
    "part_collapse_time": ("s", "time of collapse in the part's window (NaN: none)"),
    "part_at_rest_from": (
        "s",
        "time from which the structure was at rest on the quiet base in the part's rest "
        "(NaN: never, integrated to the end)",
    ),
    "part_run": ("1", "1 when the part was run (0: after a collapse that stopped the run)"),
    # shear links (stonedem.engine.links; only in a scene with links)
    "link": ("1", "shear link index"),
    "link_lower": ("1", "lower body of the link"),
    "link_upper": ("1", "upper body of the link"),
    "link_kind": ("1", "link kind (titanium, wood, custom)"),
    "link_status": ("1", "final state of the link: 0 engaged, 1 broken, 2 pulled out"),
    "link_peak_force": ("N", "peak magnitude of the link force over the run"),
    "link_plastic_slip": ("m", "plastic slip of the link at the end of the run"),
}

# the 3D wall solver (stonedem.wall.dataset.wall_dataset); lambda's units are the case's load units
WALL_VARIABLES = {
    "step": ("1", "load step (0: dead load only)"),
    "block": ("1", "block index"),
    "interface": ("1", "interface index"),
    "dof": ("1", "block degree of freedom: u1 u2 u3 (m), w1 w2 w3 (rad)"),
    "block_x": ("m", "block centre along the wall length"),
    "block_y": ("m", "block centre height"),
    "block_length": ("m", "block (cell) length along the wall"),
    "block_course": ("1", "course index from the bottom"),
    "interface_x": ("m", "interface centroid along the wall length"),
    "interface_y": ("m", "interface centroid height"),
    "interface_width": ("m", "interface side in the wall plane"),
    "interface_kind": ("1", "0 head joint, 1 bed joint, 2 support joint"),
    "interface_first": ("1", "first block of the interface (-1: fixed support)"),
    "interface_second": ("1", "second block of the interface (-1: fixed support)"),
    "interface_normal_axis": (
        "1",
        "interface normal: 0 along e1 (vertical joint), 1 along e2 (horizontal)",
    ),
    "lambda": ("1", "load multiplier (live load / weight, or pressure in Pa for pressure loads)"),
    "control_displacement": (
        "m",
        "out-of-plane displacement of the control DOF since the dead load",
    ),
    "iterations": ("1", "residual iterations of the step"),
    "residual": ("1", "final residual norm / reference load norm"),
    "damage": (
        "1",
        "interface state: 0 elastic, 1 shear, 2 flexural, 3 shear and flexural, 4 detached",
    ),
    "lambda_max": ("1", "limit load multiplier (maximum lambda along the path)"),
    "step_at_limit": ("1", "step where lambda_max is reached"),
    "displacement_at_limit": ("m", "block displacements and rotations (rad) at lambda_max"),
    "displacement_final": ("m", "block displacements and rotations (rad) at the last step"),
    "interface_forces_at_limit": (
        "N",
        "interface actions at lambda_max, local order t1 t2 n (N), b1 b2 tor (N m)",
    ),
    "damage_at_limit": ("1", "interface state at lambda_max (codes as damage)"),
    "lambda_limit_analysis": (
        "1",
        "collapse multiplier by limit analysis (HiGHS LP) with the joint "
        "caps on the pushover's actions at lambda_max: >= lambda_max, equal "
        "when the plateau is the model's collapse load",
    ),
    "lambda_limit_analysis_dead_load": (
        "1",
        "collapse multiplier by limit analysis (HiGHS LP) with the "
        "joint caps on the dead-load actions (needs no pushover)",
    ),
}

# the two solvers' names are disjoint (tests/io/test_netcdf.py), so one lookup serves both
VARIABLES = {**SCENE_VARIABLES, **WALL_VARIABLES}

# what a study cube (stonedem.study.cube.combine_cases) keeps of each case: its scalar measures,
# its time histories (NaN after a case stopped at collapse or ended), and the case
# attributes every case agrees on
CUBE_MEASURES = (
    "collapsed",
    "collapse_time",
    "max_rocking",
    "max_total_sliding",
    "residual_total_sliding",
    "rocking_onset_time",
    "max_epistyle_displacement",
    "theta_cr",
)
# ... and of a sequence's case (excitation: {kind: sequence}), on its ``part`` dimension
CUBE_PART_MEASURES = (
    "part_max_rocking",
    "part_max_total_sliding",
    "part_residual_total_sliding",
    "part_residual_rocking",
    "part_collapsed",
    "part_run",
)
CUBE_HISTORIES = (
    "rocking",
    "total_sliding",
    "epistyle_displacement",
    "base_displacement",
    "base_acceleration",
)
CUBE_SHARED_ATTRS = (
    "source",
    "study",
    "contact_model",
    "contact_law",
    "k_n",
    "c_n",
    "contact_damping",
    "contact_impact",
    "k_t",
    "c_t",
    "friction",
    "excitation",
    "contact_frame",
)


# a threshold search's variables (stonedem.study.cube): "[u]" the searched parameter's units,
# "{p}" its long name; "" no units (text, CF)
SEARCH_VARIABLES = {
    "collapse_threshold": ("[u]", "smallest {p} that collapsed in the search (NaN: none)"),
    "survived_below_threshold": (
        "[u]",
        "largest {p} below the smallest collapse that did not collapse",
    ),
    "bracket_width": ("1", "collapse_threshold / survived_below_threshold - 1"),
    "n_runs": ("1", "simulations the search ran"),
    "monotonic": (
        "1",
        "1 when no run above the smallest collapse survived (collapse monotonic on the runs)",
    ),
    "n_resurrections": ("1", "runs above the smallest collapse that did not collapse"),
    "search_status": ("", "how the search ended (stonedem.study.search)"),
    "search_order": ("1", "order in which the search ran this case, from 0"),
    "search_phase": ("", "search phase of the run: hunt, bisect or fill"),
}


def attrs_for(name: str) -> dict:
    """``units`` and ``long_name`` of a variable or coordinate either solver writes."""
    units, long_name = VARIABLES[name]
    return {"units": units, "long_name": long_name}


CONVENTIONS = "CF-1.10"


def _is_text(var) -> bool:
    return var.dtype.kind in "OUS"


def missing_metadata(ds: xr.Dataset) -> list[str]:
    """Names of variables or coordinates lacking ``long_name``, or ``units`` on a numeric
    one (CF: text variables carry no units); empty = self-describing."""
    return [
        name
        for name in list(ds.data_vars) + list(ds.coords)
        if not ds[name].attrs.get("long_name")
        or (not _is_text(ds[name]) and not ds[name].attrs.get("units"))
    ]


def cf_conventions(ds: xr.Dataset) -> xr.Dataset:
    """The dataset as CF-1.10 wants it: ``Conventions``, a ``time`` coordinate with
    ``standard_name``/``axis``, no ``units`` on text variables (a copy; data shared)."""
    ds = ds.copy()
    ds.attrs["Conventions"] = CONVENTIONS
    if "time" in ds.coords and ds["time"].dtype.kind == "f":
        ds["time"].attrs.update(standard_name="time", axis="T")
    for name in list(ds.data_vars) + list(ds.coords):
        if _is_text(ds[name]) and ds[name].attrs.get("units") in ("1", ""):
            ds[name].attrs = {k: v for k, v in ds[name].attrs.items() if k != "units"}
    return ds
