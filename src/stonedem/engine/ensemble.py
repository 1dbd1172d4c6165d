"""Many scenes in one process: their compiled loops side by side, one thread each (issue 33).

:func:`run_ensemble` gives every scene the :class:`~stonedem.engine.simulate.RunResult` that
:func:`~stonedem.engine.simulate.simulate` gives it, bit for bit: the same plan
(:func:`~stonedem.engine.simulate.plan_run`), phase by phase (the settling of a quiet lead,
then the run), with each phase's compiled loop run for all members at once by
:func:`stonedem.kernels.ensemble.run_members`. It runs in chunks of about ``CHUNK_SECONDS``
of :mod:`stonedem.engine.simulate`, so Ctrl-C ends it within a chunk. On the CPU the members'
scenes need not share a structure.

``device="gpu"`` runs each phase on an NVIDIA GPU instead, one CUDA thread per member
(:mod:`stonedem.kernels.gpu`): the members' bundles are stacked
(:mod:`stonedem.kernels.members`), so they must share a structure (bodies, contact law,
excitation kinds; records may differ in length). The GPU's arithmetic is the same IEEE
arithmetic, but its compiler may contract a*b+c into one rounding, so runs agree with the CPU
to rounding over a short horizon, not bit for bit, and over a chaotic record only in their
statistics and verdicts.
"""

from __future__ import annotations

import dataclasses
import time as wallclock

import numba
import numpy as np
from numba import typed

from stonedem.engine.scene import Scene
from stonedem.engine.simulate import (
    FIRST_CHUNK_STEPS,
    Plan,
    RunResult,
    after_settle,
    compile_for,
    finish_run,
    main_phase,
    next_chunk,
    plan_run,
    settle_phase,
)
from stonedem.entry import check_interrupt, deferred_signals
from stonedem.errors import InputError
from stonedem.io.spec import Field
from stonedem.kernels import step
from stonedem.kernels.ensemble import run_members

DEVICES = ("cpu", "gpu")
DEVICE = Field("device", "choice", default="cpu", choices=DEVICES, doc="where the members run")
# the upper bound is the threads Numba has (NUMBA_NUM_THREADS), filled in at the call
THREADS = Field("threads", "integer", range="[1, inf)", doc="threads (default: all Numba has)")


def run_ensemble(
    scenes: list[Scene], threads: int | None = None, device: str = "cpu"
) -> list[RunResult]:
    """Every scene's run, as :func:`stonedem.engine.simulate.simulate` gives it, with the
    compiled loops of all of them run side by side on ``threads`` threads (default: all
    Numba has, NUMBA_NUM_THREADS), or on the GPU (``device="gpu"``, one thread per member;
    a RuntimeError says why when none can run it)."""
    device = DEVICE.check(device)
    available = numba.config.NUMBA_NUM_THREADS
    if threads is not None:
        threads = dataclasses.replace(
            THREADS,
            range=f"[1, {available}]",
            hint=f"give e.g. threads={available}, or leave it out",
        ).check(threads)
    scenes = list(scenes)
    for i, scene in enumerate(scenes):
        if not isinstance(scene, Scene):
            raise InputError(
                f"scenes[{i}]",
                f"expected a Scene, got {type(scene).__name__}",
                "build each member with stonedem.engine.scene.scene_from_dict",
            )
    plans = [plan_run(scene) for scene in scenes]
    if not plans:
        return []
    if device == "gpu":
        from stonedem.kernels.gpu import gpu_available

        usable, why = gpu_available()
        if not usable:
            raise RuntimeError(f"device gpu: {why}")
        phase_runner = run_phase_gpu
    else:
        phase_runner = run_phase
    before = numba.get_num_threads()
    numba.set_num_threads(threads or available)
    try:
        statuses = phase_runner(plans, [settle_phase(plan) for plan in plans])
        for plan, status in zip(plans, statuses):
            if status is not None:
                after_settle(plan, status)
        statuses = phase_runner(plans, [main_phase(plan) for plan in plans])
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
    chunk's (the chunk's wall time over the members it ran), and the compile of the members'
    loop (or its load from the cache) before the first chunk is each member's compile time."""
    members, loops, at, end, first, rest_from, n_sample, collapse, status = phase_members(
        plans, phases
    )
    if not members:
        return statuses_of(plans, members, status)
    bundles = [
        typed.List([getattr(loop, name) for loop in loops])
        for name in ("model", "settings", "state")
    ]
    samples = typed.List([loop.cursor.samples for loop in loops])
    size, compiled = FIRST_CHUNK_STEPS, False
    with deferred_signals():  # a signal is raised between chunks, never inside the kernel
        while True:
            which = np.flatnonzero((status == step.STATUS_OK) & (at < end))
            if which.size == 0:
                break
            stop = np.minimum(at + size, end)
            args = (
                which,
                *bundles,
                samples,
                at,
                stop,
                first,
                rest_from,
                n_sample,
                collapse,
                status,
            )
            if not compiled:  # before the first timed chunk; each member waited for it
                seconds = compile_for(run_members, args)
                for loop in loops:
                    loop.cursor.compile += seconds
                compiled = True
                check_interrupt()
            started = wallclock.perf_counter()
            run_members(*args)
            elapsed = wallclock.perf_counter() - started
            for k in which:
                cursor = loops[k].cursor
                cursor.n_sample, cursor.collapse = int(n_sample[k]), int(collapse[k])
                cursor.ran(
                    at[k], stop[k], status[k], loops[k].settings.n_steps, elapsed / which.size
                )
                at[k] = stop[k]
            size = next_chunk(size, elapsed)
            check_interrupt()
    return statuses_of(plans, members, status)


def phase_members(plans: list[Plan], phases: list):
    """What both phase runners start from: the members that have a phase, their loops (rest
    counts reset), int64 arrays of their phases' (start, stop, first, rest_from) and of their
    cursors' n_sample and collapse sample, and their statuses (all STATUS_OK)."""
    members = [m for m, phase in enumerate(phases) if phase is not None]
    loops = [plans[m].loop for m in members]
    for loop in loops:
        loop.state.rest_count[0] = 0
    at, end, first, rest_from = (
        np.array([phases[m] for m in members], dtype=np.int64).reshape(-1, 4).T.copy()
    )
    n_sample = np.array([loop.cursor.n_sample for loop in loops], dtype=np.int64)
    collapse = np.array([loop.cursor.collapse for loop in loops], dtype=np.int64)
    status = np.full(len(members), step.STATUS_OK, dtype=np.int64)
    return members, loops, at, end, first, rest_from, n_sample, collapse, status


def statuses_of(plans: list[Plan], members: list[int], status: np.ndarray) -> list[int | None]:
    """Each plan's kernel status after a phase, None where it had no phase."""
    out: list[int | None] = [None] * len(plans)
    for i, m in enumerate(members):
        out[m] = int(status[i])
    return out


def pair_capacity(model: step.Model) -> int:
    """Candidate pairs a member's Work holds at first (the rule :func:`stonedem.kernels.step.run`
    uses, :func:`stonedem.kernels.step.first_pair_capacity`)."""
    return int(step.first_pair_capacity(model.body_mass.shape[0]))


def run_phase_gpu(plans: list[Plan], phases: list) -> list[int | None]:
    """:func:`run_phase` on the GPU: the members' stacked bundles stay on the device for the
    whole phase, which runs in chunks (one launch each, Ctrl-C between them); members whose
    pairs overflow their Work go on from that step with twice the room."""
    from numba import cuda

    from stonedem.kernels import gpu
    from stonedem.kernels.members import copy_back, stack

    members, loops, at, end, first, rest_from, n_sample, collapse, status = phase_members(
        plans, phases
    )
    if not members:
        return statuses_of(plans, members, status)
    kernel = gpu.member_kernel()
    capacity = max(pair_capacity(loop.model) for loop in loops)
    bundles = [
        (
            loop.model,
            loop.settings,
            loop.state,
            loop.cursor.samples,
            step.allocate_work(loop.model, capacity),
        )
        for loop in loops
    ]
    try:
        leaves, lengths = stack(bundles, member_fastest=gpu.MEMBER_FASTEST)
    except ValueError as exc:
        raise InputError(
            "scenes",
            f"on the GPU the members must share one structure: {exc}",
            "run each structure's members in their own call, or use device='cpu'",
        ) from None
    on_device = tuple(cuda.to_device(leaf) for leaf in leaves)
    device_lengths = cuda.to_device(lengths)
    n = len(members)
    first, rest_from = cuda.to_device(first), cuda.to_device(rest_from)
    threads = min(gpu.THREADS_PER_BLOCK, n)
    blocks = (n + threads - 1) // threads
    last: dict[
        int, tuple
    ] = {}  # the chunk that stopped each member, booked once its samples are back
    size = FIRST_CHUNK_STEPS
    with deferred_signals():  # a signal is raised between launches, never inside one
        while True:
            running = (status == step.STATUS_OK) & (at < end)
            if not running.any():
                break
            stop = np.where(running, np.minimum(at + size, end), at)
            resume = stop.copy()
            arrays = [cuda.to_device(a) for a in (at, stop, n_sample, collapse, status, resume)]
            started = wallclock.perf_counter()
            kernel[blocks, threads](
                on_device,
                device_lengths,
                arrays[0],
                arrays[1],
                first,
                rest_from,
                arrays[2],
                arrays[3],
                arrays[4],
                arrays[5],
            )
            cuda.synchronize()
            elapsed = wallclock.perf_counter() - started
            n_sample, collapse, status, resume = (a.copy_to_host() for a in arrays[2:])
            full = status == step.STATUS_PAIRS_FULL
            if full.any():  # more room for every member, then on from where the full ones stopped
                capacity *= 2
                host = [leaf.copy_to_host() for leaf in on_device]
                bundles = [(*b[:4], step.allocate_work(b[0], capacity)) for b in bundles]
                copy_back(host, lengths, bundles)
                leaves, lengths = stack(bundles, member_fastest=gpu.MEMBER_FASTEST)
                on_device = tuple(cuda.to_device(leaf) for leaf in leaves)
                device_lengths = cuda.to_device(lengths)
                status[full] = step.STATUS_OK
            ran = np.flatnonzero(running)
            for k in ran:
                cursor = loops[k].cursor
                cursor.n_sample, cursor.collapse = int(n_sample[k]), int(collapse[k])
                stopped_at = resume[k] if full[k] else stop[k]
                booking = (
                    at[k],
                    stopped_at,
                    status[k],
                    loops[k].settings.n_steps,
                    elapsed / ran.size,
                )
                if status[k] == step.STATUS_OK:
                    cursor.ran(*booking)
                else:  # Cursor.ran reads the last sample's step, which is still on the device
                    last[k] = booking
                at[k] = stopped_at
            size = next_chunk(size, elapsed)
            check_interrupt()
    host = [leaf.copy_to_host() for leaf in on_device]
    copy_back(host, lengths, bundles)
    for k, booking in last.items():
        loops[k].cursor.ran(*booking)
    return statuses_of(plans, members, status)
