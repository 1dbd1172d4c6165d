"""Impact loss: the energy ratio per impact of the study's columns under each contact law.

Each column stands on a driven base that does not move. It is released from rest leaning on
its bottom right corner at theta0 = THETA0_RATIO x alpha, alpha being the slenderness angle
of the whole column taken as one rigid body. Every drum (and the capital) is tilted about
that corner, so the stack starts as one block. The engine then integrates free rocking, and
two energy ratios are measured at each of the first N_IMPACTS impacts on the base joint.
Impacts are the sign changes of the mean drum rotation, as in the study's ``rocking``
measure (:func:`stonedem.engine.measures.rocking_bodies`).

- ``rocking_energy_ratio``: Housner's quantity. It is the rocking energy after the impact
  over the energy before, computed from successive peak angles by the exact rigid relation
  (:func:`stonedem.reference.analytic.restitution_from_peaks_exact`) with the column's own alpha.
  For a monolith this is exactly the kinetic energy ratio of Housner's impact (thesis Eq. 5.2).
  For a stack it is the ratio of an equivalent rigid column rocking through the mean drum
  rotation, which is exact only while the stack rocks as one body.
- ``energy_ratio``: the total mechanical energy above rest (kinetic + potential + elastic
  energy in the contacts) just before the next impact over just before this one. "Just
  before" an impact is halfway in time between the previous peak and the sign change. The
  ratio is the share of energy that survives the impact and the half cycle after it:
  1 - (dashpot + friction loss) / energy. A soft contact sends part of the impact's
  energy into vibrations of the column on its contacts, and a light dashpot takes seconds
  to damp them, so only a ratio over the whole cycle sees that loss. Energy still in
  vibration counts as kept. Starting halfway into the first quarter cycle also leaves out
  the release, where a heavily damped soft contact loses energy while the pivot corner
  first takes the weight. The elastic energy is included because the overlap-area law's
  pivot corner sinks about 1.4 mm into its Winkler layer when the 1 x 6 m column leans at
  theta0 = 0.5 alpha. Kinetic + potential energy alone would count that sinking as a loss
  of 4-5 %.

Housner's ratio of each column taken as one rigid body,
(1 - 2 M b^2 / I_O)^2 (:func:`rigid_column`), is the reference; for a rectangle it is
:func:`stonedem.reference.analytic.housner_restitution`.

The contact laws (:data:`LAWS`):

- ``area_study``: the overlap-area law as the study ran it until the point law became its
  default (:data:`AREA_STUDY`: k_n 1e10, c_n 1e4).
- ``area_undamped``: the same law with c_n = 0 (c_t defaults to c_n, so c_t = 0 too).
- ``point``: the study's contact (config ``defaults.contact``), the point law with its
  scene defaults (:data:`stonedem.engine.laws.LAWS`): zeta 0.05 and Housner's plastic landing.
- ``area_housner``: the area law with the c_n that gives the monolith Housner's ratio
  (:func:`stonedem.validation.cases.calibrate_restitution`, geometric mean of N_IMPACTS impacts).

The columns are the study's 6 x 1 m rectangular columns that run with the study's contact:
every ``kind: column`` structure of the config with taper 1. The tapered columns of
``ramp_taper`` and the small-scale column with its own contact are left out. ``--quick``
runs only the monolith and the 2-drum column, without capitals.

    python -m benchmarks.restitution [--quick] [--out results/bench] [--config
    config/config.yaml]
"""

from __future__ import annotations

import math
import os
import platform
import sys
import time as wallclock
import warnings
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import xarray as xr

from benchmarks.canonical import rocking_measures
from benchmarks.ours import critical_damping
from stonedem.engine.laws import DEFAULT_LAW
from stonedem.engine.laws import LAWS as CONTACT_LAWS
from stonedem.engine.measures import rocking_bodies
from stonedem.engine.scene import Scene, scene_from_dict
from stonedem.engine.simulate import simulate
from stonedem.engine.structures import build_structure
from stonedem.errors import InputError
from stonedem.io.netcdf import code_version, write_dataset
from stonedem.kernels import step
from stonedem.reference import analytic
from stonedem.study.grid import config_cases
from stonedem.validation.cases import calibrate_restitution

ROOT = Path(__file__).resolve().parents[1]
N_IMPACTS = 4
THETA0_RATIO = 0.5  # release at theta0 = THETA0_RATIO x alpha of the whole column
SAMPLE_EVERY = 1e-3  # [s]
# a half cycle whose peak is below this share of theta0 is chatter: rocking has ended
MIN_FRACTION = 0.02
LAWS = ("area_study", "area_undamped", "point", "area_housner")
# the study's contact until issue 12 (the point law is its default since)
AREA_STUDY = {"model": "area", "k_n": 1.0e10, "c_n": 1.0e4}
LAW_TITLES = {
    "area_study": "overlap-area law, k_n 1e10 and c_n 1e4 (the study's contact until issue 12)",
    "area_undamped": "overlap-area law, k_n 1e10, c_n = c_t = 0",
    "point": "point law, the study's contact (config defaults.contact; zeta 0.05, Housner's "
    "plastic landing)",
    "area_housner": "overlap-area law, k_n 1e10, c_n calibrated to Housner's ratio on the monolith",
}


@dataclass(frozen=True)
class Column:
    """One of the study's standalone columns."""

    n_drums: int
    height: float  # shaft [m]
    width: float  # [m]
    density: float  # [kg m-3]
    capital: tuple | None  # (height, width) [m] or None
    friction: float  # [1]
    studies: tuple  # the config studies that run it

    @property
    def label(self) -> str:
        drums = "monolith" if self.n_drums == 1 else f"{self.n_drums} drums"
        return drums + (" + capital" if self.capital else "")

    def structure(self) -> dict:
        spec = {
            "kind": "column",
            "n_drums": self.n_drums,
            "height": self.height,
            "width": self.width,
            "density": self.density,
        }
        if self.capital:
            spec["capital"] = {"height": self.capital[0], "width": self.capital[1]}
        return spec


def study_contact(config: dict) -> dict:
    """The study's ``contact:`` mapping (config ``defaults.contact``), its model made explicit."""
    contact = dict((config.get("defaults") or {}).get("contact") or {})
    model = contact.pop("model", DEFAULT_LAW)

    def number(value):
        # PyYAML (YAML 1.1) reads 1.0e10 as a number only with a sign after the e: accept strings
        try:
            return float(value)
        except (TypeError, ValueError):
            return value

    return {"model": model, **{k: number(v) for k, v in contact.items()}}


def study_columns(config: dict) -> list[Column]:
    """The config's standalone rectangular columns that use the study's contact, by drum count.

    A column is taken when a study has ``structure.kind: column`` with taper 1 and no
    ``contact:`` of its own. Its friction is the study-level ``friction`` of the first
    study that runs it (0.48 or 0.485). This leaves out the tapered ``ramp_taper`` columns and the
    small-scale column with its own contact.
    """
    columns: dict = {}
    studies = config.get("studies") or {}
    for name, cases in config_cases(config).items():
        if "contact" in studies[name]:
            continue
        for case in cases:
            s = case.scene.get("structure") or {}
            if s.get("kind") != "column" or float(s.get("taper", 1.0)) != 1.0:
                continue
            cap = s.get("capital")
            key = (
                int(s.get("n_drums", 1)),
                float(s.get("height", 6.0)),
                float(s.get("width", 1.0)),
                float(s.get("density", 2000.0)),
                (float(cap.get("height", 0.6)), float(cap.get("width", 1.4))) if cap else None,
            )
            # the study's own friction, not a swept value of one case (harmonic_frequency sweeps
            # 0.3-0.7)
            mu = float(
                studies[name].get("friction", (config.get("defaults") or {}).get("friction", 0.5))
            )
            friction, names = columns.get(key, (mu, ()))
            columns[key] = (friction, names if name in names else names + (name,))
    out = [Column(*key, friction=f, studies=names) for key, (f, names) in columns.items()]
    return sorted(out, key=lambda c: (c.capital is not None, c.height, c.width, c.n_drums))


def quick_columns(columns: list[Column]) -> list[Column]:
    """--quick: the monolith and the column of fewest drums, without capitals. More drums
    are slower, and the calibrated area law's heavy dashpot shortens the stable step: the
    8-drum column takes 14 s under it."""
    plain = sorted((c for c in columns if c.capital is None), key=lambda c: c.n_drums)
    return plain[:1] + [c for c in plain if c.n_drums > 1][:1]


# --- the column as one rigid body ----------------------------------------------------------


@dataclass(frozen=True)
class RigidColumn:
    """Rocking constants of a column taken as one rigid body on its bottom right corner."""

    mass: float  # M [kg]
    b: float  # horizontal distance from the centroid to the corner [m]
    h: float  # height of the centroid above the base [m]
    inertia_corner: float  # I_O about the corner [kg m2]
    alpha: float  # atan(b / h) [rad]
    p: float  # sqrt(M g R / I_O) [rad s-1]
    housner: float  # Housner's energy ratio (1 - 2 M b^2 / I_O)^2 [1]
    pivot: tuple  # the corner (x, y) [m]


def rigid_column(bodies: list[dict], gravity: float = analytic.G) -> RigidColumn:
    """Housner's constants of the free bodies of a column built by
    :mod:`stonedem.engine.structures`.

    Angular momentum about the landing corner is conserved at the impact. Before it the
    body turns at omega about the other corner O, so the momentum is (I_G + m (h^2 - b^2))
    omega, and after it I_O omega'. The kinetic energy ratio is therefore
    (1 - 2 m b^2 / I_O)^2, which for a rectangle (I_O = 4/3 m R^2, b = R sin alpha) is
    Housner's (1 - 3/2 sin^2 alpha)^2.
    """
    scene = scene_from_dict({"bodies": bodies, "solver": {"duration": 1.0}})
    free = [b for b in scene.bodies if not b.driven]
    bottom = min(free, key=lambda b: b.vertices[:, 1].min())
    low = bottom.vertices[np.isclose(bottom.vertices[:, 1], bottom.vertices[:, 1].min())]
    pivot = low[np.argmax(low[:, 0])]
    mass = sum(b.mass for b in free)
    centroid = sum(b.mass * b.centroid for b in free) / mass
    inertia = sum(b.inertia + b.mass * float(np.sum((b.centroid - pivot) ** 2)) for b in free)
    b, h = float(pivot[0] - centroid[0]), float(centroid[1] - pivot[1])
    radius = math.hypot(b, h)
    return RigidColumn(
        mass=mass,
        b=b,
        h=h,
        inertia_corner=inertia,
        alpha=math.atan2(b, h),
        p=math.sqrt(mass * gravity * radius / inertia),
        housner=(1.0 - 2.0 * mass * b * b / inertia) ** 2,
        pivot=(float(pivot[0]), float(pivot[1])),
    )


def quarter_period(rigid: RigidColumn, theta0: float) -> float:
    """Exact rigid quarter period [s] of free rocking from theta0. It is the period of the
    rectangle with the same alpha, scaled by that rectangle's p over the column's p."""
    w, h = 2.0 * rigid.b, 2.0 * rigid.h
    p_rect = analytic.rectangle_rocking_properties(w, h).p
    return float(analytic.rocking_period_exact(w, h, theta0)) / 4.0 * p_rect / rigid.p


# --- one run ---------------------------------------------------------------------------------


def rocking_scene(
    column: Column, contact: dict, n_impacts: int = N_IMPACTS, sample_every: float = SAMPLE_EVERY
) -> tuple[Scene, RigidColumn, float]:
    """(scene, rigid constants, theta0) of the column released from theta0 on its right corner.

    The run lasts 2 n_impacts + 2 rigid quarter periods at theta0. A lossless column needs
    2 n_impacts + 1 of them to finish the half cycle after impact n_impacts, and each loss
    shortens the later ones.
    """
    bodies = build_structure(column.structure())
    rigid = rigid_column(bodies)
    theta0 = THETA0_RATIO * rigid.alpha
    for body in bodies:
        if not body.get("driven"):
            body["tilt"] = {
                "angle": -theta0,
                "about": list(rigid.pivot),
            }  # clockwise: leaning right
    spec = {
        "name": f"free rocking, {column.label}",
        "bodies": bodies,
        "friction": column.friction,
        "contact": dict(contact),
        "excitation": {"kind": "none"},
        "solver": {
            "duration": (2 * n_impacts + 2) * quarter_period(rigid, theta0),
            "stop_on_collapse": False,
        },
        "output": {"every": sample_every},
    }
    return scene_from_dict(spec), rigid, theta0


@dataclass
class ImpactLoss:
    """Energy ratios of the first impacts of one free-rocking run (NaN: rocking had stopped)."""

    impact_time: np.ndarray  # (n,) [s]
    peaks: np.ndarray  # (n + 1,) |mean drum rotation| at release and after each impact [rad]
    rocking_energy_ratio: np.ndarray  # (n,) [1]
    energy_before: np.ndarray  # (n,) just before the impact [J]
    energy_next: np.ndarray  # (n,) just before the next impact [J]
    energy_ratio: np.ndarray  # (n,) [1]
    wall_seconds: float
    dt: float
    dt_limit: float


def mechanical_energy(scene: Scene, energy: np.ndarray) -> np.ndarray:
    """Kinetic + potential + elastic energy above the column at rest (untilted, no overlap) [J]."""
    rest = scene.gravity * sum(b.mass * b.centroid[1] for b in scene.bodies if not b.driven)
    return (
        energy[:, step.ENERGY_KINETIC]
        + energy[:, step.ENERGY_POTENTIAL]
        - rest
        + energy[:, step.ENERGY_ELASTIC]
    )


def impact_loss(
    time,
    theta,
    total,
    rigid: RigidColumn,
    n_impacts: int = N_IMPACTS,
    min_fraction: float = MIN_FRACTION,
    wall_seconds=math.nan,
    dt=math.nan,
    dt_limit=math.nan,
) -> ImpactLoss:
    """Energy ratios of the first ``n_impacts`` impacts from a rotation history (see the module
    doc).

    theta: the mean drum rotation, positive leaning right [rad]; total: the mechanical
    energy above rest [J] (:func:`mechanical_energy`). The impact times and peaks come from
    :func:`benchmarks.canonical.rocking_measures` (sign changes, parabola-refined peaks).
    From the first half cycle whose peak is below ``min_fraction`` x theta0, everything is
    NaN, and so is whatever the run ended before (the energy ratio of impact n needs
    impact n + 1).
    """
    time, theta, total = (np.asarray(a, dtype=float) for a in (time, theta, total))
    times, after = rocking_measures(time, theta, n_impacts)
    peaks = np.concatenate([[abs(theta[0])], after])
    s = np.sign(theta)
    cuts = np.flatnonzero(s[1:] * s[:-1] < 0) + 1  # first sample of each half cycle after an impact
    ends = np.concatenate([[0], cuts, [len(theta)]])
    extreme = [int(lo + np.argmax(np.abs(theta[lo:hi]))) for lo, hi in zip(ends[:-1], ends[1:])]
    # just before impact k + 1: halfway in time between the peak of half cycle k and the impact
    before = np.full(n_impacts + 1, np.nan)
    for k in range(min(n_impacts + 1, len(cuts))):
        before[k] = total[(extreme[k] + cuts[k]) // 2]
    stopped = np.flatnonzero(~(peaks >= min_fraction * peaks[0]))
    if len(stopped):
        first = stopped[0]  # the half cycle after impact `first` is chatter or missing
        peaks[first:] = np.nan
        times[first - 1 :] = np.nan
        before[first:] = np.nan
    rocking = analytic.restitution_from_peaks_exact(2.0 * rigid.b, 2.0 * rigid.h, peaks)
    return ImpactLoss(
        impact_time=times,
        peaks=peaks,
        rocking_energy_ratio=rocking,
        energy_before=before[:-1],
        energy_next=before[1:],
        energy_ratio=before[1:] / before[:-1],
        wall_seconds=wall_seconds,
        dt=dt,
        dt_limit=dt_limit,
    )


def free_rocking_loss(
    column: Column, contact: dict, n_impacts: int = N_IMPACTS
) -> tuple[ImpactLoss, RigidColumn]:
    """Run the column's free rocking with ``contact`` and measure its first impacts."""
    scene, rigid, _ = rocking_scene(column, contact, n_impacts)
    res = simulate(scene)
    drums = rocking_bodies(scene)
    theta = -res.theta[:, drums].mean(
        axis=1
    )  # the engine turns counter-clockwise: leaning right < 0
    loss = impact_loss(
        res.time,
        theta,
        mechanical_energy(scene, res.energy),
        rigid,
        n_impacts,
        wall_seconds=res.wall_seconds,
        dt=res.dt,
        dt_limit=res.dt_limit,
    )
    return loss, rigid


# --- the laws -----------------------------------------------------------------------------------


def housner_c_n(column: Column, k_n: float, n_impacts: int = N_IMPACTS) -> float:
    """c_n [N s m-1] of the area law at k_n that gives the monolith ``column`` Housner's ratio
    per impact (geometric mean over n_impacts;
    :func:`stonedem.validation.cases.calibrate_restitution`)."""
    if column.n_drums != 1 or column.capital:
        raise ValueError("the area law is calibrated on a monolith without a capital")
    mass = column.density * column.width * column.height  # unit depth
    target = analytic.housner_restitution(column.width, column.height)
    theta0 = THETA0_RATIO * math.atan2(column.width, column.height)
    return calibrate_restitution(target, column.width, column.height, mass, theta0, n_impacts, k_n)


def law_contacts(config: dict, monolith: Column, laws=LAWS, n_impacts: int = N_IMPACTS) -> dict:
    """{law: contact mapping} of the named laws (:data:`LAWS`)."""
    study = study_contact(config)
    if study["model"] != "point":
        raise ValueError(
            f"the study's contact is {study['model']!r}; this benchmark runs it as the point law"
        )
    contacts = {}
    for law in laws:
        if law == "area_study":
            contacts[law] = dict(AREA_STUDY)
        elif law == "area_undamped":
            contacts[law] = {**AREA_STUDY, "c_n": 0.0}
        elif law == "point":
            contacts[law] = {**CONTACT_LAWS["point"].defaults, **study}
        elif law == "area_housner":
            contacts[law] = {
                **AREA_STUDY,
                "c_n": housner_c_n(monolith, AREA_STUDY["k_n"], n_impacts),
            }
        else:
            raise ValueError(f"unknown law {law!r}; use one of {', '.join(LAWS)}")
    return contacts


# --- the table ----------------------------------------------------------------------------------


def _attrs(units, long_name):
    return {"units": units, "long_name": long_name}


def restitution_table(
    columns: list[Column], contacts: dict, n_impacts: int = N_IMPACTS, progress: bool = True
) -> xr.Dataset:
    """Dataset of the energy ratio per impact of every column under every contact law."""
    start = wallclock.perf_counter()
    laws = list(contacts)
    shape = (len(laws), len(columns))
    fields = ("impact_time", "rocking_energy_ratio", "energy_before", "energy_next", "energy_ratio")
    per_impact = {f: np.full(shape + (n_impacts,), np.nan) for f in fields}
    peaks = np.full(shape + (n_impacts + 1,), np.nan)
    wall, dt, dt_limit = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
    rigid = {}
    for j, column in enumerate(columns):
        for i, law in enumerate(laws):
            loss, rigid[j] = free_rocking_loss(column, contacts[law], n_impacts)
            for f in fields:
                per_impact[f][i, j] = getattr(loss, f)
            peaks[i, j] = loss.peaks
            wall[i, j], dt[i, j], dt_limit[i, j] = loss.wall_seconds, loss.dt, loss.dt_limit
            if progress:
                print(
                    f"  {column.label:20s} {law:14s} energy ratio "
                    + " ".join(f"{v:.4f}" for v in loss.energy_ratio)
                    + f"  ({loss.wall_seconds:.2f} s)",
                    file=sys.stderr,
                    flush=True,
                )
    monolith = next((c for c in columns if c.n_drums == 1 and not c.capital), columns[0])
    ref_mass = monolith.density * monolith.width * monolith.height
    critical = critical_damping(contacts[laws[0]]["k_n"], monolith.width, ref_mass)

    def law_value(law, key):
        return float(contacts[law].get(key, math.nan))

    c_n = np.array(
        [law_value(law, "c_n") if contacts[law]["model"] == "area" else math.nan for law in laws]
    )
    k_n = np.array([law_value(law, "k_n") for law in laws])
    crit = np.array([critical_damping(k, monolith.width, ref_mass) for k in k_n])
    with warnings.catch_warnings(), np.errstate(invalid="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)  # a run with no impact: NaN mean
        mean = {
            f: np.exp(np.nanmean(np.log(per_impact[f]), axis=-1))
            for f in ("energy_ratio", "rocking_energy_ratio")
        }
    housner = np.array([rigid[j].housner for j in range(len(columns))])
    pi = ("law", "structure", "impact")
    ls = ("law", "structure")
    ds = xr.Dataset(
        {
            "energy_ratio": (
                pi,
                per_impact["energy_ratio"],
                _attrs(
                    "1",
                    "total mechanical energy (kinetic + potential + elastic, above rest) just "
                    "before the next "
                    "impact / just before this one",
                ),
            ),
            "rocking_energy_ratio": (
                pi,
                per_impact["rocking_energy_ratio"],
                _attrs(
                    "1",
                    "rocking energy after / before the impact from successive peaks of the "
                    "mean drum rotation, "
                    "exact rigid relation with the column's alpha (Housner's ratio, thesis Eq. "
                    "5.2)",
                ),
            ),
            "energy_before_impact": (
                pi,
                per_impact["energy_before"],
                _attrs(
                    "J",
                    "total mechanical energy above rest just before the impact (halfway in "
                    "time from the "
                    "previous peak), per metre of depth",
                ),
            ),
            "energy_before_next_impact": (
                pi,
                per_impact["energy_next"],
                _attrs(
                    "J",
                    "total mechanical energy above rest just before the next impact, per metre "
                    "of depth",
                ),
            ),
            "impact_time": (
                pi,
                per_impact["impact_time"],
                _attrs("s", "time of the impact: sign change of the mean drum rotation"),
            ),
            "peak_rotation": (
                ("law", "structure", "peak"),
                peaks,
                _attrs("rad", "peak |mean drum rotation| of the half cycle (0: release)"),
            ),
            "mean_energy_ratio": (
                ls,
                mean["energy_ratio"],
                _attrs("1", "geometric mean over the impacts of energy_ratio"),
            ),
            "mean_rocking_energy_ratio": (
                ls,
                mean["rocking_energy_ratio"],
                _attrs("1", "geometric mean over the impacts of rocking_energy_ratio"),
            ),
            "housner_energy_ratio": (
                "structure",
                housner,
                _attrs(
                    "1",
                    "Housner's energy ratio of the column as one rigid body, (1 - 2 M b^2 / I_O)^2",
                ),
            ),
            "wall_seconds": (ls, wall, _attrs("s", "wall time of the compiled loop, one run")),
            "dt": (ls, dt, _attrs("s", "time step (automatic: dt_safety x stability limit)")),
            "dt_limit": (
                ls,
                dt_limit,
                _attrs(
                    "s", "stability limit of the run (stonedem.engine.simulate.stability_limit)"
                ),
            ),
        },
        coords={
            "law": ("law", laws, _attrs("1", "contact law (benchmarks.restitution.LAWS)")),
            "contact_model": (
                "law",
                [contacts[law]["model"] for law in laws],
                _attrs("1", "contact.model"),
            ),
            "k_n": (
                "law",
                k_n,
                _attrs(
                    "N m-2",
                    "normal contact stiffness contact.k_n (area: per unit overlap "
                    "area; point: per unit contact length)",
                ),
            ),
            "c_n": (
                "law",
                c_n,
                _attrs(
                    "N s m-1",
                    "normal dashpot contact.c_n of the area law (c_t = c_n; NaN: point law)",
                ),
            ),
            "c_n_over_critical": (
                "law",
                c_n / crit,
                _attrs(
                    "1", "c_n / 2 sqrt(k_n width m) of the monolith on its base (NaN: point law)"
                ),
            ),
            "zeta": (
                "law",
                [
                    law_value(law, "damping") if contacts[law]["model"] == "point" else math.nan
                    for law in laws
                ],
                _attrs("1", "damping ratio of each contact point, point law (NaN: area law)"),
            ),
            "plastic_impact": (
                "law",
                np.array(
                    [int(contacts[law].get("impact") == "plastic") for law in laws], dtype=np.int8
                ),
                _attrs("1", "1: a landing point stops plastically (point law, impact: plastic)"),
            ),
            "structure": ("structure", [c.label for c in columns], _attrs("1", "column")),
            "n_drums": (
                "structure",
                np.array([c.n_drums for c in columns], dtype=np.int32),
                _attrs("1", "number of drums of the shaft"),
            ),
            "height": ("structure", [c.height for c in columns], _attrs("m", "shaft height")),
            "width": ("structure", [c.width for c in columns], _attrs("m", "shaft width")),
            "capital_height": (
                "structure",
                [c.capital[0] if c.capital else 0.0 for c in columns],
                _attrs("m", "capital height (0: no capital)"),
            ),
            "capital_width": (
                "structure",
                [c.capital[1] if c.capital else 0.0 for c in columns],
                _attrs("m", "capital width (0: no capital)"),
            ),
            "friction": (
                "structure",
                [c.friction for c in columns],
                _attrs("1", "friction coefficient mu of the study"),
            ),
            "alpha": (
                "structure",
                [rigid[j].alpha for j in range(len(columns))],
                _attrs("rad", "slenderness atan(b / h_G) of the column as one rigid body"),
            ),
            "theta0": (
                "structure",
                [THETA0_RATIO * rigid[j].alpha for j in range(len(columns))],
                _attrs("rad", "initial tilt (released from rest)"),
            ),
            "mass": (
                "structure",
                [rigid[j].mass for j in range(len(columns))],
                _attrs("kg", "column mass per metre of depth"),
            ),
            "impact": (
                "impact",
                np.arange(1, n_impacts + 1),
                _attrs("1", "impact number on the base joint"),
            ),
            "peak": (
                "peak",
                np.arange(n_impacts + 1),
                _attrs("1", "half cycle (0: release, n: after impact n)"),
            ),
        },
        attrs={
            "title": "impact loss: energy ratio per impact of the study's columns in free rocking",
            "source": code_version(),
            "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')} "
            "benchmarks.restitution",
            "platform": f"python {platform.python_version()}, {os.cpu_count()} cores, "
            f"{sys.platform}",
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
            "n_impacts": n_impacts,
            "theta0_over_alpha": THETA0_RATIO,
            "min_fraction": MIN_FRACTION,
            "output_interval": SAMPLE_EVERY,
            "output_interval_units": "s",
            "dt_mode": "auto",
            "dt_safety": ", ".join(f"{law} {row.dt_safety:g}" for law, row in CONTACT_LAWS.items())
            + " (the engine's auto, per law)",
            "integrator": "central difference (leapfrog form)",
            "excitation": "none (free rocking on a fixed base)",
            "depth": 1.0,
            "gravity": analytic.G,
            "housner_energy_ratio_monolith": analytic.housner_restitution(
                monolith.width, monolith.height
            ),
            "monolith": f"{monolith.width:g} x {monolith.height:g} m, density "
            f"{monolith.density:g} kg m-3",
            "critical_damping_monolith": critical,
            "critical_damping_monolith_units": "N s m-1",
            "total_wall_seconds": wallclock.perf_counter() - start,
            **{f"law_{law}": LAW_TITLES.get(law, law) for law in laws},
            "studies": "; ".join(f"{c.label}: {', '.join(c.studies)}" for c in columns),
        },
    )
    return ds


def table(ds: xr.Dataset) -> str:
    """Readable table: per column and law, Housner's ratio, the rocking and the total energy
    ratios."""
    n = ds.sizes["impact"]
    width = 7 * n
    lines = [
        f"{'':33s} {'':7s}  {'rocking energy ratio':^{width}s}  {'total energy ratio':^{width}s}",
        f"{'column':18s} {'law':14s} {'Housner':>7s}  "
        + "".join(f"{k:>7d}" for k in ds.impact.values)
        + "  "
        + "".join(f"{k:>7d}" for k in ds.impact.values),
    ]
    for s in ds.structure.values:
        for law in ds.law.values:
            sub = ds.sel(structure=s, law=law)
            lines.append(
                f"{s:18s} {law:14s} {float(sub.housner_energy_ratio):7.4f}  "
                + "".join(f"{v:7.4f}" for v in sub.rocking_energy_ratio.values)
                + "  "
                + "".join(f"{v:7.4f}" for v in sub.energy_ratio.values)
            )
    notes = []
    for law in ds.law.values:
        if ds.contact_model.sel(law=law) == "area":
            notes.append(
                f"{law}: c_n = {float(ds.c_n.sel(law=law)):.4g} N s/m = "
                f"{float(ds.c_n_over_critical.sel(law=law)):.3g} x critical"
            )
    return "\n".join(lines + (["(" + "; ".join(notes) + ")"] if notes else []))


def build_parser():
    from benchmarks import options

    parser = options.parser("python -m benchmarks.restitution", __doc__)
    parser.add_argument(
        "--out",
        type=options.path_arg,
        default=str(ROOT / "results" / "bench"),
        help="directory (writes restitution.nc) or a .nc path",
    )
    parser.add_argument(
        "--config",
        type=options.path_arg,
        nargs="+",
        default=[ROOT / "config" / "config.yaml"],
        help="config file(s), merged in order like snakemake --configfile",
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="the monolith and the 2-drum column only, no capitals (CI)",
    )
    parser.add_argument(
        "--laws", nargs="+", default=list(LAWS), choices=LAWS, help="contact laws, each once"
    )
    return parser


def check_args(args):
    """(output path, config, columns, monolith), or an InputError before anything runs."""
    from benchmarks import options

    options.chosen(args.laws, "--laws", LAWS)
    out = Path(args.out)
    if out.suffix.lower() == ".nc":
        path = options.output_file(out, "--out", suffixes=(".nc",), inputs=args.config)
    else:
        path = options.output_folder(out, "--out", files=("restitution.nc",)) / "restitution.nc"
    for config_path in args.config:
        options.input_file(config_path, "--config", "YAML config file")
    config = options.workflow_config(args.config)
    if not isinstance(config.get("studies"), dict) or not config["studies"]:
        raise InputError(
            "--config",
            "no studies: mapping in the config",
            "give the workflow's config file(s), e.g. config/config.yaml",
        )
    model = study_contact(config)["model"]
    if model != "point":
        raise InputError(
            "--config",
            f"the study's contact (defaults.contact.model) is {model!r}",
            "this benchmark runs the study's contact as the point law; give a config whose "
            "model is point",
        )
    try:
        columns = study_columns(config)
    except (AttributeError, KeyError, TypeError, ValueError) as err:
        if isinstance(err, InputError):
            raise
        raise InputError(
            "--config",
            f"the studies cannot be read ({type(err).__name__}: {err})",
            "give the workflow's config file(s), e.g. config/config.yaml",
        ) from None
    if args.quick:
        columns = quick_columns(columns)
    monolith = next((c for c in columns if c.n_drums == 1 and not c.capital), None)
    if monolith is None:
        raise InputError(
            "--config",
            "no study runs a 1-drum column without capital (the monolith)",
            "give the workflow's config file(s), e.g. config/config.yaml",
        )
    return path, config, columns, monolith


def main(argv=None) -> int:
    """Options, output path and config checked first (one line, exit 2); then the table."""
    from benchmarks import options

    args = build_parser().parse_args(argv)

    def command():
        start = wallclock.perf_counter()
        path, config, columns, monolith = check_args(args)
        contacts = law_contacts(config, monolith, args.laws)
        ds = restitution_table(columns, contacts)
        ds.attrs["profile"] = "quick" if args.quick else "full"
        ds.attrs["config"] = ", ".join(str(p) for p in args.config)
        ds.attrs["total_wall_seconds"] = wallclock.perf_counter() - start
        write_dataset(ds, path)
        print(table(ds))
        print(f"wrote {path} in {wallclock.perf_counter() - start:.0f} s")
        return 0

    return options.run(command)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.exit(main())
