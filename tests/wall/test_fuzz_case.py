"""Hostile wall input: fuzzed case mappings (validation only), bad case files, the CLI's exit
conventions (exit 2, one line, no file), SIGINT/SIGTERM during a real pushover (130/143 within a
second, no file), progress lines, and an honest status when no limit load was reached.

``HYPOTHESIS_PROFILE=fuzz python3 -m pytest tests/wall -k fuzz`` runs 10 000 examples per test.
"""

from __future__ import annotations

import math
import re
import signal
import subprocess
import sys
import time

import pytest
import yaml
from hypothesis import given

from stonedem.errors import InputError
from stonedem.wall import case as wall_case
from stonedem.wall.case import MAX_BLOCKS, MAX_MEMORY_BYTES, check_case, read_case
from stonedem.wall.pushover import SolverSettings
from tests.signals import interrupt_after_line
from tests.wall import case_mutations as M

FIELD = re.compile(r"[A-Za-z_][A-Za-z_0-9]*(\[\d+\])?(\.[A-Za-z_0-9]+(\[\d+\])?)*")
DEFAULTS = SolverSettings().as_dict()


def outcome(spec, expect):
    """Validate; assert the InputError names a field (the expected one when given) in one line,
    or that the parsed case is sane."""
    try:
        ci = check_case(spec)
    except InputError as err:
        message = str(err)
        assert "\n" not in message and len(message) < 600, message
        assert err.field and err.problem and err.fix, message
        if expect[0] == "refuse":
            # the field itself, or an item of it (reference.p_experiment[0])
            assert err.field == expect[1] or err.field.startswith(expect[1] + "["), (
                f"expected an error on {expect[1]}, got: {message}"
            )
        else:
            assert FIELD.fullmatch(err.field), message
        return "refused"
    assert expect[0] == "any", f"{expect[1]} = {_value(spec, expect[1])!r} was accepted"
    assert_sane(ci)
    return "accepted"


def _value(spec, path):
    node = spec
    try:
        for step in M._steps(path):
            node = node[step]
    except (KeyError, IndexError, TypeError):
        return "(missing)"
    return node


def assert_sane(ci):
    for name in (
        "a",
        "b",
        "s",
        "blocks_per_course",
        "unit_weight",
        "joint_thickness",
        "lintel_strength",
    ):
        v = getattr(ci, name)
        assert type(v) is float and math.isfinite(v) and v >= 0, (name, v)
    assert min(ci.a, ci.b, ci.s, ci.unit_weight) > 0
    assert type(ci.courses) is int and ci.courses >= 1
    assert ci.blocks_per_course >= 1 and (2 * ci.blocks_per_course).is_integer()
    assert type(ci.first_course_offset) is bool and type(ci.extra_live) is bool
    for key, v in ci.joint.items():
        assert type(v) is float and math.isfinite(v) and v >= 0, (key, v)
    assert (
        ci.joint["mu"] > 0
        and ci.joint["k_n"] > 0
        and ci.joint["k_t"] > 0
        and ci.joint["alpha"] >= 1
    )
    for jp in ci.support_joint.values():
        assert all(type(v) is float and math.isfinite(v) for v in jp.values())
    for count, force, _edge in ci.extras:
        assert type(count) is int and count >= 1 and math.isfinite(force) and force >= 0
    for key, v in ci.settings.as_dict().items():
        assert type(v) is type(DEFAULTS[key]) and math.isfinite(v) and v >= 0, (key, v)
    s = ci.settings
    assert s.max_steps >= 1 and s.max_iterations >= 2 and s.tolerance > 0 and s.growth >= 1
    assert s.residual_stiffness > 0 and s.min_load_step > 0
    assert ci.control_block is None or (
        type(ci.control_block) is int and 0 <= ci.control_block < ci.size.n_blocks
    )
    assert 1 <= ci.size.n_blocks <= MAX_BLOCKS and ci.size.memory_bytes <= MAX_MEMORY_BYTES
    assert M.is_finite_tree(ci.spec.get("reference", {}))


# --- fuzzing the validator (no building, no pushover) -----------------------------------------


@given(M.bad_value_case())
def test_fuzz_wrong_type_or_out_of_range_value_is_refused_naming_its_field(example):
    assert outcome(*example) == "refused"


@given(M.unknown_key_case())
def test_fuzz_unknown_key_is_refused_naming_it(example):
    spec, expect = example
    try:
        check_case(spec)
    except InputError as err:
        assert (
            err.field == expect[1]
            and err.problem == "unknown key"
            and err.fix.startswith("allowed keys: ")
        )
    else:
        raise AssertionError(f"unknown key {expect[1]} accepted")


@given(M.missing_key_case())
def test_fuzz_missing_key_is_refused_when_required(example):
    outcome(*example)


@given(M.any_value_case())
def test_fuzz_arbitrary_values_are_refused_or_parse_sanely(example):
    outcome(*example)


@given(M.extreme_number_case())
def test_fuzz_extreme_numbers_are_refused_or_parse_sanely(example):
    outcome(*example)


@given(M.size_case())
def test_fuzz_wall_size_is_held_to_the_limits_before_building(example):
    t0 = time.perf_counter()
    try:
        check_case(example[0])
    except InputError as err:
        assert err.field in (
            "panel",
            "solver.max_steps",
            "solver.control_block",
        ) or err.field.startswith("panel."), str(err)
        if "n_blocks" in err.problem:
            assert f"exceeds the limit {MAX_BLOCKS}" in err.problem
    assert time.perf_counter() - t0 < 0.5, "validation estimates the size, it builds nothing"


# --- the issue's findings, one by one ---------------------------------------------------------


def base():
    return yaml.safe_load((M.CASES / "s32.yaml").read_text())


@pytest.mark.parametrize(
    "path, value, problem",
    [
        ("panel.first_course_offset", "false", "expected true or false"),  # was True
        ("load.extra_in_live_load", "false", "expected true or false"),
        ("load.extra_vertical[0].count", 0.5, "must be an integer, got a number 0.5"),  # was 0
        ("solver.max_steps", 0, "must be >= 1 and <= 1e+06, got 0"),  # was lambda_max 0, exit 0
        ("solver.secant", 0.5, "expected 0 or 1, got a number 0.5"),
        ("panel.courses", 13.5, "must be an integer, got a number 13.5"),
        ("joints.mu", "0.7x", "expected a number"),
        ("joints.k_n", float("nan"), "not finite"),
        ("panel.unit_weight", 10**400, "out of range"),
        ("panel", 3, "expected a mapping"),
        ("restraints", {"edge": "base"}, "expected a list"),
        ("load.extra_vertical", 11, "expected a list"),
        ("solver", [], "expected a mapping"),
        ("solver.tolerance", 0, "must be >= 1e-12 and <= 0.1, got 0"),
        ("solver.residual_stiffness", 0, "must be > 0 and <= 1, got 0"),
        (
            "solver.tolerance",
            1e-30,
            "must be >= 1e-12 and <= 0.1, got 1e-30",
        ),  # was "restraints: leave a mechanism"
        ("solver.first_step", 1e-300, "below 1e-12 m"),  # was lambda_max 4e-270, exit 0
    ],
)
def test_issue_findings_are_refused(path, value, problem):
    spec = base()
    M._set(spec, path, value)
    with pytest.raises(InputError) as err:
        check_case(spec)
    assert err.value.field == path and problem in err.value.problem, str(err.value)


def test_a_wall_of_100000_courses_is_refused_at_once_with_the_limit():
    spec = base()
    spec["panel"]["courses"] = 100_000
    t0 = time.perf_counter()
    with pytest.raises(
        InputError, match=rf"^panel: n_blocks 1\.45e\+06 exceeds the limit {MAX_BLOCKS} "
    ):
        check_case(spec)
    assert time.perf_counter() - t0 < 0.1


def test_every_manuscript_case_is_valid_and_well_inside_the_limits():
    for path in sorted(M.CASES.glob("*.yaml")):
        ci = check_case(read_case(path))
        assert (
            ci.size.n_blocks <= MAX_BLOCKS / 10 and ci.size.memory_bytes <= MAX_MEMORY_BYTES / 10
        ), path.name
        assert ci.size.factor_seconds < 0.1, path.name


@pytest.mark.parametrize(
    "content, problem",
    [
        (b"\xff\xfe\x00p\x00a", "UTF-16"),
        (b"", "is empty"),
        (b"# only a comment\n", "is empty"),
        (b"panel: [1, 2\n", "not valid YAML"),
        (b"\tpanel: 1\n", "not valid YAML"),
        (b"- panel\n- joints\n", "is not a YAML mapping"),
        (b"just text", "is not a YAML mapping"),
        (b"panel: 1\npanel: 2\n", "the key 'panel' is given twice"),
        (b"a: !!python/object:os.system {}\n", "not valid YAML"),
        (b"a: \x07\n", "not valid YAML"),
        (b"[" * 5000 + b"]" * 5000, "not valid YAML"),
        (b"#" * (wall_case.MAX_CASE_BYTES + 1), "exceed the limit"),
    ],
    ids=lambda v: v[:20] if isinstance(v, bytes) else v,
)
def test_bad_case_file_is_one_line_naming_the_file(tmp_path, content, problem):
    path = tmp_path / "case.yaml"
    path.write_bytes(content)
    with pytest.raises(InputError) as err:
        read_case(path)
    assert err.value.field == str(path) and problem in err.value.problem, str(err.value)
    assert "\n" not in str(err.value)


def test_yaml_alias_bomb_is_refused_without_expanding_it(tmp_path):
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{k}: &a{k} [{', '.join([f'*a{k - 1}'] * 10)}]" for k in range(1, 9)]  # 1e9 leaves
    for where in ("panel: *a8", "description: *a8", "reference: {p_experiment: *a8}"):
        path = tmp_path / "bomb.yaml"
        path.write_text("\n".join(lines) + "\n" + where + "\n")
        t0 = time.perf_counter()
        with pytest.raises(InputError) as err:
            check_case(read_case(path))
        assert time.perf_counter() - t0 < 1.0 and len(str(err.value)) < 300, str(err.value)


def test_missing_or_directory_case_file(tmp_path):
    with pytest.raises(InputError, match="a wall case file not found"):
        read_case(tmp_path / "nope.yaml")
    with pytest.raises(InputError, match="is a folder"):
        read_case(tmp_path)


# --- honest status ------------------------------------------------------------------------


def test_a_path_cut_short_says_it_reached_no_limit():
    from stonedem.wall.case import case_from_dict
    from stonedem.wall.dataset import wall_dataset
    from stonedem.wall.pushover import pushover

    spec = yaml.safe_load((M.CASES / "free_standing.yaml").read_text())
    spec["solver"] = {"max_steps": 3}
    case = case_from_dict(spec)
    ds = wall_dataset(case, pushover(case.model, case.settings))
    assert ds.attrs["limit_reached"] == "no"
    assert ds.attrs["status"].startswith("stopped: max_steps; no limit load reached")
    assert "solver.max_steps" in ds.lambda_max.attrs["comment"]
    spec["solver"] = {"max_displacement": 1e-5}  # stopped on the elastic branch
    case = case_from_dict(spec)
    ds = wall_dataset(case, pushover(case.model, case.settings))
    assert ds.attrs["limit_reached"] == "no" and "still rose" in ds.attrs["status"]
    spec.pop("solver")  # the full run: plateau
    case = case_from_dict(spec)
    ds = wall_dataset(case, pushover(case.model, case.settings))
    assert ds.attrs["limit_reached"] == "yes" and "no limit" not in ds.attrs["status"]


# --- command line -------------------------------------------------------------------------


def test_progress_log_is_quiet_on_short_runs_and_periodic_on_long_ones():
    import io

    from stonedem.wall.cli import ProgressLog

    out = io.StringIO()
    log = ProgressLog(out, every=2.0)
    for step in range(100):
        log(step, 0.1, 1e-3)
    assert out.getvalue() == ""
    log = ProgressLog(out, every=0.0)
    log(120, 0.31, 2.1e-3)
    log(121, 0.31, float("nan"), "no convergence in 25 iterations")
    lines = out.getvalue().splitlines()
    assert re.fullmatch(r"pushover: step 120, lambda 0\.31, u 0\.0021 m, \d+\.\d s", lines[0]), (
        lines
    )
    assert "step 121" in lines[1] and "no convergence" in lines[1]


def wall(*args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "stonedem.wall", *args], capture_output=True, text=True, **kw
    )


@pytest.fixture
def in_process(capsys):
    """``stonedem.wall.cli.main`` in this process (no interpreter start-up); restores the signal
    handlers ``stonedem.entry.guarded`` installs. Returns (status, stderr lines)."""
    from stonedem.wall.cli import main

    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}

    def run(*args):
        try:
            status = main(list(args))
        finally:
            for s, h in handlers.items():
                signal.signal(s, h)
        return status, capsys.readouterr().err.splitlines()

    return run


def hostile_files(folder):
    good = (M.CASES / "free_standing.yaml").read_text()
    (folder / "bool.yaml").write_text(
        good.replace("unit_weight: 20000.0", "unit_weight: 20000.0\n  first_course_offset: 'false'")
    )
    (folder / "huge.yaml").write_text(good.replace("courses: 13", "courses: 100000"))
    (folder / "steps.yaml").write_text(good + "solver: {max_steps: 0}\n")
    (folder / "latin1.yaml").write_bytes(good.encode() + "# m\xe9lange\n".encode("latin-1"))
    (folder / "case.nc").write_text(good)
    (folder / "sub").mkdir()
    return good


HOSTILE_RUNS = [
    (["bool.yaml", "-o", "out.nc"], "error: panel.first_course_offset: expected true or false"),
    (
        ["huge.yaml", "-o", "out.nc"],
        f"error: panel: n_blocks 3.5e+05 exceeds the limit {MAX_BLOCKS} ",
    ),
    (
        ["steps.yaml", "-o", "out.nc"],
        "error: solver.max_steps: must be >= 1 and <= 1e+06, got 0; give a value >= 1",
    ),
    (["latin1.yaml", "-o", "out.nc"], "error: latin1.yaml: is not UTF-8 text"),
    (["missing.yaml", "-o", "out.nc"], "error: missing.yaml: a wall case file not found"),
    ([".", "-o", "out.nc"], "error: .: is a folder"),
    (["case.nc", "-o", "case.nc"], "error: -o/--output: case.nc is the input file"),
    (["case.nc", "-o", "sub"], "error: -o/--output: sub does not end in .nc"),
    (["case.nc", "-o", "sub/../case.nc"], "error: -o/--output: sub/../case.nc is the input file"),
    (["case.nc", "-o", "case.nc/out.nc"], "error: -o/--output: case.nc is a file, not a folder"),
]


def test_cli_in_process_refuses_hostile_input_in_one_line_with_exit_2_and_no_file(
    tmp_path, monkeypatch, in_process
):
    hostile_files(tmp_path)
    (tmp_path / "sub" / "x.nc").mkdir()
    monkeypatch.chdir(tmp_path)
    for args, start in HOSTILE_RUNS + [
        (["case.nc", "-o", "sub/x.nc"], "error: -o/--output: sub/x.nc is a directory")
    ]:
        before = sorted(str(p) for p in tmp_path.rglob("*"))
        status, err = in_process(*args)
        assert status == 2 and len(err) == 1 and err[0].startswith(start), (args, err)
        assert sorted(str(p) for p in tmp_path.rglob("*")) == before, "nothing written"


def test_cli_subprocess_refuses_hostile_input_in_one_line_with_exit_2_and_no_file(tmp_path):
    hostile_files(tmp_path)
    for args, start in [HOSTILE_RUNS[0], HOSTILE_RUNS[3], HOSTILE_RUNS[6]]:
        before = sorted(str(p) for p in tmp_path.rglob("*"))
        proc = wall(*args, cwd=tmp_path)
        lines = proc.stderr.splitlines()
        assert proc.returncode == 2 and len(lines) == 1 and lines[0].startswith(start), (
            args,
            proc.stderr,
        )
        assert proc.stdout == "" and sorted(str(p) for p in tmp_path.rglob("*")) == before, (
            "nothing written"
        )


def test_cli_short_run_prints_only_its_summary(tmp_path, in_process):
    status, err = in_process(str(M.CASES / "free_standing.yaml"), "-o", str(tmp_path / "fs.nc"))
    assert (
        status == 0
        and len(err) == 1
        and err[0].startswith(f"wrote {tmp_path / 'fs.nc'}: lambda_max")
    ), err
    assert (
        "(stopped: plateau" in err[0]
        and (tmp_path / "fs.nc").is_file()
        and not list(tmp_path.glob(".*"))
    )
    status, err = in_process(
        str(M.CASES / "free_standing.yaml"), "-o", str(tmp_path / "fs.nc"), "-q"
    )
    assert status == 0 and err == []


# --- signals --------------------------------------------------------------------------------

LONG = """\
panel: {block: {a: 0.081, b: 0.21, s: 0.07}, blocks_per_course: 3, courses: 13,
       unit_weight: 20000.0}
joints: {kind: dry, mu: 0.7, k_n: 2.4e9, k_t: 1.0e9}
restraints: [{edge: base, fix: all}]
load: {kind: proportional, direction: out_of_plane}
# thousands of tiny steps: a pushover of minutes made of ~10 ms steps
solver: {first_step: 1.0e-7, growth: 1.0, plateau_steps: 1000000, max_steps: 200000}
"""


@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_signal_during_pushover_exits_at_once_and_leaves_no_file(tmp_path, signum, status):
    (tmp_path / "long.yaml").write_text(LONG)
    out = tmp_path / "long.nc"
    # stderr is a pipe, not a terminal: the progress log must still come
    code, elapsed, seen = interrupt_after_line(
        [sys.executable, "-m", "stonedem.wall", "long.yaml", "-o", out.name],
        lambda line: line.startswith("pushover: step"),
        signum,
        60,
        cwd=tmp_path,
    )
    assert re.fullmatch(r"pushover: step \d+, lambda \S+, u \S+ m, \d+\.\d s\n", seen[-1]), seen
    assert code == status and elapsed < 1.0, (code, elapsed)
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["long.yaml"]
