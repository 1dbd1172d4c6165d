"""Snakemake script: config/walls/<case>.yaml -> results/walls/<case>.nc for each case of a job
(stonedem.wall.dataset.run_case_file), one log line each."""

import sys

from stonedem.entry import logged_seconds, workflow_log
from stonedem.wall.dataset import run_case_file

workflow_log(snakemake.log[0])
for case_file, output in zip(snakemake.input, snakemake.output):
    with logged_seconds(sys.stderr, case_file):
        run_case_file(case_file, output, limit_analysis=snakemake.params.limit_analysis)
