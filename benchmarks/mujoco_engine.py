"""The canonical benchmark scenes (:mod:`benchmarks.canonical`) run in MuJoCo.

Model. Each block is a box geom (DEPTH deep, DENSITY) on its own body with a planar joint
set, the usual MuJoCo way of making a 2D model: slide x, slide z, then a hinge through the
centroid. The hinge axis is -y, so its angle is counterclockwise positive seen with x to
the right and z up (a hinge about +y turns clockwise in that view) and qpos is directly the
Trajectory's theta. The slides come first, so they stay aligned with the world axes and
their qpos is the centroid's displacement. The ground is a plane at z = 0 (plane-box
collider: a contact at each corner below the plane); drums touch each other through the
box-box collider, which puts a contact at each corner of the overlap, front and back (the
depth only scales the mass; the joints remove the out-of-plane motion). Contacts are
explicit <pair>s (ground-block, neighbouring drums), because only a pair can give friction
its own reference (solreffriction, below).

Settings, after the MuJoCo documentation (Computation > Soft contact model; Modeling >
Solver parameters; XML reference > option), aiming for stiff, accurate contacts:

* integrator ``implicitfast``: the documentation's recommended default. (Contacts are
  solved by the constraint solver, not the integrator, and there is no joint damping, so
  Euler gives the same numbers; RK4 does not help with discontinuous contact forces.)
* cone ``elliptic``, solver ``Newton``: the exact Coulomb cone (pyramidal only
  approximates it), solved to convergence; ``iterations = 100``, ``tolerance = 1e-10``
  (default 1e-8). ``impratio = 10``: friction ten times harder than the normal direction,
  as the documentation recommends with elliptic cones against the creep of soft friction.
* normal ``solref = (timeconst, 1)``: critically damped, so an impact does not bounce
  (Housner's restitution assumes a perfectly inelastic impact at the new corner), with
  timeconst = 2 dt by default, the shortest the documentation allows (``refsafe`` clamps
  it to >= 2 timestep); sweepable through ``solref_time``.
* ``solreffriction = (0.02, 1)``, MuJoCo's default time constant, for the frictional
  dimensions only. Sharing the short normal timeconst would make the friction reference
  acceleration -2 v_t / timeconst huge while sliding; MuJoCo's convex (non-complementary)
  cone then trades it for normal force and the sliding block lifts off: at dt = 1e-3 the
  pulse block hovered up to 8 mm and rocked by 2e-3 rad. With 0.02 s the lift is 0.1 mm,
  the rocking 2e-5 rad, and Newmark's u_max is still met to 0.015 %.
* ``solimp = (0.99, 0.999, 1e-4, 0.5, 2)``: impedance close to 1 makes the constraint
  nearly hard (regularisation R = (1 - d)/d A), reached within 0.1 mm of penetration.
* ``margin = 0``: a contact exists only at penetration; a positive margin would make the
  corners feel the ground early and shift the impact instants.
* ``noslip_iterations = 0``: the noslip post-pass (a friction-only hard projection) is not
  needed with elliptic cones and impratio 10, and it changes nothing here.

Stepping: ``mujoco.mj_step(model, data, nstep=k)``, one call for all the steps between two
events (a sample, or a change of the base acceleration), the fastest stepping API from
Python. The base acceleration a_g(t) enters as the uniform inertial field
``model.opt.gravity[0] = -a_g`` (exact for rigid bodies on a fixed ground), so x is already
the motion relative to the base; a change takes effect at the step nearest its instant.

Initial state: MuJoCo includes a contact only once it penetrates, so bodies released
exactly touching first fall freely for a step; down a stack that repeats one contact per
step (0.3 mm sink of the top drum at dt = 1e-3). Resting scenes (pulse, column) are
therefore first settled at rest for SETTLE_STEPS steps (set-up, not timed) and restarted
from their equilibrium sink (a few micrometres) with zero velocity. The rocking block
starts exactly on its corner: its jolt is one step of free fall, g dt^2 = 1e-5 m at
dt = 1e-3.
"""

from __future__ import annotations

import math
import time as _time

import mujoco
import numpy as np

from benchmarks.canonical import DENSITY, DEPTH, ROCKING_FRICTION, G, Trajectory

SOLIMP = "0.99 0.999 0.0001 0.5 2"
FRICTION_TIMECONST = 0.02  # [s] solreffriction: MuJoCo's default time constant, see above
SETTLE_STEPS = 200  # steps at rest that bring resting contacts to their equilibrium sink


def _model(blocks, mu, dt, solref_time):
    """Compile a planar scene: blocks = [(width, height, z_centroid)] on a ground plane.

    Contacts are explicit pairs (ground-block and neighbouring blocks), the only way MuJoCo
    gives the frictional dimensions their own reference (solreffriction).
    """
    tc = 2.0 * dt if solref_time is None else solref_time
    bodies, pairs = [], []
    for i, (w, h, zc) in enumerate(blocks):
        bodies.append(f"""
    <body name="b{i}" pos="0 0 {zc!r}">
      <joint type="slide" axis="1 0 0"/>
      <joint type="slide" axis="0 0 1"/>
      <joint type="hinge" axis="0 -1 0"/>
      <geom name="g{i}" type="box" size="{w / 2!r} {DEPTH / 2!r} {h / 2!r}" density="{DENSITY!r}"/>
    </body>""")
        pairs.append(f'<pair geom1="ground" geom2="g{i}"/>')
        if i:
            pairs.append(f'<pair geom1="g{i - 1}" geom2="g{i}"/>')
    xml = f"""
<mujoco>
  <option timestep="{dt!r}" gravity="0 0 {-G!r}" integrator="implicitfast" cone="elliptic"
          solver="Newton" impratio="10" iterations="100" tolerance="1e-10"
          noslip_iterations="0"/>
  <default>
    <geom contype="0" conaffinity="0"/>
    <pair condim="3" friction="{mu!r} {mu!r} 0 0 0" margin="0" solimp="{SOLIMP}"
          solref="{tc!r} 1" solreffriction="{FRICTION_TIMECONST!r} 1"/>
  </default>
  <worldbody>
    <geom name="ground" type="plane" size="0 0 1"/>{"".join(bodies)}
  </worldbody>
  <contact>
    {" ".join(pairs)}
  </contact>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def _settle(model, data):
    """Let resting bodies sink to their contact equilibrium (set-up, not timed), then restart
    at rest: MuJoCo includes a contact only once it penetrates, so a stack released exactly
    touching first falls one step per contact down the stack (0.3 mm at the top of 8 drums
    at dt = 1e-3)."""
    mujoco.mj_step(model, data, nstep=SETTLE_STEPS)
    data.qvel[:] = 0.0
    data.time = 0.0


def _run(model, data, duration, sample_every, base_accel=()):
    """Step to `duration`, sampling every `sample_every`; base_accel = [(t, a_g)] held constant.

    Returns a Trajectory with theta and x of every body (x from its start).
    """
    dt = model.opt.timestep
    n_total = int(round(duration / dt))
    every = max(1, int(round(sample_every / dt)))
    samples = np.arange(0, n_total + 1, every)
    # the step at which each change of a_g takes effect (rounded to the step grid)
    changes = {}
    for t, a in base_accel:
        k = int(round(t / dt))
        if k <= n_total:
            changes[k] = -a  # the last value given for a step wins
    events = np.union1d(samples, np.fromiter(changes, int, len(changes)))
    sample_set = set(samples.tolist())
    x0 = data.qpos[0::3].copy()
    theta = np.empty((len(samples), model.nbody - 1))
    x = np.empty_like(theta)
    j, k_now = 0, 0
    wall = _time.perf_counter()
    for k in events:
        if k > k_now:
            mujoco.mj_step(model, data, nstep=int(k - k_now))
            k_now = int(k)
        if k in changes:
            model.opt.gravity[0] = changes[k]
        if k in sample_set:
            theta[j] = data.qpos[2::3]
            x[j] = data.qpos[0::3] - x0
            j += 1
    wall = _time.perf_counter() - wall
    return Trajectory(time=samples * dt, theta=theta, x=x, wall_seconds=wall, steps=n_total)


def free_rocking(
    width, height, theta0, dt, duration, sample_every=1e-3, solref_time=None
) -> Trajectory:
    """Free rocking of one block released at rest, turned clockwise by theta0 about its
    bottom-right corner (which stays on the ground); theta starts at -theta0."""
    b, h = width / 2.0, height / 2.0
    model = _model([(width, height, h)], ROCKING_FRICTION, dt, solref_time)
    data = mujoco.MjData(model)
    c, s = math.cos(theta0), math.sin(theta0)
    # centroid turned clockwise about the corner (b, 0): (b, 0) + R_cw (-b, h)
    data.qpos[:] = [b - b * c + h * s, b * s + h * c - h, -theta0]
    return _run(model, data, duration, sample_every)


def pulse_sliding(
    width, height, mu, accel, pulse_duration, dt, duration, sample_every=1e-3, solref_time=None
) -> Trajectory:
    """A block on the ground under a rectangular base-acceleration pulse `accel` for
    0 <= t < pulse_duration; x is the sliding relative to the base."""
    model = _model([(width, height, height / 2.0)], mu, dt, solref_time)
    data = mujoco.MjData(model)
    _settle(model, data)
    return _run(model, data, duration, sample_every, [(0.0, accel), (pulse_duration, 0.0)])


def column_record(
    n_drums,
    width,
    height,
    mu,
    record_time,
    record_accel,
    dt,
    duration,
    sample_every=1e-3,
    solref_time=None,
) -> Trajectory:
    """n_drums equal drums stacked on the ground under the base acceleration record,
    held constant between record samples (0 from its last sample on); bodies bottom to top."""
    hd = height / n_drums
    model = _model([(width, hd, (i + 0.5) * hd) for i in range(n_drums)], mu, dt, solref_time)
    data = mujoco.MjData(model)
    _settle(model, data)
    t = np.asarray(record_time, dtype=float)
    a = np.asarray(record_accel, dtype=float)
    # a_i on [t_i, t_i+1); nothing after the record ends
    record = list(zip(t[:-1].tolist(), a[:-1].tolist())) + [(float(t[-1]), 0.0)]
    return _run(model, data, duration, sample_every, record)
