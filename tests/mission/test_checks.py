"""Routes for an action's outcome in a state that runs no action: an error at load time."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.mission.checks import check_capabilities, check_mission, check_regions
from roboscript.mission.spec import ActionSpec, MissionSpec, StateSpec, TransitionSpec
from roboscript.mission.yaml_loader import parse_yaml_mission

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


def test_a_condition_that_sends_a_state_to_itself_is_warned(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        "states:\n  go:\n    do: {drive: {distance: 3 m}}\n    on: {done: end, failed: end}\n"
        "    when: [{if: range.distance_cm < 20, goto: go}]\n  end: {final: success}\n"
    )
    _, warnings = load_mission(path)
    assert [w.format() for w in warnings] == [
        (
            f"{path}:5:12: warning: state 'go' goes to itself when 'range.distance_cm < 20' holds:"
            " it starts again at once, and again on every tick while that holds (go to another"
            " state, one that turns away, say; or leave the condition out)"
        )
    ]


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
    assert (
        "m.py:5:5: error: state 'w' moves on when its action is done, but it has no action, so"
        " it would wait for ever (give it an action, e.g. state(Drive(distance_mm=500), ...),"
        " or leave it with when= or timeout_s=)"
    ) in info.value.format()


@pytest.mark.parametrize(
    ("suffix", "text", "hint"),
    [
        (
            "yaml",
            "states:\n  go:\n    do: {drive: {distance: 50 cm}}\n    on: {done: go}\n",
            "(add a state with 'final: success' and a transition to it, e.g. on: {done: finished})",
        ),
        (
            "py",
            (
                "from roboscript import Drive, Mission, state\n\n\nclass M(Mission):\n"
                "    go = state(Drive(distance_mm=500), initial=True, on_done='go')\n"
            ),
            (
                '(add a state with final="success" and a transition to it,'
                ' e.g. finished = state(final="success") and on_done="finished")'
            ),
        ),
    ],
)
def test_a_structural_hint_is_written_in_the_missions_own_language(
    tmp_path: Path, suffix: str, text: str, hint: str
) -> None:
    path = tmp_path / f"m.{suffix}"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(MissionError) as info:
        load_mission(path)
    found = [p.format() for p in getattr(info.value, "problems", [info.value])]
    assert any(
        "can never finish: no final state can be reached from 'go' " + hint in line
        for line in found
    ), found


# -------- Whole messages for a mission's shape, its robot and its world
#
# What ``roboscript check`` says about a mission's shape, its robot and its world, in-process.
#
# Whole messages for: final states with transitions, outcomes nobody handles (a ``parallel`` or
# ``repeat`` that fails, an inner machine that can or cannot fail, a ``wait_until`` that times
# out), a state that only waits on a condition, capabilities of an unnamed robot, and regions
# a world or a robot on a port cannot answer. Missions built in code (no locations, states
# that are named but missing) are checked without crashing.


def _messages(text: str) -> list[str]:
    """Every problem ``check`` reports for the YAML mission ``text``, errors or warnings."""
    try:
        _spec, warnings = parse_yaml_mission(text, "m.yaml")
    except MissionError as exc:
        return [p.format() for p in getattr(exc, "problems", [exc])]
    return [p.format() for p in warnings]


def test_a_final_state_with_an_on_cannot_also_be_final() -> None:
    text = """
mission: m
states:
  go:
    do: {drive: {distance: 1 m}}
    on: {done: end, failed: end}
  end:
    final: success
    on: {done: go}
"""
    assert _messages(text) == [
        (
            "m.yaml:7:3: error: final state 'end' cannot also have transitions"
            " (remove 'final', or remove its 'on'/'when')"
        ),
    ]


def test_a_parallel_that_can_stall_warns_with_its_child_s_reason() -> None:
    text = """
mission: m
states:
  go:
    do: {parallel: {all: [{drive: {distance: 1 m}}, {play_tone: {frequency: 440 Hz}}]}}
    on: {done: end}
  end: {final: success}
"""
    assert _messages(text) == [
        (
            "m.yaml:5:10: warning: if 'parallel' fails (stalled) in state 'go', the mission ends"
            " in failure (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


REPEATED = """
mission: m
states:
  loop:
    do:
      repeat:
        times: 2
        do:
          initial: a
          states:
            a:
              do: {wait: {duration: 0.2 s}}
              on: {done: FINAL}
            FINAL: {final: OUTCOME}
    on: {done: end}
  end: {final: success}
"""


def test_a_repeat_of_an_inner_machine_that_can_fail_warns() -> None:
    assert _messages(REPEATED.replace("FINAL", "bad").replace("OUTCOME", "failure")) == [
        (
            "m.yaml:6:7: warning: if 'repeat' fails (its inner states reach a failure) in state"
            " 'loop', the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


def test_a_repeat_of_an_inner_machine_that_always_succeeds_does_not_warn() -> None:
    assert _messages(REPEATED.replace("FINAL", "good").replace("OUTCOME", "success")) == []


def test_a_bounded_action_whose_done_goes_nowhere_waits_on_its_condition() -> None:
    text = """
mission: m
states:
  go:
    do: {drive: {distance: 1 m}}
    when:
      - {if: bumper.any, goto: end}
    on: {failed: end}
  end: {final: success}
"""
    assert _messages(text) == [
        (
            "m.yaml:4:3: warning: state 'go' waits for 'bumper.any' with no timeout: if that"
            " never holds, the mission runs until its time limit"
            " (add 'timeout: 10 s' and 'on: {timeout: STATE}' to the state)"
        ),
    ]


def test_a_handled_wait_until_timeout_is_not_warned_about() -> None:
    text = """
mission: m
states:
  go:
    do: {wait_until: {condition: bumper.any, timeout: 5 s}}
    on: {done: end, timeout: end}
  end: {final: success}
"""
    assert _messages(text) == []


def _drive(**fields: object) -> ActionSpec:
    return ActionSpec(name="drive", kwargs={}, factory=object, **fields)  # type: ignore[arg-type]


def _tone() -> ActionSpec:
    return ActionSpec(name="play_tone", kwargs={}, factory=object)  # type: ignore[arg-type]


def _go(target: str, guard_text: str | None = "bumper.any") -> TransitionSpec:
    return TransitionSpec(target=target, guard_text=guard_text)


def test_a_mission_built_in_code_without_locations_is_checked() -> None:
    # The 'ghost' state is named but missing, and is searched first: 'b' must still be
    # followed to 'c', and problems without a location still format.
    states = {
        "a": StateSpec(
            name="a", action=_tone(), on={"done": (_go("b"),), "failed": (_go("ghost"),)}
        ),
        "b": StateSpec(name="b", action=_tone(), on={"done": (_go("c"),)}),
        "c": StateSpec(name="c", final="success"),
        "idle": StateSpec(name="idle", when=(_go("c", None),)),
    }
    spec = MissionSpec(name="m", initial="a", states=states)
    assert [p.format() for p in check_mission(spec)] == [
        "error: state 'idle' can never be reached from 'a' (add a transition to it, or remove it)",
        (
            "warning: state 'idle' waits for '?' with no timeout: if that never holds,"
            " the mission runs until its time limit"
            " (add 'timeout: 10 s' and 'on: {timeout: STATE}' to the state)"
        ),
    ]


def test_a_mission_whose_initial_state_is_missing_cannot_finish() -> None:
    spec = MissionSpec(
        name="m",
        initial="ghost",
        states={"c": StateSpec(name="c", final="success")},
        location=None,
    )
    assert [p.format() for p in check_mission(spec)] == [
        (
            "error: mission 'm' can never finish: no final state can be reached from 'ghost'"
            " (add a state with 'final: success' and a transition to it, e.g. on: {done: finished})"
        ),
        "error: state 'c' can never be reached from 'ghost' (add a transition to it, or remove it)",
    ]


def test_an_unnamed_robot_without_a_capability_list_lacks_everything() -> None:
    action = _drive(requires=frozenset({"drive_base", "jetpack"}))
    spec = MissionSpec(
        name="m",
        initial="a",
        states={
            "a": StateSpec(name="a", action=action, on={"done": (_go("c"),)}),
            "c": StateSpec(name="c", final="success"),
        },
    )
    assert [p.format() for p in check_capabilities(spec, SimpleNamespace())] == [
        (
            "error: 'drive' needs drive_base (two driven wheels with encoders or timing),"
            " which the robot does not have"
        ),
        "error: 'drive' needs jetpack (jetpack), which the robot does not have",
    ]


NESTED_REGIONS = """
mission: m
states:
  go:
    do:
      initial: a
      states:
        a:
          do: {drive: {speed: 20 cm/s, duration: 10 s}}
          when:
            - {if: in_region.centre, goto: done}
          on: {done: done, failed: done}
        done: {final: success}
    on: {done: end}
  end: {final: success}
"""


@pytest.mark.parametrize(
    ("regions", "expected"),
    [
        (
            None,
            (
                "m.yaml:11:15: error: the condition 'in_region.centre' reads in_region.centre,"
                " but a robot on a port has no world map to place itself in"
                " (run it on the simulator,"
                " or use pose.x_mm and pose.y_mm, which odometry gives)"
            ),
        ),
        (
            set(),
            (
                "m.yaml:11:15: error: the world 'the world' has no region 'centre'"
                " (its regions: none)"
            ),
        ),
        (
            {"zzzzzzzz"},
            (
                "m.yaml:11:15: error: the world 'the world' has no region 'centre'"
                " (its regions: zzzzzzzz)"
            ),
        ),
        (
            {"center", "centre-line"},
            (
                "m.yaml:11:15: error: the world 'the world' has no region 'centre'"
                " (its regions: center, centre-line) (did you mean 'in_region.center'?)"
            ),
        ),
    ],
)
def test_regions_read_inside_a_nested_state_are_checked(
    regions: set[str] | None, expected: str
) -> None:
    spec, _warnings = parse_yaml_mission(NESTED_REGIONS, "m.yaml")
    assert [p.format() for p in check_regions(spec, regions)] == [expected]
