"""A small copy of the study for the fault-injection suite (issue 31, part 4): the repo's
Snakefile, workflow/, config/, profiles/ and records/ in a folder of its own, with a config of
three tiny studies (two simulated cases, a threshold search of two runs, one ramp case), run
to its cubes and tables only (no figures, walls or validations): ~10-20 s on 2 cores once the
compiled kernels are in the numba cache (~/.cache/stonedem).

``reference()`` is that study run once, uninterrupted, per test process; each fault is
compared with it variable by variable, coordinate by coordinate (``assert_same_results``).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from stonedem.study.compare import dataset_differences, result_differences, result_files

ROOT = Path(__file__).resolve().parents[2]
COPIED = ("Snakefile", "workflow", "config", "profiles", "records")
STUDIES = {
    # two harmonic cases of a 1-drum column, 0.5 s each: one simulate job, one table
    "small_column_friction": {
        "solver": {"duration": 0.5},
        "grid": {"friction": [0.68], "frequency": [2.0, 20.0]},
    },
    # a threshold search of two runs (2 and 8 m/s2, 1 s of the Mexico City stand-in): a search file
    "standalone_records": {
        "solver": {"duration": 1.0},
        "grid": {"record": ["mexico_standin_chichi_tcu102"], "n_drums": [1]},
        "search": {"start": 2.0, "factor": 4.0, "maximum": 8.0, "tolerance": 0.5, "fill": 0},
    },
    # one ramp case of a 1-drum column (thesis Fig. 6.10's table)
    "ramp_drums": {"solver": {"duration": 1.0}, "grid": {"n_drums": [1]}},
}
# the study's cubes and tables (common.smk: rules cubes_<k>, tables_<k>)
CUBES = [f"results/cubes/{study}.nc" for study in STUDIES]
TABLES = [
    "results/tables/frequency_response_small_column_friction.csv",
    "results/tables/thesis_fig_6_10.csv",
]
TARGETS = CUBES + TABLES
RECORD = "records/mexico_standin_chichi_tcu102.nc"


def make_study(directory: Path) -> Path:
    """The workflow in ``directory`` (created) with the small config as config/config.yaml."""
    from stonedem.study.grid import load_config

    directory.mkdir(parents=True, exist_ok=True)
    for item in COPIED:
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, directory / item)
    config = load_config(ROOT / "config" / "config.yaml")
    config["studies"] = {
        name: {**config["studies"][name], **spec} for name, spec in STUDIES.items()
    }
    config.update(wall_cases=[], run_validation=False)
    config.pop("fragility", None)
    (directory / "config" / "config.yaml").write_text(yaml.safe_dump(config, sort_keys=False))
    return directory


def snakemake_command(*args, cores: int = 2) -> list[str]:
    return [sys.executable, "-m", "snakemake", f"-j{cores}", *args, *TARGETS]


def snakemake(
    directory: Path, *args, cores: int = 2, timeout: float = 300
) -> subprocess.CompletedProcess:
    """One snakemake call on the study's cubes and tables, output captured."""
    return subprocess.run(
        snakemake_command(*args, cores=cores),
        cwd=directory,
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def tail(proc, n: int = 3000) -> str:
    return f"exit {proc.returncode}\n--- stdout\n{proc.stdout[-n:]}\n--- stderr\n{proc.stderr[-n:]}"


_REFERENCE: list[Path] = []


def reference(tmp_path_factory) -> Path:
    """The small study run once, uninterrupted (per test process): the folder it ran in."""
    if not _REFERENCE:
        directory = make_study(tmp_path_factory.mktemp("reference") / "study")
        proc = snakemake(directory)
        assert proc.returncode == 0, tail(proc)
        assert all((directory / t).is_file() for t in TARGETS), result_files(directory)
        _REFERENCE.append(directory)
    return _REFERENCE[0]


def copy_study(source: Path, directory: Path) -> Path:
    """A copy of a finished study (results, .snakemake metadata, mtimes kept)."""
    shutil.copytree(source, directory, symlinks=True)
    return directory


def assert_same_dataset(path_a: Path, path_b: Path, label: str) -> None:
    """Every variable and coordinate bit-identical (NaN where NaN), their attrs and the
    file's attrs equal but for the clock-time ones."""
    differences = dataset_differences(path_a, path_b, label)
    assert not differences, differences


def assert_same_results(directory: Path, ref: Path) -> None:
    """The study in ``directory`` holds the reference's cubes, tables, cases and searches,
    bit-identical: the CSV tables byte for byte, the NetCDF files by variable."""
    differences = result_differences(directory, ref)
    assert not differences, differences


def truncate(path: Path, size: int | None = None) -> None:
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2 if size is None else size])


def stonedem_command(*args) -> list[str]:
    return [sys.executable, "-m", "stonedem", *args]


def child_env() -> dict:
    return {**os.environ, "PYTHONUNBUFFERED": "1"}


# --- a read-only folder for root: root ignores permission bits through three capabilities ----
PR_CAPBSET_DROP = 24
FILE_POWERS = (1, 2, 3)  # CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH, CAP_FOWNER


def as_plain_owner() -> None:
    """preexec_fn: drop root's file-permission capabilities from the bounding set, so the
    program run next (and everything it starts) obeys permission bits like any owner."""
    import ctypes

    if os.geteuid() != 0:
        return
    libc = ctypes.CDLL(None, use_errno=True)
    for cap in FILE_POWERS:
        if libc.prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) refused")


def read_only_works(folder: Path) -> bool:
    """Whether a child started with ``as_plain_owner`` is refused a new file in ``folder``
    (chmod 0o555 already applied)."""
    try:
        proc = subprocess.run(
            [sys.executable, "-c", f"open({str(folder / 'probe')!r}, 'w')"],
            preexec_fn=as_plain_owner,
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
    except (OSError, subprocess.SubprocessError):
        return False
    (folder / "probe").unlink(missing_ok=True)
    return proc.returncode != 0 and "PermissionError" in proc.stderr


@contextlib.contextmanager
def read_only(folder: Path):
    """``folder`` at mode 0o555 within (the test is skipped where no child can be refused a
    write there), 0o755 again after."""
    folder.chmod(0o555)
    try:
        if not read_only_works(folder):
            pytest.skip(
                "cannot make a read-only folder here (root without a way to drop CAP_DAC_OVERRIDE)"
            )
        yield folder
    finally:
        folder.chmod(0o755)


def descendants(pid: int) -> list[int]:
    """The process ids below ``pid`` (children, their children...), from /proc."""
    found, queue = [], [pid]
    while queue:
        parent = queue.pop()
        try:
            tasks = os.listdir(f"/proc/{parent}/task")
        except OSError:
            continue
        for task in tasks:
            try:
                children = Path(f"/proc/{parent}/task/{task}/children").read_text().split()
            except OSError:
                continue
            for child in map(int, children):
                if child not in found:
                    found.append(child)
                    queue.append(child)
    return found


def same_data(a, b):
    """Every variable and coordinate equal, NaN where NaN (attrs hold the run's clock time)."""
    assert set(a.variables) == set(b.variables)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        assert x.shape == y.shape and (
            np.array_equal(x, y, equal_nan=True) if x.dtype.kind in "fc" else np.array_equal(x, y)
        ), name


def no_partial_files(directory):
    """Whatever is under a result's own name is a whole dataset (temporaries start with '.')."""
    import xarray as xr

    for rel in result_files(directory):
        if rel.endswith(".nc"):
            with xr.open_dataset(directory / rel) as ds:
                assert len(ds.variables) > 0, rel
                if rel.startswith("results/cases/"):  # a whole simulation, not its first samples
                    assert "collapsed" in ds and ds.sizes["time"] > 1, rel
