"""
Shear links between drums
=========================

Ancient columns had wooden empolia between their drums, and restorations set titanium
dowels (the thesis' chapter 8.3). Here a 6 m column of three drums stands on a base that
moves with the Mexico City stand-in record (committed in ``records/``) scaled to a PGA of
8 m/s2, once without links and once with each preset at both drum-drum joints
(``structure.links``). The links resist sliding beside the friction; the drums lift off
them freely. The permanent sliding at the end is what the study ``links_records`` compares
(docs/results/links.md).
"""

# %%
# The scenes
# ----------
# ``structure.links: {kind: titanium}`` puts one link at every drum-drum joint, at the
# centre of the face (``at: 0``); a scene may instead list ``links: [{bodies: [lower,
# upper], ...}]``. The presets are illustrative numbers (``stonedem.engine.links``).
import matplotlib.pyplot as plt

import stonedem


def column(kind):
    return {
        "name": f"3-drum column, links: {kind}",
        "structure": {
            "kind": "column",
            "n_drums": 3,
            "height": 6.0,
            "width": 1.0,
            "capital": {"height": 0.6, "width": 1.4},
            "links": {"kind": kind},
        },
        "friction": 0.485,
        "excitation": {"kind": "record", "file": "mexico_standin_chichi_tcu102", "pga": 8.0},
        "solver": {"duration": 40.0},  # [s]
        "output": {"every": 0.01},
    }


runs = {kind: stonedem.run_scene(column(kind)) for kind in ("none", "wood", "titanium")}

# %%
# Sliding and the links' state
# ----------------------------
# ``total_sliding`` sums each body's sliding along the face it stands on; a linked run's
# dataset also holds each link's final state (engaged, broken, pulled out), its peak force
# and its plastic slip.
fig, ax = plt.subplots(figsize=(7, 3.8), layout="constrained")
for kind, ds in runs.items():
    (1e3 * ds.total_sliding).plot(ax=ax, label=f"links: {kind}")
    print(f"{kind:9s} permanent sliding {1e3 * float(ds.residual_total_sliding):6.2f} mm")
    if "link" in ds.dims:
        for i in ds.link.values:
            state = ds.link_status.attrs["flag_meanings"].split()[int(ds.link_status[i])]
            print(
                f"          link {ds.link_lower.values[i]}/{ds.link_upper.values[i]}: {state}, "
                f"peak {float(ds.link_peak_force[i]) / 1e3:.1f} kN, "
                f"plastic slip {1e3 * float(ds.link_plastic_slip[i]):.2f} mm"
            )
ax.set_ylabel("total sliding [mm]")
ax.legend()
plt.show()
