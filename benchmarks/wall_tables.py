"""Wall benchmark: manuscript Tables 1-3 (limit loads) with the panel pushover.

Runs every case of ``config/walls`` listed below, one after the other at the lowest CPU
priority, and prints ours vs the manuscript's DEM column vs the experiment (or, for Table 1,
Orduna & Lourenco's FEM), the relative errors, whether the 10 % tolerance on the manuscript
DEM is met, the solver status and the run time. Writes ``results/walls/benchmark.csv``.

    python benchmarks/wall_tables.py [--only orduna_case1 s11 ...] [--max-seconds 60] [--out results/walls] [--secant]
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

import numpy as np

from dem.wall.case import load_case
from dem.wall.pushover import ConvergenceError, pushover
from dem.wall.validation import LIMIT_TOLERANCE

ROOT = Path(__file__).resolve().parents[1]
CASES = ["orduna_case1", "orduna_case2",
         "s11", "s12", "s13", "s15", "s6", "s1_s2_s3", "s5", "s32", "s23", "s34",
         "chee_liang_2_3", "chee_liang_8_12", "chee_liang_14_15", "chee_liang_4_5",
         "chee_liang_9_13", "chee_liang_10_11"]


def run_case(name, max_seconds=60.0, secant=False):
    case = load_case(ROOT / "config" / "walls" / f"{name}.yaml")
    if secant:   # the manuscript's load-controlled secant scheme (section 2.3)
        case.settings.secant = 1.0
    if not case.settings.max_seconds:
        case.settings.max_seconds = max_seconds
    ref = case.spec.get("reference", {})
    t0 = time.perf_counter()
    try:
        r = pushover(case.model, case.settings, case.control_block)
    except ConvergenceError as err:   # e.g. the dead load alone does not converge
        r = None
        failure = f"failed: {err}"
    seconds = time.perf_counter() - t0
    pressure = case.load_kind == "pressure"
    scale = 1e-3 if pressure else 1.0   # pressures in kPa
    dem = ref.get("p_dem", ref.get("lambda_dem"))
    exp = ref.get("p_experiment", ref.get("lambda_experiment", ref.get("lambda_fem")))
    exp = np.atleast_1d(exp).astype(float) * scale
    dem = dem * scale
    if r is None:
        return {"table": ref.get("table"), "case": ref.get("case", name), "file": name,
                "unit": "kPa" if pressure else "lambda", "ours": float("nan"), "manuscript_dem": dem,
                "experiment": ";".join(f"{e:g}" for e in exp), "error_vs_dem": float("nan"),
                "error_vs_experiment": float("nan"), "within_10pc_of_dem": False,
                "final_over_peak": float("nan"), "traced_past_peak": False, "steps": 0,
                "max_residual": float("nan"), "status": failure, "seconds": round(seconds, 1)}
    ours = r.lambda_max * scale
    peak = r.lam.max()
    past_peak = r.step_max < len(r.lam) - 1
    return {"table": ref.get("table"), "case": ref.get("case", name), "file": name,
            "unit": "kPa" if pressure else "lambda",
            "ours": round(ours, 4), "manuscript_dem": dem,
            "experiment": ";".join(f"{e:g}" for e in exp),
            "error_vs_dem": round(ours / dem - 1, 4),
            "error_vs_experiment": round(ours / float(exp.mean()) - 1, 4),
            "within_10pc_of_dem": abs(ours / dem - 1) <= LIMIT_TOLERANCE,
            "final_over_peak": round(float(r.lam[-1] / peak), 3) if peak > 0 else float("nan"),
            "traced_past_peak": bool(past_peak),
            "steps": len(r.lam) - 1, "max_residual": float(r.residual.max()),
            "status": r.status, "seconds": round(seconds, 1)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="case file stems to run (default: all)")
    ap.add_argument("--max-seconds", type=float, default=60.0,
                    help="wall-clock budget per case (a case file's solver.max_seconds wins)")
    ap.add_argument("--out", default=str(ROOT / "results" / "walls"))
    ap.add_argument("--secant", action="store_true",
                    help="manuscript 2.3 load-controlled secant scheme; writes benchmark_secant.csv")
    args = ap.parse_args(argv)
    try:
        os.nice(19)
    except OSError:
        pass
    rows = []
    head = f"{'case':>10} {'unit':>6} {'ours':>9} {'DEM':>8} {'exp':>12} {'err DEM':>8} {'err exp':>8} {'ok':>3} {'s':>6}  status"
    print(head, flush=True)
    for name in args.only or CASES:
        row = run_case(name, args.max_seconds, args.secant)
        rows.append(row)
        print(f"{row['case']:>10} {row['unit']:>6} {row['ours']:9.4g} {row['manuscript_dem']:8.4g} "
              f"{row['experiment']:>12} {100 * row['error_vs_dem']:+7.1f}% {100 * row['error_vs_experiment']:+7.1f}% "
              f"{'yes' if row['within_10pc_of_dem'] else 'no':>3} {row['seconds']:6.1f}  {row['status']}",
              flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / ("benchmark_secant.csv" if args.secant else "benchmark.csv")
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    met = sum(r["within_10pc_of_dem"] for r in rows)
    print(f"{met} of {len(rows)} within {100 * LIMIT_TOLERANCE:.0f} % of the manuscript DEM; "
          f"total {sum(r['seconds'] for r in rows):.0f} s; wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
