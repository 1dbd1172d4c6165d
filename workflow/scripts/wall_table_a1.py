"""Snakemake script: spring sub-model -> manuscript Table A1 CSV
(stonedem.wall.validation.table_a1)."""

from stonedem.entry import workflow_log
from stonedem.io.atomic import write_csv
from stonedem.wall.validation import table_a1

workflow_log(snakemake.log[0])
write_csv(snakemake.output[0], table_a1())
