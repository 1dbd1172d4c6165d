"""Chapter 6 of the thesis: single columns under harmonics, ramps and records (Fig. 6.1-6.31),
and their tables (sliding and rocking vs frequency, ramp thresholds).

:func:`figures` and :func:`tables` are this chapter's part of the catalogue (stonedem.figures).
"""

from __future__ import annotations

from functools import partial

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.catalogue import Cube, Figure, Record, Reduction
from stonedem.figures.drawing import (
    RECORD_LABEL,
    THESIS_RECORD,
    _finish,
    _label,
    _log_frequency_axis,
    _save,
    _value_label,
    collapsed_label,
    geometry_figure,
    history_figure,
    load_cube,
    snapshot_figure,
)

# harmonic studies reduced to sliding and rocking vs frequency (thesis Fig. 6.1, 6.5, 6.6)
from stonedem.io.netcdf import open_result
from stonedem.study.reduce import frequency_response, ramp_thresholds

FREQUENCY_STUDIES = ("harmonic_frequency", "small_column_friction", "small_column_pga")
# columns under a linear acceleration ramp, 1-8 drums and tapered (thesis 6.3)
RAMP_DRUMS = Cube("ramp_drums", {"n_drums": None})
RAMP_TAPER = Cube("ramp_taper", {"taper": None})


def tables():
    """This chapter's CSV tables: name, Reduction."""
    for study in FREQUENCY_STUDIES:
        yield f"frequency_response_{study}", Reduction((Cube(study),), frequency_response)
    # PGA to initiate rocking and to overturn (thesis Fig. 6.10, 6.13)
    yield "thesis_fig_6_10", Reduction((RAMP_DRUMS,), partial(ramp_thresholds, along="n_drums"))
    yield "thesis_fig_6_13", Reduction((RAMP_TAPER,), partial(ramp_thresholds, along="taper"))


# --- ordering (issue 4: checked on the cube, verdict printed on the figure) ------------------


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
    return (
        f"Thesis 6.1 ordering (rocking at low, sliding at high frequency): "
        f"{'holds' if holds else 'does NOT hold'} on every curve: rocking dominates at the "
        "lowest frequency "
        f"that moves the column on {low_ok} of {n} curves; at {f.max():g} Hz the base slides "
        "under a standing "
        f"column on {high_ok} of {n}."
    )


# --- special figures ------------------------------------------------------------------------


def _ramp_thresholds_figure(along, xlabel, title):
    def draw(inputs, path):
        rows = ramp_thresholds(load_cube(inputs[0]), along)
        x = [r[along] for r in rows]
        fig, ax = plt.subplots(figsize=(6, 4.2), constrained_layout=True)
        onset = [r["rocking_onset_pga_m_s2"] for r in rows]
        over = [r["overturning_pga_m_s2"] for r in rows]
        ax.plot(x, onset, "o-", label="rocking onset (engine)")
        ax.plot(x, over, "s-", label="overturning (engine)")
        ax.plot(
            x,
            [r["static_rocking_pga_m_s2"] for r in rows],
            "k:",
            label="static g b/h (thesis Eq. 6.2)",
        )
        ax.set_xlabel(xlabel)
        ax.set_ylabel("base acceleration [m s-2]")
        ax.legend(fontsize=8)
        verdict = ""
        if along == "taper":
            holds = all(b >= a for a, b in zip(over, over[1:]))
            verdict = (
                f"Thesis 6.3.2 ordering (taper raises the overturning PGA): "
                f"{'holds' if holds else 'does NOT hold'}: "
                f"{', '.join(f'{v:.3g}' for v in over)} m/s2."
            )
        _finish(fig, title, verdict)
        return _save(fig, path)

    return draw


def _ramp_histories(along, title):
    def draw(inputs, path):
        cube = load_cube(inputs[0])
        fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
        for v in cube[along].values:
            case = cube.sel({along: v})
            ax.plot(
                case["base_acceleration"], case["rocking"], lw=0.9, label=_value_label(along, v)
            )
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
    """One curve per (amplitude or PGA) x friction of ``variable`` vs frequency (Fig. 6.1, 6.5,
    6.6)."""

    def draw(inputs, path):
        cube = load_cube(inputs[0])
        rows = frequency_response(cube)
        keys = [k for k in ("amplitude", "pga", "friction") if k in rows[0]]
        fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
        groups = sorted({tuple(r[k] for k in keys) for r in rows})
        for g in groups:
            sel = sorted(
                (r for r in rows if tuple(r[k] for k in keys) == g), key=lambda r: r["frequency"]
            )
            (line,) = ax.plot(
                [r["frequency"] for r in sel],
                [r[variable] for r in sel],
                "o-",
                label=", ".join(_value_label(k, v) for k, v in zip(keys, g)),
            )
            fell = [
                r for r in sel if r["collapsed"] >= 0.5
            ]  # an ensemble's fraction (K = 1: 0 or 1)
            ax.plot(
                [r["frequency"] for r in fell], [r[variable] for r in fell], "x", color="r", ms=9
            )
        if variable == "sliding_to_base_ratio":
            ax.axhline(1.0, color="k", ls=":", lw=0.8, label="thesis: -> 1 at high frequency")
        _log_frequency_axis(ax)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7, title=f"red x: {collapsed_label(cube)}", title_fontsize=7)
        cube.attrs["column_height"] = height  # [m], to compare rocking x height with sliding
        _finish(fig, title, rocking_then_sliding(cube))
        return _save(fig, path)

    return draw


def _small_column_figure(inputs, path):
    """Thesis Fig. 6.1: small-scale column, total sliding and rocking vs frequency, (a) per mu, (b)
    per PGA."""
    fig, axes = plt.subplots(2, 2, figsize=(10, 7), constrained_layout=True)
    verdicts = []
    for col, (file, hue) in enumerate(zip(inputs, ("friction", "pga"))):
        cube = load_cube(file)
        for v in cube[hue].values:
            case = cube.sel({hue: v})
            label = _value_label(hue, v)
            axes[0, col].plot(case["frequency"], case["max_total_sliding"] * 100, "o-", label=label)
            axes[1, col].plot(case["frequency"], case["max_rocking"], "o-", label=label)
        for row, name in enumerate(
            ("total sliding [cm]", "rocking (max mean drum rotation) [rad]")
        ):
            ax = axes[row, col]
            _log_frequency_axis(ax)
            ax.set_ylabel(name)
            ax.legend(fontsize=7)
        axes[0, col].set_title(
            "(a) PGA 2.15 m/s2, per friction" if col == 0 else "(b) mu = 0.68, per PGA", fontsize=9
        )
        cube.attrs["column_height"] = 0.203
        verdicts.append(("(a) " if col == 0 else "(b) ") + rocking_then_sliding(cube))
    _finish(
        fig,
        "Thesis Fig. 6.1: small-scale 7-block column (48 x 29 mm blocks) under harmonic base "
        "motion",
        "\n".join(verdicts),
    )
    return _save(fig, path)


def _spectra_figure(records, pgas):
    """Thesis Fig. 6.14: 10 %-damped pseudo-acceleration spectra of the records scaled to their
    snapshot PGAs."""

    def draw(inputs, path):
        fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
        for file, name in zip(inputs, records):
            with open_result(file) as rec:
                scale = pgas[name] / float(np.abs(rec["acceleration_corrected"]).max())
                psa = rec["psa"].sel(damping=0.10, method="nearest") * scale
                ax.plot(
                    rec["period"],
                    psa,
                    label=f"{RECORD_LABEL.get(name, name)} x {scale:.3g} (PGA {pgas[name]:g} m/s2)",
                )
        ax.set_xscale("log")
        ax.set_xlabel("period [s]")
        ax.set_ylabel("pseudo-acceleration, 10 % damping [m s-2]")
        ax.legend(fontsize=7)
        _finish(
            fig,
            "Thesis Fig. 6.14: response spectra of the records scaled to the PGAs of the snapshots",
        )
        return _save(fig, path)

    return draw


# --- the figures ---------------------------------------------------------------------------


def figures(snap):
    """This chapter's figures: name, Figure (``snap``: the config's snapshot_pgas)."""
    yield (
        "thesis_fig_6_1",
        Figure(
            "6.1",
            "Total sliding and rocking of the small-scale 7-block column (thesis 5.2.2) vs "
            "harmonic frequency, "
            "(a) for three friction coefficients at PGA 2.15 m/s2 and (b) for four PGAs at mu "
            "= 0.68. "
            "Regenerates thesis Fig. 6.1; the verdict line checks 'rocking at low, sliding at "
            "high frequency'.",
            (Cube("small_column_friction"), Cube("small_column_pga")),
            _small_column_figure,
        ),
    )
    for fig, f in (("6_2", 0.5), ("6_3", 2.0), ("6_4", 20.0)):
        params = {"amplitude": 0.25, "frequency": f, "friction": 0.48}
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                "harmonic_frequency",
                params,
                f"Thesis Fig. {fig.replace('_', '.')}: 8-drum column, harmonic {f:g} Hz, 0.25 m",
                f"Snapshots of the 8-drum 6 m x 1 m column under a {f:g} Hz, 0.25 m harmonic "
                "base displacement "
                f"(mu = 0.48). Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    yield (
        "thesis_fig_6_5",
        Figure(
            "6.5",
            "Ratio of the maximum total sliding to the base displacement amplitude vs "
            "frequency, 8-drum column, "
            "per amplitude and friction coefficient (red x: collapsed). Regenerates thesis "
            "Fig. 6.5 (the thesis: "
            "the ratio tends to 1 at high frequency).",
            (Cube("harmonic_frequency", {"friction": None}),),
            _frequency_figure(
                "sliding_to_base_ratio",
                "max total sliding / base amplitude [1]",
                "Thesis Fig. 6.5: sliding-to-base-movement ratio, 8-drum 6 m x 1 m column",
            ),
        ),
    )
    yield (
        "thesis_fig_6_6",
        Figure(
            "6.6",
            "Maximum mean drum rotation (rocking) vs frequency, 8-drum column, per amplitude "
            "and friction "
            "coefficient. Regenerates thesis Fig. 6.6.",
            (Cube("harmonic_frequency", {"friction": None}),),
            _frequency_figure(
                "max_rocking_rad",
                "max mean drum rotation [rad]",
                "Thesis Fig. 6.6: rocking response, 8-drum 6 m x 1 m column",
            ),
        ),
    )
    for fig, n in (("6_7", 4), ("6_8", 2)):
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                "harmonic_drums",
                {"n_drums": n},
                f"Thesis Fig. {fig.replace('_', '.')}: {n}-drum column (drum height {6 / n:g} "
                "m), 0.5 Hz, 0.25 m",
                f"Snapshots of a {n}-drum 6 m x 1 m column under a 0.5 Hz, 0.25 m harmonic. "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    yield (
        "thesis_fig_6_9",
        Figure(
            "6.9",
            "Mean column rotation vs the base acceleration of a 0.5 m/s2/s ramp, 1-8 drums. "
            "Regenerates thesis Fig. 6.9.",
            (RAMP_DRUMS,),
            _ramp_histories(
                "n_drums", "Thesis Fig. 6.9: mean rotation under a 0.5 m/s2/s acceleration ramp"
            ),
        ),
    )
    yield (
        "thesis_fig_6_10",
        Figure(
            "6.10",
            "Base acceleration at which rocking starts (mean rotation > theta_cr/30) and at "
            "which the column "
            "overturns, vs the number of drums, with the static value g b/h. Regenerates "
            "thesis Fig. 6.10.",
            (RAMP_DRUMS,),
            _ramp_thresholds_figure(
                "n_drums",
                "number of drums [1]",
                "Thesis Fig. 6.10: acceleration to start rocking and to overturn, 6 m x 1 m column",
            ),
        ),
    )
    tapers = [1.0, 1.5, 2.0]
    yield (
        "thesis_fig_6_11",
        geometry_figure(
            "6.11",
            "ramp_taper",
            [{"taper": t} for t in tapers],
            "Thesis Fig. 6.11: tapered 4-drum columns of equal mass",
            "The tapered 4-drum columns (base/top width 1, 1.5, 2 at constant mass). "
            "Regenerates thesis Fig. 6.11.",
        ),
    )
    yield (
        "thesis_fig_6_12",
        Figure(
            "6.12",
            "Mean rotation of the tapered columns vs the ramp's base acceleration. Regenerates "
            "thesis Fig. 6.12.",
            (RAMP_TAPER,),
            _ramp_histories(
                "taper", "Thesis Fig. 6.12: mean rotation of tapered columns under the ramp"
            ),
        ),
    )
    yield (
        "thesis_fig_6_13",
        Figure(
            "6.13",
            "Acceleration to start rocking and to overturn vs taper W_b/W_t; the verdict line "
            "checks that "
            "tapered columns need a higher PGA to overturn (thesis 6.3.2). Regenerates thesis "
            "Fig. 6.13.",
            (RAMP_TAPER,),
            _ramp_thresholds_figure(
                "taper",
                "base / top width W_b/W_t [1]",
                "Thesis Fig. 6.13: tapered 4-drum columns at constant mass",
            ),
        ),
    )
    standalone = snap.get("standalone", {})
    if standalone:
        names = [THESIS_RECORD[r] for r in ("athens", "kalamata", "mexico") if r in standalone]
        pgas = {THESIS_RECORD[r]: v for r, v in standalone.items()}
        yield (
            "thesis_fig_6_14",
            Figure(
                "6.14",
                "10 %-damped pseudo-acceleration spectra of the stand-in records scaled to the "
                "PGAs of the "
                "standalone snapshots. Regenerates thesis Fig. 6.14.",
                tuple(Record(n) for n in names),
                _spectra_figure(names, pgas),
            ),
        )
    for fig, rec, n in (
        ("6_15", "athens", 4),
        ("6_16", "kalamata", 4),
        ("6_17", "mexico", 4),
        ("6_18", "athens", 2),
        ("6_19", "athens", 3),
        ("6_20", "kalamata", 2),
        ("6_21", "kalamata", 3),
        ("6_22", "mexico", 2),
        ("6_23", "mexico", 3),
    ):
        if rec not in standalone:
            continue
        params = {"record": THESIS_RECORD[rec], "n_drums": n, "pga": float(standalone[rec])}
        yield (
            f"thesis_fig_{fig}",
            snapshot_figure(
                fig.replace("_", "."),
                "snapshots_standalone",
                params,
                f"Thesis Fig. {fig.replace('_', '.')}: {n}-drum column, {rec.capitalize()} "
                "stand-in at PGA "
                f"{standalone[rec]:g} m/s2",
                f"Snapshots of a {n}-drum standalone column under the {rec.capitalize()} "
                "stand-in record scaled to "
                f"PGA {standalone[rec]:g} m/s2 (above our collapse PGA; the thesis' record "
                "needed a different PGA). "
                f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
            ),
        )
    for n, figs in ((4, ("6_24", "6_25", "6_26", "6_27")), (8, ("6_28", "6_29", "6_30", "6_31"))):
        for fig, mu in zip(figs, (0.05, 0.2, 0.25, 0.35)):
            yield (
                f"thesis_fig_{fig}",
                history_figure(
                    fig.replace("_", "."),
                    "friction_levels",
                    "total_sliding",
                    "weak_joint",
                    {"n_drums": n, "weak_joint_mu": mu},
                    f"Thesis Fig. {fig.replace('_', '.')}: {n}-block column, one joint at mu = "
                    f"{mu:g} "
                    f"(others 0.48), harmonic 0.5 Hz, 0.3 m",
                    f"Total sliding history of a {n}-block column with one joint at friction "
                    f"{mu:g} (the rest 0.48), "
                    "one curve per position of that joint (0 = base joint), and its maximum "
                    "per position. "
                    f"Regenerates thesis Fig. {fig.replace('_', '.')}.",
                ),
            )
