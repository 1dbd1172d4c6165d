"""Command line: ``stonedem wall CASE.yaml -o OUT.nc [--limit]`` (also ``python3 -m stonedem.wall
...``).

``--limit`` adds the collapse multiplier by limit analysis (``stonedem.wall.limit_analysis``) to
the dataset and the summary line.

Bad input (the case file, its fields, its size, the output path) prints one line
``error: <field>: <problem>; <fix>`` and exits with status 2 before any computing, leaving no
output file. SIGINT exits 130, SIGTERM 143, with no file under the output name
(:func:`stonedem.entry.guarded`). A run longer than ``PROGRESS_SECONDS`` logs one line to stderr
every ``PROGRESS_SECONDS`` (``pushover: step 120, lambda 0.31, u 1.2e-03 m, 4.2 s``) unless
``--quiet``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from stonedem.entry import progress_print

HELP = "pushover of a 3D rigid-block masonry wall (manuscript cases in config/walls/)"
OUTPUT_SUFFIXES = (".nc", ".nc4")
# progress: nothing for a run shorter than this, then one line at most this often [s]
PROGRESS_SECONDS = 2.0


def _arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    parser.add_argument("case", type=Path, help="wall case YAML file (schema: stonedem.wall.case)")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output NetCDF file (.nc)")
    parser.add_argument(
        "--limit",
        action="store_true",
        help="also the collapse multiplier by limit analysis (HiGHS LP) with the joint "
        "caps on the pushover's actions at its peak: proves the plateau",
    )
    parser.add_argument(
        "-q", "--quiet", action="store_true", help="no progress lines and no summary line"
    )
    return parser


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``wall`` on the ``stonedem`` sub-command parsers; sets ``func`` to
    ``command_wall``."""
    parser = _arguments(subparsers.add_parser("wall", help=HELP, description=HELP))
    parser.set_defaults(func=command_wall)
    return parser


class ProgressLog:
    """Pushover progress callback: one stderr line every ``every`` seconds, the first after
    ``every`` seconds (a short run prints nothing); works whether or not stderr is a terminal."""

    def __init__(self, stream=None, every: float = PROGRESS_SECONDS, units: str = ""):
        self.stream = stream if stream is not None else sys.stderr
        self.every = every
        self.units = units
        self.t0 = time.monotonic()
        self.last = self.t0
        self.lines = 0

    def __call__(self, step, lam, u, message=None):
        now = time.monotonic()
        if now - self.last < self.every:
            return
        self.last = now
        line = f"pushover: step {step}, lambda {lam:.4g}{self.units}"
        if u == u:  # not NaN (a step being cut back)
            line += f", u {u:.3g} m"
        if message:
            line += f" (cutting the step back: {message})"
        self.stream = progress_print(self.stream, f"{line}, {now - self.t0:.1f} s")
        if self.stream is not None:
            self.lines += 1


def pushover(checked: dict, output=None, progress: bool = False, limit_analysis: bool = False):
    """Build a checked case (:func:`stonedem.wall.case.check_case`), push it over and, with
    ``output``, write it; ``progress``: a :class:`ProgressLog` line on stderr every few seconds."""
    from stonedem.wall.case import build_case
    from stonedem.wall.dataset import run_case  # xarray, numba, scipy: only once the input is valid

    case = build_case(checked)
    log = ProgressLog(units=" Pa" if case.load_kind == "pressure" else "") if progress else None
    return run_case(case, output, progress=log, limit_analysis=limit_analysis)


def command_wall(args) -> int:
    """Check the case and the output path (exit 2 before any computing), run, write, summarise."""
    from stonedem.entry import check_output_path
    from stonedem.wall.case import check_case, read_case

    checked = check_case(read_case(args.case), name=args.case.stem, where=str(args.case))
    check_output_path(args.output, "-o/--output", inputs=[args.case], suffixes=OUTPUT_SUFFIXES)
    ds = pushover(checked, args.output, progress=not args.quiet, limit_analysis=args.limit)
    if not args.quiet:
        print(
            f"wrote {args.output}: lambda_max = {float(ds.lambda_max):.4g} "
            f"({ds.attrs['status']}), {ds.sizes['step']} steps, {ds.attrs['n_blocks']} blocks, "
            f"{ds.attrs['wall_seconds']:.1f} s",
            file=sys.stderr,
        )
        if args.limit:
            la = ds["lambda_limit_analysis"]
            print(
                f"limit analysis: {float(la):.4g} on the joint caps at lambda_max "
                f"({la.attrs['status']}, "
                f"{la.attrs['seconds']:.1f} s); {ds.attrs['limit_analysis_verdict']}",
                file=sys.stderr,
            )
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python3 -m stonedem.wall``: the shared exit conventions of
    :func:`stonedem.entry.guarded`."""
    from stonedem.entry import Parser, guarded

    parser = _arguments(Parser(prog="stonedem wall", description=HELP))
    args = parser.parse_args(argv)
    return guarded(lambda: command_wall(args))
