"""Every YAML input file the user hands us (stonedem.io.yaml_file): the wrong kind of file,
encoding, size or depth is one line naming the file, before anything is computed; the
commands that read scenes and configs refuse in one line and exit 2."""

import subprocess
import sys
import time
from pathlib import Path

import pytest

from stonedem.errors import InputError
from stonedem.io.yaml_file import read_yaml_mapping

FIX = "give keys"
HOSTILE = {
    "latin1.yaml": (
        "bodies: [caf\xe9]\n".encode("latin-1"),
        r"not UTF-8 text \(byte 0xe9 at offset 12",
    ),
    "utf16.yaml": ("bodies: []\n".encode("utf-16"), "is UTF-16 text"),
    "binary.yaml": (b"abc\x00\x01\x02", "binary file"),
    "hdf5.nc": (b"\x89HDF\r\n\x1a\n" + b"\x00" * 64, "is a NetCDF-4/HDF5 file, not a scene"),
    "classic.nc": (b"CDF\x01" + b"\x00" * 64, "is a NetCDF file"),
    "deep.yaml": (b"[" * 5000 + b"]" * 5000, "nested deeper than 32 levels"),
    "twice.yaml": (b"a: 1\na: 2\n", "the key 'a' is given twice"),
    "list.yaml": (b"- 1\n- 2\n", r"is not a YAML mapping \(it holds a list\)"),
    "empty.yaml": (b"# nothing\n", "is empty"),
    "bad.yaml": (b"bodies: [\n  {name: a\n", r"not valid YAML: .*line 3"),
    "laughs.yaml": (
        None,
        r"aliases expand to more than 1000000 values and characters \(line 9, column 15\); write ",
    ),
    "loop.yaml": (b"bodies: &b [1, *b]\n", r"the alias \*b is inside its own anchor \(a loop\)"),
}


def billion_laughs(levels: int = 9) -> bytes:
    """A 1 kB scene whose description is 10^levels strings through nested aliases."""
    rows = ["name: bomb", "description:", "  - &l0 lol"]
    rows += [f"  - &l{i} [" + ", ".join([f"*l{i - 1}"] * 10) + "]" for i in range(1, levels + 1)]
    return ("\n".join(rows) + "\nbodies: []\n").encode()


HOSTILE["laughs.yaml"] = (billion_laughs(), HOSTILE["laughs.yaml"][1])


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_a_hostile_file_is_one_line_naming_it(tmp_path, name):
    data, message = HOSTILE[name]
    path = tmp_path / name
    path.write_bytes(data)
    start = time.perf_counter()
    with pytest.raises(InputError, match=message) as err:
        read_yaml_mapping(path, "a scene file", 10_000, FIX)
    assert err.value.field == str(path) and "\n" not in str(err.value)
    assert (
        time.perf_counter() - start < 2.0
    )  # the depth is refused from the tokens, not by recursion


def test_size_is_checked_before_reading(tmp_path):
    path = tmp_path / "big.yaml"
    with open(path, "wb") as handle:
        handle.truncate(200_000_000)  # sparse: 200 MB that take no disk
    start = time.perf_counter()
    with pytest.raises(InputError, match="200000000 bytes exceed the limit of 10000"):
        read_yaml_mapping(path, "a scene file", 10_000, FIX)
    assert time.perf_counter() - start < 1.0


def test_folders_fifos_and_missing_files(tmp_path):
    import os

    with pytest.raises(InputError, match="is a folder, not a scene file"):
        read_yaml_mapping(tmp_path, "a scene file", 10_000, FIX)
    with pytest.raises(InputError, match="a scene file not found"):
        read_yaml_mapping(tmp_path / "nope.yaml", "a scene file", 10_000, FIX)
    fifo = tmp_path / "fifo.yaml"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match="not a regular file"):  # reading it would hang
        read_yaml_mapping(fifo, "a scene file", 10_000, FIX)


def test_a_bom_and_an_empty_config_are_fine(tmp_path):
    path = tmp_path / "bom.yaml"
    path.write_bytes("\ufeffa: 1\n".encode("utf-8"))
    assert read_yaml_mapping(path, "a config file", 10_000, FIX) == {"a": 1}
    path.write_bytes(b"")
    assert read_yaml_mapping(path, "a config file", 10_000, FIX, allow_empty=True) == {}


@pytest.mark.parametrize("name", ["latin1.yaml", "hdf5.nc", "deep.yaml"])
def test_run_refuses_a_hostile_scene_in_one_line(tmp_path, name):
    data, message = HOSTILE[name]
    scene = tmp_path / name
    scene.write_bytes(data)
    out = tmp_path / "out" / "x.nc"
    proc = subprocess.run(
        [sys.executable, "-m", "stonedem", "run", str(scene), "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert (
        proc.stderr.count("\n") == 1
        and proc.stderr.startswith("error: ")
        and "Traceback" not in proc.stderr
    )
    assert not (tmp_path / "out").exists()


def test_a_deep_set_value_is_one_line(tmp_path):
    from stonedem.engine.scene import apply_overrides

    with pytest.raises(InputError, match="--set 'solver.dt'.*nested deeper"):
        apply_overrides({}, ["solver.dt=" + "[" * 2000])


def test_aliases_count_as_what_they_repeat():
    from stonedem.io.yaml_file import MAX_ALIAS_EXPANSION, parse_yaml_text

    # 5 levels of 10 are 10^5 strings of 3 characters: 4 units each, past the limit at level 6
    assert len(parse_yaml_text(billion_laughs(5).decode(), "f")["description"][5]) == 10
    with pytest.raises(InputError, match="aliases expand to more than"):
        parse_yaml_text(billion_laughs(6).decode(), "f")
    assert MAX_ALIAS_EXPANSION == 1_000_000
    # a merge key is an alias too
    with pytest.raises(InputError, match="aliases expand"):
        parse_yaml_text("a: &a {x: '" + "y" * 600_000 + "'}\nb: {<<: *a}\nc: {<<: *a}\n", "f")


def test_the_study_config_keeps_its_anchors():
    import yaml

    from stonedem.study.grid import MAX_CONFIG_BYTES

    path = Path(__file__).parents[2] / "config" / "config.yaml"
    config = read_yaml_mapping(path, "a config file", MAX_CONFIG_BYTES, FIX)
    with open(path) as handle:
        assert config == yaml.safe_load(handle)
