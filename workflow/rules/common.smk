import sys
from pathlib import Path

from snakemake.utils import validate

import dem.study
from dem.errors import InputError


def config_flag(key, default):
    """A true/false switch of the config: --config key=true arrives as a string."""
    return str(config.get(key, default)).lower() == "true"


EXTRACT_RECORDS = config_flag("extract_records", False)
# The config is refused here, at DAG time (snakemake -n), when any case would fail in its job:
# every value of every grid, every study and the defaults are built into each case's scene
# through dem run's validation; records must be listed under records: and be on disk; sizes
# past dem.study.MAX_* are refused. One line names the config path (dem.study.check_config).
# Checked once, by the main process (not again in each cluster job, which re-reads this file).
if getattr(workflow, "is_main_process", True):
    try:
        dem.study.check_config(config, records_dir="records", extract_records=EXTRACT_RECORDS,
                               schema=Path(workflow.current_basedir) / "../schemas/config.schema.yaml")
    except InputError as error:
        # one line, the last one printed, and dem's exit code for bad input (dem.entry); a
        # WorkflowError would add Snakemake's header and a traceback line after it
        print(f"Bad config: {error}", file=sys.stderr)
        sys.exit(2)
validate(config, schema="../schemas/config.schema.yaml")  # fills the schema's defaults

RECORDS = config["records"]
RECORD_NAMES = list(RECORDS)


wildcard_constraints:
    name="|".join(RECORD_NAMES),


def record_params(wildcards):
    return RECORDS[wildcards.name]


import dem.figures
import dem.study

STUDIES = {
    name: {case.id: case for case in cases} for name, cases in dem.study.config_cases(config).items()
}
# figures whose cases are in the configured grids (a reduced profile draws fewer)
FIGURES = dem.figures.figure_table(STUDIES, config)
FIGURE_NAMES = list(FIGURES)


wildcard_constraints:
    study="|".join(STUDIES),
    figure="|".join(FIGURES),
    case="[A-Za-z0-9_.+-]+",


def case_files(wildcards):
    return [f"results/cases/{wildcards.study}/{case}.nc" for case in STUDIES[wildcards.study]]


# colonnade studies that vary one parameter at a time (thesis 7.3-7.8)
EPISTYLE_STUDIES = [s for s in STUDIES if s.startswith("colonnade_") and s != "colonnade_records"]
# harmonic studies reduced to sliding and rocking vs frequency (thesis Fig. 6.1, 6.5, 6.6)
FREQUENCY_STUDIES = [s for s in ("harmonic_frequency", "small_column_friction", "small_column_pga") if s in STUDIES]


def _tables():
    tables = [f"results/tables/epistyle_{s}.csv" for s in EPISTYLE_STUDIES]
    tables += [f"results/tables/frequency_response_{s}.csv" for s in FREQUENCY_STUDIES]
    if {"standalone_records", "colonnade_records"} <= set(STUDIES):
        tables.append("results/tables/table_7_1.csv")
    if {"ramp_drums", "ramp_taper"} <= set(STUDIES):
        tables += ["results/tables/thesis_fig_6_10.csv", "results/tables/thesis_fig_6_13.csv"]
    return tables


TABLES = _tables()
# the chapter-5 validations (workflow/rules/validation.smk); off in the workflow tests' tiny config
RUN_VALIDATION = config_flag("run_validation", True)


def case_record(wildcards):
    case = STUDIES[wildcards.study][wildcards.case]
    record = case.params.get("record") or case.scene.get("excitation", {}).get("file")
    return [f"records/{record}.nc"] if record else []


def case_of(wildcards):
    case = STUDIES[wildcards.study][wildcards.case]
    return {"study": case.study, "id": case.id, "params": case.params, "scene": case.scene}



def figure_input(wildcards):
    return list(FIGURES[wildcards.figure].inputs)


def figure_caption(wildcards):
    return FIGURES[wildcards.figure].caption


def study_description(wildcards):
    return config["studies"][wildcards.study].get("description", "")


# 3D rigid-block walls (manuscript Tables 1-3, A1), rules in walls.smk
WALL_TABLES = {
    "1": ["orduna_case1", "orduna_case2"],
    "2": ["s11", "s12", "s13", "s15", "s6", "s1_s2_s3", "s5", "s32", "s23", "s34"],
    "3": ["chee_liang_2_3", "chee_liang_8_12", "chee_liang_14_15", "chee_liang_4_5",
          "chee_liang_9_13", "chee_liang_10_11"],
}
WALL_CASES = [c for cases in WALL_TABLES.values() for c in cases] + ["free_standing"]
# manuscript figure -> cases drawn (damage maps; 22 is the pushover curves)
WALL_FIGURES = {
    "13": WALL_TABLES["1"],
    "15": ["s11", "s12", "s13", "s15"],
    "16": ["s6", "s1_s2_s3", "s5"],
    "17": ["s32"],
    "18": ["s23", "s34"],
    "20": ["chee_liang_2_3", "chee_liang_8_12", "chee_liang_14_15"],
    "21": ["chee_liang_4_5", "chee_liang_9_13", "chee_liang_10_11"],
    "22": WALL_TABLES["3"],
}
# config wall_cases (default: all): the cases run with the study; each table and figure is
# drawn from its selected cases, and left out when none is selected
WALL_SELECTED = [c for c in WALL_CASES if c in config.get("wall_cases", WALL_CASES)]


def selected(cases):
    """The cases of a wall table or figure that the config selects."""
    return [c for c in cases if c in WALL_SELECTED]


WALL_OUTPUTS = (
    [f"results/walls/{c}.nc" for c in WALL_SELECTED]
    + [f"results/tables/manuscript_table_{t}.csv" for t in WALL_TABLES if selected(WALL_TABLES[t])]
    + (["results/tables/manuscript_table_a1.csv"] if WALL_SELECTED else [])
    + [f"results/figures/manuscript_fig_{n}.png" for n in WALL_FIGURES if selected(WALL_FIGURES[n])]
)


def wall_figure_caption(wildcards):
    kind = "Pushover curves" if wildcards.wall_figure == "22" else "Damage maps at the limit load"
    cases = ", ".join(selected(WALL_FIGURES[wildcards.wall_figure]))
    return (f"Regenerates manuscript Fig. {wildcards.wall_figure}: {kind.lower()} of {cases} "
            "(interfaces: elastic, shear, flexural, shear and flexural, detached).")
