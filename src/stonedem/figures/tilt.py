"""Beyond the thesis (issue 48): leaning columns (``structure.tilt``) under the stand-in records.

The study ``tilt_records`` runs the standalone 2-drum column with a capital, leaning by 0 to
0.02 rad with its seat, at a ladder of PGAs under each stand-in record. Its table
``new_tilt_overturning`` gives, per record and tilt, the smallest PGA of the ladder that
overturned the column and the runs as a collapse map; the figure ``new_tilt_overturning``
draws the overturning curves: peak rocking over theta_cr against PGA, one line per tilt.

:func:`figures` and :func:`tables` are this module's part of the catalogue (stonedem.figures).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.catalogue import Cube, Figure, Reduction
from stonedem.figures.drawing import RECORD_LABEL, _finish, _save, collapsed_label, load_cube
from stonedem.study.cube import member_summary

TILT_RECORDS = Cube("tilt_records", {"tilt": None, "pga": None})


def overturning_rows(cube: xr.Dataset) -> list[dict]:
    """Per record and tilt: theta_cr (alpha - tilt), the smallest PGA that overturned the
    column (NaN: none), the largest below it that did not, and the collapse map over the
    PGA ladder (``pga:X`` overturned, ``pga:.`` stood)."""
    cube = member_summary(cube)
    records = cube["record"].values if "record" in cube.dims else [cube.attrs.get("record", "")]
    rows = []
    for record in records:
        one = cube.sel(record=record) if "record" in cube.dims else cube
        for tilt in one["tilt"].values:
            case = one.sel(tilt=tilt)
            pga = case["pga"].values
            fell = case["collapsed"].values >= 0.5
            first = float(pga[fell].min()) if fell.any() else float("nan")
            stood = pga[~fell & (pga < first)] if fell.any() else pga[~fell]
            theta_cr = float(np.nanmin(case["theta_cr"].values))
            rows.append(
                {
                    "record": str(record),
                    "tilt_rad": float(tilt),
                    "theta_cr_rad": theta_cr,
                    "overturning_pga_m_s2": first,
                    "stood_below_m_s2": float(stood.max()) if len(stood) else float("nan"),
                    "collapse_map": " ".join(
                        f"{p:g}:{'X' if f else '.'}" for p, f in zip(pga, fell)
                    ),
                }
            )
    return rows


def tables():
    """This module's CSV tables: name, Reduction."""
    yield "new_tilt_overturning", Reduction((TILT_RECORDS,), overturning_rows)


def _overturning_figure(inputs, path):
    cube = load_cube(inputs[0])
    records = list(cube["record"].values) if "record" in cube.dims else [None]
    fig, axes = plt.subplots(
        1, len(records), figsize=(4.2 * len(records), 3.8), squeeze=False, constrained_layout=True
    )
    for ax, record in zip(axes[0], records):
        one = cube.sel(record=record) if record is not None else cube
        for tilt in one["tilt"].values:
            case = one.sel(tilt=tilt)
            pga = case["pga"].values
            ratio = np.minimum(case["max_rocking"].values / case["theta_cr"].values, 1.0)
            fell = case["collapsed"].values >= 0.5
            (line,) = ax.plot(pga, ratio, "o-", ms=3, label=f"tilt {float(tilt):g} rad")
            ax.plot(pga[fell], np.ones(fell.sum()), "x", color=line.get_color(), ms=8)
        ax.set_xscale("log")
        ax.set_ylim(0.0, 1.08)
        ax.set_xlabel("PGA [m s-2]")
        ax.set_ylabel("peak rocking / theta_cr [1]")
        ax.set_title(RECORD_LABEL.get(str(record), str(record)), fontsize=8)
    axes[0][0].legend(fontsize=7, title=f"x: {collapsed_label(cube)}", title_fontsize=7)
    _finish(fig, "New: overturning curves of a column leaning with its seat (structure.tilt)")
    return _save(fig, path)


def figures(snap):
    """This module's figures: name, Figure (``snap`` unused: the study sets its own PGAs)."""
    yield (
        "new_tilt_overturning",
        Figure(
            "new",
            "Beyond the thesis (issue 48): peak mean drum rotation over theta_cr (alpha - tilt, "
            "toward the lean) of the 2-drum 6 m x 1 m column with a capital, leaning with its "
            "seat by 0-0.02 rad, against the PGA of each stand-in record (x: overturned).",
            (TILT_RECORDS,),
            _overturning_figure,
        ),
    )
