"""How a Python mission class's states, actions and nested missions compile; where mistakes show.

Each test pins what a student reads (the whole message with its ``file:line:col`` and
hint), the actions a state builds, or which state a run goes through.
"""

from __future__ import annotations

import ast
import sys
import types
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from helpers import refusal

from roboscript.clock import SimClock
from roboscript.errors import MissionError
from roboscript.inputs.source import Location
from roboscript.mission import load_mission
from roboscript.mission.guards import GuardEnv
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.runner import MissionRunner
from roboscript.mission.spec import MissionSpec
from roboscript.mission.student_code import import_student_file
from roboscript.scheduler import Scheduler

Write = Callable[[str, str], Path]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    # Resolved, so that the paths roboscript shows (resolved too) start with it.
    return tmp_path.resolve()


@pytest.fixture
def write(folder: Path) -> Write:
    def write_file(name: str, text: str) -> Path:
        path = folder / name
        path.write_text(text, encoding="utf-8")
        return path

    return write_file


def messages(path: Path) -> list[str]:
    """Every problem loading ``path`` reports, with the folder left out of the paths."""
    return refusal(path, shown={f"{path.parent}/": ""})


def run(spec: MissionSpec, *others: MissionSpec, max_s: float = 30.0) -> list[MissionRunner]:
    """Run missions side by side on one clock (each with its own runner) until all end."""
    sched = Scheduler(SimClock(), 0.02)
    runners = [MissionRunner(s, {}) for s in (spec, *others)]
    for runner in runners:
        sched.add(runner)
    sched.run(until=lambda: all(r.finished for r in runners), max_duration_s=max_s)
    return runners


# ----------------------------------------------------------------------- states and actions

OTHER = """\
from roboscript import Mission, state


class Other(Mission):
    there = state(final=True, initial=True)
"""

MISTAKES = """\
import threading

from pc2_other import Other
from roboscript import Action, Drive, Mission, PlayTone, Result, Wait, WaitUntil, state


class Nameless(Action):
    def update(self, ctx):
        return Result.done()


class Locked(Action):
    name = "locked"

    def __init__(self):
        self.lock = threading.Lock()

    def update(self, ctx):
        return Result.done()


class Mistakes(Mission):
    go = state(Drive(-1e400), initial=True, on_done="end", on_failed="end")
    again = go
    hum = state(Nameless(), on_done="end")
    lock = state(Locked(), on_done="end")
    odd = state(42, on_done="end")
    wait = state(WaitUntil("bumpd", timeout_s=3), on_done="end", on_timeout="end")
    until = state(WaitUntil(condition="bumpd", timeout_s=3), on_done="end", on_timeout="end")
    tune = state(Wait(1), during=[PlayTone(frequency_hz=440, duration_s=1), Wait], on_done="end")
    away = state(Wait(1), on_done=Other.there, when=[("bumped", Other.there)])
    _secret = state(final=True)
    end = state(final="success", description="The end")
    hints = state(Wait(1), when=[("robt", "end"), ("_helpr", "end"), ("  rnage.x < 3", "end")])
    kw = state(action=Drive, on_done="end")
    loose = state(Wait(1), when=["end"])
    three = state(Wait(1), initial="yes", on_done="end")
    robot = "mirto"

    def bumped(self):
        return self.bumper.any

    def _helper(self):
        return True
"""


def test_golden_messages_for_mistakes_in_states_and_actions(write: Write) -> None:
    write("pc2_other.py", OTHER)
    path = write("mistakes.py", MISTAKES)
    not_an_action = "use an action such as Drive(distance_mm=300)"
    assert messages(path) == [
        (
            "mistakes.py:23:5: error: one state(...) is assigned to go and again"
            " (write a separate state(...) for each)"
        ),
        (
            "mistakes.py:23:16: error: drive distance: minus infinity is not a number the robot"
            " can use (write a distance such as '50 cm')"
        ),
        (
            "mistakes.py:24:5: error: one state(...) is assigned to go and again"
            " (write a separate state(...) for each)"
        ),
        # `again = go` has no Drive(...) of its own to point at: the state is shown instead.
        (
            "mistakes.py:24:5: error: drive distance: minus infinity is not a number the robot"
            " can use (write a distance such as '50 cm')"
        ),
        (
            "mistakes.py:24:5: error: states 'go' and 'again' are both initial;"
            " a mission starts in one"
        ),
        (
            "mistakes.py:25:17: error: action class Nameless has no name (give it the word a"
            ' mission uses for it: name = "nameless")'
        ),
        (
            "mistakes.py:26:18: error: state 'lock': locked cannot be copied for each visit"
            " (cannot pickle '_thread.lock' object)"
        ),
        f"mistakes.py:27:17: error: state 'odd' does 42, which is not an action ({not_an_action})",
        "mistakes.py:28:18: error: Mistakes has no method 'bumpd' (did you mean 'bumped'?)",
        "mistakes.py:29:39: error: Mistakes has no method 'bumpd' (did you mean 'bumped'?)",
        (
            "mistakes.py:30:77: error: state 'tune': Wait is a kind of action; call it to make one"
            " (write Wait(duration_s=2))"
        ),
        "mistakes.py:31:35: error: <state there> is not a state of Mistakes",
        "mistakes.py:31:65: error: <state there> is not a state of Mistakes",
        (
            "mistakes.py:32:5: error: a state cannot be called '_secret': Mission uses that name"
            " (choose another name)"
        ),
        # Neither 'robot' (not a method) nor '_helper' (private) is offered as a guess.
        (
            "mistakes.py:34:35: error: Mistakes has no method 'robt'"
            " (define it: def robt(self) -> bool: ... (return True or False))"
        ),
        (
            "mistakes.py:34:52: error: Mistakes has no method '_helpr'"
            " (define it: def _helpr(self) -> bool: ... (return True or False))"
        ),
        "mistakes.py:34:74: error: unknown name 'rnage' in a condition (did you mean 'range'?)",
        (
            "mistakes.py:35:23: error: state 'kw': Drive is a kind of action; call it to make one"
            " (write Drive(distance_mm=500))"
        ),
        (
            "mistakes.py:36:34: error: state 'loose': each 'when' entry is (condition, state)"
            " (e.g. when=[('bumper_hit', 'end')])"
        ),
        "mistakes.py:37:36: error: state 'three': initial is True or False, got 'yes'",
    ]


TEMPLATE = """\
from pc2_far import Far
from roboscript import Drive, Mission, Wait, WaitUntil, state


class Template(Mission):
    go = state(Drive(distance_mm=100), initial=True, on_done="end", on_failed="end")
    slow = state(Wait(1), on_done="end", timeout_s=-1)
    end = state(final="sucess")
    hold = state(WaitUntil("nothing", timeout_s=2), on_done="end", on_timeout="end")
    away = state(Wait(1), on_done=Far.there, when=[("ready", Far.there)])

    def ready(self):
        return self.bumper.any
"""


def test_mistakes_in_inherited_states_are_shown_in_the_file_that_wrote_them(write: Write) -> None:
    # The subclass's own file has no state(...) call for them: each message points at the
    # line of the base class's file instead, never at the subclass's file.
    write("pc2_far.py", OTHER.replace("Other", "Far"))
    write("pc2_template.py", TEMPLATE)
    path = write(
        "child.py",
        "from pc2_template import Template\nfrom roboscript import state\n\n\n"
        "class Child(Template):\n    extra = state(final=True)\n",
    )
    assert messages(path) == [
        (
            "pc2_template.py:7: error: state 'slow': timeout_s is a positive number of seconds,"
            " got -1 (write timeout_s=10)"
        ),
        (
            "pc2_template.py:8: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
        (
            "pc2_template.py:9: error: Child has no method 'nothing'"
            " (define it: def nothing(self) -> bool: ... (return True or False))"
        ),
        "pc2_template.py:10: error: <state there> is not a state of Child",
        "pc2_template.py:10: error: <state there> is not a state of Child",
    ]


def test_a_subclass_without_states_of_its_own_is_checked_like_its_base(write: Write) -> None:
    # Modules are imported once per name: this test has its own.
    write("pc2_far2.py", OTHER.replace("Other", "Far"))
    write("pc2_template2.py", TEMPLATE.replace("pc2_far", "pc2_far2"))
    path = write(
        "bare.py", "from pc2_template2 import Template\n\n\nclass Bare(Template):\n    pass\n"
    )
    # No state(...) of its own to find the class by: it is still found, and checked.
    assert messages(path) == [
        (
            "pc2_template2.py:7: error: state 'slow':"
            " timeout_s is a positive number of seconds, got -1 (write timeout_s=10)"
        ),
        (
            "pc2_template2.py:8: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
        (
            "pc2_template2.py:9: error: Bare has no method 'nothing'"
            " (define it: def nothing(self) -> bool: ... (return True or False))"
        ),
        "pc2_template2.py:10: error: <state there> is not a state of Bare",
        "pc2_template2.py:10: error: <state there> is not a state of Bare",
    ]


def test_of_two_classes_of_one_name_the_mission_is_the_one_whose_states_it_wrote(
    write: Write,
) -> None:
    # The mission's first inherited state (line 5 of the base's file) falls inside the first
    # Hop, so only the lines of the states written in this file find the right class.
    write(
        "pc2_twinbase.py",
        "from roboscript import Mission, Wait, state\n\n\nclass Base(Mission):\n"
        '    first = state(Wait(1), initial=True, on_done="own")\n',
    )
    path = write(
        "twins.py",
        """\
from pc2_twinbase import Base
from roboscript import Mission, Wait, state


class Hop(Mission):
    hop = state(Wait(1), initial=True, on_done="ok")
    ok = state(final="success")


First = Hop


class Hop(Base):  # noqa: F811 - a second class of the same name, the mission
    own = state(First, on_done="end", timeout_s=-2)
    end = state(final="sucess")
""",
    )
    assert messages(path) == [
        (
            "twins.py:14:49: error: state 'own': timeout_s is a positive number of seconds, got -2"
            " (write timeout_s=10)"
        ),
        (
            "twins.py:15:23: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
    ]


def test_the_mission_and_its_attributes_are_located_where_written(write: Write) -> None:
    path = write(
        "where.py",
        """\
from roboscript import Mission, PlayTone, Wait, state


class Where(Mission):
    robot = "mirto"
    world = "square-room"
    go = state(
        Wait(1), initial=True, on_done="end", during=PlayTone(frequency_hz=440, duration_s=1)
    )
    end = state(final=True, description="Stopped.")
""",
    )
    spec, warnings = load_mission(path)
    shown = str(path)
    assert warnings == []
    assert (spec.path, spec.location) == (shown, Location(shown, 4, 1))
    assert (spec.robot, spec.robot_location) == ("mirto", Location(shown, 5, 13))
    assert (spec.world, spec.world_location) == ("square-room", Location(shown, 6, 13))
    # A class without a docstring has no description; a state keeps its own.
    assert (spec.description, spec.states["end"].description) == ("", "Stopped.")
    # One action given to during= runs alongside, as a list of one would.
    assert [(a.name, a.location) for a in spec.states["go"].during] == [
        ("play_tone", Location(shown, 8, 54))
    ]


def test_attributes_of_the_wrong_kind_are_shown_at_their_line(write: Write) -> None:
    path = write(
        "attrs.py",
        """\
from roboscript import Mission, Wait, state


class Attrs(Mission):
    go = state(Wait(1), initial=True, on_done="end")
    end = state(final=True)
    robot = 5
    world = ("square-room",)
    name = 7
    requires = "rnage"
""",
    )
    assert messages(path) == [
        "attrs.py:7:13: error: 'robot' names a robot, e.g. robot = \"mirto\"",
        "attrs.py:8:13: error: 'world' names a world, e.g. world = \"square-room\"",
        "attrs.py:9:12: error: 'name' is the mission's name, as text",
        "attrs.py:10:16: error: requires: unknown capability 'rnage' (did you mean 'range'?)",
    ]


# ------------------------------------------------------------------------ nested missions

LESSON = """\
from roboscript import Mission, Wait, state


class Hop(Mission):
    hop = state(Wait(1), initial=True, on_done="ok", timeout_s=-1)
    ok = state(final="success")


class Twice(Mission):
    one = state(Hop, initial=True, on_done="two")
    two = state(Hop, on_done="end")
    end = state(final="sucess")
"""


def test_messages_name_the_file_as_the_caller_names_it(write: Write) -> None:
    # Twice and the Hop it nests share one file: both are shown under the name given.
    path = write("pc2_lesson.py", LESSON)
    twice = import_student_file(path).Twice
    with pytest.raises(MissionError) as info:
        compile_mission(twice, path="lesson.py")
    assert [p.format() for p in info.value.problems] == [
        (
            "lesson.py:5:64: error: state 'hop': timeout_s is a positive number of seconds, got -1"
            " (write timeout_s=10)"
        ),
        (
            "lesson.py:12:23: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
    ]
    # Without a name given, the file is shown as it is (relative to the working folder).
    with pytest.raises(MissionError) as info:
        compile_mission(twice)
    assert [p.format() for p in info.value.problems] == [
        (
            f"{path}:5:64: error: state 'hop': timeout_s is a positive number of seconds, got -1"
            " (write timeout_s=10)"
        ),
        (
            f"{path}:12:23: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
    ]


def test_a_mission_nested_twice_deeper_down_is_warned_about_once(write: Write) -> None:
    path = write(
        "deep.py",
        """\
from roboscript import Drive, Mission, state


class Hop(Mission):
    hop = state(Drive(distance_mm=100), initial=True, on_done="ok")
    ok = state(final="success")


class Left(Mission):
    hop = state(Hop, initial=True, on_done="done", on_failed="done")
    done = state(final="success")


class Right(Mission):
    hop = state(Hop, initial=True, on_done="done", on_failed="done")
    done = state(final="success")


class Both(Mission):
    left = state(Left, initial=True, on_done="right", on_failed="right")
    right = state(Right, on_done="end", on_failed="end")
    end = state(final="success")
""",
    )
    _, warnings = load_mission(path)
    assert [w.format().replace(f"{path.parent}/", "") for w in warnings] == [
        (
            "deep.py:5:17: warning: if 'drive' fails (stalled) in state 'hop', the mission ends"
            ' in failure (add on_failed="STATE" to handle it)'
        )
    ]


def test_a_mission_cannot_nest_itself(write: Write) -> None:
    path = write(
        "loop.py",
        """\
from roboscript import Mission, Wait, state


class Loop(Mission):
    go = state(Wait(1), initial=True, on_done="end")
    end = state(final=True)


Loop.again = state(Loop, on_done="end")
""",
    )
    assert messages(path) == [
        "loop.py:9: error: state 'again' nests its own mission (nest another Mission class)"
    ]


# --------------------------------------------------------------------- guards when running

COUNT = """\
from roboscript import Mission, Wait, state


class Hop(Mission):
    hop = state(Wait(0.1), initial=True, on_done="ok")
    ok = state(final="success")


class Count(Mission):
    go = state(Wait(2), initial=True, on_done="slow", when=[("third_look", "nest")])
    nest = state(Hop, on_done="quick")
    quick = state(final="success")
    slow = state(final="failure")

    def third_look(self):
        self.looks = getattr(self, "looks", 0) + 1
        return self.looks >= 3
"""


def test_each_run_keeps_its_own_mission_object_and_nested_states_are_prefixed(
    write: Write,
) -> None:
    path = write("count.py", COUNT)
    spec, _ = load_mission(path)
    nest = spec.states["nest"].action
    assert nest is not None and nest.location == Location(str(path), 11, 18)
    # Two runs of one mission, ticking in turn: each counts its own looks.
    runners = run(spec, spec)
    for runner in runners:
        assert runner.result.outcome == "success"
        assert [name for _, name in runner.result.states] == [
            "go",
            "nest",
            "nest.hop",
            "nest.ok",
            "quick",
        ]
        assert runner.result.states[1][0] == pytest.approx(0.04)


class Unhashable(GuardEnv):
    """A runner that cannot be a dictionary key (it compares by value)."""

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Unhashable)

    __hash__ = None  # type: ignore[assignment]


def test_a_runner_that_cannot_be_a_key_keeps_its_mission_object(write: Write) -> None:
    spec, _ = load_mission(write("count.py", COUNT))
    guard = spec.states["go"].when[0].guard
    assert guard is not None
    env = Unhashable()
    assert [guard(env), guard(env), guard(env)] == [False, False, True]


def test_mistakes_in_guard_code_when_running_are_one_sentence_with_the_line(
    write: Write,
) -> None:
    path = write(
        "oops.py",
        """\
from roboscript import Mission, Wait, state


class Sneaky(Mission):
    go = state(Wait(1), initial=True, on_done="end", when=[("sneaky", "end")])
    end = state(final=True)

    def sneaky(self):
        return self.visits("no" + "where") > 0


class Forgot(Mission):
    go = state(Wait(1), initial=True, on_done="end", when=[("forgot", "end")])
    end = state(final=True)

    def forgot(self):
        self.elapsed > 1


class Fussy(Mission):
    go = state(Wait(1), initial=True, on_done="end", when=[("never", "end")])
    end = state(final=True)

    def __init__(self):
        super().__init__()
        raise ValueError("not today")

    def never(self):
        return False
""",
    )
    module = import_student_file(path)
    reasons = []
    for cls in (module.Sneaky, module.Forgot, module.Fussy):
        spec, _ = compile_mission(cls, path=str(path))
        (runner,) = run(spec)
        assert runner.result.outcome == "failure"
        reasons.append(str(runner.result.reason).replace(f"{path.parent}/", ""))
    assert reasons == [
        (
            "your condition 'sneaky' raised KeyError in state 'go':"
            " \"there is no state 'nowhere'\" (oops.py:9)"
        ),
        (
            "your condition 'forgot' returned None instead of True or False"
            " (is 'return' missing?) in state 'go' (oops.py:16)"
        ),
        "your mission class Fussy raised ValueError in state 'go': not today (oops.py:26)",
    ]


# ------------------------------------------------------------------- where conditions are


def test_conditions_and_their_methods_are_shown_where_written(write: Write) -> None:
    path = write(
        "conds.py",
        """\
from roboscript import Mission, Wait, state

COND = "rnage.x < 3"


class Conds(Mission):
    go = state(Wait(1), initial=True, on_done="end", when=[(COND, "end"), (
        "bumper.any and "
        "rnage.x", "end")])
    end = state(final=True)
    quick = lambda self, x: True  # noqa: E731
    short = state(Wait(1), on_done="end", when=[("quick", "end")])

    def wrong(self, x):
        return True

    long = state(Wait(1), on_done="end", when=[("wrong", "end")])
""",
    )
    # A condition held in a variable or split over lines is shown where it starts: its
    # characters are not where the file has them.
    assert messages(path) == [
        "conds.py:7:61: error: unknown name 'rnage' in a condition (did you mean 'range'?)",
        "conds.py:8:9: error: unknown name 'rnage' in a condition (did you mean 'range'?)",
        "conds.py:11: error: condition method 'quick' must take only self (def quick(self):)",
        "conds.py:14:5: error: condition method 'wrong' must take only self (def wrong(self):)",
    ]


def test_a_method_given_as_a_function_is_read_for_the_sensors_it_needs(write: Write) -> None:
    path = write(
        "funcs.py",
        """\
from roboscript import Mission, Wait, state


def ready(mission):
    return True


class Funcs(Mission):
    def bumped(self):
        return self.bumper.any

    go = state(Wait(1), initial=True, on_done="other", when=[(bumped, "end")])
    # The function defined above the class, not the method of the same name below.
    other = state(Wait(1), on_done="end", when=[(ready, "end")])
    end = state(final=True)

    def ready(self):
        return self.line.any
""",
    )
    spec, _ = load_mission(path)
    assert spec.requires() == frozenset({"bumper"})


def test_a_mission_whose_file_is_gone_is_named_by_that_file(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    gone = folder / "gone.py"
    module = types.ModuleType("pc2_gone")
    module.__file__ = str(gone)
    monkeypatch.setitem(sys.modules, "pc2_gone", module)
    code = (
        "from roboscript import Mission, Wait, state\n\n\nclass Ghost(Mission):\n"
        "    go = state(Wait(1), on_done='end')\n    end = state(final=True)\n"
    )
    exec(compile(code, str(gone), "exec"), module.__dict__)  # noqa: S102 - a file now deleted
    with pytest.raises(MissionError) as info:
        compile_mission(module.Ghost)
    assert [p.format() for p in info.value.problems] == [
        (
            f"{gone}: error: mission Ghost has no initial state"
            " (mark the first state, e.g. go = state(..., initial=True))"
        )
    ]


def _kept_actions(states: int) -> str:
    """A mission of ``states`` states, each running an action kept under a name above it."""
    lines = ["from roboscript import Mission, Rotate, state", "", "", "class M(Mission):"]
    for k in range(states):
        lines.append(f"    turn{k} = Rotate(angle_deg=90)")
        lines.append(f"    s{k} = state(turn{k}, initial={k == 0}, on_done='s{k + 1}')")
    lines.append(f"    s{states} = state(final='success')")
    return "\n".join(lines) + "\n"


def test_checking_a_mission_reads_its_class_in_time_that_grows_with_its_states_not_faster(
    write: Write, monkeypatch: pytest.MonkeyPatch
) -> None:
    # whether each kept action is a state's (turn = Rotate(...); a = state(turn)) or a state
    # without its state(...) is told from the names the class reads: one walk of the class
    # for all its statements, not one per statement (a class of 4x the states is walked 4x)
    walked = [0]
    walk = ast.walk

    def counted(node: ast.AST) -> Iterator[ast.AST]:
        for found in walk(node):
            walked[0] += 1
            yield found

    monkeypatch.setattr(ast, "walk", counted)
    nodes = []
    for states in (10, 40):
        walked[0] = 0
        spec, _ = load_mission(write(f"kept{states}.py", _kept_actions(states)))
        assert len(spec.states) == states + 1
        nodes.append(walked[0])
    assert nodes[1] <= 4 * nodes[0]


def test_a_robot_given_as_a_profile_object_says_to_name_it(write: Write) -> None:
    path = write(
        "fast.py",
        """\
import dataclasses
from roboscript import Mission, Wait, state
from roboscript.profiles import get_profile


class Fast(Mission):
    robot = dataclasses.replace(get_profile("mirto"), max_speed_mm_s=600)
    go = state(Wait(1), initial=True, on_done="end")
    end = state(final=True)
""",
    )
    assert messages(path) == [
        (
            "fast.py:7:13: error: 'robot' is given a robot profile, and a mission names its"
            ' robot (write robot = "mirto"; a robot of your own is a profile file beside the'
            ' mission, named the same way: robot = "my_robot.yaml")'
        ),
    ]


def test_initial_as_text_says_to_write_it_without_quotes(write: Write) -> None:
    path = write(
        "quoted.py",
        """\
from roboscript import Mission, Wait, state


class Quoted(Mission):
    go = state(Wait(1), initial="True", on_done="end")
    end = state(final=True)
""",
    )
    assert messages(path) == [
        (
            "quoted.py:5:33: error: state 'go': initial is True or False, got 'True' (write"
            " initial=True, without quotes)"
        ),
    ]


def test_a_state_written_twice_is_refused_at_the_second(write: Write) -> None:
    path = write(
        "twice.py",
        """\
from roboscript import Drive, Mission, Rotate, state


class Twice(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end", on_failed="end")
    go = state(Rotate(angle_deg=90), initial=True, on_done="end", on_failed="end")
    end = state(final=True)
""",
    )
    assert messages(path) == [
        (
            "twice.py:6:5: error: 'go' is given twice (first on line 5), and Python keeps only the"
            " second (keep one of the two, or give one of them another name)"
        ),
    ]


def test_a_condition_written_outside_the_class_says_to_indent_it(write: Write) -> None:
    path = write(
        "outside.py",
        """\
from roboscript import Drive, Mission, state


class Outside(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end", on_failed="end",
               when=[("near", "end")])
    end = state(final=True)


def near(self):
    return self.range.distance_cm < 20
""",
    )
    assert messages(path) == [
        (
            "outside.py:6:23: error: Outside has no method 'near' ('near' is written outside the"
            " class: indent its def under class Outside: to make it a method)"
        ),
    ]


def test_a_behaviours_requires_as_text_or_missing_name_says_what_to_write(write: Write) -> None:
    path = write(
        "spin.py",
        """\
from roboscript import Action, Mission, Result, state


class Spin(Action):
    requires = "drive_base"
    name = "spin"

    def update(self, ctx):
        return Result.done()


class Nameless(Action):
    def update(self, ctx):
        return Result.done()


class M(Mission):
    go = state(Spin(), initial=True, on_done="next")
    next = state(Nameless(), on_done="end")
    end = state(final=True)
""",
    )
    assert messages(path) == [
        (
            "spin.py:18:16: error: Spin.requires is a set of capability names, not 'drive_base'"
            ' (write requires = frozenset({"drive_base"}))'
        ),
        (
            "spin.py:19:18: error: action class Nameless has no name (give it the word a mission"
            ' uses for it: name = "nameless")'
        ),
    ]
