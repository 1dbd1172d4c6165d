"""Cost-per-contact benchmark: the broad phase finds O(N) pairs in a wall of drums, and a
quick measurement returns sane numbers (no timing assertions)."""

import math

import pytest

from benchmarks import contact_cost as cc


@pytest.mark.parametrize(
    "n_body, shape",
    [(1, (1, 1)), (2, (1, 2)), (5, (1, 5)), (20, (2, 10)), (50, (5, 10)), (1000, (100, 10))],
)
def test_sizes_reachable(n_body, shape):
    assert cc.drum_wall_size(n_body) == shape


def test_drum_wall_scene_is_valid():
    scene = cc.drum_wall(20)
    assert len(scene.bodies) == 21
    assert sum(b.driven for b in scene.bodies) == 1
    assert {b.column for b in scene.bodies if not b.driven} == {0, 1}
    assert scene.horizontal.kind != 0  # harmonic base motion
    # the point law with its scene defaults unless told otherwise
    law = scene.contact
    assert (law.model, law.k_n, law.damping, law.impact) == (
        "point",
        cc.K_N_POINT,
        cc.ZETA,
        "plastic",
    )
    area = cc.drum_wall(20, model="area").contact
    assert (area.model, area.k_n, area.c_n) == ("area", cc.K_N_AREA, cc.C_N)
    with pytest.raises(ValueError, match="unknown contact model"):
        cc.drum_wall_scene(1, 1, model="points")


def test_broad_phase_pairs_grow_linearly():
    counts = {}
    for n in (1, 20, 200):
        counts[n] = cc.candidate_pairs_at_rest(cc.drum_wall(n))
        assert counts[n] >= n  # every free body rests on something
        assert counts[n] <= 4 * n + 8  # sort-and-sweep: O(n); all pairs would be ~n^2 / 2
    assert counts[200] < (200 * 201 // 2) / 20
    # linear: 10x the bodies gives about 10x the pairs
    assert 8.0 <= counts[200] / counts[20] <= 12.0


def test_broad_phase_cost_counts_all_pairs():
    scene = cc.drum_wall(20)
    cost = cc.broad_phase_cost(scene, min_seconds=0.001)
    assert cost["all_pairs_tested"] == 21 * 20 // 2  # one driven body: no pair skipped
    assert cost["sweep_pairs"] <= cost["all_pairs_tested"]
    assert cost["sweep_seconds"] > 0 and cost["all_pairs_seconds"] > 0


@pytest.mark.parametrize("model", cc.CONTACT_MODELS)
def test_quick_measure_is_finite_and_positive(model):
    scene = cc.drum_wall(20, model=model)
    row = cc.measure(scene, 0.05, warm_duration=0.005)
    for key in (
        "steps",
        "mean_contacts",
        "kernel_seconds",
        "total_seconds",
        "ns_per_contact_step",
        "ns_per_body_step",
        "kernel_per_step",
        "dt",
    ):
        assert math.isfinite(row[key]) and row[key] > 0, key
    assert 0.0 <= row["outside_fraction"] < 1.0
    assert row["kernel_seconds"] <= row["total_seconds"]
    assert row["n_free"] == 20
    if model == "area":
        assert row["mean_contacts"] >= row["n_free"]  # each drum rests on something
    else:
        # measured 19.98: the plastic landing takes the preload of every resting contact at
        # t = 0 as a landing and forgives it, so the stack starts without contact forces,
        # settles and bounces: 1-2 of the 20 joints open briefly (samples at 1.25-1.75 ms)
        assert row["mean_contacts"] >= 0.99 * row["n_free"]
        assert row["max_contacts"] == row["n_free"]
    assert row["status"] == 0


def test_linear_fit_recovers_a_line():
    fit = cc.linear_fit([1, 10, 100, 1000], [2 + 3 * x for x in (1, 10, 100, 1000)])
    assert fit["slope"] == pytest.approx(3.0)
    assert fit["intercept"] == pytest.approx(2.0)
    assert fit["r2"] == pytest.approx(1.0)
