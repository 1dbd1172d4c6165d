"""Reference solutions the engine is validated against: closed forms and compiled integrators.

:mod:`~stonedem.reference.analytic` wraps them (Housner's rigid block, its overturning
thresholds, the Bouc-Wen sliding block); :mod:`~stonedem.reference.rigid_rocking` and
:mod:`~stonedem.reference.bouc_wen` are their Numba kernels. None of them is part of the engine.
"""
