"""Snakemake script: a study's case files -> its cube (dem.study.combine_cases)."""

import sys

from dem.dataset import write_dataset
from dem.study import combine_cases

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
write_dataset(combine_cases(snakemake.input), snakemake.output[0])  # noqa: F821
