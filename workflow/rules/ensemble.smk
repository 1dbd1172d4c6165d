# `snakemake ensemble -j2`: the stored K-member baseline of the whole study (issue 44), what
# `python -m stonedem.study.equivalence BASELINE CANDIDATE` judges a changed engine against:
# every grid case and threshold search run by members j = 0..K-1 (config
# ensemble.baseline_members, k_n x (1 - j 2^-52); ensemble.perturbation: geometry also moves
# every coordinate's last bits, the baseline a change of the arithmetic needs; tilt for the
# one-time check), the stripe fills, and the exact checks and short-horizon floors (layers A
# and B). Not part of `all`: K = 20 takes 22-40 minutes on 2 cores.
import os

# K and the perturbation as the config check read them (stonedem.study.grid.ensemble_settings)
ENSEMBLE_MEMBERS, ENSEMBLE_PERTURBATION = stonedem.study.grid.ensemble_settings(
    config, baseline=True
)
ENSEMBLE_CONFIG = os.path.relpath(
    workflow.overwrite_configfiles[-1] if workflow.overwrite_configfiles else "config/config.yaml"
)


rule ensemble:
    input:
        expand("records/{name}.nc", name=RECORD_NAMES),
        COMPILED,
    output:
        "results/ensemble/ensemble.nc",
    log:
        "results/logs/ensemble/ensemble.log",
    conda:
        "../envs/stonedem.yaml"
    # Snakemake runs it on at most the cores it is given (-j2: 2); workflow.cores would make
    # `snakemake --report` and other runs without --cores refuse the whole workflow
    threads: 16
    params:
        # the last --configfile (a profile such as config/quick.yaml), which the command merges
        # over config.yaml of its folder as snakemake merged it over the configfile: directive
        config=ENSEMBLE_CONFIG,
        members=ENSEMBLE_MEMBERS,
        perturbation=ENSEMBLE_PERTURBATION,
    shell:
        "python -m stonedem.study.ensemble --config {params.config:q} --members {params.members} "
        "--perturbation {params.perturbation} --jobs {threads} --checks full --out {output:q} > {log:q} 2>&1"
