# The engine compiled once before the jobs that run it fan out (issue 45). With an empty Numba
# cache (a fresh clone, an edited kernel) the first jobs each compiled the time loop they run on,
# side by side, the same loop in several jobs at once (20-35 s each; on a cluster, every job at
# once). Now one job per compiled time loop compiles it (stonedem.engine.run.warm_compile: the
# specialisations every study run uses, and the kernels of a run's set-up and checks); every job
# that runs the engine takes their markers as ancient inputs and loads from the cache.
# The markers are named by the kernel sources' hash (stonedem.kernels.sources_key, the cache
# folder's name): unchanged kernels keep them; after an edited kernel the loops are compiled
# again, once, and the jobs that run the engine rerun on the edited code (their input changed).
import stonedem.engine.run
import stonedem.kernels

COMPILED_LOOPS = list(stonedem.engine.run.STUDY_LOOPS)
COMPILED = [
    ancient(f"results/compiled/{stonedem.kernels.sources_key()}/{loop}.txt")
    for loop in COMPILED_LOOPS
]


rule compile_kernels:
    output:
        f"results/compiled/{stonedem.kernels.sources_key()}/{{loop}}.txt",
    log:
        "results/logs/compile_kernels/{loop}.log",
    benchmark:
        "results/logs/benchmarks/compile_kernels/{loop}.tsv"
    wildcard_constraints:
        loop="|".join(COMPILED_LOOPS),
    # before everything else: the loops compile side by side while no job waits on a core; on a
    # cluster a job of its own (not a localrule), so it compiles for the compute nodes' CPU,
    # whose cache entries the jobs then load
    priority: UNPACKED_PRIORITY + 1
    conda:
        "../envs/stonedem.yaml"
    script:
        "../scripts/compile_kernels.py"
