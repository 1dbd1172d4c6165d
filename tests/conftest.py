"""Shared test settings: the hypothesis profiles of the fuzz suites.

``ci`` (default) runs 50 examples per fuzz test, a few hundred in all; ``fuzz`` runs 10 000
(the benchmark target: ``HYPOTHESIS_PROFILE=fuzz python3 -m pytest tests -k fuzz``).
"""

import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    max_examples=50,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "fuzz", max_examples=10_000, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
# another count for one run of the fuzz profile (e.g. 1000 for the slow argv fuzz of the
# subcommands)
settings.register_profile(
    "fuzz_n",
    parent=settings.get_profile("fuzz"),
    max_examples=int(os.environ.get("HYPOTHESIS_MAX_EXAMPLES", "10000")),
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture(autouse=True)
def numba_threads_unchanged():
    """No test may leave NUMBA_NUM_THREADS changed: once a parallel loop has started Numba's
    thread pool, a changed value makes Numba refuse every later compile in the process (the
    ensemble tests failed in CI after a benchmark main had set it in-process)."""
    before = os.environ.get("NUMBA_NUM_THREADS")
    yield
    after = os.environ.get("NUMBA_NUM_THREADS")
    if after != before:
        if before is None:
            os.environ.pop("NUMBA_NUM_THREADS", None)
        else:
            os.environ["NUMBA_NUM_THREADS"] = before
        pytest.fail(f"NUMBA_NUM_THREADS changed from {before!r} to {after!r} by this test")


@pytest.fixture(scope="session")
def quiet_sine_record(tmp_path_factory):
    """A record file: 1 s of silence, 1 s of a 2 Hz, 0.4 g sine, then silence to 4 s (a run
    with a quiet lead and a quiet tail)."""
    import numpy as np

    t = np.arange(0.0, 4.0 + 1e-9, 0.005)
    a = np.where((t >= 1.0) & (t < 2.0), 0.4 * 9.81 * np.sin(2 * np.pi * 2 * (t - 1.0)), 0.0)
    path = tmp_path_factory.mktemp("records") / "silence_sine_silence.txt"
    np.savetxt(path, np.column_stack([t, a]), header="time [s], acceleration [m/s2]")
    return path


# a PATH folder whose scontrol answers at once as an unreachable SLURM controller does
_DEAD_SLURM: list[str] = []


def pytest_configure(config):
    """Where SLURM is installed but its controller is down (CI's machine after its SLURM step
    stopped the daemons), ``scontrol show config`` fails only after ~9 s, and the SLURM
    executor plugin asks it each time Snakemake starts (to word a help text): ~9 s of every
    ``python3 -m snakemake`` a test runs, about 50 of them. Then the tests' children get an
    scontrol first on PATH that fails at once, with the same exit status and message (what
    the workflow and the plugin make of it is the same: no answer). A controller that answers
    within 2 s is left alone, as is a machine without scontrol; tests that fake SLURM set
    their own PATH (tests/faults/test_cluster_faults.py)."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        return  # the workers inherit the controller's PATH
    import shutil
    import subprocess
    import tempfile

    if shutil.which("scontrol") is None:
        return
    try:
        subprocess.run(["scontrol", "show", "config"], capture_output=True, timeout=2, check=False)
        return
    except subprocess.TimeoutExpired:
        pass
    except OSError:
        return
    folder = tempfile.mkdtemp(prefix="stonedem-tests-dead-slurm-")
    stub = os.path.join(folder, "scontrol")
    with open(stub, "w") as f:
        f.write(
            "#!/bin/sh\necho 'slurm_load_ctl_conf error: Unable to contact slurm controller "
            "(connect failure)' >&2\nexit 1\n"
        )
    os.chmod(stub, 0o755)
    os.environ["PATH"] = f"{folder}{os.pathsep}{os.environ.get('PATH', '')}"
    _DEAD_SLURM.append(folder)


def pytest_unconfigure(config):
    import shutil

    while _DEAD_SLURM:
        shutil.rmtree(_DEAD_SLURM.pop(), ignore_errors=True)


# the files that take longest (seconds of one worker, 2 cores and a third job, 2026-11-29), handed
# out first (pyproject's addopts: --dist loadfile --no-loadscope-reorder): xdist's default order,
# most tests first, left test_workflow.py and test_study_faults.py (a few long tests each) to start
# last, one worker running them alone at the end
LONGEST_FIRST = (
    "tests/wall/test_tables.py",  # 187 s
    "tests/workflow/test_workflow.py",  # 183 s
    "tests/faults/test_study_faults.py",  # 167 s
    "tests/faults/test_study_interrupts.py",  # 121 s
    "tests/wall/test_pushover.py",  # 50 s
    "tests/kernels/test_step.py",  # 40 s (compiles step.run and step.run_steps)
    "tests/faults/test_cluster_faults.py",  # 38 s
    "tests/faults/test_cli_faults.py",  # 33 s
    "tests/validation/test_cases.py",  # 27 s
)


def pytest_collection_modifyitems(session, config, items):
    """The LONGEST_FIRST files' tests first, in that order; every file's tests stay together and
    in their own order (the same order in every worker, as xdist requires)."""
    rank = {path: i for i, path in enumerate(LONGEST_FIRST)}

    def key(item):
        return rank.get(item.nodeid.split("::", 1)[0], len(rank))

    items[:] = sorted(items, key=key)  # stable: the rest keep pytest's order


@pytest.hookimpl(tryfirst=True)
def pytest_sessionstart(session):
    """Before the workers start (or the tests, without xdist): compile the engine's time loops
    (stonedem.engine.run.WARM_SCENES) side by side, one process each
    (stonedem.engine.run.warm_compile), into Numba's cache. With an empty cache both workers
    otherwise compiled both loops at once, each, in their first tests (~55 s of a 2-core run; ~2 s
    when the cache is full)."""
    if os.environ.get("PYTEST_XDIST_WORKER") or os.environ.get("NUMBA_DISABLE_JIT") == "1":
        return
    import subprocess
    import sys
    from pathlib import Path

    import numba

    import stonedem.kernels  # noqa: F401 - sets Numba's cache folder

    try:  # Numba's folder for this checkout's kernels (it keys the cache by the sources' path too)
        from numba.core.caching import _CacheLocator

        cached = Path(numba.config.CACHE_DIR) / _CacheLocator.get_suitable_cache_subpath(
            stonedem.kernels.__file__
        )
    except (ImportError, AttributeError):
        cached = Path(numba.config.CACHE_DIR) / "unknown"
    if all(
        any(cached.glob(f"{name}-*.nbi"))
        for name in ("step.run_area", "step.run_point", "contact_graph.run")
    ):
        return  # compiled before (for this CPU or another: a worker then compiles what it lacks)
    from stonedem.engine.run import WARM_SCENES

    # two processes for two cores (three at once took 66 s here, against ~52 s): the point law's
    # two loops (23 + 29 s) in one, the area law's general loop (29 s) in the other
    groups = [[loop for loop in WARM_SCENES if loop != "general"], ["general"]]
    code = "import sys; from stonedem.engine.run import warm_compile; warm_compile(sys.argv[1:])"
    compiles = [
        subprocess.Popen(
            [sys.executable, "-c", code, *loops],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )
        for loops in groups
    ]
    for loops, compile_ in zip(groups, compiles):
        _, err = compile_.communicate()
        if compile_.returncode != 0:  # the tests will say what is wrong; this only warms the cache
            print(
                f"warming the compiled {', '.join(loops)} loop failed: "
                f"{err.strip().splitlines()[-1:]}",
                file=sys.stderr,
            )
