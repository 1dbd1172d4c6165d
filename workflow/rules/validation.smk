# The thesis chapter-5 validations (5.1, 5.2.1) and the chapter-5 figures that are plots,
# named by thesis figure number (results/figures/thesis_fig_5_*.png). All science is in
# dem.validation and dem.validation_plots; workflow/scripts/validate_one.py is thin.
# Wildcards are `validation` and `validation_fig`, not `name` (constrained to the record
# names in common.smk) nor `figure` (the study figures of plot_figure).
import inspect

import dem.validation
import dem.validation_plots

VALIDATION_NAMES = list(dem.validation.VALIDATIONS)
VALIDATION_FIGURES = list(dem.validation_plots.THESIS_FIGURES)


def validation_inputs(wildcards):
    """The committed record a validation reads, if it takes one (``record=`` argument)."""
    func = dem.validation.VALIDATIONS[wildcards.validation]
    record = inspect.signature(func).parameters.get("record")
    return {"record": f"records/{record.default.name}"} if record else {}


def validation_dataset(wildcards):
    """The validation dataset a thesis figure is drawn from (THESIS_FIGURES)."""
    name, _ = dem.validation_plots.THESIS_FIGURES[wildcards.validation_fig]
    return f"results/validation/{name}.nc"


rule validate_one:
    input:
        unpack(validation_inputs),
    output:
        "results/validation/{validation}.nc",
    log:
        "results/logs/validation/{validation}.log",
    wildcard_constraints:
        validation="|".join(VALIDATION_NAMES),
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/validate_one.py"


rule validation_figure:
    input:
        validation_dataset,
    output:
        "results/figures/{validation_fig}.png",
    log:
        "results/logs/validation/{validation_fig}.log",
    wildcard_constraints:
        validation_fig="|".join(VALIDATION_FIGURES),
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/validate_one.py"


rule validation_summary:
    input:
        expand("results/validation/{validation}.nc", validation=VALIDATION_NAMES),
    output:
        "results/tables/validation_summary.csv",
    log:
        "results/logs/validation/validation_summary.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/validate_one.py"
