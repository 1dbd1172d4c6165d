"""Snakemake script: spring sub-model -> manuscript Table A1 CSV (stonedem.wall.validation.table_a1)."""

import sys

from stonedem.entry import workflow_log

from stonedem.wall.validation import table_a1, write_table

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
write_table(table_a1(), snakemake.output[0])  # noqa: F821
