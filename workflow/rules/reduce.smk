rule table_7_1:
    input:
        standalone="results/cubes/standalone_records.nc",
        colonnade="results/cubes/colonnade_records.nc",
    output:
        "results/tables/table_7_1.csv",
    log:
        "results/logs/tables/table_7_1.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/table_7_1.py"
