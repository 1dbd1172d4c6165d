"""Figures of the IDA (issue 16, beyond the thesis): fragility curves per structure, the
median collapse intensities side by side, and the single block under the pulse records
against rigid one-sine theory (stonedem.fragility.checks)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.drawing import _finish, _save
from stonedem.fragility.ida import LIMIT_STATES, MEASURES

SET_COLOURS = {
    "far_field": "tab:blue",
    "near_field_pulse": "tab:red",
    "near_field_no_pulse": "tab:green",
    "all": "black",
}


def fragility_curves_figure(cube: xr.Dataset, fits: xr.Dataset, structure: str, path):
    """Rows: PGA, PGV; columns: limit states. Each record set's lognormal curve, all records
    with the bootstrap band and the empirical points (censored records count as not exceeded)."""
    states = [str(s) for s in fits.limit_state.values]
    fig, axes = plt.subplots(
        len(MEASURES),
        len(states),
        figsize=(3.1 * len(states), 5.6),
        squeeze=False,
        layout="constrained",
        sharey=True,
    )
    f = fits.sel(structure=structure)
    for m, (measure, (var, units, label)) in enumerate(MEASURES.items()):
        grid = fits[f"{measure}_grid"].values
        for j, state in enumerate(states):
            ax = axes[m, j]
            for rset in [str(s) for s in fits.record_set.values]:
                sel = f.sel(record_set=rset, limit_state=state)
                p = sel[f"probability_{measure}"].values
                if not np.isfinite(p).any():
                    continue
                ax.plot(
                    grid,
                    p,
                    color=SET_COLOURS.get(rset, "grey"),
                    lw=2 if rset == "all" else 1,
                    label=f"{rset}: {float(sel[f'median_{measure}']):.3g} {units}, "
                    f"beta {float(sel[f'beta_{measure}']):.2f}",
                )
                if rset == "all":
                    band = sel[f"probability_{measure}_band"].values
                    ax.fill_between(
                        grid, band[0], band[1], color="0.8", lw=0, label="90 % bootstrap band"
                    )
            x = cube[var].sel(structure=structure, limit_state=state).values
            c = cube.censored.sel(structure=structure, limit_state=state).values
            ran = c >= 0
            hit = np.sort(x[ran & (c == 0)])
            if hit.size:
                ax.plot(
                    hit,
                    np.arange(1, hit.size + 1) / ran.sum(),
                    "k.",
                    ms=3,
                    label="records (empirical)",
                )
            ax.set_xscale("log")
            ax.set_xlim(grid[0], grid[-1])
            ax.set_ylim(0, 1)
            ax.grid(alpha=0.3)
            ax.set_title(LIMIT_STATES[state].label if state in LIMIT_STATES else state, fontsize=8)
            ax.set_xlabel(f"{label} [{units}]", fontsize=8)
            ax.legend(fontsize=5.5, loc="upper left")
        axes[m, 0].set_ylabel("P(exceeded)")
    n = int((cube.censored.sel(structure=structure, limit_state="collapse") >= 0).sum())
    _finish(
        fig, f"Fragility of {structure}: {n} FEMA P695 components, lognormal MLE per record set"
    )
    return _save(fig, path)


def medians_figure(fits: xr.Dataset, pulse: xr.Dataset | None, path):
    """Left: median collapse PGA with its 90 % band per structure and record set; right (if
    a block was searched): the block's collapse under the pulse records in Makris &
    Vassiliou's coordinates beside the rigid one-sine minimum."""
    fig, axes = plt.subplots(
        1,
        2 if pulse is not None else 1,
        figsize=(11 if pulse is not None else 6, 4.2),
        layout="constrained",
        squeeze=False,
    )
    ax = axes[0, 0]
    structures = [str(s) for s in fits.structure.values]
    sets = [str(s) for s in fits.record_set.values]
    width = 0.8 / len(sets)
    for k, rset in enumerate(sets):
        sel = fits.sel(record_set=rset, limit_state="collapse")
        x = np.arange(len(structures)) + (k - (len(sets) - 1) / 2) * width
        med = sel.median_pga.values
        err = np.abs(sel.median_pga_band.values.T - med)
        ax.errorbar(
            x,
            med,
            yerr=err,
            fmt="o",
            color=SET_COLOURS.get(rset, "grey"),
            ms=4,
            capsize=2,
            label=rset,
        )
    ax.set_xticks(np.arange(len(structures)), structures, rotation=20, fontsize=7)
    ax.set_ylabel("median collapse PGA [m s-2]")
    if np.isfinite(fits.median_pga.sel(limit_state="collapse").values).any():
        ax.set_yscale("log")
    else:  # too few records with a collapse to fit (a lognormal needs two)
        ax.text(0.5, 0.5, "no fit: too few collapses", ha="center", transform=ax.transAxes)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("median collapse PGA, 90 % bootstrap band", fontsize=8)
    if pulse is not None:
        ax = axes[0, 1]
        order = np.argsort(pulse.omega_ratio.values)
        ok = pulse.censored.values == 0
        ax.plot(
            pulse.omega_ratio.values[order],
            pulse.rigid_one_sine.values[order],
            "k-",
            lw=1,
            label="rigid block, one-sine pulse (minimum overturning)",
        )
        ax.plot(
            pulse.omega_ratio.values[ok],
            pulse.collapse_ap_pgv.values[ok],
            "o",
            color="tab:red",
            ms=4,
            label="record collapse, a_p = omega_p PGV / 2",
        )
        ax.plot(
            pulse.omega_ratio.values[ok],
            pulse.collapse_ap_pga.values[ok],
            "x",
            color="tab:orange",
            ms=4,
            label="record collapse, a_p = PGA",
        )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("omega_p / p")
        ax.set_ylabel("a_p / (g tan alpha)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title(
            f"{pulse.attrs['structure']} under the near-field pulse records (Makris & Vassiliou)",
            fontsize=8,
        )
    _finish(fig, "IDA over the FEMA P695 suites: collapse medians and the pulse-record check")
    return _save(fig, path)


def comparison_figure(fits: xr.Dataset, structures: list, path):
    """Columns: limit states. Each structure's lognormal curve of PGA over all its records,
    with its 90 % bootstrap band: variants of one structure (linked, tilted) side by side
    (config ``fragility.compare``)."""
    states = [str(s) for s in fits.limit_state.values]
    fig, axes = plt.subplots(
        1, len(states), figsize=(3.1 * len(states), 3.2), squeeze=False, layout="constrained"
    )
    grid = fits["pga_grid"].values
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for j, state in enumerate(states):
        ax = axes[0, j]
        for k, structure in enumerate(structures):
            sel = fits.sel(structure=structure, record_set="all", limit_state=state)
            p = sel["probability_pga"].values
            if not np.isfinite(p).any():
                continue
            colour = colours[k % len(colours)]
            ax.plot(
                grid,
                p,
                color=colour,
                lw=1.5,
                label=f"{structure}: {float(sel['median_pga']):.3g} m s-2, "
                f"beta {float(sel['beta_pga']):.2f}",
            )
            band = sel["probability_pga_band"].values
            ax.fill_between(grid, band[0], band[1], color=colour, alpha=0.15, lw=0)
        ax.set_xscale("log")
        ax.set_xlim(grid[0], grid[-1])
        ax.set_ylim(0, 1)
        ax.grid(alpha=0.3)
        ax.set_title(LIMIT_STATES[state].label if state in LIMIT_STATES else state, fontsize=8)
        ax.set_xlabel("PGA [m s-2]", fontsize=8)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=5.5, loc="upper left")
        else:  # a lognormal needs two records with the state exceeded
            ax.text(0.5, 0.5, "no fit", ha="center", transform=ax.transAxes)
    axes[0, 0].set_ylabel("P(exceeded)")
    _finish(fig, f"Fragility of {', '.join(structures)}: all records, 90 % bootstrap bands")
    return _save(fig, path)
