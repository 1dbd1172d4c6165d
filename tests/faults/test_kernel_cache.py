"""A damaged compiled-kernel cache (issue 43, item 3): an empty or truncated Numba index
(.nbi) or code (.nbc) file made every later run fail with EOFError or UnpicklingError until
the user deleted ~/.cache/stonedem/numba. Now the file is moved aside with one line on stderr
and the kernel is compiled again. Each run is a child process with a cache of its own
(XDG_CACHE_HOME in tmp_path: the shared cache is never touched) calling one small kernel."""

import os
import subprocess
import sys

import pytest

from tests.faults.small_study import truncate

# the smallest cached kernel: the area and centroid of the unit square
CALL = (
    "import numpy as np; from stonedem.kernels.overlap import polygon_area_centroid as f; "
    "print(f(np.array([0.0, 1.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0, 1.0]), 4))"
)
ANSWER = "(1.0, 0.5, 0.5)"


def call_kernel(home):
    env = {**os.environ, "XDG_CACHE_HOME": str(home)}
    env.pop("NUMBA_CACHE_DIR", None)
    return subprocess.run(
        [sys.executable, "-c", CALL],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    home = tmp_path_factory.mktemp("xdg")
    proc = call_kernel(home)  # compiles the one kernel into a cache of its own (~2 s)
    assert proc.returncode == 0 and proc.stdout.strip() == ANSWER, proc.stderr[-2000:]
    return home


def files(home, suffix):
    found = sorted((home / "stonedem" / "numba").rglob(f"overlap.polygon_area_centroid-*{suffix}"))
    assert found, f"no {suffix} file of the kernel in {home}"
    return found


@pytest.mark.parametrize("suffix, size", [(".nbi", 0), (".nbi", None), (".nbc", 0), (".nbc", None)])
def test_a_damaged_cache_file_is_moved_aside_and_the_kernel_compiled_again(cache, suffix, size):
    damaged = files(cache, suffix)[0]
    truncate(damaged, size)
    proc = call_kernel(cache)
    assert proc.returncode == 0 and proc.stdout.strip() == ANSWER, proc.stderr[-2000:]
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        f"warning: compiled-kernel cache file {damaged} is damaged ("
    ), lines
    assert lines[0].endswith(f"moved to {damaged.name}.damaged, compiling the kernel again"), lines
    assert (damaged.parent / f"{damaged.name}.damaged").is_file()
    # Numba wrote the entry afresh: the next run loads it without a word
    assert damaged.stat().st_size > 0
    again = call_kernel(cache)
    assert again.returncode == 0 and again.stdout.strip() == ANSWER and again.stderr == "", (
        again.stderr[-2000:]
    )
