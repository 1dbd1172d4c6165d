# The study workflow: config -> cases -> simulations -> cubes -> tables and figures.
# Stages live in workflow/rules/*.smk; all science is in the stonedem package.
from snakemake.utils import min_version

min_version("8.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/records.smk"
include: "workflow/rules/compile.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/combine.smk"
include: "workflow/rules/reduce.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/validation.smk"
include: "workflow/rules/walls.smk"
include: "workflow/rules/bench.smk"
include: "workflow/rules/fragility.smk"
include: "workflow/rules/ensemble.smk"


rule all:
    default_target: True
    input:
        expand("records/{name}.nc", name=RECORD_NAMES),
        expand("results/cubes/{study}.nc", study=STUDIES),
        expand("results/tables/{table}.csv", table=TABLES),
        expand("results/figures/{figure}.png", figure=FIGURE_NAMES),
        VALIDATION_TARGETS,
        WALL_OUTPUTS,
