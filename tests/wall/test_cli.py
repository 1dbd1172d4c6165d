"""`stonedem.wall` command: the issue's case YAML runs; bad input -> one line, exit 2, no file."""

import subprocess
import sys

import pytest
import xarray as xr

from stonedem.io.schema import missing_metadata

CASE = """\
panel: {block: {a: 0.081, b: 0.210, s: 0.070}, blocks_per_course: 3, courses: 13,
       unit_weight: 20000.0}
joints: {kind: dry, mu: 0.7, k_n: 2.4e9, k_t: 1.0e9}   # mortar: add tensile_strength, cohesion
restraints: [{edge: base, fix: all}, {edge: left, fix: translations}]
load: {kind: proportional, direction: out_of_plane}      # or {kind: pressure}
"""


def wall(*args):
    return subprocess.run(
        [sys.executable, "-m", "stonedem.wall", *args], capture_output=True, text=True
    )


@pytest.fixture(scope="module")
def issue_case(tmp_path_factory):
    d = tmp_path_factory.mktemp("wall")
    (d / "case.yaml").write_text(CASE)
    proc = wall(str(d / "case.yaml"), "-o", str(d / "out.nc"), "-q", "--limit")
    assert proc.returncode == 0, proc.stderr
    with xr.open_dataset(d / "out.nc") as ds:
        yield ds.load()


def test_issue_case_runs_and_is_self_describing(issue_case):
    ds = issue_case
    assert missing_metadata(ds) == [], "units and long_name on every variable"
    assert ds["lambda"].dims == ("step",) and ds.damage.dims == ("step", "interface")
    assert float(ds.lambda_max) == pytest.approx(float(ds["lambda"].max()))
    assert ds.displacement_at_limit.dims == ("block", "dof")
    assert (
        '"mu": 0.7' in ds.attrs["case"]
        and "solver_tolerance" in ds.attrs
        and "stonedem" in ds.attrs["source"]
    )


@pytest.mark.xfail(
    strict=True,
    reason="measured lambda_max 0.283 vs manuscript DEM 0.175 (+61 %): "
    "the issue's file pins the column at the block centres (at: centre, "
    "the default); config/walls/orduna_case1.yaml holds points on the "
    "panel edge as the manuscript does and gives 0.177",
)
def test_issue_case_is_table1_case1(issue_case):
    lam = float(issue_case.lambda_max)
    assert lam == pytest.approx(0.175, rel=0.10), f"Table 1 case 1: {lam:.4f} vs 0.175 (10 %)"


def test_limit_analysis_proves_the_plateau(issue_case):
    """--limit: the LP on the pushover's caps at its peak lies within 1 % above the plateau."""
    ds = issue_case
    lam, la = float(ds.lambda_max), float(ds.lambda_limit_analysis)
    assert lam == pytest.approx(la, rel=0.01) and la >= lam * (1 - 1e-3), (lam, la)
    assert ds.lambda_limit_analysis.attrs["units"] == "1"
    assert ds.attrs["limit_analysis_verdict"].startswith("plateau proven")


@pytest.mark.parametrize(
    "edit, field",
    [
        (("blocks_per_course: 3", "blocks_per_course: 3, colour: red"), "panel.colour"),
        (("a: 0.081", "a: -0.081"), "panel.block.a"),
        (("kind: dry, ", ""), "joints.kind"),
        (("edge: left", "edge: middle"), "restraints[1].edge"),
        (
            ("blocks_per_course: 3", "blocks_per_course: 3.3"),
            "panel.blocks_per_course",
        ),  # does not tile
        (("k_n: 2.4e9", "k_n: -2.4e9"), "joints.k_n"),
        (("mu: 0.7", "mu: 0"), "joints.mu"),
        (("{edge: base, fix: all}, ", ""), "restraints"),  # a mechanism at lambda = 0
    ],
)
def test_bad_input_one_line_exit_2_no_output(tmp_path, edit, field):
    (tmp_path / "bad.yaml").write_text(CASE.replace(*edit))
    out = tmp_path / "bad.nc"
    proc = wall(str(tmp_path / "bad.yaml"), "-o", str(out))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {field}"), proc.stderr
    assert not out.exists() and not list(tmp_path.glob(".*.tmp"))


def test_case_dataset_carries_its_verdict(tmp_path):
    """A case with a manuscript reference says in its own attrs whether it meets the tolerance."""
    from pathlib import Path

    from stonedem.wall.dataset import run_case_file

    case = Path(__file__).resolve().parents[2] / "config" / "walls" / "s15.yaml"
    ds = run_case_file(case, tmp_path / "s15.nc")
    with xr.open_dataset(tmp_path / "s15.nc") as back:
        assert back.attrs["manuscript_dem"] == 0.25
        err = float(back.lambda_max) / 0.25 - 1
        assert back.attrs["error_vs_manuscript_dem"] == pytest.approx(err, abs=1e-12)
        assert back.attrs["within_tolerance"] == ("yes" if abs(err) <= 0.10 else "no")
    assert missing_metadata(ds) == []
