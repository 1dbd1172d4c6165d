"""Writing the project's NetCDF files: one writer for every dataset of both solvers.

:func:`write_dataset` writes any dataset (scenes, cases, cubes, searches, the IDA, walls,
validations, benchmarks) atomically in the CF layout; :func:`schema_variables` builds
variables with the units and long names of :mod:`stonedem.io.schema`; :func:`code_version` is
the version written into every file's attrs.
"""

from __future__ import annotations

import functools
import json
import numbers
import os
import subprocess
import sys
from datetime import datetime, timezone
from pathlib import Path

import xarray as xr

from stonedem.errors import InputError, one_line
from stonedem.io.atomic import write_atomically
from stonedem.io.schema import attrs_for, cf_conventions
from stonedem.version import __version__


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """stonedem version, with the git commit when run from a checkout (asked of git once a process:
    a job of many cases paid 5 ms a case)."""
    try:
        here = Path(__file__).resolve().parent
        commit = subprocess.run(
            ["git", "-C", str(here), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=5,
        )
        if commit.returncode == 0:
            return f"stonedem {__version__} ({commit.stdout.strip()})"
    except (OSError, subprocess.SubprocessError):
        pass
    return f"stonedem {__version__}"


def history_line() -> str:
    """A line of CF's ``history``: when (UTC), the command that wrote the file, the code version."""
    when = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    argv = sys.argv or [""]
    command = " ".join([Path(argv[0]).name or "python", *argv[1:]])
    return f"{when} {one_line(command, 400)} ({code_version()})"


def schema_variables(arrays: dict) -> dict[str, xr.Variable]:
    """name -> (dims, data) as variables with the units and long names of
    :mod:`stonedem.io.schema`."""
    return {
        name: xr.Variable(dims, data, attrs=attrs_for(name))
        for name, (dims, data) in arrays.items()
    }


# the first bytes of a NetCDF file: classic, 64-bit offset, CDF-5, NetCDF-4 (HDF5)
NETCDF_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05", b"\x89HDF\r\n\x1a\n")
# the dtypes a NetCDF-4 variable holds (netCDF4 refuses float16, complex, void, long double)
_WRITABLE = {"b", "i", "u", "O", "S", "U", "M", "m"}


def dataset_inputs(ds: xr.Dataset) -> list[str]:
    """The files a dataset was made from, as its attrs name them: ``scene_file`` (set by
    :func:`stonedem.api.run_scene` for a scene read from a file) and the record of each
    excitation (``"file"`` in ``attrs["excitation"]``)."""
    found = [str(ds.attrs["scene_file"])] if isinstance(ds.attrs.get("scene_file"), str) else []
    for key in ("excitation", "excitation_vertical"):
        try:
            described = json.loads(ds.attrs.get(key, ""))
        except (TypeError, ValueError):
            continue
        if isinstance(described, dict) and isinstance(described.get("file"), str):
            found.append(described["file"])
    return found


def check_replaceable(path: Path, field: str) -> None:
    """Refuse to replace an existing file that is not a NetCDF file stonedem wrote (every one
    has ``stonedem`` in its ``history``): a scene, a notes file or another tool's NetCDF named
    as the output by mistake is left alone."""
    if not path.exists():
        return
    if not path.is_file():
        raise InputError(
            field, f"{path} is not a regular file", "give the path of a .nc file to write"
        )
    try:
        with open(path, "rb") as handle:
            head = handle.read(8)
    except OSError as err:
        raise InputError(
            field, f"{path} cannot be read ({err.strerror})", "give another path"
        ) from None
    fix = "remove it first or give another path" + (
        ", or pass overwrite=True" if field == "path" else ""
    )
    if not head.startswith(NETCDF_MAGIC):
        raise InputError(field, f"{path} exists and is not a NetCDF file; it is not replaced", fix)
    try:
        import netCDF4

        with netCDF4.Dataset(path, "r") as nc:
            ours = "stonedem" in str(getattr(nc, "history", ""))
    except (OSError, RuntimeError, ValueError):
        ours = False
    if not ours:
        raise InputError(
            field, f"{path} is a NetCDF file stonedem did not write; it is not replaced", fix
        )


def check_dataset_path(path, field: str = "path", inputs=(), overwrite: bool = False) -> Path:
    """The path :func:`write_dataset` may write, checked before any writing (or computing):
    :func:`stonedem.io.paths.check_output_path` (a folder, a symlink loop, an input, a folder
    that cannot be written), then :func:`check_replaceable` unless ``overwrite``."""
    from stonedem.io.paths import check_output_path

    if (
        isinstance(path, bytes)
        or not isinstance(path, (str, os.PathLike))
        or not isinstance(os.fspath(path), str)
    ):
        raise TypeError(
            f"{field}: expected a file path (str or os.PathLike), got {type(path).__name__}"
        )
    path = check_output_path(path, field, inputs=inputs)
    if not overwrite:
        check_replaceable(path, field)
    return path


def _attr_problem(value) -> str | None:
    """Why NetCDF cannot hold an attribute value (None: it can)."""
    import numpy as np

    if isinstance(value, (str, bytes)):
        return None
    if isinstance(value, (bool, np.bool_)):
        return "a bool"
    if isinstance(value, numbers.Number) and not isinstance(value, complex):
        return None if not isinstance(value, np.complexfloating) else "a complex number"
    if isinstance(value, (list, tuple, np.ndarray)):
        array = np.asarray(value) if not isinstance(value, np.ndarray) else value
        if (
            array.ndim == 1
            and (array.dtype.kind in "iuf" or array.dtype.kind in "US" and array.size)
            and array.dtype.str[1:] not in ("f2", "f16")
        ):
            return None
        return "a sequence that is not one flat list of numbers or of text"
    return f"a {type(value).__name__}"


def _check_attrs(attrs, owner: str) -> None:
    """Refuse an attribute of ``owner`` (``ds`` or ``ds['x']``) that NetCDF cannot hold."""
    for key, value in attrs.items():
        if not isinstance(key, str) or not key:
            raise InputError(
                f"{owner}.attrs[{key!r}]", "an attribute name must be non-empty text", "rename it"
            )
        problem = _attr_problem(value)
        if problem:
            raise InputError(
                f"{owner}.attrs[{key!r}]",
                f"is {problem}, which NetCDF cannot hold",
                "give text, a number or a flat list of numbers",
            )


def check_writable(ds) -> None:
    """Refuse, naming the place, what NetCDF cannot hold: a non-Dataset (TypeError), names that
    are not text or hold '/', variables of complex, float16 or raw bytes, attributes that are
    not text, numbers or flat lists of them."""
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"ds: expected an xarray.Dataset, got {type(ds).__name__}")
    _check_attrs(ds.attrs, "ds")
    names = set(ds.variables) | set(ds.dims)
    for name in names:
        if not isinstance(name, str) or not name or "/" in name:
            raise InputError(
                f"ds[{name!r}]",
                "a variable or dimension name must be non-empty text without '/'",
                "rename it",
            )
    for name, var in ds.variables.items():
        kind, size = var.dtype.kind, var.dtype.itemsize
        if not (kind in _WRITABLE or kind == "f" and size in (4, 8)):
            raise InputError(
                f"ds[{name!r}]",
                f"has dtype {var.dtype}, which NetCDF cannot hold",
                "convert it to float64, an integer type or text",
            )
        _check_attrs(var.attrs, f"ds[{name!r}]")


def write_dataset(
    ds: xr.Dataset, path: str | Path, encoding: dict | None = None, overwrite: bool = False
) -> Path:
    """Write a dataset to NetCDF atomically, in the CF-1.10 layout every file of the project has.

    The file is written to a temporary file beside ``path`` and renamed over it, so a crash
    or a full disk never leaves a partial file under the final name.
    :func:`stonedem.io.schema.cf_conventions` applies the layout: coordinates without a fill
    value, one ``units`` per numeric variable; float data are compressed (zlib, level 4). A
    line goes on top of the ``history`` attribute: the date, the command, the code version.

    Parameters
    ----------
    ds : xarray.Dataset
        The dataset to write.
    path : str or pathlib.Path
        Where to write it (its folder must exist).
    encoding : dict, optional
        Per-variable NetCDF encodings that override the defaults.
    overwrite : bool, default False
        Replace an existing file that is not a NetCDF file stonedem wrote (by default
        refused: a scene YAML or another tool's file given as the path by mistake).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    TypeError
        ``ds`` is not a Dataset, ``path`` not a str or path, ``encoding`` not a dict,
        ``overwrite`` not a bool; the message names the argument.
    InputError
        What NetCDF cannot hold (named: ``ds.attrs['key']``, ``ds['name']``); a path that is a
        folder, loops, is an input of the dataset (:func:`dataset_inputs`: its scene file or
        record), or an existing file this writer did not write; a write that failed.
    """
    check_writable(ds)
    if encoding is not None and not isinstance(encoding, dict):
        raise TypeError(
            f"encoding: expected a dict of variable name -> encoding, got {type(encoding).__name__}"
        )
    if not isinstance(overwrite, bool):
        raise TypeError(f"overwrite: expected True or False, got {type(overwrite).__name__}")
    path = check_dataset_path(path, "path", inputs=dataset_inputs(ds), overwrite=overwrite)
    ds = cf_conventions(ds)
    # CF 2.6.2: newest line first, over what the data went through before
    ds.attrs["history"] = "\n".join(
        str(line) for line in (history_line(), ds.attrs.get("history")) if line
    )
    given = encoding or {}
    encoding = {
        name: {"zlib": True, "complevel": 4}
        for name, v in ds.data_vars.items()
        if v.dtype.kind == "f" and v.ndim > 0
    }
    for name in ds.coords:
        if ds[name].dtype.kind == "f":
            encoding[name] = {"_FillValue": None}
    encoding.update(given)
    try:
        return write_atomically(
            path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding)
        )
    except InputError:
        raise
    except (TypeError, ValueError, KeyError, AttributeError, OverflowError) as err:
        # what the checks above cannot see (object arrays of mixed types, a bad encoding)
        field = "ds or encoding" if given else "ds"
        raise InputError(
            field,
            f"cannot be written as NetCDF ({type(err).__name__}: {one_line(str(err), 200)})",
            "give variables of numbers or text and a valid encoding",
        ) from None


def open_result(path: str | Path) -> xr.Dataset:
    """A result file the workflow made, read into memory; one that cannot be read (truncated
    by a crash or a full disk) is removed and refused in one line, so that the next
    ``snakemake`` call makes it again instead of failing on it for good."""
    path = Path(path)
    try:
        with xr.open_dataset(path) as ds:
            return ds.load()
    except (OSError, ValueError, RuntimeError, KeyError) as err:
        if not path.is_file():
            raise InputError(
                str(path), "result file not found", "run snakemake again: it makes the file"
            ) from None
        path.unlink(missing_ok=True)
        raise InputError(
            str(path),
            f"unreadable, removed ({one_line(str(err), 120)})",
            "run snakemake again: it makes the file anew",
        ) from None
