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
from stonedem.io.spec import Field, got, parse_range, range_words, show


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


def checked(f: Field, value, types: tuple = (int, float), exact: tuple | None = None):
    """``value`` checked as the declared field ``f`` (:mod:`stonedem.io.spec`), when a parser or a
    script gave it: only a number of ``types`` (never text or a bool, which a YAML field may
    take), finite; a whole number beyond 2**53 is compared exactly with ``exact`` = (lo, hi)
    (default: the field's range), as the kit's bounds are floats and it cannot show such a
    number."""
    lo, hi, lo_open, hi_open = parse_range(f.range)
    lo, hi = exact or (lo, hi)
    problem = None
    if isinstance(value, bool) or not isinstance(value, types):
        problem = (
            f"expected {'an integer' if f.kind == 'integer' else 'a number'}, got {got(value)}"
        )
    elif isinstance(value, float) and not math.isfinite(value):
        problem = f"{value} is not finite"
    elif isinstance(value, int) and f.kind == "integer" and abs(value) > 2**53:
        above, below = (
            (value >= hi) if hi_open else (value > hi),
            (value <= lo) if lo_open else (value < lo),
        )
        if not (above or below):
            return int(value)
        problem = f"{show(value)} is too {'large' if above else 'small'}"
    if problem:
        raise InputError(f.key, problem, f.hint)
    return f.check(value)


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
    bounds = f"{'(' if lo_open else '['}{_bound(lo)}, {_bound(hi)}]"
    kind = "a whole number" if whole else "a finite number"
    give = f"give {kind} {range_words(bounds, unit)}".rstrip()
    declared = Field(
        field,
        "integer" if whole else "number",
        units=unit,
        range=bounds,
        hint=give + (f", e.g. {example}" if example else ""),
    )
    exact = (-math.inf if lo is None else lo, math.inf if hi is None else hi)
    checked(declared, value, exact=exact)
    return int(value) if whole else float(value)  # as given: -0.0 stays -0.0


def _bound(x) -> str:
    return "" if x is None else repr(float(x))  # repr: the exact float, e.g. 9.223372036854776e+18


def chosen(
    values: Sequence[str] | None, field: str, allowed: Iterable[str], *, empty_ok: bool = False
) -> list[str]:
    """``values`` when each is one of ``allowed``, given once, and (unless empty_ok) at least
    one."""
    allowed = list(allowed)
    values = list(values or [])
    if not values and not empty_ok:
        raise InputError(field, "none given", f"give one or more of {', '.join(allowed)}")
    choice = Field(field, "choice", choices=tuple(allowed))
    for value in values:
        choice.check(value)
    twice = next((value for value in values if values.count(value) > 1), None)
    if twice is not None:
        raise InputError(field, f"{twice} given twice", "give each once")
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
        problem, fix = ": a file on the way is used as a folder", "give a path through folders"
    except OSError as err:
        problem, fix = f" cannot be looked at ({err.strerror})", "give another path"
    else:
        return "folder" if stat.S_ISDIR(mode) else "file" if stat.S_ISREG(mode) else "other"
    raise InputError(field, f"{_shown(path)}{problem}", fix)


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
        problem, fix = "is a file, not a folder", "give a folder for the results"
    else:
        for name in files:
            target = path / name
            kind = _kind(target, field)
            if kind == "folder":
                path, problem = target, f"is a folder, where the result file {name} goes"
                fix = "remove that folder or give another output folder"
                break
            if target.suffix.lower() == ".nc" and kind != "missing":
                _replaceable_netcdf(target, field)
        else:
            return path
    raise InputError(field, f"{_shown(path)} {problem}", fix)


def input_file(path: str | Path, field: str, what: str = "file") -> Path:
    """An existing regular file, or an InputError naming ``field``."""
    path = Path(path)
    _plain(path, field)
    kind = _kind(path, field)
    if kind == "file" and os.access(path, os.R_OK):
        return path
    problem = {"missing": "not found", "file": "is not readable"}.get(kind, "is not a regular file")
    fix = f"give a readable {what}" if kind == "file" else f"give the path of a {what}"
    raise InputError(field, f"{_shown(path)} {problem}", fix)


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
    problem = "is not a NetCDF file"
    if head.startswith(NETCDF_MAGIC):
        try:
            with xr.open_dataset(path, decode_times=False) as ds:
                return ds.load()
        except (KeyboardInterrupt, MemoryError):
            raise
        except Exception as err:  # noqa: BLE001 - whatever a damaged file makes the backend raise
            problem = f"cannot be read ({type(err).__name__}: {one_line(str(err), 120)})"
    raise InputError(field, f"{shown} {problem}", fix)


# --- writing --------------------------------------------------------------------------------


def save_figure(fig, path: str | Path, **savefig) -> Path:
    """``fig.savefig`` atomically, the format from the path's suffix."""
    from stonedem.io.atomic import write_atomically

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    return write_atomically(path, lambda tmp: fig.savefig(tmp, format=fmt, **savefig))
