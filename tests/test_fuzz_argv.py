"""A fuzz of every command line (issue 31 part 5): hypothesis draws argv for every
``stonedem`` subcommand and every benchmark script from their own options and from values
and files of every kind (numbers out of range, NaN, text, a folder, a NetCDF file given as
YAML, Latin-1, a path under /proc, the input as the output...).

Whatever the argv, a command ends in exit 0 or in exit 2 with exactly one ``error:`` line on
stderr and nothing created; never a traceback, another status or a hang. A benchmark argv
always holds one bad value, so its oracle is stricter: exit 2 before any computing (a valid
benchmark run takes minutes).

The ``ci`` hypothesis profile runs 50 examples per test, ``fuzz`` (``snakemake bench_fuzz``)
10 000.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import importlib.util
import io
import os
import shutil
import signal
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from stonedem.cli import main as stonedem_main

ROOT = Path(__file__).resolve().parents[1]
HANG_SECONDS = 120  # the slowest valid argv (a wall pushover with --limit) takes ~5 s

# values that fit no option, and values that fit some
BAD_NUMBERS = [
    "nan",
    "-inf",
    "inf",
    "1e309",
    "-1",
    "0",
    "-0",
    "1e-300",
    "1e300",
    "abc",
    "",
    "0x10",
    "1_0",
]
GOOD_NUMBERS = ["1", "2", "0.5", "20", "3"]
TEXT = [
    "",
    "plain title",
    "$\\frac{$",
    "$x$",
    "a\nb",
    "\x1b[31mred",
    "é ü",
    "x" * 400,
    "-",
    "--",
    "%s%d",
]


def _arena(root: Path) -> dict[str, str]:
    """The files an argv may name, made once: good ones and every wrong kind."""
    root.mkdir(parents=True, exist_ok=True)
    scene = root / "scene.yaml"
    scene.write_text(
        (ROOT / "tests/data/scenes/rocking_block.yaml")
        .read_text()
        .replace("duration: 4.0", "duration: 0.02")
        .replace("every: 0.001", "every: 0.005")
    )
    result = root / "result.nc"
    if not result.exists():
        assert stonedem_main(["run", str(scene), "-o", str(result), "-q"]) == 0
    wall = root / "wall.yaml"
    wall.write_text(
        (ROOT / "config/walls/free_standing.yaml")
        .read_text()
        .replace("blocks_per_course: 3", "blocks_per_course: 2")
        .replace("courses: 13", "courses: 3")
    )
    shutil.copy(ROOT / "tests/data/records/synthetic_two_column.txt", root / "record.txt")
    (root / "latin1.yaml").write_bytes("bodies: [caf\xe9]\n".encode("latin-1"))
    (root / "utf16.yaml").write_bytes("bodies: []\n".encode("utf-16"))
    (root / "empty.yaml").write_bytes(b"")
    (root / "list.yaml").write_text("- 1\n- 2\n")
    (root / "deep.yaml").write_text("[" * 3000 + "]" * 3000)
    (root / "garbage.nc").write_bytes(b"\x89HDF\r\n\x1a\n" + os.urandom(200))
    (root / "text.nc").write_text("not netcdf\n")
    with open(root / "sparse.yaml", "wb") as handle:
        handle.truncate(300_000_000)
    (root / "folder").mkdir(exist_ok=True)
    return {
        "scene": str(scene),
        "result": str(result),
        "wall": str(wall),
        "record": str(root / "record.txt"),
        "latin1": str(root / "latin1.yaml"),
        "utf16": str(root / "utf16.yaml"),
        "empty": str(root / "empty.yaml"),
        "list": str(root / "list.yaml"),
        "deep": str(root / "deep.yaml"),
        "garbage": str(root / "garbage.nc"),
        "text": str(root / "text.nc"),
        "sparse": str(root / "sparse.yaml"),
        "folder": str(root / "folder"),
        "missing": str(root / "missing.yaml"),
        "proc": "/proc/stonedem-fuzz/x.nc",
        "dev_null": "/dev/null",
    }


@pytest.fixture(scope="module")
def arena(tmp_path_factory):
    root = tmp_path_factory.mktemp("argv")
    return root, _arena(root / "files")


def _inputs(files, good, *other_good):
    """Half the draws the right kind of file, half any other kind."""
    wrong = [
        files[k]
        for k in (
            *other_good,
            "latin1",
            "utf16",
            "empty",
            "list",
            "deep",
            "garbage",
            "text",
            "sparse",
            "folder",
            "missing",
            "proc",
            "dev_null",
        )
    ]
    return st.one_of(st.just(files[good]), st.sampled_from(wrong))


def _outputs(files, out_dir: Path, suffixes):
    names = [str(out_dir / f"o{s}") for s in suffixes] + [
        str(out_dir / "new folder é" / f"o{suffixes[0]}")
    ]
    return st.one_of(
        st.sampled_from(names),
        st.sampled_from(
            [
                files["folder"],
                files["scene"],
                files["result"],
                files["proc"],
                str(out_dir / "o.txt"),
                str(out_dir / ("x" * 300 + suffixes[0])),
                str(out_dir / "missing" / ".." / ".." / "o.nc"),
                "",
            ]
        ),
    )


def _options(draw, pool: dict, positional=()):
    """argv of the positionals then 0-4 options in any order, values drawn from their pools."""
    argv = [draw(s) for s in positional]
    names = draw(st.lists(st.sampled_from(sorted(pool)), max_size=4))
    for name in names:
        values = pool[name]
        argv.append(name)
        if values is not None:
            argv.append(draw(values))
    if draw(st.booleans()):
        argv = draw(st.permutations(argv))
    return argv


def _tree(root: Path) -> set:
    return {(str(p), p.stat().st_size if p.is_file() else -1) for p in root.rglob("*")}


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang(f"no answer in {HANG_SECONDS} s")


def call(main, argv, root: Path):
    """(status, stdout, stderr) of main(argv) run in-process, with a watchdog for hangs."""
    out, err = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_SECONDS)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(argv)
            except SystemExit as stop:
                status = (
                    stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
                )
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    return status, out.getvalue(), err.getvalue()


def check(main, argv, root: Path, *, must_refuse: bool = False):
    before = _tree(root)
    status, out, err = call(main, argv, root)
    shown = f"argv {argv!r}: exit {status}\n{err[-2000:]}"
    event(f"exit {status}")
    assert "Traceback" not in err and "Traceback" not in out, shown
    if must_refuse:
        assert status == 2, shown
    assert status in (0, 2), shown
    if status == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("error: "), shown
        assert _tree(root) == before, f"{shown}\ncreated: {sorted(_tree(root) - before)}"


def _command(name, draw, files, out_dir):
    numbers = st.one_of(st.sampled_from(GOOD_NUMBERS), st.sampled_from(BAD_NUMBERS))
    text = st.sampled_from(TEXT)
    if name == "run":
        sets = st.sampled_from(
            [
                "solver.duration=0.01",
                "solver.duration=0.01",
                "friction=0.5",
                "solver.duration=-1",
                "solver.duration=1e12",
                "solver.dt=nan",
                "bodies.7.mass=1",
                "x=[[[",
                "friction=é",
                "=",
                "solver=3",
                "output.every=1e-12",
                "excitation.kind=record",
                "contact.k_n=0",
                "bodies=[]",
                "solver.duration=" + "[" * 99,
            ]
        )
        return ["run"] + _options(
            draw,
            {"-o": _outputs(files, out_dir, [".nc"]), "--set": sets, "-q": None},
            [_inputs(files, "scene", "result")],
        )
    if name == "validate":
        # a valid validate runs every validation (minutes): one bad --only keeps it a question of
        # checks
        argv = ["validate", "--only", draw(st.sampled_from(["nope", "", "é", "--list"]))]
        return argv + _options(
            draw, {"-o": _outputs(files, out_dir, [""]), "--only": st.sampled_from(["x", "-"])}
        )
    if name == "record":
        return ["record", "info"] + _options(
            draw,
            {
                "--units": st.sampled_from(["g", "m/s2", "cm/s2", "furlong", ""]),
                "--dt": numbers,
                "--plot": _outputs(files, out_dir, [".png", ".svg"]),
                "--damping": numbers,
            },
            [_inputs(files, "record", "result")],
        )
    if name == "snapshots":
        return ["snapshots"] + _options(
            draw,
            {
                "-o": _outputs(files, out_dir, [".png"]),
                "-n": numbers,
                "--times": numbers,
                "--title": text,
            },
            [_inputs(files, "result", "scene")],
        )
    if name == "animate":
        return ["animate"] + _options(
            draw,
            {
                "-o": _outputs(files, out_dir, [".gif"]),
                "--fps": numbers,
                "--max-frames": numbers,
                "--every": numbers,
                "--title": text,
            },
            [_inputs(files, "result", "scene")],
        )
    if name == "wall":
        return ["wall"] + _options(
            draw,
            {"-o": _outputs(files, out_dir, [".nc"]), "--limit": None, "-q": None},
            [_inputs(files, "wall", "scene")],
        )
    raise ValueError(name)


COMMANDS = ["run", "validate", "record", "snapshots", "animate", "wall"]


@pytest.mark.parametrize("command", COMMANDS)
@settings(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data())
def test_fuzz_argv_of_every_subcommand(arena, command, data):
    root, files = arena
    out_dir = root / "out"
    out_dir.mkdir(exist_ok=True)
    argv = _command(command, data.draw, files, out_dir)
    cwd = os.getcwd()
    os.chdir(root)  # default outputs (results/...) land in the arena
    try:
        check(stonedem_main, argv, root)
    finally:
        os.chdir(cwd)


# --- benchmark scripts ------------------------------------------------------------------

BENCH_MODULES = [
    f"benchmarks.{name}"
    for name in (
        "contact_cost",
        "device_logs",
        "engine_speed",
        "ensemble",
        "equivalence_calibration",
        "fuzz",
        "gpu_check",
        "kernel",
        "restitution",
        "rounding",
        "skipping",
        "stability",
        "study_time",
        "table_a1_fits",
        "tilt_quiet_probe",
        "wall_supports",
        "wall_tables",
        "work_precision",
    )
] + ["stonedem.study.ensemble"]


@functools.cache
def _bench_main(name):
    return importlib.import_module(name).main


@functools.cache
def _bench_options(main) -> dict:
    """{option: takes a value} read from the script's own parser (argparse introspection)."""
    import argparse

    captured = {}
    real = argparse.ArgumentParser.parse_args

    def spy(self, args=None, namespace=None):
        captured["parser"] = self
        raise SystemExit(0)

    argparse.ArgumentParser.parse_args = spy
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            try:
                main(["--help"])
            except SystemExit:
                pass
    finally:
        argparse.ArgumentParser.parse_args = real
    parser = captured["parser"]
    return {
        a.option_strings[-1]: (a.nargs != 0)
        for a in parser._actions
        if a.option_strings and a.dest not in ("help",)
    }


# output options that name a file (the others name a folder)
FILE_OUTPUTS = {
    ("benchmarks.fuzz", "--out"),
    ("benchmarks.table_a1_fits", "--output"),
    ("benchmarks.stability", "--figure"),
    ("benchmarks.kernel", "--figure"),
    ("benchmarks.ensemble", "--figure"),
    ("benchmarks.study_time", "--out"),
    ("stonedem.study.ensemble", "--out"),
    ("benchmarks.equivalence_calibration", "--out"),
    ("benchmarks.tilt_quiet_probe", "--out"),
}
# wrong for any number, count, name or input file an option may take
BAD_VALUES = ["nan", "-inf", "inf", "1e309", "-1", "abc", "", "0x10", "é", "1e3e3"]


def _bad_values(script, option, files) -> list[str]:
    if any(word in option for word in ("out", "figure")):
        wrong_kind = files["folder"] if (script, option) in FILE_OUTPUTS else files["garbage"]
        return [wrong_kind, files["proc"], files["scene"] + "/x", ""]
    return BAD_VALUES + [files[k] for k in ("folder", "garbage", "latin1", "sparse", "missing")]


@pytest.mark.parametrize("script", BENCH_MODULES)
@settings(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data())
def test_fuzz_argv_of_every_benchmark_refuses_bad_values_first(arena, script, data):
    root, files = arena
    main = _bench_main(script)
    options = _bench_options(main)
    valued = sorted(k for k, takes in options.items() if takes)
    assert valued, f"{script} has no option that takes a value"
    others = data.draw(st.lists(st.sampled_from(sorted(options)), max_size=2))
    argv = []
    for name in others:
        argv.append(name)
        if options[name]:
            argv.append(data.draw(st.sampled_from(BAD_VALUES + ["1", "2", "0.5", "3"])))
    bad_option = data.draw(st.sampled_from(valued))
    argv += [bad_option, data.draw(st.sampled_from(_bad_values(script, bad_option, files)))]
    cwd = os.getcwd()
    os.chdir(root)
    try:
        check(main, argv, root, must_refuse=True)
    finally:
        os.chdir(cwd)
