"""Snakemake script of workflow/rules/validation.smk, one branch per rule.

validate_<k>        a batch of stonedem.validation.cases.VALIDATIONS entries -> a dataset each
                    (write_result: atomic), one log line each
validation_figures  the validation datasets -> every thesis figure (draw_thesis_figure: atomic)
validation_summary  every validation dataset -> name, error, tolerance, passed (atomic)

A validation that fails its check still writes its dataset (attribute passed = 0, the
figure says FAILED in red, the summary row has passed = 0); `stonedem validate` is the command
whose exit status reflects the verdicts.
"""

import sys
from pathlib import Path

from stonedem.entry import logged_seconds, workflow_log
from stonedem.io.atomic import write_text
from stonedem.validation import cases as validation
from stonedem.validation import plots as validation_plots

sm = snakemake
workflow_log(sm.log[0])


def validate_batch():
    for output in sm.output:
        name = Path(output).stem
        record = sm.params.records[name]
        with logged_seconds(sys.stderr, name):
            result = validation.VALIDATIONS[name](**({"record": record} if record else {}))
            validation.write_result(result, output)
        verdict = "ok" if result.passed else "FAILED"
        print(
            f"{name}: {verdict}: " + ", ".join(f"{k} = {v:.4g}" for k, v in result.summary.items()),
            file=sys.stderr,
        )


def validation_figures():
    for (fig, path), output in zip(sm.params.figures.items(), sm.output):
        with logged_seconds(sys.stderr, fig):
            validation_plots.draw_thesis_figure(fig, path, output)


def validation_summary():
    table = validation.summary_table(sm.input)
    write_text(sm.output[0], table)
    failed = [row.split(",")[0] for row in table.splitlines()[1:] if row.endswith(",0")]
    print(f"failed: {', '.join(failed) or 'none'}", file=sys.stderr)


if sm.rule.startswith("validate_"):
    validate_batch()
else:
    {"validation_figures": validation_figures, "validation_summary": validation_summary}[sm.rule]()
