"""Drawing shared by the chapters: helpers (save, title and verdict, labels, selection) and the
generic kinds of figure (histories of one study, snapshots of one case, initial geometries).

Where an ordering the thesis reports is checked on the data, the verdict is printed under
the plot, so a figure never claims more than the cube shows.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.catalogue import Case, Cube, Figure
from stonedem.io.atomic import write_atomically
from stonedem.io.netcdf import open_result
from stonedem.study.cube import member_summary

# files only, no display: every chapter imports this module, so whichever of them comes first
# sets the backend before it draws (switching is allowed until a figure exists)
matplotlib.use("Agg")

THESIS_RECORD = {
    "athens": "athens_standin_kocaeli_arc000",
    "kalamata": "kalamata_standin_izmit_izt270",
    "mexico": "mexico_standin_chichi_tcu102",
}
RECORD_LABEL = {v: f"{k.capitalize()} stand-in" for k, v in THESIS_RECORD.items()}


# --- drawing helpers ----------------------------------------------------------------------


def load_cube(path) -> xr.Dataset:
    """A study's cube, loaded; an ensemble's as :func:`stonedem.study.cube.member_summary`
    gives it (``collapsed`` the collapse fraction)."""
    with open_result(path) as cube:
        return member_summary(cube.load())


def collapsed_label(cube: xr.Dataset) -> str:
    """What a red x marks: a collapse, or in an ensemble a collapse of at least half the members."""
    members = int(cube.attrs.get("members", 1))
    return "collapsed" if members == 1 else f"collapsed in >= half of {members} members"


def _save(fig, path) -> Path:
    """Write a PNG atomically (stonedem.io.atomic) and close the figure."""
    try:
        return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=110))
    finally:
        plt.close(fig)


def _label(da) -> str:
    return f"{da.attrs.get('long_name', da.name)} [{da.attrs.get('units', '')}]"


def _value_label(name: str, value) -> str:
    if name == "record":
        return RECORD_LABEL.get(str(value), str(value))
    units = {
        "n_drums": " drums",
        "n_columns": " columns",
        "clear_distance": " m",
        "epistyle_density": " kg/m3",
        "taper": "",
        "frequency": " Hz",
        "amplitude": " m",
        "friction": "",
        "pga": " m/s2",
        "weak_joint": "",
        "epistyle_type": "",
    }
    prefix = {
        "taper": "Wb/Wt = ",
        "friction": "mu = ",
        "weak_joint": "weak joint ",
        "epistyle_type": "type ",
    }
    v = f"{value:g}" if isinstance(value, (float, np.floating)) else str(value)
    return f"{prefix.get(name, '')}{v}{units.get(name, '')}"


def _finish(fig, title: str, verdict: str = "") -> None:
    """Title, and the ordering verdict in a strip kept free under the axes."""
    fig.suptitle(title, fontsize=9)
    if verdict:
        lines = sum(1 + len(line) // 170 for line in verdict.splitlines())
        strip = (0.16 * lines + 0.05) / fig.get_figheight()
        fig.get_layout_engine().set(rect=(0, strip, 1, 1 - strip))
        fig.text(
            0.01,
            0.005,
            verdict,
            fontsize=7.5,
            ha="left",
            va="bottom",
            wrap=True,
            color="darkred" if "does NOT hold" in verdict else "darkgreen",
        )


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
        cube = _sel(load_cube(inputs[0]), select, keep=(hue,))
        fig, (ax1, ax2) = plt.subplots(
            1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [2.2, 1]}, constrained_layout=True
        )
        values = cube[hue].values
        peaks = []
        for v in values:
            case = cube.sel({hue: v})
            ax1.plot(case["time"], case[variable], lw=0.8, label=_value_label(hue, v))
            peak = (
                float(case[scalar]) if scalar in case else float(np.nanmax(np.abs(case[variable])))
            )
            peaks.append(peak)
            if float(case["collapsed"]) >= 0.5:  # an ensemble's collapse fraction (K = 1: 0 or 1)
                ax1.axvline(
                    float(case["collapse_time"]), color=ax1.lines[-1].get_color(), ls=":", lw=0.8
                )
        ax1.set_xlabel(_label(cube["time"]))
        ax1.set_ylabel(_label(cube[variable]), fontsize=8)
        ax1.legend(fontsize=7, ncol=2)
        xs = np.arange(len(values)) if values.dtype.kind in "OUS" else values
        ax2.plot(xs, peaks, "o-")
        fractions = [float(cube.sel({hue: v})["collapsed"]) for v in values]
        collapsed = [f >= 0.5 for f in fractions]
        ax2.plot(
            np.asarray(xs)[collapsed],
            np.asarray(peaks)[collapsed],
            "rx",
            ms=10,
            label=collapsed_label(cube),
        )
        if int(cube.attrs.get("members", 1)) > 1:  # the fraction itself beside each point
            for x, peak, f in zip(xs, peaks, fractions):
                ax2.annotate(
                    f"{f:.2g}", (x, peak), fontsize=6, textcoords="offset points", xytext=(3, 3)
                )
        if values.dtype.kind in "OUS":
            ax2.set_xticks(xs, [str(v) for v in values])
        ax2.set_xlabel(_label(cube[hue]))
        ax2.set_ylabel(f"maximum of the left panel [{cube[variable].attrs.get('units', '')}]")
        if any(collapsed):
            ax2.legend(fontsize=7)
        _finish(fig, title, check(cube) if check else "")
        return _save(fig, path)

    return Figure(thesis, caption, (Cube(study, {hue: None, **select}),), draw)


def snapshot_figure(thesis, study, params, title, caption, n=6):
    """A strip of snapshots of one case (thesis snapshot sequences)."""

    def draw(inputs, path):
        from stonedem.figures.snapshots import snapshot_strip

        with open_result(inputs[0]) as ds:
            return snapshot_strip(ds.load(), path, n=n, title=title)

    return Figure(thesis, caption, (Case(study, params),), draw)


def geometry_figure(thesis, study, cases, title, caption):
    """The initial geometry of several cases side by side (thesis Fig. 6.11, 7.23, 7.31)."""

    def draw(inputs, path):
        from matplotlib.collections import PolyCollection

        from stonedem.figures.snapshots import body_polygons, posed_polygons

        fig, axes = plt.subplots(
            1, len(inputs), figsize=(3.2 * len(inputs), 3.6), constrained_layout=True
        )
        for ax, file, params in zip(np.atleast_1d(axes), inputs, cases):
            with open_result(file) as ds:
                local = body_polygons(ds)
                polys = posed_polygons(local, ds.x[0].values, ds.y[0].values, ds.theta[0].values)
                roles = [str(r) for r in ds["body_role"].values]
            colours = [
                "0.6" if r == "base" else "tan" if r == "epistyle" else "wheat" for r in roles
            ]
            ax.add_collection(
                PolyCollection(polys, facecolors=colours, edgecolors="k", linewidths=0.5)
            )
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

    return Figure(thesis, caption, tuple(Case(study, p) for p in cases), draw)
