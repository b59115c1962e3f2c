"""The mission builder's rules as a student meets them (issue 16, mutation testing).

Each test loads a whole mission, YAML or Python, and checks what the student sees: the
parameters an action runs with, the full ``file:line:col: error: message (hint)`` of each
mistake, and the robot capabilities the mission is said to need. A few rules only the builder's
own API reaches (a ``repeat`` count, a problem with no place) are checked on the builder.
"""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from roboscript.actions import ACTIONS
from roboscript.inputs.source import Location
from roboscript.mission import load_mission
from roboscript.mission.builder import MissionBuilder, MissionProblemsError
from roboscript.mission.guards import GuardEnv
from roboscript.mission.spec import ActionSpec, MissionSpec
from roboscript.mission.yaml_loader import parse_yaml_mission

END = "  b: {final: success}\n"


def _yaml(states: str, head: str = "") -> tuple[MissionSpec, list[str]]:
    """A YAML mission whose first state is ``a``, with its warnings as the student reads them."""
    spec, warnings = parse_yaml_mission(f"{head}initial: a\nstates:\n{states}", "m.yaml")
    return spec, [w.format() for w in warnings]


def _yaml_errors(states: str, head: str = "") -> list[str]:
    """Every problem of a YAML mission that does not load, in the order the student sees."""
    with pytest.raises(MissionProblemsError) as info:
        parse_yaml_mission(f"{head}initial: a\nstates:\n{states}", "m.yaml")
    return [p.format() for p in info.value.problems]


def _python(write: Callable[..., Path], body: str, name: str = "m.py") -> Path:
    return write(textwrap.dedent(body), name)


def _python_errors(path: Path) -> list[str]:
    with pytest.raises(MissionProblemsError) as info:
        load_mission(path)
    return [p.format() for p in info.value.problems]


class _Moment(GuardEnv):
    """A moment of a run in which every sensor reads 0 and no state was visited."""

    def sensor(self, root: str, attr: str | None) -> float | bool:
        return 0.0

    def visits(self, state: str) -> int:
        return 0


def _action(spec: MissionSpec, state: str = "a") -> ActionSpec:
    action = spec.states[state].action
    assert action is not None
    return action


# ------------------------------------------------------------------- the first error raised


def test_the_raised_error_reads_as_the_first_problem_with_its_hint() -> None:
    with pytest.raises(MissionProblemsError) as info:
        parse_yaml_mission(
            "initial: a\nstates:\n  a: {do: {drive: {distnce: 3 cm}}, on: {done: b}}\n" + END,
            "m.yaml",
        )
    assert str(info.value) == (
        "m.yaml:3:20: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)"
    )
    assert info.value.hint == "did you mean 'distance'?"


# ----------------------------------------------------------------------- action parameters


def test_an_unknown_parameter_lists_the_ones_the_action_takes() -> None:
    assert _yaml_errors(
        "  a: {do: {follow_wall: {colour: left}}, timeout: 2 s, on: {timeout: b}}\n" + END
    ) == [
        (
            "m.yaml:3:26: error: 'follow_wall' has no parameter 'colour' "
            "('follow_wall' takes side, distance, speed, until, duration)"
        )
    ]


def test_an_action_with_no_parameters_has_no_list_to_offer() -> None:
    assert _yaml_errors("  a: {do: {stop: {speed: 3}}, on: {done: b}}\n" + END) == [
        "m.yaml:3:19: error: 'stop' has no parameter 'speed'"
    ]


@pytest.mark.parametrize(
    ("params", "expected"),
    [
        (
            "{walk: {steps: 2.5}}",
            "m.yaml:3:26: error: walk steps: expected a whole number, got 2.5",
        ),
        (
            "{follow_wall: {side: up, duration: 2 s}}",
            "m.yaml:3:32: error: follow_wall side: expected one of left, right, got 'up'",
        ),
        (
            "{follow_wall: {until: 5}}",
            (
                "m.yaml:3:33: error: follow_wall until: "
                'expected a condition such as "range.distance_cm < 20", got 5'
            ),
        ),
        (
            "{display: {text: [1]}}",
            "m.yaml:3:28: error: display text: expected text, got [1]",
        ),
    ],
)
def test_a_parameter_of_the_wrong_kind_is_named_with_what_it_takes(
    params: str, expected: str
) -> None:
    assert _yaml_errors(f"  a: {{do: {params}, on: {{done: b}}}}\n" + END) == [expected]


def test_a_condition_parameter_knows_the_mission_s_states() -> None:
    # visits.c reads a state that does not exist: only the mission's state names can say so
    assert _yaml_errors(
        "  a: {do: {follow_wall: {until: visits.c > 1}}, on: {done: b}}\n" + END
    ) == ["m.yaml:3:40: error: follow_wall until: 'visits.c': there is no state 'c'"]
    spec, _ = _yaml(
        "  a: {do: {follow_wall: {until: visits.b > 1}}, on: {done: b, failed: b}}\n" + END
    )
    assert _action(spec).kwargs["until"].states == frozenset({"b"})


@pytest.mark.parametrize(("written", "holds"), [("true", True), ("false", False)])
def test_a_yes_or_no_condition_parameter_is_the_word_it_stands_for(
    written: str, holds: bool
) -> None:
    spec, _ = _yaml(
        f"  a: {{do: {{follow_wall: {{until: {written}}}}}, on: {{done: b, failed: b}}}}\n" + END
    )
    until = _action(spec).kwargs["until"]
    assert (until.source, until(_Moment())) == (written, holds)


def test_text_is_kept_as_text_whatever_was_written() -> None:
    for written, kept in [("12", "12"), ("hello there", "hello there"), ("2.5", "2.5")]:
        spec, _ = _yaml(f"  a: {{do: {{display: {{text: {written}}}}}, on: {{done: b}}}}\n" + END)
        assert _action(spec).kwargs == {"text": kept}


def test_a_bare_number_s_warning_points_at_the_number() -> None:
    _, warnings = _yaml("  a: {do: {drive: {distance: 30}}, on: {done: b, failed: b}}\n" + END)
    assert warnings == [
        (
            "m.yaml:3:30: warning: drive distance: 30 taken as 30 mm; write `30 mm` "
            "(or did you mean 30 cm?)"
        )
    ]


# ------------------------------------------------------------ capabilities a mission needs


def test_a_condition_parameter_s_sensor_is_needed_too() -> None:
    # until comes before duration: the condition's sensor must survive the later parameters
    spec, _ = _yaml(
        "  a: {do: {follow_wall: {until: range.distance_cm < 20, duration: 3 s}},"
        " on: {done: b, failed: b}}\n" + END
    )
    assert _action(spec).requires == frozenset({"range", "side_range", "drive_base"})
    spec, _ = _yaml(
        "  a: {do: {wait_until: {condition: bumper.any, timeout: 3 s}},"
        " on: {done: b, timeout: b}}\n" + END
    )
    assert spec.requires() == frozenset({"bumper"})


def test_a_python_repeat_or_parallel_needs_what_its_actions_need(
    write_mission: Callable[..., Path],
) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Drive, Mission, Parallel, PlayTone, Repeat, state


        class M(Mission):
            a = state(Repeat(Drive(distance_mm=100), 2), initial=True, on_done="c", on_failed="c")
            c = state(
                Parallel([PlayTone(frequency_hz=440)], "all"), on_done="b", on_failed="b"
            )
            b = state(final="success")
        """,
    )
    spec, _ = load_mission(path)
    assert _action(spec).requires == frozenset({"drive_base"})
    assert _action(spec, "c").requires == frozenset({"speaker"})


# --------------------------------------------------------------- a Python mission's actions


BEHAVIOUR = """\
from roboscript import Action, Mission, Param, Result, state


class Sweep(Action):
    '''Keeps its parameters under names of its own, and a setting that is no parameter.'''

    name = "sweep"
    params = (
        Param("reach", "reach_mm", "distance", "how far to reach"),
        Param("side", "side", "choice", "which side", "left", ("left", "right")),
        Param("width", "width_mm", "distance", "how wide", 100.0),
    )

    def __init__(self, reach_mm: float = 50.0, side: str = "left", width_mm: float = 100.0,
                 *, laps: int = 1) -> None:
        self.target = reach_mm
        self.laps = laps
        self.seen: list[int] = []

    def update(self, ctx):
        self.seen.append(1)
        return Result.done()


class M(Mission):
    a = state(Sweep(laps=3), initial=True, on_done="b")
    b = state(final="success")
"""


def test_a_behaviour_keeping_its_parameters_elsewhere_builds(
    write_mission: Callable[..., Path],
) -> None:
    # what the object does not hold takes the documented default; a required parameter it
    # does not hold was checked by its own constructor, not a mistake of the student's
    spec, warnings = load_mission(_python(write_mission, BEHAVIOUR))
    assert warnings == []
    assert _action(spec).kwargs == {"side": "left", "width_mm": 100.0}


def test_each_visit_runs_a_fresh_copy_of_the_object_the_mission_made(
    write_mission: Callable[..., Path],
) -> None:
    spec, _ = load_mission(_python(write_mission, BEHAVIOUR))
    first = _action(spec).factory()
    first.seen.append(7)
    second = _action(spec).factory()
    # the setting the student gave (laps=3) is kept, and nothing of the first visit
    assert (second.laps, second.seen) == (3, [])


# --------------------------------------------------------------------------------- parallel

PARALLEL = """\
  a:
    do:
      parallel:
        {mode}:
          - {{follow_wall: {{side: left}}}}
          - {{wait: {{duration: 2 s}}}}
    on: {{done: b}}
"""


def test_parallel_any_ends_with_its_bounded_action() -> None:
    spec, warnings = _yaml(PARALLEL.format(mode="any") + END)
    action = _action(spec)
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "parallel",
        {"mode": "any", "actions": ("follow_wall", "wait")},
        "m.yaml:5:7",
        frozenset({"side_range", "drive_base"}),
    )
    assert action.factory().mode == "any"
    assert warnings == [
        (
            "m.yaml:5:7: warning: if 'parallel' fails (lost wall or stalled) in state 'a', "
            "the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        )
    ]


def test_parallel_all_never_ends_while_one_action_runs_on() -> None:
    assert _yaml_errors(PARALLEL.format(mode="all") + END) == [
        (
            "m.yaml:5:7: error: 'parallel' in state 'a' never ends as written "
            "(give it 'until' or 'duration', or give the state a 'timeout' or a 'when')"
        ),
        (
            "m.yaml:5:7: warning: if 'parallel' fails (lost wall or stalled) in state 'a', "
            "the mission ends in failure (add 'on: {failed: STATE}' to handle it)"
        ),
    ]


def test_parallel_all_of_bounded_actions_ends() -> None:
    spec, _ = _yaml(
        "  a:\n    do:\n      parallel:\n        all:\n"
        "          - {play_tone: {frequency: 440 Hz}}\n          - {wait: {duration: 2 s}}\n"
        "    on: {done: b}\n" + END
    )
    assert _action(spec).bounded
    assert _action(spec).factory().mode == "all"


# ----------------------------------------------------------------------------------- repeat


def test_repeat_once_runs_its_action_once() -> None:
    spec, _ = _yaml(
        "  a:\n    do: {repeat: {times: 1, do: {drive: {distance: 20 cm}}}}\n"
        "    on: {done: b, failed: b}\n" + END
    )
    action = _action(spec)
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "repeat",
        {"times": 1, "action": "drive"},
        "m.yaml:4:10",
        frozenset({"drive_base"}),
    )
    repeat = action.factory()
    assert repeat.times == 1
    child = repeat.factory()
    assert (type(child).name, child.distance_mm) == ("drive", 200.0)


def test_repeat_of_an_endless_action_never_ends() -> None:
    assert _yaml_errors(
        "  a:\n    do: {repeat: {times: 2, do: follow_line}}\n    on: {done: b, failed: b}\n" + END
    ) == [
        (
            "m.yaml:4:10: error: 'repeat' in state 'a' never ends as written "
            "(give it 'until' or 'duration', or give the state a 'timeout' or a 'when')"
        )
    ]


@pytest.mark.parametrize("times", [0, -1, True, 1.5, "2"])
def test_the_builder_refuses_a_repeat_count_that_is_not_a_whole_number_from_1(
    times: Any,
) -> None:
    # the YAML reader checks the count before the builder; this is the builder's own guard
    build = MissionBuilder("m.yaml")
    child = build.action(ACTIONS["stop"], {}, Location("m.yaml", 4, 20), frozenset({"a"}))
    assert child is not None
    assert build.repeat(times, child, Location("m.yaml", 4, 10)) is None
    assert [p.format() for p in build.problems] == [
        "m.yaml:4:10: error: repeat times must be a whole number of at least 1"
    ]


# ------------------------------------------------------------------------ nested machines

INNER = """\
  a:
    do:
      initial: x
      states:
        x: {{do: {{drive: {{{param}: 30 cm}}}}{on}}}
        y: {{final: success}}
    on: {{done: b, failed: b}}
"""


def test_inner_states_run_as_one_action_needing_what_they_need() -> None:
    spec, warnings = _yaml(INNER.format(param="distance", on=", on: {done: y, failed: y}") + END)
    action = _action(spec)
    assert warnings == []
    assert (action.name, action.kwargs, str(action.location), action.requires) == (
        "states",
        {"mission": "a", "states": ("x", "y")},
        "m.yaml:5:7",
        frozenset({"drive_base"}),
    )
    assert spec.requires() == frozenset({"drive_base"})


def test_inner_states_are_checked_like_a_mission() -> None:
    assert _yaml_errors(INNER.format(param="distance", on="") + END) == [
        (
            "m.yaml:7:9: error: state 'x' has no way out "
            "(add 'on: {done: NEXT}', a 'when' condition, or 'final: success')"
        ),
        (
            "m.yaml:7:18: warning: if 'drive' fails (stalled) in state 'x', the mission ends in "
            "failure (add 'on: {failed: STATE}' to handle it)"
        ),
        (
            "m.yaml:8:9: error: state 'y' can never be reached from 'x' "
            "(add a transition to it, or remove it)"
        ),
    ]


def test_a_mistake_in_inner_states_is_reported_once_and_alone() -> None:
    assert _yaml_errors(INNER.format(param="distnce", on=", on: {done: y}") + END) == [
        "m.yaml:7:26: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)"
    ]


# ------------------------------------------------------------------ transitions, conditions


def test_a_target_that_is_not_a_name(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class M(Mission):
            a = state(Stop(), initial=True, on_done=5)
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [f"{path}:5:45: error: expected a state name, got 5"]


@pytest.mark.parametrize(("written", "holds"), [("true", True), ("false", False)])
def test_a_yes_or_no_condition_is_the_word_it_stands_for(written: str, holds: bool) -> None:
    spec, _ = _yaml(
        f"  a: {{do: follow_line, when: [{{if: {written}, goto: b}}], timeout: 3 s,"
        " on: {timeout: b, failed: b}}\n" + END
    )
    (transition,) = spec.states["a"].when
    assert (transition.guard.source, transition.guard(_Moment())) == (written, holds)


def test_a_condition_that_is_not_text() -> None:
    assert _yaml_errors("  a: {do: stop, when: [{if: 5, goto: b}]}\n" + END) == [
        'm.yaml:3:29: error: a condition is text, e.g. if: "range.distance_cm < 20"'
    ]


# ------------------------------------------------------------------------ states, mission


def test_a_timeout_s_message_quotes_it_as_written() -> None:
    assert _yaml_errors("  a: {do: stop, timeout: -2 s, on: {done: b}}\n" + END) == [
        "m.yaml:3:26: error: state 'a': timeout is a positive number of seconds, got '-2 s'"
    ]


def test_a_timeout_beyond_any_float(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Wait, state


        class M(Mission):
            a = state(Wait(duration_s=1), initial=True, timeout_s=10**400, on_done="b",
                      on_timeout="b")
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [
        f"{path}:5:59: error: state 'a': timeout_s: a number with about 401 digits is too large"
    ]


def test_a_state_keeps_its_description() -> None:
    spec, _ = _yaml("  a: {do: stop, description: '  turns about  ', on: {done: b}}\n" + END)
    assert spec.states["a"].description == "turns about"


def test_a_robot_that_is_not_a_name() -> None:
    assert _yaml_errors("  a: {final: success}\n", head="robot: 5\n") == [
        "m.yaml:1:8: error: 'robot' names a robot, e.g. robot: mirto"
    ]


def test_a_python_robot_that_is_not_a_name(write_mission: Callable[..., Path]) -> None:
    path = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class M(Mission):
            world = 5
            a = state(Stop(), initial=True, on_done="b")
            b = state(final="success")
        """,
    )
    assert _python_errors(path) == [
        f"{path}:5:13: error: 'world' names a world, e.g. world = \"square-room\""
    ]


# ---------------------------------------------------------------- the builder's own defaults


def test_a_problem_with_no_place_names_the_file() -> None:
    build = MissionBuilder("m.yaml")
    build.problem("something is wrong", None, "fix it")
    assert [p.format() for p in build.problems] == ["m.yaml: error: something is wrong (fix it)"]


def test_without_parameter_places_problems_are_at_the_action() -> None:
    build = MissionBuilder("m.yaml")
    where = Location("m.yaml", 3, 12)
    assert build.action(ACTIONS["drive"], {"distance": 30}, where, frozenset()) is not None
    assert build.action(ACTIONS["drive"], {"distnce": 3}, where, frozenset()) is None
    assert [p.format() for p in build.problems] == [
        (
            "m.yaml:3:12: warning: drive distance: 30 taken as 30 mm; write `30 mm` "
            "(or did you mean 30 cm?)"
        ),
        "m.yaml:3:12: error: 'drive' has no parameter 'distnce' (did you mean 'distance'?)",
    ]


# ------------------------------------------------------------------ the order of problems


def test_a_python_mission_s_own_mistakes_come_before_those_of_a_class_it_imports(
    write_mission: Callable[..., Path],
) -> None:
    inner = _python(
        write_mission,
        """\
        from roboscript import Mission, Stop, state


        class Inner(Mission):
            x = state(Stop(), initial=True, on_done="nowhere")
            y = state(final="success")
        """,
        "builder_mutants_inner.py",
    )
    path = _python(
        write_mission,
        """\
        from builder_mutants_inner import Inner

        from roboscript import Mission, Stop, state


        class M(Mission):
            a = state(Inner, initial=True, on_done="b")
            b = state(Stop(), on_done="elsewhere")
            c = state(final="success")
        """,
    )
    # the imported class's mistake is on an earlier line, yet the student's file comes first
    assert _python_errors(path) == [
        f"{path}:8:31: error: there is no state 'elsewhere'",
        f"{inner}:5:45: error: there is no state 'nowhere'",
    ]


def test_problems_are_in_line_then_column_order_a_whole_file_s_first() -> None:
    build = MissionBuilder("m.yaml")
    # recorded out of order, as the loaders find them
    build.problem("line 1, column 1", Location("m.yaml", 1, 1))
    build.problem("line 1", Location("m.yaml", 1))
    build.problem("the whole file", None)
    build.problem("line 2, column 9", Location("m.yaml", 2, 9))
    build.problem("line 2, column 1", Location("m.yaml", 2, 1))
    with pytest.raises(MissionProblemsError) as info:
        build.finish(None)
    assert [p.format() for p in info.value.problems] == [
        "m.yaml: error: the whole file",
        "m.yaml:1: error: line 1",
        "m.yaml:1:1: error: line 1, column 1",
        "m.yaml:2:1: error: line 2, column 1",
        "m.yaml:2:9: error: line 2, column 9",
    ]
