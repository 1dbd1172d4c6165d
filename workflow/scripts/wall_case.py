"""Snakemake script: config/walls/<case>.yaml -> results/walls/<case>.nc (stonedem.wall.dataset.run_case_file)."""

import sys

from stonedem.wall.dataset import run_case_file

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
run_case_file(snakemake.input[0], snakemake.output[0],  # noqa: F821
              limit_analysis=snakemake.params.limit_analysis)  # noqa: F821
