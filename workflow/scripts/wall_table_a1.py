"""Snakemake script: spring sub-model -> manuscript Table A1 CSV (stonedem.wall.validation.table_a1)."""

import sys

from stonedem.wall.validation import table_a1, write_table

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
write_table(table_a1(), snakemake.output[0])  # noqa: F821
