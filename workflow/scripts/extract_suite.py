"""Snakemake script: one FEMA P695 set -> records/suites/<suite>.nc (stonedem.motion.suites)."""

import sys

from stonedem.entry import workflow_log

from stonedem.motion.suites import suite_dataset, write_suite

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
write_suite(suite_dataset(snakemake.wildcards.suite), snakemake.output[0])  # noqa: F821
