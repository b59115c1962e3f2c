"""``wall_distance``: the gap kept to a wall on one side."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from grading.expectations.runs import (
    CORRIDOR_SIDE,
    _drifting_right,
    _judge,
    _mistake,
    _north,
    _params,
    _record,
)

from roboscript.grading.expectations import (
    Selection,
    WallDistance,
)
from roboscript.grading.record import Verdict


def test_wall_distance_measures_from_the_side_sensor_with_the_first_violation() -> None:
    # The side sensor sits 80 mm right of the centre: 220 mm from the wall while x = 0.
    states = ((0.0, "approach"), (1.0, "follow"))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    verdict = _judge(rule, _record(_drifting_right(), states=states))
    assert not verdict.passed
    # Below 150 mm once x > 70, i.e. after 5.4 s: the first sample past it is 5.5 s.
    assert verdict.first_violation_s == pytest.approx(5.5)
    # The worst: at 7.9 s (the last sample before the run ends), x = 195: a gap of 25 mm.
    assert verdict.margin == "failed by 12.5 cm"
    assert "the worst was 2.5 cm at 7.9 s" in verdict.detail


def test_wall_distance_passes_by_the_tightest_sample_after_settling() -> None:
    states = ((0.0, "follow"), (4.0, "stop"))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    verdict = _judge(rule, _record(_drifting_right(), states=states))
    assert verdict.passed
    assert verdict.margin == "passed by 3.0 cm"  # 220 mm: 30 mm inside the top of the band
    assert verdict.relative_margin == pytest.approx(30.0 / 50.0)


def test_wall_distance_skips_the_settling_time() -> None:
    # Far from the wall for the first 0.5 s of the state, then in the band.
    path = [(round(i * 0.1, 3), -200.0 if i < 5 else 0.0, i * 10.0, 0.0) for i in range(30)]
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.5)
    )
    assert _judge(rule, _record(path)).passed
    strict = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
    )
    verdict = _judge(strict, _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 0.0


def test_wall_distance_on_the_left_and_a_state_never_entered() -> None:
    rule = WallDistance(
        side="left", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
    )
    assert _judge(rule, _record(_north(3.0))).passed  # left wall: 220 mm
    missing = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow")
    )
    verdict = _judge(missing, _record(_north(3.0)))
    assert not verdict.passed
    assert verdict.detail == "the mission never entered state 'follow'"


def test_wall_distance_reads_with_units_and_defaults(tmp_path: Path) -> None:
    rule = _params(tmp_path, "wall_distance: {state: follow, min: 15 cm, max: 0.25 m}")
    assert rule == WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    left = _params(tmp_path, "wall_distance: {state: f, max: 30 cm, side: left, settle: 2 s}")
    assert left == WallDistance(
        side="left", min_mm=None, max_mm=300.0, selection=Selection(state="f", settle_s=2.0)
    )
    at_least = _params(tmp_path, "wall_distance: {state: f, min: 0 cm, settle: 0 s}")
    assert at_least == WallDistance(
        side="right", min_mm=0.0, max_mm=None, selection=Selection(state="f", settle_s=0.0)
    )


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        ("wall_distance: {state: f}", "4:20: error: wall_distance needs min, max or both"),
        (
            "wall_distance: {state: f, min: 20 cm, max: 20 cm}",
            "4:36: error: min must be less than max",
        ),
        ("wall_distance: {state: f, max: 0 cm}", "4:36: error: 'max' must be more than 0"),
        (
            "wall_distance: {state: f, min: 1 cm, settle: -1 s}",
            "4:50: error: settle cannot be negative",
        ),
        (
            "wall_distance: {state: f, min: 1 cm, side: up}",
            "4:48: error: 'side' must be one of: left, right (got 'up')",
        ),
        (
            "wall_distance: {min: 1 cm, during: whole ru}",
            (
                "4:40: error: during is 'whole run' or a time window such as during: {from: 5 s,"
                " to: 20 s} (got 'whole ru') (did you mean 'whole run'?)"
            ),
        ),
        ("wall_distance: {min: 1 cm, durng: whole run}", "4:32: error: unknown key 'durng'"),
        ("wall_distance: {min: 1 cm, during: {from: 5 s, too: 9 s}}", "4:52: error: unknown"),
        (
            "wall_distance: {min: 1 cm, along: {from: 2 m, to: 1 m}}",
            "4:55: error: 'from' must come before 'to'",
        ),
        (
            "wall_distance: {min: 1 cm, along: {}}",
            "4:39: error: along needs from, to or both, such as along: {from: 50 cm, to: 2.5 m}",
        ),
        (
            "wall_distance: {min: 1 cm, in_region: far-edn}",
            (
                "4:43: error: the world 'corridor' has no region 'far-edn' (its regions: far-end,"
                " start-zone) (did you mean 'far-end'?)"
            ),
        ),
    ],
)
def test_mistakes_in_wall_distance_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


def test_leaving_the_state_before_the_settling_time_fails_the_wall_distance() -> None:
    record = _record(_north(3.0), states=((0.0, "follow"), (0.8, "stop")))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    assert _judge(rule, record) == Verdict(
        "wall_distance",
        False,
        "",
        None,
        "the robot never stayed in 'follow' longer than the 1 s it is given to settle",
    )


def test_the_wall_distance_is_measured_on_the_side_named() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    right = _judge(
        WallDistance(
            side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
        ),
        record,
    )
    assert right.passed
    assert right.detail == (
        "in 'go' the right gap must stay between 15.0 cm and 25.0 cm;"
        " the worst was 22.0 cm at 0.0 s"  # the gap never changes: the first sample
    )
    left = _judge(
        WallDistance(
            side="left", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
        ),
        record,
    )
    assert not left.passed
    assert left.first_violation_s == 0.0


def test_with_no_wall_in_sight_an_at_least_band_passes_and_an_at_most_band_fails() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    at_least = WallDistance(
        side="left", min_mm=150.0, selection=Selection(state="go", settle_s=0.0)
    )
    assert _judge(at_least, record) == Verdict(
        "wall_distance", True, "", None, "no left wall was ever closer than allowed"
    )
    at_most = WallDistance(side="left", max_mm=250.0, selection=Selection(state="go", settle_s=0.0))
    assert _judge(at_most, record) == Verdict(
        "wall_distance",
        False,
        "",
        0.0,
        "in 'go' the left gap must stay at most 25.0 cm; the worst was no wall in sight at 0.0 s",
    )


def test_one_sided_wall_bands_judge_the_side_they_bound() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)  # 220 mm on the right
    assert _judge(
        WallDistance(min_mm=200.0, selection=Selection(state="go", settle_s=0.0)), record
    ).passed
    too_far = _judge(
        WallDistance(max_mm=200.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert (too_far.passed, too_far.margin) == (False, "failed by 2.0 cm")
    assert too_far.relative_margin == pytest.approx(-20.0 / 200.0)
    too_close = _judge(
        WallDistance(min_mm=250.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert (too_close.passed, too_close.margin) == (False, "failed by 3.0 cm")
    assert "must stay at least 25.0 cm" in too_close.detail


def test_a_record_without_a_world_has_no_wall_to_be_near() -> None:
    record = replace(_record(_north(3.0)), world=None)
    verdict = _judge(
        WallDistance(min_mm=150.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed


@pytest.mark.parametrize(("top_mm", "passed"), [(220.0, True), (220.5, True), (219.5, False)])
def test_the_edge_of_a_wall_band_is_inside_it(top_mm: float, passed: bool) -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)  # 220 mm on the right
    verdict = _judge(
        WallDistance(max_mm=top_mm, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed is passed
    assert (verdict.margin_value, verdict.margin_unit) == (top_mm - 220.0, "mm")


def test_an_at_least_0_band_has_no_share_to_give() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    verdict = _judge(
        WallDistance(min_mm=0.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed
    assert verdict.relative_margin is None


def test_a_wall_distance_in_a_state_never_entered_fails_with_no_margin() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    assert _judge(
        WallDistance(min_mm=150.0, selection=Selection(state="follow")), record
    ) == Verdict("wall_distance", False, "", None, "the mission never entered state 'follow'")
