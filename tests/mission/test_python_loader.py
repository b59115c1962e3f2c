"""Python mission files: loading by path, errors in the student's terms, and the YAML twins."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli

from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.mission.python_loader import is_python_mission

TWINS = sorted(p for p in MISSIONS.glob("*.py") if p.with_suffix(".yaml").exists())

GOOD = """\
from roboscript import Drive, Mission, state


class Hello(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""


def messages(path: Path) -> list[str]:
    with pytest.raises(MissionError) as info:
        load_mission(path)
    found = getattr(info.value, "problems", [info.value])
    return [p.format().replace(str(path), "M") for p in found]


def test_a_python_mission_file_loads_by_path(write_mission: Callable[..., Path]) -> None:
    spec, warnings = load_mission(write_mission(GOOD, "hello.py"))
    assert spec.name == "hello" and spec.initial == "go" and warnings == []
    assert spec.states["go"].location is not None
    assert (spec.states["go"].location.line, spec.states["go"].location.col) == (5, 5)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            GOOD.replace("initial=True,", "initial=True"),
            "M:5:48: error: invalid syntax. Perhaps you forgot a comma?",
        ),
        (
            GOOD.replace("Drive(distance_mm=300)", "Drvie(distance_mm=300)"),
            "M:5:16: error: NameError: name 'Drvie' is not defined (did you mean 'Drive'?)",
        ),
        (
            GOOD.replace("Drive(distance_mm=300)", "Rotate(angle_deg=90)"),
            (
                "M:5:16: error: NameError: name 'Rotate' is not defined"
                " (add 'from roboscript import Rotate')"
            ),
        ),
        (
            GOOD.replace("Drive, Mission", "Drvie, Mission"),
            "M:1:1: error: roboscript has no 'Drvie' to import (did you mean 'Drive'?)",
        ),
        (
            GOOD.replace("distance_mm=300", "distnce_mm=300"),
            "M:5:16: error: Drive() has no parameter 'distnce_mm' (did you mean 'distance_mm'?)",
        ),
        (
            GOOD.replace("on_done=", "on_dnoe="),
            "M:5:10: error: state() has no parameter 'on_dnoe' (did you mean 'on_done'?)",
        ),
        (
            GOOD.replace("distance_mm=300", "distance_mm=300, speed_mm_s=-5"),
            "M:5:16: error: drive speed must be positive (use a negative distance to reverse)",
        ),
        (
            GOOD + "\nprint(1 / 0)\n",
            "M:8:7: error: ZeroDivisionError: division by zero",
        ),
        (
            (
                "from roboscript import Action, Result\n\n\nclass Spin(Action):\n"
                "    name = 'spin'\n\n    def update(self, ctx):\n        return Result.done()\n"
            ),
            (
                "M:1:1: error: this file holds no mission (it holds behaviours (spin): list the"
                " file under 'behaviours:' in a YAML mission, or import it in a Python one)"
            ),
        ),
        (
            "import math\n",
            (
                "M:1:1: error: this file holds no mission"
                " (write a class that extends Mission: class MyMission(Mission): ...)"
            ),
        ),
        (
            GOOD + GOOD.replace("Hello", "Again").replace("from roboscript", "\nfrom roboscript"),
            (
                "M:11:1: error: this file holds 2 missions (Hello, Again); a mission file holds one"
                " (move each mission to a file of its own)"
            ),
        ),
    ],
)
def test_golden_messages_for_python_mission_files(
    write_mission: Callable[..., Path], text: str, expected: str
) -> None:
    assert messages(write_mission(text, "hello.py")) == [expected]


def test_a_file_may_hold_a_template_and_the_mission_built_on_it(
    write_mission: Callable[..., Path],
) -> None:
    text = GOOD + "\n\nclass Longer(Hello):\n    go = state(Drive(distance_mm=900), initial=True,"
    text += ' on_done="end", on_failed="end")\n'
    spec, _ = load_mission(write_mission(text, "longer.py"))
    assert spec.name == "longer"
    action = spec.states["go"].action
    assert action is not None and action.kwargs["distance_mm"] == 900


def test_a_mission_imports_files_beside_it(tmp_path: Path) -> None:
    (tmp_path / "distances.py").write_text("SIDE_MM = 420\n", encoding="utf-8")
    path = tmp_path / "uses.py"
    path.write_text(
        GOOD.replace("from roboscript", "from distances import SIDE_MM\nfrom roboscript").replace(
            "distance_mm=300", "distance_mm=SIDE_MM"
        ),
        encoding="utf-8",
    )
    spec, _ = load_mission(path)
    action = spec.states["go"].action
    assert action is not None and action.kwargs["distance_mm"] == 420


def test_check_finds_python_missions_in_a_folder_but_not_behaviours(tmp_path: Path) -> None:
    (tmp_path / "hello.py").write_text(GOOD, encoding="utf-8")
    (tmp_path / "helper.py").write_text("SIDE_MM = 1\n", encoding="utf-8")
    (tmp_path / "broken.py").write_text("class X(Mission)\n", encoding="utf-8")
    assert is_python_mission(tmp_path / "hello.py")
    assert not is_python_mission(tmp_path / "helper.py")
    assert is_python_mission(tmp_path / "broken.py")  # so its syntax error is reported
    assert not is_python_mission(MISSIONS / "behaviours" / "zigzag.py")
    result = run_cli("check", str(tmp_path))
    assert result.returncode == 2
    assert result.stderr.splitlines()[-1] == "checked 2 files: 1 with errors"
    assert "broken.py:1:17: error: expected ':'" in result.stderr


def test_check_reports_code_too_deep_to_parse_as_an_error_not_a_traceback(tmp_path: Path) -> None:
    deep = "from roboscript import Mission\nX = " + "+".join(["1"] * 20_000) + "\n"
    (tmp_path / "deep.py").write_text(deep, encoding="utf-8")
    assert is_python_mission(tmp_path / "deep.py")  # so what is wrong is reported
    result = run_cli("check", str(tmp_path))
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert "deep.py: error: RecursionError" in result.stderr


# ------------------------------------------------------------------------------- the twins


def test_there_are_twins() -> None:
    assert {p.stem for p in TWINS} >= {"square", "bump_and_turn"}


# That each twin builds the same spec is tests/mission/test_builder.py's.


@pytest.mark.parametrize("twin", TWINS, ids=lambda p: p.name)
def test_a_python_twin_runs_like_its_yaml(twin: Path) -> None:
    runs = []
    for path in (twin, twin.with_suffix(".yaml")):
        result = run_cli("run", str(path.relative_to(MISSIONS.parent)), "--json", "--seed", "3")
        assert result.returncode == 0, result.stderr
        runs.append(json.loads(result.stdout))
    python_run, yaml_run = runs
    assert python_run["outcome"] == yaml_run["outcome"] == "success"
    assert python_run["states"] == yaml_run["states"]
    # a condition is a method in Python and an expression in YAML: the same values decided
    for run in runs:
        for transition in run["transitions"]:
            cause = transition["cause"]
            del cause["condition"], cause["text"]
    assert python_run == yaml_run


# ------------------------------------------------------------ quantities written as in YAML

WITH_UNITS = """\
from roboscript import Drive, Mission, Rotate, state


class Units(Mission):
    go = state(Drive(distance_mm={distance!r}), initial=True, on_done="turn", on_failed="end")
    turn = state(Rotate(angle_deg={angle!r}), on_done="end", on_failed="end")
    end = state(final="success")
"""


def test_python_arguments_with_units_run_as_yaml_reads_them(tmp_path: Path) -> None:
    units = tmp_path / "units.py"
    units.write_text(WITH_UNITS.format(distance="50 cm", angle="90 deg"), encoding="utf-8")
    numbers = tmp_path / "numbers.py"
    numbers.write_text(WITH_UNITS.format(distance=500, angle=90), encoding="utf-8")
    assert run_cli("check", str(units)).returncode == 0
    runs = []
    for path in (units, numbers):
        result = run_cli("run", str(path), "--json")
        assert result.returncode == 0, result.stderr
        assert "Traceback" not in result.stderr
        runs.append(json.loads(result.stdout)["sim"])
    assert runs[0] == runs[1]  # "50 cm" is 500 mm, "90 deg" is 90 degrees


@pytest.mark.parametrize(
    ("distance", "angle", "problem"),
    [
        ("50 deg", "90 deg", "5:34: error: drive distance: 'deg' is a unit of angle"),
        ("50 cm", "90 cm", "6:35: error: rotate angle: 'cm' is a unit of distance"),
        ("fifty", "90 deg", "5:34: error: drive distance: expected a distance"),
    ],
)
def test_python_arguments_with_a_wrong_unit_are_refused_at_check(
    tmp_path: Path, distance: str, angle: str, problem: str
) -> None:
    mission = tmp_path / "wrong.py"
    mission.write_text(WITH_UNITS.format(distance=distance, angle=angle), encoding="utf-8")
    for command in ("check", "run"):
        result = run_cli(command, str(mission))
        assert result.returncode == 2, result.stderr
        assert f"{mission}:{problem}" in result.stderr
        assert "Traceback" not in result.stderr
