"""Figures of the thesis 5.1 validations: the engine's result over the reference.

Two sets, both drawn from the validation datasets only: one check figure per validation
(:func:`plot`, ``<name>.png``), and the thesis chapter-5 figures that are plots, named by
thesis figure number (:data:`THESIS_FIGURES`, ``thesis_fig_5_2.png`` ...), each with a title
naming the thesis figure and the validation's verdict under it. Labels come from the
datasets' ``long_name`` and ``units`` attributes (the xarray rule) where they fit.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

from stonedem.io.atomic import write_atomically  # noqa: E402
from stonedem.io.netcdf import open_result  # noqa: E402
from stonedem.validation import links, sequence, tilt  # noqa: E402


def label(da):
    return f"{da.attrs.get('long_name', da.name)} [{da.attrs.get('units', '')}]"


def plot(result, path: Path) -> Path:
    ds = result.dataset
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    draw = DRAWERS[result.name]
    draw(ds, ax)
    verdict = "passed" if result.passed else "FAILED"
    ax.set_title(
        f"{result.name}: {verdict} (tolerance {100 * ds.attrs['tolerance']:g} %)", fontsize=10
    )
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _housner(ds, ax):
    for i, geo in enumerate(ds.geometry.values):
        (line,) = ax.plot(ds.ratio, ds.period_exact[i], "-", label=f"{geo} exact")
        ax.plot(ds.ratio, ds.period_eq_5_1[i], ":", color=line.get_color(), label=f"{geo} Eq. 5.1")
        ax.plot(ds.ratio, ds.period_engine[i], "o", color=line.get_color(), label=f"{geo} engine")
    ax.set_xlabel(label(ds.ratio))
    ax.set_ylabel("rocking period T [s]")
    ax.legend(fontsize=7, ncol=3)


def _impact(ds, ax):
    ax.plot(
        ds.impact, ds.peak_eq_5_3, "-", label="Housner Eq. 5.3, r = %.2f" % ds.attrs["target_r"]
    )
    ax.plot(
        ds.impact,
        ds.peak_engine,
        "o",
        label="engine, c_n = %.3g N s/m" % ds.attrs["calibrated_c_n"],
    )
    ax.set_xlabel(label(ds.impact))
    ax.set_ylabel(label(ds.peak_engine))
    ax.legend()


def _newmark(ds, ax):
    for ap in sorted(set(ds.a_p_g.values)):
        sel = ds.a_p_g == ap
        (line,) = ax.plot(ds.mu[sel], ds.u_max_eq_5_5[sel], "-", label=f"Eq. 5.5, a_p = {ap:g} g")
        ax.plot(
            ds.mu[sel],
            ds.u_max_engine[sel],
            "o",
            color=line.get_color(),
            label=f"engine, a_p = {ap:g} g",
        )
    ax.set_yscale("log")
    ax.set_xlabel(label(ds.mu))
    ax.set_ylabel(label(ds.u_max_engine))
    ax.legend()


def _sliding(ds, ax):
    ax.plot(ds.time, ds.sliding_exact, "-", lw=2, label="exact rigid-plastic")
    ax.plot(ds.time, ds.sliding_bouc_wen, "--", label="Bouc-Wen Eq. 5.6-5.7")
    ax.plot(ds.time, ds.sliding_engine, ":", lw=2, label="engine")
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(label(ds.sliding_engine))
    ax.legend()


def _rocking(ds, ax):
    scale = ds.attrs["case_scale"]
    ax.plot(
        ds.time,
        ds.theta_rigid,
        "-",
        label="rigid rocking equation, r = %.3f, scale %g" % (ds.attrs["restitution_r"], scale),
    )
    ax.plot(ds.time, ds.theta_engine, ":", lw=2, label="engine, scale %g" % scale)
    inset = ax.inset_axes([0.68, 0.08, 0.3, 0.3])
    inset.plot(ds.scale, 100 * ds.peak_relative_error, "o-")
    inset.axhspan(-100 * ds.attrs["tolerance"], 100 * ds.attrs["tolerance"], color="0.9")
    inset.set_xlabel("scale", fontsize=7)
    inset.set_ylabel("peak error [%]", fontsize=7)
    inset.tick_params(labelsize=6)
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(label(ds.theta_engine))
    ax.legend()


def _two_blocks(ds, ax):
    for i, th0 in enumerate(ds.theta0.values):
        (line,) = ax.plot(ds.time, ds.theta_lower[i], "-", label=f"lower block, {th0:g} rad")
        ax.plot(
            ds.time,
            ds.theta_upper[i],
            "--",
            color=line.get_color(),
            label=f"upper block, {th0:g} rad",
        )
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel("rotation (positive: leaning right) [rad]")
    ax.legend(fontsize=8)


def _energy(ds, ax):
    ax.plot(ds.time, 100 * ds.relative_drift, "-")
    ax.axhline(100 * ds.attrs["tolerance"], color="k", ls=":")
    ax.axhline(-100 * ds.attrs["tolerance"], color="k", ls=":")
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel("energy change / rocking energy [%]")


MODE_COLOURS = ("#f2f2f2", "#f4a259", "#bc4b51")  # safe, overturned after an impact, without one


def _mode_map(ax, ds, name, title):
    """One overturning map (mode codes of stonedem.reference.analytic.ONE_SINE_MODES) as coloured
    cells."""
    from matplotlib.colors import BoundaryNorm, ListedColormap

    codes = ds[name]
    ax.pcolormesh(
        ds.map_omega_ratio,
        ds.amplitude,
        codes.T,
        shading="nearest",
        cmap=ListedColormap(MODE_COLOURS),
        norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], 3),
    )
    _log_amplitude_axis(ax)
    ax.set_xlabel(label(ds.map_omega_ratio))
    ax.set_title(title, fontsize=8)


def _log_amplitude_axis(ax):
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullLocator

    ax.set_yscale("log")
    ax.yaxis.set_major_locator(FixedLocator([1, 1.5, 2, 3, 5, 8, 12, 20, 30]))
    ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
    ax.yaxis.set_minor_locator(NullLocator())


def _one_sine(ds, ax):
    """Thresholds (engine markers over the exact line, both blocks) and the maps, exact and
    engine."""
    from matplotlib.patches import Patch

    fig = ax.figure
    fig.set_size_inches(13, 4.6)
    grid = fig.add_gridspec(1, 3, width_ratios=[1.2, 1, 1])
    ax.set_subplotspec(grid[0])  # ax (whose title plot() sets) takes the curves, the maps beside it
    curves = ax
    for i, block in enumerate(ds.block.values):
        r = float(ds.restitution[i])
        (line,) = curves.plot(
            ds.omega_ratio, ds.threshold_exact[i], "-", label=f"{block}: exact rigid, r = {r:.4f}"
        )
        curves.plot(
            ds.omega_ratio,
            ds.threshold_engine[i],
            "o",
            color=line.get_color(),
            label=f"{block}: engine (worst "
            f"{100 * float(np.abs(ds.relative_error[i]).max()):.2g} %)",
        )
    _log_amplitude_axis(curves)
    curves.set_xlabel(label(ds.omega_ratio))
    curves.set_ylabel("smallest overturning a_p / (g tan alpha) [1]")
    curves.legend(fontsize=7)
    if "map_engine" not in ds:
        return
    exact_ax = fig.add_subplot(grid[1])
    engine_ax = fig.add_subplot(grid[2], sharex=exact_ax, sharey=exact_ax)
    _mode_map(exact_ax, ds, "map_exact", f"exact rigid block, {ds.attrs['map_block']}")
    _mode_map(
        engine_ax,
        ds,
        "map_engine",
        f"engine, {ds.attrs['map_block']}: "
        f"{100 * ds.attrs['map_agreement']:.0f} % of cells agree (x: differ)",
    )
    differ = (ds.map_engine != ds.map_exact).values
    rr, aa = np.meshgrid(ds.map_omega_ratio.values, ds.amplitude.values, indexing="ij")
    engine_ax.plot(rr[differ], aa[differ], "x", color="k", ms=5)
    i = (
        list(ds.block.values).index(ds.attrs["map_block"])
        if ds.attrs["map_block"] in ds.block.values
        else None
    )
    if i is not None:
        for a in (exact_ax, engine_ax):
            a.plot(ds.omega_ratio, ds.threshold_exact[i], "-", color="k", lw=0.8)
            a.plot(ds.omega_ratio, ds.threshold_engine[i], "o", color="k", mfc="none", ms=4)
    exact_ax.set_ylabel(f"pulse amplitude a_p / (g tan alpha) [{ds.amplitude.attrs['units']}]")
    names = ("safe", "overturns after an impact", "overturns without impact")
    engine_ax.legend(
        handles=[Patch(color=c, label=n) for c, n in zip(MODE_COLOURS, names)],
        fontsize=7,
        loc="lower right",
    )


DRAWERS = {
    "housner_period": _housner,
    "impact_restitution": _impact,
    "newmark_pulse": _newmark,
    "record_sliding": _sliding,
    "record_rocking": _rocking,
    "two_blocks": _two_blocks,
    "energy_conservation": _energy,
    "one_sine_overturning": _one_sine,
}


# --- thesis chapter-5 figures ---------------------------------------------------------------


def _pena(ds, ax):
    """Thesis Fig. 5.20: engine at the checked k_n, rigid rocking equation, engine at the thesis
    k_n."""
    ax.plot(
        ds.time,
        ds.theta_rigid,
        "-",
        lw=2,
        color="0.6",
        label="rigid rocking equation, r = %.3f (engine's first impact)"
        % ds.attrs["restitution_r"],
    )
    ax.plot(
        ds.time,
        ds.theta_engine,
        "-",
        lw=0.9,
        color="C0",
        label="engine, k_n = %.0e N/m2, c_n = %.0e N s/m" % (ds.attrs["k_n"], ds.attrs["c_n"]),
    )
    ax.plot(
        ds.time,
        ds.theta_engine_k_n_thesis,
        ":",
        color="C3",
        label="engine, thesis k_n = %.0e N/m2 (not checked)" % ds.attrs["k_n_thesis"],
    )
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(label(ds.theta_engine))
    ax.legend(fontsize=7)


# the point-law variants of the 5.1 validations (stonedem.validation.cases.VALIDATIONS) draw alike
DRAWERS.update({f"{name}_point": draw for name, draw in list(DRAWERS.items())})
DRAWERS["pena_block"] = _pena
DRAWERS.update(sequence.DRAWERS)
DRAWERS.update(tilt.DRAWERS)
DRAWERS.update(links.DRAWERS)  # beyond the thesis: shear links (issue 48)


def _fig_5_2(ds, fig):
    ax = fig.add_subplot()
    x = np.linspace(0.005, 0.95, 300)
    # thesis Eq. 5.1 normalised: T/4 sqrt(W R / I_O) = acosh(1 / (1 - theta0/alpha)), any geometry
    ax.plot(x, np.arccosh(1.0 / (1.0 - x)), "-", lw=2, color="C0", label="Housner Eq. 5.1")
    for i, geo in enumerate(ds.geometry.values):
        scale = float(ds.p[i]) / 4.0
        (line,) = ax.plot(
            ds.ratio, ds.period_exact[i] * scale, "--", lw=0.8, label=f"{geo}: exact rigid block"
        )
        ax.plot(
            ds.ratio,
            ds.period_engine[i] * scale,
            "o",
            color=line.get_color(),
            label=f"{geo}: engine",
        )
    ax.set_xlabel(label(ds.ratio))
    ax.set_ylabel("T/4 x sqrt(W R / I_O) [1]")
    ax.legend(fontsize=7)


def _fig_5_4(ds, fig):
    ax = fig.add_subplot()
    ax.plot(
        ds.time,
        ds.theta_rigid,
        "-",
        lw=2,
        color="0.6",
        label="rigid rocking equation, r = %.2f (thesis Fig. 5.3)" % ds.attrs["target_r"],
    )
    ax.plot(
        ds.time,
        ds.theta_history,
        "-",
        lw=0.9,
        color="C0",
        label="engine, c_n = %.3g N s/m (calibrated to r)" % ds.attrs["calibrated_c_n"],
    )
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(label(ds.theta_history))
    ax.legend(fontsize=8)


def _fig_5_5(ds, fig):
    _impact(ds, fig.add_subplot())


def _fig_5_7(ds, fig):
    ax = fig.add_subplot()
    x = np.linspace(0.05, 0.999, 300)
    # thesis Eq. 5.5 divided by a_p T_p^2: Pi_1 = (a_p / (mu g) - 1) / 2, one curve in mu g / a_p
    ax.plot(x, 0.5 * (1.0 / x - 1.0), "-", lw=2, color="C0", label="Newmark Eq. 5.5")
    for k, ap in enumerate(sorted(set(ds.a_p_g.values))):
        sel = ds.a_p_g == ap
        t_p = float(ds.t_p[sel][0])
        ax.plot(
            ds.mu[sel] / ap,
            ds.pi_1[sel],
            "os"[k % 2],
            color=f"C{k + 1}",
            label=f"engine, a_p = {ap:g} g, T_p = {t_p:g} s",
        )
    ax.set_yscale("log")
    ax.set_xlabel("mu g / a_p [1]")
    ax.set_ylabel("Pi_1 = u_max / (a_p T_p^2) [1]")
    ax.legend(fontsize=8)


def _fig_5_8(ds, fig):
    ax = fig.add_subplot()
    pulses = sorted(set(zip(ds.a_p_g.values, ds.t_p.values)))
    ap, tp = (0.8, 1.5) if (0.8, 1.5) in pulses else pulses[0]  # the thesis figure's pulse
    for k, case in enumerate(ds.case.values[(ds.a_p_g.values == ap) & (ds.t_p.values == tp)]):
        c = ds.sel(case=case)
        ax.plot(ds.time, c.sliding_exact, "-", lw=2, color=f"C{k}", alpha=0.35)
        ax.plot(ds.time, c.sliding_engine, "--", lw=1, color=f"C{k}", label=f"mu = {float(c.mu):g}")
    ax.plot([], [], "-", lw=2, color="0.5", alpha=0.5, label="exact rigid-plastic")
    ax.plot([], [], "--", color="0.3", label="engine")
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(f"relative displacement u, a_p = {ap:g} g, T_p = {tp:g} s [m]")
    ax.legend(fontsize=7, ncol=2)


def _record_panel(ds, ax):
    ax.plot(ds.time, ds.base_acceleration, "-", lw=0.6, color="0.3")
    ax.set_ylabel(f"base acceleration [{ds.base_acceleration.attrs['units']}]", fontsize=8)
    ax.set_title(f"{ds.attrs.get('record', '')} ({ds.attrs.get('record_title', '')})", fontsize=8)


def _fig_5_10(ds, fig):
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 2]})
    _record_panel(ds, top)
    _sliding(ds, bottom)
    bottom.set_ylabel("relative displacement u = x_block - x_base [m]", fontsize=8)


def _fig_5_13(ds, fig):
    top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [1, 2]})
    _record_panel(ds, top)
    bottom.plot(
        ds.time,
        ds.theta_rigid,
        "-",
        lw=2,
        color="0.6",
        label="rigid rocking equation, r = %.3f" % ds.attrs["restitution_r"],
    )
    bottom.plot(
        ds.time,
        ds.theta_engine,
        "-",
        lw=0.9,
        color="C0",
        label="engine, c_n = %.3g N s/m" % ds.attrs["calibrated_c_n"],
    )
    bottom.set_xlabel(label(ds.time))
    bottom.set_ylabel("column rotation (+: leaning right) [rad]", fontsize=8)
    bottom.legend(fontsize=8)


def _two_blocks_figure(theta0):
    """Thesis Fig. 5.15 / 5.17: both blocks' rotations from theta0, and the energy balance
    checked."""

    def draw(ds, fig):
        c = ds.sel(theta0=theta0, method="nearest")
        top, bottom = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2, 1]})
        top.plot(ds.time, c.theta_lower, "-", label=f"block 1 (lower, {ds.attrs['lower_block']})")
        top.plot(ds.time, c.theta_upper, "--", label=f"block 2 (upper, {ds.attrs['upper_block']})")
        top.set_ylabel("rotation (+: leaning right) [rad]", fontsize=8)
        top.set_title(
            f"engine, released from {float(c.theta0):g} rad; no analytic two-block solution "
            "here: the reference is the energy balance",
            fontsize=8,
        )
        top.legend(fontsize=8)
        tol = 100 * ds.attrs["tolerance"]
        bottom.axhspan(-tol, tol, color="0.9", label=f"tolerance {tol:g} %")
        bottom.plot(ds.time, 100 * c.energy_balance_error, "-", color="C2", label="engine")
        bottom.set_xlabel(label(ds.time))
        bottom.set_ylabel("energy error / initial [%]", fontsize=8)
        bottom.legend(fontsize=7)

    return draw


def _fig_5_20(ds, fig):
    _pena(ds, fig.add_subplot())


def _fig_5_21(ds, fig):
    ax = fig.add_subplot()
    for c_n, r in zip(ds.c_n.values, ds.restitution_first_impact.values):
        ax.plot(
            ds.time,
            ds.theta_sweep.sel(c_n=c_n),
            lw=0.9,
            label=f"c_n = {c_n:.0e} N s/m, r(1st impact) = {r:.3f}",
        )
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel(label(ds.theta_sweep))
    ax.set_title(
        f"engine, k_n = {ds.attrs['k_n']:.0e} N/m2; Housner's no-bounce r = "
        f"{ds.attrs['housner_restitution']:.3f}",
        fontsize=8,
    )
    ax.legend(fontsize=7)


# name: (validation whose dataset it draws, drawer(ds, fig))
THESIS_FIGURES = {
    "thesis_fig_5_2": ("housner_period", _fig_5_2),
    "thesis_fig_5_4": ("impact_restitution", _fig_5_4),
    "thesis_fig_5_5": ("impact_restitution", _fig_5_5),
    "thesis_fig_5_7": ("newmark_pulse", _fig_5_7),
    "thesis_fig_5_8": ("newmark_pulse", _fig_5_8),
    "thesis_fig_5_10": ("record_sliding", _fig_5_10),
    "thesis_fig_5_13": ("record_rocking", _fig_5_13),
    "thesis_fig_5_15": ("two_blocks", _two_blocks_figure(0.10)),
    "thesis_fig_5_17": ("two_blocks", _two_blocks_figure(0.15)),
    "thesis_fig_5_20": ("pena_block", _fig_5_20),
    "thesis_fig_5_21": ("pena_block", _fig_5_21),
}

# the thesis's captions (list of figures), with what stands in for the thesis's data
CAPTIONS = {
    "thesis_fig_5_2": "Period T of a block rocking with amplitude theta0",
    "thesis_fig_5_4": "Computed time-history response of a rigid block left to freely vibrate "
    "from an initial angle, with energy loss during impacts",
    "thesis_fig_5_5": "Reduction of the maximum rotation angle of each cycle due to impact",
    "thesis_fig_5_7": "Normalized maximum relative displacements of a rigid body on a surface "
    "with friction mu, under rectangular acceleration pulses",
    "thesis_fig_5_8": "Time-history relative displacements of a sliding block under "
    "rectangular pulse accelerations",
    "thesis_fig_5_10": "Sliding response of a rigid body under an earthquake excitation "
    "(Northridge 1994 MUL009 stand-in)",
    "thesis_fig_5_13": "Rocking response of a rigid body under earthquake excitations "
    "(Northridge stand-in "
    "for Bucharest 1977)",
    "thesis_fig_5_15": "Rotation of the two bodies released from 0.1 rad",
    "thesis_fig_5_17": "Rotation of Block 1 from an initial rotation angle of 0.15 rad",
    "thesis_fig_5_20": "Rotation of the rigid body (Pena granite block) obtained numerically",
    "thesis_fig_5_21": "The effect of the contact damping coefficient on the free vibration of "
    "a rigid body",
}


def thesis_number(name: str) -> str:
    """'thesis_fig_5_20' -> '5.20'."""
    return name.removeprefix("thesis_fig_").replace("_", ".")


def _verdict(ds) -> str:
    if "passed" not in ds.attrs:
        return ""
    verdict = "passed" if int(ds.attrs["passed"]) else "FAILED"
    return (
        f"validation {ds.attrs.get('validation', '')}: error {float(ds.attrs['error']):.3g}, "
        f"tolerance {float(ds.attrs['tolerance']):g}: {verdict}"
    )


def _save(fig, path) -> Path:
    """Write a PNG atomically (stonedem.io.atomic) and close the figure."""
    try:
        return write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=120))
    finally:
        plt.close(fig)


def draw_thesis_figure(name: str, dataset, path) -> Path:
    """Draw thesis figure ``name`` from its validation dataset (an xr.Dataset or a NetCDF path)."""
    validation, drawer = THESIS_FIGURES[name]
    if not isinstance(dataset, xr.Dataset):
        dataset = open_result(dataset)
    found = dataset.attrs.get("validation", validation)
    if found != validation:
        raise ValueError(f"{name} draws the {validation} dataset, got {found}")
    fig = plt.figure(figsize=(8, 5), constrained_layout=True)
    drawer(dataset, fig)
    title = f"Thesis Fig. {thesis_number(name)}: {CAPTIONS[name]}"
    verdict = _verdict(dataset)
    fig.suptitle(title + (f"\n{verdict}" if verdict else ""), fontsize=9, wrap=True)
    return _save(fig, path)


def figures_of(validation: str) -> list[str]:
    """The thesis figures drawn from one validation's dataset."""
    return [name for name, (v, _) in THESIS_FIGURES.items() if v == validation]


def write_thesis_figures(validation: str, dataset, out_dir) -> list[Path]:
    """Every thesis figure of ``validation`` into ``out_dir``/<figure>.png."""
    return [
        draw_thesis_figure(name, dataset, Path(out_dir) / f"{name}.png")
        for name in figures_of(validation)
    ]
