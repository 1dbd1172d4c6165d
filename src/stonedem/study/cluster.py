"""What Snakemake's SLURM executor needs of a cluster, checked before the first job is
submitted (issue 34).

The executor asks ``sacct`` for its jobs' states wherever ``sacct`` is installed. On a cluster
without an accounting database (``AccountingStorageType=accounting_storage/none``) sacct
answers only "accounting storage is disabled", and the run waits for ever. ``squeue`` works
there, for as long as SLURM keeps a finished job in view (``MinJobAge``); when MinJobAge is
under three times the delay before the first status check, the executor goes back to sacct
without a word. :func:`slurm_settings_problem` names the setting to change instead.
"""

from __future__ import annotations

import subprocess
import sys

DEFAULT_INIT_SECONDS = 40  # the executor's slurm-init-seconds-before-status-checks


def scontrol_config(run=subprocess.run) -> dict[str, str]:
    """``scontrol show config`` as {key: value}; empty when scontrol cannot answer."""
    try:
        done = run(["scontrol", "show", "config"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return {}
    out = {}
    for line in done.stdout.splitlines():
        key, sep, value = line.partition("=")
        if sep:
            out[key.strip()] = value.strip()
    return out


def min_job_age(config: dict[str, str]) -> int | None:
    """MinJobAge [s] (``300 sec`` in scontrol's words), None when not given."""
    words = config.get("MinJobAge", "").split()
    return int(words[0]) if words and words[0].isdigit() else None


def slurm_settings_problem(status_command: str | None, init_seconds: int | None, config: dict[str, str]) -> str | None:
    """One line naming the profile setting that would leave the run waiting for ever, or None."""
    if not config:
        return None  # scontrol cannot answer: the executor's own checks apply
    if config.get("AccountingStorageType", "") not in ("", "accounting_storage/none"):
        return None  # sacct has a database to ask
    if status_command != "squeue":
        return ("this SLURM cluster keeps no accounting (AccountingStorageType=accounting_storage/none), so sacct "
                "cannot report the jobs and the run would wait for ever; set slurm-status-command: squeue "
                "in the profile (config/profiles/slurm/config.yaml)")
    init = DEFAULT_INIT_SECONDS if init_seconds is None else init_seconds
    age = min_job_age(config)
    if age is None or age < 3 * init:
        return (f"MinJobAge={age} s on this cluster is under 3 x slurm-init-seconds-before-status-checks "
                f"({init} s), so the executor would fall back to sacct, which keeps no accounting here, and wait "
                f"for ever; set slurm-init-seconds-before-status-checks: {max(1, (age or 0) // 3)} or less in the "
                f"profile, or raise MinJobAge in slurm.conf")
    return None


def check_executor(workflow) -> None:
    """Snakemake onstart: end a SLURM run in one line (exit 2) before its first job when its
    settings cannot see the jobs finish."""
    plugin = getattr(workflow, "executor_plugin", None)
    if plugin is None or getattr(plugin, "name", "") != "slurm":
        return
    settings = getattr(workflow, "executor_settings", None)
    problem = slurm_settings_problem(getattr(settings, "status_command", None),
                                     getattr(settings, "init_seconds_before_status_checks", None), scontrol_config())
    if problem:
        print(f"Bad cluster setting: {problem}", file=sys.stderr)
        sys.exit(2)
