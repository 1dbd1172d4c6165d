"""Are two runs of the study the same? Their cubes, tables, cases and searches compared file
by file (issue 34: a run through SLURM against a local one; the fault tests: a rerun after
a crash against an undisturbed run).

NetCDF files: every variable and coordinate bit-identical (NaN where NaN), their attrs and
the file's equal but for the clock-time ones (:data:`CLOCK`). CSV tables: byte for byte, or
with ``clock_columns`` equal but in the columns named in :data:`CLOCK` (the wall time of a
run, which no two runs share). Any other file: byte for byte. A file on one side only, or one
that cannot be read (a truncated NetCDF file, a table that is not UTF-8), is a difference,
named in one line.

    python -m stonedem.study.compare STUDY_A STUDY_B   # exit 0: the same; 1: the differences;
                                                       # 2: bad arguments, or no study files in
                                                       either
"""

from __future__ import annotations

import csv
import io
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.errors import InputError, one_line
from stonedem.io.paths import real_path

# attrs (and table columns) that hold the clock time or the machine of a run
CLOCK = (
    "wall_seconds",
    "compile_seconds",
    "kernel_seconds",
    "seconds",
    "created",
    "date_created",
    "history",
    "host",
    "elapsed",
    "run_seconds",
)
KINDS = ("cubes", "tables", "cases", "searches", "fragility")
# a study's CSV tables are kilobytes; two of 2 GB took 6.4 GB of memory and 28 s to call the same
MAX_TABLE_BYTES = 256 * 2**20


def result_files(directory: Path, kinds=KINDS) -> list[str]:
    """The study's files of ``kinds`` under ``directory``/results (paths relative to directory)."""
    results = Path(directory) / "results"
    # a dangling link is a file that cannot be read (a difference), not no file (ignored: "the
    # same")
    found = [
        p
        for kind in kinds
        for p in (results / kind).rglob("*")
        if (p.is_file() or p.is_symlink() and not p.exists()) and not p.name.startswith(".")
    ]
    return sorted(str(p.relative_to(directory)) for p in found)


def same_values(x, y) -> bool:
    x, y = np.asarray(x), np.asarray(y)
    if x.shape != y.shape or x.dtype.kind != y.dtype.kind:
        return False
    if x.dtype.kind in "fc":
        return np.array_equal(x, y, equal_nan=True)
    if x.dtype.kind == "O":
        return np.array_equal(x.astype(str), y.astype(str))
    return np.array_equal(x, y)


def _unclocked(attrs: dict) -> dict:
    return {k: v for k, v in attrs.items() if k not in CLOCK}


def _attrs_differ(a: dict, b: dict) -> set:
    """The attributes, clocks aside, whose values differ; a value may be an array (a link's
    flag values), which ``!=`` of two dicts cannot compare."""
    a, b = _unclocked(a), _unclocked(b)
    return {k for k in set(a) | set(b) if not same_values(a.get(k), b.get(k))}


def _load(path: Path):
    """(the dataset, in memory, None), or (None, why it cannot be read)."""
    try:
        with xr.open_dataset(path, decode_times=False) as ds:
            return ds.load(), None
    except Exception as err:  # whatever a damaged file makes the backend raise
        return None, f"{type(err).__name__}: {err}"


def dataset_differences(path_a: Path, path_b: Path, label: str) -> list[str]:
    """What differs between two NetCDF files, beyond their clock attrs; a file that cannot be
    read is a difference (one line per such file)."""
    (a, why_a), (b, why_b) = _load(path_a), _load(path_b)
    if why_a or why_b:
        return [
            one_line(f"{label}: cannot read {path} ({why})")
            for path, why in ((path_a, why_a), (path_b, why_b))
            if why
        ]
    out = []
    if set(a.variables) != set(b.variables):
        return [f"{label}: variables {sorted(set(a.variables) ^ set(b.variables))}"]
    if dict(a.sizes) != dict(b.sizes):
        return [f"{label}: sizes {dict(a.sizes)} != {dict(b.sizes)}"]
    for name in a.variables:
        if a[name].dims != b[name].dims or not same_values(a[name].values, b[name].values):
            out.append(f"{label}:{name} differs")
        elif _attrs_differ(a[name].attrs, b[name].attrs):
            out.append(f"{label}:{name} attrs differ")
    differ = _attrs_differ(a.attrs, b.attrs)
    if differ:
        out.append(f"{label}: attrs {sorted(differ)} differ")
    return out


def _text(path: Path):
    """(the file's bytes, None) when they are UTF-8 text, else (None, why not)."""
    try:
        size = Path(path).stat().st_size
        if size > MAX_TABLE_BYTES:
            return (
                None,
                f"{path} is {size / 2**20:.0f} MB, more than a study table holds "
                f"({MAX_TABLE_BYTES // 2**20} MB)",
            )
        data = Path(path).read_bytes()
    except OSError as err:
        return None, f"cannot read {path} ({err.strerror or err})"
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as err:
        return None, f"{path} is not UTF-8 text (byte {err.start})"
    return data, None


def table_differences(
    path_a: Path, path_b: Path, label: str, clock_columns: bool = False
) -> list[str]:
    """What differs between two CSV tables: their bytes, or with ``clock_columns`` their
    cells outside the CLOCK columns; a table that cannot be read as UTF-8 text is a difference."""
    (a, why_a), (b, why_b) = _text(path_a), _text(path_b)
    if why_a or why_b:
        return [one_line(f"{label}: {why}") for why in (why_a, why_b) if why]
    if a == b:
        return []
    if not clock_columns:
        return [f"{label} differs"]
    try:
        rows_a = list(csv.DictReader(io.StringIO(a.decode())))
        rows_b = list(csv.DictReader(io.StringIO(b.decode())))
    except csv.Error as err:
        return [one_line(f"{label} differs and is not a CSV table ({err})")]
    strip = [{k: v for k, v in row.items() if k not in CLOCK} for row in rows_a]
    if strip != [{k: v for k, v in row.items() if k not in CLOCK} for row in rows_b]:
        return [f"{label} differs outside its clock columns"]
    return []


def _same_bytes(path_a: Path, path_b: Path):
    try:  # in pieces: a file of any size is compared in bounded memory
        if Path(path_a).stat().st_size != Path(path_b).stat().st_size:
            return False, None
        with open(path_a, "rb") as a, open(path_b, "rb") as b:
            while True:
                piece = a.read(2**20)
                if piece != b.read(2**20):
                    return False, None
                if not piece:
                    return True, None
    except OSError as err:
        return False, f"cannot read {err.filename} ({err.strerror or err})"


def file_differences(
    directory: Path, reference: Path, kinds=KINDS, clock_columns: bool = False
) -> dict[str, list[str]]:
    """{file: what differs, empty when the same} for every study file of either folder; a
    file in one folder only is a difference naming the folder that has it."""
    mine, theirs = set(result_files(directory, kinds)), set(result_files(reference, kinds))
    out = {}
    for rel in sorted(mine | theirs):
        a, b = Path(directory) / rel, Path(reference) / rel
        if rel not in theirs or rel not in mine:
            out[rel] = [one_line(f"{rel}: only in {directory if rel in mine else reference}")]
        elif rel.endswith(".csv"):
            out[rel] = table_differences(a, b, rel, clock_columns)
        elif rel.endswith(".nc"):
            out[rel] = dataset_differences(a, b, rel)
        else:
            same, why = _same_bytes(a, b)
            out[rel] = [] if same else [one_line(f"{rel}: {why or 'differs'}")]
    return out


def result_differences(
    directory: Path, reference: Path, kinds=KINDS, clock_columns: bool = False
) -> list[str]:
    """Everything that differs between two study folders' results (empty: the same)."""
    return [
        line
        for lines in file_differences(directory, reference, kinds, clock_columns).values()
        for line in lines
    ]


def study_folder(path: str, field: str, other: Path | None = None) -> Path:
    """``path`` as a study folder (one holding a results folder), not the folder ``other``
    (the one compared with it), or the InputError saying why not."""
    real_path(path, field)  # a symlink loop: one line, not pathlib's RuntimeError
    folder = Path(path)
    fix = "give the folder a study ran in (it holds a results folder)"
    if not folder.exists():
        problem = f"{path}: no such folder"
    elif not folder.is_dir():
        problem = f"{path} is a file, not a folder"
    elif not (folder / "results").is_dir():
        problem = f"{path} holds no results folder"
        fix += ", not that results folder itself"
    elif other is not None and folder.resolve() == other.resolve():
        problem, fix = f"{path} is the folder STUDY_A names", "compare two different study folders"
    else:
        return folder
    raise InputError(field, problem, fix)


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else argv
    try:
        if len(args) != 2:
            raise InputError(
                "arguments",
                f"expected two study folders, got {len(args)}",
                "python -m stonedem.study.compare STUDY_A STUDY_B",
            )
        a = study_folder(args[0], "STUDY_A")
        b = study_folder(args[1], "STUDY_B", other=a)
        files = file_differences(a, b, clock_columns=True)
        if not files:  # two runs that both made nothing are not the same run
            raise InputError(
                "STUDY_A, STUDY_B",
                f"no study files (results folders {{{','.join(KINDS)}}}) in either folder",
                "run the study in both before comparing them",
            )
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    differing = [rel for rel, lines in files.items() if lines]
    for rel in differing:
        for line in files[rel]:
            print(line)
    print(
        f"{len(files)} files compared: {f'{len(differing)} differ' if differing else 'the same'}",
        file=sys.stderr,
    )
    return 1 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
