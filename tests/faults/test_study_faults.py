"""Faults around a whole Snakemake study (issue 31, part 4): a truncated or zero-byte result,
a full disk, a read-only results/, a study path with spaces and accents, a corrupted record
(SIGKILL at random points and two snakemake processes at once: test_study_interrupts.py, a
file of their own so that pytest-xdist's --dist loadfile gives them the other worker). Each ends in
recovery or in one clear line (``error: ...`` or ``Bad config: ...``, a non-zero exit, no traceback
in the output or in a job's log), and the healed study's cases, searches, cubes and tables are
bit-identical to an uninterrupted run (tests/faults/small_study.py: three tiny studies,
~10-20 s a run on 2 cores).

What a user does after a hard kill (kill -9, power loss): ``python3 -m snakemake --unlock``
once, then the same command; the jobs the kill cut off are rerun because
profiles/default/config.yaml sets ``rerun-incomplete``.
"""

import random
import resource
import shutil
import signal
import subprocess

import pytest

from tests.faults.small_study import (
    RECORD,
    ROOT,
    as_plain_owner,
    assert_same_results,
    copy_study,
    make_study,
    read_only,
    reference,
    result_files,
    snakemake,
    snakemake_command,
    tail,
    truncate,
)

SEARCH = "results/searches/standalone_records/rec-mexico_standin_chichi_tcu102_drums-1.nc"
CASE = "results/cases/small_column_friction/mu-0.68_f-2.nc"


@pytest.fixture(scope="module")
def ref(tmp_path_factory):
    return reference(tmp_path_factory)


def job_logs(directory):
    logs = directory / "results" / "logs"
    return (
        {p: p.read_text(errors="replace") for p in sorted(logs.rglob("*.log"))}
        if logs.is_dir()
        else {}
    )


def assert_clear_failure(proc, directory, *names):
    """A non-zero exit; a line ``error: ...`` (a job's bad input, stonedem.entry) or ``Bad
    config: ...`` (the DAG-time check) on snakemake's output naming every one of ``names``;
    no Python traceback on the output nor in any job's log."""
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0, tail(proc)
    lines = [
        line.strip()
        for line in out.splitlines()
        if line.strip().startswith(("error: ", "Bad config: "))
    ]
    assert any(all(name in line for name in names) for line in lines), (
        f"no one-line error naming {names} on snakemake's output:\n{tail(proc)}"
    )
    assert "Traceback" not in out, tail(proc)
    for path, text in job_logs(directory).items():
        assert "Traceback" not in text, (
            f"a traceback in {path.relative_to(directory)}:\n{text[-2500:]}"
        )


# --- 1. a truncated or zero-byte cube, search or case file ------------------------------------


@pytest.mark.parametrize(
    "target, size",
    [
        ("results/cubes/ramp_drums.nc", None),
        (SEARCH, 0),
        pytest.param(CASE, None, marks=pytest.mark.slow),
    ],
    ids=["truncated-cube", "zero-byte-search", "truncated-case"],
)
def test_a_truncated_result_is_remade_by_the_next_call(ref, tmp_path, target, size):
    study = copy_study(ref, tmp_path / "study")
    truncate(study / target, size)
    first = snakemake(study)
    # the job that reads it refuses in one line and removes it; the next call makes it again
    second = snakemake(study) if first.returncode != 0 else first
    assert second.returncode == 0, tail(second)
    assert_same_results(study, ref)
    if first.returncode != 0:
        assert_clear_failure(first, study, target, "unreadable")


# --- 2. a full disk while writing (RLIMIT_FSIZE, SIGXFSZ ignored: write(2) fails with EFBIG) ---

LIMIT = 32 * 1024  # bytes: below every result file, above Snakemake's own files


def limited(n):
    def preexec():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (n, n))

    return preexec


def run_limited(study, n=LIMIT):
    return subprocess.run(
        snakemake_command(),
        cwd=study,
        capture_output=True,
        text=True,
        timeout=300,
        preexec_fn=limited(n),
        check=False,
    )


def test_a_full_disk_fails_the_jobs_in_one_line_and_a_rerun_is_identical(ref, tmp_path):
    study = make_study(tmp_path / "study")
    proc = run_limited(study)
    # each job's first case names its file and the cause; nothing under a final name
    assert_clear_failure(proc, study, CASE, "cannot write")
    assert not any(rel.endswith(".nc") for rel in result_files(study)), result_files(study)
    strays = [p.name for p in (study / "results").rglob(".*.tmp*")]
    assert not strays, f"temporary files left behind: {strays}"
    proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)


def test_a_full_disk_does_not_condemn_good_store_entries(ref, tmp_path):
    study = copy_study(ref, tmp_path / "study")
    # the job's cases and its cube gone (a missing case alone is not remade: its cube is up to date)
    for path in [
        *(study / "results/cases/small_column_friction").glob("*.nc"),
        study / "results/cubes/small_column_friction.nc",
    ]:
        path.unlink()
    proc = run_limited(study)
    assert_clear_failure(proc, study, CASE, "cannot write")
    assert not (study / CASE).exists()
    proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)
    # a copy that failed for want of space is no checksum failure: the entries stay in the store
    # and the rerun restores both cases (the reference made them with the same sources)
    corrupt = study / "results/case_store/corrupt"
    moved = sorted(p.name for p in corrupt.iterdir()) if corrupt.is_dir() else []
    assert not moved, f"good store entries moved aside by a full disk: {moved}"
    log = (study / "results/logs/jobs/simulate_small_column_friction_0.log").read_text()
    assert log.count("restored from the case store") == 2, log


# --- 3. a read-only results/; a study path with spaces and accents ---------------------------


def test_a_read_only_results_folder_fails_clearly_and_a_rerun_is_identical(ref, tmp_path):
    study = make_study(tmp_path / "study")
    results = study / "results"
    results.mkdir()
    with read_only(results):
        proc = subprocess.run(
            snakemake_command(),
            cwd=study,
            capture_output=True,
            text=True,
            timeout=300,
            preexec_fn=as_plain_owner,
            check=False,
        )
    # Snakemake's own words (it makes the output folders) or the workflow's: one line naming
    # the folder and the cause, a non-zero exit, no traceback
    out = proc.stdout + proc.stderr
    assert proc.returncode != 0 and "Traceback" not in out, tail(proc)
    assert any(
        "results" in line and ("Permission denied" in line or "not writable" in line)
        for line in out.splitlines()
    ), tail(proc)
    assert not result_files(study)
    proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)


def test_a_study_path_with_spaces_and_accents(ref, tmp_path):
    study = make_study(tmp_path / "my study é ü" / "çà et là")
    proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)


# --- 6. a corrupted record file in records/ ----------------------------------------------------


def garble(path):
    data = path.read_bytes()
    path.write_bytes(random.Random(6).randbytes(len(data)))


@pytest.mark.parametrize("corrupt", [truncate, garble], ids=["truncated", "garbage"])
def test_a_corrupted_record_is_named_in_one_line_and_a_restored_one_reruns_identical(
    ref, tmp_path, corrupt
):
    study = copy_study(ref, tmp_path / "study")
    corrupt(study / RECORD)
    proc = snakemake(study)
    assert_clear_failure(proc, study, "mexico_standin_chichi_tcu102", "not a readable NetCDF file")
    shutil.copy(ROOT / RECORD, study / RECORD)  # restored, with a new mtime: its jobs rerun
    proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)
