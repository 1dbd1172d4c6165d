import math
import sys
from pathlib import Path

from snakemake.utils import validate

import stonedem.study.cluster
import stonedem.study.grid
from stonedem.errors import InputError
from stonedem.motion.suites import record_file_name


def config_flag(key, default):
    """A true/false switch of the config: --config key=true arrives as a string."""
    return str(config.get(key, default)).lower() == "true"


EXTRACT_RECORDS = config_flag("extract_records", False)
# The config is refused here, at DAG time (snakemake -n), when any case would fail in its job:
# every value of every grid, every study and the defaults are built into each case's scene
# through stonedem run's validation; records must be listed under records: and be on disk; sizes
# past stonedem.study.grid.MAX_* are refused. One line names the config path (stonedem.study.grid.check_config).
# Checked once, by the main process (not again in each cluster job, which re-reads this file).
if getattr(workflow, "is_main_process", True):
    try:
        stonedem.study.grid.check_config(
            config,
            records_dir="records",
            extract_records=EXTRACT_RECORDS,
            schema=Path(workflow.current_basedir) / "../schemas/config.schema.yaml",
            files=workflow.configfiles,
        )
    except InputError as error:
        # one line, the last one printed, and stonedem's exit code for bad input (stonedem.entry); a
        # WorkflowError would add Snakemake's header and a traceback line after it
        print(f"Bad config: {error}", file=sys.stderr)
        sys.exit(2)
validate(config, schema="../schemas/config.schema.yaml")  # fills the schema's defaults

RECORDS = config["records"]
# threshold searches write one file each; "full" also every run's case file (simulate.smk)
FULL_SEARCH_RUNS = config.get("search_runs", "summary") == "full"
RECORD_NAMES = list(RECORDS)


wildcard_constraints:
    name="|".join(RECORD_NAMES),


def record_params(wildcards):
    return RECORDS[wildcards.name]


import stonedem.figures
import stonedem.fragility.ida
import stonedem.study.jobs
import stonedem.study.stripe_fill
import stonedem.study.grid

STUDIES = {
    name: {case.id: case for case in cases}
    for name, cases in stonedem.study.grid.config_cases(config).items()
}
# the catalogue's tables and figures (stonedem.figures) whose inputs are in the configured studies
# (a reduced profile makes fewer): results/tables/<table>.csv, results/figures/<figure>.png
TABLES = stonedem.figures.reduction_table(STUDIES)
FIGURES = stonedem.figures.figure_table(STUDIES, config)
FIGURE_NAMES = list(FIGURES)


# On a cluster (config/profiles/slurm: group-components) jobs of one kind share a submission, so a
# cluster job starts one Snakemake for several of ours; local runs ignore groups.
SIMULATION_GROUP = "simulations"  # simulation, search, wall and validation jobs
REDUCTION_GROUP = "reductions"  # cubes, tables and figures
SEARCH_STUDIES = [name for name, cases in STUDIES.items() if any(c.search for c in cases.values())]
# jobs sized to their cost (stonedem.study.jobs): cheap cases share a job, and so do cheap
# searches (each job ~1.5 s to start: the full study's 18 searches in 9 jobs)
# config device: gpu runs each search study's searches in one job, side by side on the GPU
# (stonedem.study.runner.run_searches), so the device gets many members at once
GPU_SEARCHES = config.get("device", "cpu") == "gpu"
JOBS = stonedem.study.jobs.plan_jobs(
    {name: list(cases.values()) for name, cases in STUDIES.items()},
    search_seconds=math.inf if GPU_SEARCHES else stonedem.study.jobs.JOB_SECONDS,
)


def requested_targets():
    """The run's targets as far as they are known while the Snakefile is parsed: Snakemake
    sets its DAG settings only after parsing, so the command line's words that are not
    options (an option's value may slip in: harmless, it only plans more)."""
    targets = getattr(getattr(workflow, "dag_settings", None), "targets", None)
    if targets is None:
        targets = [word for word in sys.argv[1:] if not word.startswith("-")]
    return list(targets)


def fragility_requested():
    """Whether the run asks for the IDA (workflow/rules/fragility.smk: target fragility, its
    files, or one of its jobs, whose names hold ida_): its 428 searches are planned and
    their scenes checked (2 s) only then, so the study's own DAG does not pay for them."""
    return any("fragility" in t or "ida_" in t for t in requested_targets())


# the IDA over the FEMA P695 suites (config fragility:): a threshold-search study per
# structure (stonedem.fragility.ida), several searches per job (fragility.job_seconds of estimated work)
FRAGILITY_STUDIES = {}
FRAGILITY_COMPARISONS = {}  # {name: structures} drawn on one figure (fragility.compare)
if config.get("fragility") is not None and fragility_requested():
    try:  # every case checked by the main process; a cluster job only rebuilds the tables
        if getattr(workflow, "is_main_process", True):
            tables = stonedem.fragility.ida.check_fragility(config)
        else:
            tables = stonedem.study.grid.config_cases(
                stonedem.fragility.ida.fragility_config(config)
            )
        FRAGILITY_STUDIES = {
            name: {case.id: case for case in cases} for name, cases in tables.items()
        }
        FRAGILITY_COMPARISONS = stonedem.fragility.ida.fragility_comparisons(config)
    except InputError as error:
        print(f"Bad config: {error}", file=sys.stderr)
        sys.exit(2)
FRAGILITY_JOBS = stonedem.study.jobs.plan_jobs(
    {name: list(cases.values()) for name, cases in FRAGILITY_STUDIES.items()},
    search_seconds=(
        math.inf
        if GPU_SEARCHES
        else float(
            config.get("fragility", {}).get(
                "job_seconds", stonedem.fragility.ida.DEFAULT_JOB_SECONDS
            )
        )
    ),
)
JOB_PRIORITY = stonedem.study.jobs.job_priority(JOBS + FRAGILITY_JOBS)
# the jobs that are not packed (a wall pushover, a validation: up to ~40 s each) start before
# the packed ~20 s simulation jobs, so that none of them is left for the tail (S23 was: 37 s)
UNPACKED_PRIORITY = max(JOB_PRIORITY.values(), default=0) + 1


def job_runtime(job):
    """A job's SLURM time limit [min] from the job plan's estimate (stonedem.study.jobs; the
    estimate runs ~2.3x the measured kernel time): three times it, at least 10 min."""
    return max(10, math.ceil(3 * job.cost / 60))


def case_path(case):
    return f"results/cases/{case.study}/{case.id}.nc"


def search_path(system):
    return f"results/searches/{system.study}/{system.id}.nc"


# an ensemble study's stripe fills (stonedem.study.stripe_fill): one job per search system as
# configured, after its members' searches; {study: {system id: its member systems}}
STRIPE_GROUPS = {
    study: stonedem.study.stripe_fill.member_groups(list(STUDIES[study].values()))
    for study in SEARCH_STUDIES
}


def stripe_path(study, base):
    return f"results/stripes/{study}/{base}.nc"


def stripe_files(study):
    """A search study's stripe-fill tables (none without ensemble members)."""
    return [stripe_path(study, base) for base in STRIPE_GROUPS.get(study, {})]


def case_files(study):
    """A study's case files, or for a search study its systems' search files."""
    if study in SEARCH_STUDIES:
        return [search_path(system) for system in STUDIES[study].values()]
    return [case_path(case) for case in STUDIES[study].values()]


def batches(names, size):
    """Consecutive runs of ``size`` names: the outputs of one job each. A cube, table or
    figure costs ~0.1-1 s and its job ~1 s to start (Python, xarray, matplotlib)."""
    names = list(names)
    return [names[i : i + size] for i in range(0, len(names), size)]


def dealt(names, n_jobs):
    """``names`` dealt round into ``n_jobs`` jobs (name i to job i mod n_jobs): neighbours,
    which tend to cost alike, go to different jobs."""
    names = list(names)
    return [names[k::n_jobs] for k in range(min(n_jobs, len(names)))]


CUBE_BATCHES = batches(STUDIES, 6)

# the chapter-5 validations (workflow/rules/validation.smk); off in the workflow tests' tiny config
RUN_VALIDATION = config_flag("run_validation", True)


def case_records(case):
    """The record files a case reads (none or one)."""
    name = record_file_name(case.scene.get("excitation"))
    return [f"records/{name}.nc"] if isinstance(name, str) else []


def job_records(job):
    """The record files a job's cases read."""
    return sorted({path for case in job.cases for path in case_records(case)})


# the file of each kind of catalogue input (stonedem.figures.Cube, Case, Table, Record)
CATALOGUE_PATHS = {
    "Cube": "results/cubes/{study}.nc",
    "Case": "results/cases/{study}/{case}.nc",
    "Table": "results/tables/{table}.csv",
    "Record": "records/{name}.nc",
}


def table_inputs(name):
    return stonedem.figures.input_paths(TABLES[name].inputs, CATALOGUE_PATHS)


TABLE_BATCHES = batches(TABLES, 8)


def figure_inputs(name):
    return stonedem.figures.input_paths(FIGURES[name].inputs, CATALOGUE_PATHS)


# consecutive catalogue entries share their inputs (a chapter's cubes)
FIGURE_BATCHES = batches(FIGURE_NAMES, 8)


def caption_file(name, text):
    """The report caption of one figure as a file of its own (a batch job's outputs share
    its params, so a caption cannot come from them): written when it changes."""
    path = Path(workflow.basedir) / ".snakemake" / "dem_captions" / f"{name}.rst"
    if not path.is_file() or path.read_text() != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return str(path)


def figure_caption_file(name):
    return caption_file(
        name,
        f"{FIGURES[name].caption}\n\nWhere the thesis reports an ordering, "
        "the line under the plot says whether it holds on our cube.\n",
    )


def study_description(study):
    return config["studies"][study].get("description", "")


# 3D rigid-block walls (manuscript Tables 1-3, A1), rules in walls.smk
WALL_TABLES = {
    "1": ["orduna_case1", "orduna_case2"],
    "2": ["s11", "s12", "s13", "s15", "s6", "s1_s2_s3", "s5", "s32", "s23", "s34"],
    "3": [
        "chee_liang_2_3",
        "chee_liang_8_12",
        "chee_liang_14_15",
        "chee_liang_4_5",
        "chee_liang_9_13",
        "chee_liang_10_11",
    ],
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


WALL_FIGURES_SELECTED = [n for n in WALL_FIGURES if selected(WALL_FIGURES[n])]


def wall_figure_kind(number):
    return "pushover" if number == "22" else "damage"


def wall_figure_caption_file(number):
    kind = (
        "Pushover curves"
        if wall_figure_kind(number) == "pushover"
        else "Damage maps at the limit load"
    )
    cases = ", ".join(selected(WALL_FIGURES[number]))
    return caption_file(
        f"manuscript_fig_{number}",
        f"Regenerates manuscript Fig. {number}: {kind.lower()} of {cases} "
        "(interfaces: elastic, shear, flexural, shear and flexural, detached).\n",
    )


# on a SLURM cluster, a profile that could not see its jobs finish ends the run in one line
# before the first job, instead of waiting for ever (stonedem.study.cluster)
onstart:
    stonedem.study.cluster.check_executor(workflow)
