"""Every kind of output file passes the IOOS compliance checker for CF-1.10 (issue 34).

One small file of each kind the project writes (case, cube, search, IDA, fragility, wall,
record, validation, benchmark) is checked with ``compliance-checker -t cf:1.10``; its errors
(the report's high-priority section) must be none, but for one deliberate choice: simulation
time stays a plain ``time`` coordinate in seconds, so that xarray gives users seconds, not
datetimes. CF wants units "<unit> since <epoch>" on a coordinate named ``time``, and xarray
decodes any such units into dates; the two errors that choice costs (CF 3.1 and 4.4 on
``time``) are the only ones allowed (docs/guide/output.md). Needs the ``[check]`` extra.
"""

import importlib.util
import io
import json
import re
import shutil

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("compliance_checker") is None,
    reason="the IOOS compliance checker is not installed (pip install -e '.[check]')",
)

# the errors simulation time in seconds costs, and only those (see the module docstring)
DELIBERATE = (
    re.compile(r"^time must be in a valid units format <unit> since <epoch> not s$"),
    re.compile(r"^time does not have correct time units$"),
)


def cf_errors(path) -> list[str]:
    """The high-priority messages of compliance-checker -t cf:1.10 on ``path``."""
    from compliance_checker.runner import CheckSuite, ComplianceChecker

    CheckSuite().load_all_available_checkers()
    report = path.with_suffix(".cf.json")
    ComplianceChecker.run_checker(
        str(path), ["cf:1.10"], 0, "normal", output_filename=str(report), output_format="json"
    )
    results = json.loads(report.read_text())["cf:1.10"]
    return [
        message for item in results.get("high_priorities", []) for message in item.get("msgs", [])
    ]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """{kind: path} of one small file of each kind, written as the workflow writes them."""
    import stonedem
    from benchmarks import ensemble
    from stonedem.fragility.fit import fragility_dataset
    from stonedem.fragility.ida import ida_cube
    from stonedem.io.netcdf import write_dataset
    from stonedem.study.cube import combine_cases
    from stonedem.study.grid import case_table
    from stonedem.study.runner import CaseStore, run_case, run_search
    from stonedem.validation.cases import VALIDATIONS, write_result
    from tests.fragility.test_ida import COLUMN, _search_file
    from tests.study.test_runner import BLOCK
    from tests.test_api import small_wall

    folder = tmp_path_factory.mktemp("cf")
    out = {}
    excited = {**BLOCK, "excitation": {**BLOCK["excitation"], "amplitude": 0.1}}
    cases = case_table("block", {**excited, "grid": {"friction": [0.5, 0.7]}})
    for i, case in enumerate(cases):
        write_dataset(run_case(case), folder / f"case{i}.nc")
    out["case"] = folder / "case0.nc"
    out["cube"] = write_dataset(
        combine_cases([folder / "case0.nc", folder / "case1.nc"]), folder / "cube.nc"
    )
    (system,) = case_table(
        "block",
        {
            **BLOCK,
            "grid": {"friction": [0.7]},
            "search": {
                "parameter": "amplitude",
                "start": 0.1,
                "factor": 2.0,
                "tolerance": 0.5,
                "fill": 0,
                "minimum": 0.01,
                "maximum": 0.64,
            },
        },
    )
    run_search(system, folder / "runs", folder / "search.nc", CaseStore(None), io.StringIO())
    out["search"] = folder / "search.nc"
    searches = []
    for comp, pga in (("FF01a", 4.0), ("FF01b", 5.0), ("FF02a", 8.0)):
        values = np.array([1.0, 2.0, 4.0, 8.0]) * pga / 4.0
        searches.append(
            _search_file(
                folder / f"s_{comp}.nc",
                "col",
                comp,
                values,
                values >= pga,
                0.01 * values,
                np.zeros(values.size),
            )
        )
    cube = ida_cube(searches, {"col": COLUMN}, ["far_field"])
    out["ida"] = write_dataset(cube, folder / "ida.nc")
    out["fragility"] = write_dataset(fragility_dataset(cube, samples=20), folder / "fragility.nc")
    out["wall"] = write_dataset(stonedem.run_wall(small_wall()), folder / "wall.nc")
    out["record"] = folder.parent / "record.nc"
    shutil.copy("records/athens_standin_kocaeli_arc000.nc", out["record"])
    out["validation"] = write_result(
        VALIDATIONS["housner_period_point"](), folder / "validation.nc"
    )
    assert (
        ensemble.main(
            [
                "--quick",
                "--members",
                "1",
                "--scene",
                "lone_block",
                "--repeats",
                "1",
                "--out",
                str(folder / "bench"),
            ]
        )
        == 0
    )
    out["bench"] = folder / "bench" / "ensemble.nc"
    return out


@pytest.mark.parametrize(
    "kind", ["case", "cube", "search", "ida", "fragility", "wall", "record", "validation", "bench"]
)
def test_every_output_kind_passes_the_cf_checker(outputs, kind):
    import xarray as xr

    found = cf_errors(outputs[kind])
    errors = [m for m in found if not any(p.match(m) for p in DELIBERATE)]
    assert errors == [], f"{kind}: {errors}"
    with xr.open_dataset(outputs[kind], decode_times=False) as ds:
        timed = "time" in ds.coords
        assert "history" in ds.attrs and ds.attrs["Conventions"] == "CF-1.10"
    # the checker did look: where simulation time is, it reports the deliberate choice
    assert (len(found) - len(errors) == len(DELIBERATE)) == timed, (kind, found)
