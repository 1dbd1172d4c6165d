"""Faults around one ``stonedem run`` (issue 31, part 4): a full disk (RLIMIT_FSIZE), an output
folder that cannot be written, a corrupted record, closed or failing stdout and stderr. Bad
input and a failed write end in exactly one line ``error: ...`` and exit 2, with nothing
under the output name; a complete run exits 0 whatever happens to its logging, and what it
wrote is bit-identical to an undisturbed run."""

import os
import random
import resource
import shutil
import signal
import subprocess
from pathlib import Path

import pytest
import yaml

from tests.faults.small_study import (
    RECORD,
    ROOT,
    as_plain_owner,
    assert_same_dataset,
    read_only,
    stonedem_command,
    truncate,
)

# the Pena granite block of tests/data/scenes, rocking 0.5 s: ~100 kB of NetCDF, ~2 s a run
SHORT = ["--set", "solver.duration=0.5", "--set", "output.every=0.005"]


def scene_file(folder: Path, **changes) -> Path:
    scene = yaml.safe_load((ROOT / "tests/data/scenes/rocking_block.yaml").read_text())
    scene.update(changes)
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(scene, sort_keys=False))
    return path


def run(scene, output, *extra, **kwargs):
    kwargs.setdefault("capture_output", True)
    return subprocess.run(
        stonedem_command("run", str(scene), "-o", str(output), *SHORT, *extra),
        text=True,
        timeout=300,
        check=False,
        **kwargs,
    )


def show(proc):
    return f"exit {proc.returncode}\n--- stdout\n{proc.stdout}\n--- stderr\n{proc.stderr}"


def assert_one_error_line(proc, *words):
    """Exit 2 and exactly one line ``error: ...`` on stderr, the last, holding ``words``; no
    traceback."""
    assert proc.returncode == 2, show(proc)
    lines = proc.stderr.strip().splitlines()
    errors = [line for line in lines if line.startswith("error: ")]
    assert len(errors) == 1 and lines[-1] == errors[0], show(proc)
    assert all(word in errors[0] for word in words), show(proc)
    assert "Traceback" not in proc.stdout + proc.stderr, show(proc)


def nothing_under(output: Path):
    """Neither the output nor a temporary file beside it."""
    assert not output.exists(), f"{output} was written"
    strays = sorted(p.name for p in output.parent.glob(f".{output.stem}.*"))
    assert not strays, f"temporary files left: {strays}"


@pytest.fixture(scope="module")
def undisturbed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("undisturbed")
    scene = scene_file(folder)
    proc = run(scene, folder / "out.nc")
    assert proc.returncode == 0, show(proc)
    return scene, folder / "out.nc"


# --- 2. a full disk while writing -------------------------------------------------------------


def limited(n):
    def preexec():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (n, n))

    return preexec


@pytest.mark.parametrize("limit", [4096, 50_000], ids=["4k", "50k"])
def test_a_full_disk_is_one_line_naming_the_path_and_a_rerun_is_identical(
    undisturbed, tmp_path, limit
):
    scene, good = undisturbed
    assert good.stat().st_size > limit
    output = tmp_path / "runs" / "out.nc"
    proc = run(scene, output, preexec_fn=limited(limit))
    assert_one_error_line(proc, str(output), "cannot write")
    nothing_under(output)
    proc = run(scene, output)
    assert proc.returncode == 0, show(proc)
    assert_same_dataset(output, good, "out.nc")


# --- 3. an output folder that cannot be written -----------------------------------------------


def test_an_output_under_proc_is_refused_in_one_line(undisturbed):
    scene, _ = undisturbed
    proc = run(scene, "/proc/forbidden/x.nc")
    assert_one_error_line(proc, "/proc/forbidden")
    assert not Path("/proc/forbidden").exists()


def test_a_read_only_output_folder_is_refused_in_one_line(undisturbed, tmp_path):
    scene, good = undisturbed
    folder = tmp_path / "read only é"
    folder.mkdir()
    with read_only(folder):
        proc = run(scene, folder / "x.nc", preexec_fn=as_plain_owner)
        nested = run(scene, folder / "sub" / "x.nc", preexec_fn=as_plain_owner)
    assert_one_error_line(proc, str(folder))
    assert_one_error_line(nested, str(folder / "sub"))
    assert not any(folder.iterdir())
    proc = run(scene, folder / "sub" / "x.nc")
    assert proc.returncode == 0, show(proc)
    assert_same_dataset(folder / "sub" / "x.nc", good, "x.nc")


# --- 6. a corrupted record file ----------------------------------------------------------------


def garble(path):
    path.write_bytes(random.Random(6).randbytes(path.stat().st_size))


def flip(path):
    data = bytearray(path.read_bytes())
    for i in range(len(data) // 2, len(data) // 2 + 4096):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))


@pytest.mark.parametrize(
    "corrupt",
    [truncate, lambda p: truncate(p, 0), garble, flip],
    ids=["truncated", "zero-byte", "garbage", "flipped"],
)
def test_a_corrupted_record_is_one_line_naming_the_file(tmp_path, corrupt):
    record = tmp_path / "records" / "my record.nc"
    record.parent.mkdir()
    shutil.copy(ROOT / RECORD, record)
    corrupt(record)
    scene = scene_file(tmp_path, excitation={"kind": "record", "file": str(record), "pga": 2.0})
    proc = run(scene, tmp_path / "out.nc")
    assert_one_error_line(proc, "my record.nc")
    nothing_under(tmp_path / "out.nc")


# --- 7. closed or failing stdout and stderr ----------------------------------------------------


def closing(*fds):
    def preexec():
        for fd in fds:
            os.close(fd)

    return preexec


STREAMS = {
    "stdout-closed": {"preexec_fn": closing(1), "stderr": subprocess.PIPE},
    "stderr-closed": {"preexec_fn": closing(2), "stdout": subprocess.PIPE},
    "both-closed": {"preexec_fn": closing(1, 2)},
    "both-dev-full": {"stdout": "/dev/full", "stderr": "/dev/full"},
}


def streams(name):
    kwargs = dict(STREAMS[name], capture_output=False)
    for key in ("stdout", "stderr"):
        if kwargs.get(key) == "/dev/full":
            kwargs[key] = open("/dev/full", "w")  # noqa: SIM115 - closed by the caller
    return kwargs


def finish(proc, kwargs):
    for key in ("stdout", "stderr"):
        if hasattr(kwargs.get(key), "close"):
            kwargs[key].close()
    proc.stdout = proc.stdout or ""
    proc.stderr = proc.stderr or ""
    return proc


@pytest.mark.parametrize("name", list(STREAMS))
def test_a_complete_run_exits_0_whatever_its_streams(undisturbed, tmp_path, name):
    scene, good = undisturbed
    kwargs = streams(name)
    proc = finish(run(scene, tmp_path / "out.nc", **kwargs), kwargs)
    assert proc.returncode == 0, show(proc)
    assert_same_dataset(tmp_path / "out.nc", good, "out.nc")
    assert [p.name for p in tmp_path.iterdir()] == ["out.nc"], (
        "a stray file: output meant for a closed stream?"
    )


@pytest.mark.parametrize("name", list(STREAMS))
def test_bad_input_exits_2_whatever_its_streams(tmp_path, name):
    scene = scene_file(tmp_path, friction=-1.0)
    kwargs = streams(name)
    proc = finish(run(scene, tmp_path / "out.nc", **kwargs), kwargs)
    assert proc.returncode == 2, show(proc)
    assert "Traceback" not in proc.stdout + proc.stderr, show(proc)
    if name == "stdout-closed":  # stderr still open: the one line is there
        assert proc.stderr.startswith("error: friction") and len(proc.stderr.splitlines()) == 1, (
            show(proc)
        )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.yaml"]
