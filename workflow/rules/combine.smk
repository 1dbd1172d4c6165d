rule combine_cube:
    input:
        case_files,
    output:
        "results/cubes/{study}.nc",
    params:
        description=study_description,
        search=lambda wildcards: wildcards.study in SEARCH_STUDIES,
    log:
        "results/logs/cubes/{study}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/combine_cube.py"
