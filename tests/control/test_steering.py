"""Steering loops: turn-rate corrections, degrees per second, clockwise (right) positive."""

from __future__ import annotations

import math

import pytest

from roboscript.control import (
    HeadingHold,
    LineFollower,
    WallFollower,
    angle_error_deg,
    wheel_speeds,
)


@pytest.mark.parametrize(
    ("target", "measured", "error"),
    [
        (10.0, 350.0, 20.0),
        (350.0, 10.0, -20.0),
        (90.0, 0.0, 90.0),
        (0.0, 180.0, -180.0),
        (180.0, 0.0, -180.0),
        (720.0, 0.0, 0.0),
        (-170.0, 170.0, 20.0),
    ],
)
def test_angle_error_is_the_short_way_round(target: float, measured: float, error: float) -> None:
    assert angle_error_deg(target, measured) == pytest.approx(error)


def test_wheel_speeds_turn_right_with_the_left_wheel_faster() -> None:
    left, right = wheel_speeds(100.0, 90.0, 160.0)
    delta = math.radians(90.0) * 80.0
    assert (left, right) == pytest.approx((100.0 + delta, 100.0 - delta))
    assert wheel_speeds(0.0, -45.0, 200.0) == pytest.approx(
        (-math.radians(45.0) * 100.0, math.radians(45.0) * 100.0)
    )
    assert wheel_speeds(120.0, 0.0, 160.0) == (120.0, 120.0)


def test_heading_hold_turns_towards_the_target_the_short_way() -> None:
    hold = HeadingHold((2.0, 0.0, 0.0), max_rate_deg_s=100.0)
    assert hold.update(10.0, 0.0, 0.02) == pytest.approx(20.0)  # target to the right
    hold = HeadingHold((2.0, 0.0, 0.0), max_rate_deg_s=100.0)
    assert hold.update(350.0, 10.0, 0.02) == pytest.approx(-40.0)  # left across north
    hold = HeadingHold((2.0, 0.0, 0.0), max_rate_deg_s=100.0)
    assert hold.update(0.0, 0.0, 0.02) == 0.0


def test_heading_hold_is_limited_to_its_max_rate() -> None:
    hold = HeadingHold((5.0, 0.0, 0.0), max_rate_deg_s=30.0)
    assert hold.update(90.0, 0.0, 0.02) == 30.0
    assert hold.update(-90.0, 0.0, 0.02) == -30.0


@pytest.mark.parametrize(("side", "sign"), [("right", 1.0), ("left", -1.0)])
def test_wall_follower_turns_away_from_a_close_wall_and_towards_a_far_one(
    side: str, sign: float
) -> None:
    close = WallFollower((0.5, 0.0, 0.0), 200.0, side)
    assert close.update(150.0, 0.0, 0.02) * sign < 0.0  # away from the wall
    far = WallFollower((0.5, 0.0, 0.0), 200.0, side)
    assert far.update(260.0, 0.0, 0.02) * sign > 0.0  # towards it
    exact = WallFollower((0.5, 0.0, 0.0), 200.0, side)
    assert exact.update(200.0, 0.0, 0.02) == 0.0


def test_wall_follower_remembers_the_wall_direction_and_holds_it_without_an_echo() -> None:
    loop = WallFollower((0.5, 0.0, 0.0), 200.0, "right")
    loop.update(200.0, 30.0, 0.02)
    assert loop.wall_heading_deg == 30.0
    # no echo: steer back to the wall's direction
    assert loop.update(None, 40.0, 0.02) < 0.0
    assert loop.update(None, 20.0, 0.02) > 0.0


def test_wall_follower_limits_the_approach_angle() -> None:
    loop = WallFollower(
        (10.0, 0.0, 0.0),
        200.0,
        "right",
        max_approach_deg=20.0,
        heading_gains=(1.0, 0.0, 0.0),
        max_rate_deg_s=1000.0,
    )
    # far from the wall: approach at most 20 degrees, so the turn is 20 deg/s with kp 1
    assert loop.update(2000.0, 0.0, 0.02) == pytest.approx(20.0)


def test_wall_follower_corrects_an_angled_reading_by_the_cosine() -> None:
    loop = WallFollower(
        (1.0, 0.0, 0.0),
        200.0,
        "right",
        heading_gains=(1.0, 0.0, 0.0),
        max_approach_deg=90.0,
        max_rate_deg_s=1000.0,
    )
    loop.update(200.0, 0.0, 0.02)
    # 60 degrees off the wall, a 400 mm reading is a 200 mm gap: on target, approach 0,
    # and the heading loop turns back towards the wall's direction (left)
    assert loop.update(400.0, 60.0, 0.02) == pytest.approx(-60.0, abs=1e-6)


@pytest.mark.parametrize(
    ("readings", "position"),
    [
        ((0.0, 1000.0, 0.0), 0.0),
        ((1000.0, 0.0, 0.0), -1.0),
        ((0.0, 0.0, 1000.0), 1.0),
        ((1000.0, 1000.0, 0.0), -0.5),
        ((0.0, 1000.0), 1.0),
    ],
)
def test_line_position_is_the_darkness_weighted_mean(
    readings: tuple[float, ...], position: float
) -> None:
    assert LineFollower.position(readings, 500.0) == pytest.approx(position)


def test_no_line_under_the_sensors_is_none() -> None:
    assert LineFollower.position((100.0, 400.0, 100.0), 500.0) is None
    assert LineFollower.position((), 500.0) is None


def test_bare_floor_below_a_quarter_threshold_is_ignored() -> None:
    # the left sensor reads floor noise (100 < 500 / 4): it does not pull the position
    assert LineFollower.position((100.0, 900.0, 0.0), 500.0) == pytest.approx(0.0)
    assert LineFollower.position((900.0,), 500.0) == pytest.approx(-1.0)


def test_line_follower_turns_towards_the_line() -> None:
    loop = LineFollower((100.0, 0.0, 0.0), max_rate_deg_s=150.0)
    assert loop.update(-0.5, 0.0, 0.02) == pytest.approx(-50.0)  # line to the left: turn left
    assert loop.update(0.5, 0.0, 0.02) == pytest.approx(50.0)
    assert loop.update(1.0, -0.35, 0.02) == pytest.approx(135.0)  # follow the right edge
    assert loop.update(1.0, -1.0, 0.02) == 150.0  # limited


def test_heading_hold_integrates_over_the_scheduler_dt() -> None:
    # ki 1 deg/s per degree-second: 10 degrees off for 0.5 s twice is 5 then 10 deg/s
    hold = HeadingHold((0.0, 1.0, 0.0), max_rate_deg_s=100.0)
    assert hold.update(10.0, 0.0, 0.5) == pytest.approx(5.0)
    assert hold.update(10.0, 0.0, 0.5) == pytest.approx(10.0)


def test_wall_follower_integrates_both_loops_over_the_scheduler_dt() -> None:
    # outer ki: 100 mm too far for 0.5 s is 0.1 * 100 * 0.5 = 5 degrees of approach;
    # inner ki: 5 degrees off for 0.5 s is 2.5 deg/s
    loop = WallFollower(
        (0.0, 0.1, 0.0), 200.0, "right", heading_gains=(0.0, 1.0, 0.0), max_rate_deg_s=100.0
    )
    assert loop.update(300.0, 0.0, 0.5) == pytest.approx(2.5)


def test_wall_follower_without_an_echo_on_the_wall_direction_goes_straight() -> None:
    loop = WallFollower((0.5, 0.0, 0.0), 200.0, "left")
    loop.update(200.0, 30.0, 0.02)
    assert loop.update(None, 30.0, 0.02) == 0.0


def test_wall_follower_defaults_limit_the_approach_to_25_degrees_and_the_turn_to_60() -> None:
    steep = WallFollower((10.0, 0.0, 0.0), 200.0, "right", heading_gains=(1.0, 0.0, 0.0))
    assert steep.update(2000.0, 0.0, 0.02) == pytest.approx(25.0)
    fast = WallFollower((10.0, 0.0, 0.0), 200.0, "right", max_approach_deg=90.0)
    assert fast.update(2000.0, 0.0, 0.02) == pytest.approx(60.0)


def test_a_left_wall_follower_turns_left_towards_a_far_wall_by_the_same_angle() -> None:
    loop = WallFollower(
        (10.0, 0.0, 0.0),
        200.0,
        "left",
        max_approach_deg=20.0,
        heading_gains=(1.0, 0.0, 0.0),
        max_rate_deg_s=1000.0,
    )
    assert loop.update(2000.0, 0.0, 0.02) == pytest.approx(-20.0)


def test_a_left_wall_follower_corrects_an_angled_reading_by_the_cosine() -> None:
    loop = WallFollower(
        (1.0, 0.0, 0.0),
        200.0,
        "left",
        heading_gains=(1.0, 0.0, 0.0),
        max_approach_deg=90.0,
        max_rate_deg_s=1000.0,
    )
    loop.update(200.0, 0.0, 0.02)
    # turned 60 degrees right, away from a wall on the left: 400 mm read is 200 mm of gap
    assert loop.update(400.0, 60.0, 0.02) == pytest.approx(-60.0, abs=1e-6)


def test_a_line_exactly_at_the_threshold_is_seen() -> None:
    assert LineFollower.position((0.0, 500.0, 0.0), 500.0) == pytest.approx(0.0)


def test_floor_noise_just_under_a_quarter_threshold_does_not_pull_the_position() -> None:
    assert LineFollower.position((120.0, 900.0, 0.0), 500.0) == pytest.approx(0.0)


def test_line_position_works_for_sensors_reading_fractions() -> None:
    # reflected-light sensors that report 0..1 instead of raw counts
    assert LineFollower.position((0.0, 0.6, 0.0), 0.5) == pytest.approx(0.0)
    assert LineFollower.position((0.6, 0.0, 0.0), 0.5) == pytest.approx(-1.0)


def test_a_zero_threshold_on_a_blank_floor_is_no_line() -> None:
    assert LineFollower.position((0.0, 0.0, 0.0), 0.0) is None


def test_line_follower_on_target_goes_straight() -> None:
    loop = LineFollower((100.0, 0.0, 0.0))
    assert loop.update(0.0, 0.0, 0.02) == 0.0


def test_line_follower_default_limit_is_120_deg_s() -> None:
    loop = LineFollower((1000.0, 0.0, 0.0))
    assert loop.update(-1.0, 0.0, 0.02) == -120.0


def test_line_follower_integrates_over_the_scheduler_dt() -> None:
    loop = LineFollower((0.0, 10.0, 0.0))
    assert loop.update(-1.0, 0.0, 0.5) == pytest.approx(-5.0)
    assert loop.update(-1.0, 0.0, 0.5) == pytest.approx(-10.0)
