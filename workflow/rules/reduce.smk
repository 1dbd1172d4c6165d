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


rule ramp_thresholds:
    input:
        drums="results/cubes/ramp_drums.nc",
        taper="results/cubes/ramp_taper.nc",
    output:
        drums="results/tables/thesis_fig_6_10.csv",
        taper="results/tables/thesis_fig_6_13.csv",
    log:
        "results/logs/tables/ramp_thresholds.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/ramp_thresholds.py"


rule frequency_response:
    input:
        "results/cubes/{study}.nc",
    output:
        "results/tables/frequency_response_{study}.csv",
    log:
        "results/logs/tables/frequency_response_{study}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/frequency_response.py"


rule epistyle_response:
    input:
        "results/cubes/{study}.nc",
    output:
        "results/tables/epistyle_{study}.csv",
    log:
        "results/logs/tables/epistyle_{study}.log",
    conda:
        "../envs/dem.yaml"
    script:
        "../scripts/epistyle_response.py"
