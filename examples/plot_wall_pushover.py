"""
A masonry-wall pushover
=======================

The 3D solver (``stonedem.wall``) pushes a dry-joint masonry wall out of its plane with a
load proportional to its weight, multiplied by a load factor lambda, and follows the wall
past its peak. A wall standing free on a fixed base overturns as a rigid body at
lambda = s/H (thickness over height; manuscript Fig. 11a); a wall also held along one side
edge (specimen S12 of Restrepo-Velez et al. 2014) must break up first, and carries more.
The cases are files of ``config/walls/``.
"""

# %%
# Run two cases
# -------------
# :func:`stonedem.run_wall` takes a case file (or the same keys as a dict); the dataset holds
# the curve on ``step``: ``lambda`` and the displacement of the control block [m].
from pathlib import Path

import matplotlib.pyplot as plt
import yaml

import stonedem

walls = Path(stonedem.__file__).resolve().parents[2] / "config" / "walls"  # in a checkout
results = {name: stonedem.run_wall(walls / f"{name}.yaml") for name in ("free_standing", "s12")}
for name, ds in results.items():
    print(
        f"{name}: {ds.attrs['n_blocks']} blocks, lambda_max = {float(ds.lambda_max):.4f} "
        f"({ds.attrs['status']}), {ds.sizes['step']} steps, {ds.attrs['wall_seconds']:.1f} s"
    )

# %%
# Against the references
# ----------------------
# Each case records its references in ``reference``: the closed form s/H for the free-
# standing wall, the manuscript's DEM result and the experiment for S12.
reference = {
    name: yaml.safe_load((walls / f"{name}.yaml").read_text())["reference"] for name in results
}
analytic = reference["free_standing"]["lambda_analytic"]
print(
    f"free_standing: lambda_max {float(results['free_standing'].lambda_max):.4f} vs s/H = "
    f"{analytic:.4f}"
)
s12 = reference["s12"]
print(
    f"s12: lambda_max {float(results['s12'].lambda_max):.4f} vs manuscript DEM "
    f"{s12['lambda_dem']}, "
    f"experiment {s12['lambda_experiment']}"
)

# %%
# The pushover curves
# -------------------
fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
for (name, ds), colour in zip(results.items(), ("#1f77b4", "#d62728")):
    ax.plot(
        ds["control_displacement"] * 1e3,
        ds["lambda"],
        color=colour,
        label=f"{name} ({ds.attrs['n_blocks']} blocks): lambda_max {float(ds.lambda_max):.3f}",
    )
    at_limit = int(ds.step_at_limit)
    ax.plot(
        float(ds["control_displacement"][at_limit]) * 1e3, float(ds.lambda_max), "o", color=colour
    )
ax.axhline(
    analytic, color="#1f77b4", ls=":", lw=0.9, label=f"s/H = {analytic:.4f} (free-standing, rigid)"
)
ax.axhline(
    s12["lambda_dem"],
    color="#d62728",
    ls=":",
    lw=0.9,
    label=f"S12, manuscript DEM {s12['lambda_dem']}",
)
ax.axhline(
    s12["lambda_experiment"],
    color="#d62728",
    ls="--",
    lw=0.9,
    label=f"S12, experiment {s12['lambda_experiment']}",
)
ax.set_xlabel("out-of-plane displacement of the control block [mm]")
ax.set_ylabel(f"load factor lambda [{results['s12']['lambda'].attrs['units']}]")
ax.set_title("Pushover of dry-joint masonry walls", fontsize=10)
ax.legend(fontsize=8, loc="center right")
plt.show()
