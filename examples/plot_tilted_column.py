"""
A column leaning with its seat
==============================

``structure: {kind: column, tilt: beta}`` builds a column inclined as a whole, for example
by a differential settlement of its foundation: it stands square on the base's top face,
which is inclined at beta [rad] (positive leaning toward +x). Rotations are measured from
that leaning rest pose. Under a slow ramp of the base acceleration the column uplifts
where a rigid block does, at g tan(alpha - beta) when it tips toward its lean and at
g tan(alpha + beta) away from it (alpha = atan(b/h)): the checks ``tilt_*`` of
``stonedem validate`` hold the engine to these to 1 %.
"""

# %%
# Three columns under the same ramp
# ---------------------------------
# A 6 m x 1 m column of 2 drums, upright and leaning 0.05 rad either way, under the ramp
# of thesis Fig. 6.10 (0.5 m/s2 per s toward +x). The inertial force points toward -x, so
# the column leaning toward -x (tilt < 0) tips toward its lean, first.
import math

import matplotlib.pyplot as plt
import numpy as np

import stonedem

G = 9.81
alpha = math.atan(1.0 / 6.0)
fig, ax = plt.subplots(figsize=(8, 4), layout="constrained")
for tilt, colour in ((-0.05, "#d62728"), (0.0, "#1f77b4"), (0.05, "#2ca02c")):
    ds = stonedem.run_scene(
        {
            "structure": {
                "kind": "column",
                "n_drums": 2,
                "height": 6.0,
                "width": 1.0,
                "tilt": tilt,
            },
            "friction": 2.0,  # nothing slides: tan(0.05) << 2
            "excitation": {"kind": "ramp", "rate": 0.5},  # [m/s2 per s]
            "solver": {"duration": 5.0},  # [s]
            "output": {"every": 0.005},
        }
    )
    accel = ds["base_acceleration"].values  # [m s-2]
    drums = ds["theta"].isel(body=slice(1, None)).mean("body").values  # from the rest pose
    ax.plot(accel, np.abs(drums), color=colour, label=f"tilt {tilt:+g} rad")
    # the closed form: toward the lean for tilt < 0, away from it for tilt > 0
    static = G * math.tan(alpha + tilt)
    ax.axvline(static, color=colour, ls=":", lw=1)
    theta_cr = float(ds["theta_cr"])  # alpha - |tilt|: toward the lean [rad]
    print(f"tilt {tilt:+g} rad: theta_cr {theta_cr:.4f} rad, static uplift {static:.3f} m/s2")
ax.set_yscale("log")
ax.set_ylim(1e-6, 0.5)
ax.set_xlabel("base acceleration [m s-2]")
ax.set_ylabel("mean drum rotation from rest [rad]")
ax.set_title("Uplift of a leaning column under a ramp (dotted: g tan(alpha -+ beta))", fontsize=10)
ax.legend()
plt.show()
