"""Numba-compiled physics kernels of the 2D rigid-block engine (thesis chapter 3).

Everything here is ``@njit(cache=True)`` with fastmath off (reassociation would break
determinism and the energy balance). Kernels take flat structure-of-arrays inputs, never
allocate per step, never print and never raise for physics: they return status codes
that :mod:`dem.simulate` turns into one-line errors. Only :mod:`dem.simulate` imports
:mod:`dem.kernels.step`.
"""

JIT_OPTIONS = {"cache": True, "fastmath": False, "nogil": True}
