"""Numba-compiled physics kernels of the 2D rigid-block engine (thesis chapter 3).

Everything here is ``@njit(cache=True)`` with fastmath off (reassociation would break
determinism and the energy balance). Kernels take flat structure-of-arrays inputs, never
allocate per step, never print and never raise for physics: they return status codes
that :mod:`dem.simulate` turns into one-line errors. Only :mod:`dem.simulate` imports
:mod:`dem.kernels.step`.

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
