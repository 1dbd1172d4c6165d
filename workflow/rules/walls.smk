# 3D rigid-block walls (manuscript Tables 1-3, A1): one pushover per case file in config/walls/.
# The case lists (WALL_*) live in common.smk.


wildcard_constraints:
    wall_table="1|2|3",


# the wall cases in WALL_JOBS jobs, dealt round (a table's cases sit side by side and cost
# alike, so the two heaviest, s23 and s34 at ~30 s, land in different jobs); a job starts in ~1 s
WALL_JOBS = -(-len(WALL_SELECTED) // 3)

for k, batch in enumerate(dealt(WALL_SELECTED, WALL_JOBS)):

    rule:
        name:
            f"walls_{k}"
        input:
            [f"config/walls/{c}.yaml" for c in batch],
        output:
            [f"results/walls/{c}.nc" for c in batch],
        log:
            f"results/logs/walls/walls_{k}.log",
        benchmark:
            f"results/logs/benchmarks/walls/walls_{k}.tsv"
        priority: UNPACKED_PRIORITY
        group:
            SIMULATION_GROUP
        conda:
            "../envs/stonedem.yaml"
        params:
            limit_analysis=config.get("wall_limit_analysis", True),
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
        "results/logs/benchmarks/walls/table_{wall_table}.tsv"
    group:
        REDUCTION_GROUP
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
        "results/logs/benchmarks/walls/table_a1.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/wall_table_a1.py"


# every manuscript figure in one job: each is a second of drawing after 1.7 s of start-up
rule wall_figures:
    input:
        sorted(
            {
                f"results/walls/{c}.nc"
                for n in WALL_FIGURES_SELECTED
                for c in selected(WALL_FIGURES[n])
            }
        ),
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
    log:
        "results/logs/walls/figures.log",
    benchmark:
        "results/logs/benchmarks/walls/figures.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    params:
        figures={
            n: {
                "inputs": [f"results/walls/{c}.nc" for c in selected(WALL_FIGURES[n])],
                "kind": wall_figure_kind(n),
            }
            for n in WALL_FIGURES_SELECTED
        },
    script:
        "../scripts/wall_figure.py"
