# 3D rigid-block walls (manuscript Tables 1-3, A1): one pushover per case file in config/walls/.
# The case lists (WALL_*) live in common.smk.


wildcard_constraints:
    wall_case="|".join(WALL_CASES),
    wall_table="1|2|3",
    wall_figure="|".join(WALL_FIGURES),


rule wall_case:
    input:
        "config/walls/{wall_case}.yaml",
    output:
        "results/walls/{wall_case}.nc",
    log:
        "results/logs/walls/{wall_case}.log",
    priority: UNPACKED_PRIORITY
    params:
        limit_analysis=config.get("wall_limit_analysis", True),
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_case.py"


rule wall_table:
    input:
        lambda wc: expand("results/walls/{c}.nc", c=selected(WALL_TABLES[wc.wall_table])),
    output:
        "results/tables/manuscript_table_{wall_table}.csv",
    log:
        "results/logs/walls/table_{wall_table}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_table.py"


rule wall_table_a1:
    output:
        "results/tables/manuscript_table_a1.csv",
    log:
        "results/logs/walls/table_a1.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_table_a1.py"


# one job per figure (not one for all): a figure asked for on its own then waits only for
# its own walls; the longest walls start first (priority), so no figure waits at the end
rule wall_figure:
    input:
        lambda wc: expand("results/walls/{c}.nc", c=selected(WALL_FIGURES[wc.wall_figure])),
    output:
        report(
            "results/figures/manuscript_fig_{wall_figure}.png",
            caption="../report/wall_figure.rst",
            category="Manuscript figures (walls)",
            labels={"figure": "manuscript Fig. {wall_figure}"},
        ),
    params:
        kind=lambda wc: "pushover" if wc.wall_figure == "22" else "damage",
        caption=wall_figure_caption,
    log:
        "results/logs/walls/fig_{wall_figure}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_figure.py"
