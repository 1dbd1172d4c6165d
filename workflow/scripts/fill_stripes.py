"""Snakemake script: one search system's stripe fills over its ensemble members
(stonedem.study.stripe_fill.fill_stripes)."""

from stonedem.entry import workflow_log
from stonedem.study.grid import Case
from stonedem.study.runner import CaseStore
from stonedem.study.stripe_fill import fill_stripes

workflow_log(snakemake.log[0])
store = CaseStore(snakemake.config.get("case_store"), "records")
systems = [Case.from_dict(system) for system in snakemake.params.systems]
runs = snakemake.output.runs or None  # config search_runs: full, one case file per fill
fill_stripes(systems, list(snakemake.input.searches), runs, snakemake.output.stripes, store)
