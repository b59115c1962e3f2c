"""Python missions as classes: what they compile to, how guard methods run, and their errors."""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any, NoReturn

import pytest
from helpers import MISSIONS, ROOT
from helpers import refusal as messages

from roboscript import Drive, Mission, PlayTone, Rotate, Wait, WaitUntil, state
from roboscript.capabilities import COLOR
from roboscript.clock import SimClock
from roboscript.errors import MissionError
from roboscript.mission import load_mission, python_api
from roboscript.mission.checks import check_capabilities
from roboscript.mission.python_api import _run_at_exit, _Script, note_mission_run
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.runner import MissionRunner
from roboscript.mission.sensor_readings import color_or_buttons
from roboscript.mission.student_code import shown_path
from roboscript.profiles import get_profile
from roboscript.scheduler import Scheduler


class FakeBase:
    track_mm = 160.0
    max_speed_mm_s = 300.0
    odometry_is_estimated = False

    def __init__(self) -> None:
        self.speeds = (0.0, 0.0)
        self.travel = [0.0, 0.0]

    def set_wheel_speeds(self, left: float, right: float) -> None:
        self.speeds = (left, right)

    def stop(self) -> None:
        self.speeds = (0.0, 0.0)

    def wheel_distances_mm(self) -> tuple[float, float]:
        return self.travel[0], self.travel[1]

    def tick(self, now: float, dt: float) -> None:
        self.travel[0] += self.speeds[0] * dt
        self.travel[1] += self.speeds[1] * dt


class FakeSpeaker:
    def __init__(self) -> None:
        self.tones: list[tuple[float, float]] = []

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        self.tones.append((frequency_hz, duration_s))


class FakeRange:
    def __init__(self) -> None:
        self.mm: float | None = 1000.0

    def distance_mm(self) -> float | None:
        return self.mm


def run(cls: type[Mission], max_s: float = 60.0, **caps: Any) -> MissionRunner:
    spec, _ = compile_mission(cls)
    base = caps.setdefault("drive_base", FakeBase())
    caps.setdefault("speaker", FakeSpeaker())
    sched = Scheduler(SimClock(), 0.02)
    sched.add(base, "sense")
    runner = MissionRunner(spec, caps)
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=max_s)
    return runner


class Square(Mission):
    """Drive a square
    and beep at every corner.

    Twice as fun.
    """

    robot = "mirto"

    side = state(
        Drive(distance_mm=200, speed_mm_s=100),
        initial=True,
        timeout_s=10,
        on_done="corner",
        on_failed="stuck",
        on_timeout="stuck",
    )
    corner = state(Rotate(angle_deg=90), on_done="beep", on_failed="stuck")
    beep = state(
        PlayTone(frequency_hz=880, duration_s=0.1),
        on_done=[("four_sides_done", "finished"), "side"],
    )
    stuck = state(PlayTone(frequency_hz=220), final="failure")
    finished = state(final="success")

    def four_sides_done(self) -> bool:
        return self.visits("side") >= 4


def test_a_mission_class_compiles_to_states_targets_and_actions() -> None:
    spec, warnings = compile_mission(Square)
    assert warnings == []
    assert spec.name == "square"
    assert spec.description == "Drive a square and beep at every corner.\n\nTwice as fun."
    assert (spec.robot, spec.world) == ("mirto", None)
    assert spec.initial == "side"
    assert list(spec.states) == ["side", "corner", "beep", "stuck", "finished"]
    side = spec.states["side"]
    assert side.action is not None and side.action.name == "drive"
    assert side.action.kwargs["distance_mm"] == 200 and side.action.kwargs["speed_mm_s"] == 100
    assert side.timeout_s == 10.0
    assert {k: [t.target for t in v] for k, v in side.on.items()} == {
        "done": ["corner"],
        "failed": ["stuck"],
        "timeout": ["stuck"],
    }
    beep = spec.states["beep"].on["done"]
    assert [(t.target, t.guard_text) for t in beep] == [
        ("finished", "four_sides_done"),
        ("side", None),
    ]
    assert spec.states["stuck"].final == "failure" and spec.states["finished"].final == "success"
    assert spec.requires() == {"drive_base", "speaker"}


def test_a_mission_class_runs_with_its_guard_methods() -> None:
    speaker = FakeSpeaker()
    runner = run(Square, speaker=speaker)
    assert runner.result.outcome == "success"
    names = [name for _, name in runner.result.states]
    assert names == ["side", "corner", "beep"] * 4 + ["finished"]
    assert speaker.tones == [(880, 0.1)] * 4


def test_each_condition_is_evaluated_once_a_tick_in_order_up_to_the_first_that_holds() -> None:
    calls: list[tuple[str, int]] = []

    class Counting(Mission):
        go = state(
            Wait(duration_s=10),
            initial=True,
            on_done="late",
            when=[("never", "late"), ("third_tick", "end"), ("also_never", "late")],
        )
        late = state(final="failure")
        end = state(final="success")

        def __init__(self) -> None:
            super().__init__()
            self.ticks = 0

        def never(self) -> bool:
            self.ticks += 1
            calls.append(("never", self.ticks))
            return False

        def third_tick(self) -> bool:
            calls.append(("third_tick", self.ticks))
            return self.ticks >= 3

        def also_never(self) -> bool:
            calls.append(("also_never", self.ticks))
            return False

    runner = run(Counting)
    assert runner.result.outcome == "success"
    assert calls == [
        ("never", 1), ("third_tick", 1), ("also_never", 1),
        ("never", 2), ("third_tick", 2), ("also_never", 2),
        ("never", 3), ("third_tick", 3),
    ]  # fmt: skip
    cause = runner.last_cause
    assert cause is not None and cause.kind == "when" and cause.condition == "third_tick"


def test_every_visit_runs_a_fresh_copy_of_the_action() -> None:
    template = Drive(distance_mm=200)

    class Twice(Mission):
        go = state(template, initial=True, on_done=[("again", "go"), "end"])
        end = state(final=True)

        def again(self) -> bool:
            return self.visits("go") < 2

    spec, _ = compile_mission(Twice)
    action = spec.states["go"].action
    assert action is not None
    first, second = action.factory(), action.factory()
    assert first is not second and first is not template
    assert run(Twice).result.outcome == "success"
    assert template._origin == (0.0, 0.0)  # the template itself never ran


def test_guard_methods_read_the_mission_values_and_declare_what_they_read() -> None:
    class Approach(Mission):
        go = state(Drive(distance_mm=5000), initial=True, on_done="end", when=[("close", "end")])
        end = state(PlayTone(frequency_hz=440), final="success")

        def close(self) -> bool:
            return self.near(300) and self.state_time > 0.5 and self.elapsed > 0.5

        def near(self, limit_mm: float) -> bool:
            return self.range.distance_mm < limit_mm

    spec, _ = compile_mission(Approach)
    (transition,) = spec.states["go"].when
    assert transition.guard is not None
    assert set(getattr(transition.guard, "capabilities", ())) == {"range"}
    assert spec.requires() == {"drive_base", "speaker", "range"}

    sensor = FakeRange()
    base = FakeBase()

    def closer(now: float, dt: float) -> None:
        sensor.mm = 1000.0 - (base.travel[0] + base.travel[1]) / 2

    sched = Scheduler(SimClock(), 0.02)
    sched.add(base, "sense")
    sched.add(closer, "sense")
    runner = MissionRunner(spec, {"drive_base": base, "speaker": FakeSpeaker(), "range": sensor})
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=30)
    assert runner.result.outcome == "success"
    assert sensor.mm is not None and 290 < sensor.mm < 300  # 150 mm/s, 3 mm a tick


def test_capabilities_read_by_guard_methods_are_checked_against_the_robot() -> None:
    class LineCounter(Mission):
        requires = ("heading",)
        go = state(Drive(distance_mm=500), initial=True, on_done="end", when=[("dark", "end")])
        end = state(final=True)

        def dark(self) -> bool:
            return self.line.any

    spec, _ = compile_mission(LineCounter)
    problems = [p.message for p in check_capabilities(spec, get_profile("mirto"))]
    assert problems == ["the condition 'dark' reads heading, which mirto does not have"]
    problems = [p.message for p in check_capabilities(spec, get_profile("stackmod-reference"))]
    assert problems == [
        "the condition 'dark' reads heading, which stackmod-reference does not have",
        "the condition 'dark' reads line, which stackmod-reference does not have",
    ]


def test_a_condition_that_is_not_a_plain_name_is_an_expression() -> None:
    class Timed(Mission):
        go = state(
            Wait(duration_s=5), initial=True, on_done="end", when=[("state_time >= 1 s", "end")]
        )
        end = state(final=True)

    runner = run(Timed)
    assert runner.result.outcome == "success"
    assert 1.0 <= runner.result.duration_s < 1.1


def test_condition_parameters_of_actions_take_methods_or_expressions() -> None:
    class Waiting(Mission):
        first = state(
            WaitUntil(condition="elapsed > 0.5", timeout_s=5), initial=True, on_done="second"
        )
        second = state(WaitUntil(condition="later", timeout_s=5), final="success")

        def later(self) -> bool:
            return self.elapsed > 1.0

    runner = run(Waiting)
    assert runner.result.outcome == "success"
    assert 1.0 < runner.result.duration_s < 1.1


def test_targets_may_be_state_objects_and_conditions_functions() -> None:
    class Objects(Mission):
        end = state(final=True)
        go = state(
            Wait(duration_s=5), initial=True, on_done=end, when=[(lambda m: m.elapsed > 1, end)]
        )

    spec, _ = compile_mission(Objects)
    (transition,) = spec.states["go"].when
    assert (transition.target, transition.guard_text) == ("end", "lambda")
    runner = run(Objects)
    assert runner.result.outcome == "success"
    assert 1.0 < runner.result.duration_s < 1.1


def test_during_runs_actions_alongside_the_state_action() -> None:
    class Tune(Mission):
        go = state(
            Drive(distance_mm=200, speed_mm_s=100),
            initial=True,
            during=[PlayTone(frequency_hz=440, duration_s=0.5)],
            on_done="end",
            on_failed="end",
        )
        end = state(final=True)

    spec, _ = compile_mission(Tune)
    assert [extra.name for extra in spec.states["go"].during] == ["play_tone"]
    speaker = FakeSpeaker()
    assert run(Tune, speaker=speaker).result.outcome == "success"
    assert speaker.tones == [(440, 0.5)]


def test_a_guard_method_that_raises_ends_the_mission_in_one_sentence() -> None:
    class Oops(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("broken", "end")])
        end = state(final=True)

        def broken(self) -> bool:
            return self.elapsed > 0.1 and 1 / 0 > 0

    runner = run(Oops)
    assert runner.result.outcome == "failure"
    line = Oops.broken.__code__.co_firstlineno + 1
    assert runner.result.reason == (
        "your condition 'broken' raised ZeroDivisionError in state 'go': division by zero"
        f" ({shown_path(__file__)}:{line})"
    )


def test_a_guard_method_that_calls_exit_ends_the_run_not_the_program() -> None:
    class Quits(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("quits", "end")])
        end = state(final=True)

        def quits(self) -> bool:
            raise SystemExit(0)  # what exit() and sys.exit() raise

    runner = run(Quits)
    assert runner.result.outcome == "failure"
    line = Quits.quits.__code__.co_firstlineno + 1
    assert runner.result.reason == (
        "your condition 'quits' called exit() in state 'go': a mission ends by going to a final"
        f" state, not by ending the program ({shown_path(__file__)}:{line})"
    )


class Gone(BaseException):
    """A student's own exception beyond ``Exception``: ``except Exception`` lets it through."""


def test_a_guard_method_that_raises_its_own_base_exception_ends_the_run_not_the_program() -> None:
    class Leaves(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("leaves", "end")])
        end = state(final=True)

        def leaves(self) -> bool:
            raise Gone("bye")

    runner = run(Leaves)
    assert runner.result.outcome == "failure"
    assert runner.result.code_error
    line = Leaves.leaves.__code__.co_firstlineno + 1
    assert runner.result.reason == (
        f"your condition 'leaves' raised Gone in state 'go': bye ({shown_path(__file__)}:{line})"
    )


def test_a_guard_method_without_return_is_a_warning_and_a_failure_when_run() -> None:
    class Forgot(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("forgot", "end")])
        end = state(final=True)

        def forgot(self) -> bool:
            self.elapsed > 1  # noqa: B015 - the mistake under test

    _spec, warnings = compile_mission(Forgot)
    assert [w.message for w in warnings] == [
        "condition method 'forgot' never returns a value, so it never holds"
    ]
    runner = run(Forgot)
    assert runner.result.outcome == "failure"
    assert runner.result.reason is not None
    assert runner.result.reason.startswith(
        "your condition 'forgot' returned None instead of True or False (is 'return' missing?)"
        " in state 'go'"
    )


def test_a_guard_method_returning_text_is_refused_at_load_and_when_run() -> None:
    class Says(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("says", "end")])
        end = state(final=True)

        def says(self) -> bool:
            return "no"  # type: ignore[return-value] - the mistake under test

    with pytest.raises(MissionError, match="returns the text 'no', and any text but"):
        compile_mission(Says)

    class Computes(Mission):  # text the check cannot see: refused when the run reads it
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("says", "end")])
        end = state(final=True)

        def says(self) -> bool:
            return str(self.elapsed > 1)  # type: ignore[return-value]

    runner = run(Computes)
    assert runner.result.outcome == "failure"
    assert (runner.result.reason or "").startswith(
        "your condition 'says' returned the text 'False' instead of True or False"
    )


def test_a_condition_that_yields_is_refused_at_load_and_when_run() -> None:
    class Yields(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("near", "end")])
        end = state(final=True)

        def near(self) -> Any:
            yield self.elapsed > 1

    with pytest.raises(MissionError, match="uses yield, so it returns a generator"):
        compile_mission(Yields)

    def later(mission: Mission) -> Any:  # a function the check does not read
        yield mission.elapsed > 1

    class Passes(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[(later, "end")])
        end = state(final=True)

    runner = run(Passes)
    assert runner.result.outcome == "failure"
    assert "returned a generator (it uses yield) instead of True or False" in (
        runner.result.reason or ""
    )


def test_mission_values_are_read_only_and_only_there_while_running() -> None:
    with pytest.raises(RuntimeError, match="only be read while the mission runs"):
        _ = Square().elapsed
    mission = Square()
    with pytest.raises(AttributeError):
        mission.elapsed = 3.0  # type: ignore[misc]


def test_a_subclass_can_replace_one_state() -> None:
    class Slow(Square):
        corner = state(Rotate(angle_deg=90, turn_rate_deg_s=30), on_done="beep")

    spec, _ = compile_mission(Slow)
    assert list(spec.states) == ["side", "corner", "beep", "stuck", "finished"]
    corner = spec.states["corner"].action
    assert corner is not None and corner.kwargs["turn_rate_deg_s"] == 30


# ------------------------------------------------------------------------ golden messages

BAD = """\
from roboscript import Drive, Mission, PlayTone, Rotate, state


class Bad(Mission):
    side = state(Drive(distance_mm=500), initial=True, on_done="cornr", when=[("bumpd", "end")])
    corner = state(Rotate(angle_deg=90), on_done=[("visits.sied >= 4", "end"), "side"])
    beep = state(PlayTone, on_done=("side", "end"))
    wait = state(timeout_s=-1, on_timeout="end", initial=True)
    end = state(final="sucess")
    range = state(final=True)

    def bumped(self) -> bool:
        return self.bumper.any
"""


def test_golden_messages_for_a_bad_python_mission(write_mission: Callable[..., Path]) -> None:
    path = write_mission(BAD, "bad.py")
    assert messages(path) == [
        "M:5:64: error: there is no state 'cornr' (did you mean 'corner'?)",
        "M:5:80: error: Bad has no method 'bumpd' (did you mean 'bumped'?)",
        "M:6:60: error: 'visits.sied': there is no state 'sied' (did you mean 'visits.side'?)",
        (
            "M:7:18: error: state 'beep': PlayTone is a kind of action; call it to make one"
            " (write PlayTone(frequency_hz=880))"
        ),
        (
            "M:7:37: error: 'side' is a state, not a condition (a condition names a method that"
            " returns True or False; for several choices, use a list: [(condition, state), state])"
        ),
        (
            "M:8:28: error: state 'wait': timeout_s is a positive number of seconds, got -1"
            " (write timeout_s=10)"
        ),
        "M:8:58: error: states 'side' and 'wait' are both initial; a mission starts in one",
        (
            "M:9:23: error: state 'end': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
        (
            "M:10:5: error: a state cannot be called 'range': Mission uses that name"
            " (choose another name)"
        ),
    ]


def test_structure_checks_are_the_yaml_ones_with_hints_in_python(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        "from roboscript import Drive, Mission, state\n"
        "\n"
        "class Lost(Mission):\n"
        "    go = state(Drive(distance_mm=100), initial=True, on_done='end', on_failed='end')\n"
        "    end = state(final=True)\n"
        "    island = state(Drive(distance_mm=100))\n",
        "lost.py",
    )
    assert messages(path) == [
        (
            "M:6:5: error: state 'island' can never be reached from 'go'"
            " (add a transition to it, or remove it)"
        ),
        (
            "M:6:5: error: state 'island' has no way out"
            ' (add on_done="NEXT", a when= condition, or final="success")'
        ),
        (
            "M:6:20: warning: if 'drive' fails (stalled) in state 'island', the mission ends in"
            ' failure (add on_failed="STATE" to handle it)'
        ),
    ]


def test_a_mission_without_initial_state_says_how_to_mark_one(
    write_mission: Callable[..., Path],
) -> None:
    path = write_mission(
        "from roboscript import Drive, Mission, state\n"
        "\n"
        "class NoStart(Mission):\n"
        "    go = state(Drive(distance_mm=100), on_done='end', on_failed='end')\n"
        "    end = state(final=True)\n",
        "nostart.py",
    )
    assert messages(path) == [
        (
            "M:3:1: error: mission NoStart has no initial state"
            " (mark the first state, e.g. go = state(..., initial=True))"
        )
    ]


# ------------------------------------------------------------------------------- exports


def test_importing_roboscript_loads_no_heavy_library() -> None:
    code = (
        "import sys, roboscript\n"
        "heavy = {'transitions', 'yaml', 'serial'} & {m.split('.')[0] for m in sys.modules}\n"
        "assert not heavy, heavy\n"
        "from roboscript import Mission, state, Drive, Rotate, PlayTone, Wait, Stop\n"
        "heavy = {'transitions', 'yaml', 'serial'} & {m.split('.')[0] for m in sys.modules}\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_every_built_in_action_is_exported_by_its_class_name() -> None:
    import roboscript
    from roboscript.actions import ACTIONS

    for cls in ACTIONS.values():
        assert cls.__name__ in roboscript.__all__, f"roboscript.__all__ lacks {cls.__name__}"
        assert getattr(roboscript, cls.__name__) is cls
    with pytest.raises(AttributeError):
        _ = roboscript.Drvie  # type: ignore[attr-defined]


def test_the_python_tutorial_lists_every_action_with_its_keywords() -> None:
    from roboscript.actions import ACTIONS

    tutorial = (ROOT / "docs" / "tutorial" / "python-missions.md").read_text(encoding="utf-8")
    rows = {line.split("|")[1].strip(): line for line in tutorial.splitlines() if "| `" in line}
    for name, cls in ACTIONS.items():
        row = rows.get(f"`{cls.__name__}`")
        assert row is not None, f"python-missions.md lacks {cls.__name__}"
        assert f"`{name}`" in row
        for param in cls.params:
            assert f"`{param.kwarg}`" in row, f"{cls.__name__}({param.kwarg}=) is undocumented"


# -------- Mission files run as scripts: main(), the run at exit, visits and a state's name
#
# Python missions run as scripts: ``Mission.main``, the mission a script defines but never
# runs (``python my_mission.py`` runs it at exit), ``visits``, and how a state shows itself.
#
# The run at exit is driven here in-process (a fake ``__main__`` module, ``atexit.register``
# and the command it hands over to recorded) because a child process cannot run under
# mutation testing; one test runs a real script too.


SCRIPT = "/home/ada/robots/square.py"


@pytest.fixture
def registered(monkeypatch: pytest.MonkeyPatch) -> list[tuple[Callable[..., Any], tuple[Any, ...]]]:
    """A script ``square.py`` is being run; what it registers to run at exit is recorded."""
    calls: list[tuple[Callable[..., Any], tuple[Any, ...]]] = []
    monkeypatch.setattr(atexit, "register", lambda func, *args: calls.append((func, args)))
    monkeypatch.setattr(_Script, "missions", [])
    monkeypatch.setattr(_Script, "ran", False)
    main = ModuleType("__main__")
    main.__file__ = SCRIPT
    monkeypatch.setitem(sys.modules, "__main__", main)
    return calls


def _define(name: str, module: str = "__main__", **states: Any) -> type[Mission]:
    """``class NAME(Mission): ...`` as written in a file run as ``module``."""
    cls = type(name, (Mission,), {"__module__": module, "__qualname__": name, **states})
    if module == "__main__":  # the script holds it by its name, as a class statement does
        setattr(sys.modules["__main__"], name, cls)
    return cls


def _leg() -> type[Mission]:
    return _define(
        "Leg",
        go=state(Drive(distance_mm=300), initial=True, on_done="end"),
        end=state(final="success"),
    )


@pytest.fixture
def handed_over(monkeypatch: pytest.MonkeyPatch) -> list[list[str]]:
    """The commands the process would hand itself over to (recorded, not run)."""
    commands: list[list[str]] = []
    monkeypatch.setattr(python_api, "run_command", lambda args: commands.append(list(args)))
    monkeypatch.delattr(sys, "last_value", raising=False)
    monkeypatch.setattr(sys, "argv", [SCRIPT, "--seed", "3"])
    return commands


def test_a_script_that_defines_missions_but_runs_none_runs_the_outer_one_at_exit(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    handed_over: list[list[str]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    leg = _leg()
    _define("Square", one=state(leg, initial=True, on_done="end"), end=state(final=True))
    _define("Imported", module="helpers_of_square", end=state(final=True, initial=True))
    # one run at exit for the script, however many missions it defines
    assert registered == [(_run_at_exit, (SCRIPT,))]
    assert [m.__name__ for m in _Script.missions] == ["Leg", "Square"]
    _run_at_exit(SCRIPT)
    assert handed_over == [["run", SCRIPT, "--seed", "3"]], "with the script's own options"
    assert capsys.readouterr().err == (
        "square.py defines the mission Square: running it (roboscript run square.py)\n"
    )


def test_a_script_that_ran_a_mission_does_not_run_it_again(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    handed_over: list[list[str]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    _define(
        "Square", go=state(Wait(duration_s=1), initial=True, on_done="end"), end=state(final=True)
    )
    # registered with the first mission the script defines
    assert registered == [(_run_at_exit, (SCRIPT,))]
    note_mission_run()
    _run_at_exit(SCRIPT)
    assert handed_over == [] and capsys.readouterr().err == ""


def test_a_script_that_ended_on_an_error_does_not_run_its_mission(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    handed_over: list[list[str]],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    _define("Square", end=state(final=True, initial=True))
    monkeypatch.setattr(sys, "last_value", NameError("name 'Drvie' is not defined"), raising=False)
    _run_at_exit(SCRIPT)
    assert handed_over == [], "the error Python printed is the script's last word"


def test_a_mission_made_by_code_the_script_ran_is_not_run_at_exit(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    handed_over: list[list[str]],
) -> None:
    # exec(code, {"__name__": "__main__"}) makes a class of module __main__ that the script
    # does not hold: roboscript run would not find it in the file either
    namespace: dict[str, Any] = {"__name__": "__main__"}
    exec(  # noqa: S102 - what a script that makes classes with exec does
        "from roboscript import Mission, state\nclass Made(Mission):\n"
        "    end = state(final=True, initial=True)\n",
        namespace,
    )
    assert registered == [(_run_at_exit, (SCRIPT,))]
    _run_at_exit(SCRIPT)
    assert handed_over == []


def test_a_script_without_missions_of_its_own_runs_nothing(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    handed_over: list[list[str]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    _define("Imported", module="helpers_of_square", end=state(final=True, initial=True))
    assert registered == []
    _run_at_exit(SCRIPT)
    assert handed_over == [] and capsys.readouterr().err == ""


def test_python_runs_the_mission_a_file_defines_without_main(tmp_path: Path) -> None:
    square = (MISSIONS / "square.py").read_text(encoding="utf-8")
    script = tmp_path / "square.py"
    script.write_text(square.split('if __name__ == "__main__":')[0], encoding="utf-8")
    assert "main()" not in script.read_text(encoding="utf-8")
    done = subprocess.run(
        [sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "square.py defines the mission Square: running it" in done.stderr
    assert "success: square ended in 'finished'" in done.stdout + done.stderr, done.stderr


def test_no_reminder_in_a_notebook_or_the_repl(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]], monkeypatch: pytest.MonkeyPatch
) -> None:
    # a __main__ without a file: there is no script to name
    monkeypatch.setitem(sys.modules, "__main__", ModuleType("__main__"))
    _define("Square", end=state(final=True, initial=True))
    assert registered == [] and _Script.missions == []


def test_main_runs_the_mission_with_the_options_given_and_exits(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    seen: list[Sequence[str]] = []

    def run_command(args: Sequence[str]) -> NoReturn:
        seen.append(args)
        raise SystemExit(0)

    monkeypatch.setattr(python_api, "run_command", run_command)
    square = _define("Square", module="square", end=state(final=True, initial=True))
    monkeypatch.setattr(python_api, "mission_file", lambda cls: "square.py")
    with pytest.raises(SystemExit) as info:
        square.main(["--robot", "mirto"])
    assert seen == [["run", "square.py", "--robot", "mirto"]]
    assert info.value.code == 0


def test_a_mission_runs_itself_through_the_command_line_in_the_same_process(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # the command line sits above missions: the process becomes `python -m roboscript ...`
    seen: list[tuple[str, list[str], dict[str, str]]] = []

    def execve(path: str, argv: list[str], env: dict[str, str]) -> NoReturn:
        seen.append((path, argv, env))
        raise SystemExit(0)

    monkeypatch.setattr(python_api.os, "name", "posix")
    monkeypatch.setattr(python_api.os, "execve", execve)
    monkeypatch.setenv("PYTHONPATH", "elsewhere")
    with pytest.raises(SystemExit):
        python_api.run_command(["run", "square.py", "--seed", "3"])
    [(path, argv, env)] = seen
    assert path == sys.executable
    assert argv == [sys.executable, "-m", "roboscript", "run", "square.py", "--seed", "3"]
    home = str(Path(python_api.__file__).resolve().parents[2])
    assert env["PYTHONPATH"].split(os.pathsep) == [home, "elsewhere"]


class _Lost(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("lost", "end")])
    end = state(final=True)

    def lost(self) -> bool:
        # a name built at run time: the compiler cannot check it, so visits() refuses it
        return self.visits("now" + "here".strip()) > 0


def test_visits_of_a_state_that_does_not_exist_is_the_students_mistake() -> None:
    spec, _ = compile_mission(_Lost)
    sched = Scheduler(SimClock(), 0.02)
    runner = MissionRunner(spec, {})
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=5)
    line = _Lost.lost.__code__.co_firstlineno + 2
    assert runner.result.outcome == "failure"
    assert runner.result.reason is not None
    assert runner.result.reason.startswith(
        "your condition 'lost' raised KeyError in state 'go': \"there is no state 'nowhere'\" ("
    )
    assert runner.result.reason.endswith(f"test_python_api.py:{line})")


def test_values_outside_a_run_say_so() -> None:
    with pytest.raises(RuntimeError) as info:
        _Lost().visits("go")
    assert str(info.value) == "a mission's values can only be read while the mission runs"


class _OwnInit(Mission):
    end = state(final=True, initial=True)

    def __init__(self) -> None:  # a student's own __init__, forgetting super().__init__()
        self.count = 0


def test_values_outside_a_run_say_so_even_without_super_init() -> None:
    with pytest.raises(RuntimeError) as info:
        _ = _OwnInit().elapsed
    assert str(info.value) == "a mission's values can only be read while the mission runs"


def test_a_state_shows_its_name() -> None:
    assert repr(_Lost.go) == "<state go>"
    assert repr(state(final=True)) == "<state ?>"


class _NoColourYet:
    def rgb(self) -> None:
        return None


class _Context:
    def get(self, name: str) -> Any:
        assert name == COLOR
        return _NoColourYet()


def test_colour_channels_read_zero_before_the_first_reading() -> None:
    assert color_or_buttons(_Context(), "color", "rgb_red") == 0.0  # type: ignore[arg-type]
    with pytest.raises(KeyError) as info:
        color_or_buttons(_Context(), "range", "cm")  # type: ignore[arg-type]
    assert info.value.args == ("range",)


BUILT_WITH_TYPE = """\
from roboscript import Mission, Wait, state

Lost = type(
    "Lost",
    (Mission,),
    {
        "go": state(Wait(duration_s=1), initial=True, on_done="nowhere"),
        "end": state(final=True, description="back home"),
    },
)
"""


def test_a_state_without_a_class_body_is_placed_where_state_was_called(tmp_path: Path) -> None:
    # no `go = state(...)` line to find in the source: the state() call itself is the place
    path = tmp_path / "lost.py"
    path.write_text(BUILT_WITH_TYPE, encoding="utf-8")
    with pytest.raises(MissionError) as info:
        load_mission(path)
    assert [p.format() for p in info.value.problems] == [  # type: ignore[attr-defined]
        f"{path}:7: error: there is no state 'nowhere'"
    ]


def test_a_states_description_is_kept_and_empty_by_default(tmp_path: Path) -> None:
    path = tmp_path / "found.py"
    path.write_text(BUILT_WITH_TYPE.replace('"nowhere"', '"end"'), encoding="utf-8")
    spec, _ = load_mission(path)
    assert [(n, s.description) for n, s in spec.states.items()] == [
        ("go", ""),
        ("end", "back home"),
    ]


class _Line:
    names = ("left", "center", "right")
    dark_threshold = 500.0

    def values(self) -> tuple[float, ...]:
        return (100.0, 900.0, 100.0)


class _OnTheLine(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="lost", when=[("on_line", "found")])
    found = state(final="success")
    lost = state(final="failure")

    def on_line(self) -> bool:
        return self.line.center > 500 and self.line.left < 500


def test_a_guard_method_reads_the_line_sensors() -> None:
    spec, _ = compile_mission(_OnTheLine)
    sched = Scheduler(SimClock(), 0.02)
    runner = MissionRunner(spec, {"line": _Line()})
    sched.add(runner)
    sched.run(until=lambda: runner.finished, max_duration_s=10)
    # success only through the guard: the wait running out leads to failure
    assert runner.result.outcome == "success"


def test_a_condition_returning_a_distance_or_a_list_is_refused_at_load_and_when_run() -> None:
    class Far(Mission):
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("far", "end")])
        end = state(final=True)

        def far(self) -> bool:
            return self.range.distance_cm  # type: ignore[return-value] - the mistake under test

    with pytest.raises(MissionError) as refused:
        compile_mission(Far)
    assert refused.value.message == (
        "condition method 'far' returns self.range.distance_cm, a number, and any number but 0"
        " counts as true"
    )
    assert refused.value.hint == "return a comparison, e.g. return self.range.distance_cm < 20"

    class Listed(Mission):  # what the check cannot see: refused when the run reads it
        go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("near", "end")])
        end = state(final=True)

        def near(self) -> bool:
            return [self.elapsed > 1]  # type: ignore[return-value]

    runner = run(Listed)
    assert runner.result.outcome == "failure"
    assert (runner.result.reason or "").startswith(
        "your condition 'near' returned a list instead of True or False in state 'go'; return a"
        " comparison, e.g. return self.range.distance_cm < 20"
    )
