"""Snakemake script: wall datasets -> manuscript Table 1/2/3 CSV (stonedem.wall.validation.limit_load_table)."""

import sys

from stonedem.entry import workflow_log

from stonedem.wall.validation import limit_load_table, write_table

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
write_table(limit_load_table(snakemake.input), snakemake.output[0])  # noqa: F821
