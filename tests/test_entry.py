"""Entry-point conventions (stonedem.entry, stonedem.cli): output paths refused before computing,
real SIGINT / SIGTERM (exit 130 / 143 within a second, nothing left behind), broken pipes,
--version and --help, and the checks a finished run makes of itself."""

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr

from stonedem.engine.scene import scene_from_dict
from stonedem.engine.simulate import (
    ENERGY_TOLERANCE,
    MAX_STEPS,
    MIN_STEPS_PER_PERIOD,
    PENETRATION_LIMIT,
    preflight,
    run_checks,
    simulate,
)
from stonedem.entry import check_output_path
from stonedem.errors import InputError
from tests.signals import interrupt_after_line

SCENE = "tests/data/scenes/rocking_block.yaml"
# how long after the signal the process may take to end (measured 0.6-0.7 s; the issue
# asks for 1 s, plus a margin for a loaded CI machine)
SIGNAL_EXIT_SECONDS = 1.5


def stonedem(*args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "stonedem", *args], capture_output=True, text=True, **kw
    )


# --- output paths ---------------------------------------------------------------------


def test_output_path_that_is_the_input_is_refused(tmp_path):
    scene = tmp_path / "s.nc"
    scene.write_text("x")
    with pytest.raises(InputError, match="is the input file"):
        check_output_path(scene, "-o", inputs=[scene])


def test_output_path_refusals(tmp_path):
    (tmp_path / "afile").write_text("x")
    with pytest.raises(InputError, match="is a directory"):
        check_output_path(tmp_path, "-o")
    with pytest.raises(InputError, match="is a file, not a folder"):
        check_output_path(tmp_path / "afile" / "out.nc", "-o")
    with pytest.raises(InputError, match="does not end in .nc"):
        check_output_path(tmp_path / "out.txt", "-o", suffixes=(".nc",))
    with pytest.raises(InputError, match="has no name before .nc; give a name such as out.nc"):
        check_output_path(
            tmp_path / ".nc", "-o", suffixes=(".nc", ".nc4")
        )  # not "does not end in .nc"
    for empty in (
        "",
        Path(""),
    ):  # was ". does not end in .nc": argparse gives Path(""), which is "."
        with pytest.raises(InputError, match="^-o: is empty"):
            check_output_path(empty, "-o", suffixes=(".nc",))
    # accepted, and nothing created: the write makes the folder (a later refusal leaves none)
    assert check_output_path(tmp_path / "new" / "deeper" / "out.nc", "-o", suffixes=(".nc",))
    assert not (tmp_path / "new").exists()


def test_output_paths_the_filesystem_would_refuse_at_the_end(tmp_path):
    # a folder that cannot be made (root may write anywhere, but not under /proc)
    with pytest.raises(InputError, match="cannot create folder /proc/"):
        check_output_path("/proc/stonedem-test/out.nc", "-o")
    with pytest.raises(InputError, match="longer than"):
        check_output_path(tmp_path / ("x" * 250 + ".nc"), "-o")
    with pytest.raises(InputError, match="not valid UTF-8"):
        check_output_path(tmp_path / os.fsdecode(b"caf\xe9.nc"), "-o")
    # spaces and non-ASCII text are names like any other
    assert check_output_path(tmp_path / "my study é ü" / "out.nc", "-o")


def test_output_path_that_is_a_device_or_a_link_to_one_is_refused(tmp_path):
    # an atomic write renames over the path: a link to /dev/full became a PNG, "wrote" said
    link = tmp_path / "strip.png"
    link.symlink_to("/dev/full")
    os.mkfifo(tmp_path / "pipe.gif")
    for path in (link, tmp_path / "pipe.gif", "/dev/null"):
        with pytest.raises(InputError, match="is not a regular file"):
            check_output_path(path, "-o")
    assert link.is_symlink()
    # a link to a regular file is still an output like any other
    (tmp_path / "real.png").write_bytes(b"x")
    (tmp_path / "to_real.png").symlink_to(tmp_path / "real.png")
    assert check_output_path(tmp_path / "to_real.png", "-o")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere")
def test_read_only_folder_is_refused(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    folder.chmod(0o500)
    with pytest.raises(InputError, match="cannot write in folder"):
        check_output_path(folder / "out.nc", "-o")


def test_run_refuses_output_over_its_scene_before_computing(tmp_path):
    scene = tmp_path / "s.nc"
    scene.write_text(open(SCENE).read())
    start = time.perf_counter()
    proc = stonedem("run", str(scene), "-o", str(scene))
    assert proc.returncode == 2 and "is the input file" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert open(scene).read() == open(SCENE).read()
    assert time.perf_counter() - start < 20  # refused at once, not after the run


# --- conventions ----------------------------------------------------------------------


def test_version_and_help_list_every_command():
    proc = stonedem("--version")
    assert proc.returncode == 0 and proc.stdout.startswith("stonedem ")
    proc = stonedem("--help")
    for command in ("run", "validate", "record", "snapshots", "animate", "wall"):
        assert re.search(rf"^ +{command}\b", proc.stdout, re.M), command
    assert "``" not in proc.stdout


def test_usage_error_is_one_line_exit_2():
    proc = stonedem("frobnicate")
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1


def test_closed_stdout_gives_no_traceback():
    read, write = os.pipe()
    os.close(read)
    proc = subprocess.run(
        [sys.executable, "-m", "stonedem", "validate", "--list"],
        stdout=write,
        stderr=subprocess.PIPE,
        text=True,
    )
    os.close(write)
    assert "Traceback" not in proc.stderr and proc.returncode == 0


# --- real signals -----------------------------------------------------------------------

LONG_SCENE = """\
structure: {kind: column, n_drums: 8}
excitation: {kind: harmonic, amplitude: 0.02, frequency: 2.0}
solver: {duration: 600.0, stop_on_collapse: false}
output: {every: 0.01}
"""


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_during_the_compiled_loop(tmp_path, signum, status):
    scene = tmp_path / "long.yaml"
    scene.write_text(LONG_SCENE)
    out = tmp_path / "long.nc"
    # a progress line: the time loop is running
    rc, took, _ = interrupt_after_line(
        [sys.executable, "-m", "stonedem", "run", str(scene), "-o", str(out)],
        lambda line: "t = " in line,
        signum,
    )
    assert rc == status
    assert took < SIGNAL_EXIT_SECONDS, took
    assert list(tmp_path.iterdir()) == [scene], "no output and no temporary file"


SLOW_WRITER = """\
import sys, time
from stonedem.io.atomic import write_atomically
from stonedem.entry import guarded

def slow(tmp):
    with open(tmp, "w") as f:
        print("writing", file=sys.stderr, flush=True)
        for _ in range(600):
            f.write("x" * 1000)
            time.sleep(0.05)

sys.exit(guarded(lambda: write_atomically(sys.argv[1], slow) and 0))
"""


def test_signal_during_the_write_leaves_nothing(tmp_path):
    out = tmp_path / "out.nc"

    def one_temporary_file():
        assert len(list(tmp_path.iterdir())) == 1

    rc, took, _ = interrupt_after_line(
        [sys.executable, "-c", SLOW_WRITER, str(out)],
        lambda line: "writing" in line,
        signal.SIGINT,
        60,
        one_temporary_file,
    )
    assert rc == 130 and took < SIGNAL_EXIT_SECONDS
    assert list(tmp_path.iterdir()) == []


# --- refused before computing, and what a run says of itself ----------------------------


def column(**changes):
    spec = {
        "structure": {"kind": "column", "n_drums": 2},
        "solver": {"duration": 1.0},
        "output": {"every": 0.01},
    }
    for key, value in changes.items():
        spec[key] = {**spec.get(key, {}), **value}
    return spec


@pytest.mark.parametrize(
    "changes, field",
    [
        ({"solver": {"duration": 1e9}}, "solver.duration"),
        ({"solver": {"duration": 3000.0, "dt_safety": 1e-3}}, "solver.duration"),
        ({"solver": {"dt_safety": 1e-9}}, "solver.duration"),
        # a given dt that reads an 800 Hz harmonic 12.5 times a period (dt: auto would resolve it)
        (
            {
                "excitation": {"kind": "harmonic", "amplitude": 1e-9, "frequency": 800.0},
                "solver": {"dt": 1e-4},
            },
            "solver.dt",
        ),
        ({"output": {"every": 1e-7}, "solver": {"duration": 3.0}}, "output.every"),
    ],
)
def test_preflight_refuses_absurd_requests(changes, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        preflight(scene_from_dict(column(**changes)))


def test_auto_dt_resolves_a_fast_excitation():
    scene = scene_from_dict(
        column(excitation={"kind": "harmonic", "amplitude": 1e-9, "frequency": 800.0})
    )
    dt, limit, _ = preflight(scene)
    assert dt <= 1 / 800.0 / MIN_STEPS_PER_PERIOD < scene.dt_safety * limit


def test_preflight_limits_are_stated():
    assert MAX_STEPS == 2e8 and MIN_STEPS_PER_PERIOD == 20


def test_tiny_mass_and_huge_scene_refused():
    spec = yaml_block(mass=1e-30)
    with pytest.raises(InputError, match="mass"):
        scene_from_dict(spec)
    with pytest.raises(InputError, match="n_drums"):
        scene_from_dict(column(structure={"n_drums": 10**6}))


def yaml_block(**body):
    import yaml

    spec = yaml.safe_load(open(SCENE))
    spec["bodies"][1].update(body)
    return spec


def test_soft_contact_sinking_is_penetration_not_collapse():
    scene = scene_from_dict(
        column(contact={"model": "point", "k_n": 1e5}, solver={"duration": 2.0})
    )
    result = simulate(scene)
    checks = run_checks(scene, result)
    assert checks["status"] == "penetrated" and checks["penetration"] > PENETRATION_LIMIT
    assert result.collapse_sample >= 0  # the kernel's fall criterion fired, but it is not reported


def test_tall_undamped_stack_at_the_limit_reports_its_energy_drift():
    # docs/method/checks.md, "Stability": 30 undamped drums at dt_safety 1.0 drift 3.9 % (point law)
    spec = column(
        structure={"n_drums": 30},
        contact={"model": "point", "k_n": 1e10, "damping": 0.0, "impact": "none"},
        excitation={"kind": "harmonic", "amplitude": 0.05, "frequency": 1.5},
        solver={"duration": 4.0, "dt_safety": 1.0, "stop_on_collapse": False},
    )
    scene = scene_from_dict(spec)
    checks = run_checks(scene, simulate(scene))
    assert checks["energy_error"] > ENERGY_TOLERANCE and checks["status"] == "energy balance error"


def test_written_dataset_follows_cf(tmp_path):
    out = tmp_path / "rock.nc"
    proc = stonedem("run", SCENE, "-o", str(out), "--set", "solver.duration=0.2", "-q")
    assert proc.returncode == 0, proc.stderr
    import netCDF4

    with netCDF4.Dataset(out) as nc:
        assert nc.Conventions.startswith("CF-1.")
        t = nc.variables["time"]
        assert t.standard_name == "time" and t.axis == "T" and t.units == "s"
        assert "_FillValue" not in t.ncattrs()
        assert "units" not in nc.variables["body"].ncattrs()
    with xr.open_dataset(out) as ds:
        assert ds.attrs["status"] == "completed" and ds.attrs["energy_error"] < ENERGY_TOLERANCE
