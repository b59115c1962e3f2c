"""How a Python mission class compiles: its transitions, conditions, ``requires`` and mistakes.

Each test pins what a student sees, the whole message with its ``file:line:col`` and hint,
the condition a robot lacks a sensor for, or the reason a run fails, so a change to any of
them is noticed.
The missions are files in ``tmp_path`` (their line numbers do not move when this file is
edited), compiled as ``roboscript`` compiles them and named ``lesson.py`` in messages.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.capabilities import CAPABILITY_NAMES
from roboscript.clock import SimClock
from roboscript.errors import InputError, MissionError
from roboscript.mission.python_api import Mission
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.python_loader import find_mission_class
from roboscript.mission.references import mission_robot, with_world_checked
from roboscript.mission.runner import MissionRunner
from roboscript.mission.spec import MissionSpec
from roboscript.mission.student_code import import_student_file, shown_path
from roboscript.profiles import BUILTIN_PROFILES
from roboscript.scheduler import Scheduler

# Five lines, so a mission's class starts on line 6 of its file.
HEAD = """\
from functools import partial

from roboscript import Drive, FollowLine, Mission, Wait, WaitUntil, state


"""

# A robot with wheels and nothing else: every condition that reads a sensor is refused on it,
# which shows which capabilities the compiler found in a condition and where it was written.
BARE = "stackmod-reference"

ALL_CAPABILITIES = (
    "drive_base, range, side_range, bumper, line, speaker, display, heading, leds, servos,"
    " walker, joints, force, color, buttons, motors"
)


def mission_class(tmp_path: Path, body: str, name: str = "lesson.py") -> type[Mission]:
    path = tmp_path / name
    path.write_text(HEAD + body, encoding="utf-8")
    return find_mission_class(import_student_file(path, kind="mission"), str(path))


def formatted(found: list[InputError]) -> list[str]:
    return [p.format() for p in found]


def compiled(
    tmp_path: Path, body: str, profile: str | None = None
) -> tuple[MissionSpec, list[str]]:
    """The mission and its warnings, as ``roboscript check`` shows them."""
    cls = mission_class(tmp_path, body)
    spec, warnings = compile_mission(cls, _profile(profile), path="lesson.py")
    return spec, formatted(warnings)


def problems(tmp_path: Path, body: str, profile: str | None = None) -> list[str]:
    """Every problem of a mission that does not compile, in the order a student reads them."""
    cls = mission_class(tmp_path, body)
    with pytest.raises(MissionError) as info:
        compile_mission(cls, _profile(profile), path="lesson.py")
    return formatted(getattr(info.value, "problems", [info.value]))


def _profile(name: str | None) -> object:
    return BUILTIN_PROFILES[name] if name is not None else None


def run(spec: MissionSpec) -> MissionRunner:
    """Run a mission of waits and conditions (it needs no robot) until it ends."""
    sched = Scheduler(SimClock(), 0.02)
    runner = MissionRunner(spec, {})
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=30.0)
    return runner


# ------------------------------------------------------------------- the class as a whole


def test_a_mission_class_without_states_is_refused_at_the_class(tmp_path: Path) -> None:
    body = 'class Empty(Mission):\n    """Nothing yet."""\n'
    assert problems(tmp_path, body) == [
        (
            "lesson.py:6:1: error: mission Empty has no states (add one, e.g. go ="
            " state(Drive(distance_mm=300), initial=True, on_done='end'))"
        )
    ]


def test_class_attributes_of_the_wrong_kind_are_shown_where_they_are_set(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    robot = 5
    world = 7
    name = 3
    requires = ("rnage", "lidar", 5)
    go = state(Drive(distance_mm=300), initial=True, on_done=("end",), on_failed="ned")
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        "lesson.py:7:13: error: 'robot' names a robot, e.g. robot = \"mirto\"",
        "lesson.py:8:13: error: 'world' names a world, e.g. world = \"square-room\"",
        "lesson.py:9:12: error: 'name' is the mission's name, as text",
        "lesson.py:10:16: error: requires: unknown capability 'rnage' (did you mean 'range'?)",
        *(
            f"lesson.py:10:16: error: requires: unknown capability {entry}"
            f" (capabilities: {ALL_CAPABILITIES})"
            for entry in ("'lidar'", 5)
        ),
        # A one-item tuple is a choice of the wrong length, shown at its opening parenthesis.
        (
            "lesson.py:11:62: error: a conditional choice is (condition, state), e.g."
            " ('bumper_hit', 'stuck')"
        ),
        "lesson.py:11:82: error: there is no state 'ned' (did you mean 'end'?)",
    ]


def test_requires_that_is_not_a_list_is_one_unknown_capability(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    requires = 5
    go = state(Drive(distance_mm=300), initial=True, on_done="end")
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        f"lesson.py:7:16: error: requires: unknown capability 5 (capabilities: {ALL_CAPABILITIES})"
    ]


def test_a_name_robot_and_world_given_as_text_are_the_missions(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    name = "first-steps"
    robot = "mirtoo"
    world = "square-rom"
    go = state(Wait(duration_s=1), initial=True, on_done="end")
    end = state(final="success")
"""
    spec, warnings = compiled(tmp_path, body)
    assert (spec.name, spec.robot, spec.world, warnings) == (
        "first-steps",
        "mirtoo",
        "square-rom",
        [],
    )
    # A robot or world that does not exist is found when the mission runs, and shown where
    # the class names it.
    with pytest.raises(MissionError) as info:
        mission_robot(spec)
    assert info.value.format() == (
        "lesson.py:8:13: error: there is no robot called 'mirtoo' (built-in robots: mirto,"
        " asip-basic, stackmod-rover, stackmod-reference, spike-prime, plen2)"
        " (did you mean 'mirto'?)"
    )
    _, found = with_world_checked(spec)
    assert [p.format() for p in found] == [
        (
            "lesson.py:9:13: error: there is no world called 'square-rom' (built-in worlds:"
            " corridor, empty, line-track, maze, square-room) (did you mean 'square-room'?)"
        )
    ]


# ------------------------------------------------------------------ compile_mission itself


LENSES = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

    def near(self):
        return self.range.distance_cm < 20
"""


def test_messages_name_the_file_as_the_caller_does_or_as_the_student_would_type_it(
    tmp_path: Path,
) -> None:
    cls = mission_class(tmp_path, LENSES)
    profile = BUILTIN_PROFILES[BARE]
    message = (
        ":7:71: error: the condition 'near' reads range, which stackmod-reference does not have"
    )
    with pytest.raises(MissionError) as info:
        compile_mission(cls, profile, path="lesson.py")
    assert info.value.format() == "lesson.py" + message
    with pytest.raises(MissionError) as info:
        compile_mission(cls, profile)
    assert info.value.format() == shown_path(tmp_path / "lesson.py") + message
    # Without a robot, nothing is checked against one.
    _, warnings = compile_mission(cls)
    assert warnings == []


def test_problems_in_the_missions_own_file_come_first(tmp_path: Path) -> None:
    # The guard method is inherited from a file beside the mission, where it names a state
    # that does not exist, on an earlier line than the mission's own mistake.
    (tmp_path / "lesson_base.py").write_text(
        "from roboscript import Mission\n\n\nclass Base(Mission):\n    def near(self):\n"
        '        return self.visits("nowhere") > 1\n',
        encoding="utf-8",
    )
    body = """\
from lesson_base import Base


class Lesson(Base):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "ned")])
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        "lesson.py:10:80: error: there is no state 'ned' (did you mean 'end'?)",
        (
            f"{shown_path(tmp_path / 'lesson_base.py')}:6:28: error: visits('nowhere'): there is no"
            " state 'nowhere'"
        ),
    ]


# ---------------------------------------------------------------------------- transitions


def test_mistakes_in_transitions_are_shown_at_the_entry_written(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(
        Wait(duration_s=1),
        initial=True,
        on_done="end",
        when=["end", (5, "end"), ("near", "nowhere"), ("near", "end", "go")],
    )
    end = state(final="success")

    def near(self):
        return self.bumper.any
"""
    assert problems(tmp_path, body) == [
        (
            "lesson.py:11:15: error: state 'go': each 'when' entry is (condition, state)"
            " (e.g. when=[('bumper_hit', 'end')])"
        ),
        "lesson.py:11:23: error: a condition is a method's name or an expression as text, got 5",
        "lesson.py:11:43: error: there is no state 'nowhere'",
        (
            "lesson.py:11:55: error: a conditional choice is (condition, state), e.g."
            " ('bumper_hit', 'stuck')"
        ),
    ]


def test_a_when_entry_that_is_no_name_gets_no_example(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[3])
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        "lesson.py:7:71: error: state 'go': each 'when' entry is (condition, state)"
    ]


# A state made by a helper function: the class body shows no state(...) call to point into,
# so every mistake in it is shown at the state's name.
MADE = """\
def leave(route, when):
    return state(Wait(duration_s=1), initial=True, on_done=route, when=when)


class Lesson(Mission):
    go = leave(ROUTE, WHEN)
    end = state(final="success")
"""


@pytest.mark.parametrize(
    ("route", "when", "expected"),
    [
        ('"nowhere"', "None", "there is no state 'nowhere'"),
        (
            '("end",)',
            "None",
            "a conditional choice is (condition, state), e.g. ('bumper_hit', 'stuck')",
        ),
        ('"end"', '[("true", "nowhere")]', "there is no state 'nowhere'"),
        (
            '"end"',
            '[("bumped", "end")]',
            (
                "Lesson has no method 'bumped'"
                " (define it: def bumped(self) -> bool: ... (return True or False))"
            ),
        ),
        (
            '"end"',
            '[("range.distnce_cm < 20", "end")]',
            (
                "'range' has no 'distnce_cm' (it has distance_cm, distance_mm)"
                " (did you mean 'range.distance_cm'?)"
            ),
        ),
    ],
)
def test_mistakes_in_a_state_made_by_a_helper_are_shown_at_its_name(
    tmp_path: Path, route: str, when: str, expected: str
) -> None:
    body = MADE.replace("ROUTE", route).replace("WHEN", when)
    assert problems(tmp_path, body) == [f"lesson.py:11:5: error: {expected}"]


def test_choices_written_as_text_true_and_false_are_expressions(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(
        Wait(duration_s=1),
        initial=True,
        on_done="end",
        when=[("false", "end"), ("False", "end"), ("true", "end")],
    )
    end = state(final="success")
"""
    spec, warnings = compiled(tmp_path, body)
    assert [(t.guard_text, t.target) for t in spec.states["go"].when] == [
        ("false", "end"),
        ("False", "end"),
        ("true", "end"),
    ]
    # the last, true, is an otherwise; the two before it never hold
    assert warnings == [
        f"lesson.py:11:{col}: warning: the condition '{written}' is made only of fixed values,"
        " so it never changes: it never holds, so state 'go' never goes to 'end' this way"
        " (compare a sensor's value, e.g. range.distance_cm < 20)"
        for col, written in ((15, "false"), (33, "False"))
    ]


# ----------------------------------------------------------------------------- conditions


def test_what_a_condition_reads_is_checked_against_the_robot(tmp_path: Path) -> None:
    # A method named, a method passed, a function, a lambda and a partial: the robot lacks
    # what each reads, and each message names the condition as a diagram shows it.
    body = """\
def far(m):
    return m.range.distance_cm > 50


def beyond(cm, m):
    return m.range.distance_cm > cm


class Lesson(Mission):
    requires = "range"

    def near(self):
        return self.pressed() or self.range.distance_cm < 20

    def pressed(self):
        return self.bumper.any

    go = state(
        Wait(duration_s=1),
        initial=True,
        on_done="end",
        when=[
            (near, "end"),
            ("near", "end"),
            (far, "end"),
            (lambda m: m.elapsed > 3, "end"),
            (partial(beyond, 80), "end"),
        ],
    )
    end = state(final="success")
"""
    assert problems(tmp_path, body, BARE) == [
        # A guard method reads what its code and the methods it calls read, and `requires`.
        f"lesson.py:{line}:13: error: the condition 'near' reads {sensor}, which"
        " stackmod-reference does not have"
        for line in (28, 29)
        for sensor in ("bumper", "range")
    ] + [
        # A function's code is not read: it reads what `requires` says.
        f"lesson.py:{line}:13: error: the condition '{label}' reads range, which"
        " stackmod-reference does not have"
        for line, label in ((30, "far"), (31, "lambda"), (32, "condition"))
    ]


def test_a_function_is_not_the_method_of_the_same_name(tmp_path: Path) -> None:
    # The class body passes the function written above it; the method defined below it, which
    # reads the bumper, is not the condition.
    body = """\
def near(m):
    return m.elapsed > 1


class Lesson(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="end", when=[(near, "end")])
    end = state(final="success")

    def near(self):
        return self.bumper.any
"""
    spec, warnings = compiled(tmp_path, body, BARE)
    assert warnings == []
    assert run(spec).result.final_state == "end"


@pytest.mark.parametrize("written", ['"visits"', "visits"])
def test_a_method_that_replaces_one_of_missions_is_no_condition(
    tmp_path: Path, written: str
) -> None:
    body = f"""\
class Lesson(Mission):
    def visits(self):
        return True

    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[({written}, "end")])
    end = state(final="success")
"""
    # Shown at the def, where the name is chosen (it was "Lesson has no method 'visits' (did
    # you mean 'visits'?)", shown at the condition).
    assert problems(tmp_path, body) == [
        (
            "lesson.py:7:5: error: a condition method cannot be called 'visits': Mission uses that"
            " name (choose another name)"
        )
    ]


def test_a_condition_named_after_a_mission_method_not_redefined_is_no_method(
    tmp_path: Path,
) -> None:
    body = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("visits", "end")])
    end = state(final="success")
"""
    # Mission's own visits() takes a state name: shown at the condition, not in roboscript.
    assert problems(tmp_path, body) == [
        (
            "lesson.py:7:72: error: Lesson has no method 'visits' (define it: def visits(self)"
            " -> bool: ... (return True or False))"
        )
    ]


def test_a_condition_in_an_action_is_compiled_where_it_is_written(tmp_path: Path) -> None:
    body = """\
FOLLOW = FollowLine(until="rnage.distance_cm < 20")


class Lesson(Mission):
    go = state(FOLLOW, initial=True, on_done="end")
    back = state(FollowLine(speed_mm_s=80, until="  rnage.distance_cm < 20"), on_done="end")
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        # Where the action is named, and where in the text the mistake is.
        "lesson.py:10:16: error: unknown name 'rnage' in a condition (did you mean 'range'?)",
        "lesson.py:11:53: error: unknown name 'rnage' in a condition (did you mean 'range'?)",
    ]


def test_a_function_in_an_action_is_a_condition_on_the_mission(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    requires = ("range",)
    go = state(
        FollowLine(speed_mm_s=80, until=lambda m: m.elapsed > 3), initial=True, on_done="end"
    )
    end = state(final="success")
"""
    assert problems(tmp_path, body, BARE) == [
        (
            "lesson.py:9:9: warning: if 'follow_line' fails (lost line or stalled) in state 'go',"
            ' the mission ends in failure (add on_failed="STATE" to handle it)'
        ),
        (
            "lesson.py:9:9: error: 'follow_line' needs line (downward IR line sensors), which"
            " stackmod-reference does not have (use follow_wall or drive with a range condition)"
        ),
        # The lambda became a condition of the mission, which reads what `requires` says.
        (
            "lesson.py:9:9: error: 'follow_line' needs range (a distance sensor (ultrasonic or time"
            " of flight)), which stackmod-reference does not have"
        ),
    ]


def test_compiling_leaves_the_class_as_written(tmp_path: Path) -> None:
    # The template's condition is compiled into a copy of its action: the mission built on
    # it, compiled next, reads its own `near`, not the template's.
    body = """\
class Template(Mission):
    go = state(WaitUntil(condition="near", timeout_s=5), initial=True, on_done="end")
    end = state(final="success")

    def near(self):
        return self.range.distance_cm < 20


class Lesson(Template):
    def near(self):
        return self.bumper.any
"""
    lesson = mission_class(tmp_path, body)
    template = lesson.__mro__[1]
    expected = (
        "lesson.py:{}: error: 'wait_until' needs {} ({}), which stackmod-reference does not have"
    )
    # The inherited state is found by the line of its state(...) only, in the template.
    for cls, where, sensor in (
        (template, "7:16", "range"),
        (lesson, "7", "bumper"),
        (template, "7:16", "range"),
    ):
        with pytest.raises(MissionError) as info:
            compile_mission(cls, BUILTIN_PROFILES[BARE], path="lesson.py")
        assert info.value.format() == expected.format(where, sensor, CAPABILITY_NAMES[sensor])


# -------------------------------------------------------------------------- guard methods


GUARDED = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

"""


@pytest.mark.parametrize(
    ("method", "expected"),
    [
        (
            "    def near(self, cm):\n        return True\n",
            "lesson.py:10:5: error: condition method 'near' must take only self (def near(self):)",
        ),
        (
            "    def near():\n        return True\n",
            "lesson.py:10:5: error: condition method 'near' must take only self (def near(self):)",
        ),
        (
            "    def near(self):\n        return self.visits('ned') > 1\n",
            "lesson.py:11:28: error: visits('ned'): there is no state 'ned' (did you mean 'end'?)",
        ),
        (
            # Another object's visits() is not the mission's.
            "    def near(self, o=None):\n        return self.visits('ned') > o.visits('x')\n",
            "lesson.py:11:28: error: visits('ned'): there is no state 'ned' (did you mean 'end'?)",
        ),
    ],
)
def test_mistakes_in_a_guard_method_are_shown_in_it(
    tmp_path: Path, method: str, expected: str
) -> None:
    assert problems(tmp_path, GUARDED + method) == [expected]


def test_a_guard_method_may_take_parameters_with_defaults(tmp_path: Path) -> None:
    method = "    def near(self, cm=20):\n        return self.elapsed > cm\n"
    _, warnings = compiled(tmp_path, GUARDED + method)
    assert warnings == []


def test_a_guard_method_without_return_is_a_warning_at_its_def(tmp_path: Path) -> None:
    method = "    def near(self):\n        self.elapsed > 1\n"
    _, warnings = compiled(tmp_path, GUARDED + method)
    assert warnings == [
        (
            "lesson.py:10:5: warning: condition method 'near' never returns a value, so it never"
            " holds (return True or False, e.g. return self.bumper.any)"
        )
    ]


def test_a_guard_method_that_is_a_lambda_is_not_warned_about(tmp_path: Path) -> None:
    # Its code cannot be found as a def, so whether it returns cannot be told.
    method = "    near = lambda self: self.elapsed > 1  # noqa: E731\n"
    _, warnings = compiled(tmp_path, GUARDED + method)
    assert warnings == []


def test_helpers_that_call_each_other_are_read_once(tmp_path: Path) -> None:
    # near -> pressed -> touching -> pressed ...: reading them must end, and finds what each
    # reads; it also counts its calls in an attribute the class does not have.
    body = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

    def near(self):
        self.calls = getattr(self, "calls", 0) + 1
        return self.pressed() or self.range.distance_cm < 20 or self.near()

    def pressed(self):
        return self.touching()

    def touching(self):
        return self.bumper.any or self.pressed()
"""
    assert problems(tmp_path, body, BARE) == [
        f"lesson.py:7:71: error: the condition 'near' reads {sensor}, which stackmod-reference"
        " does not have"
        for sensor in ("bumper", "range")
    ]


def test_a_guard_method_used_twice_guards_both_transitions(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="back", when=[("near", "end")])
    back = state(Wait(duration_s=1), on_done="end", when=[("near", "end")])
    end = state(final="success")

    def near(self):
        return self.range.distance_cm < 20
"""
    assert problems(tmp_path, body, BARE) == [
        f"lesson.py:{line}:{col}: error: the condition 'near' reads range, which"
        " stackmod-reference does not have"
        for line, col in ((7, 72), (8, 59))
    ]


# ----------------------------------------------------------------------------- running


@pytest.mark.parametrize(
    ("condition", "reason"),
    [
        # A method is found at its def; a function at the transition that names it.
        (
            '"near"',
            (
                "your condition 'near' returned None instead of True or False (is 'return'"
                " missing?) in state 'go' (lesson.py:14)"
            ),
        ),
        (
            "forgot",
            (
                "your condition 'forgot' returned None instead of True or False (is 'return'"
                " missing?) in state 'go' (lesson.py:11)"
            ),
        ),
    ],
)
def test_a_condition_that_returns_nothing_fails_the_run_naming_where_it_is(
    tmp_path: Path, condition: str, reason: str
) -> None:
    body = """\
def forgot(m):
    m.elapsed > 1


class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[(WHEN, "end")])
    end = state(final="success")

    def near(self):
        if self.elapsed > 5:
            return True
"""
    spec, _ = compiled(tmp_path, body.replace("WHEN", condition))
    assert run(spec).result.reason == reason


def test_an_action_that_keeps_a_condition_under_another_name_compiles(tmp_path: Path) -> None:
    # A student's action need not keep its parameters as attributes of the same names.
    body = """\
from roboscript import Action, Param, Result


class Hold(Action):
    name = "hold_until"
    params = (Param("until", "until", "guard", "when to stop", default=None),)

    def __init__(self, until=None):
        self.stop_when = until

    def update(self, ctx):
        return Result.done()


class Lesson(Mission):
    go = state(Hold(), initial=True, on_done="end")
    end = state(final="success")
"""
    spec, warnings = compiled(tmp_path, body)
    action = spec.states["go"].action
    assert (action is not None and action.name, warnings) == ("hold_until", [])


def test_what_a_parallel_or_repeat_runs_is_checked_as_a_states_action(tmp_path: Path) -> None:
    body = """\
from roboscript import Parallel, PlayTone, Repeat


class Lesson(Mission):
    go = state(Parallel([Drive(distance_mm=300), "beep"]), initial=True, on_done="spin")
    spin = state(Repeat(Drive, times=2), on_done="tune")
    tune = state(Parallel([PlayTone]), on_done="end")
    end = state(final="success")
"""
    assert problems(tmp_path, body) == [
        (
            "lesson.py:10:50: error: state 'go' does 'beep', which is not an action (use an action"
            " such as Drive(distance_mm=300))"
        ),
        (
            "lesson.py:11:25: error: state 'spin': Drive is a kind of action; call it to make one"
            " (write Drive(distance_mm=500))"
        ),
        (
            "lesson.py:12:28: error: state 'tune': PlayTone is a kind of action; call it to make"
            " one (write PlayTone(frequency_hz=880))"
        ),
    ]


def test_a_parallel_and_a_repeat_of_actions_compile_as_yamls_do(tmp_path: Path) -> None:
    body = """\
from roboscript import Parallel, PlayTone, Repeat, Rotate


class Lesson(Mission):
    go = state(Parallel([Drive(distance_mm=300), PlayTone(frequency_hz=440)], "any"),
               initial=True, on_done="spin")
    spin = state(Repeat(Rotate(angle_deg=90), times=4), on_done="end")
    end = state(final="success")
"""
    spec, _ = compiled(tmp_path, body)
    go, spin = spec.states["go"].action, spec.states["spin"].action
    assert go is not None and spin is not None
    assert (go.name, go.kwargs["mode"], go.kwargs["actions"]) == (
        "parallel",
        "any",
        ("drive", "play_tone"),
    )
    assert (spin.name, spin.kwargs["times"], spin.kwargs["action"]) == ("repeat", 4, "rotate")


def test_a_sensor_value_misused_in_a_condition_method_is_found_at_check(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end",
               when=[("bumped", "end"), ("near", "end"), ("again", "end"),
                     ("closer", "end")])
    end = state(final="success")

    def bumped(self):
        return self.bumper.any()

    def near(self):
        return self.range.distance_cm < "20 cm"

    def again(self):
        return self.visits(go) > 1

    def closer(self):
        return self.range.distance_cm < "20"
"""
    assert problems(tmp_path, body) == [
        (
            "lesson.py:13:16: error: self.bumper.any is a value, not a function: it is read"
            " without () (write self.bumper.any)"
        ),
        (
            "lesson.py:16:41: error: self.range.distance_cm is compared with the text '20 cm', and"
            " a sensor's value is a number (or True/False) (compare it with a number in cm:"
            " '20 cm' is 20)"
        ),
        (
            "lesson.py:19:28: error: visits(go) names the state 'go' without quotes (write"
            " self.visits('go'))"
        ),
        (
            "lesson.py:22:41: error: self.range.distance_cm is compared with the text '20', and"
            " a sensor's value is a number (or True/False) (write the number without quotes: 20)"
        ),
    ]


def test_a_sensor_used_as_its_own_value_is_refused_naming_its_values(tmp_path: Path) -> None:
    body = """\
class Lesson(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end",
               when=[("bumped", "end"), ("near", "end")])
    end = state(final="success")

    def bumped(self):
        return self.bumper == True

    def near(self):
        return self.range < 20
"""
    assert problems(tmp_path, body) == [
        (
            "lesson.py:12:16: error: self.bumper is the bumper sensor, not one of its values, so"
            " it is never a number nor True or False (read one of its values, e.g."
            " self.bumper.any (it has left, right, any))"
        ),
        (
            "lesson.py:15:16: error: self.range is the range sensor, not one of its values, so"
            " it is never a number nor True or False (read one of its values, e.g."
            " self.range.distance_cm (it has distance_mm, distance_cm))"
        ),
    ]


def test_a_colour_name_as_text_and_a_state_name_in_a_variable_are_no_mistakes(
    tmp_path: Path,
) -> None:
    body = """\
class Lesson(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end",
               when=[("on_tape", "end"), ("off_red", "end")])
    end = state(final="success")

    def on_tape(self):
        return self.color.reflection < 40 and self.color.name == "black"

    def off_red(self):
        return "red" != self.color.name and any(self.visits(go) > 1 for go in ("go",))
"""
    # no problem: a colour's name is text, and a name the method sets holds its own value
    spec, _ = compiled(tmp_path, body)
    assert [option.guard_text for option in spec.states["go"].when] == ["on_tape", "off_red"]


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        pytest.param(
            "class Lesson(Mission):\n"
            '    go = state([Drive(distance_mm=250)], initial=True, on_done="end")\n'
            '    end = state(final="success")\n',
            "lesson.py:7:16: error: state 'go' is given its action in a list, and a state runs"
            " one action (take away the [ ] around it: state(Drive(distance_mm=250), ...))",
            id="one-action-in-a-list",
        ),
        pytest.param(
            "class Lesson(Mission):\n"
            "    go = state([Drive(distance_mm=250), Wait(duration_s=1)], initial=True,"
            ' on_done="end")\n'
            '    end = state(final="success")\n',
            "lesson.py:7:16: error: state 'go' is given 2 actions in a list, and a state runs one"
            ' (to do them one after another, give each its own state and go on with on_done="NEXT";'
            " to do them at the same time, write state(Parallel([...]), ...))",
            id="two-actions-in-a-list",
        ),
        pytest.param(
            "class Lesson(Mission):\n"
            '    go = state(Wait(duration_s=1), initial=True, on_done=["far", "end"])\n'
            '    end = state(final="success")\n\n'
            "    def far(self) -> bool:\n        return self.elapsed > 1\n",
            "lesson.py:7:59: error: 'far' is a condition method, not a state (a choice made by a"
            " condition is a tuple of the condition and the state it goes to: ('far', 'STATE'))",
            id="a-condition-where-a-state-goes",
        ),
        pytest.param(
            "class Lesson(Mission):\n"
            '    go = state(Wait(duration_s=1), initial=True, when=[(lambda: True, "end")])\n'
            '    end = state(final="success")\n',
            "lesson.py:7:57: error: the condition lambda is called with the mission, and does not"
            " take it (write the condition as a method, def near(self) -> bool: ..., and name it"
            " in quotes: when=[('near', 'STATE')])",
            id="a-lambda-without-the-mission",
        ),
    ],
)
def test_a_state_given_what_it_cannot_use_says_what_to_write(
    tmp_path: Path, body: str, expected: str
) -> None:
    assert problems(tmp_path, body) == [expected]


def test_a_number_without_its_keyword_is_warned_where_another_unit_is_likely(
    tmp_path: Path,
) -> None:
    _, warnings = compiled(
        tmp_path,
        "class Lesson(Mission):\n"
        '    go = state(Drive(30), initial=True, on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
    )
    assert warnings == [
        (
            "lesson.py:7:22: warning: 30, given to Drive without its name, is taken as"
            ' distance_mm=30, 30 mm (name it: distance_mm=30; for 30 cm, write distance_mm="30 cm")'
        )
    ]


def test_a_number_without_its_keyword_in_the_unit_meant_is_no_warning(tmp_path: Path) -> None:
    _, warnings = compiled(
        tmp_path,
        "class Lesson(Mission):\n"
        '    go = state(Wait(3), initial=True, on_done="end")\n'
        '    end = state(final="success")\n',
    )
    assert warnings == []


@pytest.mark.parametrize(
    ("go", "expected"),
    [
        pytest.param(
            'Drive(distance_mm="30")',
            'lesson.py:9:34: warning: distance_mm="30" is a number in quotes, which makes it'
            " text: taken as 30 mm (write the number without quotes: distance_mm=30)",
            id="a-distance",
        ),
        pytest.param(
            'Repeat(Rotate(angle_deg="90"), times=4)',
            'lesson.py:9:40: warning: angle_deg="90" is a number in quotes, which makes it'
            " text: taken as 90 deg (write the number without quotes: angle_deg=90)",
            id="an-angle-inside-a-repeat",
        ),
        pytest.param(
            'Wait("2")',
            'lesson.py:9:21: warning: duration_s="2" is a number in quotes, which makes it'
            " text: taken as 2 s (write the number without quotes: duration_s=2)",
            id="a-time-without-its-keyword",
        ),
    ],
)
def test_a_number_in_quotes_is_warned_at_its_value_with_how_it_was_taken(
    tmp_path: Path, go: str, expected: str
) -> None:
    _, warnings = compiled(
        tmp_path,
        "from roboscript import Repeat, Rotate\n\n"
        "class Lesson(Mission):\n"
        f'    go = state({go}, initial=True, on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
    )
    assert warnings == [expected]


def test_a_number_in_quotes_with_its_unit_is_no_warning(tmp_path: Path) -> None:
    _, warnings = compiled(
        tmp_path,
        "class Lesson(Mission):\n"
        '    go = state(Drive(distance_mm="30 cm"), initial=True, on_done="end",'
        ' on_failed="end")\n'
        '    end = state(final="success")\n',
    )
    assert warnings == []


def test_an_init_that_needs_a_value_is_refused_at_its_def(tmp_path: Path) -> None:
    assert problems(
        tmp_path,
        "class Lesson(Mission):\n"
        '    go = state(Wait(duration_s=1), initial=True, on_done="end")\n'
        '    end = state(final="success")\n\n'
        "    def __init__(self, limit):\n        self.limit = limit\n",
    ) == [
        (
            "lesson.py:10:5: error: Lesson.__init__ needs limit, and roboscript makes the mission"
            " with nothing to give it (give it a default, def __init__(self, limit=...), or set it"
            " in the class: limit = ...)"
        )
    ]
