"""Wall benchmark: manuscript Tables 1-3 (limit loads) with the panel pushover.

Runs every case of ``config/walls`` listed below, one after the other at the lowest CPU
priority, and prints ours vs the manuscript's DEM column vs the experiment (or, for Table 1,
Orduna & Lourenco's FEM), the relative errors, whether the 10 % tolerance on the manuscript
DEM is met, the solver status and the run time; beside them the limit analysis of the same
model (``stonedem.wall.limit_analysis``) on the pushover's caps at its peak (the oracle) and on
the dead-load caps. Writes ``results/walls/benchmark.csv``.

    python -m benchmarks.wall_tables [--only orduna_case1 s11 ...] [--max-seconds 150] [--out
    results/walls] [--secant]
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

# run as a file (python benchmarks/x.py) as well as a module (python -m benchmarks.x)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import options
from stonedem.wall.case import load_case
from stonedem.wall.dataset import add_limit_analysis, wall_dataset
from stonedem.wall.limit_analysis import limit_multiplier
from stonedem.wall.pushover import ConvergenceError, pushover
from stonedem.wall.validation import LIMIT_TOLERANCE, limit_load_row

ROOT = Path(__file__).resolve().parents[1]
CASES = [
    "orduna_case1",
    "orduna_case2",
    "s11",
    "s12",
    "s13",
    "s15",
    "s6",
    "s1_s2_s3",
    "s5",
    "s32",
    "s23",
    "s34",
    "chee_liang_2_3",
    "chee_liang_8_12",
    "chee_liang_14_15",
    "chee_liang_4_5",
    "chee_liang_9_13",
    "chee_liang_10_11",
]


def run_case(name, max_seconds=150.0, secant=False):
    """One case: the table row of ``stonedem.wall.validation`` plus run statistics."""
    case = load_case(ROOT / "config" / "walls" / f"{name}.yaml")
    if secant:  # the manuscript's load-controlled secant scheme (section 2.3)
        case.settings.secant = 1.0
    if not case.settings.max_seconds:
        case.settings.max_seconds = max_seconds
    ref = case.spec.get("reference", {})
    t0 = time.perf_counter()
    try:
        r = pushover(case.model, case.settings, case.control_block)
    except ConvergenceError as err:  # e.g. the dead load alone does not converge
        return {
            "table": ref.get("table"),
            "file": name,
            "case": ref.get("case", name),
            "ours": float("nan"),
            "within_tolerance": False,
            "status": f"failed: {err}",
            "seconds": round(time.perf_counter() - t0, 1),
        }
    seconds = time.perf_counter() - t0
    t1 = time.perf_counter()
    ds = add_limit_analysis(
        wall_dataset(case, r),
        limit_multiplier(case.model, caps_at=r.interface_forces_at_max, settings=case.settings),
        limit_multiplier(case.model, settings=case.settings),
    )
    row = limit_load_row(ds)
    row["limit_analysis_dead_load"] = round(
        float(ds["lambda_limit_analysis_dead_load"])
        * (1e-3 if case.load_kind == "pressure" else 1.0),
        4,
    )
    row["limit_analysis_seconds"] = round(time.perf_counter() - t1, 1)
    return {
        "table": ref.get("table"),
        "file": name,
        **row,
        "unit": "kPa" if case.load_kind == "pressure" else "lambda",
        "final_over_peak": round(float(r.lam[-1] / r.lam.max()), 3)
        if r.lam.max() > 0
        else float("nan"),
        "steps": len(r.lam) - 1,
        "iterations": int(r.iterations.sum()),
        "max_residual": float(r.residual.max()),
        "seconds": round(seconds, 1),
    }


MAX_SECONDS = 86_400.0  # [s] a day per case


def build_parser():
    ap = options.parser("python -m benchmarks.wall_tables", __doc__)
    ap.add_argument(
        "--only",
        nargs="*",
        help="case file stems to run, each once, from: " + " ".join(CASES) + " (default: all)",
    )
    ap.add_argument(
        "--max-seconds",
        type=float,
        default=150.0,
        help=f"wall-clock budget per case [s], > 0 and <= {MAX_SECONDS:g} "
        "(a case file's solver.max_seconds wins; default 150)",
    )
    ap.add_argument(
        "--out",
        type=options.path_arg,
        default=str(ROOT / "results" / "walls"),
        help="output folder (writes benchmark.csv, or benchmark_secant.csv with --secant)",
    )
    ap.add_argument(
        "--secant",
        action="store_true",
        help="manuscript 2.3 load-controlled secant scheme; writes benchmark_secant.csv",
    )
    return ap


def check_args(args):
    """(case names, budget [s], output path), or an InputError before anything runs."""
    names = options.chosen(args.only, "--only", CASES, empty_ok=True) or CASES
    for name in names:
        options.input_file(
            ROOT / "config" / "walls" / f"{name}.yaml",
            "--only",
            "case file config/walls/<name>.yaml",
        )
    budget = options.number(
        args.max_seconds,
        "--max-seconds",
        lo=0.0,
        lo_open=True,
        hi=MAX_SECONDS,
        unit="s",
        example="150",
    )
    name = "benchmark_secant.csv" if args.secant else "benchmark.csv"
    return names, budget, options.output_folder(args.out, "--out", files=(name,)) / name


def main(argv=None) -> int:
    """Options and output folder checked first (one line, exit 2); then the cases."""
    args = build_parser().parse_args(argv)
    return options.run(lambda: tables(*check_args(args), secant=args.secant))


def tables(names, max_seconds: float, path: Path, secant: bool = False) -> int:
    try:
        os.nice(19)
    except OSError:
        pass
    rows = []
    head = (
        f"{'case':>10} {'unit':>6} {'ours':>9} {'at s/10':>9} {'DEM':>8} {'reference':>12} "
        f"{'err DEM':>8} "
        f"{'err ref':>8} {'ok':>3} {'s':>6} {'LP':>9} {'push/LP':>8} {'LP dead':>9} "
        f"{'LP s':>5}  status"
    )
    print(head, flush=True)
    for name in names:
        row = run_case(name, max_seconds, secant)
        rows.append(row)
        if "manuscript_dem" not in row:
            print(f"{row['case']:>10}  {row['status']}", flush=True)
            continue
        print(
            f"{row['case']:>10} {row['unit']:>6} {row['ours']:9.4g} "
            f"{row['ours_at_s_over_10']:9.4g} "
            f"{row['manuscript_dem']:8.4g} {row['reference']:>12} "
            f"{100 * row['error_vs_manuscript_dem']:+7.1f}% "
            f"{100 * row['error_vs_reference']:+7.1f}% "
            f"{'yes' if row['within_tolerance'] else 'no':>3} "
            f"{row['seconds']:6.1f} {row['limit_analysis']:9.4g} "
            f"{100 * row['pushover_vs_limit_analysis']:+7.2f}% "
            f"{row['limit_analysis_dead_load']:9.4g} {row['limit_analysis_seconds']:5.1f}  "
            f"{row['status']}",
            flush=True,
        )
    options.write_csv(path, rows, fieldnames=max((list(r) for r in rows), key=len), restval="")
    met = sum(r["within_tolerance"] for r in rows)
    print(
        f"{met} of {len(rows)} within {100 * LIMIT_TOLERANCE:.0f} % of the manuscript DEM; "
        f"total {sum(r['seconds'] for r in rows):.0f} s; wrote {path}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())  # one-line errors, exit 2 on bad input, 130 on Ctrl-C
