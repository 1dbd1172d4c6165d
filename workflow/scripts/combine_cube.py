"""Snakemake script: a study's case files -> its cube (dem.study.combine_cases)."""

import sys

from dem.dataset import write_dataset
from dem.study import combine_cases

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
cube = combine_cases(list(snakemake.input), snakemake.params.description)  # noqa: F821
write_dataset(cube, snakemake.output[0])  # noqa: F821
