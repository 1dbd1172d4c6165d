"""sqrt, sin, cos and isfinite of one float, spelled once for the CPU and the GPU (issue 33).

The kernels call these rather than NumPy's or math's. On the CPU each is NumPy's ufunc,
inlined into the caller at Numba's IR level, so the compiled loop is the one NumPy's own
spelling gave (bit for bit, and as fast). numba-cuda lowers no scalar NumPy ufunc, so
:func:`register_cuda` gives its target math's (the same IEEE operations). Without Numba
(``NUMBA_DISABLE_JIT``) the Python bodies below run.
"""

import math

import numpy as np
from numba.core.extending import overload


def sqrt(x):
    return np.sqrt(x)


def sin(x):
    return np.sin(x)


def cos(x):
    return np.cos(x)


def isfinite(x):
    return np.isfinite(x)


FUNCTIONS = (
    (sqrt, np.sqrt, math.sqrt),
    (sin, np.sin, math.sin),
    (cos, np.cos, math.cos),
    (isfinite, np.isfinite, math.isfinite),
)


def _spelling(function):
    """The overload's typer: whatever the argument's type, the implementation calls ``function``."""

    def typer(x):
        return lambda x: function(x)

    return typer


for _stub, _numpy, _ in FUNCTIONS:
    overload(_stub, target="cpu", inline="always")(_spelling(_numpy))

_cuda_registered = False


def register_cuda() -> None:
    """Give numba-cuda's target math's spelling of each function (once; needs numba-cuda)."""
    global _cuda_registered
    if _cuda_registered:
        return
    from numba.cuda.extending import overload as cuda_overload

    for stub, _, function in FUNCTIONS:
        cuda_overload(stub, target="cuda", inline="always")(_spelling(function))
    _cuda_registered = True
