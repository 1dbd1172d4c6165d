"""Ensemble members: the same scene with a perturbation that changes nothing physical, so that
the chaotic answers of the study (a collapse verdict near its threshold, a search threshold)
come as distributions (issue 44; ../shared/research/ENSEMBLES.md, section 3.1).

Member j = 0 is the scene as configured, bit for bit. The perturbations:

- ``stiffness`` (the default): the contact stiffness k_n times 1 - j 2^-52, j units in its
  last place, so every contact force differs in its last bits and nothing else does (the time
  step is snapped to the output clock and does not move; the tangential stiffness keeps its
  value). It acts at every contact on every step, as a change of the code's rounding does.
- ``tilt``: the same k_n perturbation, and the whole structure (every body that is not driven)
  tilted by 1e-6 rad at t = 0 — counter-clockwise about its lowest left corner for odd j,
  clockwise about its lowest right corner for even j, so that it leans onto a corner and never
  into the base. 1e-6 rad is 6 um at a 6 m capital: physically nothing, but 1e10 x rounding, so
  it shows whether the rounding band is complete (ENSEMBLES.md section 3.1).
- ``geometry``: the same k_n perturbation, and the whole scene (every vertex, the base's
  included) scaled by 1 + j 2^-52 about the origin, so that every coordinate, width and
  height differs in its last bits too. A change of the code's geometric arithmetic (how a
  normal or a vertex is computed) moves those bits, which k_n alone never does: a 1-ulp
  widening of every body is rejected against a stiffness-only baseline (docs/notebook.md,
  2026-11-29), so a baseline that judges such changes has to span them.

The time step and the record scale are never perturbed: the first biases results (truncation
error), the second is the axis being measured.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from stonedem.engine.scene import scaled_bodies
from stonedem.errors import InputError
from stonedem.io.spec import Field

RELATIVE_STEP = 2.0**-52  # member j lowers k_n by j x this, relative
TILT = 1.0e-6  # [rad] the tilt of the "tilt" perturbation
PERTURBATIONS = ("stiffness", "tilt", "geometry")
MAX_MEMBERS = 1000  # j < 1000: k_n moves by < 2.3e-13 relative, still far below any physics

MEMBER = Field(
    "member",
    "integer",
    range=f"[0, {MAX_MEMBERS - 1}]",
    hint=f"give 0 ... {MAX_MEMBERS - 1} (stonedem.study.members.MAX_MEMBERS)",
    doc="the member index j",
)
PERTURBATION = Field(
    "perturbation",
    "choice",
    default=PERTURBATIONS[0],
    choices=PERTURBATIONS,
    doc="what member j changes besides k_n (stonedem.study.members)",
)


# what each perturbation's members change, in words: (for an ensemble file's title, what its
# perturbation_rule adds to the k_n change)
WORDS = {
    "stiffness": ("k_n changed", ""),
    "tilt": ("k_n changed and the structure tilted 1e-6 rad", ", structure tilted by 1e-6 rad"),
    "geometry": ("k_n and every coordinate changed", ", every vertex times 1 + j 2^-52"),
}


def perturbation_rule(perturbation: str) -> str:
    """What member j of ``perturbation`` changes, in words (an ensemble file's attribute)."""
    return (
        "member j: contact stiffness k_n times 1 - j 2^-52"
        + WORDS[check_perturbation(perturbation)][1]
    )


def perturbation_summary(perturbation: str) -> str:
    """What the members of ``perturbation`` change, in a few words (an ensemble file's title)."""
    return WORDS[check_perturbation(perturbation)][0]


def stiffness_factor(j: int) -> float:
    """The factor member j applies to k_n: 1 - j 2^-52 (exact in binary64 for j < 2^52)."""
    return 1.0 - j * RELATIVE_STEP


def check_member(j, field: str = "member") -> int:
    """A member index 0 <= j < MAX_MEMBERS, or an InputError naming ``field``."""
    return MEMBER.check(j, field)


def check_perturbation(kind, field: str = "ensemble.perturbation") -> str:
    """One of PERTURBATIONS, or an InputError naming ``field``."""
    return PERTURBATION.check(kind, field)


def member_scene(scene, j: int, perturbation: str = "stiffness", field: str = ""):
    """The Scene of member ``j``: ``scene`` itself for j = 0, else its k_n times
    stiffness_factor(j) and, for ``tilt``, the structure tilted by TILT, for ``geometry``,
    every vertex scaled by scale_factor(j) (module docstring). ``field`` names the
    perturbation in a refusal (default ``ensemble.perturbation``)."""
    j = check_member(j)
    check_perturbation(perturbation)
    if j == 0:
        return scene
    contact = scene.contact.replace(k_n=scene.contact.k_n * stiffness_factor(j))
    scene = dataclasses.replace(scene, contact=contact)
    if perturbation == "tilt":
        scene = dataclasses.replace(
            scene, bodies=tilted_bodies(scene.bodies, TILT if j % 2 else -TILT, field)
        )
    elif perturbation == "geometry":
        scene = dataclasses.replace(scene, bodies=scaled_bodies(scene.bodies, scale_factor(j)))
    return scene


def scale_factor(j: int) -> float:
    """The factor member j of ``geometry`` applies to every coordinate: 1 + j 2^-52."""
    return 1.0 + j * RELATIVE_STEP


def tilted_bodies(bodies, angle: float, field: str = "") -> tuple:
    """Every body that is not driven, rotated rigidly by ``angle`` [rad] (counter-clockwise >
    0) about the free bodies' lowest left corner (angle > 0) or lowest right corner (< 0);
    ``field`` names the perturbation in a refusal (default ``ensemble.perturbation``)."""
    free = [b for b in bodies if not b.driven]
    if any(b.tilt_angle != 0.0 for b in free):
        raise InputError(
            field or "ensemble.perturbation",
            "a tilt member of a scene whose bodies are tilted already",
            "use perturbation: stiffness",
        )
    if not free:
        return tuple(bodies)
    vertices = np.concatenate([b.vertices for b in free])
    low = vertices[:, 1] <= vertices[:, 1].min() + 1e-9 * max(1.0, float(np.ptp(vertices[:, 1])))
    corners = vertices[low]
    pivot = corners[np.argmin(corners[:, 0])] if angle > 0 else corners[np.argmax(corners[:, 0])]
    return tuple(
        b if b.driven else dataclasses.replace(b, tilt_angle=angle, tilt_pivot=pivot.copy())
        for b in bodies
    )
