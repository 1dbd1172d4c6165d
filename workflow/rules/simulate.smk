# One rule per job of stonedem.study.jobs: a job runs its cases in one interpreter (one start-up,
# one compiled-cache load), writes one NetCDF per case and logs one line per case; a
# restored case comes from the case store (results/case_store, stonedem.study.runner). Every job
# that runs the engine waits for its compile (compile.smk: COMPILED).
for job in JOBS:
    if job.is_search:
        continue

    rule:
        name:
            job.name
        input:
            job_records(job),
            COMPILED,
        output:
            [case_path(case) for case in job.cases],
        log:
            f"results/logs/jobs/{job.name}.log",
        benchmark:
            f"results/logs/benchmarks/jobs/{job.name}.tsv"
        priority: JOB_PRIORITY[job.name]
        group:
            SIMULATION_GROUP
        conda:
            "../envs/stonedem.yaml"
        resources:
            runtime=job_runtime(job),
        params:
            cases=[case.as_dict() for case in job.cases],
        script:
            "../scripts/simulate_cases.py"


# Threshold searches (stonedem.study.search), one or more per job: each system's runs and bracket
# in results/searches/<study>/<system>.nc; with config search_runs: full, also its runs' case
# files in one directory.
for job in JOBS + FRAGILITY_JOBS:
    if not job.is_search:
        continue

    rule:
        name:
            job.name
        input:
            job_records(job),
            COMPILED,
        output:
            runs=(
                [directory(f"results/cases/{job.study}/{system.id}") for system in job.cases]
                if FULL_SEARCH_RUNS
                else []
            ),
            search=[search_path(system) for system in job.cases],
        log:
            f"results/logs/jobs/{job.name}.log",
        benchmark:
            f"results/logs/benchmarks/jobs/{job.name}.tsv"
        priority: JOB_PRIORITY[job.name]
        group:
            SIMULATION_GROUP
        conda:
            "../envs/stonedem.yaml"
        resources:
            runtime=job_runtime(job),
        params:
            systems=[system.as_dict() for system in job.cases],
            # switching search_runs reruns the search (its run files come or go)
            search_runs=config["search_runs"],
        script:
            "../scripts/search_threshold.py"


# An ensemble study's stripe fills (stonedem.study.stripe_fill): after a system's member searches,
# the values any member ran inside the zone, run by the members that have not; Table 7.1 fits a50
# over the searches and the fills. Studies with one member have none.
for study, groups in STRIPE_GROUPS.items():
    for k, (base, members) in enumerate(groups.items()):

        rule:
            name:
                f"stripes_{study}_{k}"
            input:
                searches=[search_path(system) for system in members],
                records=sorted({path for system in members for path in case_records(system)}),
                compiled=COMPILED,
            output:
                runs=directory(f"results/stripes/{study}/{base}") if FULL_SEARCH_RUNS else [],
                stripes=stripe_path(study, base),
            log:
                f"results/logs/stripes/{study}/{base}.log",
            benchmark:
                f"results/logs/benchmarks/stripes/{study}/{base}.tsv"
            group:
                SIMULATION_GROUP
            conda:
                "../envs/stonedem.yaml"
            params:
                systems=[system.as_dict() for system in members],
                search_runs=config["search_runs"],
            script:
                "../scripts/fill_stripes.py"
