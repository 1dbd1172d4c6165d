"""Interrupts around a whole Snakemake study (issue 31, part 4): SIGKILL at random points, three
times in a row, and two snakemake processes in one folder at once. Each ends in recovery or in
one clear refusal, and the healed study is bit-identical to an uninterrupted run
(tests/faults/small_study.py). Apart from tests/faults/test_study_faults.py only so that
pytest-xdist (--dist loadfile) runs the two files on different workers: together they were
~480 s of one worker's ~650 s.
"""

import os
import random
import shutil
import signal
import subprocess
import time

import pytest

from tests.faults.small_study import (
    assert_same_results,
    descendants,
    make_study,
    no_partial_files,
    reference,
    snakemake,
    snakemake_command,
    tail,
)


@pytest.fixture(scope="module")
def ref(tmp_path_factory):
    return reference(tmp_path_factory)


# --- 4. SIGKILL at random points, three times in a row -----------------------------------------


def locks(study):
    folder = study / ".snakemake" / "locks"
    return sorted(p.name for p in folder.iterdir()) if folder.is_dir() else []


def kill_run_after(study, seconds):
    """Start the study and SIGKILL its process group (and every process below it) ``seconds``
    after it has locked the folder, that is while its jobs run (building the DAG takes ~3 s)."""
    run = subprocess.Popen(
        snakemake_command(),
        cwd=study,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and run.poll() is None and not locks(study):
        time.sleep(0.02)
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and run.poll() is None:
        time.sleep(0.02)
    below = descendants(run.pid)
    try:
        os.killpg(run.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    for pid in below:  # a job in a session of its own would outlive the group
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return run.wait(timeout=60)


@pytest.mark.slow
def test_three_sigkills_at_random_points_then_unlock_and_rerun_is_identical(ref, tmp_path):
    study = make_study(tmp_path / "study")
    rng = random.Random(287)  # kills 3.78, 2.57 and 1.59 s after the lock
    in_a_run = 0
    for k in range(3):
        if k:  # what a user does after a hard kill (README): --unlock once, then the same command
            unlock = snakemake(study, "--unlock")
            assert unlock.returncode == 0, tail(unlock)
        status = kill_run_after(study, rng.uniform(1.0, 6.0))
        no_partial_files(study)
        if locks(study):  # the kill came while the jobs ran: the lock stays behind
            in_a_run += 1
        # the run had finished (or was cleaning up): start over so that the next kill lands in a run
        else:
            assert status in (0, -signal.SIGKILL)
            shutil.rmtree(study / "results")
    assert in_a_run >= 2, f"only {in_a_run} of the 3 kills came while jobs ran"
    # the same command at once: it runs, or it refuses in words that say what to do
    proc = snakemake(study)
    if proc.returncode != 0:
        assert (
            "--unlock" in proc.stdout + proc.stderr and "Traceback" not in proc.stdout + proc.stderr
        ), tail(proc)
        assert snakemake(study, "--unlock").returncode == 0
        proc = snakemake(study)
    assert proc.returncode == 0, tail(proc)
    assert_same_results(study, ref)


# --- 5. two snakemake processes in the same folder at once -------------------------------------


@pytest.mark.slow
def test_two_snakemake_calls_at_once_one_refuses_or_both_succeed(ref, tmp_path):
    study = make_study(tmp_path / "study")
    runs = [
        subprocess.Popen(
            snakemake_command(),
            cwd=study,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    outs = [run.communicate(timeout=300) for run in runs]
    done = [
        subprocess.CompletedProcess(run.args, run.returncode, out, err)
        for run, (out, err) in zip(runs, outs)
    ]
    codes = sorted(proc.returncode for proc in done)
    assert codes[0] == 0, "\n".join(tail(proc) for proc in done)
    for proc in done:
        if proc.returncode != 0:  # Snakemake's lock: one paragraph, no traceback
            out = proc.stdout + proc.stderr
            assert "LockException" in out or "cannot be locked" in out, tail(proc)
            assert "Traceback" not in out, tail(proc)
    # the refused call left no lock behind, and the study is complete and identical
    again = snakemake(study)
    assert again.returncode == 0 and "Nothing to be done" in again.stdout + again.stderr, tail(
        again
    )
    assert_same_results(study, ref)
