"""
An earthquake sequence: a mainshock, a rest, an aftershock
==========================================================

``excitation: {kind: sequence}`` runs ground motions back to back with a quiet base after
each, and the state carries over: whatever residual sliding, rotation or open joints the
first event leaves, the second meets. Here the standalone 3-drum column of thesis Table 7.1
(6 m x 1 m, with a capital) is shaken by the Kalamata stand-in at 3 m/s2, rests 10 s, and
is shaken again at 4 m/s2; beside it, the same aftershock on a column that saw no
mainshock. The study ``sequence_records`` of ``config/config.yaml`` sweeps both PGAs
(:doc:`/results/sequences`).
"""

# %%
# The two scenes
# --------------
# A sequence's parts are records or pulses (motions that end); ``rest`` [s] follows each,
# and ``solver.duration`` must cover the parts and their rests (the last part runs on to it).
import matplotlib.pyplot as plt

import stonedem

RECORD = "kalamata_standin_izmit_izt270"
column = {
    "structure": {
        "kind": "column",
        "n_drums": 3,
        "height": 6.0,
        "width": 1.0,
        "capital": {"height": 0.6, "width": 1.4},
    },
    "friction": 0.485,
    "contact": {"model": "point", "k_n": 1.0e10},
    "output": {"every": 0.01},
}
sequence = {
    **column,
    "excitation": {
        "kind": "sequence",
        "parts": [
            {"kind": "record", "file": RECORD, "pga": 3.0},  # the mainshock [m s-2]
            {"kind": "record", "file": RECORD, "pga": 4.0},  # the aftershock
        ],
        "rest": 10.0,  # [s]
    },
    "solver": {"duration": 82.0},  # [s] 2 x (30 s record + 10 s rest), and 2 s more
}
alone = {
    **column,
    "excitation": {"kind": "record", "file": RECORD, "pga": 4.0},
    "solver": {"duration": 42.0},
}

# %%
# Run them
# --------
# Each part of the sequence is a run of its own, started from the state the part before it
# handed over; the rest is carried by the base once the column is at rest there.
ds = stonedem.run_scene(sequence)
fresh = stonedem.run_scene(alone)
print(ds.attrs["status"], "|", fresh.attrs["status"])

# %%
# What each part did
# ------------------
# The dataset has a ``part`` dimension: per part its peaks, the residuals at the end of its
# rest and whether the column collapsed in it (units and long names on every variable).
for name in (
    "part_max_rocking",
    "part_residual_total_sliding",
    "part_residual_rocking",
    "part_collapsed",
):
    print(f"{ds[name].attrs['long_name']} [{ds[name].attrs['units']}]:", ds[name].values)

# %%
# Draw the rocking
# ----------------
# The aftershock's window starts at ``part_start[1]``; the column alone meets the same
# record there, shifted on the same clock.
start = float(ds.part_start[1])
fig, ax = plt.subplots(figsize=(8, 3.6), constrained_layout=True)
ax.axvspan(start, float(ds.time[-1]), color="0.92", label="aftershock window")
ax.plot(ds.time, ds.rocking, lw=0.8, label="after a mainshock of 3 m/s2")
ax.plot(fresh.time + start, fresh.rocking, lw=0.8, label="the aftershock alone")
ax.axhline(float(ds.theta_cr), color="k", ls=":", lw=0.8, label="theta_cr")
ax.set_xlabel("time [s]")
ax.set_ylabel(f"{ds.rocking.attrs['long_name']} [{ds.rocking.attrs['units']}]", fontsize=8)
ax.legend(fontsize=7)
plt.show()
