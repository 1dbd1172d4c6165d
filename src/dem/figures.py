"""Figures of the study, named after the thesis figure they regenerate.

Each function takes the paths of its inputs (cubes or tables) and writes one PNG. Axis
labels come from the datasets' ``long_name`` and ``units`` where there is a dataset; where
the thesis gives numbers, they are drawn on the same axes.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402

from dem.reduce import frequency_response, ramp_thresholds  # noqa: E402

G = 9.81


def _save(fig, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _ramp_figure(cube_path, along, xlabel, title, path):
    with xr.open_dataset(cube_path) as cube:
        rows = ramp_thresholds(cube.load(), along)
    x = [r[along] for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    ax.plot(x, [r["rocking_onset_pga_m_s2"] for r in rows], "o-", label="rocking onset (engine)")
    ax.plot(x, [r["overturning_pga_m_s2"] for r in rows], "s-", label="overturning (engine)")
    ax.plot(x, [r["static_rocking_pga_m_s2"] for r in rows], "k:", label="static g b/h (thesis Eq. 6.1)")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("base acceleration [m s-2]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    return _save(fig, path)


def thesis_fig_6_10(cube_path, path):
    """PGA to initiate rocking and to overturn vs the number of drums (ramp 0.5 m/s2 per s)."""
    return _ramp_figure(cube_path, "n_drums", "number of drums [1]",
                        "Thesis Fig. 6.10: acceleration to start rocking and to overturn, 6 m x 1 m column", path)


def thesis_fig_6_13(cube_path, path):
    """PGA to initiate rocking and to overturn vs the taper W_b/W_t at constant mass."""
    return _ramp_figure(cube_path, "taper", "base / top width W_b/W_t [1]",
                        "Thesis Fig. 6.13: tapered 4-drum columns at constant mass", path)


def thesis_fig_6_5(cube_path, path):
    """Total sliding over base amplitude and rocking vs frequency (harmonic, 8 drums)."""
    with xr.open_dataset(cube_path) as cube:
        rows = frequency_response(cube.load())
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for amp in sorted({r["amplitude_m"] for r in rows}):
        sel = [r for r in rows if r["amplitude_m"] == amp]
        f = [r["frequency_hz"] for r in sel]
        ax1.plot(f, [r["sliding_to_base_ratio"] for r in sel], "o-", label=f"A = {amp:g} m")
        ax2.plot(f, [r["max_rocking_rad"] for r in sel], "o-", label=f"A = {amp:g} m")
    for ax in (ax1, ax2):
        ax.set_xscale("log")
        ax.set_xlabel("harmonic frequency [Hz]")
        ax.legend(fontsize=8)
    ax1.axhline(1.0, color="k", ls=":", label="thesis: ratio -> 1 at high frequency")
    ax1.set_ylabel("total sliding / base amplitude [1]")
    ax2.set_ylabel("maximum mean drum rotation [rad]")
    fig.suptitle("Thesis Fig. 6.5: sliding vs rocking with frequency. Unlike the thesis, our column "
                 "collapses at every frequency >= 0.5 Hz at these amplitudes", fontsize=9)
    return _save(fig, path)


def table_7_1_figure(table_path, path):
    """Smallest collapsing PGA of the grid vs the thesis' Table 7.1, per system and record."""
    with open(table_path) as handle:
        rows = list(csv.DictReader(handle))
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    markers = {"colonnade": "s", "single column": "o"}
    colours = {"colonnade": "tab:blue", "single column": "tab:orange"}
    for row in rows:
        ours = float(row["collapse_pga_m_s2"])
        thesis = float(row["thesis_accel_to_failure_m_s2"])
        if math.isnan(thesis):
            continue
        ax.scatter(thesis, ours if not math.isnan(ours) else 40.0, marker=markers[row["system"]],
                   color=colours[row["system"]],
                   label=f"{row['system']}" if row["n_drums"] == "1" and row["thesis_record"] == "mexico" else None)
        ax.annotate(f"{row['thesis_record'][:3]} {row['n_drums']}d", (thesis, ours), fontsize=6)
    lims = [0.8, 40]
    ax.plot(lims, lims, "k:", lw=0.8, label="equal")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("thesis: acceleration to failure [m s-2] (Table 7.1)")
    ax.set_ylabel("engine: smallest collapsing PGA of the grid, stand-in record [m s-2]")
    ax.set_title("Thesis Table 7.1 with stand-in records: ordering Mexico < Kalamata < Athens holds", fontsize=9)
    ax.legend(fontsize=8)
    return _save(fig, path)


FIGURES = {
    "thesis_fig_6_5": (thesis_fig_6_5, "results/cubes/harmonic_frequency.nc"),
    "thesis_fig_6_10": (thesis_fig_6_10, "results/cubes/ramp_drums.nc"),
    "thesis_fig_6_13": (thesis_fig_6_13, "results/cubes/ramp_taper.nc"),
    "table_7_1": (table_7_1_figure, "results/tables/table_7_1.csv"),
}
