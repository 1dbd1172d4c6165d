"""Figures of the study, named after the thesis figure they regenerate (``thesis_fig_6_10``).

The registry is built from the study's case tables (:func:`figure_table`): each entry names
its input files (cubes, case files, tables, records), a drawing function and a caption
saying what it shows and which thesis figure it regenerates. A figure whose cases are not
in the configured grid (e.g. a reduced profile) is left out, not drawn from missing data.
Where an ordering the thesis reports is checked on the data, the verdict is printed under
the plot, so a figure never claims more than the cube shows.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from dem.atomic import write_atomically  # noqa: E402
from dem.reduce import frequency_response, ramp_thresholds  # noqa: E402
from dem.study import case_id  # noqa: E402

G = 9.81
THESIS_RECORD = {"athens": "athens_standin_kocaeli_arc000", "kalamata": "kalamata_standin_izmit_izt270",
                 "mexico": "mexico_standin_chichi_tcu102"}
RECORD_LABEL = {v: f"{k.capitalize()} stand-in" for k, v in THESIS_RECORD.items()}


@dataclass(frozen=True)
class Figure:
    thesis: str  # thesis figure number, e.g. "6.10"
    caption: str  # what the figure shows (report caption)
    inputs: tuple  # input paths, in the order draw() takes them
    draw: Callable  # draw(inputs: list[str], path) -> Path
    requires: tuple = field(default=())  # (study, params) cases that must be in the configured grids
    # (study, params) of each case file in ``inputs``: figure_table names the file of the one
    # configured case with these parameters (a grid may sweep more keys, in any order)
    cases: tuple = field(default=())


def cube_path(study: str) -> str:
    return f"results/cubes/{study}.nc"


def case_path(study: str, params: dict) -> str:
    return f"results/cases/{study}/{case_id(params)}.nc"


# --- drawing helpers ----------------------------------------------------------------------


def _save(fig, path) -> Path:
    """Write a PNG atomically (dem.atomic) and close the figure."""
    try:
        return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=110))
    finally:
        plt.close(fig)


def _label(da) -> str:
    return f"{da.attrs.get('long_name', da.name)} [{da.attrs.get('units', '')}]"


def _value_label(name: str, value) -> str:
    if name == "record":
        return RECORD_LABEL.get(str(value), str(value))
    units = {"n_drums": " drums", "n_columns": " columns", "clear_distance": " m", "epistyle_density": " kg/m3",
             "taper": "", "frequency": " Hz", "amplitude": " m", "friction": "", "pga": " m/s2",
             "weak_joint": "", "epistyle_type": ""}
    prefix = {"taper": "Wb/Wt = ", "friction": "mu = ", "weak_joint": "weak joint ", "epistyle_type": "type "}
    v = f"{value:g}" if isinstance(value, (float, np.floating)) else str(value)
    return f"{prefix.get(name, '')}{v}{units.get(name, '')}"


def _finish(fig, title: str, verdict: str = "") -> None:
    """Title, and the ordering verdict in a strip kept free under the axes."""
    fig.suptitle(title, fontsize=9)
    if verdict:
        lines = sum(1 + len(line) // 170 for line in verdict.splitlines())
        strip = (0.16 * lines + 0.05) / fig.get_figheight()
        fig.get_layout_engine().set(rect=(0, strip, 1, 1 - strip))
        fig.text(0.01, 0.005, verdict, fontsize=7.5, ha="left", va="bottom", wrap=True,
                 color="darkred" if "does NOT hold" in verdict else "darkgreen")


def _log_frequency_axis(ax) -> None:
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    ax.set_xscale("log")
    ax.xaxis.set_major_formatter(ScalarFormatter())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("harmonic frequency [Hz]")


def _sel(cube: xr.Dataset, select: dict, keep=()) -> xr.Dataset:
    """Fix the ``select`` parameters; of the other dimensions (a sparse cube of listed cases)
    keep only the entries that were run, and squeeze those of size one."""
    cube = cube.sel({k: v for k, v in select.items() if k in cube.dims}) if select else cube
    for dim in [d for d in cube.dims if d not in (*keep, "time")]:
        cube = cube.dropna(dim, how="all", subset=["collapsed"])
        if cube.sizes[dim] == 1:
            cube = cube.squeeze(dim)
    return cube


# --- generic kinds --------------------------------------------------------------------------


def history_figure(thesis, study, variable, hue, select, title, caption, check=None, scalar=None):
    """Time histories of ``variable`` for each value of ``hue`` (other parameters fixed by
    ``select``), beside its maximum per value (thesis Fig. 6.24-6.31, 7.19-7.49)."""
    scalar = scalar or f"max_{variable}"

    def draw(inputs, path):
        with xr.open_dataset(inputs[0]) as cube:
            cube = _sel(cube.load(), select, keep=(hue,))
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [2.2, 1]},
                                       constrained_layout=True)
        values = cube[hue].values
        peaks = []
        for v in values:
            case = cube.sel({hue: v})
            ax1.plot(case["time"], case[variable], lw=0.8, label=_value_label(hue, v))
            peak = float(case[scalar]) if scalar in case else float(np.nanmax(np.abs(case[variable])))
            peaks.append(peak)
            if float(case["collapsed"]) > 0:
                ax1.axvline(float(case["collapse_time"]), color=ax1.lines[-1].get_color(), ls=":", lw=0.8)
        ax1.set_xlabel(_label(cube["time"]))
        ax1.set_ylabel(_label(cube[variable]), fontsize=8)
        ax1.legend(fontsize=7, ncol=2)
        xs = np.arange(len(values)) if values.dtype.kind in "OUS" else values
        ax2.plot(xs, peaks, "o-")
        collapsed = [float(cube.sel({hue: v})["collapsed"]) > 0 for v in values]
        ax2.plot(np.asarray(xs)[collapsed], np.asarray(peaks)[collapsed], "rx", ms=10, label="collapsed")
        if values.dtype.kind in "OUS":
            ax2.set_xticks(xs, [str(v) for v in values])
        ax2.set_xlabel(_label(cube[hue]))
        ax2.set_ylabel(f"maximum of the left panel [{cube[variable].attrs.get('units', '')}]")
        if any(collapsed):
            ax2.legend(fontsize=7)
        _finish(fig, title, check(cube) if check else "")
        return _save(fig, path)

    inputs = (cube_path(study),)
    return Figure(thesis, caption, inputs, draw, requires=((study, {hue: None, **select}),))


def snapshot_figure(thesis, study, params, title, caption, n=6):
    """A strip of snapshots of one case (thesis snapshot sequences)."""

    def draw(inputs, path):
        from dem.snapshots import snapshot_strip

        with xr.open_dataset(inputs[0]) as ds:
            return snapshot_strip(ds.load(), path, n=n, title=title)

    return Figure(thesis, caption, (case_path(study, params),), draw, requires=((study, params),),
                  cases=((study, params),))


def geometry_figure(thesis, study, cases, title, caption):
    """The initial geometry of several cases side by side (thesis Fig. 6.11, 7.23, 7.31)."""

    def draw(inputs, path):
        from matplotlib.collections import PolyCollection

        from dem.snapshots import body_polygons, posed_polygons

        fig, axes = plt.subplots(1, len(inputs), figsize=(3.2 * len(inputs), 3.6), constrained_layout=True)
        for ax, file, params in zip(np.atleast_1d(axes), inputs, cases):
            with xr.open_dataset(file) as ds:
                local = body_polygons(ds)
                polys = posed_polygons(local, ds.x[0].values, ds.y[0].values, ds.theta[0].values)
                roles = [str(r) for r in ds["body_role"].values]
            colours = ["0.6" if r == "base" else "tan" if r == "epistyle" else "wheat" for r in roles]
            ax.add_collection(PolyCollection(polys, facecolors=colours, edgecolors="k", linewidths=0.5))
            xs = np.concatenate([p[:, 0] for p, r in zip(polys, roles) if r != "base"])
            ys = np.concatenate([p[:, 1] for p in polys])
            ax.set_xlim(xs.min() - 0.5, xs.max() + 0.5)
            ax.set_ylim(max(ys.min(), -0.6), ys.max() + 0.3)
            ax.set_aspect("equal")
            ax.set_title(", ".join(_value_label(k, v) for k, v in params.items()), fontsize=8)
            ax.set_xlabel("x [m]")
        np.atleast_1d(axes)[0].set_ylabel("y [m]")
        _finish(fig, title)
        return _save(fig, path)

    return Figure(thesis, caption, tuple(case_path(study, p) for p in cases), draw,
                  requires=tuple((study, p) for p in cases), cases=tuple((study, p) for p in cases))


# --- orderings (issue 4: checked on the cube, verdict printed on the figure) -----------------


def heavier_epistyle_moves_less(cube: xr.Dataset) -> str:
    """Thesis 7.7: the maximum epistyle displacement falls as the epistyle density rises."""
    peak = cube["max_epistyle_displacement"]
    rho = cube["epistyle_density"].values
    light, heavy = peak.sel(epistyle_density=rho.min()), peak.sel(epistyle_density=rho.max())
    holds = bool((heavy <= light).all())
    return (f"Thesis 7.7 ordering (heavier epistyle moves less): {'holds' if holds else 'does NOT hold'} here: "
            f"max displacement {float(light.max()):.3g} m at {rho.min():g} kg/m3 vs "
            f"{float(heavy.max()):.3g} m at {rho.max():g} kg/m3.")


def rocking_then_sliding(cube: xr.Dataset) -> str:
    """Thesis 6.1: rocking dominates at low frequency, sliding at high frequency.

    Per curve (every combination of the other swept parameters): at the lowest frequency
    where the column moves at all (rocking angle x height or sliding above 1e-3 x height),
    rocking x height must exceed the total sliding; at the highest frequency the total
    sliding must exceed rocking x height and the column must stand.
    """
    height = float(cube.attrs.get("column_height", 1.0))
    others = [d for d in cube["max_rocking"].dims if d != "frequency"]
    stacked = cube[["max_rocking", "max_total_sliding", "collapsed"]]
    stacked = stacked.stack(curve=others) if others else stacked.expand_dims(curve=[0])
    low_ok = high_ok = 0
    n = stacked.sizes["curve"]
    for i in range(n):
        curve = stacked.isel(curve=i)
        rock = curve["max_rocking"].values * height
        slide = curve["max_total_sliding"].values
        moving = np.flatnonzero(np.maximum(rock, slide) > 1e-3 * height)
        if len(moving):
            k = moving[0]
            low_ok += bool(rock[k] > slide[k])
        high_ok += bool(slide[-1] > rock[-1] and curve["collapsed"].values[-1] == 0)
    f = cube["frequency"].values
    holds = low_ok == n and high_ok == n
    return (f"Thesis 6.1 ordering (rocking at low, sliding at high frequency): "
            f"{'holds' if holds else 'does NOT hold'} on every curve: rocking dominates at the lowest frequency "
            f"that moves the column on {low_ok} of {n} curves; at {f.max():g} Hz the base slides under a standing "
            f"column on {high_ok} of {n}.")


# --- special figures ------------------------------------------------------------------------


def _ramp_thresholds_figure(along, xlabel, title):
    def draw(inputs, path):
        with xr.open_dataset(inputs[0]) as cube:
            rows = ramp_thresholds(cube.load(), along)
        x = [r[along] for r in rows]
        fig, ax = plt.subplots(figsize=(6, 4.2), constrained_layout=True)
        onset = [r["rocking_onset_pga_m_s2"] for r in rows]
        over = [r["overturning_pga_m_s2"] for r in rows]
        ax.plot(x, onset, "o-", label="rocking onset (engine)")
        ax.plot(x, over, "s-", label="overturning (engine)")
        ax.plot(x, [r["static_rocking_pga_m_s2"] for r in rows], "k:", label="static g b/h (thesis Eq. 6.2)")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("base acceleration [m s-2]")
        ax.legend(fontsize=8)
        verdict = ""
        if along == "taper":
            holds = all(b >= a for a, b in zip(over, over[1:]))
            verdict = (f"Thesis 6.3.2 ordering (taper raises the overturning PGA): "
                       f"{'holds' if holds else 'does NOT hold'}: {', '.join(f'{v:.3g}' for v in over)} m/s2.")
        _finish(fig, title, verdict)
        return _save(fig, path)

    return draw


def _ramp_histories(along, title):
    def draw(inputs, path):
        with xr.open_dataset(inputs[0]) as cube:
            cube = cube.load()
        fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
        for v in cube[along].values:
            case = cube.sel({along: v})
            ax.plot(case["base_acceleration"], case["rocking"], lw=0.9, label=_value_label(along, v))
        theta_cr = float(cube["theta_cr"].max())
        ax.axhline(theta_cr, color="k", ls=":", lw=0.8, label=f"theta_cr = {theta_cr:.3f} rad")
        ax.set_ylim(0, 1.5 * theta_cr)
        ax.set_xlabel(_label(cube["base_acceleration"]))
        ax.set_ylabel(_label(cube["rocking"]))
        ax.legend(fontsize=7)
        _finish(fig, title)
        return _save(fig, path)

    return draw


def _frequency_figure(variable, ylabel, title, height=6.0):
    """One curve per (amplitude or PGA) x friction of ``variable`` vs frequency (Fig. 6.1, 6.5, 6.6)."""

    def draw(inputs, path):
        with xr.open_dataset(inputs[0]) as cube:
            cube = cube.load()
        rows = frequency_response(cube)
        keys = [k for k in ("amplitude", "pga", "friction") if k in rows[0]]
        fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
        groups = sorted({tuple(r[k] for k in keys) for r in rows})
        for g in groups:
            sel = sorted((r for r in rows if tuple(r[k] for k in keys) == g), key=lambda r: r["frequency"])
            line, = ax.plot([r["frequency"] for r in sel], [r[variable] for r in sel], "o-",
                            label=", ".join(_value_label(k, v) for k, v in zip(keys, g)))
            fell = [r for r in sel if r["collapsed"]]
            ax.plot([r["frequency"] for r in fell], [r[variable] for r in fell], "x", color="r", ms=9)
        if variable == "sliding_to_base_ratio":
            ax.axhline(1.0, color="k", ls=":", lw=0.8, label="thesis: -> 1 at high frequency")
        _log_frequency_axis(ax)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7, title="red x: collapsed", title_fontsize=7)
        cube.attrs["column_height"] = height  # [m], to compare rocking x height with sliding
        _finish(fig, title, rocking_then_sliding(cube))
        return _save(fig, path)

    return draw


def _small_column_figure(inputs, path):
    """Thesis Fig. 6.1: small-scale column, total sliding and rocking vs frequency, (a) per mu, (b) per PGA."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
    verdicts = []
    for col, (file, hue) in enumerate(zip(inputs, ("friction", "pga"))):
        with xr.open_dataset(file) as cube:
            cube = cube.load()
        for v in cube[hue].values:
            case = cube.sel({hue: v})
            label = _value_label(hue, v)
            axes[0, col].plot(case["frequency"], case["max_total_sliding"] * 100, "o-", label=label)
            axes[1, col].plot(case["frequency"], case["max_rocking"], "o-", label=label)
        for row, name in enumerate(("total sliding [cm]", "rocking (max mean drum rotation) [rad]")):
            ax = axes[row, col]
            _log_frequency_axis(ax)
            ax.set_ylabel(name)
            ax.legend(fontsize=7)
        axes[0, col].set_title("(a) PGA 2.15 m/s2, per friction" if col == 0 else "(b) mu = 0.68, per PGA",
                               fontsize=9)
        cube.attrs["column_height"] = 0.203
        verdicts.append(("(a) " if col == 0 else "(b) ") + rocking_then_sliding(cube))
    _finish(fig, "Thesis Fig. 6.1: small-scale 7-block column (48 x 29 mm blocks) under harmonic base motion",
            "\n".join(verdicts))
    return _save(fig, path)


def _spectra_figure(records, pgas):
    """Thesis Fig. 6.14: 10 %-damped pseudo-acceleration spectra of the records scaled to their snapshot PGAs."""

    def draw(inputs, path):
        fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
        for file, name in zip(inputs, records):
            with xr.open_dataset(file) as rec:
                scale = pgas[name] / float(np.abs(rec["acceleration_corrected"]).max())
                psa = rec["psa"].sel(damping=0.10, method="nearest") * scale
                ax.plot(rec["period"], psa, label=f"{RECORD_LABEL.get(name, name)} x {scale:.3g} "
                                                  f"(PGA {pgas[name]:g} m/s2)")
        ax.set_xscale("log")
        ax.set_xlabel("period [s]")
        ax.set_ylabel("pseudo-acceleration, 10 % damping [m s-2]")
        ax.legend(fontsize=7)
        _finish(fig, "Thesis Fig. 6.14: response spectra of the records scaled to the PGAs of the snapshots")
        return _save(fig, path)

    return draw


def _standalone_vs_colonnade(inputs, path):
    """Thesis Fig. 7.22: mean drum rotation of a standalone column and of a colonnade, same record and PGA."""
    with xr.open_dataset(inputs[0]) as single, xr.open_dataset(inputs[1]) as row:
        single, row = single.load(), row.load()
    record = THESIS_RECORD["athens"] if THESIS_RECORD["athens"] in row["record"].values else row["record"].values[0]
    n = int(row["n_drums"].values.min())
    both = (row["collapsed"].sel(record=record, n_drums=n) == 0) & (single["collapsed"].sel(record=record, n_drums=n) >= 0)
    pgas = row["pga"].values[both.values]
    pga = float(pgas.max()) if len(pgas) else float(row["pga"].values.min())
    fig, ax = plt.subplots(figsize=(9, 4.2), constrained_layout=True)
    for cube, label in ((single, "standalone column"), (row, "colonnade with epistyle")):
        case = cube.sel(record=record, n_drums=n, pga=pga)
        ax.plot(case["time"], case["rocking"], lw=0.8, label=f"{label} (collapsed: {bool(case['collapsed'] > 0)})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(_label(single["rocking"]), fontsize=8)
    ax.legend(fontsize=8)
    _finish(fig, f"Thesis Fig. 7.22: {n}-drum column alone and in a colonnade, {RECORD_LABEL.get(record, record)},\n"
                 f"PGA {pga:g} m/s2 (the largest grid PGA the colonnade survives)")
    return _save(fig, path)


def _table_7_1_figure(inputs, path):
    """Smallest collapsing PGA of the grid vs the thesis' Table 7.1, per system and record."""
    with open(inputs[0]) as handle:
        rows = list(csv.DictReader(handle))
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    markers = {"colonnade": "s", "single column": "o"}
    for system in markers:
        sel = [r for r in rows if r["system"] == system and not math.isnan(float(r["thesis_accel_to_failure_m_s2"]))]
        ours = [float(r["collapse_pga_m_s2"]) for r in sel]
        ax.scatter([float(r["thesis_accel_to_failure_m_s2"]) for r in sel], [40.0 if math.isnan(o) else o for o in ours],
                   marker=markers[system], label=system)
        for r, o in zip(sel, ours):
            ax.annotate(f"{r['thesis_record'][:3]} {r['n_drums']}d", (float(r["thesis_accel_to_failure_m_s2"]), o),
                        fontsize=6)
    ax.plot([0.8, 40], [0.8, 40], "k:", lw=0.8, label="equal")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("thesis: acceleration to failure [m s-2] (Table 7.1)")
    ax.set_ylabel("engine: smallest collapsing PGA of the grid [m s-2]")
    ax.legend(fontsize=8)
    _finish(fig, "Thesis Table 7.1 with stand-in records (ours: smallest grid PGA that collapses; 40 = none)",
            table_7_1_orderings(rows))
    return _save(fig, path)


def table_7_1_orderings(rows: list[dict]) -> str:
    """Thesis 6.4 / 7.2: Mexico < Kalamata < Athens, and a colonnade needs at least the column's PGA."""
    def value(system, rec, n):
        for r in rows:
            if r["system"] == system and r["thesis_record"] == rec and int(r["n_drums"]) == n:
                v = float(r["collapse_pga_m_s2"])
                return math.inf if math.isnan(v) else v
        return None

    drums = sorted({int(r["n_drums"]) for r in rows})
    recs = [r for r in ("mexico", "kalamata", "athens") if any(x["thesis_record"] == r for x in rows)]
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
    text = (f"Lower predominant frequency -> lower collapse PGA: {'holds' if freq_ok else 'does NOT hold'}. "
            f"Colonnade >= standalone column: {'holds' if row_ok else 'does NOT hold'}.")
    return text + (" Misses: " + "; ".join(misses) if misses else "")


# --- the registry ---------------------------------------------------------------------------


def figure_table(studies: dict, config: dict | None = None) -> dict[str, Figure]:
    """Every figure whose cases are in ``studies`` ({study: {case id: Case}})."""
    config = config or {}
    snap = config.get("snapshot_pgas", {})
    candidates = dict(_chapter_6(snap)) | dict(_chapter_7(snap))
    table = {}
    for name, fig in candidates.items():
        if not _available(fig, studies):
            continue
        if fig.cases:
            # the file of the case the figure names, by its configured id (not by the figure's
            # own parameters: a grid key added to the study is part of the id); left out
            # when no case or several match
            found = [_one_case(studies[study], params) for study, params in fig.cases]
            if any(case is None for case in found):
                continue
            fig = replace(fig, inputs=tuple(f"results/cases/{case.study}/{case.id}.nc" for case in found))
        table[name] = fig
    return table


def _one_case(cases: dict, params: dict):
    """The one case of {id: Case} whose parameters include ``params`` (None: any value), or None."""
    fixed = {k: v for k, v in params.items() if v is not None}
    found = [c for c in cases.values()
             if set(params) <= set(c.params) and all(c.params[k] == v for k, v in fixed.items())]
    return found[0] if len(found) == 1 else None


def _available(fig: Figure, studies: dict) -> bool:
    for study, params in fig.requires:
        if study not in studies:
            return False
        cases = list(studies[study].values())
        fixed = {k: v for k, v in params.items() if v is not None}
        if not any(all(c.params.get(k) == v for k, v in fixed.items()) and set(params) <= set(c.params)
                   for c in cases):
            return False
    return True


def _chapter_6(snap):
    yield "thesis_fig_6_1", Figure(
        "6.1", "Total sliding and rocking of the small-scale 7-block column (thesis 5.2.2) vs harmonic frequency, "
        "(a) for three friction coefficients at PGA 2.15 m/s2 and (b) for four PGAs at mu = 0.68. "
        "Regenerates thesis Fig. 6.1; the verdict line checks 'rocking at low, sliding at high frequency'.",
        (cube_path("small_column_friction"), cube_path("small_column_pga")), _small_column_figure,
        requires=(("small_column_friction", {}), ("small_column_pga", {})))
    for fig, f in (("6_2", 0.5), ("6_3", 2.0), ("6_4", 20.0)):
        params = {"amplitude": 0.25, "frequency": f, "friction": 0.48}
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), "harmonic_frequency", params,
            f"Thesis Fig. {fig.replace('_', '.')}: 8-drum column, harmonic {f:g} Hz, 0.25 m",
            f"Snapshots of the 8-drum 6 m x 1 m column under a {f:g} Hz, 0.25 m harmonic base displacement "
            f"(mu = 0.48). Regenerates thesis Fig. {fig.replace('_', '.')}.")
    yield "thesis_fig_6_5", Figure(
        "6.5", "Ratio of the maximum total sliding to the base displacement amplitude vs frequency, 8-drum column, "
        "per amplitude and friction coefficient (red x: collapsed). Regenerates thesis Fig. 6.5 (the thesis: "
        "the ratio tends to 1 at high frequency).", (cube_path("harmonic_frequency"),),
        _frequency_figure("sliding_to_base_ratio", "max total sliding / base amplitude [1]",
                          "Thesis Fig. 6.5: sliding-to-base-movement ratio, 8-drum 6 m x 1 m column"),
        requires=(("harmonic_frequency", {"friction": None}),))
    yield "thesis_fig_6_6", Figure(
        "6.6", "Maximum mean drum rotation (rocking) vs frequency, 8-drum column, per amplitude and friction "
        "coefficient. Regenerates thesis Fig. 6.6.", (cube_path("harmonic_frequency"),),
        _frequency_figure("max_rocking_rad", "max mean drum rotation [rad]",
                          "Thesis Fig. 6.6: rocking response, 8-drum 6 m x 1 m column"),
        requires=(("harmonic_frequency", {"friction": None}),))
    for fig, n in (("6_7", 4), ("6_8", 2)):
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), "harmonic_drums", {"n_drums": n},
            f"Thesis Fig. {fig.replace('_', '.')}: {n}-drum column (drum height {6 / n:g} m), 0.5 Hz, 0.25 m",
            f"Snapshots of a {n}-drum 6 m x 1 m column under a 0.5 Hz, 0.25 m harmonic. "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    yield "thesis_fig_6_9", Figure(
        "6.9", "Mean column rotation vs the base acceleration of a 0.5 m/s2/s ramp, 1-8 drums. "
        "Regenerates thesis Fig. 6.9.", (cube_path("ramp_drums"),),
        _ramp_histories("n_drums", "Thesis Fig. 6.9: mean rotation under a 0.5 m/s2/s acceleration ramp"),
        requires=(("ramp_drums", {"n_drums": None}),))
    yield "thesis_fig_6_10", Figure(
        "6.10", "Base acceleration at which rocking starts (mean rotation > theta_cr/30) and at which the column "
        "overturns, vs the number of drums, with the static value g b/h. Regenerates thesis Fig. 6.10.",
        (cube_path("ramp_drums"),),
        _ramp_thresholds_figure("n_drums", "number of drums [1]",
                                "Thesis Fig. 6.10: acceleration to start rocking and to overturn, 6 m x 1 m column"),
        requires=(("ramp_drums", {"n_drums": None}),))
    tapers = [1.0, 1.5, 2.0]
    yield "thesis_fig_6_11", geometry_figure(
        "6.11", "ramp_taper", [{"taper": t} for t in tapers],
        "Thesis Fig. 6.11: tapered 4-drum columns of equal mass",
        "The tapered 4-drum columns (base/top width 1, 1.5, 2 at constant mass). Regenerates thesis Fig. 6.11.")
    yield "thesis_fig_6_12", Figure(
        "6.12", "Mean rotation of the tapered columns vs the ramp's base acceleration. Regenerates thesis Fig. 6.12.",
        (cube_path("ramp_taper"),),
        _ramp_histories("taper", "Thesis Fig. 6.12: mean rotation of tapered columns under the ramp"),
        requires=(("ramp_taper", {"taper": None}),))
    yield "thesis_fig_6_13", Figure(
        "6.13", "Acceleration to start rocking and to overturn vs taper W_b/W_t; the verdict line checks that "
        "tapered columns need a higher PGA to overturn (thesis 6.3.2). Regenerates thesis Fig. 6.13.",
        (cube_path("ramp_taper"),),
        _ramp_thresholds_figure("taper", "base / top width W_b/W_t [1]",
                                "Thesis Fig. 6.13: tapered 4-drum columns at constant mass"),
        requires=(("ramp_taper", {"taper": None}),))
    standalone = snap.get("standalone", {})
    if standalone:
        names = [THESIS_RECORD[r] for r in ("athens", "kalamata", "mexico") if r in standalone]
        pgas = {THESIS_RECORD[r]: v for r, v in standalone.items()}
        yield "thesis_fig_6_14", Figure(
            "6.14", "10 %-damped pseudo-acceleration spectra of the stand-in records scaled to the PGAs of the "
            "standalone snapshots. Regenerates thesis Fig. 6.14.", tuple(f"records/{n}.nc" for n in names),
            _spectra_figure(names, pgas))
    for fig, rec, n in (("6_15", "athens", 4), ("6_16", "kalamata", 4), ("6_17", "mexico", 4),
                        ("6_18", "athens", 2), ("6_19", "athens", 3), ("6_20", "kalamata", 2),
                        ("6_21", "kalamata", 3), ("6_22", "mexico", 2), ("6_23", "mexico", 3)):
        if rec not in standalone:
            continue
        params = {"record": THESIS_RECORD[rec], "n_drums": n, "pga": float(standalone[rec])}
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), "snapshots_standalone", params,
            f"Thesis Fig. {fig.replace('_', '.')}: {n}-drum column, {rec.capitalize()} stand-in at PGA "
            f"{standalone[rec]:g} m/s2",
            f"Snapshots of a {n}-drum standalone column under the {rec.capitalize()} stand-in record scaled to "
            f"PGA {standalone[rec]:g} m/s2 (above our collapse PGA; the thesis' record needed a different PGA). "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    for n, figs in ((4, ("6_24", "6_25", "6_26", "6_27")), (8, ("6_28", "6_29", "6_30", "6_31"))):
        for fig, mu in zip(figs, (0.05, 0.2, 0.25, 0.35)):
            yield f"thesis_fig_{fig}", history_figure(
                fig.replace("_", "."), "friction_levels", "total_sliding", "weak_joint",
                {"n_drums": n, "weak_joint_mu": mu},
                f"Thesis Fig. {fig.replace('_', '.')}: {n}-block column, one joint at mu = {mu:g} "
                f"(others 0.48), harmonic 0.5 Hz, 0.3 m",
                f"Total sliding history of a {n}-block column with one joint at friction {mu:g} (the rest 0.48), "
                f"one curve per position of that joint (0 = base joint), and its maximum per position. "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.")


def _chapter_7(snap):
    for fig, rec, n in (("7_1", "athens", 2), ("7_2", "athens", 3), ("7_3", "kalamata", 2),
                        ("7_4", "kalamata", 3), ("7_5", "mexico", 2), ("7_6", "mexico", 3)):
        pga = snap.get("colonnade", {}).get(rec)
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), "snapshots_colonnade", {"record": THESIS_RECORD[rec], "n_drums": n, "pga": pga},
            f"Thesis Fig. {fig.replace('_', '.')}: colonnade of {n}-drum columns, {rec.capitalize()} stand-in",
            f"Snapshots of a colonnade of three {n}-drum columns with one epistyle under the {rec.capitalize()} "
            f"stand-in (PGA in the case name). Regenerates thesis Fig. {fig.replace('_', '.')}.")
    k = 7
    for rec in ("athens", "kalamata", "mexico"):
        for n in (1, 2, 3, 7):
            fig = f"7_{k}"
            k += 1
            pga = snap.get("colonnade", {}).get(rec)
            yield f"thesis_fig_{fig}", snapshot_figure(
                fig.replace("_", "."), "snapshots_capital", {"record": THESIS_RECORD[rec], "n_drums": n, "pga": pga},
                f"Thesis Fig. {fig.replace('_', '.')}: colonnade, {n}-drum columns with capitals, "
                f"{rec.capitalize()} stand-in",
                f"Snapshots of a colonnade of three {n}-drum columns with capitals and an epistyle under the "
                f"{rec.capitalize()} stand-in. Regenerates thesis Fig. {fig.replace('_', '.')}.")
    for fig, rec in (("7_19", "athens"), ("7_20", "kalamata"), ("7_21", "mexico")):
        yield f"thesis_fig_{fig}", history_figure(
            fig.replace("_", "."), "colonnade_arrangements", "epistyle_displacement", "n_drums",
            {"record": THESIS_RECORD[rec], "pga": snap.get("arrangements", {}).get(rec)},
            f"Thesis Fig. {fig.replace('_', '.')}: epistyle displacement, colonnades of 1-3 drum columns, "
            f"{rec.capitalize()} stand-in",
            f"Horizontal epistyle displacement relative to the base for colonnades of 1, 2 and 3-drum columns "
            f"under the {rec.capitalize()} stand-in scaled by the thesis' factor. "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    yield "thesis_fig_7_22", Figure(
        "7.22", "Mean drum rotation of a standalone column and of the same columns in a colonnade with an "
        "epistyle, same record and PGA. Regenerates thesis Fig. 7.22.",
        (cube_path("standalone_records"), cube_path("colonnade_records")), _standalone_vs_colonnade,
        requires=(("standalone_records", {"record": None}), ("colonnade_records", {"record": None})))
    yield "thesis_fig_7_23", geometry_figure(
        "7.23", "colonnade_columns", [{"n_columns": c, "n_drums": 2} for c in (3, 4, 5)],
        "Thesis Fig. 7.23: arrangements of 3, 4 and 5 columns with a single epistyle",
        "The simulated arrangements of 3, 4 and 5 two-drum columns with one epistyle. Regenerates thesis Fig. 7.23.")
    for fig, c in (("7_24", 3), ("7_25", 4), ("7_26", 5)):
        yield f"thesis_fig_{fig}", history_figure(
            fig.replace("_", "."), "colonnade_columns", "epistyle_displacement", "n_drums", {"n_columns": c},
            f"Thesis Fig. {fig.replace('_', '.')}: {c} columns with a single epistyle, by number of drums",
            f"Epistyle displacement of a colonnade of {c} columns with one epistyle, one curve per number of "
            f"drums. Regenerates thesis Fig. {fig.replace('_', '.')}.")
    for fig, n, typ, what in (("7_27", 1, "per_span", "monolithic columns, one epistyle per span"),
                              ("7_28", 1, "a", "monolithic columns, single epistyle"),
                              ("7_29", 2, "a", "two-drum columns, single epistyle"),
                              ("7_30", 4, "a", "four-drum columns, single epistyle")):
        yield f"thesis_fig_{fig}", history_figure(
            fig.replace("_", "."), "colonnade_distance", "epistyle_displacement", "clear_distance",
            {"n_drums": n, "epistyle_type": typ},
            f"Thesis Fig. {fig.replace('_', '.')}: clear distance between columns, {what}",
            f"Epistyle displacement for clear distances 1.5-4 m, {what}. "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    yield "thesis_fig_7_31", geometry_figure(
        "7.31", "colonnade_distance", [{"clear_distance": d, "n_drums": 1, "epistyle_type": "a"} for d in (1.5, 4.0)],
        "Thesis Fig. 7.31: the smallest and largest clear distance",
        "Monolithic colonnades at the smallest and largest clear distance. Regenerates thesis Fig. 7.31.")
    yield "thesis_fig_7_32", history_figure(
        "7.32", "colonnade_distance_load", "epistyle_displacement", "clear_distance", {"epistyle_density": 10000.0},
        "Thesis Fig. 7.32: clear distance with a heavy (10000 kg/m3) epistyle, monolithic columns",
        "Epistyle displacement vs clear distance for monolithic columns carrying a heavier epistyle. "
        "Regenerates thesis Fig. 7.32.")
    for fig, c in (("7_33", 3), ("7_34", 4)):
        yield f"thesis_fig_{fig}", history_figure(
            fig.replace("_", "."), "colonnade_epistyle_type", "epistyle_displacement", "epistyle_type",
            {"n_columns": c},
            f"Thesis Fig. {fig.replace('_', '.')}: {c} monolithic columns, epistyle types a-d (thesis Table 7.2)",
            f"Epistyle displacement of {c} monolithic columns for epistyle types a-d (thesis Table 7.2). "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    k = 35
    for c in (3, 4, 5):
        for n in (1, 2):
            fig = f"7_{k}"
            k += 1
            yield f"thesis_fig_{fig}", history_figure(
                fig.replace("_", "."), "colonnade_epistyle_density", "epistyle_displacement", "epistyle_density",
                {"n_columns": c, "n_drums": n},
                f"Thesis Fig. {fig.replace('_', '.')}: epistyle mass, {c} columns of {n} drum(s)",
                f"Epistyle displacement for epistyle densities 5000-10000 kg/m3, {c} columns of {n} drum(s); the "
                f"verdict line checks thesis 7.7 (a heavier epistyle moves less). "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.", check=heavier_epistyle_moves_less)
    for fig, hue, select, what in (
            ("7_41", "taper", {"n_drums": 1, "epistyle_density": 5000.0}, "monolithic tapered columns"),
            ("7_42", "taper", {"n_drums": 1, "epistyle_density": 10000.0}, "monolithic, heavier epistyle"),
            ("7_43", "taper", {"n_drums": 2, "epistyle_density": 10000.0}, "two-drum, heavier epistyle"),
            ("7_44", "n_drums", {"taper": 1.5, "epistyle_density": 5000.0}, "tapered 1/2/4-drum columns"),
            ("7_45", "n_drums", {"taper": 1.5, "epistyle_density": 10000.0}, "tapered, heavier epistyle"),
            ("7_46", "taper", {"n_drums": 1, "epistyle_density": 5000.0}, "tapered vs non-tapered, monolithic"),
            ("7_47", "taper", {"n_drums": 2, "epistyle_density": 5000.0}, "tapered vs non-tapered, two drums"),
            ("7_48", "taper", {"n_drums": 3, "epistyle_density": 5000.0}, "tapered vs non-tapered, three drums"),
            ("7_49", "taper", {"n_drums": 4, "epistyle_density": 5000.0}, "tapered vs non-tapered, four drums")):
        yield f"thesis_fig_{fig}", history_figure(
            fig.replace("_", "."), "colonnade_taper", "epistyle_displacement", hue, select,
            f"Thesis Fig. {fig.replace('_', '.')}: {what}",
            f"Epistyle displacement of colonnades, {what}. Regenerates thesis Fig. {fig.replace('_', '.')}.")
    for fig, rec, scale in (("7_50", "athens", 9.0), ("7_51", "mexico", 1.5)):
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), "two_tier_records", {"record": THESIS_RECORD[rec], "pga_scale": scale},
            f"Thesis Fig. {fig.replace('_', '.')}: two-tier colonnade, {rec.capitalize()} stand-in",
            f"Snapshots of the two-tier colonnade under the {rec.capitalize()} stand-in scaled by the thesis' "
            f"factor. Regenerates thesis Fig. {fig.replace('_', '.')}.")
    for fig, study, f, a in (("7_52", "two_tier_harmonic", 2.0, 0.25), ("7_53", "two_tier_harmonic", 1.33, 0.25),
                             ("7_54", "two_tier_harmonic", 1.0, 0.25), ("7_55", "two_tier_harmonic", 0.5, 0.1),
                             ("7_56", "two_tier_drums_harmonic", 1.33, 0.25),
                             ("7_57", "two_tier_drums_harmonic", 1.0, 0.1),
                             ("7_58", "two_tier_drums_harmonic", 0.5, 0.25)):
        kind = "two-drum" if "drums" in study else "monolithic"
        yield f"thesis_fig_{fig}", snapshot_figure(
            fig.replace("_", "."), study, {"frequency": f, "amplitude": a},
            f"Thesis Fig. {fig.replace('_', '.')}: two-tier colonnade ({kind} columns), {f:g} Hz, {a:g} m",
            f"Snapshots of the two-tier colonnade with {kind} columns under a {f:g} Hz, {a:g} m harmonic. "
            f"Regenerates thesis Fig. {fig.replace('_', '.')}.")
    yield "table_7_1", Figure(
        "Table 7.1", "Smallest PGA of the grid that collapses each system, ours vs the thesis' Table 7.1 (our "
        "records are stand-ins); the verdict line checks the frequency ordering and colonnade >= column.",
        ("results/tables/table_7_1.csv",), _table_7_1_figure,
        requires=(("standalone_records", {"record": None}), ("colonnade_records", {"record": None})))
