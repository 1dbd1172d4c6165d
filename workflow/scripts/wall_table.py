"""Snakemake script: wall datasets -> manuscript Table 1/2/3 CSV (stonedem.wall.validation.limit_load_table)."""

import sys

from stonedem.entry import workflow_log

from stonedem.io.atomic import write_csv
from stonedem.wall.validation import limit_load_table

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
write_csv(snakemake.output[0], limit_load_table(snakemake.input))  # noqa: F821
