"""Snakemake script: a batch of studies' case files (or searches) -> their cubes
(stonedem.study.grid.combine_cases, stonedem.study.cube.combine_searches)."""

import sys

from stonedem.entry import workflow_log

from stonedem.io.netcdf import write_dataset
from stonedem.study.cube import combine_searches
from stonedem.study.grid import combine_cases

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
for (study, spec), output in zip(snakemake.params.studies.items(), snakemake.output):  # noqa: F821
    combine = combine_searches if spec["search"] else combine_cases
    write_dataset(combine(list(spec["inputs"]), spec["description"]), output)
