"""`stonedem run` exit codes, messages, and no file left behind on bad input."""

import subprocess
import sys

import xarray as xr

SCENE = "tests/data/scenes/rocking_block.yaml"


def stonedem(*args):
    return subprocess.run([sys.executable, "-m", "stonedem", *args], capture_output=True, text=True)


def test_run_writes_a_dataset(tmp_path):
    out = tmp_path / "rock.nc"
    proc = stonedem("run", SCENE, "-o", str(out), "--set", "solver.duration=0.3", "-q")
    assert proc.returncode == 0, proc.stderr
    with xr.open_dataset(out) as ds:
        assert ds.theta.dims == ("time", "body")
        assert ds.time.attrs["units"] == "s" and float(ds.time[-1]) >= 0.3 - 1e-9
        assert '"mass": 503.0' in ds.attrs["scene"]


def test_bad_input_one_line_nonzero_exit_no_output(tmp_path):
    out = tmp_path / "bad.nc"
    for override in ("solver.dt=0.5", "bodies.block.mass=-3", "contact.k_x=1"):
        proc = stonedem("run", SCENE, "-o", str(out), "--set", override, "-q")
        assert proc.returncode == 2, override
        lines = proc.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: "), proc.stderr
        assert not out.exists()
        assert not list(tmp_path.glob(".*.tmp")), "no temporary file left behind"


def test_missing_scene_file():
    proc = stonedem("run", "nope.yaml", "-o", "x.nc")
    assert proc.returncode == 2 and "not found" in proc.stderr


def test_validate_list_describes_every_validation():
    proc = stonedem("validate", "--list")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.strip().splitlines()
    from stonedem.validation.cases import VALIDATIONS

    assert [line.split()[0] for line in lines] == list(VALIDATIONS)
    for line in lines:
        name, text = line.split(None, 1)
        assert "partial(" not in text and text.endswith("."), line
        if name.endswith("_point"):
            assert line.endswith("; point law."), line


def test_symlink_loops_and_links_onto_the_input_are_one_line(tmp_path):
    """A symlink loop as the scene, the output or a folder on the way, and an output that is a
    symlink to the scene: exit 2, one line, no traceback (pathlib's RuntimeError before)."""
    scene = tmp_path / "s.yaml"
    scene.write_text(open(SCENE).read())
    (tmp_path / "loop").symlink_to("loop")
    (tmp_path / "loop.nc").symlink_to("loop.nc")
    (tmp_path / "link.nc").symlink_to("s.yaml")
    cases = [
        (
            ["run", str(tmp_path / "loop"), "-o", str(tmp_path / "x.nc")],
            "Too many levels of symbolic links",
        ),
        (
            ["run", str(scene), "-o", str(tmp_path / "loop.nc")],
            "loop.nc cannot be followed (a symlink loop)",
        ),
        (
            ["run", str(scene), "-o", str(tmp_path / "loop" / "x.nc")],
            "cannot be followed (a symlink loop)",
        ),
        (["run", str(scene), "-o", str(tmp_path / "link.nc")], "link.nc is the input file"),
    ]
    for argv, message in cases:
        proc = stonedem(*argv, "-q")
        lines = proc.stderr.strip().splitlines()
        assert proc.returncode == 2 and len(lines) == 1 and message in lines[0], (argv, proc.stderr)
    assert scene.read_text() == open(SCENE).read() and not (tmp_path / "x.nc").exists()
