"""
A collapse-threshold search
===========================

Which peak ground acceleration makes a column collapse? Rather than a fine grid of runs,
the hunt-and-fill search of incremental dynamic analysis (Vamvatsikos & Cornell 2002,
``stonedem.study.search``) *hunts* upward in growing steps until the column collapses,
*bisects* between the last survivor and that first collapse to a narrow bracket, then
*fills* the widest gaps, since collapse need not be monotonic in the intensity. The
search is a pure function of the runs so far; a "run" is whatever the caller does with a
value, here one simulation.
"""

# %%
# The system and the search settings
# ----------------------------------
# A study with ``search:`` makes one *system* per grid case: its threshold is searched in
# ``pga`` [m s-2]. Here a two-drum column, 6 m x 1 m, under a 1.5 Hz harmonic, searched
# from 1 m/s2 to a 5 % bracket, then one run filling the widest gap below the bracket.
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import stonedem
from stonedem.study.cube import search_dataset
from stonedem.study.grid import case_table, search_case
from stonedem.study.runner import run_case
from stonedem.study.search import next_value, search, summary

defaults = {
    "contact": {"model": "point", "k_n": 1.0e10},
    "solver": {"dt": "auto", "dt_safety": 1.0, "stop_on_collapse": True},
    "output": {"every": 0.01},
}
study = {
    "structure": {"kind": "column", "n_drums": 2, "height": 6.0, "width": 1.0},
    "friction": 0.485,
    "excitation": {"kind": "harmonic"},
    "solver": {"duration": 4.0},
    "grid": {"frequency": [1.5]},
    "search": {
        "parameter": "pga",
        "start": 1.0,
        "factor": 1.8,
        "tolerance": 0.05,
        "maximum": 32.0,
        "fill": 1,
    },
}
[system] = case_table("search_example", study, defaults)
settings = system.search
print(settings)
print("first value to run:", next_value([], settings))

# %%
# Run the search
# --------------
# :func:`stonedem.study.search.search` calls ``collapses(value, phase)`` until the search
# is done; each call simulates the system at that PGA (:func:`~stonedem.study.grid.search_case`
# makes the case, :func:`~stonedem.study.runner.run_case` runs it) and keeps its file.
workdir = tempfile.TemporaryDirectory(prefix="stonedem_search_")  # removed when the script ends
folder = Path(workdir.name)
files = {}


def collapses(value, phase):
    case = search_case(system, value)
    ds = run_case(case)
    files[value] = stonedem.write_dataset(ds, folder / f"{case.id}.nc")
    print(
        f"{phase:7s} PGA {value:6.4g} m/s2: "
        + (f"collapsed at {float(ds['collapse_time']):.2f} s" if ds["collapsed"] else "survived")
    )
    return bool(ds["collapsed"])


runs = search(collapses, settings)
result = summary(runs, settings)
print(
    f"{result['status']}: collapse between {result['lower']:.4g} and {result['upper']:.4g} m/s2 "
    f"({result['n_runs']} runs)"
)

# %%
# The search file
# ---------------
# :func:`stonedem.study.cube.search_dataset` gathers the runs (sorted by value) and the
# bracket into one dataset, as the workflow's ``results/searches/<study>/<system>.nc``;
# :func:`stonedem.open_search` opens such a file.
path = stonedem.write_dataset(
    search_dataset(system, runs, [files[r.value] for r in runs], result), folder / "search.nc"
)
found = stonedem.open_search(path)
print(found[["collapse_threshold", "survived_below_threshold", "bracket_width", "search_status"]])

# %%
# How the search went
# -------------------
# Left, the values in the order they were run; right, each run's peak rocking against its
# PGA, with the bracket shaded.
fig, (order, curve) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
colour = {True: "#d62728", False: "#2ca02c"}
for k, r in enumerate(runs, start=1):
    order.plot(k, r.value, "X" if r.collapsed else "o", color=colour[r.collapsed], ms=9)
    order.annotate(r.phase, (k, r.value), textcoords="offset points", xytext=(6, -3), fontsize=8)
order.plot(range(1, len(runs) + 1), [r.value for r in runs], color="0.7", lw=0.8, zorder=0)
order.set_yscale("log")
order.set_xlabel("run")
order.set_ylabel("PGA [m s-2] (X: collapsed)")

theta_cr = float(found["theta_cr"].max())
fell = found["collapsed"].values > 0
curve.axvspan(
    float(found.survived_below_threshold),
    float(found.collapse_threshold),
    color="0.85",
    label=f"bracket ({float(found.bracket_width):.1%})",
)
curve.plot(
    found["pga"][~fell],
    found["max_rocking"][~fell] / theta_cr,
    "o",
    color=colour[False],
    label="survived",
)
curve.plot(
    found["pga"][fell], [1.0] * int(fell.sum()), "X", color=colour[True], ms=9, label="collapsed"
)
curve.set_xscale("log")
curve.set_xlabel("PGA [m s-2]")
curve.set_ylabel("max rocking / theta_cr [1]")
curve.legend()
fig.suptitle(f"{found.attrs['title']}: {found.search_status.item()}", fontsize=10)
plt.show()
