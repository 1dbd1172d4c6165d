"""Snakemake script: one FEMA P695 set -> records/suites/<suite>.nc (stonedem.motion.suites)."""

from stonedem.entry import workflow_log
from stonedem.motion.suites import suite_dataset, write_suite

workflow_log(snakemake.log[0])
write_suite(suite_dataset(snakemake.wildcards.suite), snakemake.output[0])
