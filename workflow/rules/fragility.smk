# Seismic fragility by incremental dynamic analysis (config fragility:, stonedem.fragility.ida): the
# searches are jobs of simulate.smk (FRAGILITY_JOBS); here they become the structure x
# record x limit-state cube, the lognormal fits, the tables and the figures.
# `snakemake fragility -j2`; not part of `all`.
FRAGILITY = config.get("fragility") or {}
if not FRAGILITY and fragility_requested():
    print(
        "Bad config: fragility: missing; add a fragility: section with structures (see config/config.yaml)",
        file=sys.stderr,
    )
    sys.exit(2)
FRAGILITY_STRUCTURES = [
    name[len(stonedem.fragility.ida.STUDY_PREFIX) :] for name in FRAGILITY_STUDIES
]
# the searched structures' config entries (drum width, kind: the cube and the checks read them)
FRAGILITY_SPECS = {name: FRAGILITY["structures"][name] for name in FRAGILITY_STRUCTURES}
FRAGILITY_SEARCHES = [
    search_path(s) for cases in FRAGILITY_STUDIES.values() for s in cases.values()
]
# the single block set against rigid one-sine theory (stonedem.fragility.checks.pulse_check)
PULSE_STRUCTURE = (
    FRAGILITY.get("pulse_check") if FRAGILITY.get("pulse_check") in FRAGILITY_STRUCTURES else None
)
PULSE_FILE = ["results/fragility/pulse_check.nc"] if PULSE_STRUCTURE else []
FRAGILITY_OUTPUTS = (
    [
        "results/fragility/ida.nc",
        "results/fragility/fragility.nc",
        "results/tables/fragility.csv",
        "results/tables/fragility_checks.csv",
    ]
    + PULSE_FILE
    + [f"results/figures/fragility_{name}.png" for name in FRAGILITY_STRUCTURES]
    + ["results/figures/fragility_medians.png"]
    + [f"results/figures/fragility_compare_{name}.png" for name in FRAGILITY_COMPARISONS]
)


rule fragility:
    input:
        FRAGILITY_OUTPUTS,


rule ida_cube:
    input:
        FRAGILITY_SEARCHES,
    output:
        "results/fragility/ida.nc",
    log:
        "results/logs/fragility/ida_cube.log",
    benchmark:
        "results/logs/benchmarks/fragility/ida_cube.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    params:
        structures=FRAGILITY_SPECS,
        suites=FRAGILITY.get("suites"),
    script:
        "../scripts/ida_cube.py"


rule fragility_fits:
    input:
        "results/fragility/ida.nc",
    output:
        fits="results/fragility/fragility.nc",
        table="results/tables/fragility.csv",
        checks="results/tables/fragility_checks.csv",
        pulse=PULSE_FILE,
    log:
        "results/logs/fragility/fragility_fits.log",
    benchmark:
        "results/logs/benchmarks/fragility/fragility_fits.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    params:
        bootstrap=FRAGILITY.get("bootstrap", 1000),
        structures=FRAGILITY_SPECS,
        pulse_structure=PULSE_STRUCTURE,
    script:
        "../scripts/fragility_fits.py"


rule fragility_figures:
    input:
        cube="results/fragility/ida.nc",
        fits="results/fragility/fragility.nc",
        pulse=PULSE_FILE,
    output:
        curves=[
            report(
                f"results/figures/fragility_{name}.png",
                caption="../report/fragility_curves.rst",
                category="Fragility (IDA over the FEMA P695 suites)",
                labels={"figure": f"fragility of {name}"},
            )
            for name in FRAGILITY_STRUCTURES
        ],
        medians=report(
            "results/figures/fragility_medians.png",
            caption="../report/fragility_medians.rst",
            category="Fragility (IDA over the FEMA P695 suites)",
            labels={"figure": "collapse medians and the pulse check"},
        ),
        compared=[
            report(
                f"results/figures/fragility_compare_{name}.png",
                caption="../report/fragility_compare.rst",
                category="Fragility (IDA over the FEMA P695 suites)",
                labels={"figure": f"fragility of {', '.join(names)}"},
            )
            for name, names in FRAGILITY_COMPARISONS.items()
        ],
    log:
        "results/logs/fragility/fragility_figures.log",
    benchmark:
        "results/logs/benchmarks/fragility/fragility_figures.tsv"
    group:
        REDUCTION_GROUP
    conda:
        "../envs/stonedem.yaml"
    params:
        structures=FRAGILITY_STRUCTURES,
        compared=list(FRAGILITY_COMPARISONS.values()),
    script:
        "../scripts/fragility_figures.py"
