"""Layers A and B of the equivalence test (issue 44): the numbers that are not chaotic.

Layer A (:func:`layer_a`): the chapter-5 validations, the Pena block and the ramp's rocking
onset and overturning PGAs, one ``check`` row per scalar number, each beside its reference
and the reference's own tolerance (:mod:`stonedem.validation.cases`, docs/method/checks.md).
A candidate passes (:func:`compare_layer_a`) when every check meets its reference and lies
within 1e-9 relative of the baseline's (ENSEMBLES.md section 4, "Layer A"), or within 100 x
the check's own last-bit floor where that is larger: undamped or many-impact rocking
(energy_conservation, two_blocks, the later impact peaks) moves by 1e-9..1e-3 under
k_n x (1 - 2^-52) alone, and a two-block balance error by 3.6e-4 under every coordinate
x (1 + 2^-52) (FLOOR_PERTURBATIONS).

Layer B (:func:`layer_b`): the short-horizon scenes of
:func:`stonedem.study.reference_scenes.short_horizon_members`, member 0's trajectories and the
code's own last-bit floor per scene: the largest divergence from member 0 of the same scene under
any of its last-bit families (:func:`last_bit_families`: k_n, the structure's or block's width
and height, the initial tilt, the excitation's amplitude; ENSEMBLES.md section 2.3). A
candidate passes (:func:`compare_layer_b`) when each scene stays within 100 x the baseline's
floor.

Left out: ``record_rocking`` (chaotic near uplift: its reference band stays a test, not a
regression) and the checks the test suite marks as known misses (the area law's one-sine
threshold at omega_p / p = 2, -6.9 %; tests/validation/test_one_sine.py): a check that fails
its reference today would fail every candidate.
"""

from __future__ import annotations

import copy
import inspect
import math
import time

import numpy as np
import xarray as xr

# --- Layer A -----------------------------------------------------------------------------

RELATIVE = 1e-9  # candidate vs baseline, relative (ENSEMBLES.md section 4)
FACTOR_A = 100.0  # or this many times the check's own last-bit floor, where that is larger
# the floors' perturbations (stonedem.study.members): k_n alone moves a two-block balance error
# by ~1e-11, every coordinate's last bit by 3.6e-4 (docs/method/equivalence.md), and a change
# of the code's geometric arithmetic moves those bits
FLOOR_PERTURBATIONS = ("stiffness", "geometry")
RAMP_RATE = 0.5  # [m s-3] the study's ramp (config ramp_drums; thesis Fig. 6.10)
RAMP_TOLERANCE = 1e-3  # relative, as tests/validation/test_point.py holds the ramp's overturning
RAMP_CONTACTS = {
    "ramp_point_study": {"model": "point", "k_n": 1e10},  # the study's contact
    "ramp_point": None,
}  # the engine's default point law (k_n 1e11)
ONE_SINE_QUICK = {"omega_ratios": (2.0,), "blocks": ((0.5, 2.0),)}


def _attrs(units, long_name):
    return {"units": units, "long_name": long_name}


def _row(name, value, reference, tolerance, units, relative=True):
    """One check: ``relative``: error = |value / reference - 1| (units "1"); else the value is
    itself an error held to 0 (error = |value|, in the value's units)."""
    value, reference = float(value), float(reference)
    error = abs(value / reference - 1.0) if relative else abs(value - reference)
    return {
        "check": name,
        "value": value,
        "reference": reference,
        "error": error,
        "tolerance": float(tolerance),
        "units": units,
        "measure": "relative" if relative else "absolute",
        # regression scale: |reference|, or 1 for an error normalised by an O(1) quantity
        "scale": abs(reference) if relative else 1.0,
        "passes": bool(error <= tolerance),
    }


def _validation(name, factor, **kwargs):
    """Validation ``name`` of stonedem.validation.cases.VALIDATIONS with its k_n x factor
    (the point variants: the point law's k_n)."""
    from stonedem.validation import cases

    if name.endswith("_point"):
        base = cases.VALIDATIONS[name.removesuffix("_point")]
        contact = {**cases.POINT_CONTACT, "k_n": cases.POINT_CONTACT["k_n"] * factor}
        return base(contact=contact, **kwargs)
    check = cases.VALIDATIONS[name]
    k_n = inspect.signature(check).parameters["k_n"].default
    return check(k_n=k_n * factor, **kwargs)


def _housner_rows(name, factor, quick):
    kwargs = {"geometries": ((0.25, 1.0),), "ratios": (0.3, 0.6, 0.9)} if quick else {}
    result = _validation(name, factor, **kwargs)
    ds = result.dataset
    tol = ds.attrs["tolerance"]
    return [
        _row(
            f"{name}/{g}/theta0_over_alpha={r:g}",
            ds.period_engine.values[i, j],
            ds.period_exact.values[i, j],
            tol,
            "s",
        )
        for i, g in enumerate(ds.geometry.values)
        for j, r in enumerate(ds.ratio.values)
    ]


def _impact_rows(name, factor, quick):
    ds = _validation(name, factor).dataset
    tol = ds.attrs["tolerance"]
    return [
        _row(
            f"{name}/peak_after_impact_{k}",
            ds.peak_engine.values[k],
            ds.peak_eq_5_3.values[k],
            tol,
            "rad",
        )
        for k in range(1, ds.sizes["impact"])
    ]


def _newmark_rows(name, factor, quick):
    kwargs = {"cases": ((0.8, 1.5, (0.3,)), (0.5, 1.0, (0.2,)))} if quick else {}
    ds = _validation(name, factor, **kwargs).dataset
    tol = ds.attrs["tolerance"]
    return [
        _row(
            f"{name}/a_p={ds.a_p_g.values[k]:g}g/t_p={ds.t_p.values[k]:g}s/mu={ds.mu.values[k]:g}",
            ds.u_max_engine.values[k],
            ds.u_max_eq_5_5.values[k],
            tol,
            "m",
        )
        for k in range(ds.sizes["case"])
    ]


def _sliding_rows(name, factor, quick):
    result = _validation(name, factor)
    ds = result.dataset
    tol = ds.attrs["tolerance"]
    peak_engine = float(np.abs(ds.sliding_engine).max())
    peak_exact = float(np.abs(ds.sliding_exact).max())
    return [
        _row(f"{name}/peak_sliding", peak_engine, peak_exact, tol, "m"),
        _row(
            f"{name}/history_error_over_peak",
            ds.attrs["max_error_over_peak"],
            0.0,
            tol,
            "1",
            relative=False,
        ),
    ]


def _two_blocks_rows(name, factor, quick):
    ds = _validation(name, factor).dataset
    tol = ds.attrs["tolerance"]
    return [
        _row(f"{name}/theta0={t:g}/balance_error", e, 0.0, tol, "1", relative=False)
        for t, e in zip(ds.theta0.values, ds.max_abs_balance_error.values)
    ]


def _energy_rows(name, factor, quick):
    ds = _validation(name, factor).dataset
    return [
        _row(
            f"{name}/final_drift",
            ds.attrs["final_drift"],
            0.0,
            ds.attrs["tolerance"],
            "1",
            relative=False,
        )
    ]


def _pena_rows(name, factor, quick):
    from stonedem.validation import cases

    ds = cases.pena_block(k_n=cases.PENA_K_N * factor, c_sweep=(cases.PENA_C_N,)).dataset
    tol = ds.attrs["tolerance"]
    rows = [
        _row(f"{name}/peak_{k}", ds.peak_engine.values[k], ds.peak_rigid.values[k], tol, "rad")
        for k in range(1, ds.sizes["peak"])
    ]
    rows += [
        _row(
            f"{name}/half_cycle_{k}",
            ds.half_cycle_engine.values[i],
            ds.half_cycle_exact.values[i],
            tol,
            "s",
        )
        for i, k in enumerate(ds.half_cycle.values)
    ]
    return rows


def _one_sine_rows(name, factor, quick):
    kwargs = dict(ONE_SINE_QUICK) if quick else {}
    ds = _validation(name, factor, map_block=None, **kwargs).dataset
    tol = ds.attrs["tolerance"]
    return [
        _row(
            f"{name}/{b}/omega_ratio={r:g}",
            ds.threshold_engine.values[i, j],
            ds.threshold_exact.values[i, j],
            tol,
            "1",
        )
        for i, b in enumerate(ds.block.values)
        for j, r in enumerate(ds.omega_ratio.values)
    ]


def rigid_ramp_thresholds(width=1.0, height=6.0, rate=RAMP_RATE, step=1e-5, duration=7.0):
    """(rocking onset, overturning) PGA [m s-2] of the rigid block under the ramp a_g = rate t.

    The rigid rocking equation with Housner's r (stonedem.reference.analytic); onset where
    |theta| first exceeds alpha / 30 (the engine's onset, thesis 6.3.1), overturning where it
    reaches alpha (the engine's collapse angle, tests/validation/test_point.py).
    """
    from stonedem.engine.measures import ONSET_FRACTION
    from stonedem.reference import analytic

    t = np.arange(0.0, duration, step)
    res = analytic.rigid_rocking_response_compiled(
        t, -rate * t, width, height, analytic.housner_restitution(width, height)
    )
    theta = np.abs(np.nan_to_num(res.theta, nan=10.0))
    alpha = math.atan(width / height)
    return float(rate * t[np.argmax(theta > ONSET_FRACTION * alpha)]), float(
        rate * t[np.argmax(theta >= alpha)]
    )


def _ramp_rows(name, factor, quick):
    """The 6 x 1 m monolith under the study's ramp (thesis Fig. 6.10): rocking onset and
    overturning PGAs against the rigid block's, 0.1 %."""
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import simulate
    from stonedem.validation import cases

    contact = RAMP_CONTACTS[name] or cases.POINT_CONTACT
    contact = {**contact, "k_n": contact["k_n"] * factor}
    spec = {
        "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
        "friction": 0.485,
        "contact": contact,
        "excitation": {"kind": "ramp", "rate": RAMP_RATE},
        "solver": {"duration": 7.0, "stop_on_collapse": True},
    }
    run = simulate(scene_from_dict(spec))
    onset, over = rigid_ramp_thresholds()
    return [
        _row(
            f"{name}/rocking_onset_pga",
            RAMP_RATE * run.rocking_onset_time,
            onset,
            RAMP_TOLERANCE,
            "m s-2",
        ),
        _row(
            f"{name}/overturning_pga", RAMP_RATE * run.collapse_time, over, RAMP_TOLERANCE, "m s-2"
        ),
    ]


# name -> (rows builder, in the quick set)
CHECKS = {
    "housner_period": (_housner_rows, True),
    "housner_period_point": (_housner_rows, False),
    "impact_restitution": (_impact_rows, False),
    "impact_restitution_point": (_impact_rows, True),
    "newmark_pulse": (_newmark_rows, False),
    "newmark_pulse_point": (_newmark_rows, True),
    "record_sliding": (_sliding_rows, False),
    "record_sliding_point": (_sliding_rows, True),
    "two_blocks": (_two_blocks_rows, True),
    "two_blocks_point": (_two_blocks_rows, False),
    "energy_conservation": (_energy_rows, True),
    "energy_conservation_point": (_energy_rows, False),
    "pena_block": (_pena_rows, True),
    "ramp_point_study": (_ramp_rows, True),
    "ramp_point": (_ramp_rows, False),
    "one_sine_overturning_point": (_one_sine_rows, True),
}


def check_rows(quick: bool = False, member: int = 0, perturbation: str = "stiffness") -> list[dict]:
    """Every check row of :data:`CHECKS` (the quick set: fewer checks, smaller grids), each
    run with its contact stiffness k_n x stiffness_factor(member) and, for the ``geometry``
    perturbation, every coordinate x scale_factor(member) (stonedem.study.members)."""
    from stonedem.engine.scene import GEOMETRY_SCALE
    from stonedem.study.members import check_perturbation, scale_factor, stiffness_factor

    factor = stiffness_factor(member)
    scale = scale_factor(member) if check_perturbation(perturbation) == "geometry" else 1.0
    rows = []
    token = GEOMETRY_SCALE.set(scale)
    try:
        for name, (build, in_quick) in CHECKS.items():
            if quick and not in_quick:
                continue
            rows += build(name, factor, quick)
    finally:
        GEOMETRY_SCALE.reset(token)
    return rows


def _provenance():
    import llvmlite

    from stonedem.io.netcdf import code_version
    from stonedem.study.runner import library_versions, machine

    return {
        "source": code_version(),
        "machine": machine(),
        **library_versions(),
        "llvmlite_version": llvmlite.__version__,
    }


def layer_a(quick: bool = False, *, floor_members=(1, 2, 3), member: int = 0) -> xr.Dataset:
    """Layer A's dataset: one ``check`` row per number (:func:`check_rows`) with its value,
    reference, error, tolerance and verdict against the reference, and its last-bit floor:
    the largest |value - value of member j|, j in ``floor_members``, under each of
    FLOOR_PERTURBATIONS (k_n x (1 - j 2^-52), and that with every coordinate x (1 + j 2^-52));
    () for a candidate, whose floors are not used)."""
    start = time.perf_counter()
    rows = check_rows(quick, member)

    def column(key, dtype=float):
        return np.array([r[key] for r in rows], dtype=dtype)

    floor = np.zeros(len(rows))
    for j in floor_members:
        for perturbation in FLOOR_PERTURBATIONS:
            other = {r["check"]: r["value"] for r in check_rows(quick, j, perturbation)}
            floor = np.maximum(
                floor, [abs(other.get(r["check"], math.inf) - r["value"]) for r in rows]
            )

    ds = xr.Dataset(
        {
            "check_value": (
                "check",
                column("value"),
                _attrs("1", "the check's number (units: check_units)"),
            ),
            "check_reference": (
                "check",
                column("reference"),
                _attrs("1", "its reference (units: check_units)"),
            ),
            "check_error": (
                "check",
                column("error"),
                _attrs(
                    "1",
                    "|value / reference - 1| (check_measure relative) or |value - reference| "
                    "(absolute)",
                ),
            ),
            "check_tolerance": (
                "check",
                column("tolerance"),
                _attrs("1", "the reference's own tolerance on check_error"),
            ),
            "check_passes": (
                "check",
                column("passes", np.int8),
                _attrs("1", "check_error <= check_tolerance (1) or not (0)"),
            ),
            "check_scale": (
                "check",
                column("scale"),
                _attrs(
                    "1",
                    "magnitude the baseline regression is relative to: |reference|, or 1 for a "
                    "normalised error",
                ),
            ),
            "check_floor": (
                "check",
                floor if floor_members else np.full(len(rows), np.nan),
                _attrs(
                    "1",
                    "largest |value change| under k_n x (1 - j 2^-52), and that with every "
                    "coordinate x "
                    "(1 + j 2^-52), j in floor_members (units: check_units)",
                ),
            ),
            "check_units": (
                "check",
                column("units", object),
                {"long_name": "units of check_value and check_reference"},
            ),
            "check_measure": (
                "check",
                column("measure", object),
                {"long_name": "how check_error is formed"},
            ),
        },
        coords={
            "check": ("check", column("check", object), {"long_name": "validation/what is checked"})
        },
        attrs={
            "title": "stonedem equivalence layer A: non-chaotic checks against their references",
            "profile": "quick" if quick else "full",
            "member": int(member),
            "floor_members": np.array(floor_members, dtype=np.int32),
            "perturbation": "contact stiffness k_n times 1 - member 2^-52",
            "floor_perturbations": " ".join(FLOOR_PERTURBATIONS),
            "checks_passed": int(column("passes").sum()),
            "checks": len(rows),
            "wall_seconds": time.perf_counter() - start,
            **_provenance(),
        },
    )
    return ds


def _finite(x):
    return x is not None and np.isfinite(x)


def _paired(base: xr.Dataset, cand: xr.Dataset, dim: str, layer: str):
    """(failing rows, None) when a side has no ``dim`` at all; else (None, [(name, why it is
    missing: '' when both sides have it)]) over the entries of either side, baseline's first."""
    for ds, side in ((base, "baseline"), (cand, "candidate")):
        if dim not in ds.dims:
            return [
                {
                    dim: "",
                    "passed": False,
                    "reason": f"the {side} has no {layer} (no {dim} dimension)",
                }
            ], None
    base_names, cand_names = [str(x) for x in base[dim].values], [str(x) for x in cand[dim].values]
    return None, [
        (
            name,
            ""
            if name in base_names and name in cand_names
            else f"missing in the {'candidate' if name not in cand_names else 'baseline'}",
        )
        for name in dict.fromkeys(base_names + cand_names)
    ]


def compare_layer_a(
    base: xr.Dataset, cand: xr.Dataset, relative: float = RELATIVE
) -> tuple[bool, list[dict]]:
    """(passed, one row per check): each candidate check meets its reference tolerance and
    |cand - base| <= max(relative x max(|base|, scale), FACTOR_A x floor): scale is the
    baseline's ``check_scale`` (|reference|, or 1 for an error held to 0: the absolute floor
    of a value that is 0), floor its ``check_floor`` (the check's own last-bit change, which
    exceeds 1e-9 relative for the few checks that rock through many impacts). A check
    missing on either side fails."""
    failed, names = _paired(base, cand, "check", "layer A")
    if failed:
        return False, failed
    table = []
    for name, missing in names:
        row = {"check": name}
        if missing:
            table.append({**row, "passed": False, "reason": missing})
            continue
        b, c = base.sel(check=name), cand.sel(check=name)
        b_value, c_value = float(b.check_value), float(c.check_value)
        scale = float(b.check_scale) if "check_scale" in b else abs(float(b.check_reference))
        floor = float(b.check_floor) if "check_floor" in b else 0.0
        allowed = max(
            relative * max(abs(b_value), scale), FACTOR_A * floor if _finite(floor) else 0.0
        )
        difference = abs(c_value - b_value)
        meets = bool(int(c.check_passes)) and _finite(c_value)
        close = _finite(difference) and difference <= allowed
        reasons = (
            []
            if meets
            else [
                f"misses its reference: error {float(c.check_error):.3g} > "
                f"tolerance {float(c.check_tolerance):.3g}"
            ]
        )
        if not close:
            reasons.append(f"moved from the baseline by {difference:.3g} > {allowed:.3g}")
        row.update(
            value=c_value,
            baseline=b_value,
            reference=float(c.check_reference),
            error=float(c.check_error),
            tolerance=float(c.check_tolerance),
            difference=difference,
            allowed=allowed,
            relative_difference=difference / abs(b_value) if b_value else math.inf,
            passed=meets and close,
            reason="; ".join(reasons),
        )
        table.append(row)
    return all(r["passed"] for r in table), table


# --- Layer B -----------------------------------------------------------------------------

FLOOR_ULPS = 4  # a floor is at least this many ulps of the trajectory's scale
FACTOR = 100.0  # candidate vs baseline, in floors (ENSEMBLES.md section 4, "Layer B")
# last-bit families of a scene (:func:`last_bit_families`), each value x (1 +- j 2^-52). k_n
# alone misses what a rounding-only code change does: issue 32's body-frame edge normals moved
# column_8_record 8e4 x and colonnade_harmonic/pga_9 7e5 x past k_n floors, but stay within
# 0.12 and 0.84 floors of these (docs/method/equivalence.md). The scenes start on exact contact
# ties (a corner on a face, aligned drums); a last-bit change of a length decides them, as a
# rounding change of the code does.
FAMILIES = ("stiffness", "width", "height", "tilt", "amplitude")


def short_horizon_scenes(duration: float = 0.5, kinds=None) -> dict:
    """{name: Scene}: gpu_check's short-horizon members, one per distinct spec, named
    ``kind`` or ``kind/pga_<PGA>`` when the kind's members differ by PGA."""
    from stonedem.study.reference_scenes import short_horizon_members

    out = {}
    for kind, scenes in short_horizon_members(duration).items():
        if kinds is not None and kind not in kinds:
            continue
        distinct = []
        for scene in scenes:
            if all(scene.spec != other.spec for other in distinct):
                distinct.append(scene)
        for scene in distinct:
            pga = scene.spec.get("excitation", {}).get("pga")
            out[kind if len(distinct) == 1 else f"{kind}/pga_{pga:g}"] = scene
    return out


def _kind(name: str) -> str:
    return name.split("/")[0]


def last_bit_families(spec: dict) -> dict:
    """{family: spec path} of the values a scene's last-bit variants scale, of :data:`FAMILIES`
    but stiffness: a structure's width and height, else the first free box body's width,
    height and initial tilt; the excitation's pga (FMA and libm changes perturb the base
    motion's arithmetic by as much)."""
    out = {}
    if "structure" in spec:
        out.update(width=("structure", "width"), height=("structure", "height"))
    else:
        for i, body in enumerate(spec.get("bodies", ())):
            if "box" in body and not body.get("driven", False):
                out.update(
                    width=("bodies", i, "box", "width"), height=("bodies", i, "box", "height")
                )
                if "tilt" in body:
                    out["tilt"] = ("bodies", i, "tilt", "angle")
                break
    if "pga" in spec.get("excitation", {}):
        out["amplitude"] = ("excitation", "pga")
    return out


def _geometry_variant(scene, path, sign, j):
    """The scene rebuilt from its spec with the value at ``path`` times (1 + sign j 2^-52)."""
    from stonedem.engine.scene import scene_from_dict
    from stonedem.study.members import RELATIVE_STEP

    spec = copy.deepcopy(scene.spec)
    node = spec
    for key in path[:-1]:
        node = node[key]
    value = node[path[-1]]
    node[path[-1]] = value * (1.0 + sign * j * RELATIVE_STEP)
    if node[path[-1]] == value:  # rounded back: a variant that is no variant would floor at 0
        raise ValueError(
            f"{'.'.join(map(str, path))} = {value!r} x (1 {'+' if sign > 0 else '-'} "
            f"{j} 2^-52) rounds to itself"
        )
    return scene_from_dict(spec)


def trajectory(run) -> np.ndarray:
    """(sample, 3 x body) x [m], y [m], theta [rad] of each body, coordinate = 3 body + dof."""
    return np.stack([run.x, run.y, run.theta], axis=-1).reshape(len(run.time), -1)


def _divergence(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """(max |d position| [m], max |d rotation| [rad]) over the samples both have; inf when
    the bodies differ."""
    if a.shape[1] != b.shape[1]:
        return math.inf, math.inf
    n = min(a.shape[0], b.shape[0])
    d = np.abs(a[:n] - b[:n]).reshape(n, -1, 3)
    return float(np.max(d[..., :2], initial=0.0)), float(np.max(d[..., 2], initial=0.0))


def layer_b(
    duration: float = 0.5, floor_members=(1, 2, 3), *, kinds=None, member: int = 0
) -> xr.Dataset:
    """Layer B's dataset: per short-horizon scene, member ``member``'s trajectory
    (:func:`stonedem.study.members.member_scene`; a baseline's is member 0's) and the last-bit
    floor of its positions and rotations (NaN with no ``floor_members``: a candidate's floors
    are not used).

    The floor is the largest divergence of member 0 from the scene with k_n x (1 - j 2^-52),
    j in ``floor_members``, and with each value of :func:`last_bit_families` x (1 +- j 2^-52);
    ``divergence_*(scene, variant)`` keeps each variant's, ``family_*(scene, family)`` each
    family's largest. It is at least FLOOR_ULPS ulps of the trajectory's scale (positions:
    the largest |x|, |y|; rotations: the largest |theta|, and at least 1 rad, an angle going
    through sin and cos), so a floor measured as 0 does not demand bit identity.
    """
    from stonedem.engine.simulate import simulate
    from stonedem.study.members import member_scene

    start = time.perf_counter()
    scenes = short_horizon_scenes(duration, kinds)
    # (family, sign, j): stiffness_j, then <family>_+j and <family>_-j
    variants = [("stiffness", -1.0, j) for j in floor_members]
    variants += [(f, s, j) for f in FAMILIES[1:] for j in floor_members for s in (1.0, -1.0)]
    variant_names = [
        f"stiffness_{j}" if f == "stiffness" else f"{f}_{'+' if s > 0 else '-'}{j}"
        for f, s, j in variants
    ]
    names = list(scenes)
    trajectories, times, kinds_of_coordinate = [], [], []
    divergence = np.full((len(names), 2, len(variants)), np.nan)
    parameter = np.full((len(names), len(FAMILIES)), "none", dtype=object)
    for i, name in enumerate(names):
        scene = scenes[name]
        run = simulate(member_scene(scene, member))
        base = trajectory(run)
        trajectories.append(base)
        times.append(run.time)
        kinds_of_coordinate.append(np.tile(np.array([0, 0, 1], dtype=np.int8), base.shape[1] // 3))
        paths = last_bit_families(scene.spec)
        parameter[i, 0] = "contact.k_n"
        for f, family in enumerate(FAMILIES[1:], start=1):
            if family in paths:
                parameter[i, f] = ".".join(str(p) for p in paths[family])
        for v, (family, sign, j) in enumerate(variants):
            if family == "stiffness":
                other = member_scene(scene, j)
            elif family in paths:
                other = _geometry_variant(scene, paths[family], sign, j)
            else:
                continue
            divergence[i, :, v] = _divergence(
                base, trajectory(simulate(member_scene(other, member)))
            )
    n_sample = max(t.shape[0] for t in trajectories)
    n_coordinate = max(t.shape[1] for t in trajectories)
    padded = np.full((len(names), n_sample, n_coordinate), np.nan)
    sample_time = np.full((len(names), n_sample), np.nan)
    coordinate_kind = np.full((len(names), n_coordinate), -1, dtype=np.int8)
    for i, t in enumerate(trajectories):
        padded[i, : t.shape[0], : t.shape[1]] = t
        sample_time[i, : len(times[i])] = times[i]
        coordinate_kind[i, : t.shape[1]] = kinds_of_coordinate[i]
    family_of = np.array([f for f, _, _ in variants], dtype=object)
    by_family = np.full((len(names), 2, len(FAMILIES)), np.nan)
    for f, family in enumerate(FAMILIES):
        picked = divergence[:, :, family_of == family]
        has = ~np.all(np.isnan(picked), axis=2)
        if has.any():
            by_family[:, :, f][has] = np.nanmax(picked[has], axis=-1)
    measured = np.nanmax(divergence, axis=2) if variants else np.full((len(names), 2), np.nan)
    eps = np.finfo(float).eps
    position_scale = np.array(
        [
            np.nanmax(np.abs(np.where(coordinate_kind[i] == 0, padded[i], np.nan)))
            for i in range(len(names))
        ]
    )
    rotation_scale = np.array(
        [
            max(1.0, np.nanmax(np.abs(np.where(coordinate_kind[i] == 1, padded[i], np.nan))))
            for i in range(len(names))
        ]
    )
    floor_position = np.maximum(measured[:, 0], FLOOR_ULPS * eps * position_scale)
    floor_rotation = np.maximum(measured[:, 1], FLOOR_ULPS * eps * rotation_scale)
    return xr.Dataset(
        {
            "trajectory": (
                ("scene", "sample", "coordinate"),
                padded,
                _attrs(
                    "1",
                    f"member {member}: x [m], y [m], theta [rad] of each body (coordinate = 3 "
                    "body + dof), NaN-padded",
                ),
            ),
            "coordinate_kind": (
                ("scene", "coordinate"),
                coordinate_kind,
                {
                    **_attrs("1", "kind of a trajectory coordinate"),
                    "flag_values": np.array([-1, 0, 1], dtype=np.int8),
                    "flag_meanings": "padding position rotation",
                },
            ),
            "sample_time": (
                ("scene", "sample"),
                sample_time,
                _attrs("s", "time of each output sample, NaN-padded"),
            ),
            "floor_position": (
                "scene",
                floor_position,
                _attrs(
                    "m",
                    "last-bit floor of positions: largest |divergence| of a variant of any "
                    "family, at least "
                    f"{FLOOR_ULPS} ulps of the largest |position|",
                ),
            ),
            "floor_rotation": (
                "scene",
                floor_rotation,
                _attrs(
                    "rad",
                    f"last-bit floor of rotations: largest |divergence|, at least {FLOOR_ULPS} "
                    "ulps of max(1, |theta|)",
                ),
            ),
            "divergence_position": (
                ("scene", "variant"),
                divergence[:, 0, :],
                _attrs(
                    "m",
                    "largest |position difference| from member 0 of the variant (NaN: the "
                    "scene has none)",
                ),
            ),
            "divergence_rotation": (
                ("scene", "variant"),
                divergence[:, 1, :],
                _attrs(
                    "rad",
                    "largest |rotation difference| from member 0 of the variant (NaN: the "
                    "scene has none)",
                ),
            ),
            "family_position": (
                ("scene", "family"),
                by_family[:, 0, :],
                _attrs(
                    "m",
                    "largest divergence_position of the family's variants (NaN: the scene has "
                    "none)",
                ),
            ),
            "family_rotation": (
                ("scene", "family"),
                by_family[:, 1, :],
                _attrs(
                    "rad",
                    "largest divergence_rotation of the family's variants (NaN: the scene has "
                    "none)",
                ),
            ),
            "family_parameter": (
                ("scene", "family"),
                parameter,
                {"long_name": "scene spec value the family scales (none: the scene has none)"},
            ),
        },
        coords={
            "scene": (
                "scene",
                np.array(names, dtype=object),
                {"long_name": "short-horizon scene (kind/PGA)"},
            ),
            "variant": (
                "variant",
                np.array(variant_names, dtype=object),
                {
                    "long_name": "stiffness_j: k_n x (1 - j 2^-52); <family>_+-j: "
                    "family_parameter x (1 +- j 2^-52)"
                },
            ),
            "variant_family": (
                "variant",
                family_of,
                {"long_name": "last-bit family of the variant"},
            ),
            "family": (
                "family",
                np.array(FAMILIES, dtype=object),
                {"long_name": "last-bit family"},
            ),
        },
        attrs={
            "title": "stonedem equivalence layer B: short-horizon trajectories and their "
            "last-bit floors",
            "duration": float(duration),
            "duration_units": "s",
            "member": int(member),
            "floor_members": np.array(floor_members, dtype=np.int32),
            "floor_ulps": FLOOR_ULPS,
            "wall_seconds": time.perf_counter() - start,
            **_provenance(),
        },
    )


def _unpadded(ds: xr.Dataset, name: str) -> np.ndarray:
    """The scene's trajectory without the NaN padding of samples and coordinates."""
    t = ds.trajectory.sel(scene=name).values
    rows = np.flatnonzero(~np.all(np.isnan(t), axis=1))
    columns = np.flatnonzero(~np.all(np.isnan(t), axis=0))
    n_rows = rows[-1] + 1 if len(rows) else 0
    n_columns = columns[-1] + 1 if len(columns) else 0
    return t[:n_rows, :n_columns]


def compare_layer_b(
    base: xr.Dataset, cand: xr.Dataset, factor: float = FACTOR
) -> tuple[bool, list[dict]]:
    """(passed, one row per scene): per scene max |d position| <= factor x the baseline's
    floor_position and max |d rotation| <= factor x its floor_rotation. A scene missing on
    either side, or a trajectory of another shape, fails."""
    failed, names = _paired(base, cand, "scene", "layer B")
    if failed:
        return False, failed
    table = []
    for name, missing in names:
        row = {"scene": name}
        if missing:
            table.append({**row, "passed": False, "reason": missing})
            continue
        b, c = _unpadded(base, name), _unpadded(cand, name)
        floor_p = float(base.floor_position.sel(scene=name))
        floor_r = float(base.floor_rotation.sel(scene=name))
        row.update(
            floor_position=floor_p,
            floor_rotation=floor_r,
            allowed_position=factor * floor_p,
            allowed_rotation=factor * floor_r,
        )
        if b.shape != c.shape:
            row.update(
                passed=False,
                reason=f"trajectory shape {c.shape} (samples, coordinates) differs from "
                f"the baseline's {b.shape}",
            )
            table.append(row)
            continue
        d_position, d_rotation = _divergence(b, c)
        reasons = []
        if not np.array_equal(np.isnan(b), np.isnan(c)):
            d_position = d_rotation = math.inf
            reasons.append("NaN where the baseline has a number (or the reverse)")
        if not d_position <= factor * floor_p:
            reasons.append(
                f"position moved {d_position:.3g} m > {factor:g} x floor {floor_p:.3g} m"
            )
        if not d_rotation <= factor * floor_r:
            reasons.append(
                f"rotation moved {d_rotation:.3g} rad > {factor:g} x floor {floor_r:.3g} rad"
            )
        row.update(
            position_difference=d_position,
            rotation_difference=d_rotation,
            position_in_floors=d_position / floor_p if floor_p > 0 else math.inf,
            rotation_in_floors=d_rotation / floor_r if floor_r > 0 else math.inf,
            passed=not reasons,
            reason="; ".join(reasons),
        )
        table.append(row)
    return all(r["passed"] for r in table), table
