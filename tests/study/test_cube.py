"""A study cube merges its case pieces up a tree (stonedem.study.cube.merged_pieces): the same
cube as one merge of them all, integers kept where no cell is missing."""

import numpy as np
import pytest
import xarray as xr

from stonedem.study.cube import merged_pieces, on_parameter_dimensions


def _piece(pga, kind, member, n_time=4):
    ds = xr.Dataset(
        {
            "peak": ((), pga * 10 + member),
            "collapsed": ((), np.int8(pga > 2)),
            "theta": ("time", np.arange(n_time) * pga),
        },
        coords={"time": np.arange(n_time) * 0.5, "pga": pga, "kind": kind, "member": member},
    )
    return on_parameter_dimensions(ds, ["pga", "kind", "member"])


@pytest.mark.parametrize("complete", [True, False])
def test_the_tree_gives_the_cube_of_one_merge(complete):
    pieces = [
        _piece(pga, kind, member, n_time=3 + member)
        for pga in (1.0, 2.0, 3.0)
        for kind in ("none", "wood", "titanium")
        for member in range(3)
        if complete or (pga, kind) != (2.0, "wood")
    ]
    flat = xr.merge(pieces, join="outer", compat="no_conflicts", combine_attrs="drop")
    tree = merged_pieces(list(pieces))
    assert tree.identical(flat)
    assert (tree["collapsed"].dtype.kind == "i") == complete  # a missing cell is NaN
    assert list(tree["kind"].values) == ["none", "titanium", "wood"]
