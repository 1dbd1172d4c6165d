"""The catalogue of the study's figures and CSV tables, by thesis chapter.

Each figure is named after the thesis figure it regenerates (``thesis_fig_6_10``) and is a
:class:`Figure`: the inputs it reads, named symbolically (``Cube("ramp_drums")``,
``Case(study, params)``, ``Table("table_7_1")``, ``Record(name)``), a drawing function and a
caption. Each CSV table is a :class:`Reduction`: its input cubes and the stonedem.study.reduce
function of them. The chapters list their entries (:mod:`.chapter6`, :mod:`.chapter7`; shared
drawing in :mod:`.drawing`); :func:`figure_table` and :func:`reduction_table` keep those whose
inputs are in the configured studies, inputs resolved; the workflow maps each input to its file
(:func:`input_paths`).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")  # before the chapters import pyplot: files only, no display
from stonedem.figures import chapter6, chapter7  # noqa: E402
from stonedem.figures.catalogue import (
    Case,
    Cube,
    Figure,
    Record,
    Reduction,
    Table,
    available,  # noqa: E402
    input_paths,
)
from stonedem.figures.chapter6 import rocking_then_sliding  # noqa: E402
from stonedem.figures.chapter7 import heavier_epistyle_moves_less, table_7_1_orderings  # noqa: E402

CHAPTERS = (chapter6, chapter7)

__all__ = [
    "CHAPTERS",
    "Case",
    "Cube",
    "Figure",
    "Record",
    "Reduction",
    "Table",
    "figure_table",
    "figures",
    "heavier_epistyle_moves_less",
    "input_paths",
    "reduction_table",
    "rocking_then_sliding",
    "table_7_1_orderings",
    "tables",
]


def figures(config: dict | None = None) -> dict[str, Figure]:
    """Every figure of the catalogue, inputs unresolved (``config``: its snapshot_pgas)."""
    snap = (config or {}).get("snapshot_pgas", {})
    return {name: figure for chapter in CHAPTERS for name, figure in chapter.figures(snap)}


def tables() -> dict[str, Reduction]:
    """Every CSV table of the catalogue, inputs unresolved."""
    return {name: table for chapter in CHAPTERS for name, table in chapter.tables()}


def reduction_table(studies: dict) -> dict[str, Reduction]:
    """Every table whose cubes are in ``studies`` ({study: {case id: Case}})."""
    return available(tables(), studies)


def figure_table(studies: dict, config: dict | None = None) -> dict[str, Figure]:
    """Every figure whose inputs are in ``studies`` ({study: {case id: Case}}) and the tables
    made from them; a case input names the one configured case with its parameters (left
    out when none or several match)."""
    return available(figures(config), studies, reduction_table(studies))
