# The catalogue's figures (stonedem.figures), a batch of FIGURES_PER_JOB per job (common.smk).
for k, batch in enumerate(FIGURE_BATCHES):

    rule:
        name:
            f"figures_{k}"
        input:
            sorted({path for name in batch for path in figure_inputs(name)}),
        output:
            [
                report(
                    f"results/figures/{name}.png",
                    caption=figure_caption_file(name),
                    category="Thesis figures",
                    labels={"figure": name},
                )
                for name in batch
            ],
        log:
            f"results/logs/figures/figures_{k}.log",
        benchmark:
            f"results/logs/benchmarks/figures/figures_{k}.tsv"
        group:
            REDUCTION_GROUP
        conda:
            "../envs/stonedem.yaml"
        params:
            figures={name: figure_inputs(name) for name in batch},
        script:
            "../scripts/plot_figures.py"
