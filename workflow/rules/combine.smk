rule combine_cube:
    input:
        case_files,
    output:
        "results/cubes/{study}.nc",
    log:
        "results/logs/cubes/{study}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/combine_cube.py"
