"""The thesis' ref. [70] finding read from a links cube (stonedem.figures.links.finding), on a
synthetic cube whose answer is known."""

import numpy as np
import pytest
import xarray as xr

from stonedem.figures.links import finding

PGA = np.array([1.0, 2.0, 4.0, 8.0])


def _cube(linked_sliding, linked_first_collapse):
    """Two records; the unlinked column slides 2, 4, 6 mm and falls at 8 m/s2; the linked
    one slides ``linked_sliding`` [mm] and falls from ``linked_first_collapse``."""
    kinds = ["none", "titanium"]
    sliding = np.zeros((2, 4, 2))
    collapsed = np.zeros((2, 4, 2), dtype=np.int8)
    sliding[0, :3, :] = np.array([2.0, 4.0, 6.0])[:, None] * 1e-3
    sliding[1, :3, :] = np.array(linked_sliding)[:, None] * 1e-3
    collapsed[0, PGA >= 8.0, :] = 1
    collapsed[1, PGA >= linked_first_collapse, :] = 1
    rocking = np.zeros((2, 4, 2, 3))
    return xr.Dataset(
        {
            "residual_total_sliding": (("link_kind", "pga", "record"), sliding),
            "collapsed": (("link_kind", "pga", "record"), collapsed),
            "rocking": (("link_kind", "pga", "record", "time"), rocking),
        },
        coords={"link_kind": kinds, "pga": PGA, "record": ["a", "b"], "time": [0.0, 1.0, 2.0]},
    )


def test_fewer_displacements_in_most_cases_and_no_later_collapse_is_the_finding():
    row = finding(_cube([1.0, 3.0, 5.0], 8.0), "titanium")
    assert row["moderate_cases"] == 6 and row["fewer_residual_cases"] == 6
    assert row["residual_sliding_linked_mm"] == pytest.approx(18.0, rel=1e-12)
    assert row["finding_shows"] == "yes" and row["collapse_earlier"] == 0


def test_a_lower_sum_from_one_case_of_six_is_no_finding():
    # linked lower in the first PGA only (both records), higher in the other four cases
    row = finding(_cube([0.1, 4.1, 6.1], 8.0), "titanium")
    assert row["residual_sliding_linked_mm"] < row["residual_sliding_unlinked_mm"]
    assert row["fewer_residual_cases"] == 2 and row["fewer_permanent_displacements"] == "no"


def test_a_later_collapse_is_a_gain_and_not_the_finding():
    row = finding(_cube([1.0, 3.0, 5.0], np.inf), "titanium")
    assert row["collapse_later"] == 2 and row["finding_shows"] == "no"
