"""Routes for an action's outcome in a state that runs no action: an error at load time."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import load_mission

# ------------------------------------------------------- routes that nothing can take


def test_a_done_route_in_a_state_without_an_action_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text("states:\n  wait_a_bit:\n    on: {done: end}\n  end: {final: success}\n")
    with pytest.raises(MissionError) as info:
        load_mission(path)
    assert info.value.format().endswith(
        "m.yaml:2:3: error: state 'wait_a_bit' moves on when its action is done, but it has no"
        " 'do:' action, so it would wait for ever (give it an action, e.g. do: {drive:"
        " {distance: 50 cm}}, or leave it with 'when:' or 'timeout:')"
    )


def test_a_failed_route_without_an_action_is_named_as_failing(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        "states:\n  w:\n    timeout: 1 s\n    on: {failed: end, timeout: end}\n"
        "  end: {final: success}\n"
    )
    with pytest.raises(MissionError) as info:
        load_mission(path)
    assert "state 'w' moves on when its action fails, but it has no 'do:' action" in str(
        info.value.format()
    )


def test_a_state_without_an_action_may_leave_by_its_timeout(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        "states:\n  w:\n    timeout: 1 s\n    on: {timeout: end}\n  end: {final: success}\n"
    )
    assert load_mission(path)[0].states["w"].action is None


def test_a_python_state_without_an_action_but_a_done_route_is_the_same_error(
    tmp_path: Path,
) -> None:
    path = tmp_path / "m.py"
    path.write_text(
        "from roboscript import Mission, state\n\n\nclass M(Mission):\n"
        "    w = state(initial=True, on_done='end')\n    end = state(final='success')\n"
    )
    with pytest.raises(MissionError) as info:
        load_mission(path)
    assert "state 'w' moves on when its action is done, but it has no 'do:' action" in (
        info.value.format()
    )
