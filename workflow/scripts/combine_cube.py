"""Snakemake script: a study's case files (or its searches) -> its cube (dem.study.combine_cases,
dem.search_dataset.combine_searches)."""

import sys

from dem.dataset import write_dataset
from dem.search_dataset import combine_searches
from dem.study import combine_cases

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
combine = combine_searches if snakemake.params.search else combine_cases  # noqa: F821
write_dataset(combine(list(snakemake.input), snakemake.params.description), snakemake.output[0])  # noqa: F821
