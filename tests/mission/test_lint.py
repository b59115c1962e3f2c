"""Golden messages for a mission's structure: can it finish, can it wait forever, who handles
an action's failure. And every shipped mission checks clean."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.grading.spec import is_test_spec
from roboscript.mission import mission_for_robot
from roboscript.mission.python_loader import is_python_mission

MISSIONS = Path(__file__).resolve().parents[2] / "missions"


def report(path: Path) -> list[str]:
    """What ``roboscript check`` prints for ``path``: its errors, or else its warnings."""
    try:
        _spec, _profile, warnings = mission_for_robot(path)
    except MissionError as exc:
        found = getattr(exc, "problems", [exc])
    else:
        found = warnings
    return [p.format().replace(str(path), "M") for p in found]


def test_a_mission_that_can_reach_no_final_state_is_an_error(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        """\
mission: m
states:
  go:
    do: {drive: {distance: 50 cm}}
    on: {done: back, failed: back}
  back:
    do: {drive: {distance: -50 cm}}
    on: {done: go, failed: go}
"""
    )
    assert report(path) == [
        (
            "M:3:3: error: mission 'm' can never finish: no final state can be reached from 'go'"
            " (add a state with 'final: success' and a transition to it, e.g. on: {done: finished})"
        )
    ]


def test_a_dead_end_is_reported_once_as_the_state_with_no_way_out(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission("mission: m\nstates:\n  go:\n    do: {wait: {duration: 1 s}}\n")
    assert report(path) == [
        (
            "M:3:3: error: state 'go' has no way out"
            " (add 'on: {done: NEXT}', a 'when' condition, or 'final: success')"
        )
    ]


def test_a_state_that_cannot_lead_to_a_final_state_is_a_warning(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        """\
mission: m
states:
  go:
    do: {drive: {distance: 50 cm}}
    on: {done: end, failed: spin}
  spin:
    do: {rotate: {angle: 90 deg}}
    on: {done: spin, failed: spin}
  end:
    final: success
"""
    )
    assert report(path) == [
        (
            "M:6:3: warning: once in state 'spin' the mission can never finish: no final state can"
            " be reached from it (add a transition from it to a final state, e.g. 'timeout: 30 s'"
            " and 'on: {timeout: FINAL_STATE}')"
        )
    ]


def test_waiting_on_a_condition_without_a_timeout_is_a_warning(
    write_mission: Callable[..., Path],
) -> None:
    waiting = """\
mission: m
states:
  go:
    when:
      - {if: "bumper.any", goto: end}
      - {if: "elapsed > 5 s", goto: end}
  end:
    final: success
"""
    assert report(write_mission(waiting)) == [
        (
            "M:3:3: warning: state 'go' waits for 'bumper.any' or 'elapsed > 5 s' with no timeout:"
            " if that never holds, the mission runs until its time limit (add 'timeout: 10 s' and"
            " 'on: {timeout: STATE}' to the state)"
        )
    ]
    bounded = waiting.replace("    when:", "    timeout: 10 s\n    on: {timeout: end}\n    when:")
    assert report(write_mission(bounded)) == []


def test_an_action_that_ends_by_itself_needs_no_timeout_for_its_when(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        """\
mission: m
states:
  go:
    do: {wait: {duration: 2 s}}
    on: {done: end}
    when:
      - {if: "bumper.any", goto: end}
  end:
    final: success
"""
    )
    assert report(path) == []


def test_unhandled_failures_and_timeouts_of_actions_are_warnings(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        """\
mission: m
states:
  go:
    do: {follow_wall: {duration: 5 s}}
    on: {done: hold}
  hold:
    do: {wait_until: {condition: "bumper.any", timeout: 5 s}}
    on: {done: inner}
  inner:
    do:
      states:
        a:
          do: {wait: {duration: 1 s}}
          on: {done: bad}
        bad:
          final: failure
    on: {done: end}
  end:
    final: success
"""
    )
    assert report(path) == [
        (
            "M:4:10: warning: if 'follow_wall' fails (lost wall or stalled) in state 'go', the"
            " mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        ),
        (
            "M:7:10: warning: if 'wait_until' times out in state 'hold', the mission ends in"
            " failure (add 'on: {timeout: STATE}' to handle it)"
        ),
        (
            "M:11:7: warning: if the inner states of 'inner' end in failure, the mission ends in"
            " failure (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


def _shipped() -> list[Path]:
    found = sorted(p for p in MISSIONS.rglob("*.yaml") if not is_test_spec(p))
    found += sorted(p for p in MISSIONS.rglob("*.py") if is_python_mission(p))
    return found


def test_the_shipped_missions_are_all_found() -> None:
    names = {p.relative_to(MISSIONS).as_posix() for p in _shipped()}
    assert {"square.yaml", "square.py", "teacher/corridor/bad.yaml"} <= names


@pytest.mark.parametrize("path", _shipped(), ids=lambda p: p.relative_to(MISSIONS).as_posix())
def test_every_shipped_mission_checks_clean(path: Path) -> None:
    _spec, _profile, warnings = mission_for_robot(path)
    found = [w.format() for w in warnings]
    if path.relative_to(MISSIONS).as_posix() == "teacher/corridor/bad.yaml":
        # the teacher's deliberately wrong solution: its 20-for-20-cm slip is what check shows
        assert len(found) == 1
        assert found[0].endswith(
            "warning: follow_wall distance: 20 taken as 20 mm; write"
            " `20 mm` (or did you mean 20 cm?)"
        )
    else:
        assert found == []
