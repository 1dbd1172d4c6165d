"""Are two runs of the study the same? Their cubes, tables, cases and searches compared file
by file (issue 34: a run through SLURM against a local one; the fault tests: a rerun after
a crash against an undisturbed run).

NetCDF files: every variable and coordinate bit-identical (NaN where NaN), their attrs and
the file's equal but for the clock-time ones (:data:`CLOCK`). CSV tables: byte for byte, or
with ``clock_columns`` equal but in the columns named in :data:`CLOCK` (the wall time of a
run, which no two runs share).

    python -m stonedem.study.compare RESULTS_A RESULTS_B     # exit 0: the same; 1: the differences
"""

from __future__ import annotations

import csv
import io
import sys
from pathlib import Path

import numpy as np
import xarray as xr

# attrs (and table columns) that hold the clock time or the machine of a run
CLOCK = ("wall_seconds", "kernel_seconds", "seconds", "created", "date_created", "history", "host", "elapsed",
         "run_seconds")
KINDS = ("cubes", "tables", "cases", "searches", "fragility")


def result_files(directory: Path, kinds=KINDS) -> list[str]:
    """The study's files of ``kinds`` under ``directory``/results (paths relative to directory)."""
    results = Path(directory) / "results"
    found = [p for kind in kinds for p in (results / kind).rglob("*") if p.is_file() and not p.name.startswith(".")]
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


def dataset_differences(path_a: Path, path_b: Path, label: str) -> list[str]:
    """What differs between two NetCDF files, beyond their clock attrs."""
    out = []
    with xr.open_dataset(path_a, decode_times=False) as a, xr.open_dataset(path_b, decode_times=False) as b:
        if set(a.variables) != set(b.variables):
            return [f"{label}: variables {sorted(set(a.variables) ^ set(b.variables))}"]
        if dict(a.sizes) != dict(b.sizes):
            return [f"{label}: sizes {dict(a.sizes)} != {dict(b.sizes)}"]
        for name in a.variables:
            if a[name].dims != b[name].dims or not same_values(a[name].values, b[name].values):
                out.append(f"{label}:{name} differs")
            elif _unclocked(a[name].attrs) != _unclocked(b[name].attrs):
                out.append(f"{label}:{name} attrs differ")
        differ = {k for k in set(_unclocked(a.attrs)) | set(_unclocked(b.attrs))
                  if not same_values(a.attrs.get(k), b.attrs.get(k))}
        if differ:
            out.append(f"{label}: attrs {sorted(differ)} differ")
    return out


def table_differences(path_a: Path, path_b: Path, label: str, clock_columns: bool = False) -> list[str]:
    """What differs between two CSV tables: their bytes, or with ``clock_columns`` their
    cells outside the CLOCK columns."""
    a, b = Path(path_a).read_bytes(), Path(path_b).read_bytes()
    if a == b:
        return []
    if not clock_columns:
        return [f"{label} differs"]
    rows_a = list(csv.DictReader(io.StringIO(a.decode())))
    rows_b = list(csv.DictReader(io.StringIO(b.decode())))
    strip = [{k: v for k, v in row.items() if k not in CLOCK} for row in rows_a]
    if strip != [{k: v for k, v in row.items() if k not in CLOCK} for row in rows_b]:
        return [f"{label} differs outside its clock columns"]
    return []


def result_differences(directory: Path, reference: Path, kinds=KINDS, clock_columns: bool = False) -> list[str]:
    """Everything that differs between two study folders' results (empty: the same)."""
    files = result_files(reference, kinds)
    mine = result_files(directory, kinds)
    if mine != files:
        return [f"files only in one: {sorted(set(mine) ^ set(files))}"]
    out = []
    for rel in files:
        if rel.endswith(".csv"):
            out += table_differences(Path(directory) / rel, Path(reference) / rel, rel, clock_columns)
        elif rel.endswith(".nc"):
            out += dataset_differences(Path(directory) / rel, Path(reference) / rel, rel)
    return out


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 2 or not all((Path(a) / "results").is_dir() for a in args):
        print("usage: python -m stonedem.study.compare STUDY_A STUDY_B (study folders, each holding its results folder)", file=sys.stderr)
        return 2
    differences = result_differences(Path(args[0]), Path(args[1]), clock_columns=True)
    for line in differences:
        print(line)
    n = len(result_files(Path(args[1])))
    print(f"{n} files compared: {'the same' if not differences else f'{len(differences)} differ'}", file=sys.stderr)
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main())
