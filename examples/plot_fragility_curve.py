"""
A fragility curve from a small IDA
==================================

A fragility curve gives the probability that a structure reaches a limit state, here
collapse, at a given intensity of ground motion. Incremental dynamic analysis (IDA) finds,
for each record of a suite, the smallest PGA at which the structure collapses (a threshold
search per record); a lognormal curve P = Phi(ln(PGA / theta) / beta) is then fitted to
these intensities by maximum likelihood. The workflow runs this for whole FEMA P695 suites
(``snakemake fragility``); this example runs the sixteen components of the first eight
far-field records to a 10 % bracket, enough to see the method at work.
"""

# %%
# The IDA as a study
# ------------------
# The ``fragility:`` section of the workflow config names structures and record suites;
# :func:`stonedem.fragility.ida.fragility_studies` turns each structure into a threshold-
# search study over the suite's components (FEMA P695 records, committed in
# ``records/suites/``), searched in PGA [m s-2]. Each run lasts its record's length plus
# 2 s for the column to come to rest, unless it collapses first.
import sys
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import stonedem
from stonedem.fragility.fit import empirical_points, fit_lognormal, fragility_dataset
from stonedem.fragility.ida import LIMIT_STATES, fragility_studies, ida_cube
from stonedem.study.grid import case_table
from stonedem.study.runner import CaseStore, run_search

structures = {
    "column": {
        "structure": {
            "kind": "column",
            "n_drums": 1,
            "height": 6.0,
            "width": 1.0,
            "capital": {"height": 0.6, "width": 1.4},
        },
        "friction": 0.485,
    }
}
config = {
    "defaults": {
        "contact": {"model": "point", "k_n": 1.0e10},
        "solver": {"dt": "auto", "dt_safety": 1.0, "stop_on_collapse": True},
        "output": {"every": 0.01},
    },
    "fragility": {
        "structures": structures,
        "suites": ["far_field"],
        "components": [f"FF{k:02d}{c}" for k in range(1, 9) for c in "ab"],  # FF01a ... FF08b
        "search": {"start": 2.0, "factor": 1.8, "tolerance": 0.1, "fill": 0, "max_runs": 12},
    },
}
[(study, spec)] = fragility_studies(config).items()
systems = case_table(study, spec, config["defaults"])
print(study, "-", len(systems), "records:", ", ".join(system.id for system in systems))

# %%
# One search per record
# ---------------------
# :func:`stonedem.study.runner.run_search` runs a system's hunt-and-fill search, writes each
# run's case file and the search file, and logs one line per run.
workdir = tempfile.TemporaryDirectory(prefix="stonedem_ida_")  # removed when the script ends
folder = Path(workdir.name)
searches = []
for system in systems:
    path = folder / f"{system.id}.nc"
    run_search(system, folder / system.id, path, CaseStore(None), log=sys.stdout)
    searches.append(path)

# %%
# The IDA cube and the fits
# -------------------------
# :func:`stonedem.fragility.ida.ida_cube` reads the searches into the cube (structure x
# record x limit state): the intensity at which each limit state is first exceeded, and
# whether only a lower bound is known (no collapse up to the search maximum: *censored*).
# :func:`stonedem.fragility.fit.fragility_dataset` fits every limit state, with a bootstrap
# band over the records. Both are files of the workflow; :func:`stonedem.open_ida` and
# :func:`stonedem.open_fragility` open them.
stonedem.write_dataset(ida_cube(searches, structures, ["far_field"]), folder / "ida.nc")
ida = stonedem.open_ida(folder / "ida.nc")
stonedem.write_dataset(fragility_dataset(ida, samples=300), folder / "fragility.nc")
fits = stonedem.open_fragility(folder / "fragility.nc")

collapse = ida.sel(structure="column", limit_state="collapse")
ran = collapse["censored"].values >= 0
pga = collapse["pga_at_limit"].values[ran]
censored = collapse["censored"].values[ran] == 1
for name, x, c in zip(collapse["record"].values[ran], pga, censored):
    print(
        f"{name}: collapse at {x:.3g} m/s2"
        + (" (no collapse up to here: a lower bound)" if c else "")
    )

# %%
# The fragility curve
# -------------------
# :func:`stonedem.fragility.fit.fit_lognormal` is the fit itself (censored records enter the
# likelihood as lower bounds); it agrees with the fits file. The lesser limit states come
# from the same runs: rocking starts at nearly the same PGA under every record (near the
# static g b/h), so its curve is steep; collapse scatters widely from record to record.
fit = fit_lognormal(pga, censored)
f = fits.sel(structure="column", record_set="all", limit_state="collapse")
print(
    f"median {fit.median:.3g} m/s2 (file: {float(f.median_pga):.3g}), beta {fit.beta:.2f} "
    f"(file: {float(f.beta_pga):.2f}), {fit.n} records, {fit.censored} censored"
)

grid = fits["pga_grid"].values
band = f["probability_pga_band"].values
x, p = empirical_points(pga, censored)
fig, ax = plt.subplots(figsize=(7, 4.2), layout="constrained")
ax.fill_between(grid, band[0], band[1], color="0.85", lw=0, label="90 % bootstrap band")
ax.plot(
    grid,
    fit.probability(grid),
    color="k",
    label=f"lognormal MLE: theta {fit.median:.3g} m/s2, beta {fit.beta:.2f}",
)
ax.plot(x, p, "o", color="#d62728", label="records (empirical)")
for state, colour in (("half_critical_rotation", "#1f77b4"), ("rocking_onset", "#2ca02c")):
    curve = fits["probability_pga"].sel(structure="column", record_set="all", limit_state=state)
    if np.isfinite(curve).any():
        ax.plot(grid, curve, color=colour, lw=1, ls="--", label=LIMIT_STATES[state].label)
ax.set_xscale("log")
ax.set_xlim(0.3, 60)
ax.set_ylim(0, 1)
ax.set_xlabel("PGA [m s-2]")
ax.set_ylabel("P(limit state exceeded | PGA)")
ax.set_title(
    f"Fragility of a 6 m x 1 m column with a capital: {fit.n} far-field records", fontsize=10
)
ax.legend(fontsize=8, loc="lower right")
plt.show()
