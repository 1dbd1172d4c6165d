"""Hunt-and-fill collapse-threshold search (stonedem.study.search) on known thresholds."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from stonedem.errors import InputError
from stonedem.study.grid import SEARCH_PARAMETERS
from stonedem.study.search import (
    BRACKETED,
    COLLAPSE_AT_MINIMUM,
    FINEST_TOLERANCE,
    NO_COLLAPSE,
    ROUNDING,
    Run,
    SearchSettings,
    next_value,
    search,
    search_together,
    summary,
)

SETTINGS = SearchSettings()


@pytest.mark.parametrize("threshold", [0.2, 1.0, 1.37, 3.0001, 12.3, 27.69, 63.0])
def test_a_monotonic_threshold_is_bracketed_within_the_tolerance(threshold):
    runs = search(lambda value, phase: value >= threshold, SETTINGS)
    result = summary(runs, SETTINGS)
    assert result["status"] == BRACKETED and result["monotonic"]
    assert result["lower"] < threshold <= result["upper"]
    assert result["width"] <= SETTINGS.tolerance
    # hunt + five bisections + three fills, at most (1.8 < 1.02 ** 32)
    assert len(runs) <= math.ceil(math.log(64 / 0.125) / math.log(1.8)) + 5 + 3
    assert [r.phase for r in runs].count("bisect") <= 5
    assert [r.phase for r in runs].count("fill") <= SETTINGS.fill


def test_a_collapse_found_by_a_fill_run_lowers_the_threshold_and_reports_resurrections():
    # collapses in a window [2.0, 2.6] the hunt steps over (1.8, 3.24 survive), and above 10
    def collapses(value, phase):
        return 2.0 <= value <= 2.6 or value >= 10.0

    runs = search(collapses, SearchSettings(fill=6))
    result = summary(runs, SearchSettings(fill=6))
    assert 1.96 <= result["lower"] < 2.0 <= result["upper"] <= 2.04
    assert not result["monotonic"] and 3.24 in result["resurrections"]
    assert result["status"] == BRACKETED


def test_no_collapse_and_collapse_at_the_minimum_end_the_search():
    runs = search(lambda v, p: False, SETTINGS)
    assert summary(runs, SETTINGS)["status"] == NO_COLLAPSE and runs[-1].value == SETTINGS.maximum
    runs = search(lambda v, p: True, SETTINGS)
    assert (
        summary(runs, SETTINGS)["status"] == COLLAPSE_AT_MINIMUM
        and runs[-1].value == SETTINGS.minimum
    )


def test_a_resumed_search_continues_where_it_stopped():
    full = search(lambda v, p: v >= 5.0, SETTINGS)
    resumed = search(lambda v, p: v >= 5.0, SETTINGS, runs=full[:4])
    assert resumed == full
    assert next_value(full, SETTINGS) is None
    assert next_value([Run(1.0, False, "hunt")] * SETTINGS.max_runs, SETTINGS) is None


@pytest.mark.parametrize(
    "spec, field",
    [
        ("pga", "search"),
        ({"parameter": "n_drums"}, "search.parameter"),
        ({"start": -1}, "search.start"),
        ({"factor": 1.01}, "search.factor"),
        ({"tolerance": 1.5}, "search.tolerance"),
        ({"fill": 2.5}, "search.fill"),
        ({"max_runs": 3}, "search.max_runs"),
        ({"speed": 1}, "search.speed"),
        ({"start": 100.0}, "search.start"),
        ({"tolerance": True}, "search.tolerance"),
        ({"tolerance": 1e-6, "max_runs": 1000}, "search.tolerance"),
    ],
)
def test_bad_settings_name_their_field(spec, field):
    with pytest.raises(InputError) as error:
        SearchSettings.from_config(spec, "search", SEARCH_PARAMETERS)
    assert error.value.field == field


def test_a_tolerance_finer_than_the_rounding_is_refused_naming_the_finest():
    with pytest.raises(
        InputError,
        match=r"search\.tolerance: must be >= 0\.001 and < 1, got 1e-06; "
        r"give tolerance >= 0\.001, the finest the search can do \(values run are rounded",
    ):
        SearchSettings.from_config(
            {"tolerance": 1e-6, "max_runs": 1000}, "search", SEARCH_PARAMETERS
        )
    assert (
        SearchSettings.from_config({"tolerance": 0.001}, "search", SEARCH_PARAMETERS).tolerance
        == FINEST_TOLERANCE
    )


@pytest.mark.parametrize(
    "threshold", [0.01001, 0.1234567, 1.001, 1.23456789, 9.9995, 10.001, 63.999]
)
def test_the_finest_tolerance_is_reached(threshold):
    settings = SearchSettings(tolerance=FINEST_TOLERANCE, minimum=0.01, max_runs=100)
    result = summary(search(lambda value, phase: value >= threshold, settings), settings)
    assert result["status"] == BRACKETED and result["width"] <= FINEST_TOLERANCE
    assert result["lower"] < threshold <= result["upper"]


def test_a_search_the_rounding_stops_short_of_its_tolerance_says_so():
    # settings made in code, past the config's check: 1.234 ... 1.235 is as narrow as 4 digits go
    settings = SearchSettings(tolerance=1e-6, max_runs=1000)
    result = summary(search(lambda value, phase: value >= 1.23456789, settings), settings)
    assert (result["lower"], result["upper"]) == (1.234, 1.235)
    assert result["status"] == ROUNDING and result["width"] == pytest.approx(8.1e-4, rel=1e-3)


def test_every_second_fill_run_looks_above_the_threshold_for_resurrections():
    # collapses from 1.85 to 2.5 and from 3.0: the hunt (1.8, 3.24) and bisection see a
    # monotonic threshold; the fill above it (2.797, between 2.415 and 3.24) survives
    runs = search(lambda value, phase: 1.85 <= value < 2.5 or value >= 3.0, SETTINGS)
    result = summary(runs, SETTINGS)
    assert [r.phase for r in runs if r.phase == "fill"] == ["fill"] * 3
    assert result["resurrections"] == [2.797] and not result["monotonic"]
    assert 1.8 < result["lower"] < 1.85 <= result["upper"] and result["status"] == BRACKETED


# collapse as a function of the intensity: a threshold, windows of collapse below it (found by
# fills or not), windows of survival above it (resurrections)
windows = st.lists(st.tuples(st.floats(0.1, 70.0), st.floats(1.0, 1.5), st.booleans()), max_size=3)


def outcome_rule(threshold, windows):
    def collapses(value):
        for low, ratio, collapse in windows:
            if low <= value <= low * ratio:
                return collapse
        return value >= threshold

    return collapses


@given(
    st.lists(st.tuples(st.floats(0.1, 80.0), windows), min_size=1, max_size=4),
    st.sampled_from([1, 3, 8, 32]),
    st.sampled_from(
        [
            SETTINGS,
            SearchSettings(start=4.0, fill=5),
            SearchSettings(factor=3.0, tolerance=0.05, fill=0),
        ]
    ),
)
def test_searches_together_make_exactly_the_runs_each_search_makes_alone(systems, width, settings):
    rules = [outcome_rule(threshold, w) for threshold, w in systems]
    asked = []

    def run_many(requests):
        asked.append(len(requests))
        return [rules[i](value) for i, value, _ in requests]

    together, rounds = search_together(run_many, [settings] * len(rules), width)
    for rule, runs in zip(rules, together):
        assert runs == search(lambda value, phase, rule=rule: rule(value), settings)
    assert rounds == len(asked) and max(asked) <= width * len(rules)
    if width == 1:  # one run a round: the sequential search itself
        assert rounds == max(len(runs) for runs in together)
    else:
        assert rounds <= max(len(runs) for runs in together)


def test_wide_rounds_need_fewer_rounds_than_runs():
    runs, rounds = search_together(
        lambda requests: [value >= 12.3 for _, value, _ in requests], [SETTINGS], 16
    )
    assert runs[0] == search(lambda value, phase: value >= 12.3, SETTINGS)
    assert rounds <= len(runs[0]) / 2  # 3 rounds for 14 runs (measured)


@pytest.mark.parametrize("width", [0, -1, 2.5, True, "8"])
def test_a_bad_width_is_refused(width):
    with pytest.raises(InputError, match="width"):
        search_together(lambda requests: [], [SETTINGS], width)
