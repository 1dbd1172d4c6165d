"""The memory a run may take, and what it will need: refused before computing, like its steps.

A run holds its samples (x, y, theta of every body, the energies), then builds its dataset
and writes it; measured with tracemalloc (2 and 21 bodies, 40 000-120 000 samples), the
peak was 20 + 5.8 x bodies doubles per sample, over the run and the write alike.
:data:`DOUBLES_PER_SAMPLE` and :data:`DOUBLES_PER_BODY` round that up; the contact memory
adds n^2 x 24 doubles. The budget is :data:`MEMORY_SHARE` of what this process may still
take: the physical memory, under RLIMIT_AS and a cgroup memory limit when they are set.
"""

from __future__ import annotations

import os
import resource

DOUBLES_PER_SAMPLE = 32  # per output sample: energies, time, base motion, measures (measured 20)
DOUBLES_PER_BODY = 8  # per sample and body: samples, relative motion, sliding (measured 5.8)
CONTACT_DOUBLES = 24  # per pair of bodies: friction force and contact memory
MEMORY_SHARE = 0.5  # of the available memory: numba, xarray and the OS need the rest
# above this a run is refused on any machine (the same answer everywhere)
MAX_RUN_BYTES = 16 * 2**30


def run_bytes(n_samples: float, n_bodies: int) -> float:
    """Bytes a run of ``n_samples`` output samples of ``n_bodies`` bodies needs at its peak."""
    return 8.0 * (
        n_samples * (DOUBLES_PER_SAMPLE + DOUBLES_PER_BODY * n_bodies)
        + CONTACT_DOUBLES * n_bodies * n_bodies
    )


def _read_int(path: str) -> int | None:
    try:
        with open(path) as handle:
            text = handle.read().split()[0]
    except (OSError, IndexError):
        return None
    return int(text) if text.isdigit() else None


def available_memory() -> int:
    """Bytes this process may still take: the physical memory, less what RLIMIT_AS and a
    cgroup (v2) memory limit leave when they are set."""
    page = os.sysconf("SC_PAGE_SIZE")
    sizes = [page * os.sysconf("SC_PHYS_PAGES")]
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY:
        pages = _read_int("/proc/self/statm")  # the address space in use, in pages
        sizes.append(soft - page * (pages or 0))
    limit = _read_int("/sys/fs/cgroup/memory.max")  # "max" when unlimited
    if limit is not None:
        sizes.append(limit - (_read_int("/sys/fs/cgroup/memory.current") or 0))
    return max(0, min(sizes))


def memory_budget() -> float:
    """Bytes one run may take: MEMORY_SHARE of :func:`available_memory`, at most MAX_RUN_BYTES."""
    return min(MAX_RUN_BYTES, MEMORY_SHARE * available_memory())
