"""Many members' bundles stacked along a leading axis, and one member's bundles taken back out
of them in compiled code (issue 33: one GPU thread per member).

A bundle of :mod:`stonedem.kernels.step` is a named tuple of arrays, numbers and smaller
named tuples. Its *leaves* (arrays and numbers, depth first in field order) are stacked
member by member: a number becomes an array over the members, an array gains a leading
member axis and is padded along its first axis to the longest member's (records differ in
length); ``lengths[m, k]`` keeps member m's own length of leaf k. :func:`member_bundles`
slices member m's leaves back out, so :func:`stonedem.kernels.step.run_steps` sees each
member exactly as a single run would, on the CPU and in a CUDA thread alike.

Numba cannot walk a named tuple's fields in compiled code, so :func:`member_bundles` is
written out from the bundle classes when this module is imported: it always matches them.
"""

import numpy as np
from numba import njit

from stonedem.kernels import JIT_OPTIONS, step

BUNDLES = (step.Model, step.Settings, step.State, step.Samples, step.Work)
# the bundles :func:`stonedem.kernels.step.run_steps` writes (copied back to each member)
WRITTEN = (step.State, step.Samples)
SCALAR_DTYPES = {float: np.float64, int: np.int64, bool: np.bool_}


def _is_bundle(kind) -> bool:
    """Whether a field's annotation is a named tuple class (a bundle within the bundle)."""
    return isinstance(kind, type) and issubclass(kind, tuple) and hasattr(kind, "_fields")


def leaf_kinds(cls) -> list[tuple[str, object]]:
    """(dotted path, np.ndarray or float, int, bool) of each leaf of a bundle class, depth first."""
    out = []
    for name, kind in cls.__annotations__.items():
        if _is_bundle(kind):
            out += [(f"{name}.{path}", leaf) for path, leaf in leaf_kinds(kind)]
        elif kind is np.ndarray or kind in SCALAR_DTYPES:
            out.append((name, kind))
        else:
            raise TypeError(
                f"{cls.__name__}.{name}: a bundle holds arrays, float, int, bool or named tuples"
            )
    return out


def _constructor(cls, first: int) -> tuple[str, int]:
    """Source of ``cls(...)`` over leaves first, first + 1, ... of member m; the next free leaf."""
    parts = []
    k = first
    for kind in cls.__annotations__.values():
        if _is_bundle(kind):
            source, k = _constructor(kind, k)
            parts.append(source)
        elif kind is np.ndarray:
            parts.append(f"leaves[{k}][m, :lengths[m, {k}]]")
            k += 1
        else:
            parts.append(f"leaves[{k}][m]")
            k += 1
    return f"{cls.__name__}({', '.join(parts)})", k


def _member_bundles_source() -> str:
    k = 0
    constructors = []
    for cls in BUNDLES:
        source, k = _constructor(cls, k)
        constructors.append(source)
    body = ",\n            ".join(constructors)
    return f"def member_bundles(leaves, lengths, m):\n    return ({body})\n"


N_LEAVES = sum(len(leaf_kinds(cls)) for cls in BUNDLES)
_namespace = {
    cls.__name__: cls for cls in (*BUNDLES, step.Law, step.Excitation, step.Watch, step.Links)
}
exec(compile(_member_bundles_source(), f"<{__name__}.member_bundles>", "exec"), _namespace)
# not cached: Numba caches only functions that live in a source file
member_bundles = njit(**{**JIT_OPTIONS, "cache": False, "inline": "always"})(
    _namespace["member_bundles"]
)
member_bundles.__doc__ = (
    """(model, settings, state, samples, work) of member m: views into the stacked leaves."""
)


# ---------------------------------------------------------------- plain Python: stack and copy back


def leaves_of(bundle) -> list:
    """The leaves of one bundle instance, depth first in field order (as :func:`leaf_kinds`)."""
    out = []
    for value in bundle:
        if isinstance(value, tuple) and hasattr(value, "_fields"):
            out += leaves_of(value)
        else:
            out.append(value)
    return out


def member_leaves(member: tuple) -> list:
    """The leaves of a member's (model, settings, state, samples, work), in stacking order."""
    return [leaf for bundle in member for leaf in leaves_of(bundle)]


def stack(members: list[tuple], member_fastest: bool = False) -> tuple[tuple, np.ndarray]:
    """(leaves, lengths) of members, each a (model, settings, state, samples, work) tuple:
    every leaf stacked over the members, arrays padded along their first axis (the padding
    is never read: each member's slice is its own length). Members must share every other
    axis (one structure); a ValueError names the leaf that differs.

    ``member_fastest`` lays the stacked arrays out in Fortran order, the member index varying
    fastest in memory: the GPU's threads (members) of a warp then read one element of their
    members from adjacent addresses, in one memory transaction instead of 32. The CPU keeps
    each member's arrays together (C order), for its caches."""
    order = "F" if member_fastest else "C"
    names = [f"{cls.__name__}.{path}" for cls in BUNDLES for path, _ in leaf_kinds(cls)]
    kinds = [kind for cls in BUNDLES for _, kind in leaf_kinds(cls)]
    flat = [member_leaves(member) for member in members]
    n = len(members)
    lengths = np.zeros((n, N_LEAVES), dtype=np.int64, order=order)
    leaves = []
    for k, (name, kind) in enumerate(zip(names, kinds)):
        column = [member[k] for member in flat]
        if kind is not np.ndarray:
            leaves.append(np.array(column, dtype=SCALAR_DTYPES[kind]))
            continue
        arrays = [np.asarray(a) for a in column]
        rest = {a.shape[1:] for a in arrays}
        if len(rest) > 1 or len({a.dtype for a in arrays}) > 1:
            raise ValueError(
                f"{name}: members differ in shape {sorted(rest)} or type: they must share one "
                "structure"
            )
        lengths[:, k] = [a.shape[0] for a in arrays]
        out = np.zeros(
            (n, int(lengths[:, k].max()), *arrays[0].shape[1:]), dtype=arrays[0].dtype, order=order
        )
        for m, a in enumerate(arrays):
            out[m, : a.shape[0]] = a
        leaves.append(out)
    return tuple(leaves), lengths


def written_leaves() -> list[int]:
    """Indices of the leaves :func:`stonedem.kernels.step.run_steps` writes (State and Samples)."""
    out, k = [], 0
    for cls in BUNDLES:
        n = len(leaf_kinds(cls))
        if cls in WRITTEN:
            out += range(k, k + n)
        k += n
    return out


def copy_back(leaves, lengths, members: list[tuple]) -> None:
    """Copy the written leaves (State, Samples) of each member back into its own arrays."""
    flat = [member_leaves(member) for member in members]
    for k in written_leaves():
        for m, member in enumerate(flat):
            member[k][...] = leaves[k][m, : lengths[m, k]]
