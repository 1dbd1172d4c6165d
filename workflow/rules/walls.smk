# 3D rigid-block walls (manuscript Tables 1-3, A1): one pushover per case file in config/walls/.
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
WALL_OUTPUTS = (
    [f"results/walls/{c}.nc" for c in WALL_CASES]
    + [f"results/tables/manuscript_table_{t}.csv" for t in ["1", "2", "3", "a1"]]
    + [f"results/figures/manuscript_fig_{n}.png" for n in WALL_FIGURES]
)


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
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_case.py"


rule wall_table:
    input:
        lambda wc: expand("results/walls/{c}.nc", c=WALL_TABLES[wc.wall_table]),
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


rule wall_figure:
    input:
        lambda wc: expand("results/walls/{c}.nc", c=WALL_FIGURES[wc.wall_figure]),
    output:
        "results/figures/manuscript_fig_{wall_figure}.png",
    params:
        kind=lambda wc: "pushover" if wc.wall_figure == "22" else "damage",
    log:
        "results/logs/walls/fig_{wall_figure}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/wall_figure.py"
