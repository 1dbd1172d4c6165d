"""benchmarks/gpu_equivalence.py (issue 44, item 7): the GPU's verdicts judged against the
CPU's own last-bit ensemble. No simulation here: the statistics on small made-up verdicts
whose answers are worked out by hand, the whole command through ``--reuse``, and its
refusals (one line, exit 2, nothing written)."""

import importlib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stonedem.io.netcdf import write_dataset

ROOT = Path(__file__).resolve().parents[2]


ge = importlib.import_module("benchmarks.gpu_equivalence")

# 4 cases x 4 CPU members: case 0 never collapses, case 1 always, case 2 splits 2/4, case 3 1/4
CPU = np.array([[0, 0, 0, 0], [1, 1, 1, 1], [1, 0, 1, 0], [0, 0, 0, 1]], dtype=np.int8)
CASES = [{"id": f"rec-A_pga-{p:g}", "record": "A", "pga": p} for p in (1.0, 2.0, 3.0, 4.5)]


def test_pair_flips_count_each_pair_of_members():
    pairs, flips = ge.pair_flips(CPU)
    assert pairs.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
    # members 0..3 as columns: (1,0,1,0) and (0,0,0,1) in the split cases
    assert flips.tolist() == [1, 0, 2, 1, 1, 2]


def test_flips_of_unanimous_cases_get_the_smallest_p():
    # the candidate flips both unanimous cases: each adds (1 - 0)^2 / (0.2 x 0.8 + 0.01) = 5.88
    # to its S_v (13.1 in all), where a CPU member taken as the candidate reaches at most
    # 0.37 + 0.37 + 2.25 + 5.88 = 8.9, so the observed labelling is the largest of 5: p = 1/5
    candidate = np.array([1, 0, 1, 0], dtype=np.int8)
    judged = ge.judge(CPU, candidate)
    assert judged["s_v"] == pytest.approx(2 / 0.17 + 0.25 / 0.25 + 0.0625 / 0.17)
    assert judged["p_v"] == pytest.approx(1 / 5)
    assert judged["unanimous_flips"].tolist() == [0, 1]
    assert (judged["flips_member_0"], judged["flips_min"], judged["flips_max"]) == (2, 2, 4)
    assert judged["flips_mean"] == pytest.approx(11 / 4)
    assert judged["n_assignments"] == 5 and judged["exact"]


def test_a_candidate_inside_the_split_cases_is_not_unusual():
    # equal to member 0, (1, 0) in the split cases as members 0 and 2: S_v 1 + 0.37 = 1.37,
    # the smallest of the five labellings (member 1's (0, 0) gives 2.62, member 3's (0, 1) 8.1)
    judged = ge.judge(CPU, CPU[:, 0].copy())
    assert judged["s_v"] == pytest.approx(1.0 + 0.0625 / 0.17)
    assert judged["p_v"] == pytest.approx(1.0)
    assert judged["unanimous_flips"].size == 0
    assert judged["flips_member_0"] == 0


def _inputs(tmp_path, gpu, host):
    """An earlier output (CPU verdicts, floors) and a gpu_check.nc with these verdicts."""
    floors = xr.Dataset(
        {"floor_position": ("scene", [1e-14, 4e-6]), "floor_rotation": ("scene", [2e-14, 5e-6])},
        coords={"scene": ["lone_block", "column_1_area_law/pga_9"]},
    )
    device = {
        "kind": ["lone_block", "column_1_area_law"],
        "position_difference": np.array([1e-6, 6e-6]),
        "rotation_difference": np.array([1e-7, 8e-6]),
    }
    verdicts = {"gpu_h100": gpu, "cpu_h100_host": host}
    earlier = ge.equivalence_dataset(
        CASES,
        CPU,
        np.zeros(CPU.shape),
        verdicts,
        device,
        floors,
        {"source": "test", "machine": "test"},
    )
    write_dataset(earlier, tmp_path / "earlier.nc")
    check = xr.Dataset(
        {
            "gpu_collapsed": ("case", gpu, {"units": "1"}),
            "cpu_collapsed": ("case", host, {"units": "1"}),
            "position_difference": ("kind", device["position_difference"], {"units": "m"}),
            "rotation_difference": ("kind", device["rotation_difference"], {"units": "rad"}),
        },
        coords={"case": [c["id"] for c in CASES], "kind": device["kind"]},
        attrs={"device": "test GPU", "source": "stonedem (abc)"},
    ).isel(case=[3, 1, 0, 2])  # read back by id
    write_dataset(check, tmp_path / "gpu_check.nc")
    return tmp_path / "earlier.nc", tmp_path / "gpu_check.nc"


def test_reuse_remakes_the_report_without_running(tmp_path, capsys):
    gpu = np.array(
        [0, 1, 0, 1], dtype=np.int8
    )  # differs from its host on cases 2 (split) and 3 (split)
    host = np.array([0, 1, 1, 0], dtype=np.int8)
    earlier, check = _inputs(tmp_path, gpu, host)
    out = tmp_path / "again.nc"
    assert ge.main(["--reuse", str(earlier), "--gpu-check", str(check), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "GPU vs its host CPU: 2 of 4 differ, 2 on split cases" in printed
    assert "1.17 of 4 verdicts differ on average, 0 ... 2" in printed  # (1+0+2+1+1+2)/6
    assert "smallest attainable p is 1/(K+1) = 0.2" in printed
    ds = xr.open_dataset(out)
    assert ds.gpu_collapsed.values.tolist() == gpu.tolist()  # re-ordered by case id
    assert ds.split.values.tolist() == [0, 0, 1, 1]
    assert ds.attrs["gpu_host_disagreements_on_split"] == 2 and ds.attrs["split_cases"] == 2
    assert float(ds.position_gap_in_floors.sel(scene="lone_block")) == pytest.approx(1e8)
    assert float(ds.position_gap_in_floors.sel(scene="column_1_area_law/pga_9")) == pytest.approx(
        1.5
    )
    assert float(ds.p_v_smallest[0]) == pytest.approx(0.2)
    for name, var in ds.variables.items():
        if var.dtype.kind in "fiu":
            assert "units" in var.attrs, name


def refused(argv, field, folder, capsys):
    before = sorted(folder.rglob("*"))
    assert ge.main(argv) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and field in lines[0], lines
    assert sorted(folder.rglob("*")) == before


@pytest.mark.parametrize(
    "argv, field",
    [
        (["--members", "1"], "--members"),
        (["--jobs", "0"], "--jobs"),
        (["--records", "0"], "--records"),
        (["--gpu-check", "{tmp}/missing.nc"], "--gpu-check"),
        (["--out", "{tmp}/out.txt"], "--out"),
        (["--reuse", "{tmp}/gpu_check.nc"], "--reuse"),  # a file, but not an earlier output
    ],
)
def test_bad_options_are_refused_before_anything_runs(argv, field, tmp_path, capsys):
    _, check = _inputs(tmp_path, np.zeros(4, np.int8), np.zeros(4, np.int8))
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    if "--gpu-check" not in argv:
        argv += ["--gpu-check", str(check)]
    refused(
        argv + ([] if "--out" in argv else ["--out", str(tmp_path / "new" / "out.nc")]),
        field,
        tmp_path,
        capsys,
    )


def test_a_device_file_without_the_cases_is_refused(tmp_path, capsys):
    earlier, check = _inputs(tmp_path, np.zeros(4, np.int8), np.zeros(4, np.int8))
    xr.open_dataset(check).load().isel(case=[0, 1]).pipe(write_dataset, tmp_path / "short.nc")
    refused(
        [
            "--reuse",
            str(earlier),
            "--gpu-check",
            str(tmp_path / "short.nc"),
            "--out",
            str(tmp_path / "o.nc"),
        ],
        "--gpu-check",
        tmp_path,
        capsys,
    )
