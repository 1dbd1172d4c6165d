# The catalogue's CSV tables (dem.figures: TABLES in common.smk), one generic rule.


rule table:
    input:
        table_input,
    output:
        "results/tables/{table}.csv",
    log:
        "results/logs/tables/{table}.log",
    wildcard_constraints:
        table="|".join(TABLES),
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/table.py"
