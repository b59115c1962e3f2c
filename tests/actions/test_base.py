"""What every action shares: an action made without what it needs says what to write.

A beginner's ``Rotate()`` or ``rotate: {}`` is answered with an example to copy, in the
mission's own language, and every example given is one that works.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from helpers import run_cli

import roboscript
from roboscript.actions import ACTIONS, Action, Parallel, Param, Repeat, Result, Wait
from roboscript.actions.base import PARAM_EXAMPLES, UnderSpecifiedError
from roboscript.inputs.quantities import DIMENSIONS, parse_quantity
from roboscript.mission import load_mission

NEEDING = sorted(
    (cls for cls in ACTIONS.values() if any(p.required for p in cls.params)),
    key=lambda cls: cls.name,
)
"""Every built-in action that has a parameter without a default."""


@pytest.mark.parametrize("cls", [*NEEDING, Repeat, Parallel], ids=lambda cls: cls.__name__)
def test_an_action_made_with_nothing_says_what_to_write_and_the_example_works(
    cls: type[Action],
) -> None:
    with pytest.raises(UnderSpecifiedError) as refused:
        cls()  # type: ignore[call-arg]
    error = refused.value
    assert str(error) == f"{error.python_message} (write {error.python})"
    assert error.python.startswith(f"{cls.__name__}(")
    names = {name: getattr(roboscript, name) for name in roboscript.__all__}
    made = eval(error.python, names)
    assert type(made) is cls


@pytest.mark.parametrize("cls", NEEDING, ids=lambda cls: cls.name)
def test_a_yaml_action_without_its_parameters_shows_ones_that_load(
    tmp_path: Path, cls: type[Action]
) -> None:
    state = "mission: m\nstates:\n  go:\n    do: {%s}\n    timeout: 5 s\n"
    state += "    on: {done: end, failed: end, timeout: end}\n  end: {final: success}\n"
    (tmp_path / "empty.yaml").write_text(state % f"{cls.name}: {{}}", encoding="utf-8")
    result = run_cli("check", "empty.yaml", cwd=tmp_path)
    assert result.returncode == 2
    written = []
    for line in result.stderr.splitlines()[:-1]:
        assert line.startswith(f"empty.yaml:4:10: error: '{cls.name}' needs '"), line
        assert line.endswith("`)"), line
        written.append(line.rsplit("(write `", 1)[1].removesuffix("`)"))
    assert len(written) == sum(p.required for p in cls.params)
    (tmp_path / "full.yaml").write_text(
        state % f"{cls.name}: {{{', '.join(written)}}}", encoding="utf-8"
    )
    load_mission(tmp_path / "full.yaml")  # no error: the examples are what it needed


def test_check_shows_what_to_write_for_wait_until_repeat_and_parallel_in_each_language(
    tmp_path: Path,
) -> None:
    (tmp_path / "m.yaml").write_text(
        "mission: m\nstates:\n  wait:\n    do: {wait_until: {condition: bumper.any}}\n"
        "    on: {done: turn, timeout: turn}\n"
        "  turn:\n    do: {repeat: {do: {rotate: {angle: 90 deg}}}}\n"
        "    on: {done: both, failed: both}\n"
        "  both:\n    do: {parallel: [{drive: {distance: 50 cm}}]}\n"
        "    on: {done: end, failed: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    (tmp_path / "m.py").write_text(
        "from roboscript import Mission, Parallel, Repeat, Rotate, WaitUntil, state\n\n\n"
        "class M(Mission):\n"
        '    wait = state(WaitUntil("bumper.any"), initial=True, on_done="end")\n'
        '    turn = state(Repeat(Rotate(angle_deg=90)), on_done="end")\n'
        '    both = state(Parallel(Rotate(angle_deg=90)), on_done="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    for name in ("m.yaml", "m.py"):
        result = run_cli("check", name, cwd=tmp_path)
        assert result.returncode == 2
        assert "Traceback" not in result.stderr
    yaml_lines = run_cli("check", "m.yaml", cwd=tmp_path).stderr.splitlines()
    assert yaml_lines == [
        (
            "m.yaml:4:10: error: 'wait_until' needs 'timeout', the most it waits"
            " (every wait has a bound) (write `timeout: 10 s`)"
        ),
        (
            "m.yaml:7:10: error: repeat needs 'times', how many times"
            " (write `repeat: {times: 4, do: {rotate: {angle: 90 deg}}}`)"
        ),
        (
            "m.yaml:10:10: error: parallel needs 'all' or 'any', with the list of actions to run"
            " together (write `parallel: {all: [{drive: {distance: 50 cm}},"
            " {play_tone: {frequency: 880 Hz}}]}`; with any: it ends when the first one does)"
        ),
        "checked 1 file: 1 with errors",
    ]
    # a Python class body stops at its first mistake, so each is shown one at a time
    python_lines = run_cli("check", "m.py", cwd=tmp_path).stderr.splitlines()
    assert python_lines == [
        (
            "m.py:5:18: error: WaitUntil needs 'timeout_s', the most it waits"
            " (every wait has a bound)"
            ' (write WaitUntil(condition="range.distance_cm < 20", timeout_s=10))'
        ),
        "checked 1 file: 1 with errors",
    ]
    fixed = (tmp_path / "m.py").read_text(encoding="utf-8")
    fixed = fixed.replace('WaitUntil("bumper.any")', 'WaitUntil("bumper.any", timeout_s=5)')
    (tmp_path / "m.py").write_text(fixed, encoding="utf-8")
    assert run_cli("check", "m.py", cwd=tmp_path).stderr.splitlines()[0] == (
        "m.py:6:18: error: repeat needs 'times', how many times to run the action"
        " (write Repeat(Rotate(angle_deg=90), times=4))"
    )
    fixed = fixed.replace("Repeat(Rotate(angle_deg=90))", "Repeat(Rotate(angle_deg=90), times=2)")
    (tmp_path / "m.py").write_text(fixed, encoding="utf-8")
    assert run_cli("check", "m.py", cwd=tmp_path).stderr.splitlines()[0] == (
        "m.py:7:18: error: parallel takes a list of actions, in [ ]"
        " (write Parallel([Rotate(angle_deg=90)]))"  # the student's own action, in [ ]
    )


@pytest.mark.parametrize(
    ("yaml_action", "python_action", "expected"),
    [
        pytest.param(
            "{drive: {speed: 10 cm/s}}",
            "Drive()",
            [
                (
                    "m.yaml:4:10: error: drive needs a distance or a duration"
                    " (write `distance: 50 cm` or `duration: 2 s`)"
                ),
                (
                    "m.py:5:16: error: drive needs a distance or a duration"
                    " (write Drive(distance_mm=500) or Drive(duration_s=2))"
                ),
            ],
            id="drive-without-an-end",
        ),
        pytest.param(
            "{follow_wall: {side: left}}",
            'FollowWall(side="left")',
            [
                (
                    "m.yaml:4:10: error: 'follow_wall' in state 'go' never ends as written (write"
                    " `until: range.distance_cm < 20` or `duration: 10 s`, or give the state"
                    " `timeout: 10 s` or a `when`)"
                ),
                (
                    "m.py:5:16: error: 'follow_wall' in state 'go' never ends as written (write"
                    ' FollowWall(until="range.distance_cm < 20") or FollowWall(duration_s=10),'
                    " or give the state timeout_s=10 or a when=)"
                ),
            ],
            id="follow_wall-that-never-ends",
        ),
    ],
)
def test_check_shows_what_to_write_in_the_missions_own_language(
    tmp_path: Path, yaml_action: str, python_action: str, expected: list[str]
) -> None:
    (tmp_path / "m.yaml").write_text(
        f"mission: m\nstates:\n  go:\n    do: {yaml_action}\n"
        "    on: {done: end, failed: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    (tmp_path / "m.py").write_text(
        "from roboscript import Drive, FollowWall, Mission, state\n\n\nclass M(Mission):\n"
        f'    go = state({python_action}, initial=True, on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", "m.yaml", "m.py", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [*expected, "checked 2 files: 2 with errors"]


class Wiggle(Action):
    """A student's behaviour with a parameter it needs."""

    name = "wiggle"
    params = (Param("times", "times", "count", "how often to wiggle"),)

    def __init__(self, times: int) -> None:
        self.times = times + 0  # a str is refused by Python inside __init__

    def update(self, ctx: Any) -> Result | None:
        return Result.done()


def test_a_students_behaviour_made_without_its_parameter_says_what_to_write() -> None:
    with pytest.raises(UnderSpecifiedError) as refused:
        Wiggle()  # type: ignore[call-arg]
    assert str(refused.value) == (
        "Wiggle needs 'times', how often to wiggle (write Wiggle(times=4))"
    )
    assert (refused.value.message, refused.value.yaml) == (
        "'wiggle' needs 'times', how often to wiggle",
        "`times: 4`",
    )


def test_other_mistakes_in_a_call_keep_pythons_own_message() -> None:
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'time'$"):
        Wiggle(time=3)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"takes 2 positional arguments but 3 were given$"):
        Wiggle(3, 4)  # type: ignore[call-arg]
    with pytest.raises(TypeError, match=r"can only concatenate str|unsupported operand"):
        Wiggle("3")  # type: ignore[arg-type]  # raised inside __init__: not a missing value


QUANTITIES = [
    (cls, param)
    for cls in sorted(ACTIONS.values(), key=lambda cls: cls.name)
    for param in cls.params
    if param.kind in DIMENSIONS and param.kind != "count"
]


@pytest.mark.parametrize(
    ("cls", "param"), QUANTITIES, ids=[f"{cls.name}-{param.name}" for cls, param in QUANTITIES]
)
def test_a_quantity_written_as_text_in_python_is_read_in_its_keywords_unit(
    cls: type[Action], param: Param
) -> None:
    needed = {p.kwarg: eval(p.python_example.split("=", 1)[1]) for p in cls.params if p.required}
    if cls.name == "drive":  # a distance or a duration, neither required alone
        needed["distance_mm"] = 500
    text = param.example or PARAM_EXAMPLES[param.kind]
    as_text = cls(**(needed | {param.kwarg: text}))
    as_number = cls(**(needed | {param.kwarg: parse_quantity(text, param.kind)}))
    assert getattr(as_text, param.kwarg) == getattr(as_number, param.kwarg)
    assert not isinstance(getattr(as_text, param.kwarg), str)


def test_text_an_action_compares_but_cannot_read_is_named_not_pythons_comparison() -> None:
    with pytest.raises(ValueError) as refused:
        Wait(duration_s="2 deg")
    assert str(refused.value) == (
        "wait duration: 'deg' is a unit of angle, but this is a time (use s, sec, ms, min)"
    )


@pytest.mark.parametrize(
    ("given", "expected"),
    [
        ([2], "wait duration: expected a time such as '200 ms', got [2]"),
        (None, "wait duration: expected a time such as '200 ms', got None"),
        ({"s": 2}, "wait duration: expected a time such as '200 ms', got {'s': 2}"),
    ],
)
def test_a_quantity_an_action_compares_but_is_no_number_is_named_not_pythons_comparison(
    given: Any, expected: str
) -> None:
    with pytest.raises(ValueError) as refused:
        Wait(duration_s=given)
    assert str(refused.value) == expected
