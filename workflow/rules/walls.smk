# 3D rigid-block walls (manuscript Tables 1-3, A1): one pushover per case file in config/walls/.
# The case lists (WALL_*) live in common.smk.


wildcard_constraints:
    wall_case="|".join(WALL_CASES),
    wall_table="1|2|3",


rule wall_case:
    input:
        "config/walls/{wall_case}.yaml",
    output:
        "results/walls/{wall_case}.nc",
    log:
        "results/logs/walls/{wall_case}.log",
    benchmark:
        "results/logs/benchmarks/walls/{wall_case}.tsv",
    priority: UNPACKED_PRIORITY
    params:
        limit_analysis=config.get("wall_limit_analysis", True),
    group: SIMULATION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/wall_case.py"


rule wall_table:
    input:
        lambda wc: expand("results/walls/{c}.nc", c=selected(WALL_TABLES[wc.wall_table])),
    output:
        "results/tables/manuscript_table_{wall_table}.csv",
    log:
        "results/logs/walls/table_{wall_table}.log",
    benchmark:
        "results/logs/benchmarks/walls/table_{wall_table}.tsv",
    group: REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/wall_table.py"


rule wall_table_a1:
    output:
        "results/tables/manuscript_table_a1.csv",
    log:
        "results/logs/walls/table_a1.log",
    benchmark:
        "results/logs/benchmarks/walls/table_a1.tsv",
    group: REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/wall_table_a1.py"


# every manuscript figure in one job: each is a second of drawing after 1.7 s of start-up
rule wall_figures:
    input:
        sorted({f"results/walls/{c}.nc" for n in WALL_FIGURES_SELECTED for c in selected(WALL_FIGURES[n])}),
    output:
        [
            report(
                f"results/figures/manuscript_fig_{n}.png",
                caption=wall_figure_caption_file(n),
                category="Manuscript figures (walls)",
                labels={"figure": f"manuscript Fig. {n}"},
            )
            for n in WALL_FIGURES_SELECTED
        ],
    params:
        figures={
            n: {"inputs": [f"results/walls/{c}.nc" for c in selected(WALL_FIGURES[n])], "kind": wall_figure_kind(n)}
            for n in WALL_FIGURES_SELECTED
        },
    log:
        "results/logs/walls/figures.log",
    benchmark:
        "results/logs/benchmarks/walls/figures.tsv",
    group: REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/wall_figure.py"
