"""NetCDF dataset of one wall pushover: curve, limit load, damage per step, inputs in attrs."""

from __future__ import annotations

import json
from contextlib import contextmanager
from datetime import datetime, timezone

import numpy as np
import xarray as xr

from stonedem.entry import check_interrupt
from stonedem.io.netcdf import code_version, schema_variables, write_dataset
from stonedem.io.provenance import bounded_json
from stonedem.wall.constitutive import STATE_NAMES
from stonedem.wall.limit_analysis import ORACLE_TOLERANCE
from stonedem.wall.panel import KIND_NAMES
from stonedem.wall.validation import LIMIT_TOLERANCE


def wall_dataset(case, result, pressure_units="Pa") -> xr.Dataset:
    panel = case.model.panel
    nb = panel.n_blocks
    lam_units = pressure_units if case.load_kind == "pressure" else "1"
    q = result.q.reshape(len(result.q), nb, 6)
    data = schema_variables(
        {
            "lambda": (("step",), result.lam),
            "control_displacement": (("step",), result.control),
            "iterations": (("step",), result.iterations.astype(np.int32)),
            "residual": (("step",), result.residual),
            "damage": (("step", "interface"), result.state.astype(np.int8)),
            "lambda_max": ((), result.lambda_max),
            "step_at_limit": ((), np.int32(result.step_max)),
            "displacement_at_limit": (("block", "dof"), q[result.step_max]),
            "displacement_final": (("block", "dof"), q[-1]),
            "interface_forces_at_limit": (("interface", "dof"), result.interface_forces_at_max),
            "damage_at_limit": (("interface",), result.state[result.step_max].astype(np.int8)),
        }
    )
    data["lambda"].attrs["units"] = lam_units
    data["lambda_max"].attrs["units"] = lam_units
    if not result.limit_reached:
        data["lambda_max"].attrs["comment"] = result.limit_note
    coords = schema_variables(
        {
            "step": (("step",), np.arange(len(result.lam), dtype=np.int32)),
            "block": (("block",), np.arange(nb, dtype=np.int32)),
            "interface": (("interface",), np.arange(panel.n_interfaces, dtype=np.int32)),
            "dof": (("dof",), np.array(["u1", "u2", "u3", "w1", "w2", "w3"], dtype=object)),
            "block_x": (("block",), panel.centre[:, 0]),
            "block_y": (("block",), panel.centre[:, 1]),
            "block_length": (("block",), panel.size[:, 0]),
            "block_course": (("block",), panel.course.astype(np.int32)),
            "interface_x": (("interface",), panel.centroid[:, 0]),
            "interface_y": (("interface",), panel.centroid[:, 1]),
            "interface_width": (("interface",), panel.width),
            "interface_kind": (("interface",), panel.kind.astype(np.int8)),
            "interface_first": (("interface",), panel.first.astype(np.int32)),
            "interface_second": (("interface",), panel.second.astype(np.int32)),
            "interface_normal_axis": (("interface",), panel.normal_axis.astype(np.int8)),
        }
    )
    spec = case.spec
    joints = spec["joints"]
    attrs = {
        "title": f"stonedem 3D rigid-block wall pushover: {case.name}",
        "source": code_version(),
        "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')} "
        "stonedem.wall.pushover",
        "case": bounded_json(spec, "case", check=check_interrupt),
        "case_name": case.name,
        "load_kind": case.load_kind,
        "lambda_units": lam_units,
        "joint_kind": joints["kind"],
        "mu": float(joints["mu"]),
        "k_n": float(joints["k_n"]),
        "k_n_units": "N m-3",
        "k_t": float(joints["k_t"]),
        "k_t_units": "N m-3",
        "tensile_strength": float(joints.get("tensile_strength", 0.0)),
        "tensile_strength_units": "Pa",
        "alpha": float(joints.get("alpha", 1.5)),
        "block_a": float(spec["panel"]["block"]["a"]),
        "block_b": float(spec["panel"]["block"]["b"]),
        "block_s": float(spec["panel"]["block"]["s"]),
        "block_units": "m",
        "n_blocks": nb,
        "n_interfaces": panel.n_interfaces,
        "panel_length": panel.length,
        "panel_height": panel.height,
        "control_dof": result.control_dof,
        "control_block": result.control_dof // 6,
        # the status says when the path ended before a limit (max_steps, max_seconds, ...)
        "status": result.status
        if result.limit_reached
        else f"{result.status}; {result.limit_note}",
        "limit_reached": "yes" if result.limit_reached else "no",
        # every plateau (and end past a peak) the path met, with the limit analysis on its caps
        "plateau_checks": "; ".join(result.plateau_checks) or "none",
        "wall_seconds": result.wall_seconds,
        "solver": "generalized displacement control (load-weighted mean displacement), "
        "bordered Newton "
        "with the consistent tangent of the Eq. 9-14 return map (forward differences) and "
        "residual line search; banded LU (LAPACK dgbtrf), sparse LU (scipy splu) for a wide band",
        "solver_settings": json.dumps(result.settings, sort_keys=True),
        "damage_codes": json.dumps(STATE_NAMES),
        "interface_kinds": json.dumps(KIND_NAMES),
    }
    for key, val in result.settings.items():
        attrs[f"solver_{key}"] = val
    if "reference" in spec:
        attrs["reference"] = json.dumps(spec["reference"], sort_keys=True)
        ref = spec["reference"].get("lambda_dem", spec["reference"].get("p_dem"))
        if ref:  # the verdict travels with the data, not only in the tables
            err = float(result.lambda_max) / float(ref) - 1
            attrs["manuscript_dem"] = float(ref)
            attrs["error_vs_manuscript_dem"] = err
            attrs["within_tolerance"] = (
                ("yes" if abs(err) <= LIMIT_TOLERANCE else "no")
                if result.limit_reached
                else "not determined: no limit load reached"
            )
            attrs["tolerance"] = f"{LIMIT_TOLERANCE:.0%} of the manuscript DEM limit load"
    return xr.Dataset(data, coords=coords, attrs=attrs)


# lambda_tolerance of the study's limit analysis: ten times tighter than the oracle's 1 %
LIMIT_ANALYSIS_TOLERANCE = 1e-3


def add_limit_analysis(ds, at_limit, dead_load=None):
    """The limit-analysis multipliers (``stonedem.wall.limit_analysis``) beside the pushover's: on
    the caps at its peak (the oracle) and, if given, on the dead-load caps."""
    units = ds.attrs["lambda_units"]
    pairs = [("lambda_limit_analysis", at_limit)]
    if dead_load is not None:
        pairs.append(("lambda_limit_analysis_dead_load", dead_load))
    for name, r in pairs:
        var = schema_variables({name: ((), r.lambda_limit)})[name]
        var.attrs.update(
            units=units,
            status=r.status,
            lp_rounds=np.int32(r.rounds),
            supporting_planes=np.int32(r.cuts),
            domain_excess=r.domain_excess,
            seconds=round(r.seconds, 2),
        )
        ds[name] = var
    gap = float(ds.lambda_max) / at_limit.lambda_limit - 1
    ds.attrs["pushover_vs_limit_analysis"] = gap
    ds.attrs["limit_analysis_verdict"] = (
        f"plateau proven: lambda_max within {ORACLE_TOLERANCE:.0%} of the limit analysis on "
        "its caps"
        if abs(gap) <= ORACLE_TOLERANCE
        else f"plateau NOT proven: lambda_max {gap:+.1%} from the limit analysis on its caps"
    )
    ds.attrs["limit_analysis_solver"] = (
        "static theorem, HiGHS interior point (highspy) with Kelley cutting planes of the Eq. 14 "
        "shear-torsion domain; joint caps (Eq. 9-12, Fig. 10) on the given actions"
    )
    return ds


def run_case(case, output=None, progress=None, limit_analysis=False) -> xr.Dataset:
    """Run the pushover of a built case (:func:`stonedem.wall.case.build_case`) and, with
    ``limit_analysis``, the LP of the same model (:func:`add_limit_analysis`); optionally write
    the NetCDF atomically (a SIGINT/SIGTERM during the run or the write leaves no file)."""
    from stonedem.wall.pushover import ConvergenceError, DeadLoadError, pushover

    # a failure of the run that the input causes, as the one-line refusal of that input; the
    # live load cannot be started from the dead-load state, or the dead load finds a mechanism
    with _refused(ConvergenceError, lambda err: f"the live load cannot be applied: {err}"):
        with _refused(DeadLoadError, lambda err: f"leave a mechanism at lambda = 0: {err}", _BELOW):
            result = pushover(case.model, case.settings, case.control_block, progress=progress)
    ds = wall_dataset(case, result)
    if limit_analysis:
        from stonedem.wall.limit_analysis import LimitAnalysisError, limit_multiplier

        with _refused(LimitAnalysisError, lambda err: f"the limit analysis has no answer: {err}"):
            at_limit = limit_multiplier(
                case.model,
                caps_at=result.interface_forces_at_max,
                lambda_tolerance=LIMIT_ANALYSIS_TOLERANCE,
            )
        add_limit_analysis(ds, at_limit)
    if output is not None:
        # disk full, folder removed meanwhile, ...: one line, no file
        with _refused(
            OSError,
            lambda err: f"cannot write {output} ({err.strerror or err})",
            "give a path on a writable disk with free space",
            "-o/--output",
        ):
            write_dataset(ds, output)
    return ds


_BELOW = "hold the wall from below, e.g. add {edge: base, fix: all}"


@contextmanager
def _refused(kind, problem, fix="check the restraints and the load direction", field="restraints"):
    """An error of ``kind`` raised inside, as an InputError naming ``field`` with
    ``problem(error)`` and the fix."""
    from stonedem.errors import InputError

    try:
        yield
    except kind as err:
        raise InputError(field, problem(err), fix) from err


def run_case_file(path, output=None, progress=None, limit_analysis=False) -> xr.Dataset:
    """Load a case YAML, run the pushover (and the limit analysis), optionally write the NetCDF
    atomically."""
    from stonedem.wall.case import load_case

    return run_case(load_case(path), output, progress, limit_analysis)
