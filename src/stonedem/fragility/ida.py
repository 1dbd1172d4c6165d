"""Incremental dynamic analysis (IDA) over the FEMA P695 record suites: config -> searches ->
the structure x record x limit-state cube.

The config's ``fragility:`` section names structures (scene keys, as a study) and record
suites; each structure becomes one threshold-search study (``ida_<structure>``) whose
systems are the suite components (study parameter ``component``), searched in PGA by the
hunt-and-fill machinery of the Table 7.1 thresholds (``stonedem.study.search``). Collapse is
the search's bracket; the lesser limit states are read off the same runs (IDA curves:
each run's peak response against its PGA, interpolated between the runs that bracket the
first exceedance). PGV follows from PGA by the record's own PGV/PGA ratio, since a run is
the record scaled. ``stonedem.fragility.fit`` fits the curves.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.netcdf import open_result
from stonedem.io.spec import REQUIRED, Field, Spec, got
from stonedem.motion.suites import SUITES, load_suite

STUDY_PREFIX = "ida_"
DEFAULT_JOB_SECONDS = 120.0  # estimated kernel seconds of searches packed into one job
# the config's fragility: section (pulse_check: one of the structures, checked at the call)
FRAGILITY = Spec(
    (
        Field("description", "any", doc="what the IDA is for"),
        Field(
            "structures",
            "mapping",
            REQUIRED,
            hint="write structures: {column_3_drums: {structure: {kind: column, ...}}}",
            doc="{name: scene keys}: each structure becomes the search study ida_<name>",
        ),
        Field(
            "suites",
            "list",
            default=list(SUITES),
            hint=f"use some of {', '.join(SUITES)}",
            doc="the FEMA P695 record suites (records/suites/)",
        ),
        Field(
            "components",
            "list",
            hint="list components by name, e.g. FF01a",
            doc="the suites' components to run (default: all)",
        ),
        Field(
            "run_structures",
            "list",
            hint="list structures by name",
            doc="the structures to run (default: all)",
        ),
        Field(
            "search",
            "mapping",
            default={},
            hint="write search: {tolerance: 0.05, ...}",
            doc="the search settings over DEFAULT_SEARCH",
        ),
        Field(
            "job_seconds",
            "number",
            "s",
            "[1, 86400]",
            DEFAULT_JOB_SECONDS,
            hint=f"give e.g. job_seconds: {DEFAULT_JOB_SECONDS:g}",
            doc="estimated kernel seconds of searches packed into one job",
        ),
        Field(
            "bootstrap",
            "integer",
            range="[10, 100000]",
            default=1000,
            hint="give e.g. bootstrap: 1000",
            doc="bootstrap samples of each fit",
        ),
        Field("pulse_check", "text", hint="name one of the structures", doc="its structure"),
        Field(
            "compare",
            "mapping",
            default={},
            hint="write compare: {links: [column_3_drums, column_3_drums_titanium]}",
            doc="{name: structures} drawn side by side in the figure fragility_compare_<name>"
            ".png (variants of one structure: linked, tilted)",
        ),
    )
)
# a structure's keys: scene keys (checked as its study's cases), its suites, a description
STRUCTURE = Spec(
    tuple(
        Field(key, "any")
        for key in (
            "structure",
            "friction",
            "contact",
            "solver",
            "output",
            "interface_friction",
            "suites",
            "description",
        )
    )
)
SUITE = Field("suite", "choice", choices=SUITES)
COMPONENT = Field("component", "text")
# the search of every (structure, record): the Table 7.1 machinery, a 5 % bracket (the
# record-to-record dispersion of collapse PGA, beta ~ 0.3-0.6, dwarfs it)
# the IDA cube and fragility figures read the runs' measures only, so its search files keep no
# histories
DEFAULT_SEARCH = {
    "parameter": "pga",
    "start": 1.0,
    "factor": 1.8,
    "tolerance": 0.05,
    "maximum": 64.0,
    "fill": 1,
    "max_runs": 20,
    "histories": False,
}


@dataclass(frozen=True)
class LimitState:
    """One limit state of the IDA: everything about it in one row of LIMIT_STATES."""

    measure: (
        str  # case measure (stonedem.engine.measures) compared with the threshold; "" for collapse
    )
    threshold: (
        Callable | None
    )  # (theta_cr [rad], drum width [m]) -> the measure's value at the limit; None: collapse
    long_name: str  # the cube's attrs limit_state_<name>
    label: str  # figure titles


# lesser limit states (issue 16; Psycharis et al. 2013 use normalised rotation and residual
# drum displacement for ancient columns), then collapse, the search's own verdict
LIMIT_STATES: dict[str, LimitState] = {
    # thesis 6.3.1, as stonedem.engine.measures.rocking_onset_time
    "rocking_onset": LimitState(
        "max_rocking",
        lambda theta_cr, width: theta_cr / 30.0,
        "mean drum rotation first exceeds theta_cr / 30 (uplift)",
        "rocking onset (theta_cr / 30)",
    ),
    "half_critical_rotation": LimitState(
        "max_rocking",
        lambda theta_cr, width: theta_cr / 2.0,
        "peak mean drum rotation exceeds theta_cr / 2",
        "rotation theta_cr / 2",
    ),
    "residual_sliding": LimitState(
        "residual_total_sliding",
        lambda theta_cr, width: 0.01 * width,
        "residual joint sliding exceeds 1 % of the drum width",
        "residual sliding 1 % of width",
    ),
    "collapse": LimitState("", None, "collapse (the search's smallest collapsing PGA)", "collapse"),
}


def suite_components(suites) -> dict[str, str]:
    """{component name: suite} of the named suites, in file order."""
    names = {}
    for suite in suites:
        names.update({str(n): suite for n in load_suite(suite).record.values})
    return names


def fragility_studies(config: dict) -> dict[str, dict]:
    """{study name: study spec} of the config's ``fragility:`` section ({} when there is none):
    one threshold-search study per structure, over the components of its suites."""
    spec = config.get("fragility")
    if spec is None:
        return {}
    where = "fragility"
    FRAGILITY.check_keys(spec, where)
    structures = _given(FRAGILITY["structures"], spec.get("structures"), f"{where}.structures")
    search = spec.get("search")
    search = (
        {} if search is None else _given(FRAGILITY["search"], search, f"{where}.search", empty=True)
    )
    pulse_check = dataclasses.replace(
        FRAGILITY["pulse_check"], kind="choice", choices=tuple(structures), hint=""
    )
    values = FRAGILITY.replace(pulse_check).check(spec, where)
    suites = _given(
        FRAGILITY["suites"], spec.get("suites", values["suites"]), f"{where}.suites", SUITE
    )
    chosen = list(structures)
    if values["run_structures"] is not None:
        structure = Field("structure", "choice", choices=tuple(structures))
        chosen = _given(
            FRAGILITY["run_structures"],
            values["run_structures"],
            f"{where}.run_structures",
            structure,
        )
    every = suite_components(list(SUITES))  # {component: suite}, each suite file read once
    components = values["components"]
    if components is not None:
        components = _given(FRAGILITY["components"], components, f"{where}.components", COMPONENT)
        unknown = next((i for i, name in enumerate(components) if name not in every), None)
        if unknown is not None:
            raise InputError(
                f"{where}.components[{unknown}]",
                f"{components[unknown]!r} is not a FEMA P695 component",
                "use names of records/suites/, e.g. FF01a, NP01b, NN15a",
            )
    search = {**DEFAULT_SEARCH, **search}
    studies = {}
    for name in chosen:
        body = structures[name]
        place = f"{where}.structures.{name}"
        STRUCTURE.check_keys(body, place)
        own = _given(FRAGILITY["suites"], body.get("suites", suites), f"{place}.suites", SUITE)
        names = [n for n in (every if components is None else components) if every[n] in own]
        if not names:
            raise InputError(
                f"{where}.components",
                f"no component of {name}'s suites ({', '.join(own)})",
                "name components of the structure's suites, e.g. FF01a",
            )
        study = {k: copy.deepcopy(v) for k, v in body.items() if k not in ("suites", "description")}
        study.update(
            excitation={"kind": "record"},
            grid={"component": names},
            search=dict(search),
            description=body.get("description", f"IDA of {name} over {', '.join(own)}"),
        )
        studies[f"{STUDY_PREFIX}{name}"] = study
    return studies


def _given(f: Field, value, where: str, item: Field | None = None, empty: bool = False):
    """``value`` as the list or mapping field ``f``, refused with the field's own hint (the
    kit's mapping refusal has a generic one) and, unless ``empty``, when empty (the kit has no
    least count); a list's items checked as ``item``."""
    shape = dict if f.kind == "mapping" else list
    if not isinstance(value, shape) or not (value or empty):
        kind = f"{'' if empty else 'non-empty '}{'mapping' if shape is dict else 'list'}"
        raise InputError(where, f"expected a {kind}, got {got(value)}", f.hint)
    return value if item is None else [item.check(v, f"{where}[{i}]") for i, v in enumerate(value)]


def fragility_comparisons(config: dict) -> dict[str, list[str]]:
    """{name: structures} of the config's ``fragility.compare``, each two or more of its
    structures; a comparison naming a structure the run leaves out (``run_structures``) is not
    drawn."""
    from stonedem.study.grid import NAME_PATTERN

    spec = config.get("fragility") or {}
    compare = spec.get("compare")
    if compare is None:
        return {}
    where = "fragility.compare"
    compare = _given(FRAGILITY["compare"], compare, where, empty=True)
    structures = tuple(spec.get("structures") or ())
    run = spec.get("run_structures") or structures
    structure = Field("structure", "choice", choices=structures)
    drawn = {}
    for name, names in compare.items():
        place = f"{where}.{name}"
        if not isinstance(name, str) or not NAME_PATTERN.fullmatch(name):
            raise InputError(
                place, "a comparison's name is a file name", "use letters, digits, _ and -"
            )
        if not isinstance(names, list) or len(names) < 2:
            raise InputError(
                place,
                f"expected a list of two or more structures, got {got(names)}",
                FRAGILITY["compare"].hint,
            )
        names = [structure.check(n, f"{place}[{i}]") for i, n in enumerate(names)]
        if len(set(names)) < len(names):
            raise InputError(place, "a structure is named twice", "name each structure once")
        if all(n in run for n in names):
            drawn[name] = names
    return drawn


def fragility_config(config: dict) -> dict:
    """The config with its fragility studies as ``studies:`` (and nothing else studied); one
    member each: the study's ensemble (issue 44) would multiply the IDA's 4 209 runs."""
    return {**config, "studies": fragility_studies(config), "ensemble": None}


def check_fragility(config: dict, records_dir="records") -> dict:
    """{study: case table} of the fragility studies, every case checked as its job would
    run it (stonedem.study.grid.check_config); an InputError names the fragility config path."""
    from stonedem.study.grid import check_config

    studies = fragility_studies(config)
    if not studies:
        return {}
    try:
        return check_config(fragility_config(config), records_dir=records_dir)
    except InputError as error:
        field = error.field
        for study in studies:
            for prefix, where in (
                (f"studies.{study}.grid.component", "fragility.components"),
                (f"studies.{study}.search", "fragility.search"),
                (f"studies.{study}", f"fragility.structures.{study[len(STUDY_PREFIX) :]}"),
            ):
                if (
                    field == prefix
                    or field.startswith(prefix + ".")
                    or field.startswith(prefix + "[")
                ):
                    field = where + field[len(prefix) :]
                    break
            else:
                continue
            break
        raise InputError(field, error.problem, error.fix) from None


# --- from the searches to the cube --------------------------------------------------------


def first_exceedance(values, exceeded, response, threshold) -> tuple[float, float, float, bool]:
    """(estimate, lower, upper, censored) of the intensity at which a limit state is first
    exceeded on one record's runs (any order). upper: the smallest run exceeding it; lower:
    the largest run below that did not (NaN: none); estimate: the IDA curve (response against
    intensity, log-log) interpolated to the threshold between them, or their geometric mean
    when a response is not usable (a collapse ends the run); censored: never exceeded, the
    estimate is the largest run (a lower bound)."""
    order = np.argsort(values)
    x = np.asarray(values, float)[order]
    hit = np.asarray(exceeded, bool)[order]
    r = np.asarray(response, float)[order]
    if not hit.any():
        return float(x[-1]), float(x[-1]), math.nan, True
    i = int(np.argmax(hit))
    if i == 0:
        return float(x[0]), math.nan, float(x[0]), False
    lo, hi = float(x[i - 1]), float(x[i])
    r_lo, r_hi = r[i - 1], r[i]
    if (
        np.isfinite(threshold)
        and np.isfinite(r_lo)
        and np.isfinite(r_hi)
        and 0 < r_lo < threshold <= r_hi
    ):
        share = math.log(threshold / r_lo) / math.log(r_hi / r_lo)
        return float(math.exp(math.log(lo) + share * math.log(hi / lo))), lo, hi, False
    return math.sqrt(lo * hi), lo, hi, False


def record_table(suites) -> xr.Dataset:
    """Per component of the suites: suite, PGA and PGV of the baseline-corrected record (the
    runs scale its corrected peak to the target, so PGV = PGA x pgv / pga), predominant
    frequency, the period of the 5 % pseudo-velocity spectrum's peak (a pulse period: Baker
    2007 finds T_p near it) and provenance."""
    from stonedem.motion.records import baseline_correct

    pieces = []
    for suite in suites:
        ds = load_suite(suite)
        peaks = []
        for k in range(ds.sizes["record"]):
            r = ds.isel(record=k)
            n, dt = int(r.n_samples), float(r.dt)
            accel = np.asarray(r.acceleration.values[:n], float)
            peaks.append(float(np.abs(baseline_correct(np.arange(n) * dt, accel)).max()))
        psv = ds.psa * ds.period / (2 * math.pi)
        table = xr.Dataset(coords={"record": ds.record.values})
        table["suite"] = (
            "record",
            np.array([suite] * ds.sizes["record"], dtype=object),
            {"long_name": "record suite"},
        )
        table["record_pga"] = (
            "record",
            np.array(peaks),
            {"units": "m s-2", "long_name": "PGA of the baseline-corrected record"},
        )
        table["record_pgv"] = (
            "record",
            ds.pgv.values,
            {"units": "m s-1", "long_name": "PGV of the baseline-corrected record"},
        )
        table["predominant_frequency"] = (
            "record",
            ds.predominant_frequency.values,
            {"units": "Hz", "long_name": "predominant frequency of the record"},
        )
        table["pulse_period"] = (
            "record",
            ds.period.values[psv.argmax("period").values],
            {"units": "s", "long_name": "period of the peak of the 5 % pseudo-velocity spectrum"},
        )
        for name in ("event", "station", "magnitude", "rsn"):
            table[name] = ("record", ds[name].values, dict(ds[name].attrs))
        pieces.append(table)
    return xr.concat(pieces, dim="record")


def ida_cube(search_paths, structures: dict, suites) -> xr.Dataset:
    """The IDA cube (structure x record x limit_state) from the search files of the
    fragility studies; ``structures``: {name: its fragility spec} (drum width for sliding)."""
    records = record_table(suites)
    names = [str(n) for n in records.record.values]
    order = list(structures)
    shape = (len(order), len(names), len(LIMIT_STATES))
    out = {k: np.full(shape, math.nan) for k in ("pga", "lower", "upper")}
    censored = np.zeros(shape, np.int8)
    n_runs = np.zeros(shape[:2], np.int32)
    monotonic = np.ones(shape[:2], np.int8)
    ran = np.zeros(shape[:2], bool)
    theta = np.full(len(order), math.nan)
    settings = {}
    for path in search_paths:
        with open_result(path) as ds:
            ds = ds.load()
        study = ds.attrs.get("study", "")
        name = study[len(STUDY_PREFIX) :]
        if name not in structures:
            raise InputError(
                "fragility.structures",
                f"{path}: structure {name!r} is not configured",
                "rerun snakemake fragility after editing the config",
            )
        s, k = order.index(name), names.index(str(ds.component.values))
        ran[s, k] = True
        settings = {key: ds.attrs[key] for key in ds.attrs if key.startswith("search_")}
        width = float(structures[name]["structure"].get("width", 1.0))
        values = ds.pga.values
        collapsed = ds.collapsed.values > 0
        theta_cr = float(np.nanmin(ds.theta_cr.values))
        theta[s] = theta_cr
        for j, ls in enumerate(LIMIT_STATES.values()):
            if ls.threshold is None:
                upper = float(ds.collapse_threshold)
                if math.isfinite(upper):
                    est, lo, hi, cen = upper, float(ds.survived_below_threshold), upper, False
                else:
                    est, lo, hi, cen = float(values.max()), float(values.max()), math.nan, True
            else:
                response = np.where(collapsed, math.nan, ds[ls.measure].values)
                limit = ls.threshold(theta_cr, width)
                exceeded = collapsed | (np.nan_to_num(response, nan=-1.0) > limit)
                est, lo, hi, cen = first_exceedance(values, exceeded, response, limit)
            out["pga"][s, k, j], out["lower"][s, k, j], out["upper"][s, k, j] = est, lo, hi
            censored[s, k, j] = cen
        n_runs[s, k] = int(ds.n_runs)
        monotonic[s, k] = int(ds.monotonic)
    ratio = (records.record_pgv / records.record_pga).values
    cube = xr.Dataset(
        coords={
            "structure": (
                "structure",
                np.array(order, dtype=object),
                {"long_name": "structure (config fragility.structures)"},
            ),
            "record": (
                "record",
                np.array(names, dtype=object),
                {"long_name": "FEMA P695 component (records/suites/)"},
            ),
            "limit_state": (
                "limit_state",
                np.array(list(LIMIT_STATES), dtype=object),
                {"long_name": "limit state; see attrs limit_state_<name>"},
            ),
        }
    )
    cube = cube.assign_coords({v: records[v] for v in records.data_vars})
    mask = ran[:, :, None]
    attrs = {
        "pga": (
            "m s-2",
            "PGA at which the limit state is first exceeded (censored: a lower bound)",
        ),
        "lower": ("m s-2", "largest PGA run below it that did not exceed it"),
        "upper": ("m s-2", "smallest PGA run that exceeded it"),
    }
    for key, var in (("pga", "pga_at_limit"), ("lower", "pga_lower"), ("upper", "pga_upper")):
        units, long_name = attrs[key]
        cube[var] = (
            ("structure", "record", "limit_state"),
            np.where(mask, out[key], math.nan),
            {"units": units, "long_name": long_name},
        )
    cube["pgv_at_limit"] = (
        ("structure", "record", "limit_state"),
        cube.pga_at_limit.values * ratio[None, :, None],
        {
            "units": "m s-1",
            "long_name": "PGV at which the limit state is first exceeded "
            "(the record's PGV/PGA times pga_at_limit)",
        },
    )
    cube["censored"] = (
        ("structure", "record", "limit_state"),
        np.where(mask, censored, -1).astype(np.int8),
        {
            "units": "1",
            "long_name": "1: not exceeded up to the search maximum (a lower bound); -1: not run",
        },
    )
    cube["n_runs"] = (
        ("structure", "record"),
        np.where(ran, n_runs, 0),
        {"units": "1", "long_name": "simulations of the record's search"},
    )
    cube["monotonic"] = (
        ("structure", "record"),
        np.where(ran, monotonic, -1).astype(np.int8),
        {"units": "1", "long_name": "1: no survivor above the smallest collapse; -1: not run"},
    )
    cube["theta_cr"] = (
        "structure",
        theta,
        {"units": "rad", "long_name": "critical angle atan(b/h) of the column"},
    )
    cube.attrs = {
        "title": "stonedem IDA cube: limit-state intensities per structure and FEMA P695 record",
        "method": "hunt-and-fill search in PGA per (structure, record) (stonedem.study.search); "
        "lesser limit states interpolated on the runs' IDA curves (stonedem.fragility.ida)",
        "n_simulations": int(cube.n_runs.sum()),
        **settings,
        **{f"limit_state_{name}": ls.long_name for name, ls in LIMIT_STATES.items()},
    }
    return cube


# intensity measures of the cube: the variable holding each and its units
MEASURES = {"pga": ("pga_at_limit", "m s-2", "PGA"), "pgv": ("pgv_at_limit", "m s-1", "PGV")}
