"""The motor action: an arm or a claw on a SPIKE hub's port, by angle, for a time, or running."""

from __future__ import annotations

from typing import Any

import pytest
from helpers import run_action

from roboscript.actions import ACTIONS, Motor, Outcome
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot

F = 5  # port F, where the spike-prime profile's extra motor is


def arm_position(bot: Robot) -> float:
    hub: Any = bot.simulation.device
    return float(hub.extra_motors[F].position_deg)


def test_motor_is_a_mission_action() -> None:
    assert ACTIONS["motor"] is Motor


def test_an_angle_turns_the_motor_that_far_and_ends_done() -> None:
    with Robot.connect("spike-prime") as bot:
        result: Any = run_action(bot, Motor("F", angle_deg=90.0, speed_deg_s=180.0))
        assert result.outcome is Outcome.DONE
        assert arm_position(bot) == 90.0


def test_counterclockwise_turns_the_angle_the_other_way() -> None:
    with Robot.connect("spike-prime") as bot:
        run_action(bot, Motor("f", angle_deg=45.0, direction="counterclockwise"))
        assert arm_position(bot) == -45.0


def test_a_duration_runs_the_motor_then_brakes_it() -> None:
    with Robot.connect("spike-prime") as bot:
        result: Any = run_action(bot, Motor("F", speed_deg_s=100.0, duration_s=1.0))
        assert result.outcome is Outcome.DONE
        position = arm_position(bot)
        assert position == pytest.approx(100.0, abs=10.0)
        bot.run_for(0.5)
        assert arm_position(bot) == position


def test_a_port_without_a_motor_fails_not_supported() -> None:
    with Robot.connect("spike-prime") as bot:
        result: Any = run_action(bot, Motor("C", angle_deg=90.0))
        assert result.outcome is Outcome.FAILED
        assert result.reason == "not supported: no motor on port C (motors: F)"


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"port": "G"}, "port must be one of A, B, C, D, E, F"),
        ({"port": "C", "angle_deg": 90.0, "duration_s": 1.0}, "an angle or a duration"),
        ({"port": "C", "speed_deg_s": 0.0}, "a positive speed"),
        ({"port": "C", "direction": "up"}, "direction must be"),
    ],
)
def test_bad_parameters_are_refused(kwargs: dict[str, Any], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Motor(**kwargs)


def test_a_mission_moving_a_motor_reads_well_in_yaml() -> None:
    spec, problems = parse_yaml_mission(
        """
states:
  lift:
    do: {motor: {port: C, angle: 90 deg, speed: 180 deg/s}}
    on: {done: end}
  end: {final: success}
"""
    )
    assert not [p for p in problems if p.severity == "error"]
    (action,) = spec.states["lift"].actions()
    assert action.requires == frozenset({"motors"})
    built = action.factory()
    assert (built.port, built.angle_deg, built.speed_deg_s) == ("C", 90.0, 180.0)
