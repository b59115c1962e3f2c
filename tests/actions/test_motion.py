"""drive and rotate end where they should, on firmware PID (mirto) and host PID (asip-basic).

Accuracy is measured against the simulator's true pose, not the robot's own odometry.
"""

from __future__ import annotations

import math

import pytest
from helpers import run_action

from roboscript import capabilities as cap
from roboscript.actions import ActionContext, Drive, Outcome, Result, Rotate
from roboscript.robot import Robot

ROBOTS = ["mirto", "asip-basic"]


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_drive_50_cm_ends_within_1_cm(robot: str, seed: int) -> None:
    with Robot.connect(robot, seed=seed) as bot:
        body = bot.simulation.body
        result = run_action(bot, Drive(distance_mm=500, speed_mm_s=150))
        travelled = math.hypot(body.x_mm, body.y_mm)
    assert result.outcome is Outcome.DONE
    assert abs(travelled - 500.0) <= 10.0, travelled


@pytest.mark.parametrize("robot", ROBOTS)
def test_drive_backwards_goes_south(robot: str) -> None:
    with Robot.connect(robot) as bot:
        run_action(bot, Drive(distance_mm=-200, speed_mm_s=100))
        assert bot.simulation.body.y_mm == pytest.approx(-200.0, abs=10.0)


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize(("angle", "seed"), [(90.0, 1), (90.0, 2), (-90.0, 3), (180.0, 4)])
def test_rotate_ends_within_2_degrees(robot: str, angle: float, seed: int) -> None:
    with Robot.connect(robot, seed=seed) as bot:
        body = bot.simulation.body
        result = run_action(bot, Rotate(angle_deg=angle))
        turned = (body.heading_deg + 180.0) % 360.0 - 180.0
    assert result.outcome is Outcome.DONE
    expected = (angle + 180.0) % 360.0 - 180.0
    assert abs(((turned - expected + 180.0) % 360.0) - 180.0) <= 2.0, turned


@pytest.mark.parametrize("robot", ROBOTS)
def test_drive_into_a_wall_fails_stalled(robot: str) -> None:
    with Robot.connect(robot, world="square-room") as bot:
        result = run_action(bot, Drive(distance_mm=3000, speed_mm_s=150))
        collisions = bot.simulation.log.collisions
    assert result.outcome is Outcome.FAILED
    assert result.reason == "stalled"
    assert len(collisions) == 1


def test_drive_for_a_time() -> None:
    with Robot.connect("mirto") as bot:
        start = bot.clock.now()
        result = run_action(bot, Drive(duration_s=2.0, speed_mm_s=100))
        assert result.outcome is Outcome.DONE
        assert bot.clock.now() - start == pytest.approx(2.5, abs=0.05)  # + 0.5 s coasting
        assert 150 < bot.simulation.body.y_mm < 230


class _JammedWheels:
    """A drive base whose wheels do not turn whatever power they get (a jammed gearbox)."""

    track_mm = 150.0
    max_speed_mm_s = 300.0

    def __init__(self, *, odometry_is_estimated: bool = False) -> None:
        self.odometry_is_estimated = odometry_is_estimated
        self.speeds = (0.0, 0.0)
        self.stops = 0

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        self.speeds = (left_mm_s, right_mm_s)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)
        self.stops += 1

    def wheel_distances_mm(self) -> tuple[float, float]:
        return (12.0, 34.0)


def _run_on(base: _JammedWheels, action: Rotate, limit_s: float = 5.0) -> tuple[object, float]:
    ctx = ActionContext({cap.DRIVE_BASE: base})
    ctx.dt_s = 0.02
    action.start(ctx)
    for tick in range(1, round(limit_s / ctx.dt_s) + 1):
        ctx.now_s = tick * ctx.dt_s
        result = action.update(ctx)
        if result is not None:
            return result, ctx.now_s
    return None, ctx.now_s


def test_rotate_with_jammed_wheels_fails_stalled_after_a_second_and_stops_them() -> None:
    base = _JammedWheels()
    result, ended_s = _run_on(base, Rotate(angle_deg=90.0))
    assert result == Result.failed("stalled")
    assert ended_s == pytest.approx(1.0, abs=0.03)
    assert base.speeds == (0.0, 0.0)
    assert base.stops >= 1


def test_rotate_cannot_see_a_stall_without_encoders() -> None:
    # estimated odometry never stalls: it would fail every turn of a robot without encoders
    result, _ = _run_on(_JammedWheels(odometry_is_estimated=True), Rotate(angle_deg=90.0))
    assert result is None
