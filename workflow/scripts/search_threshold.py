"""Snakemake script: one system's collapse-threshold search (dem.case_runner.run_search)."""

import sys

from dem.case_runner import CaseStore, run_search
from dem.study import Case

sys.stderr = open(snakemake.log[0], "w", buffering=1)  # noqa: F821 - provided by Snakemake
store = CaseStore(snakemake.config.get("case_store"), "records")  # noqa: F821
run_search(Case.from_dict(snakemake.params.system), snakemake.output.runs, snakemake.output.search, store)  # noqa: F821
