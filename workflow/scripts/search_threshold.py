"""Snakemake script: the collapse-threshold searches of one job (stonedem.study.runner).

config device: cpu runs them one after another (run_search); gpu runs them together on the
GPU (run_searches), or on every CPU core when no GPU can run them, saying why in one line.
"""

import sys

from stonedem.entry import workflow_log
from stonedem.study.grid import Case
from stonedem.study.runner import CaseStore, choose_device, run_search, run_searches

workflow_log(snakemake.log[0])
store = CaseStore(snakemake.config.get("case_store"), "records")
systems = [Case.from_dict(system) for system in snakemake.params.systems]
outputs = snakemake.output
# config search_runs: full writes every run's case file too (one folder per system); else none
runs_dirs = list(outputs.runs) if outputs.runs else None
if snakemake.config.get("device", "cpu") == "gpu":
    device, line = choose_device("gpu")
    print(line, file=sys.stderr)
    run_searches(systems, runs_dirs, outputs.search, store, device=device)
else:
    for i, (system, search) in enumerate(zip(systems, outputs.search)):
        print(f"system {i + 1}/{len(systems)}", file=sys.stderr)
        run_search(system, runs_dirs[i] if runs_dirs else None, search, store)
