"""The simulated body: motors, encoders, collisions and sensors, as a mission would feel them."""

from __future__ import annotations

import itertools
import math
import random

import pytest

from roboscript.sim.body import Body, BodySpec
from roboscript.sim.geometry import Segment
from roboscript.sim.world import Pose, TapeLine, World

DT_S = 0.005
SPEC = BodySpec()
NORTH_WALL = World("north-wall", walls=(Segment(-1000.0, 500.0, 1000.0, 500.0),))
TAPE_ALONG_Y = World("tape", lines=(TapeLine((Segment(0.0, -1000.0, 0.0, 1000.0),), 20.0),))


def make_body(world: World = NORTH_WALL, seed: int = 1, start: Pose | None = None) -> Body:
    return Body(world, SPEC, random.Random(seed), start or Pose())


def run(body: Body, seconds: float, left: float, right: float) -> None:
    body.set_power(left, right)
    for _ in range(round(seconds / DT_S)):
        body.step(DT_S)


# ------------------------------------------------------------------------------------ motors


def test_a_wheel_reaches_63_percent_of_its_target_speed_after_one_time_constant() -> None:
    body = make_body(World("empty"))
    run(body, SPEC.motor_lag_s, 0.5, 0.5)
    target = 0.5 * SPEC.max_wheel_speed_mm_s
    assert body.wheel_speed_mm_s[0] == pytest.approx(target * (1 - math.exp(-1)), rel=0.01)
    run(body, 5 * SPEC.motor_lag_s, 0.5, 0.5)
    assert body.wheel_speed_mm_s[0] == pytest.approx(target, rel=0.01)


def test_power_beyond_full_saturates_at_the_top_wheel_speed() -> None:
    body = make_body(World("empty"))
    run(body, 1.0, 3.0, -3.0)
    top = SPEC.max_wheel_speed_mm_s
    assert body.wheel_speed_mm_s == pytest.approx([top, -top], rel=1e-3)


def test_power_inside_the_dead_band_does_not_move_the_robot() -> None:
    body = make_body(World("empty"))
    run(body, 2.0, SPEC.dead_band * 0.9, SPEC.dead_band * 0.9)
    assert (body.x_mm, body.y_mm, body.ticks) == (0.0, 0.0, [0, 0])
    run(body, 2.0, SPEC.dead_band * 1.5, SPEC.dead_band * 1.5)
    assert body.y_mm > 10.0


def test_encoders_count_whole_ticks_of_wheel_rotation() -> None:
    body = make_body(World("empty"))
    body.set_power(0.1, 0.1)
    turned_ticks = 0.0
    seen = set()
    for _ in range(400):
        body.step(DT_S)
        turned_ticks += body.wheel_speed_mm_s[0] * DT_S / SPEC.mm_per_tick
        assert body.ticks[0] == math.floor(turned_ticks)
        seen.add(body.ticks[0])
    assert {0, 1, 2} <= seen  # it starts below one tick and counts up one by one


# -------------------------------------------------------------------------------- collisions


def test_a_wall_stops_the_robot_and_pushing_on_is_one_collision_with_the_bumper_held() -> None:
    body = make_body()
    body.set_power(0.6, 0.6)
    pressed: list[bool] = []
    while body.time_s < 4.0:
        body.step(DT_S)
        if body.log.collisions:
            pressed.append(any(body.bumpers_pressed()))
    assert body.y_mm < 500.0 - SPEC.body_radius_mm
    assert body.y_mm > 500.0 - SPEC.body_radius_mm - 3.0  # stopped against it
    assert len(body.log.collisions) == 1
    assert len(pressed) > 200 and all(pressed)  # no flicker while it pushes
    assert body.log.contacts[0].end_s is None


def test_pushing_stalls_the_encoders() -> None:
    body = make_body()
    run(body, 2.5, 0.6, 0.6)
    assert body.log.collisions
    before = list(body.ticks)
    run(body, 1.0, 0.6, 0.6)
    moved_mm = [(after - b) * SPEC.mm_per_tick for after, b in zip(body.ticks, before, strict=True)]
    assert max(moved_mm) < 3.0  # a free wheel would have rolled 240 mm


def test_backing_off_ends_the_contact_and_a_new_bump_counts_again() -> None:
    body = make_body()
    run(body, 3.0, 0.6, 0.6)
    run(body, 1.0, -0.4, -0.4)
    assert not any(body.bumpers_pressed())
    first = body.log.contacts[0]
    assert first.end_s is not None
    assert first.duration_s(body.time_s) == pytest.approx(first.end_s - first.start_s)
    assert 1.0 < first.duration_s(body.time_s) < 2.5
    # It began with the body's edge at the wall (y = 500), give or take one step's travel.
    assert first.y_mm == pytest.approx(500.0 - SPEC.body_radius_mm, abs=5.0)
    run(body, 2.0, 0.6, 0.6)
    assert len(body.log.collisions) == 2


def test_the_bumper_on_the_side_that_touches_is_pressed() -> None:
    body = make_body(start=Pose(0.0, 0.0, 30.0))  # the wall is ahead and to the left
    run(body, 3.0, 0.6, 0.6)
    assert body.bumpers_pressed() == (True, False)
    assert body.log.contacts[0].side == "left"


# ---------------------------------------------------------------------------------- range


def test_range_is_the_distance_from_the_sensor_to_the_wall_with_noise() -> None:
    body = make_body(start=Pose(0.0, 100.0, 0.0))
    expected = 500.0 - 100.0 - SPEC.range_offset_mm
    readings = []
    for i in range(50):
        body.time_s = i * SPEC.range_period_s
        reading = body.range_mm()
        assert reading is not None
        readings.append(reading)
    assert sum(readings) / len(readings) == pytest.approx(expected, abs=2.0)
    assert len(set(readings)) > 40  # noisy


def test_range_measures_at_most_every_60_ms_and_repeats_the_last_value_between() -> None:
    body = make_body(start=Pose(0.0, 0.0, 0.0))
    first = body.range_mm()
    body.y_mm = 200.0  # much closer now
    body.time_s = 0.05
    assert body.range_mm() == first
    body.time_s = 0.06
    second = body.range_mm()
    assert second is not None and first is not None
    assert second == pytest.approx(first - 200.0, abs=15.0)


def test_no_echo_beyond_the_maximum_range() -> None:
    body = make_body(start=Pose(0.0, 500.0 - SPEC.range_offset_mm - SPEC.range_max_mm - 50.0))
    assert body.range_mm() is None


@pytest.mark.parametrize(
    ("turned_deg", "echo"),
    [(0.0, True), (20.0, True), (29.0, True), (32.0, False), (60.0, False)],
)
def test_a_wall_met_at_a_grazing_angle_gives_no_echo(turned_deg: float, echo: bool) -> None:
    # Sensor 300 mm from the wall; the beam is 15 deg wide and echoes up to 22.5 deg from square.
    body = make_body(start=Pose(0.0, 500.0 - 300.0 - SPEC.range_offset_mm, turned_deg))
    body.y_mm = 500.0 - 300.0 - SPEC.range_offset_mm * math.cos(math.radians(turned_deg))
    assert (body.range_mm() is not None) is echo


def test_the_side_sensor_measures_the_gap_to_a_wall_on_the_right() -> None:
    wall_east = World("east", walls=(Segment(400.0, -1000.0, 400.0, 1000.0),))
    body = make_body(wall_east)
    reading = body.side_range_mm()
    assert reading == pytest.approx(400.0 - SPEC.side_range_offset_mm, abs=12.0)
    assert make_body(World("empty")).side_range_mm() is None


# ------------------------------------------------------------------------------ line sensors


def centre_sensor_mean(offset_mm: float, reads: int = 40) -> float:
    """Mean reading of the middle IR sensor with its centre ``offset_mm`` right of the tape."""
    forward, right = SPEC.line_sensor_offsets_mm[1]
    body = make_body(TAPE_ALONG_Y, start=Pose(offset_mm - right, -forward, 0.0))
    return sum(body.line_readings()[1] for _ in range(reads)) / reads


def test_line_sensors_read_dark_on_tape_and_light_on_the_floor() -> None:
    body = make_body(TAPE_ALONG_Y, start=Pose(0.0, 0.0, 0.0))
    left, centre, right = body.line_readings()
    assert centre > 800
    assert left < 200 and right < 200


def test_the_ir_reading_falls_smoothly_across_the_tape_edge() -> None:
    edge_mm = 10.0  # half the tape's 20 mm
    half_spot = SPEC.line_spot_mm / 2.0
    assert centre_sensor_mean(edge_mm - half_spot - 1.0) > 820
    assert centre_sensor_mean(edge_mm + half_spot + 1.0) < 120
    assert centre_sensor_mean(edge_mm) == pytest.approx((850 + 90) / 2, abs=25)
    across = [centre_sensor_mean(edge_mm + d) for d in (-3.0, -1.5, 0.0, 1.5, 3.0)]
    assert all(a > b + 40 for a, b in itertools.pairwise(across))  # proportional, not a step


# ------------------------------------------------------------------------------------- IMU


def test_imu_heading_drifts_slowly_while_the_robot_stands_still() -> None:
    body = make_body(World("empty"))
    run(body, 100.0, 0.0, 0.0)
    assert body.heading_deg == 0.0
    assert body.imu_heading_deg() == pytest.approx(100.0 * SPEC.imu_drift_deg_s)


# ----------------------------------------------------------------------------- determinism


def trace(seed: int, sensor_reads_per_step: int) -> list[tuple[float, ...]]:
    body = make_body(seed=seed, start=Pose(0.0, -300.0, 10.0))
    rows: list[tuple[float, ...]] = []
    body.set_power(0.5, 0.45)
    for step in range(800):
        body.step(DT_S)
        reads = [body.range_mm() for _ in range(sensor_reads_per_step)]
        if step % 20 == 0:
            rows.append((body.x_mm, body.y_mm, body.heading_deg, *body.ticks))
            rows.append(tuple(r or -1.0 for r in reads) + body.line_readings())
    return rows


def test_the_same_seed_gives_the_same_trace_and_another_seed_does_not() -> None:
    assert trace(5, 1) == trace(5, 1)
    assert trace(5, 1) != trace(6, 1)


def test_reading_sensors_more_often_does_not_change_how_the_robot_moves() -> None:
    assert trace(5, 1)[::2] == trace(5, 3)[::2]
