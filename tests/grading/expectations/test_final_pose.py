"""``final_pose_within``: where the robot ended, and facing which way."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from grading.expectations.runs import _judge, _mistake, _north, _params, _record

from roboscript.grading.expectations import (
    FinalPose,
    final_pose_target,
)
from roboscript.grading.record import Verdict


def test_final_pose_margin_is_signed_in_centimetres() -> None:
    record = _record(_north(5.0))  # ends at (0, 500)
    near = _judge(FinalPose(0.0, 521.0, 80.0), record)
    assert near.passed
    assert near.margin == "passed by 5.9 cm"
    assert near.margin_value == pytest.approx(59.0)
    far = _judge(FinalPose(0.0, 600.0, 80.0), record)
    assert not far.passed
    assert far.margin == "failed by 2.0 cm"
    assert far.first_violation_s == 5.0


def test_final_pose_relative_to_the_start_follows_the_start_heading() -> None:
    # Start at (100, 0) facing east (90°): "50 cm ahead" is (600, 0) in the world.
    path = [(0.0, 100.0, 0.0, 90.0), (5.0, 600.0, 10.0, 90.0)]
    target = FinalPose(0.0, 500.0, 30.0, heading_deg=0.0, relative_to="start")
    verdict = _judge(target, _record(path))
    assert verdict.passed, verdict.detail
    assert verdict.margin == "passed by 2.0 cm"


def test_final_pose_heading_outside_its_tolerance_fails_in_degrees() -> None:
    path = [(0.0, 0.0, 0.0, 0.0), (2.0, 0.0, 0.0, 40.0)]
    verdict = _judge(FinalPose(0.0, 0.0, 50.0, 0.0, 15.0), _record(path))
    assert not verdict.passed
    assert verdict.margin == "failed by 25.0°"
    assert verdict.margin_unit == "deg"


def test_final_pose_reads_with_units_and_defaults(tmp_path: Path) -> None:
    pose = _params(tmp_path, "final_pose_within: {x: 1 m, y: -20 cm, radius: 5 cm}")
    assert pose == FinalPose(1000.0, -200.0, 50.0, None, 15.0, "world")
    facing = _params(
        tmp_path,
        "final_pose_within: {x: 0, y: 0, radius: 5 cm, heading: 0.25 rev,"
        " heading_tolerance: 5 deg, relative_to: start}",
    )
    assert facing == FinalPose(0.0, 0.0, 50.0, 90.0, 5.0, "start")


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        (
            "final_pose_within: {x: 0, y: 0, radius: 5 cm, heading_tolerance: 5 deg}",
            "4:51: error: heading_tolerance needs a heading to compare with",
        ),
        (
            "final_pose_within: {x: 0, y: 0, radius: 0 cm}",
            "4:45: error: 'radius' must be more than 0",
        ),
        (
            "final_pose_within: {x: 0, y: 0, radius: 1, relative_to: here}",
            "4:61: error: 'relative_to' must be one of: world, start (got 'here')",
        ),
        ("final_pose_within: {x: 0, radius: 1}", "4:24: error:"),
    ],
)
def test_mistakes_in_final_pose_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


@pytest.mark.parametrize(("x", "passed"), [(80.0, True), (-80.0, True), (81.0, False)])
def test_the_final_pose_radius_counts_sideways_error_and_is_inclusive(
    x: float, passed: bool
) -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, x, 500.0, 0.0)])
    verdict = _judge(FinalPose(0.0, 500.0, 80.0), record)
    assert verdict.passed is passed
    assert verdict.first_violation_s == (None if passed else 5.0)


def test_the_final_pose_verdict_names_where_it_ended_and_what_was_allowed() -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 30.0, 540.0, 0.0)])
    verdict = _judge(FinalPose(0.0, 500.0, 80.0), record)
    assert verdict == Verdict(
        "final_pose_within",
        True,
        "passed by 3.0 cm",
        None,
        "ended at (30, 540) mm, 5.0 cm from the target (0, 500) mm (allowed 8.0 cm)",
        30.0,
        "mm",
        30.0 / 80.0,
    )


@pytest.mark.parametrize(("heading", "passed"), [(15.0, True), (345.0, True), (15.5, False)])
def test_the_final_heading_tolerance_is_inclusive(heading: float, passed: bool) -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 500.0, heading)])
    target = FinalPose(0.0, 500.0, 80.0, heading_deg=0.0, heading_tolerance_deg=15.0)
    assert _judge(target, record).passed is passed


def test_the_tighter_of_position_and_heading_gives_the_margin() -> None:
    # 6 cm inside an 8 cm radius (75 % spare) but 12 of 15 degrees off (20 % spare)
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 520.0, 12.0)])
    target = FinalPose(0.0, 500.0, 80.0, heading_deg=0.0, heading_tolerance_deg=15.0)
    verdict = _judge(target, record)
    assert verdict.passed
    assert verdict.margin == "passed by 3.0°"
    assert (verdict.margin_value, verdict.margin_unit) == (3.0, "deg")
    assert verdict.relative_margin == pytest.approx(3.0 / 15.0)
    assert verdict.detail.endswith("; heading 12°, 12.0° off (allowed 15.0°)")
    assert verdict.detail.startswith("ended at (0, 520) mm")
    # heading well inside, position tight: the position's margin stays
    near = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 570.0, 1.0)])
    assert _judge(target, near).margin_unit == "mm"


def test_a_target_relative_to_a_slanted_start_is_turned_with_it() -> None:
    # Start at (50, -20) facing 30°: 100 mm to its right and 200 mm ahead is (236.6, 103.2)
    # in the world, and 10° from its heading is 40°.
    record = _record([(0.0, 50.0, -20.0, 30.0), (5.0, 236.6, 103.2, 41.0)])
    target = FinalPose(100.0, 200.0, 50.0, 10.0, 15.0, "start")
    world = final_pose_target(target, record)
    assert (world.x_mm, world.y_mm, world.heading_deg) == (
        pytest.approx(236.603, abs=1e-3),
        pytest.approx(103.205, abs=1e-3),
        40.0,
    )
    assert (world.radius_mm, world.heading_tolerance_deg, world.relative_to) == (
        50.0,
        15.0,
        "world",
    )
    assert final_pose_target(replace(target, heading_deg=None), record).heading_deg is None
    verdict = _judge(target, record)
    assert verdict.detail == (
        "ended at (237, 103) mm, 0.0 cm from the target (237, 103) mm (allowed 5.0 cm);"
        " heading 41°, 1.0° off (allowed 15.0°)"
    )
