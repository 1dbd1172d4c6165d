"""Snakemake script of workflow/rules/bench.smk: one benchmarks module per rule, thin.

The benchmark modules time one thread (none of their loops is parallel).
Each rule's outputs must be the files its module writes (the module is told their folders):
a mismatch, an unknown rule or a refused option ends the job with one line in the log and
exit 2, before anything runs; the job's exit status is the module's.
"""

import os
import sys
from pathlib import Path

sm = snakemake
# the benchmarks are a package of the checkout, not installed: import them from its root
sys.path.insert(0, str(Path(sm.scriptdir).resolve().parents[1]))
sys.stderr = open(sm.log[0], "w")
sys.stdout = sys.stderr
quick = ["--quick"] if sm.params.quick else []
d = os.path.dirname


def bench_work_precision():
    from benchmarks import work_precision

    out, figures = d(sm.output[0]), d(sm.output[1])
    expected = [os.path.join(out, "work_precision.nc")] + [
        os.path.join(figures, f"work_precision_{s}.png") for s in work_precision.SCENES
    ]
    return expected, lambda: work_precision.main(quick + ["--out", out, "--figures", figures])


def bench_contact_cost():
    from benchmarks import contact_cost

    root = d(d(sm.output[0]))
    expected = [
        os.path.join(root, "bench", "contact_cost.nc"),
        os.path.join(root, "figures", "contact_cost.png"),
    ]
    return expected, lambda: contact_cost.main(quick + ["--out", root])


def bench_stability():
    from benchmarks import stability

    out = d(sm.output[0])
    expected = [
        os.path.join(out, "stability_map.nc"),
        os.path.join(out, "auto_dt_margin.nc"),
        sm.output[2],
    ]
    return expected, lambda: stability.main(quick + ["--out", out, "--figure", sm.output[2]])


def bench_skipping():
    from benchmarks import skipping

    out = d(sm.output[0])
    limit = ["--limit", "4"] if sm.params.quick else []
    expected = [os.path.join(out, "skipping.nc")]
    return expected, lambda: skipping.main(
        ["--config", str(sm.params.config), "--out", out] + limit
    )


RULES = {
    "bench_work_precision": bench_work_precision,
    "bench_contact_cost": bench_contact_cost,
    "bench_stability": bench_stability,
    "bench_skipping": bench_skipping,
}


def refuse(field, problem, fix):
    from stonedem.errors import InputError

    print(f"error: {InputError(field, problem, fix)}", file=sys.stderr, flush=True)
    sys.exit(2)


def main() -> int:
    if sm.rule not in RULES:
        refuse("rule", f"{sm.rule} has no benchmark here", f"use one of {', '.join(RULES)}")
    expected, run = RULES[sm.rule]()
    given = [os.path.normpath(str(p)) for p in sm.output]
    if sorted(os.path.normpath(p) for p in expected) != sorted(given):
        refuse(
            f"{sm.rule}.output",
            f"{', '.join(given)} are not the files the module writes ({', '.join(expected)})",
            "list those outputs in workflow/rules/bench.smk",
        )
    return run()


sys.exit(main())
