"""Python missions run as scripts: ``Mission.main``, the reminder printed when a script
defines a mission but never runs it, ``visits``, and how a state shows itself (issue 16).

The reminder is what ``python my_mission.py`` prints at exit; it is driven here in-process
(a fake ``__main__`` module, ``atexit.register`` recorded) because a child process cannot run
under mutation testing.
"""

from __future__ import annotations

import atexit
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any, NoReturn

import pytest

from roboscript import Drive, Mission, Wait, state
from roboscript.capabilities import COLOR
from roboscript.clock import SimClock
from roboscript.errors import MissionError
from roboscript.mission import load_mission, python_api
from roboscript.mission.python_api import _remind, _Script, note_mission_run
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.runner import MissionRunner
from roboscript.mission.sensor_readings import color_or_buttons
from roboscript.scheduler import Scheduler

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
    return type(name, (Mission,), {"__module__": module, "__qualname__": name, **states})


def _leg() -> type[Mission]:
    return _define(
        "Leg",
        go=state(Drive(distance_mm=300), initial=True, on_done="end"),
        end=state(final="success"),
    )


REMINDER = (
    "square.py defines the mission Square but does not run it. To run it, end the file with\n"
    '    if __name__ == "__main__":\n'
    "        Square.main()\n"
    "or run: roboscript run square.py\n"
)


def test_a_script_that_defines_missions_but_runs_none_is_reminded_of_the_outer_one(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    leg = _leg()
    _define("Square", one=state(leg, initial=True, on_done="end"), end=state(final=True))
    _define("Imported", module="helpers_of_square", end=state(final=True, initial=True))
    # one reminder for the script, however many missions it defines
    assert registered == [(_remind, (SCRIPT,))]
    assert [m.__name__ for m in _Script.missions] == ["Leg", "Square"]
    _remind(SCRIPT)
    assert capsys.readouterr().err == REMINDER


def test_a_script_that_ran_a_mission_is_not_reminded(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    _define(
        "Square", go=state(Wait(duration_s=1), initial=True, on_done="end"), end=state(final=True)
    )
    # registered with the first mission the script defines
    assert registered == [(_remind, (SCRIPT,))]
    note_mission_run()
    _remind(SCRIPT)
    assert capsys.readouterr().err == ""


def test_a_script_without_missions_of_its_own_is_not_reminded(
    registered: list[tuple[Callable[..., Any], tuple[Any, ...]]],
    capsys: pytest.CaptureFixture[str],
) -> None:
    _define("Imported", module="helpers_of_square", end=state(final=True, initial=True))
    assert registered == []
    _remind(SCRIPT)
    assert capsys.readouterr().err == ""


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
    assert runner.result.reason.endswith(f"test_python_api_mutants.py:{line})")


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
