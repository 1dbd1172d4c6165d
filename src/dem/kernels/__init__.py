"""Numba-compiled physics kernels of the 2D rigid-block engine (thesis chapter 3).

Everything here is ``@njit(cache=True)`` with fastmath off (reassociation would break
determinism and the energy balance). Kernels take structure-of-arrays inputs (flat arrays;
the time loop :func:`dem.kernels.step.run` takes named tuples of them), never allocate per
step, never print and never raise for physics: they return status codes that
:mod:`dem.simulate` turns into one-line errors.

Who imports what: :mod:`dem.simulate` is the only caller of :func:`dem.kernels.step.run`;
:mod:`dem.dataset`, :mod:`dem.validation` and benchmarks of :mod:`dem.bench` read its
ENERGY_* columns and STATUS_* codes. Outside the time loop, :mod:`dem.ground_motion`
evaluates base motion with :mod:`dem.kernels.excitation`, and :mod:`dem.scene` and
benchmarks of :mod:`dem.bench` call the broad phase and overlap kernels directly.
:mod:`dem.kernels.rigid_rocking` and :mod:`dem.kernels.bouc_wen` are not part of the engine:
they are compiled references that :mod:`dem.analytic` wraps (the rigid block under a record
and under a one-sine pulse; the Bouc-Wen sliding block).

Numba checks a cached function against its own source file only, so a cached time loop
would keep running an old copy of a changed kernel it calls. The cache therefore lives in
a folder named by a hash of all kernel sources (unless NUMBA_CACHE_DIR is set): any edit
compiles afresh, once, and unchanged code is compiled once per machine, not per case.
"""

import hashlib
import os
from pathlib import Path

import numba

JIT_OPTIONS = {"cache": True, "fastmath": False, "nogil": True}


def _kernel_cache_dir() -> Path:
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for source in sorted(here.glob("*.py")):
        digest.update(source.name.encode())
        digest.update(source.read_bytes())
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return root / "dem" / "numba" / digest.hexdigest()[:16]


if not os.environ.get("NUMBA_CACHE_DIR"):
    numba.config.CACHE_DIR = str(_kernel_cache_dir())
