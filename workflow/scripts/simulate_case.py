"""Snakemake script: one case of a study -> results/cases/<study>/<case>.nc (dem.study.run_case)."""

import sys

from dem.dataset import write_dataset
from dem.study import Case, run_case

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 - provided by Snakemake
case = Case(**snakemake.params.case)  # noqa: F821
write_dataset(run_case(case, base_dir="records"), snakemake.output[0])  # noqa: F821
