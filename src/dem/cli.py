"""Command line: ``dem run SCENE.yaml -o OUT.nc``, ``dem validate``.

Bad input prints one line, ``error: <field>: <problem>; <fix>``, exits with status 2 and
leaves no output file behind (outputs are written atomically after the run).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from dem.errors import InputError


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="dem", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)

    run = sub.add_parser("run", help="simulate one scene file and write a NetCDF dataset")
    run.add_argument("scene", type=Path, help="scene YAML file (format: README)")
    run.add_argument("-o", "--output", type=Path, required=True, help="output NetCDF file")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scene field, e.g. --set solver.duration=2 (repeatable)")
    run.add_argument("-q", "--quiet", action="store_true", help="no progress line")

    val = sub.add_parser("validate", help="run the thesis 5.1 validations, write datasets and plots")
    val.add_argument("-o", "--output", type=Path, default=Path("results/validation"),
                     help="output folder (default results/validation)")
    val.add_argument("--only", action="append", default=[], metavar="NAME",
                     help="run only these validations (repeatable); see --list")
    val.add_argument("--list", action="store_true", help="list the validations and exit")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        if args.command == "run":
            return command_run(args)
        if args.command == "validate":
            return command_validate(args)
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 1


def command_run(args) -> int:
    from dem.dataset import write_dataset
    from dem.scene import load_scene
    from dem.simulate import run_scene

    scene = load_scene(args.scene, args.overrides)
    ds = run_scene(scene, progress=not args.quiet and sys.stderr.isatty())
    write_dataset(ds, args.output)
    if not args.quiet:
        print(f"wrote {args.output}: {ds.sizes['time']} samples, {ds.sizes['body']} bodies, "
              f"dt = {ds.attrs['dt']:.3g} s, {ds.attrs['status']}, "
              f"wall {ds.attrs['wall_seconds']:.2f} s", file=sys.stderr)
    return 0


def command_validate(args) -> int:
    from dem import validation

    if args.list:
        for name, func in validation.VALIDATIONS.items():
            print(f"{name:20s} {func.__doc__.splitlines()[0]}")
        return 0
    unknown = [n for n in args.only if n not in validation.VALIDATIONS]
    if unknown:
        raise InputError("--only", f"unknown validation '{unknown[0]}'",
                         f"choose from {', '.join(validation.VALIDATIONS)}")
    failed = validation.run_all(args.output, names=args.only or None)
    return 1 if failed else 0
