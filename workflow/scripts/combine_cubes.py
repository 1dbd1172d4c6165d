"""Snakemake script: a batch of studies' case files (or searches, with an ensemble's stripe
fills) -> their cubes (stonedem.study.cube.combine_cases, stonedem.study.cube.combine_searches)."""

from stonedem.entry import workflow_log
from stonedem.io.netcdf import write_dataset
from stonedem.study.cube import combine_cases, combine_searches
from stonedem.study.stripe_fill import stripe_pieces

workflow_log(snakemake.log[0])
for (_study, spec), output in zip(snakemake.params.studies.items(), snakemake.output):
    if spec["search"]:
        # None: one member, no fills
        stripes = stripe_pieces(spec["stripes"]) if spec["stripes"] else None
        cube = combine_searches(list(spec["inputs"]), spec["description"], stripes)
    else:
        cube = combine_cases(list(spec["inputs"]), spec["description"])
    write_dataset(cube, output)
