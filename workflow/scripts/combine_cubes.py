"""Snakemake script: a batch of studies' case files (or searches) -> their cubes
(dem.study.combine_cases, dem.search_dataset.combine_searches)."""

import sys

from dem.dataset import write_dataset
from dem.search_dataset import combine_searches
from dem.study import combine_cases

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
for (study, spec), output in zip(snakemake.params.studies.items(), snakemake.output):  # noqa: F821
    combine = combine_searches if spec["search"] else combine_cases
    write_dataset(combine(list(spec["inputs"]), spec["description"]), output)
