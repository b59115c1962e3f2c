"""walk and turn move the simulated PLEN2 by whole steps and end when it stands still."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import run_action

from roboscript.actions import ActionContext, Outcome, Turn, Walk
from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.robot import Robot

STRIDE_MM = 40.5
TURN_STEP_DEG = 15.0


def test_walk_ends_when_the_robot_has_taken_its_steps() -> None:
    with Robot.connect("plen2") as bot:
        result = run_action(bot, Walk(steps=3))
        board = bot.simulation.device
        assert not board.playing
        body = bot.simulation.body
        assert body.y_mm == pytest.approx(3 * STRIDE_MM, abs=3.0)
        assert body.x_mm == pytest.approx(0.0, abs=1e-6)
    assert result.outcome is Outcome.DONE


def test_negative_steps_walk_backward_and_turn_left() -> None:
    with Robot.connect("plen2") as bot:
        assert run_action(bot, Walk(steps=-2)).outcome is Outcome.DONE
        assert run_action(bot, Turn(steps=-3)).outcome is Outcome.DONE
        body = bot.simulation.body
        assert body.y_mm == pytest.approx(-2 * STRIDE_MM, abs=3.0)
        assert body.heading_deg == pytest.approx(360.0 - 3 * TURN_STEP_DEG, abs=0.5)


def test_positive_turn_is_clockwise() -> None:
    with Robot.connect("plen2") as bot:
        assert run_action(bot, Turn(steps=6)).outcome is Outcome.DONE
        assert bot.simulation.body.heading_deg == pytest.approx(90.0, abs=0.5)
        assert run_action(bot, Walk(steps=2)).outcome is Outcome.DONE
        body = bot.simulation.body
    assert math.hypot(body.x_mm - 2 * STRIDE_MM, body.y_mm) < 3.0


def test_leaving_the_state_early_finishes_the_step_in_progress() -> None:
    with Robot.connect("plen2") as bot:
        ctx = ActionContext(bot.capabilities)
        walk = Walk(steps=8)
        walk.start(ctx)
        bot.run_for(1.5)  # in the middle of the second step
        assert walk.update(ctx) is None
        assert walk.feedback == "walking 8 steps forward"
        walk.stop(ctx)
        bot.run_for(2.0)
        assert not bot.capabilities["walker"].busy()
        assert bot.simulation.body.y_mm == pytest.approx(2 * STRIDE_MM, abs=3.0)


def test_a_robot_without_legs_fails_not_supported() -> None:
    with Robot.connect("mirto") as bot:
        result = run_action(bot, Turn(steps=2))
    assert result.outcome is Outcome.FAILED
    assert result.reason == "not supported"


@pytest.mark.parametrize(("steps", "message"), [(1.5, "whole steps"), (0, "at least one step")])
def test_steps_must_be_whole_and_not_zero(steps: float, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Walk(steps=steps)


MISSION = """\
mission: stroll
robot: plen2
initial: go
states:
  go:
    do: {walk: {steps: STEPS}}
    on: {done: end}
  end:
    final: success
"""


def test_a_mission_counts_steps(write_mission: Callable[..., Path]) -> None:
    spec, warnings = load_mission(write_mission(MISSION.replace("STEPS", "-4")))
    assert spec.states["go"].action.kwargs == {"steps": -4.0}
    assert warnings == []


def test_a_mission_with_half_a_step_is_refused(write_mission: Callable[..., Path]) -> None:
    path = write_mission(MISSION.replace("STEPS", "2.5"))
    with pytest.raises(MissionError) as info:
        load_mission(path, get_profile("plen2"))
    (problem,) = getattr(info.value, "problems", [info.value])
    assert problem.line == 6
    assert "whole" in problem.message and "2.5" in problem.message
