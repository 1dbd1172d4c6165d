"""Manuscript Tables 1-3 (limit loads): every case file of config/walls/ against the manuscript's
DEM column, 10 % tolerance. Cases we miss are strict xfails carrying the measured value; the
same numbers are in results/tables/manuscript_table_*.csv (within_tolerance per case) and
benchmarks/wall_tables.py. Then every pushover plateau against the limit analysis of the same
model (the LP oracle, stonedem.wall.limit_analysis), 1 %."""

from pathlib import Path

import pytest

from stonedem.wall.case import load_case
from stonedem.wall.dataset import ORACLE_TOLERANCE
from stonedem.wall.limit_analysis import limit_multiplier
from stonedem.wall.pushover import pushover
from stonedem.wall.validation import LIMIT_TOLERANCE

CASES = Path(__file__).resolve().parents[2] / "config" / "walls"
WITHIN = [
    "orduna_case1",
    "s11",
    "s12",
    "s13",
    "s15",
    "s6",
    "s1_s2_s3",
    "s32",
    "s23",
    "s34",
    "chee_liang_2_3",
    "chee_liang_14_15",
]
MISSES = {  # measured on this machine; reasons in docs/results/walls.md
    "orduna_case2": "0.191 vs 0.215 (-11 %; Orduna & Lourenco's limit analysis 0.193)",
    "s5": "0.297 vs 0.350 (-15 %)",
    "chee_liang_8_12": "19.7 vs 25.0 kPa (-21 %)",
    "chee_liang_4_5": "7.95 vs 10.0 kPa (-20 %)",
    "chee_liang_9_13": "14.8 vs 20.0 kPa (-26 %)",
    "chee_liang_10_11": "5.80 vs 6.50 kPa (-10.8 %)",
}


PUSHOVERS = {}  # name -> (case, result): the oracle test reuses the table test's pushover


def _pushover(name):
    if name not in PUSHOVERS:
        case = load_case(CASES / f"{name}.yaml")
        PUSHOVERS[name] = case, pushover(case.model, case.settings, case.control_block)
    return PUSHOVERS[name]


@pytest.mark.parametrize(
    "name",
    WITHIN
    + [
        pytest.param(name, marks=pytest.mark.xfail(strict=True, reason=f"measured {why}"))
        for name, why in MISSES.items()
    ],
)
def test_limit_load_within_10_percent_of_manuscript_dem(name):
    case, r = _pushover(name)
    ref = case.spec["reference"]
    expected = ref.get("lambda_dem", ref.get("p_dem"))
    assert r.residual.max() < case.settings.accept_tolerance
    assert r.lambda_max == pytest.approx(expected, rel=LIMIT_TOLERANCE), (
        f"{name}: lambda_max {r.lambda_max:.4g} vs manuscript DEM {expected:.4g} "
        f"({LIMIT_TOLERANCE:.0%})"
    )


def test_every_table_case_is_tested():
    tables = {p.stem for p in CASES.glob("*.yaml")} - {"free_standing"}
    assert tables == set(WITHIN) | set(MISSES)


@pytest.mark.parametrize("name", WITHIN + list(MISSES) + ["free_standing"])
def test_plateau_is_the_collapse_load_of_the_model(name):
    """The limit analysis with the joint caps on the pushover's actions at its peak: that peak
    is a feasible point of the LP, so the LP is >= the plateau, and within 1 % of it when the
    plateau is the model's collapse load. Every round's LP is an upper bound, so stopping
    early (lambda_tolerance 3e-3) can only make this test harder, never pass a wrong plateau."""
    case, r = _pushover(name)
    la = limit_multiplier(case.model, caps_at=r.interface_forces_at_max, lambda_tolerance=3e-3)
    assert la.converged, la.status
    assert r.lambda_max == pytest.approx(la.lambda_limit, rel=ORACLE_TOLERANCE), (
        f"{name}: pushover {r.lambda_max:.5g} vs limit analysis {la.lambda_limit:.5g} ({la.status})"
    )
