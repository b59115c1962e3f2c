"""Conditions and Python missions reading a colour sensor and a hub's buttons."""

from __future__ import annotations

from typing import Any

import pytest

from roboscript.clock import SimClock
from roboscript.mission.checks import check_capabilities
from roboscript.mission.guards import GuardEnv, GuardError, compile_guard
from roboscript.mission.python_api import Mission, state
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.runner import MissionRunner
from roboscript.profiles import get_profile
from roboscript.scheduler import Scheduler


class FakeColor:
    def __init__(self) -> None:
        self.reflection: float | None = None
        self.name: str | None = None
        self.channels: tuple[int, int, int] | None = None

    def reflection_percent(self) -> float | None:
        return self.reflection

    def color_name(self) -> str | None:
        return self.name

    def rgb(self) -> tuple[int, int, int] | None:
        return self.channels


class FakeButtons:
    names = ("left", "right")

    def __init__(self) -> None:
        self.held: frozenset[str] = frozenset()

    def pressed(self) -> frozenset[str]:
        return self.held


def runner_for(mission: type[Mission] | str, **caps: Any) -> MissionRunner:
    if isinstance(mission, str):
        from roboscript.mission.yaml_loader import parse_yaml_mission

        spec, _ = parse_yaml_mission(mission)
    else:
        spec, _ = compile_mission(mission)
    return MissionRunner(spec, caps)


def guard_value(source: str, **caps: Any) -> bool:
    runner = runner_for("states:\n  s: {final: success}\n", **caps)
    env: GuardEnv = runner
    return compile_guard(source)(env)


def test_reflection_compares_in_percent_and_no_reading_compares_false() -> None:
    color = FakeColor()
    assert not guard_value("color.reflection < 40", color=color)
    assert not guard_value("color.reflection >= 40", color=color)
    color.reflection = 12.0
    assert guard_value("color.reflection < 40", color=color)
    assert not guard_value("color.reflection > 40", color=color)


def test_a_colour_is_a_yes_no_name_and_rgb_channels_are_numbers() -> None:
    color = FakeColor()
    color.name, color.channels = "red", (900, 180, 160)
    assert guard_value("color.red and not color.black", color=color)
    assert guard_value("color.rgb_red - color.rgb_green > 500", color=color)
    color.name = None
    assert not guard_value("color.red or color.white", color=color)


def test_buttons_read_what_is_held() -> None:
    buttons = FakeButtons()
    assert not guard_value("buttons.any", buttons=buttons)
    buttons.held = frozenset({"right"})
    assert guard_value("buttons.right and not buttons.left and buttons.any", buttons=buttons)


def test_guards_name_the_capabilities_they_read() -> None:
    guard = compile_guard("color.reflection < 40 or buttons.left")
    assert guard.capabilities == frozenset({"color", "buttons"})


@pytest.mark.parametrize(
    ("source", "message", "hint"),
    [
        (
            "buttons.center",
            "'buttons' has no 'center' (it has any, left, right)",
            (
                "the hub's centre button stops the program, so a mission never sees it"
                " pressed; use buttons.left or buttons.right"
            ),
        ),
        ("color.blak", "'color' has no 'blak'", "did you mean 'color.black'?"),
        ("color.reflection == 'black'", "a condition compares numbers, not text", None),
    ],
)
def test_mistakes_are_named(source: str, message: str, hint: str | None) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert str(caught.value).startswith(message)
    assert caught.value.hint == hint


def test_a_python_mission_reads_colour_and_buttons_through_self() -> None:
    seen: list[tuple[float, str | None, tuple[int, int, int], bool]] = []

    class Watch(Mission):
        wait = state(initial=True, when=[("ready", "done")])
        done = state(final="success")

        def ready(self) -> bool:
            color = self.color
            seen.append((color.reflection, color.name, color.rgb, self.buttons.left))
            return self.buttons.left and color.reflection < 40

    color, buttons = FakeColor(), FakeButtons()
    color.reflection, color.name, color.channels = 15.0, "black", (60, 60, 70)
    runner = runner_for(Watch, color=color, buttons=buttons)
    scheduler = Scheduler(SimClock(), 0.02)
    scheduler.add(runner)
    scheduler.run(until=lambda: runner.finished, max_duration_s=0.1)
    assert not runner.finished and seen[-1] == (15.0, "black", (60, 60, 70), False)
    buttons.held = frozenset({"left"})
    scheduler.run(until=lambda: runner.finished, max_duration_s=0.1)
    assert runner.result.outcome == "success"


def test_a_mission_reading_the_colour_sensor_is_refused_on_a_robot_without_one() -> None:
    class Stop(Mission):
        wait = state(initial=True, when=[("dark", "done")])
        done = state(final="success")

        def dark(self) -> bool:
            return self.color.reflection < 40 or self.buttons.right

    spec, _ = compile_mission(Stop)
    assert [p.message for p in check_capabilities(spec, get_profile("mirto"))] == [
        "the condition 'dark' reads buttons, which mirto does not have",
        "the condition 'dark' reads color, which mirto does not have",
    ]
    assert check_capabilities(spec, get_profile("spike-prime")) == []
