"""The SLURM profile where SLURM is missing or stops answering (issue 43, item 1). Before, the
documented command waited for ever on a machine without SLURM (the executor's submission
thread died on a missing sacct), and a squeue that stopped answering was retried for ever.
Each case runs the small study's workflow with ``--profile config/profiles/slurm``; a fake
SLURM is a folder of stub scripts first on PATH."""

import os
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.faults.small_study import TARGETS, make_study, tail

PROFILE = ("--profile", "config/profiles/slurm")


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    return make_study(tmp_path_factory.mktemp("cluster") / "study")


def bare_path(folder: Path) -> str:
    """A PATH with this Python and a shell, and no SLURM even where the machine has one."""
    folder.mkdir(exist_ok=True)
    for tool in ("sh", "bash", "env", "which", "uname", "cat", "rm", "sleep"):
        found = subprocess.run(
            ["sh", "-c", f"command -v {tool}"], capture_output=True, text=True
        ).stdout.strip()
        if found and not (folder / tool).exists():
            (folder / tool).symlink_to(found)
    return f"{Path(sys.executable).parent}{os.pathsep}{folder}"


def run(study, args, path, timeout=120, **env):
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "snakemake", *PROFILE, *args, *TARGETS],
        cwd=study,
        env={**os.environ, "PATH": path, **env},
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    return proc, time.monotonic() - start


def test_the_slurm_profile_without_slurm_refuses_in_one_line(study, tmp_path):
    path = bare_path(tmp_path / "bin")
    proc, seconds = run(study, [], path)
    assert proc.returncode == 2, tail(proc)
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith(
        "Cannot use SLURM here: sbatch, squeue, sacct, sinfo, scontrol not found on PATH"
    ), tail(proc)
    assert (
        "Submitted" not in proc.stdout + proc.stderr and not (study / "results" / "cubes").exists()
    )
    assert seconds < 60
    # a dry run needs no cluster: it plans and ends
    proc, seconds = run(study, ["-n"], path)
    assert proc.returncode == 0 and "dry-run" in proc.stdout + proc.stderr, tail(proc)


STUB = {
    "sinfo": 'echo "local*"',
    "scontrol": 'case "$*" in "show config") printf "AccountingStorageType   = '
    "accounting_storage/none\\n"
    'MinJobAge               = 600 sec\\nMaxArraySize            = 1001\\n";; esac',
    "sacct": 'echo "sacct: error: Slurm accounting storage is disabled" >&2; exit 1',
    "sbatch": 'n=$(cat "$0.n" 2>/dev/null || echo 100); echo $((n + 1)) > "$0.n"; echo $((n + 1))',
    # answers the pre-flight's probe (no --states), then stops answering the executor's queries
    "squeue": 'case "$*" in *--states=all*) {then};; *) exit 0;; esac',
}
STOPS = {"hangs": "exec sleep 600", "disappears": 'rm -f "$0"; exit 127'}


def fake_slurm(folder: Path, then: str) -> None:
    folder.mkdir()
    for tool, body in STUB.items():
        script = folder / tool
        script.write_text("#!/bin/sh\n" + body.replace("{then}", then) + "\n")
        script.chmod(script.stat().st_mode | stat.S_IXUSR)


@pytest.mark.parametrize("stop", list(STOPS))
def test_a_slurm_that_stops_answering_ends_the_run(study, tmp_path, stop):
    fake_slurm(tmp_path / "slurm", STOPS[stop])
    path = f"{tmp_path / 'slurm'}{os.pathsep}{bare_path(tmp_path / 'bin')}"
    proc, seconds = run(
        study,
        ["--slurm-init-seconds-before-status-checks", "1"],
        path,
        STONEDEM_SLURM_QUERY_SECONDS="2",
        STONEDEM_SLURM_SILENT_SECONDS="4",
    )
    out = proc.stdout + proc.stderr
    assert proc.returncode == 1, tail(proc)
    assert "has been submitted with SLURM jobid 101" in out, tail(proc)
    assert "SLURM stopped answering: `squeue` has not reported the jobs' states for" in out, tail(
        proc
    )
    assert ("no answer within 2 s" if stop == "hangs" else "No such file") in out, tail(proc)
    assert seconds < 90, seconds
