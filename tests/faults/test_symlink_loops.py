"""A symlink loop on every path argument of every command (issue 43, part 4): one line
``error: <argument>: ...``, exit 2, no traceback and nothing written. pathlib raised a bare
``RuntimeError: Symlink loop`` from the output-path check before; a record or a study folder
that loops was "not found". Run in-process (``stonedem.cli.main``, ``compare.main``): a few
milliseconds each, none reaches a simulation."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from stonedem.cli import main as stonedem_main
from stonedem.study.compare import main as compare_main

ROOT = Path(__file__).resolve().parents[2]
LOOPS = ("loop", "loop.yaml", "loop.nc", "loop.png", "loop.gif", "loop.txt")

# (argv with {loop...}/{scene}/{wall}/{case} placeholders, the argument the line must name)
CASES = [
    (["run", "{loop.yaml}", "-o", "out.nc"], "loop.yaml"),
    (["run", "{scene}", "-o", "{loop.nc}"], "-o/--output"),
    (["run", "{scene}", "-o", "{loop}/out.nc"], "-o/--output"),
    (["wall", "{loop.yaml}", "-o", "out.nc"], "loop.yaml"),
    (["wall", "{wall}", "-o", "{loop.nc}"], "-o/--output"),
    (["wall", "{wall}", "-o", "{loop}/out.nc"], "-o/--output"),
    (["validate", "--only", "block_free_rocking", "-o", "{loop}"], "-o/--output"),
    (["record", "info", "{loop.txt}"], "file"),
    (["record", "info", "athens_standin_kocaeli_arc000", "--plot", "{loop.png}"], "--plot"),
    (["snapshots", "{loop.nc}"], "loop.nc"),
    (["snapshots", "{case}", "-o", "{loop.png}"], "-o"),
    (["animate", "{loop.nc}"], "loop.nc"),
    (["animate", "{case}", "-o", "{loop.gif}"], "-o"),
]


@pytest.fixture
def arena(tmp_path, monkeypatch):
    for name in LOOPS:
        (tmp_path / name).symlink_to(name)
    shutil.copy(ROOT / "tests/data/scenes/rocking_block.yaml", tmp_path / "scene.yaml")
    shutil.copy(ROOT / "config/walls/free_standing.yaml", tmp_path / "wall.yaml")
    (tmp_path / "case.nc").write_bytes(
        b"CDF\x01" + bytes(60)
    )  # never read: the output is refused first
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _fill(argv, arena):
    names = {name: str(arena / name) for name in LOOPS}
    names.update(
        scene=str(arena / "scene.yaml"), wall=str(arena / "wall.yaml"), case=str(arena / "case.nc")
    )
    filled = []
    for arg in argv:
        for name, path in names.items():
            arg = arg.replace("{" + name + "}", path)
        filled.append(arg)
    return filled


def _one_line(capsys, status, argument):
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert status == 2, (status, err)
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert argument in lines[0] and ("symbolic link" in lines[0] or "symlink loop" in lines[0]), (
        lines[0]
    )
    assert "Traceback" not in out + err


@pytest.mark.parametrize(
    "argv, argument", CASES, ids=lambda c: " ".join(c) if isinstance(c, list) else None
)
def test_a_symlink_loop_on_a_command_path_is_one_line(arena, capsys, argv, argument):
    before = sorted(p.name for p in arena.iterdir())
    _one_line(capsys, stonedem_main(_fill(argv, arena)), argument)
    assert sorted(p.name for p in arena.iterdir()) == before, "nothing written"


@pytest.mark.parametrize("which", [0, 1])
def test_a_symlink_loop_as_a_compared_study_folder_is_one_line(arena, capsys, which):
    (arena / "study" / "results").mkdir(parents=True)
    folders = [str(arena / "study"), str(arena / "study")]
    folders[which] = str(arena / "loop")
    _one_line(capsys, compare_main(folders), ("STUDY_A", "STUDY_B")[which])
