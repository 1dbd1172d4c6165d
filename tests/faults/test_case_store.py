"""Faults around the case store and the files the workflow reads (issue 31, part 1): a
truncated or zero-byte result, a corrupted store entry. Each ends in recovery or one clear
line, and what is recovered is identical to an uninterrupted run."""

import io

import pytest

from stonedem.errors import InputError
from stonedem.io.netcdf import open_result
from stonedem.study.cube import combine_cases
from stonedem.study.grid import case_table
from stonedem.study.runner import CaseStore, run_cases
from tests.faults.small_study import same_data

# a 1 x 4 m block under a 2 Hz harmonic, two amplitudes (the second overturns)
BLOCK = {
    "structure": {"kind": "column", "n_drums": 1, "height": 4.0, "width": 1.0},
    "friction": 0.7,
    "excitation": {"kind": "harmonic", "frequency": 2.0},
    "solver": {"duration": 1.0},
    "contact": {"model": "point", "k_n": 1.0e9},
    "output": {"every": 0.01},
    "grid": {"amplitude": [0.01, 0.4]},
}


@pytest.fixture
def study(tmp_path):
    cases = case_table("block", BLOCK)
    outputs = [tmp_path / "cases" / f"{c.id}.nc" for c in cases]
    store = CaseStore(tmp_path / "store", "records")
    run_cases(cases, outputs, store, io.StringIO())
    return cases, outputs, store, combine_cases(outputs)


def truncate(path, size=None):
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2 if size is None else size])


def test_a_result_is_never_the_store_entry(study):
    cases, outputs, store, _ = study
    entries = sorted(store.directory.glob("*.nc"))
    assert len(entries) == 2 and all(e.with_suffix(".sha256").is_file() for e in entries)
    for output in outputs:
        assert output.stat().st_nlink == 1 and all(not output.samefile(e) for e in entries)


@pytest.mark.parametrize("size", [None, 0])
def test_a_truncated_result_heals_from_the_store(study, size):
    cases, outputs, store, cube = study
    truncate(outputs[0], size)
    # the job that reads it refuses in one line and removes it (snakemake then remakes it)
    with pytest.raises(InputError, match="unreadable, removed.*run snakemake again"):
        combine_cases(outputs)
    assert not outputs[0].exists()
    log = io.StringIO()
    info = run_cases(cases[:1], outputs[:1], store, log)
    assert info[0]["restored"] and "warning" not in log.getvalue(), "the store was not touched"
    same_data(combine_cases(outputs), cube)


def test_a_corrupted_store_entry_is_moved_aside_and_the_case_recomputed(study):
    cases, outputs, store, cube = study
    entry = store.directory / f"{store.key(cases[1])}.nc"
    data = bytearray(entry.read_bytes())
    data[len(data) // 2] ^= 0xFF  # one flipped byte: still a readable file, maybe
    entry.write_bytes(bytes(data))
    outputs[1].unlink()
    log = io.StringIO()
    info = run_cases(cases[1:], outputs[1:], store, log)
    lines = log.getvalue().splitlines()
    assert not info[0]["restored"] and len(lines) == 2
    assert lines[0].startswith("warning: case store entry") and "failed its checksum" in lines[0]
    assert (store.directory / "corrupt" / entry.name).is_file()
    same_data(combine_cases(outputs), cube)
    # the recomputed case is a good entry again
    assert run_cases(cases[1:], outputs[1:], store, io.StringIO())[0]["restored"]


def test_an_entry_without_its_checksum_is_not_trusted(study):
    cases, outputs, store, _ = study
    store.key(cases[0])
    (store.directory / f"{store.key(cases[0])}.sha256").unlink()
    outputs[0].unlink()
    assert not run_cases(cases[:1], outputs[:1], store, io.StringIO())[0]["restored"]


def test_open_result_names_a_missing_file(tmp_path):
    with pytest.raises(InputError, match="result file not found"):
        open_result(tmp_path / "nope.nc")
