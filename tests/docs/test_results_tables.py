"""The docs' results-table directive (docs/_ext/results_tables.py) keeps the rows its
``where`` asks for: a value, a number written another way, or alternatives with ``|``."""

import importlib.util
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
SPEC = importlib.util.spec_from_file_location(
    "results_tables", Path(__file__).parents[2] / "docs" / "_ext" / "results_tables.py"
)
results_tables = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(results_tables)


@pytest.mark.parametrize(
    "where, kept",
    [
        ({"name": "a"}, ["a"]),
        ({"name": "a|c"}, ["a", "c"]),
        ({"n": "2.0"}, ["b"]),
        ({"n": "1|2"}, ["a", "b"]),
        ({"name": "a|b", "n": "2"}, ["b"]),
        ({"name": "z"}, []),
    ],
)
def test_where_keeps_equal_rows_and_alternatives(where, kept):
    rows = [{"name": "a", "n": "1"}, {"name": "b", "n": "2"}, {"name": "c", "n": "x"}]
    assert [r["name"] for r in rows if results_tables._matches(r, where)] == kept
