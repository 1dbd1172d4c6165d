"""The Snakemake workflow: lint clean, config validated, committed records up to date."""

import shutil
import subprocess
import sys
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]


def snakemake(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "snakemake", *args], cwd=cwd, capture_output=True, text=True)


def test_lint_is_clean():
    for args in ((), ("--config", "extract_records=true")):
        proc = snakemake("--lint", *args)
        assert proc.returncode == 0, proc.stdout + proc.stderr


def test_committed_records_need_no_rerun():
    proc = snakemake("-n")
    assert proc.returncode == 0, proc.stderr
    assert "Nothing to be done" in proc.stdout + proc.stderr, proc.stdout


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
