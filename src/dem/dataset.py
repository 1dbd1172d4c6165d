"""The output schema: every variable's dims, units and long name; building and atomic writing.

Both solvers write through this module, so every file carries ``units`` and ``long_name``
on every variable and coordinate (xarray turns them into plot labels), the full input as
JSON in ``attrs["scene"]``, solver settings and the code version in attrs.
"""

from __future__ import annotations

import json
import platform
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import xarray as xr

from dem.atomic import write_atomically

import dem

# name: (units, long_name)
VARIABLES = {
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
    "displacement_relative_to_base": ("m", "horizontal displacement of the body relative to the base"),
    "sliding": ("m", "sliding of the body along the face of its support since t = 0"),
    "total_sliding": ("m", "total sliding: sum over bodies of absolute sliding (thesis 6)"),
    "rocking": ("rad", "rocking: mean absolute rotation of the drums (thesis 6)"),
    "epistyle_displacement": ("m", "mean horizontal epistyle displacement relative to the base"),
    "energy_kinetic": ("J", "kinetic energy of the free bodies"),
    "energy_potential": ("J", "gravitational potential energy relative to t = 0"),
    "energy_elastic": ("J", "elastic energy stored in the contacts (Winkler layer + tangential springs)"),
    "energy_dissipated": ("J", "energy dissipated by dashpots and friction since t = 0"),
    "energy_dissipated_normal": ("J", "energy dissipated by the normal dashpots"),
    "energy_dissipated_tangential": ("J", "energy dissipated by friction slip and tangential dashpots"),
    "energy_base_work": ("J", "work done by the driven base on the free bodies since t = 0"),
    "energy_balance_error": ("J", "kinetic + potential + elastic + dissipated - base work - initial energy"),
    "n_contact": ("1", "number of contacts"),
    "max_total_sliding": ("m", "maximum total sliding"),
    "residual_total_sliding": ("m", "total sliding at the end of the run"),
    "max_rocking": ("rad", "maximum mean absolute drum rotation"),
    "rocking_onset_time": ("s", "first time rocking exceeds theta_cr / 30 (NaN: never)"),
    "theta_cr": ("rad", "critical angle atan(b/h) of the column (thesis Eq. 6.2)"),
    "collapsed": ("1", "1 when the structure collapsed"),
    "collapse_time": ("s", "time of collapse (NaN: no collapse)"),
    "max_epistyle_displacement": ("m", "maximum absolute epistyle displacement relative to the base (NaN: no epistyle)"),
    "max_abs_theta": ("rad", "maximum absolute rotation of each body"),
}


def attrs_for(name: str) -> dict:
    units, long_name = VARIABLES[name]
    return {"units": units, "long_name": long_name}


def code_version() -> str:
    """dem version, with the git commit when run from a checkout."""
    import subprocess

    try:
        here = Path(__file__).resolve().parent
        commit = subprocess.run(["git", "-C", str(here), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, timeout=5)
        if commit.returncode == 0:
            return f"dem {dem.__version__} ({commit.stdout.strip()})"
    except (OSError, subprocess.SubprocessError):
        pass
    return f"dem {dem.__version__}"


def scene_dataset(scene, result, checks: dict | None = None) -> xr.Dataset:
    """Dataset of one simulated scene: histories, energies, response measures, provenance.

    ``checks``: :func:`dem.simulate.run_checks` (computed here when not given); a penetrated
    run is never reported as a collapse."""
    from dem import measures
    from dem.kernels import step
    from dem.simulate import pack_scene

    time = result.time
    names = scene.body_names
    d_h, v_h, a_h = scene.horizontal.evaluate(time)
    d_v, _, _ = scene.vertical.evaluate(time)
    e = result.energy
    support = measures.supports(scene)
    sliding = measures.relative_sliding(scene, result.x, result.y, result.theta, support)
    free = np.array([not b.driven for b in scene.bodies])
    total_sliding = np.abs(sliding[:, free]).sum(axis=1)
    rock_idx = measures.rocking_bodies(scene)
    rocking = np.abs(result.theta[:, rock_idx]).mean(axis=1)
    arrays = pack_scene(scene)
    groups = np.unique(arrays.body_group[rock_idx])
    theta_cr = float(arrays.group_theta_cr[groups].min())
    rel = result.x - result.x[0] - d_h[:, None]
    epistyles = [i for i, b in enumerate(scene.bodies) if b.role == "epistyle"]
    epi = rel[:, epistyles].mean(axis=1) if epistyles else np.full(len(time), np.nan)

    kinetic = e[:, step.ENERGY_KINETIC]
    potential = e[:, step.ENERGY_POTENTIAL] - e[0, step.ENERGY_POTENTIAL]
    elastic = e[:, step.ENERGY_ELASTIC]
    diss_n = e[:, step.ENERGY_DAMPING]
    diss_t = e[:, step.ENERGY_TANGENTIAL]
    base_work = e[:, step.ENERGY_BASE_WORK]
    balance = kinetic + potential + elastic + diss_n + diss_t - base_work
    balance = balance - (kinetic[0] + elastic[0])
    if checks is None:
        from dem.simulate import run_checks

        checks = run_checks(scene, result)
    collapsed = result.collapse_sample >= 0 and checks["status"] != "penetrated"
    collapse_time = float(time[result.collapse_sample]) if collapsed else float("nan")

    def var(name, dims, data):
        return xr.Variable(dims, data, attrs=attrs_for(name))

    tb = ("time", "body")
    data_vars = {
        "x": var("x", tb, result.x), "y": var("y", tb, result.y),
        "theta": var("theta", tb, result.theta),
        "base_displacement": var("base_displacement", ("time",), d_h),
        "base_velocity": var("base_velocity", ("time",), v_h),
        "base_acceleration": var("base_acceleration", ("time",), a_h),
        "base_vertical_displacement": var("base_vertical_displacement", ("time",), d_v),
        "displacement_relative_to_base": var("displacement_relative_to_base", tb, rel),
        "sliding": var("sliding", tb, sliding),
        "total_sliding": var("total_sliding", ("time",), total_sliding),
        "rocking": var("rocking", ("time",), rocking),
        "epistyle_displacement": var("epistyle_displacement", ("time",), epi),
        "energy_kinetic": var("energy_kinetic", ("time",), kinetic),
        "energy_potential": var("energy_potential", ("time",), potential),
        "energy_elastic": var("energy_elastic", ("time",), elastic),
        "energy_dissipated": var("energy_dissipated", ("time",), diss_n + diss_t),
        "energy_dissipated_normal": var("energy_dissipated_normal", ("time",), diss_n),
        "energy_dissipated_tangential": var("energy_dissipated_tangential", ("time",), diss_t),
        "energy_base_work": var("energy_base_work", ("time",), base_work),
        "energy_balance_error": var("energy_balance_error", ("time",), balance),
        "n_contact": var("n_contact", ("time",), result.n_contact.astype(np.int32)),
        "max_abs_theta": var("max_abs_theta", ("body",), np.abs(result.theta).max(axis=0)),
        "max_total_sliding": var("max_total_sliding", (), float(total_sliding.max())),
        "residual_total_sliding": var("residual_total_sliding", (), float(total_sliding[-1])),
        "max_rocking": var("max_rocking", (), float(rocking.max())),
        "theta_cr": var("theta_cr", (), theta_cr),
        "rocking_onset_time": var("rocking_onset_time", (),
                                  measures.rocking_onset_time(time, rocking, theta_cr)),
        "collapsed": var("collapsed", (), np.int8(collapsed)),
        "collapse_time": var("collapse_time", (), collapse_time),
        "max_epistyle_displacement": var("max_epistyle_displacement", (),
                                         float(np.nanmax(np.abs(epi))) if epistyles else float("nan")),
    }
    coords = {
        "time": var("time", ("time",), time),
        "body": var("body", ("body",), np.array(names, dtype=object)),
        "body_role": var("body_role", ("body",), np.array([b.role for b in scene.bodies], dtype=object)),
        "body_column": var("body_column", ("body",), np.array([b.column for b in scene.bodies], dtype=np.int32)),
        "body_mass": var("body_mass", ("body",), np.array([b.mass for b in scene.bodies])),
        "body_inertia": var("body_inertia", ("body",), np.array([b.inertia for b in scene.bodies])),
        "body_support": var("body_support", ("body",), np.array(support, dtype=np.int32)),
    }
    law = scene.contact
    attrs = {
        "title": f"dem rigid-block simulation: {scene.spec.get('name', 'scene')}",
        "source": code_version(),
        "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')} simulated by dem.simulate",
        "platform": f"python {platform.python_version()}, numba {_numba_version()}",
        "scene": json.dumps(scene.spec, sort_keys=True, default=str),
        "excitation": json.dumps(scene.horizontal.description, sort_keys=True, default=str),
        "excitation_vertical": json.dumps(scene.vertical.description, sort_keys=True, default=str),
        "dt": result.dt, "dt_units": "s",
        "dt_stability_limit": result.dt_limit,
        "dt_safety": scene.dt_safety if scene.dt is None else result.dt / result.dt_limit,
        "dt_mode": "auto" if scene.dt is None else "given",
        "output_interval": result.out_every * result.dt,
        "contact_model": law.model,
        "contact_law": ("point contacts at the contact face's end vertices, k_n per unit contact length"
                        if law.model == "point" else "overlap area, thesis Eq. 3.4-3.6"),
        "k_n": law.k_n, "k_n_units": "N m-2", "c_n": law.c_n, "c_n_units": "N s m-1",
        "contact_damping": law.damping, "contact_damping_units": "1", "contact_impact": law.impact if law.model == "point" else "none",
        "k_t": law.k_t, "k_t_units": "N m-1",
        "c_t": law.c_t, "c_t_units": "N s m-1",
        "friction": scene.friction, "gravity": scene.gravity, "depth": scene.depth,
        "duration": scene.duration, "n_steps": result.n_steps, "steps_run": result.steps_run,
        "stop_on_collapse": int(scene.stop_on_collapse),
        "skip_quiet": int(scene.skip_quiet),
        "quiet_lead_skipped": result.quiet_lead, "quiet_lead_skipped_units": "s",
        "at_rest_from": result.rest_time, "at_rest_from_units": "s",
        "status": checks["status"],
        "energy_error": checks["energy_error"],
        "energy_error_definition": "max |energy balance drift| / energy the run moves (dem.simulate.energy_drift)",
        "energy_error_limit": _limit("ENERGY_TOLERANCE"),
        "penetration": checks["penetration"],
        "penetration_definition": "largest overlap of two bodies over the samples / the smaller body's area",
        "penetration_limit": _limit("PENETRATION_LIMIT"),
        "wall_seconds": result.wall_seconds,
        "integrator": "central difference (leapfrog form), thesis Eq. 3.7-3.16",
        "contact_frame": law.frame,
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _limit(name: str) -> float:
    import dem.simulate

    return float(getattr(dem.simulate, name))


def _numba_version() -> str:
    import numba

    return numba.__version__


CONVENTIONS = "CF-1.10"


def _is_text(var) -> bool:
    return var.dtype.kind in "OUS"


def missing_metadata(ds: xr.Dataset) -> list[str]:
    """Names of variables or coordinates lacking ``long_name``, or ``units`` on a numeric
    one (CF: text variables carry no units); empty = self-describing."""
    return [name for name in list(ds.data_vars) + list(ds.coords)
            if not ds[name].attrs.get("long_name")
            or (not _is_text(ds[name]) and not ds[name].attrs.get("units"))]


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


def write_dataset(ds: xr.Dataset, path: str | Path) -> Path:
    """Write NetCDF atomically (a temporary file beside ``path``, renamed over it), CF-1.10:
    coordinates without a fill value, float data compressed."""
    ds = cf_conventions(ds)
    encoding = {name: {"zlib": True, "complevel": 4} for name, v in ds.data_vars.items()
                if v.dtype.kind == "f" and v.ndim > 0}
    for name in ds.coords:
        if ds[name].dtype.kind == "f":
            encoding[name] = {"_FillValue": None}
    return write_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding))
