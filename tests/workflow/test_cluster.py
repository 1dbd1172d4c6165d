"""A SLURM profile that could not see its jobs finish is refused in one line
(stonedem.study.cluster)."""

import subprocess

import pytest

from stonedem.study.cluster import (
    check_executor,
    min_job_age,
    scontrol_config,
    slurm_settings_problem,
)

NO_ACCOUNTING = {"AccountingStorageType": "accounting_storage/none", "MinJobAge": "300 sec"}
ACCOUNTING = {"AccountingStorageType": "accounting_storage/slurmdbd", "MinJobAge": "300 sec"}


@pytest.mark.parametrize(
    "command, init, config, setting",
    [
        ("sacct", 40, NO_ACCOUNTING, "slurm-status-command: squeue"),
        (None, 40, NO_ACCOUNTING, "slurm-status-command: squeue"),  # the executor's default: sacct
        ("squeue", 150, NO_ACCOUNTING, "slurm-init-seconds-before-status-checks: 100"),
        (
            "squeue",
            None,
            {**NO_ACCOUNTING, "MinJobAge": "60 sec"},
            "slurm-init-seconds-before-status-checks: 20",
        ),
        ("squeue", 20, {"AccountingStorageType": "accounting_storage/none"}, "MinJobAge"),
    ],
)
def test_settings_that_would_wait_for_ever_name_the_setting(command, init, config, setting):
    problem = slurm_settings_problem(command, init, config)
    assert problem and setting in problem and "\n" not in problem


@pytest.mark.parametrize(
    "command, init, config",
    [
        ("squeue", 20, NO_ACCOUNTING),
        ("squeue", 100, NO_ACCOUNTING),
        ("sacct", 40, ACCOUNTING),
        (None, 40, ACCOUNTING),
        ("squeue", 40, ACCOUNTING),
        ("sacct", 40, {}),
    ],
)
def test_settings_that_see_jobs_finish_pass(command, init, config):
    assert slurm_settings_problem(command, init, config) is None


def test_scontrol_output_is_read_and_a_missing_scontrol_is_no_answer():
    text = (
        "Configuration data as of 2026-11-27T01:00:00\nAccountingStorageType   = "
        "accounting_storage/none\n"
        "MinJobAge               = 600 sec\n"
    )

    def run(*args, **kwargs):
        return subprocess.CompletedProcess(args, 0, stdout=text, stderr="")

    def missing(*args, **kwargs):
        raise FileNotFoundError("scontrol")

    config = scontrol_config(run)
    assert (
        config["AccountingStorageType"] == "accounting_storage/none" and min_job_age(config) == 600
    )
    assert scontrol_config(missing) == {}


def test_a_slurm_run_with_a_bad_setting_ends_before_its_first_job(monkeypatch, capsys):
    from types import SimpleNamespace

    from stonedem.study import cluster

    monkeypatch.setattr(cluster, "scontrol_config", lambda: NO_ACCOUNTING)
    workflow = SimpleNamespace(
        executor_plugin=SimpleNamespace(name="slurm"),
        executor_settings=SimpleNamespace(
            status_command="sacct", init_seconds_before_status_checks=40
        ),
    )
    with pytest.raises(SystemExit) as stop:
        check_executor(workflow)
    assert stop.value.code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Bad cluster setting:")
    check_executor(
        SimpleNamespace(executor_plugin=SimpleNamespace(name="local"))
    )  # not SLURM: nothing to say


@pytest.mark.skipif(
    not hasattr(__import__("os"), "geteuid")
    or __import__("os").geteuid() != 0
    or __import__("shutil").which("runuser") is None,
    reason="needs root and runuser to act as nobody",
)
def test_the_local_cluster_script_says_in_one_line_why_it_cannot_start():
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "workflow" / "cluster" / "start-local-slurm.sh"
    done = subprocess.run(
        ["runuser", "-u", "nobody", "--", "bash", str(script)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert done.returncode == 3
    assert (
        done.stderr.strip()
        == "local SLURM not started: not root (it installs packages and starts daemons)"
    )
