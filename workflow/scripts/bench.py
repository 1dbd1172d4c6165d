"""Snakemake script of workflow/rules/bench.smk: one stonedem.bench module per rule, thin.

The benchmark modules time one thread, so NUMBA_NUM_THREADS is set before numba loads.
"""

import os
import sys

from stonedem.entry import workflow_log

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

sm = snakemake  # noqa: F821 - provided by Snakemake
workflow_log(sm.log[0])
sys.stdout = sys.stderr
quick = ["--quick"] if sm.params.quick else []


def bench_work_precision():
    from stonedem.bench import work_precision

    work_precision.main(quick + ["--out", os.path.dirname(sm.output[0]),
                                 "--figures", os.path.dirname(sm.output[1])])


def bench_contact_cost():
    from stonedem.bench import contact_cost

    contact_cost.main(quick + ["--out", os.path.dirname(os.path.dirname(sm.output[0]))])


def bench_stability():
    from stonedem.bench import stability

    stability.main(quick + ["--out", os.path.dirname(sm.output[0]), "--figure", sm.output[2]])


def bench_skipping():
    from stonedem.bench import skipping

    limit = ["--limit", "4"] if sm.params.quick else []
    skipping.main(["--config", sm.params.config, "--out", os.path.dirname(sm.output[0])] + limit)


{"bench_work_precision": bench_work_precision, "bench_contact_cost": bench_contact_cost,
 "bench_stability": bench_stability, "bench_skipping": bench_skipping}[sm.rule]()
