"""Chapter 7 of the thesis: colonnades (Fig. 7.1-7.58, Table 7.1), and their tables (epistyle
response per one-parameter study, Table 7.1).

:func:`figures` and :func:`tables` are this chapter's part of the catalogue (stonedem.figures).
"""

from __future__ import annotations

import csv
import math

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.errors import InputError
from stonedem.figures.catalogue import Cube, Figure, Reduction, Table
from stonedem.figures.drawing import (
    RECORD_LABEL,
    THESIS_RECORD,
    _finish,
    _label,
    _save,
    geometry_figure,
    history_figure,
    load_cube,
    snapshot_figure,
)
from stonedem.study.reduce import epistyle_response, table_7_1

# colonnade studies that vary one parameter at a time, reduced to the epistyle response (thesis
# 7.3-7.8)
EPISTYLE_STUDIES = (
    "colonnade_arrangements",
    "colonnade_columns",
    "colonnade_distance",
    "colonnade_distance_load",
    "colonnade_epistyle_type",
    "colonnade_epistyle_density",
    "colonnade_taper",
)
# the two studies of thesis Table 7.1 and Fig. 7.22 (a standalone column beside a colonnade)
RECORD_STUDIES = (
    Cube("standalone_records", {"record": None}),
    Cube("colonnade_records", {"record": None}),
)


def tables():
    """This chapter's CSV tables: name, Reduction."""
    for study in EPISTYLE_STUDIES:
        yield f"epistyle_{study}", Reduction((Cube(study),), epistyle_response)
    yield "table_7_1", Reduction(RECORD_STUDIES, table_7_1)


# --- ordering (issue 4: checked on the cube, verdict printed on the figure) ------------------


def heavier_epistyle_moves_less(cube: xr.Dataset) -> str:
    """Thesis 7.7: the maximum epistyle displacement falls as the epistyle density rises."""
    peak = cube["max_epistyle_displacement"]
    rho = cube["epistyle_density"].values
    light, heavy = peak.sel(epistyle_density=rho.min()), peak.sel(epistyle_density=rho.max())
    holds = bool((heavy <= light).all())
    return (
        "Thesis 7.7 ordering (heavier epistyle moves less): "
        f"{'holds' if holds else 'does NOT hold'} here: "
        f"max displacement {float(light.max()):.3g} m at {rho.min():g} kg/m3 vs "
        f"{float(heavy.max()):.3g} m at {rho.max():g} kg/m3."
    )


# --- Table 7.1 and Fig. 7.22: standalone column vs colonnade ------------------------------


def _runs(cube: xr.Dataset, record, n: int) -> dict:
    """{pga: that run's data} of one system of a record study: a threshold search's runs
    (``run`` dimension, pga a coordinate) or a grid's pga levels."""
    system = cube.sel(record=record, n_drums=n)
    if "run" in system.dims:
        runs = [system.isel(run=i) for i in range(system.sizes["run"])]
        return {float(r["pga"]): r for r in runs if np.isfinite(float(r["pga"]))}
    return {float(p): system.sel(pga=p) for p in system["pga"].values}


def _standalone_vs_colonnade(inputs, path):
    """Thesis Fig. 7.22: mean drum rotation of a standalone column and of a colonnade, same record
    and PGA (the largest PGA both were run at that the colonnade survives: the searches share their
    hunt
    values)."""
    single, row = load_cube(inputs[0]), load_cube(inputs[1])
    for cube in (single, row):
        if "rocking" not in cube:  # a search with histories: false keeps the runs' measures only
            raise InputError(
                f"studies.{cube.attrs.get('study', '?')}.search.histories",
                "false: its searches kept no time histories, which Fig. 7.22 draws",
                "set histories: true (the default) in that study's search:",
            )
    record = (
        THESIS_RECORD["athens"]
        if THESIS_RECORD["athens"] in row["record"].values
        else row["record"].values[0]
    )
    n = int(row["n_drums"].values.min())
    alone, together = _runs(single, record, n), _runs(row, record, n)
    common = sorted(set(alone) & set(together))
    survived = [p for p in common if not float(together[p]["collapsed"]) > 0]
    pga = max(survived) if survived else min(common)
    fig, ax = plt.subplots(figsize=(9, 4.2), constrained_layout=True)
    for case, label in (
        (alone[pga], "standalone column"),
        (together[pga], "colonnade with epistyle"),
    ):
        ax.plot(
            case["time"],
            case["rocking"],
            lw=0.8,
            label=f"{label} (collapsed: {bool(case['collapsed'] > 0)})",
        )
    ax.set_xlabel("time [s]")
    ax.set_ylabel(_label(single["rocking"]), fontsize=8)
    ax.legend(fontsize=8)
    _finish(
        fig,
        f"Thesis Fig. 7.22: {n}-drum column alone and in a colonnade, "
        f"{RECORD_LABEL.get(record, record)},\n"
        f"PGA {pga:g} m/s2 (the largest PGA run for both that the colonnade survives)",
    )
    return _save(fig, path)


def _table_7_1_figure(inputs, path):
    """Our collapse threshold (the bracket: largest survivor to smallest collapse) vs the
    thesis' Table 7.1, per system and record."""
    with open(inputs[0]) as handle:
        rows = list(csv.DictReader(handle))
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    markers = {"colonnade": "s", "single column": "o"}
    none = 80.0  # where a system that never collapsed is drawn
    for system in markers:
        sel = [
            r
            for r in rows
            if r["system"] == system and not math.isnan(float(r["thesis_accel_to_failure_m_s2"]))
        ]
        thesis = [float(r["thesis_accel_to_failure_m_s2"]) for r in sel]
        ours = [
            none if math.isnan(float(r["collapse_pga_m_s2"])) else float(r["collapse_pga_m_s2"])
            for r in sel
        ]
        below = [
            0.0
            if math.isnan(float(r["survived_pga_m_s2"])) or o == none
            else o - float(r["survived_pga_m_s2"])
            for r, o in zip(sel, ours)
        ]
        ax.errorbar(
            thesis,
            ours,
            yerr=[below, [0.0] * len(ours)],
            fmt=markers[system],
            ms=5,
            capsize=2,
            label=system,
        )
        for r, t, o in zip(sel, thesis, ours):
            ax.annotate(f"{r['thesis_record'][:3]} {r['n_drums']}d", (t, o), fontsize=6)
    ax.plot([0.8, none], [0.8, none], "k:", lw=0.8, label="equal")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("thesis: acceleration to failure [m s-2] (Table 7.1)")
    ax.set_ylabel(
        "engine: smallest collapsing PGA [m s-2]\n(bar down to the largest survivor below it)"
    )
    ax.legend(fontsize=8)
    _finish(
        fig,
        f"Thesis Table 7.1 with stand-in records (ours: collapse threshold by search; {none:g} "
        "= none)",
        table_7_1_orderings(rows),
    )
    return _save(fig, path)


def table_7_1_orderings(rows: list[dict]) -> str:
    """Thesis 6.4 / 7.2: Mexico < Kalamata < Athens, and a colonnade needs at least the column's
    PGA."""

    def value(system, rec, n):
        for r in rows:
            if r["system"] == system and r["thesis_record"] == rec and int(r["n_drums"]) == n:
                v = float(r["collapse_pga_m_s2"])
                return math.inf if math.isnan(v) else v
        return None

    drums = sorted({int(r["n_drums"]) for r in rows})
    recs = [
        r for r in ("mexico", "kalamata", "athens") if any(x["thesis_record"] == r for x in rows)
    ]
    freq_ok, row_ok, misses = True, True, []
    for system in ("single column", "colonnade"):
        for n in drums:
            vals = [value(system, r, n) for r in recs]
            if any(v is None for v in vals):
                continue
            if any(b < a for a, b in zip(vals, vals[1:])):
                freq_ok = False
                misses.append(f"{system} {n} drums: {vals}")
    for rec in recs:
        for n in drums:
            col, single = value("colonnade", rec, n), value("single column", rec, n)
            if col is not None and single is not None and col < single:
                row_ok = False
                misses.append(f"{rec} {n} drums: colonnade {col:g} < column {single:g}")
    text = (
        "Lower predominant frequency -> lower collapse PGA: "
        f"{'holds' if freq_ok else 'does NOT hold'}. "
        f"Colonnade >= standalone column: {'holds' if row_ok else 'does NOT hold'}."
    )
    return text + (" Misses: " + "; ".join(misses) if misses else "")


# --- the figures ---------------------------------------------------------------------------


def figures(snap):
    """This chapter's figures: name, Figure (``snap``: the config's snapshot_pgas)."""
    for fig, rec, n in (
        ("7_1", "athens", 2),
        ("7_2", "athens", 3),
        ("7_3", "kalamata", 2),
        ("7_4", "kalamata", 3),
        ("7_5", "mexico", 2),
        ("7_6", "mexico", 3),
    ):
        pga = snap.get("colonnade", {}).get(rec)
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                "snapshots_colonnade",
                {"record": THESIS_RECORD[rec], "n_drums": n, "pga": pga},
                f"Thesis Fig. {fig.replace('_', '.')}: colonnade of {n}-drum columns, "
                f"{rec.capitalize()} stand-in",
                f"Snapshots of a colonnade of three {n}-drum columns with one epistyle under "
                f"the {rec.capitalize()} "
                "stand-in (PGA in the case name). Regenerates thesis Fig. "
                f"{fig.replace('_', '.')}.",
            ),
        )
    k = 7
    for rec in ("athens", "kalamata", "mexico"):
        for n in (1, 2, 3, 7):
            fig = f"7_{k}"
            k += 1
            pga = snap.get("colonnade", {}).get(rec)
            yield (
                f"thesis_fig_{fig}",
                snapshot_figure(
                    fig.replace("_", "."),
                    "snapshots_capital",
                    {"record": THESIS_RECORD[rec], "n_drums": n, "pga": pga},
                    f"Thesis Fig. {fig.replace('_', '.')}: colonnade, {n}-drum columns with "
                    "capitals, "
                    f"{rec.capitalize()} stand-in",
                    f"Snapshots of a colonnade of three {n}-drum columns with capitals and an "
                    "epistyle under the "
                    f"{rec.capitalize()} stand-in. Regenerates thesis Fig. "
                    f"{fig.replace('_', '.')}.",
                ),
            )
    for fig, rec in (("7_19", "athens"), ("7_20", "kalamata"), ("7_21", "mexico")):
        yield (
            f"thesis_fig_{fig}",
            history_figure(
                fig.replace("_", "."),
                "colonnade_arrangements",
                "epistyle_displacement",
                "n_drums",
                {"record": THESIS_RECORD[rec], "pga": snap.get("arrangements", {}).get(rec)},
                f"Thesis Fig. {fig.replace('_', '.')}: epistyle displacement, colonnades of "
                "1-3 drum columns, "
                f"{rec.capitalize()} stand-in",
                "Horizontal epistyle displacement relative to the base for colonnades of 1, 2 "
                "and 3-drum columns "
                f"under the {rec.capitalize()} stand-in scaled by the thesis' factor. "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    yield (
        "thesis_fig_7_22",
        Figure(
            "7.22",
            "Mean drum rotation of a standalone column and of the same columns in a colonnade "
            "with an "
            "epistyle, same record and PGA. Regenerates thesis Fig. 7.22.",
            RECORD_STUDIES,
            _standalone_vs_colonnade,
        ),
    )
    yield (
        "thesis_fig_7_23",
        geometry_figure(
            "7.23",
            "colonnade_columns",
            [{"n_columns": c, "n_drums": 2} for c in (3, 4, 5)],
            "Thesis Fig. 7.23: arrangements of 3, 4 and 5 columns with a single epistyle",
            "The simulated arrangements of 3, 4 and 5 two-drum columns with one epistyle. "
            "Regenerates thesis Fig. 7.23.",
        ),
    )
    for fig, c in (("7_24", 3), ("7_25", 4), ("7_26", 5)):
        yield (
            f"thesis_fig_{fig}",
            history_figure(
                fig.replace("_", "."),
                "colonnade_columns",
                "epistyle_displacement",
                "n_drums",
                {"n_columns": c},
                f"Thesis Fig. {fig.replace('_', '.')}: {c} columns with a single epistyle, by "
                "number of drums",
                f"Epistyle displacement of a colonnade of {c} columns with one epistyle, one "
                "curve per number of "
                f"drums. Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    for fig, n, typ, what in (
        ("7_27", 1, "per_span", "monolithic columns, one epistyle per span"),
        ("7_28", 1, "a", "monolithic columns, single epistyle"),
        ("7_29", 2, "a", "two-drum columns, single epistyle"),
        ("7_30", 4, "a", "four-drum columns, single epistyle"),
    ):
        yield (
            f"thesis_fig_{fig}",
            history_figure(
                fig.replace("_", "."),
                "colonnade_distance",
                "epistyle_displacement",
                "clear_distance",
                {"n_drums": n, "epistyle_type": typ},
                f"Thesis Fig. {fig.replace('_', '.')}: clear distance between columns, {what}",
                f"Epistyle displacement for clear distances 1.5-4 m, {what}. "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    yield (
        "thesis_fig_7_31",
        geometry_figure(
            "7.31",
            "colonnade_distance",
            [{"clear_distance": d, "n_drums": 1, "epistyle_type": "a"} for d in (1.5, 4.0)],
            "Thesis Fig. 7.31: the smallest and largest clear distance",
            "Monolithic colonnades at the smallest and largest clear distance. Regenerates "
            "thesis Fig. 7.31.",
        ),
    )
    yield (
        "thesis_fig_7_32",
        history_figure(
            "7.32",
            "colonnade_distance_load",
            "epistyle_displacement",
            "clear_distance",
            {"epistyle_density": 10000.0},
            "Thesis Fig. 7.32: clear distance with a heavy (10000 kg/m3) epistyle, monolithic "
            "columns",
            "Epistyle displacement vs clear distance for monolithic columns carrying a heavier "
            "epistyle. "
            "Regenerates thesis Fig. 7.32.",
        ),
    )
    for fig, c in (("7_33", 3), ("7_34", 4)):
        yield (
            f"thesis_fig_{fig}",
            history_figure(
                fig.replace("_", "."),
                "colonnade_epistyle_type",
                "epistyle_displacement",
                "epistyle_type",
                {"n_columns": c},
                f"Thesis Fig. {fig.replace('_', '.')}: {c} monolithic columns, epistyle types "
                "a-d (thesis Table 7.2)",
                f"Epistyle displacement of {c} monolithic columns for epistyle types a-d "
                "(thesis Table 7.2). "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    k = 35
    for c in (3, 4, 5):
        for n in (1, 2):
            fig = f"7_{k}"
            k += 1
            yield (
                f"thesis_fig_{fig}",
                history_figure(
                    fig.replace("_", "."),
                    "colonnade_epistyle_density",
                    "epistyle_displacement",
                    "epistyle_density",
                    {"n_columns": c, "n_drums": n},
                    f"Thesis Fig. {fig.replace('_', '.')}: epistyle mass, {c} columns of {n} "
                    "drum(s)",
                    f"Epistyle displacement for epistyle densities 5000-10000 kg/m3, {c} "
                    f"columns of {n} drum(s); the "
                    f"verdict line checks thesis 7.7 (a heavier epistyle moves less). "
                    f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
                    check=heavier_epistyle_moves_less,
                ),
            )
    for fig, hue, select, what in (
        ("7_41", "taper", {"n_drums": 1, "epistyle_density": 5000.0}, "monolithic tapered columns"),
        (
            "7_42",
            "taper",
            {"n_drums": 1, "epistyle_density": 10000.0},
            "monolithic, heavier epistyle",
        ),
        (
            "7_43",
            "taper",
            {"n_drums": 2, "epistyle_density": 10000.0},
            "two-drum, heavier epistyle",
        ),
        (
            "7_44",
            "n_drums",
            {"taper": 1.5, "epistyle_density": 5000.0},
            "tapered 1/2/4-drum columns",
        ),
        (
            "7_45",
            "n_drums",
            {"taper": 1.5, "epistyle_density": 10000.0},
            "tapered, heavier epistyle",
        ),
        (
            "7_46",
            "taper",
            {"n_drums": 1, "epistyle_density": 5000.0},
            "tapered vs non-tapered, monolithic",
        ),
        (
            "7_47",
            "taper",
            {"n_drums": 2, "epistyle_density": 5000.0},
            "tapered vs non-tapered, two drums",
        ),
        (
            "7_48",
            "taper",
            {"n_drums": 3, "epistyle_density": 5000.0},
            "tapered vs non-tapered, three drums",
        ),
        (
            "7_49",
            "taper",
            {"n_drums": 4, "epistyle_density": 5000.0},
            "tapered vs non-tapered, four drums",
        ),
    ):
        yield (
            f"thesis_fig_{fig}",
            history_figure(
                fig.replace("_", "."),
                "colonnade_taper",
                "epistyle_displacement",
                hue,
                select,
                f"Thesis Fig. {fig.replace('_', '.')}: {what}",
                f"Epistyle displacement of colonnades, {what}. Regenerates thesis Fig. "
                f"{fig.replace('_', '.')}.",
            ),
        )
    for fig, rec, scale in (("7_50", "athens", 9.0), ("7_51", "mexico", 1.5)):
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                "two_tier_records",
                {"record": THESIS_RECORD[rec], "pga_scale": scale},
                f"Thesis Fig. {fig.replace('_', '.')}: two-tier colonnade, {rec.capitalize()} "
                "stand-in",
                f"Snapshots of the two-tier colonnade under the {rec.capitalize()} stand-in "
                "scaled by the thesis' "
                f"factor. Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    for fig, study, f, a in (
        ("7_52", "two_tier_harmonic", 2.0, 0.25),
        ("7_53", "two_tier_harmonic", 1.33, 0.25),
        ("7_54", "two_tier_harmonic", 1.0, 0.25),
        ("7_55", "two_tier_harmonic", 0.5, 0.1),
        ("7_56", "two_tier_drums_harmonic", 1.33, 0.25),
        ("7_57", "two_tier_drums_harmonic", 1.0, 0.1),
        ("7_58", "two_tier_drums_harmonic", 0.5, 0.25),
    ):
        kind = "two-drum" if "drums" in study else "monolithic"
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                study,
                {"frequency": f, "amplitude": a},
                f"Thesis Fig. {fig.replace('_', '.')}: two-tier colonnade ({kind} columns), "
                f"{f:g} Hz, {a:g} m",
                f"Snapshots of the two-tier colonnade with {kind} columns under a {f:g} Hz, "
                f"{a:g} m harmonic. "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    yield (
        "table_7_1",
        Figure(
            "Table 7.1",
            "Smallest collapsing PGA of each system found by hunt-and-fill search (bar: down "
            "to the largest "
            "PGA below it that survived), ours vs the thesis' Table 7.1 (our records are "
            "stand-ins); the verdict line "
            "checks the frequency ordering and colonnade >= column.",
            (Table("table_7_1"),),
            _table_7_1_figure,
        ),
    )
