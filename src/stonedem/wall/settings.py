"""Solver settings of the wall pushover (``solver:`` in a case file): a light module, so that
validating a case file does not import numba or scipy."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class SolverSettings:
    tolerance: float = 1e-5  # residual norm / reference load norm
    max_iterations: int = 25  # a step that has not converged by then is halved (fails fast)
    dead_load_iterations: int = 100  # the dead load (load control, secant matrix) converges slower
    max_steps: int = 1000
    # control displacement at which to stop [m]; 0: s (the plateau stop ends most runs first)
    max_displacement: float = 0.0
    first_step: float = 0.0  # first control increment [m]; 0: automatic
    growth: float = 1.3  # step growth after an easy step ...
    easy_iterations: int = 6  # ... one that converged within this many iterations
    max_failures: int = 4  # consecutive failed (halved) steps before accepting/giving up
    accept_tolerance: float = 1e-3  # residual accepted after max_failures (recorded per step)
    work_control: float = 1.0  # 1: step the load-weighted mean displacement, 0: the control DOF
    consistent: float = 1.0  # 1: consistent (return-map derivative) tangent, 0: Eq. 13-14 secant
    # fraction of K-bar kept on yielded components (iteration matrix only)
    residual_stiffness: float = 0.001
    # 1: start each step from the last increment, scaled; 0: from the last state
    extrapolate: float = 1.0
    # keep the LU while an iteration cuts the residual below this x; 0: refactor always
    reuse_ratio: float = 0.25
    drop_ratio: float = 0.5  # stop when lambda falls below this x lambda_max
    plateau_steps: int = 12  # stop after this many steps (and twice the displacement) ...
    plateau_tolerance: float = 1e-3  # ... in which lambda rose by less than this fraction
    max_seconds: float = 0.0  # wall-clock budget of the live-load phase; 0: none
    # manuscript 2.3 scheme (``secant`` = 1): load increments, stiffness of step i from the
    # interface damage of step i-1 (Eq. 13-14), residual iterations with that matrix; the
    # limit load is where the step no longer converges or the displacement grows unboundedly
    secant: float = 0.0  # 1: manuscript load-controlled secant scheme, 0: displacement control
    # first load increment (lambda units); 0: 1/50 of the elastic-limit estimate
    load_step: float = 0.0
    min_load_step: float = 1e-3  # stop refining when the increment falls below this x the first one
    singular_ratio: float = 1e3  # "unbounded": incremental flexibility > this x the initial one
    secant_refresh: float = 0.0  # >0: also rebuild the secant matrix every this many iterations

    def as_dict(self):
        return dict(self.__dict__)
