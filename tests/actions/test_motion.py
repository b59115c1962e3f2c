"""drive and rotate end where they should, on firmware PID (mirto) and host PID (asip-basic).

Accuracy is measured against the simulator's true pose, not the robot's own odometry.
"""

from __future__ import annotations

import math

import pytest
from helpers import run_action

from roboscript.actions import Drive, Outcome, Rotate
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
