"""A read-only case store with a damaged entry (issue 43, item 2): the entry is skipped with one
warning line, the case is simulated into its output, and nothing in the store is written,
moved or deleted. Before, quarantine fell back to deleting the entry and the job died with
``OSError: Read-only file system``."""

import builtins
import errno
import io
import os
import subprocess
import sys
import textwrap

import pytest

from stonedem.study.cube import combine_cases
from stonedem.study.grid import case_table
from stonedem.study.runner import CaseStore, run_cases, source_fingerprint
from tests.faults.small_study import as_plain_owner, read_only, same_data

# a 1 x 4 m block under a 2 Hz harmonic for 0.5 s: one cheap case
BLOCK = {
    "structure": {"kind": "column", "n_drums": 1, "height": 4.0, "width": 1.0},
    "friction": 0.7,
    "excitation": {"kind": "harmonic", "frequency": 2.0},
    "solver": {"duration": 0.5},
    "contact": {"model": "point", "k_n": 1.0e9},
    "output": {"every": 0.01},
    "grid": {"amplitude": [0.2]},
}


@pytest.fixture
def damaged(tmp_path):
    """A store holding the case's entry without its checksum file, and the case's good result."""
    cases = case_table("block", BLOCK)
    output = tmp_path / "cases" / f"{cases[0].id}.nc"
    store = CaseStore(tmp_path / "store", "records")
    run_cases(cases, [output], store, io.StringIO())
    entry = store.directory / f"{store.key(cases[0])}.nc"
    entry.with_suffix(".sha256").unlink()
    good = tmp_path / "good.nc"
    output.replace(good)
    return cases, output, store, entry, good


def store_snapshot(store):
    return sorted(
        (p.relative_to(store.directory), p.stat().st_size) for p in store.directory.rglob("*")
    )


def refuse_writes_under(monkeypatch, folder):
    """Every call that would change ``folder`` fails with EROFS, as on a read-only mount (root
    ignores chmod, so this is how the suite makes a store read-only for root)."""
    folder = str(folder)

    def inside(*paths):
        return any(os.path.abspath(os.fspath(p)).startswith(folder) for p in paths)

    def refusing(real, n_paths=1):
        def call(*args, **kwargs):
            if inside(*args[:n_paths]):
                raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(args[0]))
            return real(*args, **kwargs)

        return call

    real_open = builtins.open

    def open_(file, mode="r", *args, **kwargs):
        if isinstance(file, (str, os.PathLike)) and set(mode) & set("wax+") and inside(file):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(file))
        return real_open(file, mode, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", open_)
    monkeypatch.setattr(io, "open", open_)
    for name in ("unlink", "remove", "rmdir", "mkdir"):
        monkeypatch.setattr(os, name, refusing(getattr(os, name)))
    for name in ("replace", "rename"):
        monkeypatch.setattr(os, name, refusing(getattr(os, name), 2))


def test_a_read_only_store_skips_a_damaged_entry_and_simulates_the_case(damaged, monkeypatch):
    cases, output, store, entry, good = damaged
    before = store_snapshot(store)
    refuse_writes_under(monkeypatch, store.directory)
    log = io.StringIO()
    info = run_cases(cases, [output], store, log)
    monkeypatch.undo()
    lines = log.getvalue().splitlines()
    assert not info[0]["restored"] and len(lines) == 2, lines
    assert lines[0] == (
        f"warning: case store entry {entry.name} failed its checksum; left in place "
        f"(Read-only file system), skipped, simulating the case again"
    )
    assert store_snapshot(store) == before and not (store.directory / "corrupt").exists()
    same_data(combine_cases([output]), combine_cases([good]))


def test_a_writable_store_still_moves_a_damaged_entry_aside(damaged):
    cases, output, store, entry, _ = damaged
    log = io.StringIO()
    run_cases(cases, [output], store, log)
    assert f"moved to {store.directory / 'corrupt'}" in log.getvalue().splitlines()[0]
    assert (store.directory / "corrupt" / entry.name).is_file()


def test_a_chmod_read_only_store_in_a_child_process(damaged):
    cases, output, store, entry, good = damaged
    before = store_snapshot(store)
    script = textwrap.dedent(f"""
        import io, sys
        from stonedem.study.grid import case_table
        from stonedem.study.runner import _SOURCE_FINGERPRINT, CaseStore, run_cases
        # the parent's key, even if a source changed since
        _SOURCE_FINGERPRINT[:] = [{source_fingerprint()!r}]
        cases = case_table("block", {BLOCK!r})
        store = CaseStore({str(store.directory)!r}, "records")
        info = run_cases(cases, [{str(output)!r}], store, sys.stderr)
        sys.exit(0 if not info[0]["restored"] else 3)
    """)
    with read_only(store.directory):
        proc = subprocess.run(
            [sys.executable, "-c", script],
            preexec_fn=as_plain_owner,
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
    assert proc.returncode == 0, proc.stderr[-2000:]
    warning = [line for line in proc.stderr.splitlines() if line.startswith("warning:")]
    assert warning == [
        f"warning: case store entry {entry.name} failed its checksum; left in place "
        f"(Permission denied), skipped, simulating the case again"
    ], proc.stderr[-2000:]
    assert store_snapshot(store) == before
    same_data(combine_cases([output]), combine_cases([good]))
