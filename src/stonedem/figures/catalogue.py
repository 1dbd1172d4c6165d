"""Catalogue entries (a figure, a CSV table) and the inputs they name symbolically.

An entry names what it reads, not where it lies: a study's cube (:class:`Cube`), one
configured case (:class:`Case`), another entry's table (:class:`Table`) or a record
(:class:`Record`). The workflow maps each kind to its file (``CATALOGUE_PATHS`` in
workflow/rules/common.smk) with :func:`input_paths`. :func:`available` keeps the entries
whose inputs are all in the configured studies (a reduced profile makes fewer).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable


def matching_cases(cases: dict, params: dict) -> list:
    """The cases of {id: Case} whose parameters include ``params`` (a value None: any value)."""
    fixed = {k: v for k, v in params.items() if v is not None}
    return [
        c
        for c in cases.values()
        if set(params) <= set(c.params) and all(c.params[k] == v for k, v in fixed.items())
    ]


@dataclass(frozen=True)
class Cube:
    """A study's cube; ``where``: parameters (None: any value) some configured case must have."""

    study: str
    where: dict = field(default_factory=dict)

    def resolve(self, studies: dict, tables) -> Cube | None:
        return self if matching_cases(studies.get(self.study, {}), self.where) else None

    def wildcards(self) -> dict:
        return {"study": self.study}


@dataclass(frozen=True)
class Case:
    """The one configured case of ``study`` whose parameters include ``params`` (None: any
    value). :meth:`resolve` sets its ``id``: a grid key added to the study is part of the id."""

    study: str
    params: dict
    id: str | None = None

    def resolve(self, studies: dict, tables) -> Case | None:
        found = matching_cases(studies.get(self.study, {}), self.params)
        if (
            "member" not in self.params
        ):  # an ensemble's members of the case: member 0, as configured
            found = [c for c in found if c.params.get("member", 0) == 0]
        return replace(self, id=found[0].id) if len(found) == 1 else None

    def wildcards(self) -> dict:
        return {"study": self.study, "case": self.id}


@dataclass(frozen=True)
class Table:
    """The CSV of a catalogue table, made when its own inputs are configured."""

    name: str

    def resolve(self, studies: dict, tables) -> Table | None:
        return self if self.name in tables else None

    def wildcards(self) -> dict:
        return {"table": self.name}


@dataclass(frozen=True)
class Record:
    """A ground-motion record file."""

    name: str

    def resolve(self, studies: dict, tables) -> Record:
        return self

    def wildcards(self) -> dict:
        return {"name": self.name}


@dataclass(frozen=True)
class Figure:
    thesis: str  # thesis figure number, e.g. "6.10"
    caption: str  # what the figure shows (report caption)
    inputs: tuple  # Cube, Case, Table, Record: their paths are draw()'s inputs, in this order
    draw: Callable  # draw(inputs: list[str], path) -> Path


@dataclass(frozen=True)
class Reduction:
    """A CSV table: a stonedem.study.reduce function of the input cubes, written by
    stonedem.io.atomic.write_csv."""

    inputs: tuple  # Cube refs, in the order reduce() takes the cubes
    reduce: Callable  # reduce(*cubes) -> rows (list of dicts)

    def write(self, paths: list, path) -> Path:
        from stonedem.io.atomic import write_csv
        from stonedem.io.netcdf import open_result  # xarray: only when reducing

        cubes = []
        for file in paths:
            with open_result(file) as cube:
                cubes.append(cube.load())
        return write_csv(path, self.reduce(*cubes))


def available(entries: dict, studies: dict, tables=()) -> dict:
    """The entries whose inputs all resolve in ``studies`` ({study: {case id: Case}}) and
    ``tables`` (names of the tables made), with their inputs resolved."""
    found = {}
    for name, entry in entries.items():
        inputs = [ref.resolve(studies, tables) for ref in entry.inputs]
        if all(ref is not None for ref in inputs):
            found[name] = replace(entry, inputs=tuple(inputs))
    return found


def input_paths(refs, patterns: dict) -> list[str]:
    """The files of resolved refs; ``patterns``: {kind: path pattern of the ref's wildcards}."""
    return [patterns[type(ref).__name__].format(**ref.wildcards()) for ref in refs]
