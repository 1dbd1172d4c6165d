"""Command lines: every option and output path checked before anything runs.

Shared by the ``main`` of every :mod:`benchmarks` module, the study's commands
(:mod:`stonedem.study.ensemble`, :mod:`stonedem.study.equivalence`), ``benchmarks/*.py`` and
``workflow/scripts/bench.py``, with the conventions of :mod:`stonedem.entry`: a bad option is
refused in one line, ``error: <field>: <problem>; <fix>``, exit 2, before any computing, and
the refusal creates nothing, no file and no folder (folders are made only when a result is
written, by :func:`stonedem.io.atomic.write_atomically`, which also leaves nothing under the
final name when a write fails). Usage errors of the parser (:class:`stonedem.entry.Parser`)
are one line with exit 2 too.

Output paths are checked by :func:`stonedem.entry.check_output_path`, which creates nothing:
the nearest folder that exists on the way to the output must be a folder and must take a
new entry, which is tried and removed at once (``os.access`` says yes to root everywhere,
/proc included).
"""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

from stonedem.entry import Parser, check_output_path, guarded
from stonedem.errors import InputError, doc_summary, one_line
from stonedem.io.atomic import write_csv, write_text  # noqa: F401 - the scripts' writers


def parser(prog: str, doc: str | None = None, **kwargs) -> Parser:
    """An argparse parser whose usage errors are one line with exit 2
    (:class:`stonedem.entry.Parser`)."""
    description = doc_summary(doc) or None
    return Parser(prog=prog, description=description, **kwargs)


def path_arg(text: str) -> Path:
    """argparse ``type`` of a path option: an empty value is a usage error (Path("") would be
    the current folder)."""
    import argparse

    if not text.strip():
        raise argparse.ArgumentTypeError("an empty path")
    return Path(text)


def run(command: Callable[[], int | None]) -> int:
    """``command()`` under :func:`stonedem.entry.guarded`: an InputError is one line and exit 2,
    SIGINT / SIGTERM exit 130 / 143; a command returning None counts as done (0)."""
    status = guarded(command)
    return 0 if status is None else int(status)


# --- numbers and choices ------------------------------------------------------------------


def number(
    value,
    field: str,
    *,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
    whole: bool = False,
    unit: str = "",
    example: str | None = None,
):
    """``value`` if it is a finite number within [lo, hi] ((lo, hi] when lo_open; a whole number
    when whole), else an InputError naming ``field``."""

    def refuse(problem: str):
        span = []
        if lo is not None:
            span.append(f"{'>' if lo_open else '>='} {lo:g}")
        if hi is not None:
            span.append(f"<= {hi:g}")
        kind = "a whole number" if whole else "a finite number"
        give = f"give {kind} {' and '.join(span)}{(' ' + unit) if unit else ''}".rstrip()
        raise InputError(field, problem, give + (f", e.g. {example}" if example else ""))

    if isinstance(value, bool) or not isinstance(value, (int, float)):
        refuse(f"expected a number, got {one_line(repr(value), 60)}")
    shown = one_line(repr(value), 40)  # an int of 400 digits has no float
    if isinstance(value, float) and not math.isfinite(value):
        refuse(f"{value} is not finite")
    if whole and isinstance(value, float) and not value.is_integer():
        refuse(f"{shown} is not a whole number")
    if lo is not None and (value <= lo if lo_open else value < lo):
        refuse(f"{shown} is too small")
    if hi is not None and value > hi:
        refuse(f"{shown} is too large")
    return int(value) if whole else float(value)


def chosen(
    values: Sequence[str] | None, field: str, allowed: Iterable[str], *, empty_ok: bool = False
) -> list[str]:
    """``values`` when each is one of ``allowed``, given once, and (unless empty_ok) at least
    one."""
    allowed = list(allowed)
    values = list(values or [])
    if not values and not empty_ok:
        raise InputError(field, "none given", f"give one or more of {', '.join(allowed)}")
    for value in values:
        if value not in allowed:
            raise InputError(
                field, f"unknown {one_line(repr(value), 80)}", f"choose from {', '.join(allowed)}"
            )
    for value in values:
        if values.count(value) > 1:
            raise InputError(field, f"{value} given twice", "give each once")
    return values


# --- files ----------------------------------------------------------------------------------


def _shown(path) -> str:
    return one_line(str(path), 200)


def _plain(path: Path, field: str) -> None:
    if not str(path).isprintable():
        raise InputError(field, f"{_shown(path)} contains control characters", "give a plain path")


def _kind(path: Path, field: str) -> str:
    """'missing', 'folder', 'file' or 'other' (a device, a pipe); an InputError when the path
    cannot even be looked at (a name too long, a file used as a folder on the way)."""
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        return "missing"
    except NotADirectoryError:
        raise InputError(
            field,
            f"{_shown(path)}: a file on the way is used as a folder",
            "give a path through folders",
        ) from None
    except OSError as err:
        raise InputError(
            field, f"{_shown(path)} cannot be looked at ({err.strerror})", "give another path"
        ) from None
    return "folder" if stat.S_ISDIR(mode) else "file" if stat.S_ISREG(mode) else "other"


def output_file(
    path: str | Path,
    field: str,
    *,
    suffixes: tuple[str, ...] = (),
    inputs: Iterable[str | Path] = (),
) -> Path:
    """An output file path, refused before any computing when it has another suffix (any
    case), is a folder, is one of ``inputs``, or lies where no file can be written
    (:func:`stonedem.entry.check_output_path`); creates nothing. An existing ``.nc`` file is
    replaced only when it is a NetCDF dataset (an earlier result), never another file that
    happens to bear the name."""
    path = Path(path)
    _plain(path, field)
    if suffixes and path.suffix.lower() not in suffixes:
        raise InputError(
            field,
            f"{_shown(path)} does not end in {' or '.join(suffixes)}",
            f"give an output path ending in {suffixes[0]}",
        )
    path = check_output_path(path, field, inputs=inputs)
    if path.suffix.lower() == ".nc" and _kind(path, field) != "missing":
        _replaceable_netcdf(path, field)
    return path


def _replaceable_netcdf(path: Path, field: str) -> None:
    """Refuse to replace an existing file that is not a readable NetCDF dataset."""
    import xarray as xr

    refusal = InputError(
        field,
        f"{_shown(path)} exists and is not a NetCDF dataset",
        "give a new path or remove that file; a result replaces only an earlier result",
    )
    if not path.is_file():
        raise refusal
    try:
        with xr.open_dataset(path):
            pass
    except (KeyboardInterrupt, MemoryError):
        raise
    except Exception:  # noqa: BLE001 - whatever the backends raise on a foreign file
        raise refusal from None


def output_folder(path: str | Path, field: str, files: Iterable[str]) -> Path:
    """An output folder (made when the first result is written) for the result ``files``,
    refused before any computing when it is a file, lies where nothing can be written, or
    holds a folder under the name of one of the files; creates nothing."""
    path = Path(path)
    _plain(path, field)
    for name in files:
        check_output_path(path / name, field)  # names too long, a file on the way, no write access
    if _kind(path, field) not in ("missing", "folder"):
        raise InputError(
            field, f"{_shown(path)} is a file, not a folder", "give a folder for the results"
        )
    for name in files:
        target = path / name
        if _kind(target, field) == "folder":
            raise InputError(
                field,
                f"{_shown(target)} is a folder, where the result file {name} goes",
                "remove that folder or give another output folder",
            )
        if target.suffix.lower() == ".nc" and _kind(target, field) != "missing":
            _replaceable_netcdf(target, field)
    return path


def input_file(path: str | Path, field: str, what: str = "file") -> Path:
    """An existing regular file, or an InputError naming ``field``."""
    path = Path(path)
    _plain(path, field)
    kind = _kind(path, field)
    if kind == "missing":
        raise InputError(field, f"{_shown(path)} not found", f"give the path of a {what}")
    if kind != "file":
        raise InputError(
            field, f"{_shown(path)} is not a regular file", f"give the path of a {what}"
        )
    if not os.access(path, os.R_OK):
        raise InputError(field, f"{_shown(path)} is not readable", f"give a readable {what}")
    return path


def read_netcdf(path: str | Path, field: str, what: str, fix: str):
    """The NetCDF file at ``path`` (an xarray Dataset, in memory), or an InputError naming
    ``field``: not a regular readable file, not NetCDF by its first bytes, or a file the
    backend cannot read (``fix``: what to give instead)."""
    import xarray as xr

    from stonedem.io.netcdf import NETCDF_MAGIC

    path = input_file(path, field, what)
    shown = one_line(str(path), 200)
    with open(path, "rb") as handle:
        head = handle.read(8)
    if not head.startswith(NETCDF_MAGIC):
        raise InputError(field, f"{shown} is not a NetCDF file", fix)
    try:
        with xr.open_dataset(path, decode_times=False) as ds:
            return ds.load()
    except (KeyboardInterrupt, MemoryError):
        raise
    except Exception as err:  # noqa: BLE001 - whatever a damaged file makes the backend raise
        raise InputError(
            field, f"{shown} cannot be read ({type(err).__name__}: {one_line(str(err), 120)})", fix
        ) from None


# --- writing --------------------------------------------------------------------------------


def save_figure(fig, path: str | Path, **savefig) -> Path:
    """``fig.savefig`` atomically, the format from the path's suffix."""
    from stonedem.io.atomic import write_atomically

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    return write_atomically(path, lambda tmp: fig.savefig(tmp, format=fmt, **savefig))
