"""Jobs of many cases (stonedem.study.runner): one log line per case, the case store, a search."""

import io
import re

import numpy as np
import pytest
import xarray as xr

from stonedem.io.schema import missing_metadata
from stonedem.study.cube import combine_searches
from stonedem.study.grid import case_table
from stonedem.study.jobs import plan_jobs
from stonedem.study.runner import CaseStore, run_cases, run_search

# a 1 x 4 m block under a 2 Hz harmonic: overturns within 1.5 s at an amplitude of 0.4 m, not 0.2 m
BLOCK = {
    "structure": {"kind": "column", "n_drums": 1, "height": 4.0, "width": 1.0},
    "friction": 0.7,
    "excitation": {"kind": "harmonic", "frequency": 2.0},
    "solver": {"duration": 1.5},
    "contact": {"model": "point", "k_n": 1.0e9},
    "output": {"every": 0.01},
}


def test_a_job_logs_one_line_per_case_and_restores_unchanged_cases_from_the_store(tmp_path):
    cases = case_table("block", {**BLOCK, "grid": {"amplitude": [0.01, 0.4]}})
    outputs = [tmp_path / "cases" / f"{c.id}.nc" for c in cases]
    store = CaseStore(tmp_path / "store", "records")
    log = io.StringIO()
    first = run_cases(cases, outputs, store, log)
    lines = log.getvalue().splitlines()
    assert len(lines) == 2 and lines[0].startswith("[1/2] block/A-0.01: ") and "steps" in lines[0]
    assert [i["collapsed"] for i in first] == [False, True] and "collapsed at" in lines[1]
    before = [p.read_bytes() for p in outputs]
    for p in outputs:
        p.unlink()
    # the job reruns (one case changed): the unchanged case comes back bit for bit
    changed = (
        case_table("block", {**BLOCK, "friction": 0.6, "grid": {"amplitude": [0.4]}}) + cases[:1]
    )
    log = io.StringIO()
    again = run_cases(changed, [tmp_path / "b.nc", outputs[0]], store, log)
    assert [i["restored"] for i in again] == [False, True], log.getvalue()
    assert "restored from the case store" in log.getvalue().splitlines()[1]
    assert outputs[0].read_bytes() == before[0]
    # no store: always simulated
    assert not run_cases(cases[:1], [tmp_path / "c.nc"], CaseStore(None), io.StringIO())[0][
        "restored"
    ]


def test_a_search_job_writes_every_run_and_a_self_describing_bracket(tmp_path):
    study = {
        **BLOCK,
        "grid": {"friction": [0.7]},
        "search": {
            "parameter": "amplitude",
            "start": 0.02,
            "factor": 2.0,
            "tolerance": 0.1,
            "fill": 1,
            "minimum": 0.005,
            "maximum": 0.64,
        },
    }
    (system,) = case_table("block", study)
    log = io.StringIO()
    runs, result = run_search(
        system, tmp_path / "runs", tmp_path / "search.nc", CaseStore(None), log
    )
    assert result["status"] == "bracketed" and result["width"] <= 0.1
    assert len(list((tmp_path / "runs").glob("*.nc"))) == len(runs) == result["n_runs"]
    assert len(log.getvalue().splitlines()) == len(runs) + 1  # one per run, one for the bracket
    cube = combine_searches([tmp_path / "search.nc"])
    assert missing_metadata(cube) == []
    assert cube["amplitude"].dims == ("friction", "run")
    amplitudes = cube["amplitude"].values[0]
    assert np.all(np.diff(amplitudes) > 0), "runs sorted by the searched value"
    first = amplitudes[cube["collapsed"].values[0] > 0].min()
    assert cube["collapse_threshold"].values.item() == pytest.approx(first)
    assert cube.attrs["search_parameter"] == "amplitude" and cube.attrs["n_cases"] == len(runs)


def test_a_search_summary_from_the_runs_in_memory_is_the_one_from_their_files(tmp_path):
    """run_search builds its summary from the datasets it wrote, not by reading them back; a
    search restored from the store reads the files. Both give the summary the files give."""
    from stonedem.io.netcdf import open_result, write_dataset
    from stonedem.study.cube import search_dataset
    from stonedem.study.grid import search_case

    study = {
        **BLOCK,
        "grid": {"friction": [0.7]},
        "search": {
            "parameter": "amplitude",
            "start": 0.05,
            "factor": 2.0,
            "tolerance": 0.2,
            "fill": 0,
            "minimum": 0.005,
            "maximum": 0.64,
        },
    }
    (system,) = case_table("block", study)
    store = CaseStore(tmp_path / "store", "records")
    summaries = []
    for k in range(2):  # simulated, then restored from the store
        runs, result = run_search(
            system, tmp_path / f"runs{k}", tmp_path / f"search{k}.nc", store, io.StringIO()
        )
        files = [tmp_path / f"runs{k}" / f"{search_case(system, r.value).id}.nc" for r in runs]
        write_dataset(search_dataset(system, runs, files, result), tmp_path / f"files{k}.nc")
        summaries.append(open_result(tmp_path / f"search{k}.nc"))
        assert unstamped(summaries[-1]).identical(unstamped(open_result(tmp_path / f"files{k}.nc")))
    assert (
        unstamped(summaries[0]).identical(unstamped(summaries[1]))
        and summaries[0].sizes["run"] >= 3
    )


def test_a_search_without_run_files_writes_one_file_that_the_store_gives_back_whole(tmp_path):
    """run_search without a runs folder (the workflow's default, search_runs: summary) writes
    only the search file: the summary the full case files give, values and attributes alike.
    The store keeps that file whole: a second search restores it (byte for byte, one log line,
    nothing simulated); other search settings are another entry."""
    from stonedem.io.netcdf import open_result

    search = {
        "parameter": "amplitude",
        "start": 0.05,
        "factor": 2.0,
        "tolerance": 0.2,
        "fill": 1,
        "minimum": 0.005,
        "maximum": 0.64,
    }
    (system,) = case_table("block", {**BLOCK, "grid": {"friction": [0.7]}, "search": search})
    full = run_search(
        system, tmp_path / "runs", tmp_path / "full.nc", CaseStore(None), io.StringIO()
    )
    store = CaseStore(tmp_path / "store", "records")
    log = io.StringIO()
    slim = run_search(system, None, tmp_path / "slim.nc", store, log)
    assert slim == full and sorted(p.name for p in tmp_path.iterdir()) == [
        "full.nc",
        "runs",
        "slim.nc",
        "store",
    ]
    assert len(log.getvalue().splitlines()) == len(slim[0]) + 1 and "s kernel" in log.getvalue()
    assert unstamped(open_result(tmp_path / "slim.nc")).identical(
        unstamped(open_result(tmp_path / "full.nc"))
    )
    log = io.StringIO()
    assert run_search(system, None, tmp_path / "again.nc", store, log) == full
    assert log.getvalue().count("\n") == 1 and "(restored from the case store)" in log.getvalue()
    assert (tmp_path / "again.nc").read_bytes() == (tmp_path / "slim.nc").read_bytes()
    (other,) = case_table(
        "block", {**BLOCK, "grid": {"friction": [0.7]}, "search": {**search, "fill": 0}}
    )
    log = io.StringIO()
    run_search(other, None, tmp_path / "other.nc", store, log)
    assert "restored" not in log.getvalue() and "s kernel" in log.getvalue()


def test_a_search_without_histories_keeps_the_same_runs_and_measures(tmp_path):
    """search: {histories: false} (the IDA's default): the file holds every run's measures
    and the bracket, no time dimension; the runs and measures are those with histories."""
    import dataclasses

    from stonedem.errors import InputError
    from stonedem.io.netcdf import open_result
    from stonedem.study.search import SearchSettings

    search = {
        "parameter": "amplitude",
        "start": 0.05,
        "factor": 2.0,
        "tolerance": 0.2,
        "fill": 0,
        "minimum": 0.005,
        "maximum": 0.64,
    }
    (system,) = case_table("block", {**BLOCK, "grid": {"friction": [0.7]}, "search": search})
    bare = dataclasses.replace(system, search=dataclasses.replace(system.search, histories=False))
    with_histories = run_search(system, None, tmp_path / "h.nc", CaseStore(None), io.StringIO())
    assert (
        run_search(bare, None, tmp_path / "m.nc", CaseStore(None), io.StringIO()) == with_histories
    )
    full, measures = open_result(tmp_path / "h.nc"), open_result(tmp_path / "m.nc")
    assert (
        "time" not in measures.dims
        and "rocking" not in measures
        and measures.attrs["search_histories"] == 0
    )
    kept = full.drop_dims("time")
    assert kept.drop_attrs(deep=False).equals(measures.drop_attrs(deep=False))
    with pytest.raises(InputError, match="search.histories"):
        SearchSettings.from_config({**search, "histories": "no"}, "search", ["amplitude"])


def test_searches_together_without_run_files_match_searches_alone(tmp_path):
    from stonedem.io.netcdf import open_result
    from stonedem.study.runner import run_searches

    study = {
        **BLOCK,
        "grid": {"friction": [0.5, 0.7]},
        "search": {
            "parameter": "amplitude",
            "start": 0.05,
            "factor": 2.0,
            "tolerance": 0.2,
            "fill": 1,
            "minimum": 0.005,
            "maximum": 0.64,
        },
    }
    systems = case_table("block", study)
    store = CaseStore(tmp_path / "store", "records")
    alone = run_search(
        systems[0], None, tmp_path / "alone.nc", store, io.StringIO()
    )  # kept in the store
    log = io.StringIO()
    together = run_searches(
        systems, None, [tmp_path / "t0.nc", tmp_path / "t1.nc"], store, "cpu", width=4, log=log
    )
    assert (
        together[0] == alone and "(restored from the case store)" in log.getvalue().splitlines()[0]
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["alone.nc", "store", "t0.nc", "t1.nc"]
    assert (tmp_path / "t0.nc").read_bytes() == (tmp_path / "alone.nc").read_bytes()
    assert together[1] == run_search(
        systems[1], None, tmp_path / "alone1.nc", CaseStore(None), io.StringIO()
    )
    a, b = open_result(tmp_path / "alone1.nc"), open_result(tmp_path / "t1.nc")
    assert a.drop_attrs(deep=False).equals(b.drop_attrs(deep=False)) and b.attrs["device"] == "cpu"


def test_cheap_cases_share_jobs_and_each_search_is_one_job():
    grid = case_table("block", {**BLOCK, "grid": {"amplitude": [0.01, 0.02, 0.03, 0.04]}})
    searches = case_table(
        "s",
        {
            **BLOCK,
            "grid": {"friction": [0.5, 0.7]},
            "search": {"parameter": "amplitude", "start": 0.02, "minimum": 0.01},
        },
    )
    jobs = plan_jobs({"block": grid, "s": searches}, job_seconds=1e9)
    assert sorted((j.study, len(j.cases), j.is_search) for j in jobs) == [
        ("block", 4, False),
        ("s", 1, True),
        ("s", 1, True),
    ]
    assert jobs[0].cost >= jobs[-1].cost, "the costliest job first"
    alone = plan_jobs({"block": grid}, job_seconds=0.0)
    assert [len(j.cases) for j in alone] == [1, 1, 1, 1]
    assert {j.name for j in alone} == {f"simulate_block_{k}" for k in range(4)}


def test_an_unknown_case_store_file_is_never_read_as_a_case(tmp_path):
    (case,) = case_table("block", {**BLOCK, "grid": {"amplitude": [0.01]}})
    store = CaseStore(tmp_path / "store", "records")
    assert not store.restore(case, tmp_path / "out.nc") and not (tmp_path / "out.nc").exists()
    with xr.open_dataset(
        run_cases([case], [tmp_path / "out.nc"], store, io.StringIO()) and tmp_path / "out.nc"
    ) as ds:
        assert ds.attrs["case"] == case.id


def unstamped(ds):
    """The dataset without its history (each write stamps the time it was written)."""
    return ds.drop_attrs(deep=False).assign_attrs(
        {k: v for k, v in ds.attrs.items() if k != "history"}
    )


def tree(folder):
    return sorted(p.name for p in folder.iterdir())


def test_searches_run_together_give_the_summaries_searches_run_alone_give(tmp_path):
    """run_searches (rounds of runs side by side, the CPU ensemble here) makes each search's
    runs exactly as run_search does, and its summaries differ only in the attributes that say
    how they were computed; the device fallback says why in one line."""
    from stonedem.io.netcdf import open_result
    from stonedem.study.runner import choose_device, run_searches

    study = {
        **BLOCK,
        "grid": {"friction": [0.5, 0.7]},
        "search": {
            "parameter": "amplitude",
            "start": 0.05,
            "factor": 2.0,
            "tolerance": 0.2,
            "fill": 1,
            "minimum": 0.005,
            "maximum": 0.64,
        },
    }
    systems = case_table("block", study)
    alone = [
        run_search(
            s, tmp_path / f"alone{i}", tmp_path / f"alone{i}.nc", CaseStore(None), io.StringIO()
        )
        for i, s in enumerate(systems)
    ]
    store = CaseStore(tmp_path / "store", "records")
    for k in range(2):  # simulated, then restored from the store (speculative runs were never kept)
        log = io.StringIO()
        together = run_searches(
            systems,
            [tmp_path / f"together{k}_{i}" for i in range(2)],
            [tmp_path / f"together{k}_{i}.nc" for i in range(2)],
            store,
            "cpu",
            width=4,
            log=log,
        )
        assert [runs for runs, _ in together] == [runs for runs, _ in alone]
        for i in range(2):
            a, b = (
                open_result(tmp_path / f"alone{i}.nc"),
                open_result(tmp_path / f"together{k}_{i}.nc"),
            )
            assert a.drop_attrs(deep=False).equals(b.drop_attrs(deep=False))
            assert (
                b.attrs["device"] == "cpu"
                and "rounds" in b.attrs["search_plan"]
                and "numba_version" in b.attrs
            )
            # the run files are the ones the search alone writes: the speculative runs are dropped
            assert tree(tmp_path / f"together{k}_{i}") == tree(tmp_path / f"alone{i}")
        assert "round of" in log.getvalue()
    # the second time the runs on the paths come from the store; only speculative ones run again
    assert re.search(
        r"round of 8 runs over 2 searches: [0-7] simulated on the CPU, [1-8] restored",
        log.getvalue(),
    )
    device, line = choose_device("cpu")
    assert (device, line) == ("cpu", "device: cpu")


def test_a_gpu_asked_for_without_one_falls_back_to_the_cpu_in_one_line(monkeypatch):
    from stonedem.kernels import gpu
    from stonedem.study.runner import choose_device

    monkeypatch.setattr(gpu, "gpu_available", lambda: (False, "no CUDA GPU or driver found"))
    device, line = choose_device("gpu")
    assert device == "cpu" and "\n" not in line and "no CUDA GPU" in line and "CPU" in line


def test_a_speculative_run_dropped_and_later_reached_is_simulated_again_and_written(
    tmp_path, monkeypatch
):
    """With collapse from an amplitude of 0.535 (the verdicts stand in for the physics), the
    search's path reaches 0.2828 through a branch other than the one it was first run in, after
    its dataset was dropped: it is simulated once more and written, so every run on the path
    has its file (found by a search over rules with stonedem.study.search alone)."""
    from stonedem.study import runner
    from stonedem.study.runner import run_searches

    real = runner._info
    monkeypatch.setattr(
        runner, "_info", lambda ds: {**real(ds), "collapsed": float(ds["amplitude"]) >= 0.535}
    )
    study = {
        **BLOCK,
        "grid": {"friction": [0.7]},
        "search": {
            "parameter": "amplitude",
            "start": 0.05,
            "factor": 2.0,
            "tolerance": 0.2,
            "fill": 1,
            "minimum": 0.005,
            "maximum": 0.64,
        },
    }
    systems = case_table("block", study)
    simulated = []
    together = runner.run_cases_together
    monkeypatch.setattr(
        runner,
        "run_cases_together",
        lambda cases, *a: simulated.extend(c.id for c in cases) or together(cases, *a),
    )
    ((runs, result),) = run_searches(
        systems,
        [tmp_path / "runs"],
        [tmp_path / "search.nc"],
        CaseStore(None),
        "cpu",
        width=4,
        log=io.StringIO(),
    )
    assert 0.2828 in [r.value for r in runs]
    late = [i for i in simulated if i.endswith("_A-0.2828")]
    assert len(late) == 2, simulated  # speculative, dropped; then again on the path
    assert len(tree(tmp_path / "runs")) == len(runs) == result["n_runs"]


def test_a_search_builds_each_later_run_from_its_first_scene_and_gets_the_scene_case_scene_builds():
    """SearchScenes: the first run's scene in full, each later one with its base motion alone
    built anew, sharing the bodies; every field is what case_scene gives, the provenance too."""
    import dataclasses

    from stonedem.study.grid import search_case
    from stonedem.study.runner import SearchScenes, case_scene

    (system,) = case_table(
        "block",
        {
            **BLOCK,
            "grid": {"friction": [0.7]},
            "search": {"parameter": "amplitude", "start": 0.05, "minimum": 0.005, "maximum": 0.64},
        },
    )
    scenes = SearchScenes("records")
    first = scenes(search_case(system, 0.05))
    for value in (0.1, 0.4, 0.0125):
        case = search_case(system, value)
        got, want = scenes(case), case_scene(case, "records")
        assert (
            got.bodies is first.bodies
            and got.spec == want.spec
            and got.spec["excitation"]["amplitude"] == value
        )
        for f in dataclasses.fields(want):
            if f.name in ("bodies", "horizontal", "vertical"):
                continue
            assert getattr(got, f.name) == getattr(want, f.name), f.name
        for motion in ("horizontal", "vertical"):
            a, b = getattr(got, motion), getattr(want, motion)
            assert a.kind == b.kind and a.description == b.description and a.table_dt == b.table_dt
            for name in ("params", "table_accel", "table_vel", "table_disp"):
                assert np.array_equal(getattr(a, name), getattr(b, name)), (motion, name)
        assert [b.name for b in got.bodies] == [b.name for b in want.bodies]
        assert all(
            np.array_equal(x.vertices, y.vertices) and x.mass == y.mass
            for x, y in zip(got.bodies, want.bodies)
        )
