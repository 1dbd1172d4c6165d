"""The block on a driven base that the validations shake, and what their datasets share: the
engine's default contact law, the contact attributes and the first zero crossing of a
rotation (:mod:`stonedem.validation.cases` and the modules of checks it registers)."""

from __future__ import annotations

import numpy as np

from stonedem.engine.laws import LAWS

POINT_CONTACT = {"model": "point", **LAWS["point"].defaults}  # the engine's default law


def block_scene(
    width,
    height,
    *,
    mass=None,
    density=2700.0,
    friction=10.0,
    k_n=1e9,
    c_n=0.0,
    c_t=None,
    tilt=0.0,
    excitation=None,
    duration=1.0,
    dt="auto",
    every=1e-3,
    base_width=None,
    stop_on_collapse=False,
    dt_safety="auto",
    contact=None,
):
    """Scene dict of one rectangular block resting on a driven base (top at y = 0).

    The contact is the area law with k_n, c_n (and c_t) unless ``contact`` gives the whole
    contact mapping (e.g. {"model": "point", "k_n": 1e11}); the step is the engine's
    automatic one for that law (stonedem.engine.laws.LAWS) unless ``dt_safety`` is given.
    """
    block = {
        "name": "block",
        "box": {"width": width, "height": height, "center": [0.0, height / 2]},
    }
    if mass is not None:
        block["mass"] = mass
    else:
        block["density"] = density
    if tilt:
        block["tilt"] = {"angle": abs(tilt), "about": "bottom_right" if tilt > 0 else "bottom_left"}
    base_width = base_width or max(4.0, 4.0 * width)
    return {
        "bodies": [
            {
                "name": "base",
                "box": {"width": base_width, "height": 0.5, "center": [0.0, -0.25]},
                "driven": True,
            },
            block,
        ],
        "friction": friction,
        "contact": dict(contact)
        if contact is not None
        else {"model": "area", "k_n": k_n, "c_n": c_n, **({} if c_t is None else {"c_t": c_t})},
        "excitation": excitation or {"kind": "none"},
        "solver": {
            "duration": duration,
            "dt": dt,
            "dt_safety": dt_safety,
            "stop_on_collapse": stop_on_collapse,
        },
        "output": {"every": every},
    }


def contact_attrs(contact, **area):
    """Dataset attrs naming the contact law of a validation: the point mapping, or the area law's
    k_n, c_n."""
    if contact is None:
        return {"contact_model": "area", **area}
    return {"contact_model": contact["model"], **{k: v for k, v in contact.items() if k != "model"}}


def first_crossing_time(time, theta):
    """Time [s] of the first sign change of theta, linearly interpolated; NaN if none."""
    s = np.sign(theta)
    idx = np.flatnonzero(s[1:] * s[0] <= 0)
    if len(idx) == 0:
        return float("nan")
    i = idx[0]
    return float(time[i] + (0.0 - theta[i]) / (theta[i + 1] - theta[i]) * (time[i + 1] - time[i]))
