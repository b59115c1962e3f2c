"""The load-time checks hold for Python missions as for YAML ones: "runs forever" above all.

A ``follow_wall`` or ``follow_line`` with neither ``until`` nor ``duration``, in a state with
no ``timeout_s`` and no ``when``, would drive until the battery dies; ``roboscript check``
refuses it before the robot moves (missions.md, "Checks before the robot moves").
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import load_mission

FOREVER = """\
from roboscript import FollowLine, FollowWall, Mission, state


class Forever(Mission):
    go = state(ACTION, initial=True, on_done="end", on_failed="end"EXTRA)
    end = state(final="success")
"""


def _problems(path: Path) -> list[str]:
    with pytest.raises(MissionError) as info:
        load_mission(path)
    found = getattr(info.value, "problems", [info.value])
    return [p.format().replace(str(path), "M") for p in found]


def _write(write_mission: Callable[..., Path], action: str, extra: str = "") -> Path:
    text = FOREVER.replace("ACTION", action).replace("EXTRA", extra)
    return write_mission(text, "forever.py")


@pytest.mark.parametrize(
    ("action", "name"),
    [("FollowWall(side='right')", "follow_wall"), ("FollowLine()", "follow_line")],
)
def test_an_action_that_never_ends_is_refused(
    write_mission: Callable[..., Path], action: str, name: str
) -> None:
    problems = _problems(_write(write_mission, action))
    expected = (
        f"M:5:16: error: '{name}' in state 'go' never ends as written (give it 'until' or"
        " 'duration', or give the state a 'timeout' or a 'when')"
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
