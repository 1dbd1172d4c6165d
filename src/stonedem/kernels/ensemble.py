"""Many runs in one call of compiled code: the time loop over members, one thread each (issue 33).

:func:`run_members` hands each member's bundles (:mod:`stonedem.kernels.step`) to the same
compiled loop :func:`stonedem.kernels.step.run` that runs a single scene, in a ``prange``
over the members, so one process uses every core and each member's run is bit for bit the
one :func:`stonedem.engine.simulate.simulate` gives. Members need not share a structure on
the CPU: each brings its own arrays.
"""

from numba import njit, prange

from stonedem.kernels import JIT_OPTIONS
from stonedem.kernels.step import run


@njit(parallel=True, **JIT_OPTIONS)
def run_members(
    which,
    models,
    settings,
    states,
    samples,
    start,
    stop,
    first,
    rest_from,
    n_sample,
    collapse_sample,
    status,
):
    """Steps start[m]..stop[m]-1 of each member m in ``which`` (typed lists of the members'
    bundles; int64 arrays of their other arguments to :func:`stonedem.kernels.step.run`).
    Writes each one's status, n_sample and collapse_sample in place."""
    for i in prange(which.shape[0]):
        m = which[i]
        status[m], n_sample[m], collapse_sample[m] = run(
            models[m],
            settings[m],
            states[m],
            samples[m],
            start[m],
            stop[m],
            first[m],
            rest_from[m],
            n_sample[m],
            collapse_sample[m],
        )
