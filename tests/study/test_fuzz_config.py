"""Fuzzing the study config (issue 13): what ``snakemake -n`` refuses and what it lets through.

``stonedem.study.grid.check_config`` is what workflow/rules/common.smk runs at DAG time. Hypothesis
mutates the real config (config/config.yaml under tests/workflow/config.yaml: every study,
one to three cases each) with wrong types, negative, zero, NaN and huge values, unknown keys,
missing structures, unknown records, added, removed and reordered grid keys. Each mutated
config is either refused with one InputError line naming a path of the config, or accepted,
and then every case's scene builds as its job builds it (``stonedem.study.runner.run_case`` up to
the simulation: natural duration, ``scene_from_dict``, the time step) and every input of every
figure and table is made by a rule. ``HYPOTHESIS_PROFILE=fuzz`` runs 10 000 examples per test.
"""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import pytest
from hypothesis import given, note
from hypothesis import strategies as st

from stonedem.errors import InputError
from stonedem.io.spec import parse_range
from stonedem.study.grid import (
    CASE_ID_PATTERN,
    PARAMETERS,
    SWEPT,
    check_config,
    config_cases,
    ensemble_settings,
    load_config,
    study_members,
    with_members,
)

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
RECORDS = ROOT / "records"
BASE = load_config(ROOT / "config" / "config.yaml", ROOT / "tests" / "workflow" / "config.yaml")
RECORD_NAMES = sorted(BASE["records"])

# values no parameter or scene field should take, and some it should
HOSTILE = st.one_of(
    st.sampled_from(
        [
            -2.0,
            -1,
            0,
            0.0,
            -0.0,
            float("nan"),
            float("inf"),
            -float("inf"),
            1e300,
            1e-300,
            10**9,
            "high",
            "1.0e9",
            "",
            " ",
            "a/b",
            True,
            False,
            None,
            [],
            {},
            [1.0],
            {"a": 1},
            "per_span",
            "nope",
            "mexico_standin_chichi_tcu102",
            1,
            2,
            3,
            0.5,
            1.5,
            1000.0,
        ]
    ),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-5, 200),
    st.text(max_size=4),
)


def plausible(key: str):
    """Values a study could sensibly sweep for parameter ``key``."""
    if key == "record":
        return st.sampled_from(RECORD_NAMES)
    if key == "component":
        return st.sampled_from(["FF01a", "NP03b", "NN15a"])
    field = SWEPT[key]
    if field.kind == "choice":
        return st.sampled_from(field.choices)
    if field.kind == "integer":
        low, high = (int(x) for x in parse_range(field.range)[:2])
        return st.integers(low, min(low + 7, high))
    low, high = {
        "pga": (0.5, 16.0),
        "pga_scale": (0.5, 9.0),
        "frequency": (0.1, 20.0),
        "amplitude": (0.01, 0.5),
        "clear_distance": (1.0, 4.0),
        "epistyle_density": (2000.0, 12000.0),
        "taper": (1.0, 2.0),
        "friction": (0.2, 1.0),
        "weak_joint_mu": (0.0, 0.5),
    }.get(key, (0.5, 2.0))  # a new parameter: refused by name, or a case that builds
    return st.floats(low, high).map(lambda v: round(v, 3))


assert set(PARAMETERS) == set(SWEPT.keys), "a parameter without a value rule"

SCENE_FIELDS = [
    ("friction",),
    ("contact", "k_n"),
    ("contact", "model"),
    ("contact", "c_n"),
    ("contact", "damping"),
    ("contact", "k_t"),
    ("contact", "frame"),
    ("solver", "duration"),
    ("solver", "dt"),
    ("solver", "dt_safety"),
    ("solver", "stop_on_collapse"),
    ("output", "every"),
    ("excitation",),
    ("excitation", "kind"),
    ("excitation", "pga"),
    ("excitation", "frequency"),
    ("excitation", "amplitude"),
    ("excitation", "file"),
    ("excitation", "rate"),
    ("excitation", "scale"),
    ("structure",),
    ("structure", "kind"),
    ("structure", "n_drums"),
    ("structure", "height"),
    ("structure", "width"),
    ("structure", "taper"),
    ("structure", "capital"),
    ("structure", "n_columns"),
    ("structure", "clear_distance"),
    ("structure", "epistyle_type"),
    ("structure", "density"),
    ("structure", "links"),
    ("structure", "links", "kind"),
    ("links",),
    ("weak_joint",),
    ("weak_joint", "mu"),
    ("interface_friction",),
    ("depth",),
    ("gravity",),
]


def _set_path(node: dict, path, value) -> None:
    for part in path[:-1]:
        if not isinstance(node.get(part), dict):
            node[part] = {}
        node = node[part]
    node[path[-1]] = value


@st.composite
def mutations(draw, hostile: bool = True):
    """(config, study name): one study of BASE (with records and defaults) after 1-3 mutations."""
    config = copy.deepcopy(BASE)
    name = draw(st.sampled_from(sorted(config["studies"])))
    config["studies"] = {name: config["studies"][name]}
    study = config["studies"][name]
    values = (lambda key: st.one_of(plausible(key), HOSTILE)) if hostile else plausible
    kinds = ["grid_values", "add_grid_key", "remove_grid_key", "reorder_grid", "case"]
    if hostile:
        kinds += [
            "unknown_grid_key",
            "scene_field",
            "drop_key",
            "unknown_key",
            "unknown_record",
            "record_file",
        ]
    for kind in draw(st.lists(st.sampled_from(kinds), min_size=1, max_size=3)):
        grid = study.get("grid") if isinstance(study.get("grid"), dict) else None
        if kind == "grid_values":
            key = draw(st.sampled_from(sorted(PARAMETERS)))
            study["grid"] = grid if grid is not None else {}
            study["grid"][key] = draw(
                st.lists(values(key), min_size=0 if hostile else 1, max_size=3)
            )
        elif kind == "add_grid_key":
            key = draw(st.sampled_from(sorted(set(PARAMETERS) - set(grid or {}))))
            study["grid"] = grid if grid is not None else {}
            study["grid"][key] = list(
                dict.fromkeys(draw(st.lists(plausible(key), min_size=1, max_size=3)))
            )
        elif kind == "remove_grid_key" and grid:
            del grid[draw(st.sampled_from(sorted(grid)))]
        elif kind == "reorder_grid" and grid:
            study["grid"] = dict(draw(st.permutations(list(grid.items()))))
        elif kind == "case":
            keys = draw(
                st.lists(
                    st.sampled_from(sorted(PARAMETERS) + (["bogus"] if hostile else [])),
                    min_size=1,
                    max_size=3,
                    unique=True,
                )
            )
            case = {k: draw(values(k) if k in PARAMETERS else HOSTILE) for k in keys}
            study["cases"] = [
                *(study.get("cases") if isinstance(study.get("cases"), list) else []),
                case,
            ]
        elif kind == "unknown_grid_key":
            study["grid"] = {
                **(grid or {}),
                draw(st.sampled_from(["speed", "Pga", "duration", "k_n", ""])): [1.0],
            }
        elif kind == "scene_field":
            target = config["defaults"] if draw(st.booleans()) else study
            _set_path(target, draw(st.sampled_from(SCENE_FIELDS)), draw(HOSTILE))
        elif kind == "drop_key":
            where = draw(
                st.sampled_from(
                    [
                        "structure",
                        "excitation",
                        "grid",
                        "cases",
                        "solver",
                        "friction",
                        "contact",
                        "defaults.contact",
                        "defaults.solver",
                        "records",
                    ]
                )
            )
            if where.startswith("defaults."):
                config["defaults"].pop(where.split(".")[1], None)
            elif where == "records":
                config["records"].pop(draw(st.sampled_from(RECORD_NAMES)), None)
            else:
                study.pop(where, None)
        elif kind == "unknown_key":
            target = draw(
                st.sampled_from(
                    ["study", "structure", "contact", "solver", "excitation", "defaults", "config"]
                )
            )
            node = {"study": study, "defaults": config["defaults"], "config": config}.get(target)
            if node is None:
                node = (
                    study.setdefault(target, {})
                    if isinstance(study.get(target, {}), dict)
                    else study
                )
            node["bogus_key"] = 1
        elif kind == "unknown_record":
            bad = draw(
                st.sampled_from(
                    ["nope", "athens", "Mexico_standin_chichi_tcu102", "records/x.nc", 5]
                )
            )
            if draw(st.booleans()):
                study["grid"] = {**(grid or {}), "record": [bad]}
            else:
                _set_path(study, ("excitation", "file"), bad)
        elif kind == "record_file":  # listed under records:, but no records/<name>.nc
            config["records"]["missing_record"] = {"set": "farfield", "id": 3, "component": "a"}
    note(f"study {name}: {study}")
    note(f"defaults: {config['defaults']}")
    return config, name


def _is_config_path(field: str, config: dict) -> bool:
    parts = [p for p in re.split(r"[.\[\]]", field) if p]
    if not parts or (
        parts[0] not in config and parts[0] not in ("config", "studies", "defaults", "records")
    ):
        return False
    return (
        parts[0] != "studies"
        or len(parts) == 1
        or any(field.startswith(f"studies.{n}") for n in config["studies"])
    )


def _assert_refused_cleanly(error: InputError, config: dict) -> None:
    message = str(error)
    assert "\n" not in message, message
    assert message.startswith(f"{error.field}: ") and error.problem, message
    assert _is_config_path(error.field, config), (
        f"{error.field!r} is not a path of the config: {message}"
    )


def _outputs(config: dict, tables: dict, catalogue_tables: dict) -> set:
    """Files some rule makes (workflow/rules/*.smk, common.smk), or on disk (records/)."""
    made = {f"records/{name}.nc" for name in config["records"]} | {
        f"records/{p.name}" for p in RECORDS.glob("*.nc")
    }
    made |= {f"results/cubes/{s}.nc" for s in tables}
    made |= {f"results/cases/{s}/{c.id}.nc" for s, cases in tables.items() for c in cases}
    made |= {f"results/tables/{name}.csv" for name in catalogue_tables}
    return made


def _assert_dag_builds(config: dict, tables: dict) -> None:
    """What common.smk derives from the cases: ids that fit {case}, record inputs that exist,
    figure and table inputs that some rule makes."""
    from stonedem.figures import figure_table, input_paths, reduction_table
    from tests.workflow_files import catalogue_paths

    studies = {name: {c.id: c for c in cases} for name, cases in tables.items()}
    catalogue_tables = reduction_table(studies)
    made = _outputs(config, tables, catalogue_tables)
    for cases in tables.values():
        for case in cases:
            assert CASE_ID_PATTERN.fullmatch(case.id), case.id
            record = case.params.get("record") or (case.scene.get("excitation") or {}).get("file")
            if record:
                assert record in config["records"] and (RECORDS / f"{record}.nc").is_file(), record
    patterns = catalogue_paths()
    for name, entry in {**catalogue_tables, **figure_table(studies, config)}.items():
        for path in input_paths(entry.inputs, patterns):
            assert path in made, f"{name} needs {path}, which no rule makes"


def _assert_cases_run(tables: dict) -> None:
    """Each case's scene builds as stonedem.study.runner.run_case builds it before it simulates."""
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import choose_time_step
    from stonedem.study.runner import natural_duration

    for cases in tables.values():
        for case in cases:
            spec = copy.deepcopy(case.scene)
            solver = spec.setdefault("solver", {})
            if solver.get("duration") is None:
                solver["duration"] = natural_duration(spec.get("excitation"), RECORDS)
            choose_time_step(scene_from_dict(spec, base_dir=RECORDS))


def _check(config: dict):
    """check_config's verdict: the case tables, or None when refused (cleanly, or the test
    fails)."""
    try:
        tables = check_config(config, records_dir=RECORDS, schema=SCHEMA)
    except InputError as error:
        _assert_refused_cleanly(error, config)
        return None
    members, perturbation = ensemble_settings(config)
    assert {
        n: [
            c.id
            for c in with_members(
                cases, study_members(config["studies"][n], members, n), perturbation
            )
        ]
        for n, cases in tables.items()
    } == {n: [c.id for c in cases] for n, cases in config_cases(config).items()}, (
        "common.smk's STUDIES"
    )
    return tables


@given(mutations())
def test_fuzz_config_refused_by_name_or_every_case_builds(mutated):
    config, _ = mutated
    tables = _check(config)
    if tables is not None:
        _assert_cases_run(tables)
        _assert_dag_builds(config, tables)


@given(mutations(hostile=False))
def test_fuzz_config_grid_keys_added_removed_reordered_keep_the_dag(mutated):
    """Plausible grid changes of one study, in the whole tiny config: the DAG always builds
    (or the change is refused by name, e.g. a record swept under a harmonic excitation)."""
    config, name = mutated
    tables = _check(config)
    if tables is None:
        return
    whole = copy.deepcopy(BASE)
    whole["studies"][name] = config["studies"][name]
    _assert_dag_builds(whole, config_cases(whole))


@pytest.mark.parametrize(
    "mutate, field",
    [
        (
            lambda c: c["studies"]["ramp_drums"]["grid"].update(n_drums=[1, -2]),
            "studies.ramp_drums.grid.n_drums[1]",
        ),
        (
            lambda c: c["studies"]["standalone_records"]["grid"].update(pga=["high"]),
            "studies.standalone_records.grid.pga[0]",
        ),
        (
            lambda c: c["studies"]["standalone_records"]["grid"].update(pga=[math.nan]),
            "studies.standalone_records.grid.pga[0]",
        ),
        (lambda c: c["defaults"]["contact"].update(k_n=-1.0e9), "defaults.contact.k_n"),
        (
            lambda c: c["studies"]["ramp_drums"].update(contact={"k_n": -1.0}),
            "studies.ramp_drums.contact.k_n",
        ),
        (lambda c: c["studies"]["ramp_drums"].pop("structure"), "studies.ramp_drums.structure"),
        (
            lambda c: c["studies"]["standalone_records"]["grid"].update(record=["nope"]),
            "studies.standalone_records.grid.record[0]",
        ),
        (
            lambda c: c["studies"]["colonnade_columns"]["excitation"].update(file="nope"),
            "studies.colonnade_columns.excitation.file",
        ),
        (
            lambda c: c["records"].update(
                missing_record={"set": "farfield", "id": 3, "component": "a"}
            ),
            "records.missing_record",
        ),
        (
            lambda c: c["studies"]["ramp_drums"]["grid"].update(speed=[1.0]),
            "studies.ramp_drums.grid.speed",
        ),
        (
            lambda c: c["studies"]["ramp_drums"]["grid"].update(
                n_drums=list(range(1, 101)), friction=[0.1 * i for i in range(30)]
            ),
            "studies.ramp_drums.grid",
        ),
        (
            lambda c: c["studies"]["ramp_drums"]["solver"].update(duration=1.0e6),
            "studies.ramp_drums.solver.duration",
        ),
        (
            lambda c: c["studies"]["ramp_drums"].update(output={"every": 1e-8}),
            "studies.ramp_drums.output.every",
        ),
        (
            lambda c: c["studies"]["ramp_drums"]["solver"].update(dt=0.1),
            "studies.ramp_drums.solver.dt",
        ),
        (
            lambda c: c["studies"]["ramp_taper"]["structure"].update(n_drums=10**6),
            "studies.ramp_taper.structure.n_drums",
        ),
        (
            lambda c: c["studies"]["friction_levels"]["grid"].update(weak_joint=[4]),
            "studies.friction_levels.grid.weak_joint[0]",
        ),
        (
            lambda c: c["studies"]["harmonic_drums"]["grid"].update(record=[RECORD_NAMES[0]]),
            "studies.harmonic_drums.grid.record[0]",
        ),
        (
            lambda c: c["studies"]["colonnade_distance"]["grid"].update(clear_distance=[1e-6]),
            "studies.colonnade_distance.structure",
        ),
        (lambda c: c.update(wall_cases=["nope"]), "wall_cases[0]"),
        (lambda c: c.update(studdies={}), "studdies"),  # ignored, it planned the whole study
    ],
)
def test_each_class_of_bad_config_is_refused_by_its_path(mutate, field):
    config = copy.deepcopy(BASE)
    mutate(config)
    with pytest.raises(InputError) as caught:
        check_config(config, records_dir=RECORDS, schema=SCHEMA)
    assert caught.value.field == field, str(caught.value)
    _assert_refused_cleanly(caught.value, config)


def test_the_real_configs_pass_and_the_schema_knows_every_parameter():
    import yaml

    for extra in (
        (),
        (ROOT / "config" / "quick.yaml",),
        (ROOT / "tests" / "workflow" / "config.yaml",),
    ):
        config = load_config(ROOT / "config" / "config.yaml", *extra)
        tables = check_config(config, records_dir=RECORDS, schema=SCHEMA)
        _assert_dag_builds(config, tables)
    schema = yaml.safe_load(SCHEMA.read_text())
    study = schema["properties"]["studies"]["additionalProperties"]["properties"]
    assert study["grid"]["$ref"] == "#/$defs/grid" and study["cases"]["items"]["$ref"] == (
        "#/$defs/case"
    )
    assert (
        set(schema["$defs"]["grid"]["properties"])
        == set(PARAMETERS)
        == set(schema["$defs"]["case"]["properties"])
    )
    for key in ("n_drums", "n_columns", "weak_joint"):
        low, high = parse_range(SWEPT[key].range)[:2]
        assert (schema["$defs"][key]["minimum"], schema["$defs"][key]["maximum"]) == (low, high), (
            key
        )
    assert schema["$defs"]["epistyle_type"]["enum"] == list(SWEPT["epistyle_type"].choices)
