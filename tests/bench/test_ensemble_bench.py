"""The ensemble throughput benchmark (benchmarks.ensemble, issue 33) writes a
self-describing dataset whose numbers add up."""

import numpy as np

from benchmarks import ensemble
from stonedem.io.netcdf import open_result
from stonedem.io.schema import missing_metadata


def test_the_benchmark_writes_member_steps_per_second_for_each_backend(tmp_path, capsys):
    status = ensemble.main(
        [
            "--quick",
            "--members",
            "1",
            "3",
            "--scene",
            "lone_block",
            "--repeats",
            "1",
            "--out",
            str(tmp_path / "bench"),
        ]
    )
    assert status == 0
    ds = open_result(tmp_path / "bench" / "ensemble.nc")
    assert missing_metadata(ds) == []
    assert list(ds["members"].values) == [1, 3]
    assert {"cpu_1_thread", "cpu_all_threads"} <= set(ds["backend"].values)
    cpu = ds.sel(backend="cpu_1_thread")
    # three members integrate three times the steps of one (same structure, same duration)
    assert float(cpu["member_steps"].sel(members=3)) == 3 * float(
        cpu["member_steps"].sel(members=1)
    )
    assert np.allclose(ds["throughput"], ds["member_steps"] / ds["wall"])
    assert np.allclose(ds["ns_per_member_step"] * ds["throughput"], 1e9)
    assert (tmp_path / "figures" / "ensemble_throughput.png").stat().st_size > 10_000
    assert "member-steps/s" in capsys.readouterr().out
