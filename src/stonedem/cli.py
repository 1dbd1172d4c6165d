"""Command line of stonedem: rigid-block simulations of ancient columns and masonry walls.

Bad input prints one line, ``error: <field>: <problem>; <fix>``, exits with status 2 and
leaves no output file behind (outputs are written atomically after the run). SIGINT and
SIGTERM stop any command within a second, exit 130 / 143 and leave no output
(:mod:`stonedem.entry`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from stonedem.entry import Parser, check_output_path, exit_now, guarded, progress_print
from stonedem.errors import InputError, doc_summary
from stonedem.figures import snapshots
from stonedem.version import __version__

DESCRIPTION = "stonedem: rigid-block simulations of ancient columns, colonnades and masonry walls."
EPILOG = """examples:
  stonedem run scene.yaml -o out.nc        simulate one scene (format: docs/guide/scenes.md)
  stonedem validate --list                 the thesis 5.1 validations
  stonedem record info athens_standin_kocaeli_arc000
  stonedem wall config/walls/<case>.yaml -o wall.nc
  stonedem snapshots out.nc                draw a run at six times
  stonedem <command> --help                that command's options

exit status: 0 done, 1 a validation failed, 2 bad input (one line names the field),
130 / 143 stopped by SIGINT / SIGTERM (nothing written)."""


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="stonedem",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"stonedem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="command", title="commands")

    run = sub.add_parser("run", help="simulate one scene file and write a NetCDF dataset")
    run.add_argument("scene", type=Path, help="scene YAML file (format: docs/guide/scenes.md)")
    run.add_argument("-o", "--output", type=Path, required=True, help="output NetCDF file")
    run.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a scene field, e.g. --set solver.duration=2 (repeatable)",
    )
    run.add_argument("-q", "--quiet", action="store_true", help="no progress line")

    val = sub.add_parser(
        "validate", help="run the thesis 5.1 validations, write datasets and plots"
    )
    val.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("results/validation"),
        help="output folder (default results/validation)",
    )
    val.add_argument(
        "--only",
        action="append",
        default=[],
        metavar="NAME",
        help="run only these validations (repeatable); see --list",
    )
    val.add_argument("--list", action="store_true", help="list the validations and exit")

    from stonedem.motion.cli import add_parser as add_record_parser

    add_record_parser(sub)
    snapshots.add_parser(sub)
    from stonedem.wall.cli import add_parser as add_wall_parser

    add_wall_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)

    def command():
        if hasattr(args, "handler"):
            return args.handler(args)
        if args.command == "wall":
            return args.func(args)
        if args.command == "run":
            return command_run(args)
        if args.command == "validate":
            return command_validate(args)
        return 1

    status = guarded(command)
    from stonedem.io import atomic

    if atomic.abandoned:
        # a writer thread was interrupted mid-file (its temporary file is already gone):
        # end now rather than wait for it at interpreter exit
        exit_now(status)
    return status


def console() -> None:
    """The ``stonedem`` command: :func:`main`, then end without the interpreter's teardown (all
    output is written and closed by then; the teardown of numba and xarray takes ~0.5 s)."""
    from stonedem.entry import exit_now

    exit_now(main())


def scene_inputs(scene_path: Path, scene) -> list[Path]:
    """The files a scene reads: itself and its record, if any (outputs must not overwrite them)."""
    inputs = [scene_path]
    for motion in (scene.horizontal, scene.vertical):
        source = motion.description.get("path") or motion.description.get("file")
        if source:
            inputs.append(Path(str(source)))
    return inputs


def command_run(args) -> int:
    from stonedem.api import load_scene, run_scene, write_dataset
    from stonedem.io.netcdf import check_dataset_path

    check_output_path(args.output, "-o/--output", inputs=[args.scene], suffixes=(".nc", ".nc4"))
    scene = load_scene(args.scene, overrides=args.overrides)
    # also what write_dataset refuses at the end (a file it did not write), before the run
    check_dataset_path(args.output, "-o/--output", inputs=scene_inputs(args.scene, scene))
    ds = run_scene(scene, progress=not args.quiet)  # refuses absurd requests first (preflight)
    write_dataset(ds, args.output)
    if not args.quiet:
        progress_print(
            sys.stderr,
            f"wrote {args.output}: {ds.sizes['time']} samples, {ds.sizes['body']} bodies, "
            f"dt = {ds.attrs['dt']:.3g} s, {ds.attrs['status']}, "
            f"wall {ds.attrs['wall_seconds']:.2f} s",
        )
    return 0


def command_validate(args) -> int:
    from stonedem.validation import cases as validation

    if args.list:
        for name, func in validation.VALIDATIONS.items():
            print(f"{name:26s} {doc_summary(func.__doc__)}")
        return 0
    check_output_path(
        args.output / "x.nc", "-o/--output"
    )  # a file there: "is a file, not a folder"
    unknown = [n for n in args.only if n not in validation.VALIDATIONS]
    if unknown:
        raise InputError(
            "--only",
            f"unknown validation '{unknown[0]}'",
            f"choose from {', '.join(validation.VALIDATIONS)}",
        )
    failed = validation.run_all(args.output, names=args.only or None)
    return 1 if failed else 0
