"""Contact laws: one row each, read by every consumer (scene parsing, packing, the time step,
dataset attributes and the benchmarks).

A new law is three files: its kernel (``stonedem/kernels/<law>.py``), its branch in
:mod:`stonedem.kernels.step` (its force call in ``run_under_law`` and a ``run_<law>`` loop
compiled with it alone) and its row here, which declares its own keys and names that loop.
Every other consumer reads the row (tests/test_registries.py adds a toy law with a key of its
own).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Callable

from stonedem.io.spec import Derived, Field, Spec
from stonedem.kernels import step

# above the fields' ranges a value is taken for a units mistake
SI_HINT = "give SI units (k_n in N/m2 per m of contact, c_n in N s/m, damping as a fraction)"


def k_n_field(default: float, doc: str) -> Field:
    """The normal stiffness every law reads, with the law's own default."""
    return Field("k_n", "number", "N m-2", "(0, 1e16]", default, SI_HINT, doc=doc)


# what every law reads after its own fields (thesis Eq. 3.5-3.6)
K_T = Field(
    "k_t",
    "number",
    "N m-1",
    "(0, 1e18]",
    Derived("k_n x 1 m", lambda v: v["k_n"] * 1.0),  # a 1 m long face contact's
    SI_HINT,
    doc="tangential stiffness per contact",
)


def c_t_field(default) -> Field:
    return Field(
        "c_t", "number", "N s m-1", "[0, 1e16]", default, SI_HINT, doc="tangential dashpot"
    )


@dataclass(frozen=True)
class Law:
    """What the Python side knows of one contact law: its own keys as kit fields, in the order
    of the kernel's params array (:class:`stonedem.kernels.step.Law`), and how to use them."""

    code: int  # the kernel's CONTACT_* (stonedem.kernels.step)
    k_n: float  # the default normal stiffness [N m-2]
    own: tuple  # the law's own Fields (stonedem.io.spec)
    kernel_params: Callable  # checked values -> the kernel's params, in order
    dt_safety: float  # the automatic share of the stability limit
    arm2: float  # rotational stiffness of a face contact of length l about its middle: k l^3 x arm2
    frames: tuple  # contact frame rules a scene may name; the first is the default
    frame: str | None  # the frame it always uses (None: the scene's choice)
    describe: str  # the dataset's contact_law attribute
    damping_key: str  # the key of its damping: c_n [N s m-1] or zeta [1]
    # (ContactLaw, face length [m], body mass [kg]) -> normal dashpot [N s m-1]
    pair_dashpot: Callable
    loop: Callable  # the general loop compiled with this law alone (stonedem.kernels.step.run_*)
    hint: str  # how to choose it, for error messages
    c_t: object = 0.0  # the default tangential dashpot (a value or a Derived)

    @cached_property
    def spec(self) -> Spec:
        """The keys of a scene's ``contact:`` under this law, checked by :mod:`stonedem.io.spec`."""
        frame_hint = (
            f"the {self.frame} frame is this law's own; drop contact.frame"
            if self.frame
            else "choose the contact frame rule"
        )
        return Spec(
            (
                Field("model", "text", default=None, doc=f"the contact law: {self.hint}"),
                k_n_field(self.k_n, "normal stiffness"),
                *self.own,
                K_T,
                c_t_field(self.c_t),
                Field(
                    "frame", "choice", choices=self.frames, default=self.frames[0], hint=frame_hint
                ),
            )
        )

    @property
    def defaults(self) -> dict:
        """k_n and the law's own keys, with their defaults."""
        return {"k_n": self.k_n, **{f.key: f.default for f in self.own}}

    @property
    def own_keys(self) -> tuple:
        """Keys of the scene's contact mapping only this law reads."""
        return tuple(f.key for f in self.own)

    def mapping(self, name: str, k_n: float, damping: float, **more) -> dict:
        """A scene's ``contact:`` mapping of this law (benchmarks and validations build them)."""
        return {"model": name, "k_n": k_n, self.damping_key: damping, **more}


@dataclass(frozen=True)
class ContactLaw:
    """A scene's checked contact law: its model (a row of :data:`LAWS`) and its values, k_n,
    the law's own keys, k_t, c_t and the frame it uses; ``law.k_n`` reads a value."""

    model: str
    params: dict

    def __getattr__(self, key):
        params = self.__dict__.get("params")
        if params is None or key not in params:
            raise AttributeError(key)
        return params[key]

    def replace(self, **changes) -> ContactLaw:
        """This law with some values changed (an ensemble member's k_n)."""
        return replace(self, params={**self.params, **changes})


DEFAULT_LAW = "point"
LAWS: dict[str, Law] = {
    # thesis Eq. 3.4-3.6: a Winkler layer over the overlap polygon, c_n a dashpot [N s m-1]
    "area": Law(
        code=step.CONTACT_AREA,
        k_n=1.0e8,
        own=(Field("c_n", "number", "N s m-1", "[0, 1e16]", 1.0e3, SI_HINT, doc="normal dashpot"),),
        kernel_params=lambda v: (v["c_n"],),
        dt_safety=0.25,
        arm2=1.0 / 12.0,
        frames=("boundary", "thesis"),
        frame=None,
        describe="overlap area, thesis Eq. 3.4-3.6",
        damping_key="c_n",
        pair_dashpot=lambda law, length, mass: law.c_n,
        loop=step.run_area,
        hint="area (thesis overlap area)",
        c_t=Derived("c_n", lambda v: v["c_n"]),
    ),
    # the contact face's two end vertices, each 2 zeta sqrt(K m) with K = k_n l / 2; the frame
    # is its two faces' ("boundary" is what files written before that recorded for it).
    # dt_safety 1: its thresholds and impacts do not move from 0.25 to 1.0, and its stable step
    # is above the bound (measured: docs/notebook.md, "Measurements moved out of the code"). An
    # auto step that drifts or diverges is halved (stonedem.engine.run).
    "point": Law(
        code=step.CONTACT_POINT,
        k_n=1.0e11,
        own=(
            Field(
                "damping",
                "number",
                "1",
                "[0, 100]",
                0.05,
                SI_HINT,
                doc="dashpot of each contact point, a fraction of critical",
            ),
            Field(
                "impact",
                "choice",
                choices=("plastic", "none"),
                default="plastic",
                hint="plastic: a landing point stops (Housner); none: dashpots only",
            ),
        ),
        kernel_params=lambda v: (v["damping"], 1.0 if v["impact"] == "plastic" else 0.0),
        dt_safety=1.0,
        arm2=0.25,
        frames=("faces", "boundary"),
        frame="faces",
        describe="point contacts at the contact face's end vertices, k_n per unit contact length",
        damping_key="damping",
        pair_dashpot=lambda law, length, mass: (
            4.0 * law.damping * math.sqrt(0.5 * law.k_n * length * mass)
        ),
        loop=step.run_point,
        hint="point (vertex contacts, default)",
    ),
}


def general_loop(code: int) -> Callable:
    """The compiled general loop of the law whose kernel is ``code`` (a row's CONTACT_*)."""
    return next(row.loop for row in LAWS.values() if row.code == code)
