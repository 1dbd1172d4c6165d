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

import importlib

from stonedem.figures.catalogue import (
    Case,
    Cube,
    Figure,
    Record,
    Reduction,
    Table,
    available,
    input_paths,
)

# the chapters (and matplotlib and xarray with them) load on first use (PEP 562), so that
# ``stonedem --help`` and ``--version``, which import stonedem.figures.snapshots, stay light
_LAZY = {
    "rocking_then_sliding": "stonedem.figures.chapter6",
    "heavier_epistyle_moves_less": "stonedem.figures.chapter7",
    "table_7_1_orderings": "stonedem.figures.chapter7",
}

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


def chapters() -> tuple:
    """The chapter modules whose entries make the catalogue (imported on first call)."""
    return (
        importlib.import_module("stonedem.figures.chapter6"),
        importlib.import_module("stonedem.figures.chapter7"),
        importlib.import_module("stonedem.figures.sequences"),
        importlib.import_module("stonedem.figures.tilt"),
        importlib.import_module("stonedem.figures.links"),  # beyond the thesis (issue 48)
    )


def __getattr__(name: str):
    if name == "CHAPTERS":
        return chapters()
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'stonedem.figures' has no attribute {name!r}")


def figures(config: dict | None = None) -> dict[str, Figure]:
    """Every figure of the catalogue, inputs unresolved (``config``: its snapshot_pgas)."""
    snap = (config or {}).get("snapshot_pgas", {})
    return {name: figure for chapter in chapters() for name, figure in chapter.figures(snap)}


def tables() -> dict[str, Reduction]:
    """Every CSV table of the catalogue, inputs unresolved."""
    return {name: table for chapter in chapters() for name, table in chapter.tables()}


def reduction_table(studies: dict) -> dict[str, Reduction]:
    """Every table whose cubes are in ``studies`` ({study: {case id: Case}})."""
    return available(tables(), studies)


def figure_table(studies: dict, config: dict | None = None) -> dict[str, Figure]:
    """Every figure whose inputs are in ``studies`` ({study: {case id: Case}}) and the tables
    made from them; a case input names the one configured case with its parameters (left
    out when none or several match)."""
    return available(figures(config), studies, reduction_table(studies))
