"""The GPU kernel compiles for NVIDIA GPUs from the source the CPU runs (issue 33).

numba-cuda compiles the ensemble's kernel, :func:`stonedem.kernels.gpu.run_members_on_gpu`,
with everything it inlines or calls (the members' bundles, the time loop, both contact laws,
the broad phase, the excitation), into PTX for compute capability 9.0 (H100). No GPU is
needed, only numba-cuda and its compiler (``pip install -e '.[gpu]'``); without them the test
is skipped and says why. It takes about a minute.
"""

import importlib.util
import types

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("numba_cuda") is None,
    reason="numba-cuda is not installed (pip install -e '.[gpu]')",
)


def test_the_member_kernel_compiles_to_ptx(monkeypatch):
    import numba.cuda.dispatcher as dispatcher
    from numba import cuda, typeof

    from stonedem.engine.ensemble import pair_capacity
    from stonedem.engine.scene import scene_from_dict
    from stonedem.engine.simulate import plan_run
    from stonedem.kernels import gpu, step
    from stonedem.kernels.members import stack
    from stonedem.study.reference_scenes import SCENES

    try:
        from numba.cuda.cudadrv import nvvm

        nvvm.NVVM()
    except Exception as exc:  # the compiler library is missing: nothing to test here
        pytest.skip(f"numba-cuda has no NVVM: {exc}")
    # the functions the kernel calls are compiled for the current device; with no GPU, say H100
    monkeypatch.setattr(
        dispatcher, "get_current_device", lambda: types.SimpleNamespace(compute_capability=(9, 0))
    )
    gpu.member_kernel()  # numba.cuda in the kernel's globals; math's sqrt, sin, cos for the GPU
    loops = [plan_run(scene_from_dict(SCENES["colonnade_3x3"][1](1.0))).loop for _ in range(2)]
    leaves, lengths = stack(
        [
            (
                loop.model,
                loop.settings,
                loop.state,
                loop.cursor.samples,
                step.allocate_work(loop.model, pair_capacity(loop.model)),
            )
            for loop in loops
        ],
        member_fastest=gpu.MEMBER_FASTEST,
    )
    counts = np.zeros(2, dtype=np.int64)
    args = (leaves, lengths) + (counts,) * 8
    options = []  # what NVVM is asked, compile by compile
    unit = nvvm.CompilationUnit.__init__
    monkeypatch.setattr(
        nvvm.CompilationUnit,
        "__init__",
        lambda self, o: (options.append(dict(o)), unit(self, o))[1],
    )
    ptx, _ = cuda.compile_ptx(gpu.run_members_on_gpu, tuple(typeof(a) for a in args), cc=(9, 0))
    assert ".target sm_90" in ptx and ".entry" in ptx
    assert "sqrt" in ptx and "sin" in ptx  # the contact laws and the base motion are in it
    # no multiply-add fused by NVVM: the GPU rounds as the CPU does
    # (gpu.compile_without_contraction)
    assert options and all(o.get("fma") is False for o in options), options
