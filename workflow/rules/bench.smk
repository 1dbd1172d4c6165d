# Benchmarks (issue 6): run time against error beside pymunk and MuJoCo, cost per contact,
# the stability map and the skips, each a dataset in results/bench/ and figures in
# results/figures/. Not part of `all` (timings want a quiet machine): `snakemake bench -j1`.
# config bench_profile: full (the sweeps) or quick (a few points per engine: CI).
import shlex

# the scenes of benchmarks/work_precision.py (SCENES), one figure each: named here, not
# imported, so that the workflow parses where benchmarks/ is not (a copy of the rules); the
# job checks that its module writes exactly these files (workflow/scripts/bench.py)
WORK_PRECISION_SCENES = ("a", "a1", "b", "c")
BENCH_QUICK = config.get("bench_profile", "full") == "quick"
BENCH_OUTPUTS = {
    "bench_work_precision": ["results/bench/work_precision.nc"]
    + [f"results/figures/work_precision_{scene}.png" for scene in WORK_PRECISION_SCENES],
    "bench_contact_cost": ["results/bench/contact_cost.nc", "results/figures/contact_cost.png"],
    "bench_stability": [
        "results/bench/stability_map.nc",
        "results/bench/auto_dt_margin.nc",
        "results/figures/stability_map.png",
    ],
    "bench_skipping": ["results/bench/skipping.nc"],
    "bench_restitution": ["results/bench/restitution.nc"],
    "bench_fuzz": ["results/bench/fuzz.nc"],
    "bench_kernel": [
        "results/bench/kernel.nc",
        "results/bench/kernel.csv",
        "results/figures/kernel_cost.png",
    ],
    "bench_gpu": ["results/bench/ensemble.nc", "results/figures/ensemble_throughput.png"],
    "bench_rounding": ["results/bench/rounding.nc"],
}


rule bench_work_precision:
    output:
        BENCH_OUTPUTS["bench_work_precision"],
    log:
        "results/logs/bench/work_precision.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick=BENCH_QUICK,
    script:
        "../scripts/bench.py"


rule bench_contact_cost:
    output:
        BENCH_OUTPUTS["bench_contact_cost"],
    log:
        "results/logs/bench/contact_cost.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick=BENCH_QUICK,
    script:
        "../scripts/bench.py"


rule bench_stability:
    output:
        BENCH_OUTPUTS["bench_stability"],
    log:
        "results/logs/bench/stability.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick=BENCH_QUICK,
    script:
        "../scripts/bench.py"


rule bench_skipping:
    input:
        expand("records/{name}.nc", name=RECORD_NAMES),
    output:
        BENCH_OUTPUTS["bench_skipping"],
    log:
        "results/logs/bench/skipping.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick=BENCH_QUICK,
        # the quick study's record and ramp cases (33; the quick profile takes 4 of them)
        config="config/quick.yaml",
    script:
        "../scripts/bench.py"


# energy ratio per impact of the study's columns under each contact law
# (docs/results/benchmarks.md, "Impact loss"); quick: the monolith and the 2-drum column
# (~20 s), full: every column (~2 min)
rule bench_restitution:
    input:
        "config/config.yaml",
    output:
        BENCH_OUTPUTS["bench_restitution"],
    log:
        "results/logs/bench/restitution.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick="--quick" if BENCH_QUICK else "",
    shell:
        "NUMBA_NUM_THREADS=1 python -m benchmarks.restitution {params.quick} --config {input} "
        "--out {output} > {log} 2>&1"


# the fuzz suites (tests/*fuzz*) at 10 000 examples per test (quick: 100), counts per test
rule bench_fuzz:
    output:
        BENCH_OUTPUTS["bench_fuzz"],
    log:
        "results/logs/bench/fuzz.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick="--quick" if BENCH_QUICK else "",
    shell:
        "python -m benchmarks.fuzz {params.quick} --out {output} > {log} 2>&1"


# ns per step of the compiled loop, stage by stage, for six scenes from a lone block to a row
# of ten columns, beside the parent commit (config bench_parent, default HEAD~1 where the
# checkout has it; "none" skips it) imported from a git worktree into the same process; quick: 2 simulated s per scene
rule bench_kernel:
    input:
        "records/athens_standin_kocaeli_arc000.nc",
    output:
        dataset=BENCH_OUTPUTS["bench_kernel"][0],
        table=BENCH_OUTPUTS["bench_kernel"][1],
        figure=BENCH_OUTPUTS["bench_kernel"][2],
    log:
        "results/logs/bench/kernel.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick="--quick" if BENCH_QUICK else "",
        # no --parent: HEAD~1 where the checkout has it, else a warning and no comparison
        parent=(
            f"--parent {shlex.quote(str(config['bench_parent']))}"
            if config.get("bench_parent")
            else ""
        ),
    shell:
        "NUMBA_NUM_THREADS=1 python -m benchmarks.kernel {params.quick} {params.parent} "
        "--out $(dirname {output.dataset}) --figure {output.figure} > {log} 2>&1"


# member-steps per second of the ensemble engine against members, on one CPU thread, every CPU
# thread and the GPU where one can run the loop (issue 33); quick: 1-4 members, 0.5 s each
rule bench_gpu:
    input:
        "records/athens_standin_kocaeli_arc000.nc",
    output:
        dataset=BENCH_OUTPUTS["bench_gpu"][0],
        figure=BENCH_OUTPUTS["bench_gpu"][1],
    log:
        "results/logs/bench/ensemble.log",
    conda:
        "../envs/stonedem.yaml"
    params:
        quick="--quick" if BENCH_QUICK else "",
    shell:
        "python -m benchmarks.ensemble {params.quick} --out $(dirname {output.dataset}) "
        "--figure {output.figure} > {log} 2>&1"


# how far the study's verdicts and Table 7.1 thresholds move when only the last bits of the
# arithmetic change (k_n times 1 - j 2^-52; issue 32): the full config's 309 cases and 18
# searches, as configured and 7 times perturbed (~15 min on 2 cores); quick: the quick
# config's ramp and standalone-record studies, once perturbed (~10 s)
rule bench_rounding:
    input:
        expand("records/{name}.nc", name=RECORD_NAMES),
    output:
        BENCH_OUTPUTS["bench_rounding"],
    log:
        "results/logs/bench/rounding.log",
    conda:
        "../envs/stonedem.yaml"
    threads: 2
    params:
        args=(
            "--config config/quick.yaml --studies ramp_drums standalone_records --perturbations 1"
            if BENCH_QUICK
            else "--config config/config.yaml --perturbations 7"
        ),
    shell:
        "python -m benchmarks.rounding {params.args} --jobs {threads} "
        "--out $(dirname {output}) > {log} 2>&1"


# `snakemake bench -j1`: every benchmark (one job at a time keeps the timings honest)
rule bench:
    input:
        [path for outputs in BENCH_OUTPUTS.values() for path in outputs],
