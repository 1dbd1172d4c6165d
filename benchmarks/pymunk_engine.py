"""The canonical benchmark scenes (:mod:`benchmarks.canonical`) run in pymunk 7 (Chipmunk2D).

Stepping: one ``Space.step(dt)`` Python call per fixed step, pymunk's fastest stepping API
(broad phase, narrow phase, sequential-impulse solve and integration all run in C). The
``Space.step`` docs: "Using a fixed time step is highly recommended" (it keeps the contact
persistence / warm starting effective); every scene uses one. Sampling reads ``body.angle``
and ``body.position`` between steps; the base acceleration is written to ``space.gravity``
only when it changes.

Set-up, after the pymunk API reference (pymunk.readthedocs.io: Space, Body, Poly, Arbiter):

* Dynamic ``Body(mass, moment_for_box)``, ``Poly.create_box`` shapes with radius 0 (sharp
  corners: the rocking pivot is a corner). The ground is a static box on
  ``space.static_body`` with its top face at y = 0. Stacked shapes start exactly touching;
  nothing is settled before t = 0.
* Friction: Chipmunk's pair friction is the *product* of the two shapes' frictions
  ("The default calculation multiplies the friction of the two shapes together",
  ``Arbiter.friction``), so every shape gets sqrt(mu) and every pair has mu. (With mu on
  both shapes the pulse block slid 2.7 m instead of Newmark's 0.92 m.)
* Elasticity 0 on every shape: the contact impulse is perfectly plastic at the impacting
  corner, so a rocking impact conserves angular momentum about the new pivot: Housner's
  restitution by construction.
* ``collision_slop`` = :data:`COLLISION_SLOP`. The docs: "Amount of overlap between shapes
  that is allowed ... set this as high as you can without noticeable overlapping. It
  defaults to 0.1", which is 10 cm in these metre units. Measured: 0.1 and 1e-3..1e-4 give
  identical results here (the penetrations, ~1e-5 m, never reach the slop, so the
  positional bias never acts); from 1e-5 down the bias starts to act and the results shift
  slightly. 1e-4 m keeps the allowed overlap negligible against the geometry.
* ``iterations`` = :data:`ITERATIONS` (default 10, "sufficient for most simple games"; more
  passes "make the solution more accurate"). Chipmunk keeps a contact point only while its
  separation is <= 0 (cpCollision.c, ContactPoints), so exactly touching drums lose a
  corner contact at the first tiny rotation and the resting 8-drum stack acquires a
  spurious, O(dt) rotation. Measured at dt = 1e-3 under a 0.01 g sine: max |theta| 7e-5 rad
  at 10 iterations, 3.8e-5 at 20, 2e-5 at 50 (7e-7 at dt = 1e-4), for 15, 18, 27 us per
  step. 20 halves it for +17 % cost; the rocking and sliding results do not depend on it.
* ``collision_bias`` and ``collision_persistence`` stay at their defaults ("Very very few
  games will need to change this value").
* No sleeping (``sleep_time_threshold`` = inf, pymunk's default): a sleeping body would
  freeze the small motions the benchmark measures.
* Base acceleration a_g(t): the uniform inertial field ``space.gravity = (-a_g, -G)``,
  exact for rigid bodies on a fixed ground, taken at the start t_n of each step.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pymunk

from benchmarks.canonical import DENSITY, DEPTH, ROCKING_FRICTION, G, Trajectory

COLLISION_SLOP = 1e-4  # [m] allowed overlap (pymunk default 0.1); see module docstring
ITERATIONS = 20  # solver passes per step (pymunk default 10); see module docstring
GROUND_HALF_WIDTH = 100.0  # [m] the static ground box reaches far past any sliding


def _space(friction):
    space = pymunk.Space()
    space.gravity = (0.0, -G)
    space.iterations = ITERATIONS
    space.collision_slop = COLLISION_SLOP
    # ground: a static box whose top face is y = 0
    ground = pymunk.Poly(
        space.static_body,
        [
            (-GROUND_HALF_WIDTH, -1.0),
            (GROUND_HALF_WIDTH, -1.0),
            (GROUND_HALF_WIDTH, 0.0),
            (-GROUND_HALF_WIDTH, 0.0),
        ],
    )
    ground.friction = math.sqrt(friction)  # pair friction is the product: sqrt * sqrt = mu
    ground.elasticity = 0.0
    space.add(ground)
    return space


def _block(space, width, height, friction, position, angle=0.0):
    mass = DENSITY * width * height * DEPTH
    body = pymunk.Body(mass, pymunk.moment_for_box(mass, (width, height)))
    body.position = position
    body.angle = angle
    shape = pymunk.Poly.create_box(body, (width, height))
    shape.friction = math.sqrt(friction)  # see _space
    shape.elasticity = 0.0
    space.add(body, shape)
    return body


def _run(space, bodies, dt, duration, sample_every, gravity_x=None):
    """Step ``space`` for ``duration``; ``gravity_x[n]`` is the x-gravity during step n."""
    n_steps = int(round(duration / dt))
    every = max(1, int(round(sample_every / dt)))
    n_samples = n_steps // every + 1
    theta = np.empty((n_samples, len(bodies)))
    x = np.empty_like(theta)
    x0 = [b.position.x for b in bodies]
    step = space.step
    gx = space.gravity.x
    start = time.perf_counter()
    for n in range(n_steps + 1):
        if n % every == 0:
            k = n // every
            theta[k] = [b.angle for b in bodies]
            x[k] = [b.position.x - s for b, s in zip(bodies, x0)]
        if n == n_steps:
            break
        # touch the space only when the base acceleration changes
        if gravity_x is not None and gravity_x[n] != gx:
            gx = gravity_x[n]
            space.gravity = (gx, -G)
        step(dt)
    wall = time.perf_counter() - start
    return Trajectory(
        time=np.arange(n_samples) * every * dt, theta=theta, x=x, wall_seconds=wall, steps=n_steps
    )


def free_rocking(width, height, theta0, dt, duration, sample_every=1e-3) -> Trajectory:
    """Free rocking from rest, rotated clockwise by theta0 about the bottom-right corner."""
    space = _space(ROCKING_FRICTION)
    # centroid = pivot corner (w/2, 0) minus the rotated corner offset (w/2, -h/2)
    c, s = math.cos(-theta0), math.sin(-theta0)
    ox, oy = width / 2, -height / 2
    centre = (width / 2 - (c * ox - s * oy), -(s * ox + c * oy))
    body = _block(space, width, height, ROCKING_FRICTION, centre, -theta0)
    return _run(space, [body], dt, duration, sample_every)


def pulse_sliding(
    width, height, mu, accel, pulse_duration, dt, duration, sample_every=1e-3
) -> Trajectory:
    """Sliding under a rectangular base-acceleration pulse a_g = accel for t < pulse_duration."""
    space = _space(mu)
    body = _block(space, width, height, mu, (0.0, height / 2))
    # a step belongs to the pulse if its midpoint does: the pulse ends on the nearest step
    n_pulse = int(round(pulse_duration / dt))
    gravity_x = [-accel if n < n_pulse else 0.0 for n in range(int(round(duration / dt)))]
    return _run(space, [body], dt, duration, sample_every, gravity_x)


def column_record(
    n_drums, width, height, mu, record_time, record_accel, dt, duration, sample_every=1e-3
) -> Trajectory:
    """A column of n_drums equal drums under a base-acceleration record (linear interpolation)."""
    space = _space(mu)
    h = height / n_drums
    bodies = [_block(space, width, h, mu, (0.0, (i + 0.5) * h)) for i in range(n_drums)]
    n_steps = int(round(duration / dt))
    # a_g at every step start t_n, interpolated once, outside the timed loop
    gravity_x = (-np.interp(np.arange(n_steps) * dt, record_time, record_accel)).tolist()
    return _run(space, bodies, dt, duration, sample_every, gravity_x)
