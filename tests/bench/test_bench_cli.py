"""Every benchmark's command line refuses a bad option or output path before running anything:
one line ``error: <field>: ...``, exit 2, and no file or folder created (issue: hostile round).

The mains run in this process; each refusal comes before any simulation, so the file takes
seconds. workflow/scripts/bench.py is run with a stand-in for Snakemake's ``snakemake``
object.
"""

import csv
import importlib
import runpy
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from benchmarks import (
    fuzz,
    kernel,
    options,
    restitution,
    skipping,
)
from stonedem.errors import InputError
from stonedem.kernels.gpu import gpu_available

ROOT = Path(__file__).resolve().parents[2]


# on a machine whose GPU can run the loop, gpu_check runs instead of refusing
NO_GPU_REFUSAL_SKIPPED = gpu_available()[0]


def main_of(name):
    return importlib.import_module(f"benchmarks.{name}").main


def tree(folder):
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*"))


def refused(main, argv, field, folder, capsys):
    """main(argv) exits 2 with one 'error:' line holding ``field``; nothing appears under folder."""
    before = tree(folder)
    try:
        status = main(argv)
    except SystemExit as stop:  # a usage error of the parser
        status = stop.code
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert status == 2, (argv, captured.err)
    assert len(lines) == 1 and lines[0].startswith("error: ") and field in lines[0], (argv, lines)
    assert captured.out == "", "nothing runs, nothing is printed"
    assert tree(folder) == before, f"{argv} created {sorted(set(tree(folder)) - set(before))}"
    return lines[0]


@pytest.fixture
def places(tmp_path):
    """tmp_path with a plain file in it; {name: path} of the places the cases below point at."""
    (tmp_path / "file").write_text("not a folder\n")
    (tmp_path / "bad.yaml").write_text("studies: [unclosed\n")
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    (tmp_path / "taken" / "skipping.nc").mkdir(parents=True)
    return {
        "new": str(tmp_path / "new"),  # does not exist: must still not exist after a refusal
        "file": str(tmp_path / "file"),
        "under_file": str(tmp_path / "file" / "sub"),
        "proc": "/proc/stonedem_bench",
        "taken": str(tmp_path / "taken"),
        "bad_yaml": str(tmp_path / "bad.yaml"),
        "list_yaml": str(tmp_path / "list.yaml"),
        "missing": str(tmp_path / "missing.yaml"),
        "folder": str(tmp_path),
    }


# (script, argv with {place} fields, the field the error line names): one smoke test per
# script that its main refuses through the shared kit (benchmarks.options) before running; the
# kit's own checks are tested below and every option of every script is fuzzed by
# tests/test_fuzz_argv.py
CASES = [
    ("kernel", ["--parent", "no-such-commit", "--out", "{new}"], "--parent"),
    ("ensemble", ["--scene", "nope", "--out", "{new}"], "--scene"),
    *([("gpu_check", ["--out", "{new}"], "device")] if not NO_GPU_REFUSAL_SKIPPED else []),
    ("gpu_check", ["--records", "-1", "--out", "{new}"], "--records"),
    ("study_time", ["--target", "everything", "--out", "{new}/t.csv"], "--target"),
    ("contact_cost", ["--sizes", "5", "5", "--out", "{new}"], "--sizes"),
    ("fuzz", ["--out", "{new}/fuzz.txt"], "--out"),
    ("restitution", ["--out", "{new}", "--config", "{bad_yaml}"], "--config"),
    ("skipping", ["--out", "{taken}"], "--out"),
    ("stability", ["--out", "{new}", "--figure", "{new}/m.txt"], "--figure"),
    ("work_precision", ["--out", "{new}", "--figures", "{file}"], "--figures"),
    ("geometry_band", ["--work", "{folder}", "--out", "{new}/g.nc"], "--work"),
    ("engine_speed", ["--out", "{under_file}"], "--out"),
    ("table_a1_fits", ["-o", "{new}/fits.txt"], "-o/--output"),
    ("wall_supports", ["--only", "../../etc/passwd", "--out", "{new}"], "--only"),
    ("wall_tables", ["--only", "free_standing", "--out", "{new}"], "--only"),
]


@pytest.mark.parametrize(
    "name, argv, field", CASES, ids=[f"{c[0]}:{' '.join(c[1][:2])}" for c in CASES]
)
def test_bad_option_is_refused_before_running(places, tmp_path, capsys, name, argv, field):
    argv = [a.format(**places) for a in argv]
    refused(main_of(name), argv, field, tmp_path, capsys)
    assert not Path(places["new"]).exists()


def test_wall_tables_negative_budget_writes_no_table(tmp_path, capsys):
    """Once, with a negative budget, every case 'ran' in no time and a table of lambda = 0 was
    written."""
    line = refused(
        main_of("wall_tables"),
        ["--max-seconds", "-1", "--out", str(tmp_path / "walls")],
        "--max-seconds",
        tmp_path,
        capsys,
    )
    assert "> 0" in line
    assert not (tmp_path / "walls").exists()


def bench_script(rule, outputs, log, quick=False, config="config/quick.yaml"):
    """Run workflow/scripts/bench.py as Snakemake would, with a stand-in ``snakemake``; its exit
    status."""
    sm = SimpleNamespace(
        rule=rule,
        output=[str(p) for p in outputs],
        log=[str(log)],
        params=SimpleNamespace(quick=quick, config=config),
        scriptdir=str(ROOT / "workflow" / "scripts"),
    )
    stdout, stderr = sys.stdout, sys.stderr
    try:
        runpy.run_path(
            str(ROOT / "workflow" / "scripts" / "bench.py"), init_globals={"snakemake": sm}
        )
        status = 0
    except SystemExit as stop:
        status = stop.code
    finally:
        sys.stderr.close()  # the script's log file
        sys.stdout, sys.stderr = stdout, stderr
    return status


@pytest.mark.parametrize(
    "rule, outputs, field",
    [
        ("bench_nonsense", ["{new}/x.nc"], "rule"),
        ("bench_skipping", ["{new}/other_name.nc"], "bench_skipping.output"),
        ("bench_skipping", ["{file}/skipping.nc"], "--out"),
        (
            "bench_stability",
            ["{new}/stability_map.nc", "{new}/auto_dt_margin.nc", "{file}/map.png"],
            "--figure",
        ),
        (
            "bench_contact_cost",
            ["{proc}/bench/contact_cost.nc", "{proc}/figures/contact_cost.png"],
            "--out",
        ),
    ],
)
def test_workflow_script_refuses_before_running(places, tmp_path, rule, outputs, field):
    logs = tmp_path / "logs"
    logs.mkdir()
    log = logs / "bench.log"
    before = tree(tmp_path)
    status = bench_script(rule, [o.format(**places) for o in outputs], log)
    lines = log.read_text().strip().splitlines()
    assert status == 2, lines
    assert len(lines) == 1 and lines[0].startswith("error: ") and field in lines[0], lines
    assert tree(tmp_path) == sorted([*before, "logs/bench.log"]), "only the log is written"
    assert not Path(places["new"]).exists()


def test_numbers_and_paths_helpers(tmp_path):
    assert options.number(3, "--n", lo=1, hi=5, whole=True) == 3
    assert options.number(0.5, "--x", lo=0, lo_open=True) == 0.5
    for bad in (float("nan"), float("inf"), -1.0, 0.0, True, "1"):
        with pytest.raises(InputError, match="--x"):
            options.number(bad, "--x", lo=0, lo_open=True, hi=10)
    with pytest.raises(InputError, match="whole"):
        options.number(1.5, "--n", whole=True)
    with pytest.raises(InputError, match="given twice"):
        options.chosen(["a", "a"], "--c", "ab")
    target = tmp_path / "a" / "b" / "out.csv"
    assert options.output_file(target, "-o", suffixes=(".csv",)) == target
    assert not (tmp_path / "a").exists(), "checking a path creates nothing"
    written = options.write_csv(target, [{"x": 1, "y": 2}])
    assert written.read_bytes() == b"x,y\r\n1,2\r\n"  # as csv writes it
    assert [p.name for p in target.parent.iterdir()] == ["out.csv"], "no temporary file left"


def test_an_output_is_never_an_empty_path_or_a_foreign_file(tmp_path, capsys):
    """An empty --out would be the current folder; a .nc output replaces only an earlier
    NetCDF result, not a file of another kind bearing the name."""
    refused(restitution.main, ["--out", ""], "--out", tmp_path, capsys)
    refused(skipping.main, ["--out", " ", "--limit", "1"], "--out", tmp_path, capsys)
    foreign = tmp_path / "notes.nc"
    foreign.write_text("my notes\n")
    refused(restitution.main, ["--out", str(foreign)], "--out", tmp_path, capsys)
    refused(fuzz.main, ["--out", str(foreign)], "--out", tmp_path, capsys)
    assert foreign.read_text() == "my notes\n"


def test_study_time_keeps_the_other_targets_rows_and_times_one_commit_with_parent_none(
    tmp_path, monkeypatch, capsys
):
    """A fragility run (--parent none: this commit alone) replaces only the fragility rows of
    an earlier run's CSV; the study's rows stay (the clones are stood in for)."""
    module = importlib.import_module("benchmarks.study_time")
    calls = []

    def fake_run(commit, target, configfiles, workdir):
        calls.append((commit, target))
        return {"wall_seconds": 10.0 * len(calls), "exit_status": 0, "jobs": 3}

    monkeypatch.setattr(module, "run_target", fake_run)
    out = tmp_path / "t.csv"
    assert module.main(["--parent", "HEAD", "--out", str(out)]) == 0
    assert module.main(["--parent", "none", "--target", "fragility", "--out", str(out)]) == 0
    assert module.main(["--parent", "none", "--target", "fragility", "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    assert [(r["target"], r["version"], r["wall_seconds"]) for r in rows] == [
        ("all", "current", "10.0"),
        ("all", "parent", "20.0"),
        ("fragility", "current", "40.0"),
    ]
    assert [target for _, target in calls] == ["all", "all", "fragility", "fragility"]
    assert "fragility: 40 s; wrote" in capsys.readouterr().out


def test_kernel_dataset_says_which_of_the_issue_targets_are_met():
    """kernel.nc carries issue 32's bounds and, per scene, met (1), missed (0) or none (-1)."""
    rows, stages = {}, {}
    for name in kernel.SCENES:
        ns = {"lone_block": 149.0, "column_8": 71.0 * 9}.get(name, 1000.0)
        one = {
            "ns_per_step": ns,
            "contacts": 9.0 if name == "column_8" else 1.0,
            "python_ns_per_step": 1.0,
            "steps": 10.0,
            "dt": 1e-4,
        }
        rows[name] = {"current": one, "parent": dict(one, ns_per_step=2 * ns), "n_body": 2}
        stages[name] = {k: 1.0 for k in kernel.STAGES}
    ds = kernel.kernel_dataset(rows, stages, "abc", "compared", True)
    met = dict(zip(ds["scene"].values, ds["target_met"].values))
    assert (
        met["lone_block"] == 1
        and met["column_8"] == 0
        and met["colonnade_3x3"] == 0
        and met["column_30"] == -1
    )
    assert float(ds["target_ns"].sel(scene="column_8")) == 70.0 and np.isnan(
        float(ds["target_ns"].sel(scene="column_1"))
    )
    assert ds["target_met"].attrs["flag_meanings"] == "no_target missed met"
    from stonedem.io.schema import missing_metadata

    assert missing_metadata(ds) == []
