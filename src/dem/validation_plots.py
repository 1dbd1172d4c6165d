"""Figures of the thesis 5.1 validations: the engine's result over the reference.

Labels come from the datasets' ``long_name`` and ``units`` attributes (the xarray rule).
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def label(da):
    return f"{da.attrs.get('long_name', da.name)} [{da.attrs.get('units', '')}]"


def plot(result, path: Path) -> Path:
    ds = result.dataset
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    draw = DRAWERS[result.name]
    draw(ds, ax)
    verdict = "passed" if result.passed else "FAILED"
    ax.set_title(f"{result.name}: {verdict} (tolerance {100 * ds.attrs['tolerance']:g} %)", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _housner(ds, ax):
    for i, geo in enumerate(ds.geometry.values):
        line, = ax.plot(ds.ratio, ds.period_exact[i], "-", label=f"{geo} exact")
        ax.plot(ds.ratio, ds.period_eq_5_1[i], ":", color=line.get_color(), label=f"{geo} Eq. 5.1")
        ax.plot(ds.ratio, ds.period_engine[i], "o", color=line.get_color(), label=f"{geo} engine")
    ax.set_xlabel(label(ds.ratio))
    ax.set_ylabel("rocking period T [s]")
    ax.legend(fontsize=7, ncol=3)


def _impact(ds, ax):
    ax.plot(ds.impact, ds.peak_eq_5_3, "-", label="Housner Eq. 5.3, r = %.2f" % ds.attrs["target_r"])
    ax.plot(ds.impact, ds.peak_engine, "o", label="engine, c_n = %.3g N s/m" % ds.attrs["calibrated_c_n"])
    ax.set_xlabel(label(ds.impact))
    ax.set_ylabel(label(ds.peak_engine))
    ax.legend()


def _newmark(ds, ax):
    for ap in sorted(set(ds.a_p_g.values)):
        sel = ds.a_p_g == ap
        line, = ax.plot(ds.mu[sel], ds.u_max_eq_5_5[sel], "-", label=f"Eq. 5.5, a_p = {ap:g} g")
        ax.plot(ds.mu[sel], ds.u_max_engine[sel], "o", color=line.get_color(), label=f"engine, a_p = {ap:g} g")
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
    ax.plot(ds.time, ds.theta_rigid, "-", label="rigid rocking equation, r = %.3f, scale %g" % (ds.attrs["restitution_r"], scale))
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
        line, = ax.plot(ds.time, ds.theta_lower[i], "-", label=f"lower block, {th0:g} rad")
        ax.plot(ds.time, ds.theta_upper[i], "--", color=line.get_color(), label=f"upper block, {th0:g} rad")
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel("rotation (positive: leaning right) [rad]")
    ax.legend(fontsize=8)


def _energy(ds, ax):
    ax.plot(ds.time, 100 * ds.relative_drift, "-")
    ax.axhline(100 * ds.attrs["tolerance"], color="k", ls=":")
    ax.axhline(-100 * ds.attrs["tolerance"], color="k", ls=":")
    ax.set_xlabel(label(ds.time))
    ax.set_ylabel("energy change / rocking energy [%]")


DRAWERS = {
    "housner_period": _housner,
    "impact_restitution": _impact,
    "newmark_pulse": _newmark,
    "record_sliding": _sliding,
    "record_rocking": _rocking,
    "two_blocks": _two_blocks,
    "energy_conservation": _energy,
}
