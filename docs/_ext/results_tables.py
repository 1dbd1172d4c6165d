"""Sphinx directive ``results-table``: a table read from a results file when the docs are built.

The numbers on the results pages are never typed: each table is read from the CSV (or
NetCDF) file the workflow wrote. In MyST::

    ```{results-table} results/tables/validation_summary.csv
    :columns: name, error=error (relative), tolerance, passed
    :make: snakemake -j2 validation_all
    ```

The path is relative to the repository root (the folder above ``docs/``). Options:

``columns``   the columns to show, in order, comma-separated; ``name=Header`` renames one
              (default: every column of the file)
``where``     keep the rows whose columns equal the values: ``system=colonnade; n_drums=1``;
              ``name=a|b`` keeps either
``digits``    significant digits of floating-point values (default 4)
``max-rows``  show at most this many rows and say how many were left out
``make``      the command that makes the file, for the note shown when it is missing
              (default ``snakemake -j2``)
``caption``   a title above the table
``variables`` NetCDF only: the data variables to tabulate (``Dataset.to_dataframe``, the
              dimensions as leading columns)
``attrs``     NetCDF only: these global attributes as a two-column table instead

A file that is not there (a fresh clone that has not run the study, or a docs build after
the quick study, which makes only some tables), or one with no row that ``where`` selects,
gives a short note, not a warning, so the ``-W`` build passes. A file that is there but lacks an
asked-for column, variable or attribute is a warning: the page has drifted from what the workflow
writes."""

from __future__ import annotations

import csv
import math
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

logger = logging.getLogger(__name__)

DEFAULT_MAKE = "snakemake -j2"
DEFAULT_DIGITS = 4


def _split(text: str, sep: str = ",") -> list[str]:
    return [part.strip() for part in (text or "").split(sep) if part.strip()]


def format_value(value, digits: int = DEFAULT_DIGITS) -> str:
    """A cell's text: integers and words as written, floats to ``digits`` significant digits."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "–"
        if value.is_integer() and abs(value) < 1e6:
            return str(int(value))
        return f"{value:.{digits}g}"
    text = str(value).strip()
    try:
        number = float(text)
    except ValueError:
        return text
    if text.lower() in ("nan", "inf", "-inf", "infinity", "-infinity"):
        return "–" if text.lower() == "nan" else text
    if all(c in "+-0123456789" for c in text):  # an integer as written
        return text
    return format_value(number, digits)


def read_csv(path: Path) -> tuple[list[str], list[dict]]:
    with path.open(newline="") as fh:
        reader = csv.DictReader(fh)
        return list(reader.fieldnames or []), list(reader)


def read_netcdf(path: Path, variables: list[str], attrs: list[str]):
    """(header, rows) of a NetCDF file: its attributes ``attrs`` as name/value rows, or the
    data variables ``variables`` flattened to a table (dimensions first); the names the
    file lacks as a third item."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        if attrs:
            missing = [a for a in attrs if a not in ds.attrs]
            rows = [{"attribute": a, "value": ds.attrs[a]} for a in attrs if a in ds.attrs]
            return ["attribute", "value"], rows, missing
        names = variables or list(ds.data_vars)
        missing = [v for v in names if v not in ds.variables]
        frame = ds[[v for v in names if v not in missing]].load().to_dataframe().reset_index()
    header = [str(c) for c in frame.columns]
    rows = [{str(k): v for k, v in record.items()} for record in frame.to_dict("records")]
    return header, rows, missing


def _matches(row: dict, where: dict) -> bool:
    return all(
        any(_equal(row.get(key), one) for one in want.split("|")) for key, want in where.items()
    )


def _equal(have, want: str) -> bool:
    if str(have).strip() == want:
        return True
    try:
        return float(have) == float(want)
    except (TypeError, ValueError):
        return False


def build_table(header: list[str], rows: list[list[str]], caption: str | None) -> nodes.table:
    table = nodes.table(classes=["results-table"])
    if caption:
        table += nodes.title(text=caption)
    group = nodes.tgroup(cols=len(header))
    table += group
    for _ in header:
        group += nodes.colspec(colwidth=1)
    head = nodes.thead()
    group += head
    head += _row(header)
    body = nodes.tbody()
    group += body
    for cells in rows:
        body += _row(cells)
    return table


def _row(cells: list[str]) -> nodes.row:
    row = nodes.row()
    for text in cells:
        entry = nodes.entry()
        entry += nodes.paragraph(text=text)
        row += entry
    return row


def missing_note(relpath: str, make: str) -> nodes.note:
    para = nodes.paragraph()
    para += nodes.literal(text=relpath)
    para += nodes.Text(" is not there yet: run ")
    para += nodes.literal(text=make)
    para += nodes.Text(" to make this table.")
    return nodes.note("", para)


class ResultsTable(SphinxDirective):
    required_arguments = 1
    has_content = False
    option_spec = {
        "columns": directives.unchanged,
        "where": directives.unchanged,
        "digits": directives.nonnegative_int,
        "max-rows": directives.nonnegative_int,
        "make": directives.unchanged,
        "caption": directives.unchanged,
        "variables": directives.unchanged,
        "attrs": directives.unchanged,
    }

    def run(self):
        relpath = self.arguments[0]
        root = Path(self.env.srcdir, self.config.results_tables_root).resolve()
        path = root / relpath
        # rebuild the page when the file changes (or appears: a missing one always rebuilds it)
        self.env.note_dependency(str(path))
        if not path.is_file():
            return [missing_note(relpath, self.options.get("make", DEFAULT_MAKE))]
        digits = self.options.get("digits", DEFAULT_DIGITS)
        absent = []
        try:
            if path.suffix == ".nc":
                header, rows, absent = read_netcdf(
                    path, _split(self.options.get("variables")), _split(self.options.get("attrs"))
                )
            else:
                header, rows = read_csv(path)
        except Exception as exc:  # a corrupt or half-written file: say so, do not crash the build
            logger.warning(
                f"results-table: cannot read {relpath}: {exc}", location=self.get_location()
            )
            return []
        columns, titles = [], []
        for spec in _split(self.options.get("columns")) or header:
            name, _, title = spec.partition("=")
            columns.append(name.strip())
            titles.append(title.strip() or name.strip())
        where = {}
        for cond in _split(self.options.get("where", ""), ";"):
            key, _, value = cond.partition("=")
            where[key.strip()] = value.strip()
        absent += [c for c in columns + list(where) if c not in header]
        if absent:
            logger.warning(
                f"results-table: {relpath} has no {', '.join(sorted(set(absent)))} "
                f"(it has: {', '.join(header)})",
                location=self.get_location(),
            )
            return []
        kept = [row for row in rows if _matches(row, where)]
        if not kept:  # e.g. a quick run that made fewer rows than the page selects
            para = nodes.paragraph()
            para += nodes.literal(text=relpath)
            para += nodes.Text(
                " has no rows" + (f" where {self.options['where']}" if where else "") + " yet: run "
            )
            para += nodes.literal(text=self.options.get("make", DEFAULT_MAKE))
            para += nodes.Text(" to make them.")
            return [nodes.note("", para)]
        limit = self.options.get("max-rows")
        shown = kept if limit is None else kept[:limit]
        cells = [[format_value(row.get(c), digits) for c in columns] for row in shown]
        out = [build_table(titles, cells, self.options.get("caption"))]
        source = nodes.paragraph(classes=["results-table-source"])
        source += nodes.Text("From ")
        source += nodes.literal(text=relpath)
        if len(shown) < len(kept):
            source += nodes.Text(f" (the first {len(shown)} of {len(kept)} rows)")
        source += nodes.Text(".")
        out.append(source)
        return out


class SchemaTable(SphinxDirective):
    """``{schema-table} SCENE_VARIABLES``: a variable table of :mod:`stonedem.io.schema`
    (name, units, long name), read at build time, so the page never drifts from the files."""

    required_arguments = 1
    has_content = False

    def run(self):
        from stonedem.io import schema

        table = getattr(schema, self.arguments[0], None)
        if not isinstance(table, dict):
            logger.warning(
                f"schema-table: stonedem.io.schema has no table {self.arguments[0]}",
                location=self.get_location(),
            )
            return []
        rows = [[name, units, long_name] for name, (units, long_name) in table.items()]
        return [build_table(["variable", "units", "long name"], rows, None)]


def setup(app):
    # where results/ lives, relative to docs/ (conf.py's folder)
    app.add_config_value("results_tables_root", "..", "env")
    app.add_directive("results-table", ResultsTable)
    app.add_directive("schema-table", SchemaTable)
    return {"version": "1.0", "parallel_read_safe": True, "parallel_write_safe": True}
