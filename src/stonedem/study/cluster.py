"""What Snakemake's SLURM executor needs of a cluster, checked before the first job is
submitted (issue 34).

The executor asks ``sacct`` for its jobs' states wherever ``sacct`` is installed. On a cluster
without an accounting database (``AccountingStorageType=accounting_storage/none``) sacct
answers only "accounting storage is disabled", and the run waits for ever. ``squeue`` works
there, for as long as SLURM keeps a finished job in view (``MinJobAge``); when MinJobAge is
under three times the delay before the first status check, the executor goes back to sacct
without a word. :func:`slurm_settings_problem` names the setting to change instead.

Issue 43: the executor (snakemake-executor-plugin-slurm 2.8.0, pinned) calls sbatch, squeue,
sacct (to guess an account), sinfo (the default partition) and scontrol; where one is missing
its submission thread dies and the run waits for ever for a job never sent.
:func:`slurm_tools_problem` refuses such a machine before the first job. Once jobs run, a
squeue or sacct that stops answering was retried for ever: :func:`bound_status_checks` gives
each status query :data:`QUERY_SECONDS` and ends the run once queries have failed for
:data:`SILENT_SECONDS` without an answer between.
"""

from __future__ import annotations

import asyncio
import csv
import io
import os
import shlex
import shutil
import subprocess
import sys
import time

DEFAULT_INIT_SECONDS = 40  # the executor's slurm-init-seconds-before-status-checks
PROBE_SECONDS = 10  # a SLURM command that has not answered by then is taken as not answering
# the SLURM commands the executor runs with the project's profile (no account, no partition)
TOOLS = ("sbatch", "squeue", "sacct", "sinfo", "scontrol")
# a status query's time limit, and how long no query may answer before the run ends
# (environment variables of the same name override them: the fault suite's stub SLURM)
QUERY_SECONDS = 60
SILENT_SECONDS = 900
RETRY_SECONDS = 10  # between failed status queries


def scontrol_config(run=subprocess.run) -> dict[str, str]:
    """``scontrol show config`` as {key: value}; empty when scontrol cannot answer."""
    try:
        done = run(
            ["scontrol", "show", "config"], capture_output=True, text=True, timeout=PROBE_SECONDS
        )
    except (OSError, subprocess.SubprocessError):
        return {}
    if done.returncode != 0:
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


def slurm_settings_problem(
    status_command: str | None, init_seconds: int | None, config: dict[str, str]
) -> str | None:
    """One line naming the profile setting that would leave the run waiting for ever, or None."""
    if not config:
        return None  # scontrol cannot answer: the executor's own checks apply
    if config.get("AccountingStorageType", "") not in ("", "accounting_storage/none"):
        return None  # sacct has a database to ask
    if status_command != "squeue":
        return (
            "this SLURM cluster keeps no accounting "
            "(AccountingStorageType=accounting_storage/none), so sacct "
            "cannot report the jobs and the run would wait for ever; set slurm-status-command: "
            "squeue "
            "in the profile (config/profiles/slurm/config.yaml)"
        )
    init = DEFAULT_INIT_SECONDS if init_seconds is None else init_seconds
    age = min_job_age(config)
    if age is None or age < 3 * init:
        return (
            f"MinJobAge={age} s on this cluster is under 3 x "
            "slurm-init-seconds-before-status-checks "
            f"({init} s), so the executor would fall back to sacct, which keeps no accounting "
            "here, and wait "
            f"for ever; set slurm-init-seconds-before-status-checks: {max(1, (age or 0) // 3)} "
            "or less in the "
            f"profile, or raise MinJobAge in slurm.conf"
        )
    return None


def slurm_tools_problem(
    status_command: str | None, config: dict[str, str], which=shutil.which, run=subprocess.run
) -> str | None:
    """One line saying which SLURM command is missing or does not answer here, or None."""
    missing = [tool for tool in TOOLS if which(tool) is None]
    if missing:
        return (
            f"{', '.join(missing)} not found on PATH (the SLURM executor runs "
            f"{', '.join(TOOLS)}; without "
            "one it waits for ever for jobs it never sent); run from a SLURM login node, or "
            "locally "
            f"without --profile config/profiles/slurm"
        )
    if not config:
        return (
            f"scontrol show config did not answer within {PROBE_SECONDS} s: the SLURM "
            "controller cannot "
            "be reached from here. Check `scontrol ping`, or run locally without --profile "
            "config/profiles/slurm"
        )
    probe = (
        ["squeue", "--noheader", "--format=%i", "--name=stonedem-probe"]
        if status_command == "squeue"
        else ["sacct", "--noheader", "--format=JobIdRaw", "--name=stonedem-probe"]
    )
    try:
        done = run(probe, capture_output=True, text=True, timeout=PROBE_SECONDS)
        why = (
            None
            if done.returncode == 0
            else f"exit {done.returncode}: {(done.stderr or '').strip()[:200]}"
        )
    except subprocess.TimeoutExpired:
        why = f"no answer within {PROBE_SECONDS} s"
    except OSError as err:
        why = err.strerror
    if why:
        return (
            f"{probe[0]}, the profile's status command, does not answer ({why}), so the run "
            "could not see "
            "its jobs finish. Check the SLURM controller, or run locally without --profile "
            "config/profiles/slurm"
        )
    return None


def _limit(name: str, default: float) -> float:
    try:
        return float(os.environ.get(f"STONEDEM_SLURM_{name}", default))
    except ValueError:
        return default


def bound_status_checks(plugin_module=None, now=time.monotonic) -> bool:
    """Replace the executor's status query by one that kills a query past QUERY_SECONDS, retries
    a failed one every RETRY_SECONDS and raises a WorkflowError (the run ends) once queries have
    failed for SILENT_SECONDS. False where the plugin is not the pinned one (no
    ``query_job_status`` to replace)."""
    if plugin_module is None:
        try:
            import snakemake_executor_plugin_slurm as plugin_module
        except ImportError:
            return False
    if not hasattr(plugin_module, "query_job_status"):
        return False
    from snakemake_interface_common.exceptions import WorkflowError

    query_seconds, silent_seconds = (
        _limit("QUERY_SECONDS", QUERY_SECONDS),
        _limit("SILENT_SECONDS", SILENT_SECONDS),
    )

    async def query_once(command: str):
        """(states, None) or (None, why)."""
        try:
            process = await asyncio.create_subprocess_exec(
                *shlex.split(command),
                stdout=asyncio.subprocess.PIPE,
                stderr=asyncio.subprocess.PIPE,
            )
            try:
                out, err = await asyncio.wait_for(process.communicate(), timeout=query_seconds)
            except asyncio.TimeoutError:
                process.kill()  # a hung query must not outlive its turn
                await process.wait()
                return None, f"no answer within {query_seconds:g} s"
        except OSError as error:
            return None, error.strerror or str(error)
        if process.returncode != 0:
            return None, f"exit {process.returncode}: {err.decode(errors='replace').strip()[:200]}"
        return {
            row[0].strip(): row[1].strip()
            for row in csv.reader(io.StringIO(out.decode()), delimiter="|")
            if len(row) >= 2 and row[0].strip()
        }, None

    async def query_job_status(command: str, logger):
        # a failed query is retried here until one answers or SILENT_SECONDS pass: the plugin
        # (2.8.0) drops its active jobs after a cycle of failed queries and never asks again,
        # so the run waited for ever (measured: slurmctld stopped mid-run, no end after 290 s)
        started = now()
        while True:
            states, why = await query_once(command)
            if why is None:
                return states, now() - started
            logger.debug(f"SLURM status query failed: {why}")
            if now() - started > silent_seconds:
                raise WorkflowError(
                    f"SLURM stopped answering: `{shlex.split(command)[0]}` has not reported the "
                    f"jobs' states for {now() - started:.0f} s (last: {why}); the jobs may still "
                    f"run. When `squeue` answers again, run the same command again"
                )
            await asyncio.sleep(
                min(RETRY_SECONDS, max(0.0, silent_seconds - (now() - started)) + 0.1)
            )

    plugin_module.query_job_status = query_job_status
    return True


def check_executor(workflow) -> None:
    """Snakemake onstart: end a SLURM run in one line (exit 2) before its first job when its
    settings cannot see the jobs finish, or when SLURM's commands are missing or do not answer;
    then bound the status checks of the run."""
    plugin = getattr(workflow, "executor_plugin", None)
    if plugin is None or getattr(plugin, "name", "") != "slurm":
        return
    settings = getattr(workflow, "executor_settings", None)
    status_command = getattr(settings, "status_command", None)
    config = scontrol_config()
    problem = slurm_settings_problem(
        status_command, getattr(settings, "init_seconds_before_status_checks", None), config
    )
    if problem:
        print(f"Bad cluster setting: {problem}", file=sys.stderr)
        sys.exit(2)
    problem = slurm_tools_problem(status_command, config)
    if problem:
        print(f"Cannot use SLURM here: {problem}", file=sys.stderr)
        sys.exit(2)
    bound_status_checks()
