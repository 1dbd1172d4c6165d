"""Comparing two runs of the study (python -m stonedem.study.compare): what counts as the same,
and what a missing, damaged or unreadable file and wrong arguments give (issue 43)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import xarray as xr

from stonedem.study.compare import main, result_differences

CUBE = "results/cubes/s.nc"
TABLE = "results/tables/t.csv"


def _study(folder: Path, wall_seconds: float = 1.0, wall_time: str = "3.5") -> Path:
    """A study folder with one cube and one table; the clock attr and column as given."""
    (folder / "results/cubes").mkdir(parents=True)
    (folder / "results/tables").mkdir(parents=True)
    ds = xr.Dataset(
        {"collapsed": ("pga", np.array([0, 1], np.int8))},
        coords={"pga": [1.0, 2.0]},
        attrs={"study": "s", "wall_seconds": wall_seconds},
    )
    ds.to_netcdf(folder / CUBE, engine="netcdf4")
    (folder / TABLE).write_text(f"system,threshold,wall_seconds\na,1.5,{wall_time}\n")
    return folder


def _compare(capsys, *args) -> tuple[int, list[str], list[str]]:
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out.splitlines(), err.splitlines()


def test_two_runs_differing_only_in_their_clocks_are_the_same(tmp_path, capsys):
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b", wall_seconds=9.0, wall_time="7.25")
    assert _compare(capsys, a, b) == (0, [], ["2 files compared: the same"])
    (b / TABLE).write_text("system,threshold,wall_seconds\na,1.6,3.5\n")
    assert _compare(capsys, a, b) == (
        1,
        [f"{TABLE} differs outside its clock columns"],
        ["2 files compared: 1 differ"],
    )


def test_a_variable_s_array_attribute_is_compared_by_value(tmp_path, capsys):
    # a link's status carries flag_values [0, 1, 2]: dicts of arrays cannot be compared by !=
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    for folder, flags in ((a, [0, 1, 2]), (b, [0, 1, 2])):
        ds = xr.Dataset({"status": ("link", [0, 2], {"flag_values": np.array(flags)})})
        ds.to_netcdf(folder / "results/cubes/links.nc", engine="netcdf4")
    assert _compare(capsys, a, b) == (0, [], ["3 files compared: the same"])
    ds = xr.Dataset({"status": ("link", [0, 2], {"flag_values": np.array([0, 1, 3])})})
    ds.to_netcdf(b / "results/cubes/links.nc", engine="netcdf4")
    assert _compare(capsys, a, b) == (
        1,
        ["results/cubes/links.nc:status attrs differ"],
        ["3 files compared: 1 differ"],
    )


def test_a_file_on_either_side_only_is_a_difference_named_with_its_folder(tmp_path, capsys):
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    (a / "results/tables/left.csv").write_text("x\n1\n")
    (b / "results/cases/s").mkdir(parents=True)
    (b / "results/cases/s/right.nc").write_bytes((b / CUBE).read_bytes())
    code, out, err = _compare(capsys, a, b)
    assert code == 1 and err == ["4 files compared: 2 differ"]
    assert out == [
        f"results/cases/s/right.nc: only in {b}",
        f"results/tables/left.csv: only in {a}",
    ]


def test_a_damaged_file_is_a_difference_in_one_line_not_a_traceback(tmp_path, capsys):
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    data = (b / CUBE).read_bytes()
    (b / CUBE).write_bytes(data[: len(data) // 2])  # truncated
    (a / TABLE).write_bytes(b"system,threshold\n\xe9t\xe9,1.5\n")  # Latin-1, not UTF-8
    code, out, err = _compare(capsys, a, b)
    assert code == 1 and err == ["2 files compared: 2 differ"] and len(out) == 2
    assert out[0].startswith(f"{CUBE}: cannot read {b / CUBE} (")
    assert out[1] == f"{TABLE}: {a / TABLE} is not UTF-8 text (byte 17)"
    # damaged alike on both sides is no sameness: each side is named
    (a / CUBE).write_bytes(b"")
    assert len(result_differences(a, b)) == 3


def test_a_huge_table_is_a_difference_named_by_its_size(tmp_path, capsys, monkeypatch):
    import stonedem.study.compare as compare

    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    monkeypatch.setattr(compare, "MAX_TABLE_BYTES", 20)  # the tables are 40 bytes
    code, out, err = _compare(
        capsys, a, b
    )  # was: both read whole, 6.4 GB of memory for 2 GB tables
    assert code == 1 and out == [
        f"{TABLE}: {a / TABLE} is 0 MB, more than a study table holds (0 MB)",
        f"{TABLE}: {b / TABLE} is 0 MB, more than a study table holds (0 MB)",
    ]
    # any other file is compared in pieces: a difference past the first MiB is found
    for side, last in ((a, b"x"), (b, b"y")):
        (side / "results/cases").mkdir()
        (side / "results/cases/big.bin").write_bytes(bytes(3 * 2**20) + last)
    assert "results/cases/big.bin: differs" in result_differences(a, b)
    (b / "results/cases/big.bin").write_bytes(bytes(3 * 2**20) + b"x")
    assert not any(line.startswith("results/cases/") for line in result_differences(a, b))


def test_an_unreadable_file_is_a_difference(tmp_path, capsys, monkeypatch):
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    unreadable, read_bytes = b / TABLE, Path.read_bytes

    def refuse(path):  # root reads a chmod 000 file: refuse it here instead
        if path == unreadable:
            raise PermissionError(13, "Permission denied", str(path))
        return read_bytes(path)

    monkeypatch.setattr(Path, "read_bytes", refuse)
    assert _compare(capsys, a, b) == (
        1,
        [f"{TABLE}: cannot read {unreadable} (Permission denied)"],
        ["2 files compared: 1 differ"],
    )


def test_two_folders_with_nothing_to_compare_are_refused(tmp_path, capsys):
    for side in "ab":
        (tmp_path / side / "results/logs").mkdir(parents=True)
        (tmp_path / side / "results/logs/job.log").write_text("ran\n")  # not a study file
    code, out, err = _compare(capsys, tmp_path / "a", tmp_path / "b")
    assert code == 2 and out == [] and len(err) == 1
    assert err[0].startswith(
        "error: STUDY_A, STUDY_B: no study files (results folders {cubes,tables,"
    )


def test_wrong_arguments_give_one_line_and_exit_2(tmp_path, capsys):
    study = _study(tmp_path / "a")
    (tmp_path / "plain").write_text("")
    (tmp_path / "bare").mkdir()
    for args, expected in [
        ([study], "error: arguments: expected two study folders, got 1"),
        ([study, tmp_path / "missing"], f"error: STUDY_B: {tmp_path / 'missing'}: no such folder"),
        (
            [tmp_path / "plain", study],
            f"error: STUDY_A: {tmp_path / 'plain'} is a file, not a folder",
        ),
        (
            [study, tmp_path / "bare"],
            f"error: STUDY_B: {tmp_path / 'bare'} holds no results folder",
        ),
        (
            [study, study / "results" / ".."],
            f"error: STUDY_B: {study / 'results' / '..'} is the folder STUDY_A",
        ),
    ]:
        code, out, err = _compare(capsys, *args)
        assert code == 2 and out == [] and len(err) == 1 and err[0].startswith(expected), err
    # and so from the command line (.ci/run's call)
    proc = subprocess.run(
        [sys.executable, "-m", "stonedem.study.compare", str(study), str(tmp_path / "bare")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert (proc.returncode, proc.stdout) == (2, "") and proc.stderr.count("\n") == 1, proc.stderr


def test_a_dangling_link_is_a_difference_not_a_missing_file(tmp_path, capsys):
    """Was: a link to nothing on one side was skipped, and the two runs compared 'the same'."""
    a, b = _study(tmp_path / "a"), _study(tmp_path / "b")
    (a / "results/tables/u.csv").symlink_to("nowhere.csv")
    code, out, err = _compare(capsys, a, b)
    assert code == 1 and out == ["results/tables/u.csv: only in " + str(a)], out
    (b / "results/tables/u.csv").symlink_to("nowhere.csv")
    code, out, err = _compare(capsys, a, b)
    assert code == 1 and err == ["3 files compared: 1 differ"], err
    assert out and all(line.startswith("results/tables/u.csv: cannot read ") for line in out), out
