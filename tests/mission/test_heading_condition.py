"""The ``heading_deg`` condition: degrees clockwise (right) positive, with or without an IMU.

missions.md: "how far the robot has turned since the start, -180 to 180, clockwise positive".
A robot without an IMU (mirto, asip-basic) measures it from wheel travel; one with an IMU
(spike-prime) reads the IMU. Both must agree on the sign, or a mission written on one robot
turns the wrong way on the other.
"""

from __future__ import annotations

import pytest

from roboscript import capabilities as cap
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot

LOOK = """
states:
  turn:
    do: {rotate: {angle: ANGLE deg}}
    on: {done: look}
  look:
    do: {wait: {duration: 1 s}}
    when:
      - {if: heading_deg > 45, goto: right}
      - {if: heading_deg < -45, goto: left}
    on: {done: neither}
  right: {final: success}
  left: {final: success}
  neither: {final: failure}
"""


def _where(robot: str, angle: float) -> str:
    spec, _ = parse_yaml_mission(LOOK.replace("ANGLE", str(angle)))
    with Robot.connect(robot) as bot:
        runner = MissionRunner(spec, bot.capabilities, gains=bot.profile.gains)
        bot.scheduler.add(runner)
        bot.scheduler.run(until=lambda: runner.finished, max_duration_s=30)
    return runner.result.states[-1][1]


@pytest.mark.parametrize("robot", ["mirto", "asip-basic"])
def test_without_an_imu_turning_right_reads_positive(robot: str) -> None:
    with Robot.connect(robot) as bot:
        assert cap.HEADING not in bot.capabilities
    assert _where(robot, 90.0) == "right"
    assert _where(robot, -90.0) == "left"


def test_with_an_imu_turning_right_reads_positive() -> None:
    with Robot.connect("spike-prime") as bot:
        assert cap.HEADING in bot.capabilities
    assert _where("spike-prime", 90.0) == "right"
    assert _where("spike-prime", -90.0) == "left"
