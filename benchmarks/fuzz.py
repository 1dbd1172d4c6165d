"""Fuzz benchmark: every fuzz suite at 10 000 examples per test (issue 13).

``python -m benchmarks.fuzz [--quick] --out results/bench/fuzz.nc``: runs the tests named
``*fuzz*`` under tests/ with the hypothesis profile ``fuzz`` (10 000 examples per test;
``--quick``: the ``ci`` profile, 100), and writes per test the examples run (passing,
failing, invalid as hypothesis counts them), its outcome and wall time. Exit 1 if any
test failed: a failing example is a traceback, a hang or a wrong answer to fix.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.io.netcdf import code_version, write_dataset

ROOT = Path(__file__).resolve().parents[1]
# hypothesis' statistics line, e.g. "- 10000 passing examples, 0 failing examples, 12 invalid
# examples"
COUNTS = re.compile(r"(\d+) passing examples?, (\d+) failing examples?, (\d+) invalid examples?")
TEST = re.compile(r"^(tests/\S+::\S+):$", re.M)


def run(profile: str) -> tuple[list[dict], str]:
    """Run the fuzz tests under ``profile``; (rows per test, pytest's output)."""
    env = {**os.environ, "HYPOTHESIS_PROFILE": profile}
    start = time.perf_counter()
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-q",
            "-k",
            "fuzz",
            "--hypothesis-show-statistics",
            "-p",
            "no:cacheprovider",
            "tests",
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - start
    out = proc.stdout
    rows = []
    heads = list(TEST.finditer(out))
    for k, head in enumerate(heads):
        block = out[head.end() : heads[k + 1].start() if k + 1 < len(heads) else len(out)]
        counts = np.array([list(map(int, m.groups())) for m in COUNTS.finditer(block)]).reshape(
            -1, 3
        )
        passing, failing, invalid = counts.sum(axis=0) if len(counts) else (0, 0, 0)
        rows.append(
            {
                "test": head.group(1),
                "passing": int(passing),
                "failing": int(failing),
                "invalid": int(invalid),
            }
        )
    failed = set(re.findall(r"^FAILED (\S+)", out, re.M))
    for row in rows:
        row["failed"] = int(row["test"] in failed)
    print(
        f"{len(rows)} fuzz tests, {sum(r['passing'] + r['failing'] for r in rows)} examples, "
        f"{len(failed)} failed, {wall:.0f} s (profile {profile})"
    )
    return rows, out + f"\nwall {wall:.1f} s, pytest exit {proc.returncode}\n"


def fuzz_dataset(rows: list[dict], profile: str) -> xr.Dataset:
    tests = [r["test"] for r in rows]
    meta = {
        "passing": "examples that passed",
        "failing": "examples that failed (a bug)",
        "invalid": "examples hypothesis discarded",
        "failed": "1 when the test failed",
    }
    data = {
        key: (
            "test",
            np.array([r[key] for r in rows], dtype=np.int64),
            {"units": "1", "long_name": text},
        )
        for key, text in meta.items()
    }
    return xr.Dataset(
        data,
        coords={"test": ("test", np.array(tests, dtype=object), {"long_name": "fuzz test"})},
        attrs={
            "title": "fuzz suites: examples run and failures",
            "source": code_version(),
            "hypothesis_profile": profile,
        },
    )


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.fuzz", __doc__)
    parser.add_argument(
        "--quick", action="store_true", help="the ci profile (100 examples per test)"
    )
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=Path("results/bench/fuzz.nc"),
        help="output NetCDF file (.nc)",
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Options and output path checked first (one line, exit 2); then the fuzz suites."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        out = options.output_file(args.out, "--out", suffixes=(".nc",))
        if not (ROOT / "tests").is_dir():
            raise InputError(
                "tests", f"no tests/ folder in {ROOT}", "run the benchmark from a source checkout"
            )
        profile = "ci" if args.quick else "fuzz"
        rows, log = run(profile)
        print(log[-3000:], file=sys.stderr)
        write_dataset(fuzz_dataset(rows, profile), out)
        return 1 if any(r["failed"] for r in rows) or not rows else 0

    return options.run(command)


if __name__ == "__main__":
    raise SystemExit(main())
