"""Snakemake script: the collapse-threshold searches of one job (stonedem.study.runner.run_search)."""

import sys

from stonedem.entry import workflow_log

from stonedem.study.runner import CaseStore, run_search
from stonedem.study.grid import Case

workflow_log(snakemake.log[0])  # noqa: F821 - provided by Snakemake
store = CaseStore(snakemake.config.get("case_store"), "records")  # noqa: F821
systems = snakemake.params.systems  # noqa: F821
for i, (system, runs, search) in enumerate(zip(systems, snakemake.output.runs, snakemake.output.search)):  # noqa: F821
    print(f"system {i + 1}/{len(systems)}", file=sys.stderr)
    run_search(Case.from_dict(system), runs, search, store)
