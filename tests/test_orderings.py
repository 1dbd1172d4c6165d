"""Orderings the thesis reports, checked on small study cubes (issue 4: chapters 6-7).

Our records are stand-ins, so absolute PGAs differ from the thesis'; these orderings must
hold. (Not yet checked here: rocking vs sliding dominance with frequency, thesis Fig. 6.1
and 6.5, and the heavier epistyle moving less, 7.7: a quick look found neither ordering
to hold in our model at the grid points tried; see the issue 4 notes.)
"""

import numpy as np

from dem.study import case_table, combine_cases, run_case

DEFAULTS = {"contact": {"k_n": 1.0e9, "c_n": 1.0e4}, "output": {"every": 0.01}}
COLUMN = {"kind": "column", "height": 6.0, "width": 1.0, "capital": {"height": 0.6, "width": 1.4}}


def cube(tmp_path, name, study):
    from dem.dataset import write_dataset

    paths = [write_dataset(run_case(c), tmp_path / name / f"{c.id}.nc")
             for c in case_table(name, study, DEFAULTS)]
    return combine_cases(paths)


def test_tapered_columns_need_a_higher_pga_to_overturn(tmp_path):
    c = cube(tmp_path, "taper", {
        "structure": {"kind": "column", "n_drums": 4, "height": 6.0, "width": 1.0}, "friction": 0.485,
        "excitation": {"kind": "ramp", "rate": 0.5}, "solver": {"duration": 30.0},
        "grid": {"taper": [1.0, 1.5, 2.0]}})
    overturn = 0.5 * c["collapse_time"].values
    onset = 0.5 * c["rocking_onset_time"].values
    assert np.all(np.diff(overturn) > 0), f"thesis 6.3.2: overturning PGA rises with taper {overturn}"
    assert np.all(np.diff(onset) > 0), f"and so does the PGA that starts rocking {onset}"


def test_lower_predominant_frequency_collapses_at_lower_pga_and_epistyle_helps(tmp_path):
    records = ["mexico_standin_chichi_tcu102", "athens_standin_kocaeli_arc000"]
    single = cube(tmp_path, "single", {
        "structure": {**COLUMN, "n_drums": 1}, "friction": 0.485, "excitation": {"kind": "record"},
        "grid": {"record": records, "pga": [2.0, 8.0]}})
    collapsed = single["collapsed"].sel(n_drums=1) if "n_drums" in single.dims else single["collapsed"]
    # 0.41 Hz record collapses the column at 2 m/s2; the 5.7 Hz one does not
    assert int(collapsed.sel(record=records[0], pga=2.0)) == 1
    assert int(collapsed.sel(record=records[1], pga=2.0)) == 0
    colonnade = cube(tmp_path, "colonnade", {
        "structure": {"kind": "colonnade", "n_columns": 3, "n_drums": 1, "height": 6.0, "width": 1.0,
                      "clear_distance": 2.0, "epistyle_type": "a", "capital": {"height": 0.6, "width": 1.4}},
        "friction": 0.485, "excitation": {"kind": "record"},
        "grid": {"record": records[1:], "pga": [8.0]}})
    # thesis 7.1-7.2: the colonnade with an epistyle survives where the single column falls
    assert int(single["collapsed"].sel(record=records[1], pga=8.0)) == 1
    assert int(colonnade["collapsed"].sel(record=records[1], pga=8.0)) == 0
