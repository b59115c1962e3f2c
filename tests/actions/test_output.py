"""display, set_led and servo on the simulated MIRTO, through ASIP bytes."""

from __future__ import annotations

from typing import Any

import pytest
from helpers import run_action

from roboscript.actions import Display, Outcome, Servo, SetLed
from roboscript.actions.output import parse_color
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot


def test_display_writes_the_lcd() -> None:
    with Robot.connect("mirto") as bot:
        result = run_action(bot, Display(text="Hello, class 3B! Ready to roll?"))
        assert result.outcome is Outcome.DONE
        # The MIRTO LCD keeps 20 characters a row.
        assert bot.simulation.log.display == "Hello, class 3B! Rea\ndy to roll?"


def test_set_led_and_servo_reach_the_board() -> None:
    with Robot.connect("mirto") as bot:
        assert bot.has("leds") and bot.capabilities["leds"].count == 9
        assert run_action(bot, SetLed(color=(0, 128, 255), index=2)).outcome is Outcome.DONE
        assert run_action(bot, Servo(angle_deg=30, index=0)).outcome is Outcome.DONE
        state = bot.simulation.device.state
        assert state.pixels[2] == (0, 128, 255)
        assert state.servos_deg == [30]


def test_a_servo_the_board_lacks_fails_with_the_boards_reason(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import dataclasses

    import roboscript.drivers.asip.device as board
    from roboscript.profiles import get_profile

    # A profile that promises two servos, on a sketch with one.
    mirto = get_profile("mirto")
    two = dataclasses.replace(mirto, options={**mirto.options, "servo_count": 2})
    one = board.BoardConfig(servo_count=1)
    monkeypatch.setattr(
        board, "simulated_device", lambda profile: lambda body: board.MirtoBoard(body, one)
    )
    spec, _ = parse_yaml_mission(
        "states:\n  arm:\n    do: {servo: {index: 1, angle: 30 deg}}\n"
        "    on: {done: ok, failed: refused}\n  ok: {final: success}\n"
        "  refused: {final: failure}\n"
    )
    with Robot.connect(two) as bot:
        runner = MissionRunner(spec, bot.capabilities, device_errors=bot.driver.take_device_error)
        bot.scheduler.add(runner)
        bot.scheduler.run(until=lambda: runner.finished, max_duration_s=5)
    assert runner.result.final_state == "refused"
    assert runner.result.reason is not None
    assert runner.result.reason.endswith(
        "servo failed in state 'arm': the board refused 'S,W': there is no device with that number"
    )


def test_an_led_past_the_end_of_the_strip_is_not_supported() -> None:
    with Robot.connect("mirto") as bot:
        too_far = run_action(bot, SetLed(color="red", index=9))
    assert too_far.outcome is Outcome.FAILED
    assert too_far.reason == "not supported: the robot has 9 LEDs"


@pytest.mark.parametrize(
    ("text", "rgb"), [("red", (255, 0, 0)), ("#10a0FF", (16, 160, 255)), ([1, 2, 3], (1, 2, 3))]
)
def test_colours(text: object, rgb: tuple[int, int, int]) -> None:
    assert parse_color(text) == rgb


@pytest.mark.parametrize("text", [None, ["hello"], ("a", "b")])
def test_display_refuses_what_is_not_text_instead_of_showing_its_python_form(text: Any) -> None:
    with pytest.raises(ValueError, match=r'^display text: expected text such as "hello", got'):
        Display(text=text)


@pytest.mark.parametrize("color", [None, 5, [1, 2]])
def test_set_led_refuses_what_is_no_colour_naming_its_parameter(color: Any) -> None:
    with pytest.raises(ValueError, match=r"^set_led color: expected a colour \(off, black"):
        SetLed(color=color)
