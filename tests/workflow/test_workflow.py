"""The Snakemake workflow: lint clean, config validated, committed records up to date."""

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np


ROOT = Path(__file__).resolve().parents[2]


def snakemake(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=cwd, capture_output=True, text=True)


def test_lint_is_clean():
    for args in ((), ("--config", "extract_records=true")):
        proc = snakemake("--lint", *args)
        assert proc.returncode == 0, proc.stdout + proc.stderr


def test_committed_records_need_no_rerun():
    assert len(list((ROOT / "records").glob("*.nc"))) == 4
    proc = snakemake("-n", "--configfile", "tests/workflow/config.yaml")
    assert proc.returncode == 0, proc.stderr
    assert "extract_record" not in proc.stdout, proc.stdout


def test_extraction_rule_on_request():
    proc = snakemake("-n", "--config", "extract_records=true", "--forcerun", "extract_record")
    assert proc.returncode == 0, proc.stderr
    assert "extract_record" in proc.stdout


def test_bad_config_is_refused(tmp_path):
    for item in ("Snakefile", "workflow", "records"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "config.yaml").write_text(
        "records:\n  x: {set: farfield, id: 0, component: c}\n")
    proc = snakemake("-n", cwd=tmp_path)
    assert proc.returncode != 0
    assert "ValidationError" in proc.stdout + proc.stderr or "validat" in (proc.stdout + proc.stderr).lower()


def test_tiny_study_runs_end_to_end_and_is_deterministic(tmp_path):
    for item in ("Snakefile", "workflow", "records", "config"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp_path / item)
    shutil.copy(ROOT / "tests" / "workflow" / "config.yaml", tmp_path / "tiny.yaml")
    proc = snakemake("-j2", "--configfile", "tiny.yaml", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    import xarray as xr

    with xr.open_dataset(tmp_path / "results/cubes/colonnade_records.nc") as cube:
        assert dict(cube.sizes) == {"record": 1, "n_drums": 1, "pga": 2}
        first = cube.load()
    assert (tmp_path / "results/tables/table_7_1.csv").read_text().startswith("system,n_drums,record")
    figures = sorted(p.name for p in (tmp_path / "results/figures").glob("*.png"))
    assert figures == ["table_7_1.png", "thesis_fig_6_10.png", "thesis_fig_6_13.png", "thesis_fig_6_5.png"]
    # rerun from scratch: bit-identical cube values
    shutil.rmtree(tmp_path / "results")
    proc = snakemake("-j2", "--configfile", "tiny.yaml", cwd=tmp_path)
    assert proc.returncode == 0
    with xr.open_dataset(tmp_path / "results/cubes/colonnade_records.nc") as cube:
        for name in first.data_vars:
            assert np.array_equal(cube[name].values, first[name].values, equal_nan=True), name


def test_slurm_profile_dry_run():
    proc = snakemake("-n", "--profile", "config/profiles/slurm", "--configfile", "tests/workflow/config.yaml")
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "dry-run" in proc.stdout + proc.stderr
