"""Scene builders: taper at constant mass, stacking without gaps, epistyle types of Table 7.2."""

import numpy as np
import pytest

from stonedem.engine import geometry
from stonedem.engine.scene import scene_from_dict
from stonedem.engine.structures import (
    build_structure,
    colonnade,
    standalone_column,
    two_tier_colonnade,
)
from stonedem.errors import InputError


def verts(body):
    if "polygon" in body:
        return np.array(body["polygon"]["vertices"], dtype=float)
    b = body["box"]
    return geometry.box_vertices(b["width"], b["height"], b["center"])


@pytest.mark.parametrize("taper", [1.0, 1.25, 1.5, 2.0])
def test_taper_keeps_shaft_area_and_stacks_flush(taper):
    bodies = standalone_column(4, taper=taper)
    drums = [b for b in bodies if b.get("role") == "drum"]
    area = sum(geometry.signed_area(verts(b)) for b in drums)
    assert area == pytest.approx(6.0 * 1.0, rel=1e-12), "thesis 6.3.2: constant total mass"
    for low, up in zip(drums[:-1], drums[1:]):
        v0, v1 = verts(low), verts(up)
        assert v0[:, 1].max() == pytest.approx(v1[:, 1].min(), abs=1e-12), "no gap, no overlap"
        top = np.sort(v0[v0[:, 1] == v0[:, 1].max(), 0])
        bottom = np.sort(v1[v1[:, 1] == v1[:, 1].min(), 0])
        assert top == pytest.approx(bottom, abs=1e-12), "shared faces of equal width"
    w_bottom = np.ptp(verts(drums[0])[:2, 0])
    w_top = np.ptp(verts(drums[-1])[2:, 0])
    assert w_bottom / w_top == pytest.approx(taper, rel=1e-12)
    for b in drums:
        assert geometry.signed_area(verts(b)) > 0 and geometry.is_convex(verts(b))


def test_colonnade_spacing_and_epistyle_types():
    cap = {"height": 0.6, "width": 1.4}
    spans = {}
    for kind in ("a", "b", "c", "d"):
        bodies = colonnade(n_columns=3, clear_distance=2.5, epistyle_type=kind, capital=cap)
        bases = [b for b in bodies if b.get("role") == "drum"]
        xs = sorted(b["box"]["center"][0] for b in bases)
        assert np.diff(xs) == pytest.approx([3.5, 3.5]), "clear distance + width"
        epis = [verts(b) for b in bodies if b.get("role") == "epistyle"]
        spans[kind] = [(v[:, 0].min(), v[:, 0].max()) for v in epis]
        for v in epis:
            assert v[:, 1].min() == pytest.approx(6.6), "rests on the capitals"
    assert spans["a"] == [pytest.approx((-4.2, 4.2))], "outer edge to outer edge"
    assert spans["c"] == [pytest.approx((-3.5, 3.5))], "centre line to centre line"
    assert [tuple(s) for s in spans["b"]] == [pytest.approx((-4.2, 0.0)), pytest.approx((0.0, 4.2))]
    assert [tuple(s) for s in spans["d"]] == [pytest.approx((-3.5, 0.0)), pytest.approx((0.0, 3.5))]


def test_built_scenes_load_without_initial_overlap():
    for spec in (
        {"kind": "column", "n_drums": 8},
        {"kind": "column", "n_drums": 3, "taper": 1.5, "capital": {"height": 0.6, "width": 1.4}},
        {"kind": "colonnade", "n_columns": 5, "n_drums": 3, "epistyle_type": "per_span"},
        {"kind": "two_tier_colonnade", "lower": {"n_drums": 2}, "upper": {"n_drums": 1}},
    ):
        scene = scene_from_dict({"structure": spec, "solver": {"duration": 0.1}})
        names = scene.body_names
        assert len(set(names)) == len(names)


def test_two_tier_upper_columns_stand_on_the_lower_epistyle():
    bodies = two_tier_colonnade()
    lower_epi = [b for b in bodies if b.get("role") == "epistyle" and not b.get("tier")][0]
    upper_drums = [b for b in bodies if b.get("tier") == 1 and b.get("role") == "drum"]
    top = verts(lower_epi)[:, 1].max()
    assert all(verts(b)[:, 1].min() == pytest.approx(top) for b in upper_drums)
    assert len(upper_drums) == 3


@pytest.mark.parametrize(
    "spec, field",
    [
        ({"kind": "column", "n_drums": 0}, "structure.n_drums"),
        ({"kind": "column", "n_drums": 2, "taper": -1}, "structure.taper"),
        ({"kind": "colonnade", "clear_distance": 0}, "structure.clear_distance"),
        ({"kind": "colonnade", "epistyle_type": "z"}, "structure.epistyle_type"),
        ({"kind": "colonnade", "wings": 2}, "structure.wings"),
        ({"kind": "tower"}, "structure.kind"),
    ],
)
def test_bad_parameters_name_the_field(spec, field):
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        build_structure(spec)
