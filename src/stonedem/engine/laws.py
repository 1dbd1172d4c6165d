"""Contact laws: one row each, read by every consumer (scene parsing, packing, the time step,
dataset attributes and the benchmarks).

A new law is its kernel (``stonedem/kernels/<law>.py``), its branch in the contact-law
dispatch of :func:`stonedem.kernels.step.run` and its row here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from stonedem.kernels import step


@dataclass(frozen=True)
class Law:
    """What the Python side knows of one contact law."""

    code: int  # the kernel's CONTACT_* (stonedem.kernels.step)
    defaults: dict  # k_n [N m-2] and the law's own keys, with their defaults
    dt_safety: float  # the automatic share of the stability limit
    arm2: float  # rotational stiffness of a face contact of length l about its middle: k l^3 x arm2
    frames: tuple  # contact frame rules a scene may name; the first is the default
    frame: str | None  # the frame it always uses (None: the scene's choice)
    describe: str  # the dataset's contact_law attribute
    damping_key: str  # the key of the kernel's damping argument: c_n [N s m-1] or zeta [1]
    pair_dashpot: (
        Callable  # (ContactLaw, face length [m], body mass [kg]) -> normal dashpot [N s m-1]
    )
    hint: str  # how to choose it, for error messages

    def kernel_damping(self, law) -> float:
        """The kernel's damping argument of a scene's ContactLaw."""
        return getattr(law, self.damping_key)

    def mapping(self, name: str, k_n: float, damping: float, **more) -> dict:
        """A scene's ``contact:`` mapping of this law (benchmarks and validations build them)."""
        return {"model": name, "k_n": k_n, self.damping_key: damping, **more}

    @property
    def own_keys(self) -> tuple:
        """Keys of the scene's contact mapping only this law reads."""
        return tuple(k for k in self.defaults if k != "k_n")


DEFAULT_LAW = "point"
LAWS: dict[str, Law] = {
    # thesis Eq. 3.4-3.6: a Winkler layer over the overlap polygon, c_n a dashpot [N s m-1]
    "area": Law(
        code=step.CONTACT_AREA,
        defaults={"k_n": 1.0e8, "c_n": 1.0e3},
        dt_safety=0.25,
        arm2=1.0 / 12.0,
        frames=("boundary", "thesis"),
        frame=None,
        describe="overlap area, thesis Eq. 3.4-3.6",
        damping_key="c_n",
        pair_dashpot=lambda law, length, mass: law.c_n,
        hint="area (thesis overlap area)",
    ),
    # the contact face's two end vertices, each 2 zeta sqrt(K m) with K = k_n l / 2; the frame
    # is its two faces' ("boundary" is what files written before that recorded for it).
    # dt_safety 1: its thresholds and impacts do not move from 0.25 to 1.0 (ramp 6 x 1 m, 1-8
    # drums: 2.5205 -> 2.520 m/s2) and its stable step is 1.4-2.9x the bound; at 1.0 with k_n
    # 1e11 a case costs 0.8x the area law's at 1e10 and 0.25. An auto step that drifts or
    # diverges is halved (stonedem.engine.run).
    "point": Law(
        code=step.CONTACT_POINT,
        defaults={"k_n": 1.0e11, "damping": 0.05, "impact": "plastic"},
        dt_safety=1.0,
        arm2=0.25,
        frames=("faces", "boundary"),
        frame="faces",
        describe="point contacts at the contact face's end vertices, k_n per unit contact length",
        damping_key="damping",
        pair_dashpot=lambda law, length, mass: (
            4.0 * law.damping * math.sqrt(0.5 * law.k_n * length * mass)
        ),
        hint="point (vertex contacts, default)",
    ),
}
