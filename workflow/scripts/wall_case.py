"""Snakemake script: config/walls/<case>.yaml -> results/walls/<case>.nc (stonedem.wall.dataset.run_case_file)."""

import sys

from stonedem.entry import workflow_log

from stonedem.wall.dataset import run_case_file

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
run_case_file(snakemake.input[0], snakemake.output[0],  # noqa: F821
              limit_analysis=snakemake.params.limit_analysis)  # noqa: F821
