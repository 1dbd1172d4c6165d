"""Is a changed engine equivalent to the stored baseline, when it is no longer bit-identical?
(issue 44; ../shared/research/ENSEMBLES.md, section 4, and docs/method/equivalence.md)

Two ensemble files (:mod:`stonedem.study.ensemble`, the layout in its docstring) are judged in
up to four layers, each of which must pass:

- A, exact checks: the non-chaotic checks agree with their references and with the baseline
  to 1e-9 relative (:func:`stonedem.study.exact_checks.compare_layer_a`);
- B, short horizon: 0.5 s trajectories within 100 x the last-bit floor stored with the
  baseline (:func:`stonedem.study.exact_checks.compare_layer_b`);
- C, ensemble: a permutation test over whole runs on the grid's collapse fractions (S_v) and
  the searches' median thresholds (S_T), rejected when either p <= alpha
  (:func:`stonedem.study.permutation.permutation_test`);
- F, fragility fits (when the files carry ``fit_theta``, ``fit_beta``, ``fit_n``):
  |d ln theta| and |d beta| <= 0.02 sqrt(100/n) (ENSEMBLES.md section 5).

    python -m stonedem.study.equivalence BASELINE CANDIDATE [--layers A B C F] [--permutations
    10000]
        [--seed 0] [--alpha 0.005] [--out results/equivalence/equivalence.nc]
    # exit 0: every layer run passes; 1: a layer fails or a requested one could not run; 2: bad
    input
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError, one_line
from stonedem.io.spec import Field, Spec

LAYERS = ("A", "B", "C", "F")
LAYER_NAMES = {"A": "exact checks", "B": "short horizon", "C": "ensemble", "F": "fragility fits"}
ALPHA = 0.005  # per statistic: a family-wise false-alarm rate <= 1 % (ENSEMBLES.md section 4)
RELATIVE = 1e-9  # layer A: agreement with the baseline, relative
FLOOR_FACTOR = 100.0  # layer B: the allowed divergence, in units of the scene's last-bit floor
PERMUTATIONS = 10_000
MAX_PERMUTATIONS = 1_000_000
OUTPUT = Path("results/equivalence/equivalence.nc")
MAKE_CANDIDATE = "python -m stonedem.study.ensemble --members 4 --out cand.nc"
FIT_VARIABLES = ("fit_theta", "fit_beta", "fit_n")
# the command's numbers (--seed: an int64, below 2**63)
ARGS = Spec(
    (
        Field(
            "--permutations",
            "integer",
            range=f"[1, {MAX_PERMUTATIONS}]",
            default=PERMUTATIONS,
            hint=f"give e.g. --permutations {PERMUTATIONS}",
            doc="random label assignments, when there are more than that many",
        ),
        Field(
            "--seed",
            "integer",
            range=f"[0, {2**63})",
            default=0,
            hint="give e.g. --seed 0",
            doc="seed of the random assignments",
        ),
        Field(
            "--alpha",
            "number",
            range="(0, 0.5]",
            default=ALPHA,
            hint=f"give e.g. --alpha {ALPHA}",
            doc="reject when either p <= alpha",
        ),
    )
)


# --- reading the two files ----------------------------------------------------------------


def read_ensemble(path: str | Path, field: str) -> xr.Dataset:
    """The ensemble file at ``path``, in memory, or an InputError naming ``field`` and what is
    missing: not a file, not NetCDF, unreadable, no ``member`` dimension, neither grid verdicts
    (``collapsed(case, member)``) nor search thresholds (``threshold(system, member)``)."""
    from stonedem import options

    make = f"give an ensemble file, written by {MAKE_CANDIDATE}"
    ds = options.read_netcdf(path, field, "ensemble NetCDF file", make)
    shown = one_line(str(path), 200)
    wanted = {"case": ("collapsed",), "system": ("threshold", "search_tolerance")}
    missing = {
        dim: [n for n in names if n not in ds.variables]
        for dim, names in wanted.items()
        if dim in ds.dims
    }
    lacking = next(((dim, names) for dim, names in missing.items() if names), None)
    if "member" not in ds.dims:
        problem = "it has no dimension 'member'"
    elif lacking:
        problem = f"it has a '{lacking[0]}' dimension but no {', '.join(lacking[1])}"
    elif not missing:
        problem = (
            "neither grid cases (collapsed(case, member)) nor searches (threshold(system, member))"
        )
    else:
        return ds
    raise InputError(field, f"{shown} is not an ensemble file: {problem}", make)


def _labels(ds: xr.Dataset, dim: str) -> list[str]:
    return [str(v) for v in ds[dim].values] if dim in ds.dims else []


def matched(baseline: xr.Dataset, candidate: xr.Dataset, dims=("case", "system")) -> xr.Dataset:
    """The candidate with its cases, systems (or other ``dims``: "fit") in the baseline's order,
    or an InputError when the two files hold different ones or different search tolerances
    (made from another config), or the baseline names one twice."""
    config = one_line(str(baseline.attrs.get("config", "not recorded")), 200)
    field, problem = "CANDIDATE", ""
    fix = (
        "the candidate was made from another config: run it with the baseline's config, "
        f"attrs `config` ({config})"
    )
    for dim in dims:
        what = {"system": "search system"}.get(dim, dim)
        base, cand = _labels(baseline, dim), _labels(candidate, dim)
        if set(base) != set(cand):
            only_base, only_cand = sorted(set(base) - set(cand)), sorted(set(cand) - set(base))
            example = (
                f"{what} {only_base[0]!r} is in the baseline only"
                if only_base
                else f"{what} {only_cand[0]!r} is in the candidate only"
            )
            problem = f"{example} ({len(only_base) + len(only_cand)} {what}s differ)"
        elif len(set(base)) != len(base):
            field, problem = "BASELINE", f"{what}s named twice in one file"
            fix = "give an ensemble file of distinct names"
        if problem:
            break
        if base:
            candidate = candidate.sel({dim: baseline[dim].values})
    if not problem and "system" in dims and "system" in baseline.dims:
        tb, tc = baseline.search_tolerance.values, candidate.search_tolerance.values
        if not np.array_equal(tb, tc):
            k = int(np.flatnonzero(tb != tc)[0])
            problem = (
                f"search {_labels(baseline, 'system')[k]!r} has tolerance {tc[k]:g}, "
                f"the baseline's {tb[k]:g}"
            )
    if problem:
        raise InputError(field, problem, fix)
    return candidate


def same_runs_warning(baseline: xr.Dataset, candidate: xr.Dataset) -> str:
    """A warning (empty: none) when both files come from the same source commit and share member
    indices: their shared members are the same runs, so the test compares a run with itself."""
    source_b, source_c = baseline.attrs.get("source"), candidate.attrs.get("source")
    shared = sorted(
        set(int(j) for j in baseline.member.values) & set(int(j) for j in candidate.member.values)
    )
    if source_b is None or source_b != source_c or not shared:
        return ""
    return one_line(
        f"both files come from {source_b} and share members j = {_spans(shared)}: those are "
        "identical "
        "runs, so the ensemble test is lenient; make the candidate on the changed code",
        300,
    )


def perturbation_warning(baseline: xr.Dataset, candidate: xr.Dataset) -> str:
    """A warning (empty: none) when the two files' members were perturbed differently: a
    stiffness-only group has less spread than a geometry one, so the test compares unlike groups
    (a 1-ulp change of every coordinate is rejected against a stiffness baseline)."""
    kind_b, kind_c = baseline.attrs.get("perturbation"), candidate.attrs.get("perturbation")
    if kind_b is None or kind_c is None or kind_b == kind_c:
        return ""
    return one_line(
        f"the baseline's members are perturbed by {kind_b}, the candidate's by {kind_c}: make the "
        f"candidate with --perturbation {kind_b}",
        300,
    )


def _spans(values: list[int]) -> str:
    return (
        f"{values[0]}..{values[-1]}"
        if values == list(range(values[0], values[-1] + 1)) and len(values) > 2
        else ", ".join(str(v) for v in values)
    )


def available(baseline: xr.Dataset, candidate: xr.Dataset) -> dict[str, str]:
    """{layer: why it cannot run (empty: it can)} from what the two files hold."""

    def lacking(names, dim):
        for label, ds in (("baseline", baseline), ("candidate", candidate)):
            if dim not in ds.dims or any(n not in ds.variables for n in names):
                return f"the {label} holds no {dim} data ({', '.join(names)})"
        return ""

    return {
        "A": lacking(("check_value", "check_reference", "check_passes"), "check"),
        "B": lacking(("trajectory", "floor_position", "floor_rotation"), "scene"),
        "C": "",
        "F": lacking(FIT_VARIABLES, "fit"),
    }


def check_layer_c(
    baseline: xr.Dataset, candidate: xr.Dataset, n_permutations: int, alpha: float
) -> None:
    """Layer C needs at least two members on each side (a permutation of one run is no test),
    and enough label assignments that p can reach alpha at all: the smallest p is
    1 / C(K_B + K_N, K_N) when every assignment is tried, 1 / (n_permutations + 1) otherwise."""
    k_b, k_n = int(baseline.sizes["member"]), int(candidate.sizes["member"])
    count = math.comb(k_b + k_n, k_n)
    leave_out = "or leave layer C out: --layers A B"
    if k_b < 2 or k_n < 2:
        field, k, fix = (
            ("BASELINE", k_b, "give the stored K = 20 baseline")
            if k_b < 2
            else ("CANDIDATE", k_n, f"make it with {MAKE_CANDIDATE}")
        )
        problem = f"{k} member: the ensemble test (layer C) needs at least 2 in each file"
        fix += f", {leave_out}"
    elif count <= n_permutations and 1.0 / count > alpha:
        field = "BASELINE, CANDIDATE"
        problem = (
            f"{k_b} + {k_n} members give {count} label assignments: p can never "
            f"reach alpha {alpha:g} (the smallest p is 1/{count}), so layer C could not fail"
        )
        fix = (
            f"run more members, C(K_B + K_N, K_N) >= {math.ceil(1.0 / alpha)} (K_B = 20 and "
            f"K_N = 4 give 10 626), {leave_out}"
        )
    elif count > n_permutations and 1.0 / (n_permutations + 1) > alpha:
        field = "--permutations"
        problem = f"{n_permutations} random assignments: p can never reach alpha {alpha:g}"
        fix = f"give at least {math.ceil(1.0 / alpha)}, e.g. {PERMUTATIONS}"
    else:
        return
    raise InputError(field, problem, fix)


# --- the layers -------------------------------------------------------------------------------


def _stack(ds: xr.Dataset, name: str, dim: str) -> np.ndarray:
    """``ds[name]`` as an array (dim, member), (0, K) when the file has no ``dim``."""
    if dim not in ds.dims:
        return np.zeros((0, ds.sizes["member"]))
    return np.asarray(ds[name].transpose(dim, "member").values, dtype=float)


def layer_c(
    baseline: xr.Dataset, candidate: xr.Dataset, n_permutations: int, seed: int, alpha: float
) -> dict:
    """The ensemble test (:func:`stonedem.study.permutation.permutation_test`) and its group
    summaries per case and system."""
    from stonedem.study.permutation import permutation_test

    tolerance = (
        np.asarray(baseline.search_tolerance.values, dtype=float)
        if "system" in baseline.dims
        else np.zeros(0)
    )
    result = permutation_test(
        _stack(baseline, "collapsed", "case"),
        _stack(baseline, "threshold", "system"),
        _stack(candidate, "collapsed", "case"),
        _stack(candidate, "threshold", "system"),
        tolerance,
        n_permutations=n_permutations,
        seed=seed,
        alpha=alpha,
    )
    result["unanimous_flips"] = [int(k) for k in result["unanimous_flips"]]
    return result


def _worst(values) -> float:
    """The largest of ``values`` (inf counts; NaN when there are none)."""
    values = [float(v) for v in values if not math.isnan(float(v))]
    return max(values) if values else math.nan


def _failures(table: list[dict], key: str) -> str:
    """ "; N fail, e.g. the first: why" for a layer's table (empty when every row passes)."""
    failed = [r for r in table if not r["passed"]]
    if not failed:
        return ""
    first = failed[0]
    return one_line(
        f"; {len(failed)} fail, e.g. {first[key] or 'all'}: {first.get('reason', '')}", 300
    )


def layer_f(baseline: xr.Dataset, candidate: xr.Dataset) -> dict:
    """Each fragility fit's shift: |d ln theta| and |d beta| against fit_shift_tolerance(n)
    (n the baseline's records), or an InputError when the two files hold different fits."""
    from stonedem.study.permutation import fit_shift_tolerance

    candidate = matched(baseline, candidate, ("fit",))
    d_ln_theta = np.abs(
        np.log(candidate.fit_theta.values.astype(float))
        - np.log(baseline.fit_theta.values.astype(float))
    )
    d_beta = np.abs(
        candidate.fit_beta.values.astype(float) - baseline.fit_beta.values.astype(float)
    )
    tolerance = np.array([fit_shift_tolerance(float(n)) for n in baseline.fit_n.values])
    passes = (d_ln_theta <= tolerance) & (d_beta <= tolerance)  # NaN fails
    return {"d_ln_theta": d_ln_theta, "d_beta": d_beta, "tolerance": tolerance, "passes": passes}


# --- the judgement ----------------------------------------------------------------------------


def default_layers(baseline: xr.Dataset, candidate: xr.Dataset) -> list[str]:
    """A, B and C; F too when either file carries fragility fits."""
    fits = any(n in ds.variables for ds in (baseline, candidate) for n in FIT_VARIABLES)
    return ["A", "B", "C"] + (["F"] if fits else [])


def _text(values) -> np.ndarray:
    return np.array([str(v) for v in values], dtype=object)


def _group_fraction(ds: xr.Dataset) -> np.ndarray:
    return np.asarray(ds.collapsed.transpose("case", "member").values, dtype=float).mean(axis=1)


def _group_median(ds: xr.Dataset) -> np.ndarray:
    """Each system's median threshold over the members (NaN, no collapse up to the maximum, counts
    as above every threshold found: the median is NaN only when half the members found none)."""
    values = np.asarray(ds.threshold.transpose("system", "member").values, dtype=float)
    return np.median(np.where(np.isnan(values), np.inf, values), axis=1)


def judge(
    baseline: xr.Dataset,
    candidate: xr.Dataset,
    layers=None,
    n_permutations: int = PERMUTATIONS,
    seed: int = 0,
    alpha: float = ALPHA,
    relative: float = RELATIVE,
    factor: float = FLOOR_FACTOR,
) -> xr.Dataset:
    """The judgement of ``candidate`` against ``baseline`` (two ensemble files, read), as a
    self-describing dataset: per layer its verdict ("pass", "fail", "not run" when a file lacks
    its data, "not requested") and its summary line, the layers' numbers, the candidate's flips
    of cases every baseline member agrees on, and attrs ``equivalent`` ("yes" only when every
    requested layer ran and passed).

    ``layers``: the layers to run (default :func:`default_layers`). Bad input (different cases or
    systems, fewer than 2 members on a side for layer C) raises :class:`InputError`.
    """
    from stonedem.io.netcdf import code_version

    requested = list(default_layers(baseline, candidate) if layers is None else layers)
    candidate = matched(baseline, candidate)
    if "C" in requested:
        check_layer_c(baseline, candidate, n_permutations, alpha)
    missing = available(baseline, candidate)
    warning = "; ".join(
        w
        for w in (same_runs_warning(baseline, candidate), perturbation_warning(baseline, candidate))
        if w
    )
    verdict, summary = {}, {}
    data, coords = {}, {}

    def record(layer, passed, line):
        verdict[layer] = "pass" if passed else "fail"
        summary[layer] = f"{layer} {LAYER_NAMES[layer]}: {verdict[layer]} ({line})"

    for layer in LAYERS:
        if layer not in requested:
            verdict[layer], summary[layer] = (
                "not requested",
                f"{layer} {LAYER_NAMES[layer]}: not requested",
            )
        elif missing[layer]:
            verdict[layer], summary[layer] = (
                "not run",
                f"{layer} {LAYER_NAMES[layer]}: not run ({missing[layer]})",
            )

    if verdict.get("A") is None:
        from stonedem.study.exact_checks import compare_layer_a

        passed, table = compare_layer_a(baseline, candidate, relative=relative)
        # the regression measure: |candidate - baseline| / max(|baseline|, scale), held to
        # `relative`
        worst = _worst(
            [
                relative * r["difference"] / r["allowed"]
                if r["allowed"]
                else (0.0 if r["difference"] == 0 else math.inf)
                for r in table
                if "difference" in r
            ]
        )
        record(
            "A",
            passed,
            f"{len(table)} checks, worst {worst:.2g} of {relative:g} "
            f"relative{_failures(table, 'check')}",
        )
        data.update(_table_variables(table, "check", CHECK_COLUMNS))
        coords["check"] = (
            "check",
            _text(r["check"] for r in table),
            {"long_name": "validation/what is checked"},
        )
    if verdict.get("B") is None:
        from stonedem.study.exact_checks import compare_layer_b

        passed, table = compare_layer_b(baseline, candidate, factor=factor)
        worst = _worst(
            [
                max(r["position_in_floors"], r["rotation_in_floors"])
                for r in table
                if "position_in_floors" in r
            ]
        )
        record(
            "B",
            passed,
            f"{len(table)} scenes, worst {worst:.3g}x the floor of "
            f"{factor:g}x{_failures(table, 'scene')}",
        )
        data.update(_table_variables(table, "scene", SCENE_COLUMNS))
        coords["scene"] = (
            "scene",
            _text(r["scene"] for r in table),
            {"long_name": "short-horizon scene"},
        )
    if verdict.get("C") is None:
        result = layer_c(baseline, candidate, n_permutations, seed, alpha)
        assignments = f"{int(result['n_assignments']):,}".replace(",", " ")
        record(
            "C",
            not result["reject"],
            f"S_v {result['s_v']:.3g}, p {result['p_v']:.3g}; S_T {result['s_t']:.3g} "
            f"brackets, p {result['p_t']:.3g}; {assignments} assignments, "
            f"{'exact' if result['exact'] else 'random'}",
        )
        c_data, c_coords = _layer_c_variables(baseline, candidate, result)
        data.update(c_data)
        coords.update(c_coords)
    if verdict.get("F") is None:
        fits = layer_f(baseline, candidate)
        worst = np.max(
            np.maximum(fits["d_ln_theta"], fits["d_beta"]) / fits["tolerance"], initial=0.0
        )
        record(
            "F",
            bool(np.all(fits["passes"])),
            f"{len(fits['passes'])} fits, worst {worst:.2g} of the tolerance",
        )
        coords["fit"] = ("fit", _text(baseline.fit.values), {"long_name": "fragility fit"})
        data["fit_d_ln_theta"] = (
            "fit",
            fits["d_ln_theta"],
            {"units": "1", "long_name": "|ln theta_N - ln theta_B|"},
        )
        data["fit_d_beta"] = (
            "fit",
            fits["d_beta"],
            {"units": "1", "long_name": "|beta_N - beta_B|"},
        )
        data["fit_tolerance"] = (
            "fit",
            fits["tolerance"],
            {"units": "1", "long_name": "0.02 sqrt(100/n), n the baseline's records"},
        )
        data["fit_passes"] = (
            "fit",
            fits["passes"].astype(np.int8),
            {"units": "1", "long_name": "1: within tolerance"},
        )

    equivalent = all(verdict[layer] == "pass" for layer in requested)
    coords["layer"] = (
        "layer",
        np.array(LAYERS, dtype=object),
        {"long_name": "layer of the equivalence test"},
    )
    data["verdict"] = (
        "layer",
        _text(verdict[k] for k in LAYERS),
        {"long_name": "pass, fail, not run (a file lacks the data) or not requested"},
    )
    data["layer_passes"] = (
        "layer",
        np.array([verdict[k] == "pass" for k in LAYERS], dtype=np.int8),
        {"units": "1", "long_name": "1: the layer ran and passed"},
    )
    data["layer_summary"] = (
        "layer",
        _text(summary[k] for k in LAYERS),
        {"long_name": "the layer's verdict and numbers"},
    )
    attrs = {
        "title": "equivalence of a changed engine to the stored baseline ensemble (issue 44)",
        "equivalent": "yes" if equivalent else "no",
        "layers_requested": " ".join(requested),
        "alpha": float(alpha),
        "permutations": int(n_permutations),
        "seed": int(seed),
        "relative_tolerance": float(relative),
        "floor_factor": float(factor),
        "source": code_version(),
        "warning": warning,
    }
    for label, ds in (("baseline", baseline), ("candidate", candidate)):
        attrs[f"{label}_members"] = int(ds.sizes["member"])
        attrs[f"{label}_first_member"] = int(ds.member.values.min())
        for key in ("source", "machine", "perturbation", "config", "config_digest"):
            if key in ds.attrs:
                attrs[f"{label}_{key}"] = str(ds.attrs[key])
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _layer_c_variables(
    baseline: xr.Dataset, candidate: xr.Dataset, result: dict
) -> tuple[dict, dict]:
    """(variables, coordinates) of layer C: the test's numbers, the group summaries."""
    from stonedem.study.permutation import threshold_shifts

    coords = {}
    data = {
        "s_v": (
            (),
            float(result["s_v"]),
            {"units": "1", "long_name": "S_v: chi2-like distance of the collapse fractions"},
        ),
        "p_v": ((), float(result["p_v"]), {"units": "1", "long_name": "permutation p of S_v"}),
        "s_t": (
            (),
            float(result["s_t"]),
            {"units": "1", "long_name": "S_T: median ln threshold shifts, in search brackets"},
        ),
        "p_t": ((), float(result["p_t"]), {"units": "1", "long_name": "permutation p of S_T"}),
        "n_assignments": (
            (),
            np.int64(result["n_assignments"]),
            {"units": "1", "long_name": "label assignments tried"},
        ),
        "exact": (
            (),
            np.int8(bool(result["exact"])),
            {"units": "1", "long_name": "1: every assignment, 0: random ones"},
        ),
    }
    if "case" in baseline.dims:
        flips = np.zeros(baseline.sizes["case"], dtype=np.int8)
        flips[result["unanimous_flips"]] = 1
        data["collapse_fraction_baseline"] = (
            "case",
            _group_fraction(baseline),
            {"units": "1", "long_name": "baseline members that collapsed, fraction"},
        )
        data["collapse_fraction_candidate"] = (
            "case",
            _group_fraction(candidate),
            {"units": "1", "long_name": "candidate members that collapsed, fraction"},
        )
        data["unanimous_flip"] = (
            "case",
            flips,
            {
                "units": "1",
                "long_name": "1: every baseline member agrees and a candidate member does not",
            },
        )
        coords["case"] = ("case", _text(baseline.case.values), {"long_name": "study/case"})
    if "system" in baseline.dims:
        unit = str(baseline.threshold.attrs.get("units", "1"))
        median_b, median_c = _group_median(baseline), _group_median(candidate)
        # each system's term of S_T, as the test counts it
        shift = threshold_shifts(
            _stack(baseline, "threshold", "system"),
            _stack(candidate, "threshold", "system"),
            baseline.search_tolerance.values.astype(float),
        )
        coords["system"] = (
            "system",
            _text(baseline.system.values),
            {"long_name": "study/system of a threshold search"},
        )
        data["median_threshold_baseline"] = (
            "system",
            median_b,
            {
                "units": unit,
                "long_name": "median threshold of the "
                "baseline members (inf: half found no collapse up to the maximum)",
            },
        )
        data["median_threshold_candidate"] = (
            "system",
            median_c,
            {"units": unit, "long_name": "median threshold of the candidate members"},
        )
        data["threshold_shift"] = (
            "system",
            shift,
            {
                "units": "1",
                "long_name": "the system's term of S_T: |median_N "
                "ln T - median_B ln T| in search brackets, ln(1 + tolerance) (no "
                "collapse against a collapse: "
                "stonedem.study.permutation.NO_COLLAPSE_SHIFT)",
            },
        )
    return data, coords


# a layer's table (rows of dicts, stonedem.study.exact_checks) -> variables on its dimension:
# column -> (variable, units (None: text), long name)
CHECK_COLUMNS = {
    "value": (
        "check_value",
        "1",
        "the candidate's number (units: the ensemble files' check_units)",
    ),
    "baseline": ("check_baseline", "1", "the baseline's number (units: check_units)"),
    "reference": ("check_reference", "1", "its reference (units: check_units)"),
    "error": (
        "check_error",
        "1",
        "the candidate's error against the reference, in the check's own measure",
    ),
    "tolerance": ("check_tolerance", "1", "the reference's own tolerance on check_error"),
    "difference": ("check_difference", "1", "|candidate - baseline| (units: check_units)"),
    "allowed": (
        "check_allowed",
        "1",
        "relative tolerance x max(|baseline|, the check's scale) (units: check_units)",
    ),
    "passed": (
        "check_passes",
        "1",
        "1: meets its reference and lies within check_allowed of the baseline",
    ),
    "reason": ("check_reason", None, "why it fails (empty: it passes)"),
}
SCENE_COLUMNS = {
    "position_difference": (
        "scene_position_difference",
        "m",
        "largest |candidate - baseline| of a position",
    ),
    "rotation_difference": (
        "scene_rotation_difference",
        "rad",
        "largest |candidate - baseline| of a rotation",
    ),
    "floor_position": ("scene_floor_position", "m", "the baseline's last-bit floor of positions"),
    "floor_rotation": ("scene_floor_rotation", "rad", "the baseline's last-bit floor of rotations"),
    "position_in_floors": (
        "scene_position_in_floors",
        "1",
        "scene_position_difference / scene_floor_position",
    ),
    "rotation_in_floors": (
        "scene_rotation_in_floors",
        "1",
        "scene_rotation_difference / scene_floor_rotation",
    ),
    "passed": ("scene_passes", "1", "1: both within the factor x the floor"),
    "reason": ("scene_reason", None, "why it fails (empty: it passes)"),
}


def _table_variables(table: list[dict], dim: str, columns: dict) -> dict:
    """The rows of a layer's table as variables on ``dim``, the ``columns`` only (a value a row
    lacks: NaN, or empty text)."""
    data = {}
    for column, (name, units, long_name) in columns.items():
        values = [row.get(column) for row in table]
        if units is None:
            data[name] = (
                dim,
                _text("" if v is None else v for v in values),
                {"long_name": long_name},
            )
        else:
            data[name] = (
                dim,
                np.array([np.nan if v is None else float(v) for v in values]),
                {"units": units, "long_name": long_name},
            )
        if column == "passed":
            data[name] = (dim, np.array([bool(v) for v in values], dtype=np.int8), data[name][2])
    return data


def flip_lines(judgement: xr.Dataset) -> list[str]:
    """The candidate's flips of cases every baseline member agrees on, a line each (for a look)."""
    if "unanimous_flip" not in judgement:
        return []
    flipped = np.flatnonzero(judgement.unanimous_flip.values)
    if not flipped.size:
        return ["no candidate flips of cases the baseline members all agree on"]
    lines = [
        f"{flipped.size} candidate flip(s) of cases the baseline members all agree on (not a "
        "failure; look at them):"
    ]
    for k in flipped:
        lines.append(
            f"  {judgement.case.values[k]}: baseline collapse fraction "
            f"{float(judgement.collapse_fraction_baseline[k]):.2f}, candidate "
            f"{float(judgement.collapse_fraction_candidate[k]):.2f}"
        )
    return lines


def report_lines(judgement: xr.Dataset) -> list[str]:
    """What the command prints: each layer run, the flips, the warning, the answer."""
    lines = [
        str(s)
        for s, v in zip(judgement.layer_summary.values, judgement.verdict.values)
        if v != "not requested"
    ]
    lines += flip_lines(judgement)
    if judgement.attrs.get("warning"):
        lines.append(f"warning: {judgement.attrs['warning']}")
    lines.append(f"equivalent: {judgement.attrs['equivalent']}")
    return lines


# --- the command ------------------------------------------------------------------------------


def build_parser():
    from stonedem import options

    parser = options.parser("python -m stonedem.study.equivalence", __doc__)
    parser.add_argument(
        "baseline",
        metavar="BASELINE",
        type=options.path_arg,
        help="the stored baseline ensemble file (e.g. K = 20)",
    )
    parser.add_argument(
        "candidate",
        metavar="CANDIDATE",
        type=options.path_arg,
        help=f"the changed code's ensemble file ({MAKE_CANDIDATE})",
    )
    parser.add_argument(
        "--layers",
        nargs="+",
        default=None,
        help="layers to run, of A B C F (default A B C, and F when a file carries fits)",
    )
    parser.add_argument(
        "--permutations",
        type=int,
        default=PERMUTATIONS,
        help=f"random assignments when there are more than that many (default {PERMUTATIONS})",
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="seed of the random assignments (default 0)"
    )
    parser.add_argument(
        "--alpha",
        type=float,
        default=ALPHA,
        help=f"reject when either p <= alpha (default {ALPHA})",
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=OUTPUT,
        help=f"the judgement dataset (default {OUTPUT})",
    )
    return parser


def main(argv=None) -> int:
    """Arguments and both files checked first (one line, exit 2); then the layers, the report,
    the dataset; exit 0 when equivalent, 1 when not."""
    from stonedem import options

    args = build_parser().parse_args(argv)

    def command():
        from stonedem.io.netcdf import write_dataset

        start = time.perf_counter()
        layers = None if args.layers is None else options.chosen(args.layers, "--layers", LAYERS)
        values = ARGS.check({k: getattr(args, k[2:]) for k in ARGS.keys})
        n_permutations, seed, alpha = values["--permutations"], values["--seed"], values["--alpha"]
        baseline = read_ensemble(args.baseline, "BASELINE")
        candidate = read_ensemble(args.candidate, "CANDIDATE")
        if Path(args.baseline).resolve() == Path(args.candidate).resolve():
            raise InputError(
                "CANDIDATE", "is the file BASELINE names", "give the changed code's ensemble file"
            )
        out = options.output_file(
            args.out, "--out", suffixes=(".nc",), inputs=(args.baseline, args.candidate)
        )
        judgement = judge(
            baseline, candidate, layers, n_permutations=n_permutations, seed=seed, alpha=alpha
        )
        judgement.attrs.update(
            baseline_file=str(args.baseline),
            candidate_file=str(args.candidate),
            command=one_line(
                " ".join(
                    [
                        "python -m stonedem.study.equivalence",
                        *(argv if argv is not None else sys.argv[1:]),
                    ]
                ),
                400,
            ),
            wall_seconds=time.perf_counter() - start,
        )
        write_dataset(judgement, out)
        for line in report_lines(judgement):
            print(line)
        return 0 if judgement.attrs["equivalent"] == "yes" else 1

    return options.run(command)


if __name__ == "__main__":
    sys.exit(main())
