"""Writing the project's NetCDF files: one writer for every dataset of both solvers.

:func:`write_dataset` writes any dataset (scenes, cases, cubes, searches, the IDA, walls,
validations, benchmarks) atomically in the CF layout; :func:`schema_variables` builds
variables with the units and long names of :mod:`stonedem.io.schema`; :func:`code_version` is
the version written into every file's attrs.
"""

from __future__ import annotations

import functools
import subprocess
import sys
from datetime import datetime, timezone
from pathlib import Path

import xarray as xr

from stonedem.errors import InputError, one_line
from stonedem.version import __version__
from stonedem.io.atomic import write_atomically
from stonedem.io.schema import attrs_for, cf_conventions


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """stonedem version, with the git commit when run from a checkout (asked of git once a process:
    a job of many cases paid 5 ms a case)."""
    try:
        here = Path(__file__).resolve().parent
        commit = subprocess.run(["git", "-C", str(here), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, timeout=5)
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
    """name -> (dims, data) as variables with the units and long names of :mod:`stonedem.io.schema`."""
    return {name: xr.Variable(dims, data, attrs=attrs_for(name)) for name, (dims, data) in arrays.items()}


def write_dataset(ds: xr.Dataset, path: str | Path, encoding: dict | None = None) -> Path:
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

    Returns
    -------
    pathlib.Path
        The path written.
    """
    ds = cf_conventions(ds)
    # CF 2.6.2: newest line first, over what the data went through before
    ds.attrs["history"] = "\n".join(line for line in (history_line(), ds.attrs.get("history")) if line)
    given = encoding or {}
    encoding = {name: {"zlib": True, "complevel": 4} for name, v in ds.data_vars.items()
                if v.dtype.kind == "f" and v.ndim > 0}
    for name in ds.coords:
        if ds[name].dtype.kind == "f":
            encoding[name] = {"_FillValue": None}
    encoding.update(given)
    return write_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", encoding=encoding))


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
            raise InputError(str(path), "result file not found", "run snakemake again: it makes the file") from None
        path.unlink(missing_ok=True)
        raise InputError(str(path), f"unreadable, removed ({one_line(str(err), 120)})",
                         "run snakemake again: it makes the file anew") from None
