"""Beyond the thesis (its 8.3, issue 48): a 3-drum column with shear links at its drum-drum
joints beside the unlinked column under the stand-in records, study ``links_records``.

Its tables: ``links_records`` (per link kind and PGA: collapses over the records, mean
permanent sliding and rotation of the records that left the column standing) and
``links_records_finding`` (per link kind: is the thesis' ref. [70] finding there, fewer
permanent displacements at moderate PGA and no gain or a loss near collapse, read from the
numbers); its figure ``new_links_overturning``. :func:`figures` and :func:`tables` are this
module's part of the catalogue (stonedem.figures).
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from stonedem.figures.catalogue import Cube, Figure, Reduction
from stonedem.figures.drawing import _finish, _save, load_cube
from stonedem.study.cube import member_summary

STUDY = "links_records"
CUBE = Cube(STUDY, {"link_kind": None, "pga": None})
KINDS = ("none", "wood", "titanium")
# a case moves at moderate PGA when the unlinked column stands and slides at least this [m]
MOVING = 1e-3


def _residual_rocking(cube: xr.Dataset) -> xr.DataArray:
    """The last finite mean |theta| of the drums of each case [rad] (its rocking history)."""
    rocking = cube["rocking"]
    finite = np.isfinite(rocking.values)
    last = finite.shape[-1] - 1 - np.argmax(finite[..., ::-1], axis=-1)
    values = np.take_along_axis(rocking.values, last[..., None], axis=-1)[..., 0]
    values = np.where(finite.any(axis=-1), values, np.nan)
    return xr.DataArray(
        values, dims=rocking.dims[:-1], coords={d: cube[d] for d in rocking.dims[:-1]}
    )


def _prepared(cube: xr.Dataset) -> xr.Dataset:
    cube = member_summary(cube)
    standing = cube["collapsed"] < 0.5
    return xr.Dataset(
        {
            "collapsed": cube["collapsed"],
            "residual_sliding": cube["residual_total_sliding"].where(standing),
            "residual_rocking": _residual_rocking(cube).where(standing),
        }
    ).transpose("link_kind", "pga", ...)


def links_table(cube: xr.Dataset) -> list[dict]:
    """Per link kind and PGA: records run, collapses, and the mean permanent total sliding [mm]
    and mean |theta| [mrad] at the end over the records that left the column standing."""
    data = _prepared(cube)
    rows = []
    for kind in data.link_kind.values:
        for pga in data.pga.values:
            case = data.sel(link_kind=kind, pga=pga)
            standing = int(np.sum(case.collapsed.values < 0.5))
            rows.append(
                {
                    "link_kind": str(kind),
                    "pga_m_s2": float(pga),
                    "records": int(case.collapsed.size),
                    "collapsed": int(np.sum(case.collapsed.values >= 0.5)),
                    "residual_sliding_mm": float(np.nanmean(case.residual_sliding.values)) * 1e3
                    if standing
                    else math.nan,
                    "residual_rotation_mrad": float(np.nanmean(case.residual_rocking.values)) * 1e3
                    if standing
                    else math.nan,
                }
            )
    return rows


def _first_collapse(collapsed: np.ndarray, pga: np.ndarray) -> float:
    hit = np.flatnonzero(collapsed >= 0.5)
    return float(pga[hit[0]]) if len(hit) else math.inf


def finding(cube: xr.Dataset, kind: str) -> dict:
    """The thesis' ref. [70] finding for one link kind against the unlinked column, from the
    numbers: at moderate PGA (both stand, the unlinked column slides >= MOVING) the summed
    permanent sliding, linked vs unlinked, fewer when lower in sum and in most cases; near
    collapse, per record, the lowest collapsing PGA of the grid, linked vs unlinked (higher: a
    gain; lower: a loss)."""
    data = _prepared(cube)
    free, linked = data.sel(link_kind="none"), data.sel(link_kind=kind)
    moving = (
        (free.collapsed.values < 0.5)
        & (linked.collapsed.values < 0.5)
        & (free.residual_sliding.values >= MOVING)
    )
    s_free = float(np.sum(free.residual_sliding.values[moving]))
    s_link = float(np.sum(linked.residual_sliding.values[moving]))
    fewer = int(
        np.sum(linked.residual_sliding.values[moving] < free.residual_sliding.values[moving])
    )
    pga = data.pga.values
    gains = losses = 0
    for r in data.record.values:
        a_free = _first_collapse(free.collapsed.sel(record=r).values, pga)
        a_link = _first_collapse(linked.collapsed.sel(record=r).values, pga)
        gains += a_link > a_free
        losses += a_link < a_free
    n_records = int(data.sizes["record"])
    # fewer in sum and in most of the moderate cases: a sum a fraction of a percent lower,
    # with the links lower in one case of six, is no finding
    less_moving = bool(moving.any() and s_link < s_free and 2 * fewer > moving.sum())
    no_gain = gains == 0
    return {
        "link_kind": kind,
        "moderate_cases": int(moving.sum()),
        "fewer_residual_cases": fewer,
        "residual_sliding_unlinked_mm": s_free * 1e3,
        "residual_sliding_linked_mm": s_link * 1e3,
        "records": n_records,
        "collapse_later": int(gains),
        "collapse_earlier": int(losses),
        "fewer_permanent_displacements": "yes" if less_moving else "no",
        "no_gain_near_collapse": "yes" if no_gain else "no",
        "finding_shows": "yes" if less_moving and no_gain else "no",
    }


def findings_table(cube: xr.Dataset) -> list[dict]:
    """:func:`finding` of each link kind of the cube."""
    return [finding(cube, str(k)) for k in cube.link_kind.values if str(k) != "none"]


def _verdict(cube: xr.Dataset) -> str:
    lines = []
    for row in findings_table(cube):
        lines.append(
            f"{row['link_kind']}: permanent sliding over {row['moderate_cases']} moderate cases "
            f"{row['residual_sliding_linked_mm']:.3g} mm vs "
            f"{row['residual_sliding_unlinked_mm']:.3g}"
            f" mm unlinked ({row['fewer_residual_cases']} cases fewer); first collapse later on "
            f"{row['collapse_later']}, earlier on {row['collapse_earlier']} of {row['records']} "
            f"records: ref. [70] finding "
            f"{'shows' if row['finding_shows'] == 'yes' else 'does NOT show'}"
        )
    return "\n".join(lines)


def draw_overturning(inputs, path):
    """Collapses, permanent sliding and permanent rotation vs PGA, one curve per link kind."""
    cube = load_cube(inputs[0])
    data = _prepared(cube)
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.2), layout="constrained")
    pga = data.pga.values
    marks = {"none": ("o", "-", 9), "wood": ("s", "--", 6), "titanium": ("^", ":", 6)}
    for kind in data.link_kind.values:
        case = data.sel(link_kind=kind)
        marker, line, size = marks.get(str(kind), ("x", "-", 6))
        style = {"marker": marker, "ls": line, "ms": size, "mfc": "none", "label": f"links: {kind}"}
        axes[0].plot(pga, (case.collapsed >= 0.5).sum("record"), **style)
        axes[1].plot(pga, case.residual_sliding.mean("record") * 1e3, **style)
        axes[2].plot(pga, case.residual_rocking.mean("record") * 1e3, **style)
    n = int(data.sizes["record"])
    axes[0].set_ylabel(f"records that overturned it (of {n})")
    axes[1].set_ylabel("permanent total sliding [mm]")
    axes[2].set_ylabel("permanent mean |theta| of the drums [mrad]")
    axes[1].set_title("mean over the records it survived", fontsize=8)
    axes[2].set_title("mean over the records it survived", fontsize=8)
    for ax in axes:
        ax.set_xlabel("PGA [m s-2]")
        ax.legend(fontsize=7)
    _finish(
        fig,
        "New (beyond the thesis, its 8.3): 3-drum column with shear links at its joints, "
        "stand-in records",
        _verdict(cube),
    )
    return _save(fig, path)


def tables():
    """This module's CSV tables: name, Reduction."""
    yield STUDY, Reduction((CUBE,), links_table)
    yield f"{STUDY}_finding", Reduction((CUBE,), findings_table)


def figures(snap):
    """This module's figures: name, Figure."""
    yield (
        "new_links_overturning",
        Figure(
            "new",
            "Shear links (dowels, empolia; thesis 8.3, beyond the thesis): a 3-drum column with "
            "links at every drum-drum joint (wood and titanium presets, illustrative) beside "
            "the unlinked column under the three stand-in records scaled to each PGA: records "
            "that overturned it, and the permanent sliding and rotation of those that left it "
            "standing. The strip says whether the thesis' ref. [70] finding shows.",
            (CUBE,),
            draw_overturning,
        ),
    )
