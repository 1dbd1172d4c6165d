"""Resource bombs (issue 43): a 1 kB YAML whose aliases repeat 10^9 strings (a "billion
laughs") is refused in one line, fast, by every reader: a scene (stonedem run and
stonedem.load_scene), a wall case (stonedem wall) and a study config (snakemake -n
--configfile, which Snakemake parses itself). Before, the scene simulated and then
json.dumps of its provenance never ended."""

import subprocess
import sys
import time

import pytest

from stonedem.errors import InputError
from tests.faults.small_study import ROOT, stonedem_command

LAUGHS = "aliases expand to more than 1000000 values and characters"


def laughs(indent: str) -> str:
    """A description: list of 9 levels of 10 aliases each (10^9 strings), 565 bytes."""
    rows = [f"{indent}- &l0 lol"]
    rows += [f"{indent}- &l{i} [" + ", ".join([f"*l{i - 1}"] * 10) + "]" for i in range(1, 10)]
    return "\n".join(rows) + "\n"


def one_line(proc, prefix: str):
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines[-1].startswith(prefix) and LAUGHS in lines[-1], proc.stderr
    assert sum(LAUGHS in line for line in lines) == 1 and "Traceback" not in proc.stderr, (
        proc.stderr
    )


@pytest.fixture()
def bomb_scene(tmp_path):
    path = tmp_path / "bomb.yaml"
    text = (ROOT / "tests/data/scenes/rocking_block.yaml").read_text()
    path.write_text(text + "description:\n" + laughs("  "))
    assert path.stat().st_size < 2000
    return path


def test_run_refuses_a_bomb_scene_in_one_line(tmp_path, bomb_scene):
    out = tmp_path / "out.nc"
    start = time.perf_counter()
    proc = subprocess.run(
        stonedem_command("run", str(bomb_scene), "-o", str(out)),
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert time.perf_counter() - start < 20.0  # the interpreter's start; the check is 10 ms
    one_line(proc, f"error: {bomb_scene}: its {LAUGHS}")
    assert not out.exists()


def test_load_scene_refuses_a_bomb(bomb_scene):
    import stonedem

    start = time.perf_counter()
    with pytest.raises(InputError, match=f"its {LAUGHS} \\(line 20, column 15\\)"):
        stonedem.load_scene(bomb_scene)
    assert time.perf_counter() - start < 1.0


def test_wall_refuses_a_bomb_case_in_one_line(tmp_path):
    case = tmp_path / "bomb_wall.yaml"
    text = (ROOT / "config/walls/free_standing.yaml").read_text()
    case.write_text(text + "description:\n" + laughs("  "))
    out = tmp_path / "wall.nc"
    proc = subprocess.run(
        stonedem_command("wall", str(case), "-o", str(out), "-q"),
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    one_line(proc, f"error: {case}: its {LAUGHS}")
    assert not out.exists()


def test_snakemake_refuses_a_bomb_config_in_one_line(tmp_path):
    config = tmp_path / "bomb.yaml"
    config.write_text("studies:\n  bomb:\n    description:\n" + laughs("      "))
    start = time.perf_counter()
    proc = subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "--configfile", str(config)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert time.perf_counter() - start < 60.0  # measured 3.6 s, all of it Snakemake's start
    one_line(proc, f"Bad config: {config}: its {LAUGHS}")
