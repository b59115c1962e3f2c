"""Python mission files: loading by path, errors in the student's terms, and the YAML twins."""

from __future__ import annotations

import json
import linecache
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S, MISSIONS, refusal, run_cli
from helpers import refusal as messages

from roboscript import Mission
from roboscript.errors import MissionError
from roboscript.mission import load_mission
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.python_loader import is_python_mission
from roboscript.profiles import get_profile

TWINS = sorted(p for p in MISSIONS.glob("*.py") if p.with_suffix(".yaml").exists())

GOOD = """\
from roboscript import Drive, Mission, state


class Hello(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="end", on_failed="end")
    end = state(final="success")
"""


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


# -------- A file that is not one mission, which files are missions, and where mistakes show
#
# Python mission files: the messages for a file that is not one mission, which files
# ``roboscript check`` takes for missions, and the ``file:line:col`` a mistake is shown at.
#
# One golden above quotes Python's own ``TypeError``, whose wording depends on how the test is
# run; the messages a student reads for a file with no mission, or two, are pinned again here,
# each whole, in words that are roboscript's own. The positions are
# those of mistakes found when the class is checked, after the file was imported (a mistake that
# raises while the file is imported is placed by Python's traceback instead).


# Two behaviours, one named by its `name` and one left to its class name, beside a helper
# class, a constant, and a behaviour imported from roboscript (not the file's own).
BEHAVIOURS_ONLY = """\
from roboscript import Action, Drive, Result

SPEED_MM_S = 120


class Helper:
    pass


class Spin(Action):
    name = "spin"

    def update(self, ctx):
        return Result.done()


class Wiggle(Action):
    def update(self, ctx):
        return Result.done()
"""


def messages_in_folder(path: Path, profile: object = None) -> list[str]:
    """What ``roboscript check`` prints for the file, its folder written as ``T``."""
    return refusal(path, profile, shown={str(path.parent): "T"})


# ------------------------------------------------------------------- not one mission


def test_a_file_of_behaviours_names_them_and_says_where_they_go(tmp_path: Path) -> None:
    path = tmp_path / "moves.py"
    path.write_text(BEHAVIOURS_ONLY, encoding="utf-8")
    assert messages_in_folder(path) == [
        (
            "T/moves.py:1:1: error: this file holds no mission (it holds behaviours (Wiggle, spin):"
            " list the file under 'behaviours:' in a YAML mission, or import it in a Python one)"
        )
    ]


def test_a_file_without_classes_is_told_to_write_a_mission(tmp_path: Path) -> None:
    path = tmp_path / "helper.py"
    path.write_text("import math\n\nSIDE_MM = 300\n\n\nclass Helper:\n    pass\n", encoding="utf-8")
    assert messages_in_folder(path) == [
        (
            "T/helper.py:1:1: error: this file holds no mission"
            " (write a class that extends Mission: class MyMission(Mission): ...)"
        )
    ]


def test_a_file_of_two_missions_points_at_the_second(tmp_path: Path) -> None:
    path = tmp_path / "two.py"
    second = GOOD.replace("Hello", "Again").replace("from roboscript", "\nfrom roboscript")
    path.write_text(GOOD + second, encoding="utf-8")
    assert messages_in_folder(path) == [
        (
            "T/two.py:11:1: error: this file holds 2 missions (Hello, Again); a mission file holds"
            " one (move each mission to a file of its own)"
        )
    ]


def test_three_missions_are_counted_and_the_second_is_pointed_at(tmp_path: Path) -> None:
    path = tmp_path / "three.py"
    text = GOOD + "\n\n" + GOOD.split("\n\n\n")[1].replace("Hello", "Again")
    text += "\n\n" + GOOD.split("\n\n\n")[1].replace("Hello", "Third")
    path.write_text(text, encoding="utf-8")
    assert messages_in_folder(path) == [
        (
            "T/three.py:9:1: error: this file holds 3 missions (Hello, Again, Third); a mission"
            " file holds one (move each mission to a file of its own)"
        )
    ]


def test_a_file_that_exits_while_loaded_is_called_a_mission_file(tmp_path: Path) -> None:
    path = tmp_path / "quits.py"
    path.write_text("import sys\n\nsys.exit(3)\n", encoding="utf-8")
    assert messages_in_folder(path) == [
        "T/quits.py:3:1: error: the mission file called exit() while it was loaded"
    ]


# ------------------------------------------------------------------- one mission, checked


def test_messages_name_the_file_as_the_student_named_it(tmp_path: Path) -> None:
    """Through a link to the folder, not the folder the link resolves to."""
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "link").symlink_to(real)
    (real / "hello.py").write_text(GOOD.replace('on_done="end"', 'on_done="ned"'), encoding="utf-8")
    assert messages_in_folder(tmp_path / "link" / "hello.py") == [
        "T/hello.py:5:62: error: there is no state 'ned' (did you mean 'end'?)"
    ]


def test_a_mission_is_checked_against_the_robot_it_names(tmp_path: Path) -> None:
    path = tmp_path / "wall.py"
    path.write_text(
        GOOD.replace("Drive,", "Drive, FollowWall,").replace(
            "Drive(distance_mm=300)", "FollowWall(side='left', distance_mm=200, duration_s=3)"
        ),
        encoding="utf-8",
    )
    load_mission(path, get_profile("mirto"))  # it has a side sensor
    assert messages_in_folder(path, get_profile("spike-prime")) == [
        (
            "T/wall.py:5:16: error: 'follow_wall' needs side_range (a distance sensor facing"
            " sideways (for wall following)), which spike-prime does not have"
        )
    ]


# ------------------------------------------------------------- which files are missions


@pytest.mark.parametrize(
    ("text", "mission"),
    [
        ("from roboscript import Mission\n\n\nclass Hello(Mission):\n    pass\n", True),
        ("import roboscript\n\n\nclass Hello(roboscript.Mission):\n    pass\n", True),
        ("import roboscript as rs\n\n\nclass Hello(rs.api.Mission):\n    pass\n", True),
        # mentions Mission, but defines no class on it: a helper for missions
        ("from roboscript import Mission\n\nSIDE_MM = 300\n", False),
        (
            "import roboscript\n\n\nclass Step(roboscript.Action):  # not a Mission\n    pass\n",
            False,
        ),
        # a base that is neither a name nor an attribute, beside the Mission
        ("def base():\n    return object\n\n\nclass Odd(base(), Mission):\n    pass\n", True),
        (
            "def base():\n    return object\n\n\nclass Odd(base()):  # Mission\n    pass\n",
            False,
        ),
        ("class Mission:\n    pass\n", False),
        ("SIDE_MM = 300\n", False),
        ("class Broken(Mission)\n", True),  # a mission with a syntax error is reported
    ],
)
def test_a_python_file_is_a_mission_when_a_class_extends_mission(
    tmp_path: Path, text: str, mission: bool
) -> None:
    path = tmp_path / "file.py"
    path.write_text(text, encoding="utf-8")
    assert is_python_mission(path) is mission


def test_files_that_cannot_be_read_are_not_missions(tmp_path: Path) -> None:
    latin1 = tmp_path / "latin1.py"
    latin1.write_bytes(b"# caf\xe9\nclass Hello(Mission):\n    pass\n")
    assert is_python_mission(latin1) is False
    assert is_python_mission(tmp_path / "missing.py") is False
    folder = tmp_path / "folder.py"
    folder.mkdir()
    assert is_python_mission(folder) is False


# ------------------------------------------------- where a mistake in a Python file is shown

WHERE = {
    # a condition method written as a lambda has no `def` line: its line alone is shown
    "lambda": (
        """\
from roboscript import Mission, Wait, state


class Hello(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("blocked", "end")])
    end = state(final="success")
    blocked = lambda self, far: True  # noqa: E731
""",
        "T/lambda.py:7: error: condition method 'blocked' must take only self (def blocked(self):)",
    ),
    # columns on the file's first line count from its start too
    "first_line": (
        """\
def far(self): return self.visits("nope") > 0  # noqa: E704
from roboscript import Mission, Wait, state


class Hello(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("far", "end")])
    end = state(final="success")
    far = far
""",
        "T/first_line.py:1:35: error: visits('nope'): there is no state 'nope'",
    ),
    # a mission made by type() has no class statement to point at: the file is named
    "made_by_type": (
        GOOD
        + """

Again = type(
    "Again",
    (Mission,),
    {"go": state(Drive(distance_mm=3), initial=True, on_done="end"), "end": state(final=True)},
)
""",
        (
            "T/made_by_type.py: error: this file holds 2 missions (Hello, Again); a mission file"
            " holds one (move each mission to a file of its own)"
        ),
    ),
    # a page break (form feed) on a line of its own is no line end to Python: the lines
    # after it keep their numbers, and their columns are counted in their own text
    "page_break": (
        GOOD.replace("\n\n\nclass", "\n\x0c\n\nclass").replace('on_done="end"', 'on_done="ned"'),
        "T/page_break.py:5:62: error: there is no state 'ned' (did you mean 'end'?)",
    ),
    # states written with a type annotation are found as well as plain ones
    "annotated": (
        """\
from typing import Any

from roboscript import Drive, Mission, state


class Hello(Mission):
    go: Any = state(Drive(distance_mm=300), initial=True, on_done="ned")
    end: Any = state(final="success")
""",
        "T/annotated.py:7:67: error: there is no state 'ned' (did you mean 'end'?)",
    ),
    # a class written twice: the second one is the mission, and is the one pointed into,
    # whether it is written on one line or its only state is on its last line
    "rewritten_on_one_line": (
        GOOD
        + "\n\nclass Hello(Mission): go = state(Drive(distance_mm=300), initial=True,"
        + ' final="sucess")\n',
        (
            "T/rewritten_on_one_line.py:9:78: error: state 'go': final is 'success' or 'failure',"
            " got 'sucess' (did you mean 'success'?)"
        ),
    ),
    "rewritten": (
        GOOD
        + '''

class Hello(Mission):
    """Drives, and that is all."""

    go = state(Drive(distance_mm=300), initial=True, final="sucess")
''',
        (
            "T/rewritten.py:12:60: error: state 'go': final is 'success' or 'failure', got 'sucess'"
            " (did you mean 'success'?)"
        ),
    ),
}


@pytest.mark.parametrize("case", list(WHERE))
def test_where_a_mistake_in_a_python_mission_is_shown(tmp_path: Path, case: str) -> None:
    text, expected = WHERE[case]
    path = tmp_path / f"{case}.py"
    path.write_text(text, encoding="utf-8")
    assert messages_in_folder(path) == [expected]


NOTEBOOK_CELL = """\
from roboscript import Mission, Wait, state


class Hello(Mission):
    go = state(Wait(duration_s=5), initial=True, on_done="end", when=[("blocked", "end")])
    end = state(final="success")

    def blocked(self, far):
        return True
"""


def compiled(cls: type[Mission]) -> list[str]:
    with pytest.raises(MissionError) as info:
        compile_mission(cls)
    return [p.format() for p in getattr(info.value, "problems", [info.value])]


def test_a_mission_typed_into_a_notebook_is_shown_by_line_and_column(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Jupyter compiles each cell under a file name that is not on disk, and gives its text
    to ``linecache``; the column of a mistake comes from there."""
    cell = str(tmp_path / "cell-1.py")
    lines = NOTEBOOK_CELL.splitlines(keepends=True)
    monkeypatch.setitem(linecache.cache, cell, (len(NOTEBOOK_CELL), None, lines, cell))
    namespace: dict[str, Any] = {"__name__": "notebook_cell"}
    exec(compile(NOTEBOOK_CELL, cell, "exec"), namespace)  # noqa: S102 - the notebook's run
    assert [m.replace(str(tmp_path), "T") for m in compiled(namespace["Hello"])] == [
        (
            "T/cell-1.py:8:5: error: condition method 'blocked' must take only self"
            " (def blocked(self):)"
        )
    ]


def test_a_mission_run_from_a_string_is_shown_by_line() -> None:
    """Code given to exec() has no text anywhere to take a column from."""
    namespace: dict[str, Any] = {"__name__": "lesson"}
    exec(compile(NOTEBOOK_CELL, "<lesson>", "exec"), namespace)  # noqa: S102 - under test
    assert compiled(namespace["Hello"]) == [
        "<lesson>:8: error: condition method 'blocked' must take only self (def blocked(self):)"
    ]


SHADOWED = (
    GOOD
    + """

if __name__ == "__main__":
    from roboscript import run

    run(Hello)
"""
)


@pytest.mark.parametrize("mission_name", ["hello.py", "roboscript.py"])
def test_a_file_named_like_the_package_is_named_by_check_and_run_before_python_trips_on_it(
    tmp_path: Path, mission_name: str
) -> None:
    mission = tmp_path / mission_name
    mission.write_text(SHADOWED, encoding="utf-8")
    (tmp_path / "roboscript.py").write_text(SHADOWED, encoding="utf-8")  # a copy, or itself
    # what the warning foretells: `python hello.py` finds that file, not the package
    with_python = subprocess.run(
        [sys.executable, str(mission)],
        capture_output=True,
        text=True,
        check=False,
        timeout=HANG_BOUND_S,
    )
    assert with_python.returncode != 0
    assert "ImportError: cannot import name " in with_python.stderr
    assert f"({tmp_path / 'roboscript.py'})" in with_python.stderr
    checked = run_cli("check", str(mission))
    assert checked.returncode == 0  # roboscript itself is not fooled
    warning = checked.stderr.splitlines()[0]
    assert warning.startswith(f"{mission}:1:1: warning: ")
    assert f"`python {mission_name}` would import" in warning
    assert "instead of roboscript and fail" in warning
    assert "(rename " in warning and "for example to my_" in warning
    strict = run_cli("check", "--strict", str(mission))
    assert strict.returncode == 2
    assert strict.stderr.startswith(f"{mission}:1:1: error: ")
    ran = run_cli("run", str(mission), "--quiet")
    assert ran.returncode == 0, ran.stderr
    assert ran.stderr.splitlines()[0] == warning


def test_a_mission_with_no_file_named_like_the_package_beside_it_gets_no_such_warning(
    tmp_path: Path,
) -> None:
    mission = tmp_path / "hello.py"
    mission.write_text(SHADOWED, encoding="utf-8")
    checked = run_cli("check", str(mission))
    assert checked.returncode == 0
    assert "roboscript.py" not in checked.stderr
