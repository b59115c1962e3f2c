"""The load-time checks hold for Python missions as for YAML ones: "runs forever" above all.

A ``follow_wall`` or ``follow_line`` with neither ``until`` nor ``duration``, in a state with
no ``timeout_s`` and no ``when``, would drive until the battery dies; ``roboscript check``
refuses it before the robot moves (missions.md, "Checks before the robot moves").
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import refusal as _problems

from roboscript.actions import ACTIONS, REQUIRED, Drive, Param
from roboscript.actions.base import FROM_INIT
from roboscript.mission import load_mission, mission_for_robot

FOREVER = """\
from roboscript import FollowLine, FollowWall, Mission, state


class Forever(Mission):
    go = state(ACTION, initial=True, on_done="end", on_failed="end"EXTRA)
    end = state(final="success")
"""


def _write(write_mission: Callable[..., Path], action: str, extra: str = "") -> Path:
    text = FOREVER.replace("ACTION", action).replace("EXTRA", extra)
    return write_mission(text, "forever.py")


@pytest.mark.parametrize(
    ("action", "name"),
    [("FollowWall(side='right')", "FollowWall"), ("FollowLine()", "FollowLine")],
)  # the mission's own language: Python keywords, not YAML's `until:`
def test_an_action_that_never_ends_is_refused_showing_how_to_end_it_in_python(
    write_mission: Callable[..., Path], action: str, name: str
) -> None:
    problems = _problems(_write(write_mission, action))
    word = next(cls.name for cls in ACTIONS.values() if cls.__name__ == name)
    expected = (
        f"M:5:16: error: '{word}' in state 'go' never ends as written (write"
        f' {name}(until="range.distance_cm < 20") or {name}(duration_s=10), or give the state'
        " timeout_s=10 or a when=)"
    )
    assert problems == [expected]


@pytest.mark.parametrize(
    ("action", "extra"),
    [
        ("FollowWall(side='right', duration_s=5.0)", ""),
        ("FollowLine(until=lambda m: m.elapsed > 3)", ""),
        ("FollowWall(side='right')", ", timeout_s=10.0, on_timeout='end'"),
        ("FollowLine()", ", when=[(lambda m: m.elapsed > 3, 'end')]"),
    ],
    ids=["duration", "until", "timeout", "when"],
)
def test_a_bound_in_the_action_or_the_state_is_enough(
    write_mission: Callable[..., Path], action: str, extra: str
) -> None:
    spec, _ = load_mission(_write(write_mission, action, extra))
    assert spec.states["go"].action is not None


RENAMED = """\
from roboscript import Drive, Mission, Rotate, WaitUntil, state


class Cruise(Drive):
    \"\"\"Drive in all but name.\"\"\"

    name = "cruise"


class Spin(Rotate):
    name = "spin"


class Hold(WaitUntil):
    name = "hold"


class Lap(Mission):
    go = state(Cruise(distance_mm=500, speed_mm_s=5000), initial=True, on_done="turn")
    turn = state(Spin(angle_deg=90, turn_rate_deg_s=5000), on_done="wait")
    wait = state(Hold(condition=lambda m: m.elapsed > 1, timeout_s=3), on_done="end")
    end = state(final="success")
"""


def test_an_action_that_is_drive_in_all_but_name_gets_every_warning_drive_gets(
    write_mission: Callable[..., Path],
) -> None:
    # what is true of an action lives on its class, so a subclass needs no table edited
    _, _, warnings = mission_for_robot(write_mission(RENAMED, "lap.py"), "mirto")
    found = [w.message for w in warnings]
    assert "if 'cruise' fails (stalled) in state 'go', the mission ends in failure" in found
    assert "if 'spin' fails (stalled) in state 'turn', the mission ends in failure" in found
    assert "if 'hold' times out in state 'wait', the mission ends in failure" in found
    assert any(
        m.startswith("cruise speed: 5000 mm/s is faster than mirto can drive") for m in found
    )
    assert any(
        m.startswith("spin turn_rate: 5000 deg/s is faster than mirto can turn") for m in found
    )


def test_a_parameter_default_is_written_once_on_the_action() -> None:
    # a Param written without a default takes the one of __init__
    for cls in ACTIONS.values():
        signature = inspect.signature(cls.__init__)
        for param in cls.params:
            written = signature.parameters[param.kwarg].default
            expected = REQUIRED if written is inspect.Parameter.empty else written
            assert param.default == expected or param.default is expected, (cls.name, param)
    assert Drive.params[1].default == 150.0


def test_a_default_taken_from_init_must_be_there() -> None:
    with pytest.raises(TypeError, match="FROM_INIT needs a default for speed_mm_s in __init__"):

        class Hurry(Drive):
            params = (Param("speed", "speed_mm_s", "speed", "how fast", FROM_INIT),)

            def __init__(self, speed_mm_s: float) -> None:
                super().__init__(distance_mm=100.0, speed_mm_s=speed_mm_s)


def test_an_action_that_is_drive_in_all_but_name_refuses_what_drive_refuses(
    write_mission: Callable[..., Path],
) -> None:
    both = RENAMED.replace("Cruise(distance_mm=500, speed_mm_s=5000)", "Cruise(500, duration_s=2)")
    found = _problems(write_mission(both, "lap.py"))
    assert any(
        "error: cruise takes a distance or a duration, not both: it would drive the distance"
        " and ignore the duration (remove 'duration' to drive the distance" in p
        for p in found
    ), found
    far = RENAMED.replace("Cruise(distance_mm=500,", "Cruise(distance_mm=1e6,")
    assert any(
        "error: cruise distance: 1e+06 mm is farther than any room (at most 100 m)" in p
        for p in _problems(write_mission(far, "far.py"))
    )
