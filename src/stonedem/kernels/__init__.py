"""Numba-compiled physics kernels of the 2D rigid-block engine (thesis chapter 3).

Everything here is ``@njit(cache=True)`` with fastmath off (reassociation would break
determinism and the energy balance). Kernels take structure-of-arrays inputs (flat arrays;
the time loop :func:`stonedem.kernels.step.run` takes named tuples of them), never allocate per
step, never print and never raise for physics: they return status codes that
:mod:`stonedem.engine.simulate` turns into one-line errors.

Who imports what: :mod:`stonedem.engine.simulate` is the only caller of
:func:`stonedem.kernels.step.run`;
:mod:`stonedem.engine.run`, :mod:`stonedem.validation.cases` and benchmarks of :mod:`benchmarks`
read its ENERGY_* columns and STATUS_* codes. Outside the time loop,
:mod:`stonedem.motion.excitation` evaluates base motion with :mod:`stonedem.kernels.excitation`, and
:mod:`stonedem.engine.scene` and benchmarks of :mod:`benchmarks` call the broad phase and
overlap kernels directly.
:mod:`stonedem.reference.rigid_rocking` and :mod:`stonedem.reference.bouc_wen` are not part of the
engine: they are compiled references that :mod:`stonedem.reference.analytic` wraps (the rigid block
under a record and under a one-sine pulse; the Bouc-Wen sliding block).

Numba checks a cached function against its own source file only, so a cached time loop
would keep running an old copy of a changed kernel it calls. The cache therefore lives in
a folder named by a hash of all kernel sources (unless NUMBA_CACHE_DIR is set): any edit
compiles afresh, once, and unchanged code is compiled once per machine, not per case.
"""

import hashlib
import os
from pathlib import Path

import numba

from stonedem.io import numba_cache

numba_cache.guard()  # a damaged cache file costs a compile, not the run

JIT_OPTIONS = {"cache": True, "fastmath": False, "nogil": True}
# Kernels that never allocate compile without Numba's runtime (NRT): handing them arrays then
# costs no reference counting, which was ~40 % of a lone block's step (an atomic increment
# and decrement per array and call). Such a kernel cannot create or return an array.
NO_ALLOC_OPTIONS = {**JIT_OPTIONS, "_nrt": False}
# Small kernels the step calls: inlined into their caller, so a call does not pass every
# array as seven words on the stack. LLVM declined to on its own; ``forceinline`` marks them
# always-inline for LLVM. Numba's own inlining (``inline="always"``) types every inlined copy
# again and compiles slower, for the same results bit for bit (docs/notebook.md, "Measurements
# moved out of the code").
INLINE_OPTIONS = {**NO_ALLOC_OPTIONS, "forceinline": True}


def sources_key() -> str:
    """16 hex digits of a hash of all kernel sources: the cache folder's name, and the name of the
    workflow's marker of a compile (workflow/rules/compile.smk)."""
    # the compiled references (stonedem.reference) share this cache and its key
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for source in sorted(here.glob("*.py")) + sorted((here.parent / "reference").glob("*.py")):
        digest.update(source.name.encode())
        digest.update(source.read_bytes())
    return digest.hexdigest()[:16]


def _kernel_cache_dir() -> Path:
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "stonedem" / "numba" / sources_key()


if not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(_kernel_cache_dir())
