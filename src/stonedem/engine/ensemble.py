"""Many scenes in one process: their compiled loops side by side, one thread each (issue 33).

:func:`run_ensemble` gives every scene the :class:`~stonedem.engine.simulate.RunResult` that
:func:`~stonedem.engine.simulate.simulate` gives it, bit for bit: the same plan
(:func:`~stonedem.engine.simulate.plan_run`), phase by phase (the settling of a quiet lead,
then the run), with each phase's compiled loop run for all members at once by
:func:`stonedem.kernels.ensemble.run_members`. It runs in chunks of about ``CHUNK_SECONDS``
of :mod:`stonedem.engine.simulate`, so Ctrl-C ends it within a chunk. This is the CPU side of
the ensemble engine; the members' scenes need not share a structure.
"""

from __future__ import annotations

import time as wallclock

import numba
import numpy as np
from numba import typed

from stonedem.engine.scene import Scene
from stonedem.engine.simulate import (FIRST_CHUNK_STEPS, Plan, RunResult, after_settle, finish_run, main_phase,
                                      next_chunk, plan_run, settle_phase)
from stonedem.entry import check_interrupt, deferred_signals
from stonedem.errors import InputError
from stonedem.kernels import step
from stonedem.kernels.ensemble import run_members


def run_ensemble(scenes: list[Scene], threads: int | None = None) -> list[RunResult]:
    """Every scene's run, as :func:`stonedem.engine.simulate.simulate` gives it, with the
    compiled loops of all of them run side by side on ``threads`` threads (default: all
    Numba has, NUMBA_NUM_THREADS)."""
    available = numba.config.NUMBA_NUM_THREADS
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, (int, np.integer))
                                or not 1 <= threads <= available):
        raise InputError("threads", f"expected a whole number 1 ... {available}, got {threads!r}",
                         f"give e.g. threads={available}, or leave it out")
    scenes = list(scenes)
    for i, scene in enumerate(scenes):
        if not isinstance(scene, Scene):
            raise InputError(f"scenes[{i}]", f"expected a Scene, got {type(scene).__name__}",
                             "build each member with stonedem.engine.scene.scene_from_dict")
    plans = [plan_run(scene) for scene in scenes]
    if not plans:
        return []
    before = numba.get_num_threads()
    numba.set_num_threads(threads or available)
    try:
        statuses = run_phase(plans, [settle_phase(plan) for plan in plans])
        for plan, status in zip(plans, statuses):
            if status is not None:
                after_settle(plan, status)
        statuses = run_phase(plans, [main_phase(plan) for plan in plans])
        for plan, status in zip(plans, statuses):
            if status is not None:
                plan.status = status
    finally:
        numba.set_num_threads(before)
    return [finish_run(plan) for plan in plans]


def run_phase(plans: list[Plan], phases: list) -> list[int | None]:
    """Run each plan's phase (start, stop, first, rest_from), None for none, all members at
    once in chunks; returns each member's kernel status (None where it had no phase).

    A member's cursor (samples, steps, wall time) moves on as in
    :meth:`stonedem.engine.simulate.CompiledLoop.run`; its wall time is its share of each
    chunk's (the chunk's wall time over the members it ran)."""
    members = [m for m, phase in enumerate(phases) if phase is not None]
    statuses: list[int | None] = [None] * len(plans)
    if not members:
        return statuses
    for m in members:
        plans[m].loop.state.rest_count[0] = 0
    loops = [plans[m].loop for m in members]
    bundles = [typed.List([getattr(loop, name) for loop in loops]) for name in ("model", "settings", "state")]
    samples = typed.List([loop.cursor.samples for loop in loops])
    n = len(members)
    at = np.array([phases[m][0] for m in members], dtype=np.int64)
    end = np.array([phases[m][1] for m in members], dtype=np.int64)
    first = np.array([phases[m][2] for m in members], dtype=np.int64)
    rest_from = np.array([phases[m][3] for m in members], dtype=np.int64)
    n_sample = np.array([loop.cursor.n_sample for loop in loops], dtype=np.int64)
    collapse = np.array([loop.cursor.collapse for loop in loops], dtype=np.int64)
    status = np.full(n, step.STATUS_OK, dtype=np.int64)
    size = FIRST_CHUNK_STEPS
    with deferred_signals():  # a signal is raised between chunks, never inside the kernel
        while True:
            which = np.flatnonzero((status == step.STATUS_OK) & (at < end))
            if which.size == 0:
                break
            stop = np.minimum(at + size, end)
            started = wallclock.perf_counter()
            run_members(which, *bundles, samples, at, stop, first, rest_from, n_sample, collapse, status)
            elapsed = wallclock.perf_counter() - started
            for k in which:
                cursor = loops[k].cursor
                cursor.n_sample, cursor.collapse = int(n_sample[k]), int(collapse[k])
                cursor.ran(at[k], stop[k], status[k], loops[k].settings.n_steps, elapsed / which.size)
                at[k] = stop[k]
            size = next_chunk(size, elapsed)
            check_interrupt()
    for i, m in enumerate(members):
        statuses[m] = int(status[i])
    return statuses
