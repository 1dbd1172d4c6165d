# The catalogue's CSV tables (stonedem.figures: TABLES in common.smk), a batch per job.
for k, batch in enumerate(TABLE_BATCHES):

    rule:
        name:
            f"tables_{k}"
        input:
            sorted({path for name in batch for path in table_inputs(name)}),
        output:
            [f"results/tables/{name}.csv" for name in batch],
        log:
            f"results/logs/tables/tables_{k}.log",
        benchmark:
            f"results/logs/benchmarks/tables/tables_{k}.tsv"
        group:
            REDUCTION_GROUP
        conda:
            "../envs/stonedem.yaml"
        params:
            tables={name: table_inputs(name) for name in batch},
        script:
            "../scripts/write_tables.py"
