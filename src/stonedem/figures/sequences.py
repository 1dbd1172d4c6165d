"""Beyond the thesis (issue 48, item 2): earthquake sequences, the ``sequence_records`` study.

A column under a mainshock (``mainshock_pga``), a rest, and an aftershock (``aftershock_pga``),
the state carried over (``excitation: {kind: sequence}``). The table: per (mainshock,
aftershock) PGA, the collapse in each event and the residual deformation the mainshock left;
the figure (named as new, not as a thesis figure): collapse in the aftershock against that
residual. With ``ensemble: {members: K}`` a verdict is the fraction of the K members.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.catalogue import Cube, Figure, Reduction
from stonedem.figures.drawing import _finish, _save
from stonedem.io.netcdf import open_result
from stonedem.study.grid import MEMBER

STUDY = "sequence_records"
SEQUENCE_CUBE = Cube(STUDY, {"mainshock_pga": None, "aftershock_pga": None})


def _members(cube: xr.Dataset, name: str) -> np.ndarray:
    """A per-part variable as (mainshock, aftershock, member, part), one member when K = 1."""
    var = cube[name]
    if MEMBER not in var.dims:
        var = var.expand_dims(MEMBER, axis=-1)
    return var.transpose("mainshock_pga", "aftershock_pga", MEMBER, "part").values.astype(float)


def sequence_rows(cube: xr.Dataset) -> list[dict]:
    """One row per (mainshock, aftershock) PGA: the share of members collapsing in the
    mainshock; of those that survived it, the median residual total sliding [m] and mean
    drum rotation [rad] at the end of the mainshock's rest, and the share collapsing in the
    aftershock (NaN: every member fell in the mainshock); the median peak rocking in the
    aftershock [rad]."""
    collapsed = _members(cube, "part_collapsed")
    ran = _members(cube, "part_run")
    sliding = _members(cube, "part_residual_total_sliding")
    rocking = _members(cube, "part_residual_rocking")
    peak = _members(cube, "part_max_rocking")
    rows = []
    for i, a in enumerate(cube["mainshock_pga"].values):
        for j, b in enumerate(cube["aftershock_pga"].values):
            main = collapsed[i, j, :, 0]
            kept = (main == 0) & (ran[i, j, :, 1] == 1)  # survived the mainshock, ran the second
            after = collapsed[i, j, kept, 1]
            rows.append(
                {
                    "mainshock_pga": float(a),
                    "aftershock_pga": float(b),
                    "members": int(len(main)),
                    "mainshock_collapse_fraction": float(np.nanmean(main)),
                    "residual_sliding_after_mainshock": _median(sliding[i, j, kept, 0]),
                    "residual_rocking_after_mainshock": _median(rocking[i, j, kept, 0]),
                    "aftershock_collapse_fraction": float(after.mean()) if kept.any() else np.nan,
                    "aftershock_max_rocking": _median(peak[i, j, kept, 1]),
                }
            )
    return rows


def _median(values) -> float:
    values = np.asarray(values, dtype=float)
    return float(np.median(values)) if len(values) else float("nan")


def tables():
    """This module's CSV table: name, Reduction."""
    yield STUDY, Reduction((SEQUENCE_CUBE,), sequence_rows)


def _sequence_figure(inputs, path):
    """Collapse in the aftershock against the residual sliding the mainshock left (left), and
    the outcome map of mainshock x aftershock PGA (right)."""
    with open_result(inputs[0]) as cube:
        cube = cube.load()
    rows = sequence_rows(cube)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    after = sorted({r["aftershock_pga"] for r in rows})
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(after)))
    for k, (b, colour) in enumerate(zip(after, colours)):
        mine = sorted(
            (r for r in rows if r["aftershock_pga"] == b),
            key=lambda r: r["residual_sliding_after_mainshock"],
        )
        x = [1e3 * r["residual_sliding_after_mainshock"] for r in mine]
        # offset a little per aftershock, so that equal verdicts stay apart
        y = [r["aftershock_collapse_fraction"] + 0.015 * (k - len(after) / 2) for r in mine]
        left.plot(x, y, "o:", lw=0.8, color=colour, label=f"aftershock {b:g} m/s2")
    left.set_xlabel("residual total sliding after the mainshock's rest [mm]")
    left.set_ylabel("collapse in the aftershock (fraction of members) [1]")
    left.set_ylim(-0.1, 1.1)
    left.legend(fontsize=7)
    mains = sorted({r["mainshock_pga"] for r in rows})
    for r in rows:
        i, j = mains.index(r["mainshock_pga"]), after.index(r["aftershock_pga"])
        if r["mainshock_collapse_fraction"] >= 0.5:
            right.plot(j, i, "s", color="0.6", ms=12)
        elif r["aftershock_collapse_fraction"] >= 0.5:
            right.plot(j, i, "x", color="red", ms=12, mew=2)
        else:
            right.plot(j, i, "o", color="C0", ms=10, mfc="none")
        right.annotate(
            f"{1e3 * r['residual_sliding_after_mainshock']:.2g}",
            (j, i),
            textcoords="offset points",
            xytext=(0, 9),
            ha="center",
            fontsize=6,
        )
    right.set_xticks(range(len(after)), [f"{b:g}" for b in after])
    right.set_yticks(range(len(mains)), [f"{a:g}" for a in mains])
    right.set_xlabel("aftershock PGA [m/s2]")
    right.set_ylabel("mainshock PGA [m/s2]")
    right.plot([], [], "s", color="0.6", label="collapsed in the mainshock")
    right.plot([], [], "x", color="red", mew=2, label="collapsed in the aftershock")
    right.plot([], [], "o", color="C0", mfc="none", label="survived both")
    right.plot([], [], " ", label="numbers: residual sliding\nafter the mainshock [mm]")
    right.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    members = int(rows[0]["members"]) if rows else 1
    _finish(
        fig,
        "Earthquake sequences (new): 3-drum column, one record as mainshock and aftershock, "
        f"{members} member{'s' if members > 1 else ''} per case",
    )
    return _save(fig, path)


def figures(snap):
    """This module's figures: name, Figure."""
    yield (
        "new_sequence_aftershock_collapse",
        Figure(
            "new",
            "Earthquake sequences (beyond the thesis, issue 48): collapse of the standalone "
            "3-drum column in the aftershock against the residual sliding the mainshock left "
            "(left), and the outcome of every mainshock x aftershock PGA (right); the state "
            "carries over from the mainshock through a 10 s rest.",
            (SEQUENCE_CUBE,),
            _sequence_figure,
        ),
    )
