"""Snakemake script: a job's cases -> one NetCDF each (stonedem.study.runner.run_cases)."""

from stonedem.entry import workflow_log
from stonedem.study.grid import Case
from stonedem.study.runner import CaseStore, run_cases

workflow_log(snakemake.log[0])
cases = [Case.from_dict(spec) for spec in snakemake.params.cases]
run_cases(cases, list(snakemake.output), CaseStore(snakemake.config.get("case_store"), "records"))
