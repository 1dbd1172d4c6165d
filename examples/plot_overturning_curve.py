"""
A study cube and an overturning curve
=====================================

A study runs one scene over a grid of parameters and combines the cases into a *cube*: one
NetCDF file whose dimensions are the swept parameters. Here a 6 m x 1 m monolithic column
is shaken by harmonic base motions of three frequencies and increasing peak acceleration; the
peak rocking of each case, over the critical angle, draws the column's overturning curve.
The workflow does the same for the studies of ``config/config.yaml`` (``snakemake``
writes ``results/cubes/<study>.nc``); this example builds its own small cube.
"""

# %%
# The study
# ---------
# A study is a base scene plus a ``grid``; each grid parameter maps to one scene field
# (``stonedem.study.grid.PARAMETERS``: ``pga`` is ``excitation.pga`` [m s-2],
# ``frequency`` is ``excitation.frequency`` [Hz]). The defaults are those of the study's
# config: the point contact law, the automatic step, a run stopped at collapse.
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import stonedem
from stonedem.study.cube import combine_cases
from stonedem.study.grid import case_table
from stonedem.study.runner import run_case

defaults = {
    "contact": {"model": "point", "k_n": 1.0e10},
    "solver": {"dt": "auto", "dt_safety": 1.0, "stop_on_collapse": True},
    "output": {"every": 0.01},
}
study = {
    "structure": {"kind": "column", "n_drums": 1, "height": 6.0, "width": 1.0},
    "friction": 0.485,
    "excitation": {"kind": "harmonic"},
    "solver": {"duration": 4.0},  # [s]
    "grid": {
        "frequency": [1.0, 2.0, 4.0],
        "pga": [1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 11.0, 15.0],
    },
}
cases = case_table("overturning", study, defaults)
print(f"{len(cases)} cases:", ", ".join(case.id for case in cases))

# %%
# Run the cases and combine them
# ------------------------------
# Each case is one simulation whose dataset carries its parameters as scalar coordinates;
# :func:`stonedem.study.cube.combine_cases` merges the case files into the cube.
workdir = tempfile.TemporaryDirectory(prefix="stonedem_cube_")  # removed when the script ends
folder = Path(workdir.name)
paths = [stonedem.write_dataset(run_case(case), folder / f"{case.id}.nc") for case in cases]
stonedem.write_dataset(
    combine_cases(paths, description="gallery example"), folder / "overturning.nc"
)

# %%
# Open the cube
# -------------
# :func:`stonedem.open_cube` reads a cube into memory and refuses any other kind of file
# with a one-line message naming the fix.
cube = stonedem.open_cube(folder / "overturning.nc")
print(cube[["collapsed", "max_rocking", "theta_cr"]])

# %%
# The overturning curve
# ---------------------
# The static limit of a rigid block is g b/h (here 1.6 m/s2): below it the column does not
# uplift. The 1 Hz motion overturns the column from 5 m/s2, yet it survives 11 and 15 m/s2:
# overturning is not monotonic in the intensity, which is why the threshold searches of the
# study fill the gaps above their first collapse. The faster motions, whose pulses are too
# short to tip a 6 m column over, leave it standing over the whole range (Housner's scale
# effect).
theta_cr = float(cube["theta_cr"].max())
fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
for f, colour in zip(cube["frequency"].values, ("#1f77b4", "#d62728", "#2ca02c")):
    one = cube.sel(frequency=f)
    ratio = np.minimum(one["max_rocking"].values / theta_cr, 1.0)
    fell = one["collapsed"].values > 0
    ax.plot(one["pga"], ratio, "-", color=colour, label=f"{f:g} Hz")
    ax.plot(one["pga"][~fell], ratio[~fell], "o", color=colour)
    ax.plot(one["pga"][fell], ratio[fell], "X", color=colour, ms=10)
ax.axvline(9.81 * 1.0 / 6.0, color="0.5", ls=":", label="g b/h (static)")
ax.set_xscale("log")
ax.set_xlabel(f"PGA [{cube['pga'].attrs['units']}]")
ax.set_ylabel("max rocking / theta_cr [1] (X: overturned)")
ax.set_ylim(0, 1.1)
ax.set_title(f"{cube.attrs['title']}: {cube.attrs['n_cases']} cases", fontsize=10)
ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
plt.show()
