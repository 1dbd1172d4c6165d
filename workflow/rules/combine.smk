# Each study's cases (or searches) combined into its cube, a batch of studies per job.
for k, batch in enumerate(CUBE_BATCHES):

    rule:
        name:
            f"cubes_{k}"
        input:
            [path for study in batch for path in case_files(study) + stripe_files(study)],
        output:
            [f"results/cubes/{study}.nc" for study in batch],
        log:
            f"results/logs/cubes/cubes_{k}.log",
        benchmark:
            f"results/logs/benchmarks/cubes/cubes_{k}.tsv"
        group:
            REDUCTION_GROUP
        conda:
            "../envs/stonedem.yaml"
        params:
            studies={
                study: {
                    "inputs": case_files(study),
                    "description": study_description(study),
                    "search": study in SEARCH_STUDIES,
                    "stripes": stripe_files(study),
                }
                for study in batch
            },
        script:
            "../scripts/combine_cubes.py"
