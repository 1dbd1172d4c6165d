"""Snakemake script: wall datasets -> manuscript Table 1/2/3 CSV
(stonedem.wall.validation.limit_load_table)."""

from stonedem.entry import workflow_log
from stonedem.io.atomic import write_csv
from stonedem.wall.validation import limit_load_table

workflow_log(snakemake.log[0])
write_csv(snakemake.output[0], limit_load_table(snakemake.input))
