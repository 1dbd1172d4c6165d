rule simulate_case:
    input:
        case_record,
    output:
        "results/cases/{study}/{case}.nc",
    params:
        case=case_of,
    log:
        "results/logs/cases/{study}/{case}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/simulate_case.py"
