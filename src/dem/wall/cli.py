"""Command line: ``dem wall CASE.yaml -o OUT.nc`` (also ``python3 -m dem.wall CASE.yaml -o OUT.nc``).

Bad input prints one line ``error: <field>: <problem>; <fix>`` and exits with status 2,
leaving no output file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from dem.errors import InputError

HELP = "pushover of a 3D rigid-block masonry wall (manuscript cases in config/walls/)"


def _arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    parser.add_argument("case", type=Path, help="wall case YAML file (schema: dem.wall.case)")
    parser.add_argument("-o", "--output", type=Path, required=True, help="output NetCDF file")
    parser.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    return parser


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``wall`` on the ``dem`` sub-command parsers; sets ``func`` to ``command_wall``."""
    parser = _arguments(subparsers.add_parser("wall", help=HELP, description=HELP))
    parser.set_defaults(func=command_wall)
    return parser


def command_wall(args) -> int:
    from dem.wall.dataset import run_case_file

    if args.output.suffix not in (".nc", ".nc4"):
        raise InputError("-o/--output", f"{args.output} is not a .nc file", "give an output path ending in .nc")
    ds = run_case_file(args.case, args.output)
    if not args.quiet:
        print(f"wrote {args.output}: lambda_max = {float(ds.lambda_max):.4g} "
              f"({ds.attrs['status']}), {ds.sizes['step']} steps, {ds.attrs['n_blocks']} blocks, "
              f"{ds.attrs['wall_seconds']:.1f} s", file=sys.stderr)
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = _arguments(argparse.ArgumentParser(prog="dem wall", description=HELP))
    args = parser.parse_args(argv)
    try:
        return command_wall(args)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
