# The thesis chapter-5 validations (5.1, 5.2.1) and the chapter-5 figures that are plots,
# named by thesis figure number (results/figures/thesis_fig_5_*.png). All science is in
# stonedem.validation.cases and stonedem.validation.plots; workflow/scripts/validate_one.py is thin.
# The wildcard is `validation`, not `name` (constrained to the record names in common.smk).
import inspect

import stonedem.validation.cases
import stonedem.validation.plots

VALIDATION_NAMES = list(stonedem.validation.cases.VALIDATIONS)
VALIDATION_FIGURES = list(stonedem.validation.plots.THESIS_FIGURES)
VALIDATION_TARGETS = (
    [f"results/figures/{fig}.png" for fig in VALIDATION_FIGURES]
    + ["results/tables/validation_summary.csv"]
    if RUN_VALIDATION
    else []
)


# the committed record each validation reads (its ``record=`` argument), as a named input
VALIDATION_RECORDS = {
    name: {"record": f"records/{param.default.name}"}
    for name, func in stonedem.validation.cases.VALIDATIONS.items()
    if (param := inspect.signature(func).parameters.get("record"))
}
# the validation dataset each thesis figure is drawn from
VALIDATION_FIGURE_INPUT = {
    fig: f"results/validation/{name}.nc"
    for fig, (name, _) in stonedem.validation.plots.THESIS_FIGURES.items()
}
VALIDATION_CAPTIONS = {
    fig: f"{stonedem.validation.plots.CAPTIONS[fig]}\n\nThe title's second line gives the validation's verdict "
    "against its stated tolerance (``results/tables/validation_summary.csv``).\n"
    for fig in VALIDATION_FIGURES
}


# the validations in batches of VALIDATIONS_PER_JOB: each runs in 0.2-8 s after ~1.3 s of
# start-up (Python, numba, xarray, scipy)
VALIDATIONS_PER_JOB = 6
VALIDATION_BATCHES = batches(VALIDATION_NAMES, VALIDATIONS_PER_JOB)

for k, batch in enumerate(VALIDATION_BATCHES):

    rule:
        name:
            f"validate_{k}"
        input:
            sorted({path for name in batch for path in VALIDATION_RECORDS.get(name, {}).values()}),
            compiled=COMPILED,
        output:
            [f"results/validation/{name}.nc" for name in batch],
        log:
            f"results/logs/validation/validate_{k}.log",
        benchmark:
            f"results/logs/benchmarks/validation/validate_{k}.tsv"
        priority: UNPACKED_PRIORITY
        group:
            SIMULATION_GROUP
        conda:
            "../envs/stonedem.yaml"
        params:
            records={name: VALIDATION_RECORDS.get(name, {}).get("record") for name in batch},
        script:
            "../scripts/validate_one.py"


# every thesis figure of the validations in one job: each is a second of drawing after 1.7 s
# of start-up
rule validation_figures:
    input:
        sorted(set(VALIDATION_FIGURE_INPUT.values())),
    output:
        [
            report(
                f"results/figures/{fig}.png",
                caption=caption_file(fig, VALIDATION_CAPTIONS[fig]),
                category="Thesis figures",
                labels={"figure": fig},
            )
            for fig in VALIDATION_FIGURES
        ],
    log:
        "results/logs/validation/figures.log",
    benchmark:
        "results/logs/benchmarks/validation/figures.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    params:
        figures=VALIDATION_FIGURE_INPUT,
    script:
        "../scripts/validate_one.py"


rule validation_summary:
    input:
        expand("results/validation/{validation}.nc", validation=VALIDATION_NAMES),
    output:
        "results/tables/validation_summary.csv",
    log:
        "results/logs/validation/validation_summary.log",
    benchmark:
        "results/logs/benchmarks/validation/validation_summary.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/validate_one.py"


# `snakemake -j2 validation_all`: the validations, their thesis figures and the summary only
rule validation_all:
    input:
        expand("results/figures/{validation_fig}.png", validation_fig=VALIDATION_FIGURES),
        "results/tables/validation_summary.csv",
