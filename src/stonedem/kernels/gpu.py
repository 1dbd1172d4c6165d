"""The time loop on an NVIDIA GPU: one CUDA thread runs one member (issue 33).

Each thread takes its member's bundles out of the stacked leaves
(:func:`stonedem.kernels.members.member_bundles`) and runs the loop the CPU runs,
:func:`stonedem.kernels.step.run_steps`, compiled for the GPU by numba-cuda from the same
source (the ``[gpu]`` extra). Under Numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``) the
threads run on the CPU, which the tests use. The kernel is built on first use, so importing
this module needs no GPU and no numba-cuda.
"""

import functools

import numba
import numpy as np
from numba import njit

from stonedem.kernels import NO_ALLOC_OPTIONS, scalar
from stonedem.kernels.members import member_bundles
from stonedem.kernels.step import STATUS_OK, run_steps

THREADS_PER_BLOCK = 64  # members per block: the loop is long and branchy, so small blocks
# the stacked arrays with the member index fastest in memory (stonedem.kernels.members.stack), so
# that a warp's loads coalesce. Off: on an H100 (2026-11-27) it was not shown to pay (1 181 ns per
# member-step at 1 024 members, against 2 488 at 256 laid out per member; no like-for-like pair
# was measured, docs/notebook.md). A lone member's Fortran-ordered arrays are C-contiguous too,
# so Numba would compile the kernel a second time for it.
MEMBER_FASTEST = False
cuda = None  # numba.cuda, imported on first use; a global, so the simulator can stand in for it


@njit(
    **{**NO_ALLOC_OPTIONS, "cache": False}
)  # member_bundles is not cacheable (stonedem.kernels.members)
def run_member(
    leaves, lengths, m, start, stop, first, rest_from, n_sample, collapse_sample, status, resume
):
    """Member m's steps start[m]..stop[m]-1, unless its status is no longer STATUS_OK; writes
    its status, n_sample, collapse_sample and the step to go on from (``resume``: where
    STATUS_PAIRS_FULL stopped it) in place."""
    if status[m] != STATUS_OK or start[m] >= stop[m]:
        return
    model, settings, state, samples, work = member_bundles(leaves, lengths, m)
    s, n, c, go_on = run_steps(
        model,
        settings,
        state,
        samples,
        work,
        start[m],
        stop[m],
        first[m],
        rest_from[m],
        n_sample[m],
        collapse_sample[m],
    )
    status[m] = s
    n_sample[m] = n
    collapse_sample[m] = c
    resume[m] = go_on


def _host_array(a):
    """The NumPy array behind one of the CUDA simulator's stand-ins for a device array."""
    while hasattr(a, "_item"):
        a = a._item
    return getattr(a, "_ary", a)


@functools.lru_cache(maxsize=None)
def member_kernel():
    """The CUDA kernel ``kernel[blocks, THREADS_PER_BLOCK](leaves, lengths, start, stop, first,
    rest_from, n_sample, collapse_sample, status, resume)``: thread m runs :func:`run_member`.

    Under the simulator the threads hand :func:`run_member`, compiled for the CPU, the NumPy
    arrays behind the simulator's stand-ins (compiled code cannot take those): what it tests
    is the stacking, the launches and the copies, with the loop the CPU runs; that the loop
    compiles for a GPU is tests/kernels/test_cuda_compile.py's job."""
    global cuda
    from numba import cuda

    if numba.config.ENABLE_CUDASIM:

        @cuda.jit
        def run_members_simulated(
            leaves,
            lengths,
            start,
            stop,
            first,
            rest_from,
            n_sample,
            collapse_sample,
            status,
            resume,
        ):
            m = cuda.grid(1)
            if m < start.shape[0]:
                arrays = [
                    _host_array(a)
                    for a in (
                        lengths,
                        start,
                        stop,
                        first,
                        rest_from,
                        n_sample,
                        collapse_sample,
                        status,
                        resume,
                    )
                ]
                run_member(tuple(_host_array(a) for a in leaves), arrays[0], m, *arrays[1:])

        return run_members_simulated

    if not hasattr(np, "row_stack"):  # numba-cuda 0.30.4 still calls it; NumPy 2.5 removed it
        np.row_stack = np.vstack
    scalar.register_cuda()
    compile_without_contraction()
    return cuda.jit(cache=True)(
        run_members_on_gpu
    )  # cached under the kernel-source hash (stonedem.kernels)


def compile_without_contraction() -> None:
    """Have NVVM keep ``a * b + c`` as two roundings, as the CPU does (once per process).

    NVVM fuses a multiply and an add into one FMA by default (``-fma=1``); Numba's CPU target
    does not, so fused the two round differently and rocking impacts amplify it: fused, a lone
    block was 1e-6 m from the CPU's after 0.5 s (H100, 2026-11-27; unfused not yet measured on
    a GPU). numba-cuda's ``cuda.jit`` passes NVVM no such option, so its compile call gets it
    here, unless the caller asked for fast math."""
    from numba.cuda.cudadrv import nvvm

    if getattr(nvvm.compile_ir, "keeps_two_roundings", False):
        return
    fused = nvvm.compile_ir

    def compile_ir(llvmir, **options):
        if not options.get("fastmath"):
            options.setdefault("fma", False)
        return fused(llvmir, **options)

    compile_ir.keeps_two_roundings = True
    nvvm.compile_ir = compile_ir


def run_members_on_gpu(
    leaves, lengths, start, stop, first, rest_from, n_sample, collapse_sample, status, resume
):
    """The kernel's source (compiled by :func:`member_kernel`): thread m runs member m."""
    m = cuda.grid(1)
    if m < start.shape[0]:
        run_member(
            leaves,
            lengths,
            m,
            start,
            stop,
            first,
            rest_from,
            n_sample,
            collapse_sample,
            status,
            resume,
        )


def gpu_available() -> tuple[bool, str]:
    """(whether a CUDA GPU can run the loop, why not or which device) - never raises."""
    try:
        from numba import cuda

        if numba.config.ENABLE_CUDASIM:
            return True, "Numba's CUDA simulator (NUMBA_ENABLE_CUDASIM=1)"
        if not cuda.is_available():
            return False, "no CUDA GPU or driver found"
        import importlib.util

        if importlib.util.find_spec("numba_cuda") is None:
            return False, "numba-cuda is not installed (pip install 'stonedem[gpu]')"
        device = cuda.get_current_device()
        return (
            True,
            f"{device.name.decode() if isinstance(device.name, bytes) else device.name}, "
            f"compute capability {device.compute_capability[0]}.{device.compute_capability[1]}",
        )
    except Exception as exc:  # a broken driver or toolkit: say why, fall back
        return (
            False,
            f"CUDA unusable: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}",
        )
