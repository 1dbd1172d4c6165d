"""Damage maps (manuscript Figs. 13, 15-18, 20-21) and pushover curves (Fig. 22)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# manuscript Fig. 20 colours: green elastic, red shear, magenta flexural
STATE_COLOURS = {0: "tab:green", 1: "red", 2: "magenta", 3: "darkviolet", 4: "black"}


def damage_map(ax, ds, scale=None):
    """Wall elevation: block outlines shaded by out-of-plane displacement, joints coloured by
    state."""
    from matplotlib.patches import Rectangle

    q = ds.displacement_at_limit.values
    u3 = q[:, 2]
    umax = np.abs(u3).max() or 1.0
    a_cell = float(ds.attrs["panel_height"]) / (int(ds.block_course.max()) + 1)
    for x, y, length, u in zip(ds.block_x.values, ds.block_y.values, ds.block_length.values, u3):
        ax.add_patch(
            Rectangle(
                (x - length / 2, y - a_cell / 2),
                length,
                a_cell,
                facecolor=plt.cm.Blues(0.15 + 0.7 * abs(u) / umax),
                edgecolor="0.6",
                linewidth=0.3,
            )
        )
    state = ds.damage_at_limit.values
    for x, y, w, ax_n, st in zip(
        ds.interface_x.values,
        ds.interface_y.values,
        ds.interface_width.values,
        ds.interface_normal_axis.values,
        state,
    ):
        xs, ys = ((x, x), (y - w / 2, y + w / 2)) if ax_n == 0 else ((x - w / 2, x + w / 2), (y, y))
        ax.plot(xs, ys, color=STATE_COLOURS[int(st)], linewidth=1.2 if st else 0.5)
    ax.set_aspect("equal")
    ax.set_xlim(-0.02, float(ds.attrs["panel_length"]) + 0.02)
    ax.set_ylim(-0.02, float(ds.attrs["panel_height"]) + 0.02)
    ax.set_title(limit_label(ds), fontsize=7)
    ax.set_xticks([]), ax.set_yticks([])


def limit_label(ds):
    """'<case>: ours <value> vs manuscript DEM <value> (<error>)', in kPa for a pressure."""
    import json

    pressure = ds.attrs["load_kind"] == "pressure"
    scale, unit = (1e-3, " kPa") if pressure else (1.0, "")
    ours = float(ds.lambda_max) * scale
    ref = json.loads(ds.attrs["case"]).get("reference", {})
    dem = ref.get("p_dem", ref.get("lambda_dem"))
    text = f"{ds.attrs['case_name']}: ours {ours:.4g}{unit}"
    if dem:
        dem *= scale
        text += f" vs manuscript DEM {dem:.4g}{unit} ({(ours - dem) / dem:+.0%})"
    return text


def damage_figure(datasets, path, ncols=3):
    n = len(datasets)
    ncols = min(ncols, n)
    nrows = int(np.ceil(n / ncols))
    fig, axes = plt.subplots(
        nrows, ncols, figsize=(max(3.4 * ncols, 6.0), 3.4 * nrows), squeeze=False
    )
    for ax, ds in zip(axes.ravel(), datasets):
        damage_map(ax, ds)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    handles = [
        plt.Line2D([], [], color=c, label=lab)
        for c, lab in zip(
            STATE_COLOURS.values(), ["elastic", "shear", "flexural", "shear+flexural", "detached"]
        )
    ]
    fig.legend(handles=handles, loc="lower center", ncol=5, fontsize=7)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def pushover_figure(datasets, path):
    fig, ax = plt.subplots(figsize=(6, 4))
    for ds in datasets:
        pressure = ds.attrs["load_kind"] == "pressure"
        lam = ds["lambda"].values * (1e-3 if pressure else 1.0)
        ax.plot(ds.control_displacement.values * 1e3, lam, label=limit_label(ds))
        ax.set_ylabel("pressure p [kPa]" if pressure else "load multiplier lambda")
    ax.set_xlabel("out-of-plane displacement of the control block [mm]")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def plot_from_files(paths, path, kind="damage"):
    from stonedem.io.netcdf import open_result

    datasets = [open_result(p) for p in paths]
    return (damage_figure if kind == "damage" else pushover_figure)(datasets, path)
