"""Errors in a student's own code, told in the student's terms (issue 16).

Each test imports a small student file the way ``roboscript run``/``check`` does and pins the
whole ``file:line:col: error: message (hint)`` the student reads. The student files call only
functions and classes they define themselves, or roboscript classes, never ``state()``: under
mutation testing ``state`` is wrapped, and Python's own ``TypeError`` would name the wrapper.
"""

from __future__ import annotations

import dataclasses
import hashlib
import logging
import os
import sys
import textwrap
from pathlib import Path

import pytest
from helpers import run_cli

from roboscript.actions.base import Action, Result
from roboscript.errors import MissionError
from roboscript.inputs.quantities import CURLY_QUOTES, DASHES
from roboscript.mission import error_column
from roboscript.mission.python_api import Mission, state
from roboscript.mission.student_code import (
    StudentCodeError,
    import_student_file,
    is_student_class,
    loop_around,
    stuck_at,
    student_fault,
)
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.profiles import BUILTIN_PROFILES
from roboscript.watchdog import CodePlace


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def _message(path: str | Path, *, kind: str | None = None) -> str:
    with pytest.raises(MissionError) as info:
        if kind is None:
            import_student_file(path)
        else:
            import_student_file(path, kind=kind)
    return info.value.format()


# ------------------------------------------------------------------ load time: golden messages

# (file text, the message for m.py); each mistake a student makes while the file is imported.
LOAD_TIME = [
    pytest.param(
        """\
        def square(side_mm):
            return side_mm


        square(sid_mm=3)
        """,
        "m.py:5:1: error: square() has no parameter 'sid_mm' (did you mean 'side_mm'?)",
        id="unknown-keyword-to-own-function",
    ),
    pytest.param(
        """\
        class Box:
            def __init__(self, size):
                self.size = size


        Box(sze=1)
        """,
        "m.py:6:1: error: Box() has no parameter 'sze' (did you mean 'size'?)",
        id="unknown-keyword-to-own-class",
    ),
    pytest.param(
        """\
        import roboscript

        roboscript.Drive(distnce_mm=300)
        """,
        "m.py:3:1: error: Drive() has no parameter 'distnce_mm' (did you mean 'distance_mm'?)",
        id="unknown-keyword-to-roboscript-class-not-imported-by-name",
    ),
    pytest.param(
        # a lowercase callee is only looked up in the file itself: the student's own method
        # `run` must not borrow roboscript.run's parameters for its hint
        """\
        class Robot:
            def run(self, speed):
                return speed


        Robot().run(mision=1)
        """,
        "m.py:6:1: error: run() has no parameter 'mision'",
        id="unknown-keyword-to-own-method-named-like-roboscript-run",
    ),
    pytest.param(
        # `state` not defined in the file is roboscript's state() (as roboscript.state); a
        # method of that name stands in for it, because under mutation testing state() is
        # wrapped and Python's own message would name the wrapper
        """\
        class Robot:
            def state(self, name):
                return name


        Robot().state(on_dnoe="end")
        """,
        "m.py:6:1: error: state() has no parameter 'on_dnoe' (did you mean 'on_done'?)",
        id="unknown-keyword-to-state",
    ),
    pytest.param(
        """\
        def square(side_mm):
            return side_mm


        square()
        """,
        "m.py:5:1: error: square() missing 1 required positional argument: 'side_mm'",
        id="missing-argument-to-own-function",
    ),
    pytest.param(
        """\
        class Box:
            def __init__(self, size):
                self.size = size


        Box()
        """,
        "m.py:6:1: error: Box() missing 1 required positional argument: 'size'",
        id="missing-argument-to-own-class",
    ),
    pytest.param(
        """\
        class Robot:
            def turn(self, angle):
                return angle


        Robot().turn()
        """,
        "m.py:6:1: error: turn() missing 1 required positional argument: 'angle'",
        id="missing-argument-to-own-method",
    ),
    pytest.param(
        """\
        def square(side_mm):
            return side_mm


        sqaure(3)
        """,
        "m.py:5:1: error: NameError: name 'sqaure' is not defined (did you mean 'square'?)",
        id="typo-of-own-name",
    ),
    pytest.param(
        "prnit('hello')\n",
        ("m.py:1:1: error: NameError: name 'prnit' is not defined (did you mean 'print'?)"),
        id="typo-of-builtin",
    ),
    pytest.param(
        "Rotate(angle_deg=90)\n",
        (
            "m.py:1:1: error: NameError: name 'Rotate' is not defined"
            " (add 'from roboscript import Rotate')"
        ),
        id="roboscript-name-not-imported",
    ),
    pytest.param(
        "Drvie(distance_mm=300)\n",
        "m.py:1:1: error: NameError: name 'Drvie' is not defined (did you mean 'Drive'?)",
        id="typo-of-roboscript-name",
    ),
    pytest.param(
        """\
        COUNT = 0


        def bump():
            COUNT += 1


        bump()
        """,
        (
            "m.py:5:5: error: UnboundLocalError: cannot access local variable 'COUNT'"
            " where it is not associated with a value"
        ),
        id="unbound-local-is-not-a-typo",
    ),
    pytest.param(
        "from roboscript import Drvie\n",
        "m.py:1:1: error: roboscript has no 'Drvie' to import (did you mean 'Drive'?)",
        id="roboscript-has-no-such-name",
    ),
    pytest.param(
        "from roboscript import Drive\n\nDrive(distance_mm=300, speed_mm_s=-5)\n",
        "m.py:3:1: error: drive speed must be positive (use a negative distance to reverse)",
        id="roboscript-own-sentence",
    ),
    pytest.param(
        # the student's own ValueError is theirs: named, not passed off as roboscript's sentence
        "raise ValueError('too far')\n",
        "m.py:1:1: error: ValueError: too far",
        id="student-value-error",
    ),
    pytest.param(
        "raise RuntimeError\n",
        "m.py:1:1: error: RuntimeError",
        id="exception-without-text",
    ),
    pytest.param(
        "import sys\n\nsys.exit(3)\n",
        "m.py:3:1: error: the mission file called exit() while it was loaded",
        id="exit",
    ),
    pytest.param(
        # a class of the student's own beyond Exception is still the student's error
        "class Gone(BaseException):\n    pass\n\nraise Gone('at load')\n",
        "m.py:4:1: error: Gone: at load",
        id="own-base-exception",
    ),
    pytest.param(
        "class Turn(Mission)\n    pass\n",
        "m.py:1:20: error: expected ':' (a line starting with class, def, if, elif, else, for"
        " or while ends with ':')",
        id="syntax-expected",
    ),
    pytest.param(
        "x = 1\n    y = 2\n",
        "m.py:2:5: error: unexpected indent (this line is indented further than the line above"
        " it: line it up with its block)",
        id="syntax-unexpected",
    ),
    pytest.param(
        "x = = 1\n",
        "m.py:1:5: error: invalid syntax",
        id="syntax-invalid",
    ),
    pytest.param(
        "x = 'open\n",
        "m.py:1:5: error: syntax error: unterminated string literal (detected at line 1)",
        id="syntax-other",
    ),
    pytest.param(
        """\
        from roboscript import Drive, Mission, state


        class Out(Mission):
            go = state(Drive(distance_mm=500), initial=True, on_done=turn)
            turn = state(final="success")
        """,
        "m.py:5:62: error: NameError: name 'turn' is not defined"
        " (a state is named in quotes: write 'turn')",
        id="state-named-without-quotes",
    ),
    pytest.param(
        """\
        from roboscript import Drive, Mission, state


        class Out(Mission):
            go = state(Drive(distance_mm=500), initial=True, when=[(near, "end")])
            end = state(final="success")

            def near(self):
                return True
        """,
        "m.py:5:61: error: NameError: name 'near' is not defined"
        " (a condition is named in quotes: write 'near')",
        id="condition-named-without-quotes",
    ),
    pytest.param(
        "from wiggle import Wiggle\n",
        "m.py:1:1: error: ModuleNotFoundError: No module named 'wiggle' (if 'wiggle' is a file"
        " of yours, it must sit in the same folder as m.py: wiggle.py, or a folder wiggle/"
        " holding __init__.py)",
        id="own-module-not-beside-the-mission",
    ),
    pytest.param(
        "import wiggle.moves\n",
        "m.py:1:1: error: ModuleNotFoundError: No module named 'wiggle'"
        " (if 'wiggle' is a file of yours, it must sit in the same folder as m.py: wiggle.py,"
        " or a folder wiggle/ holding __init__.py)",
        id="package-not-beside-the-mission",
    ),
    pytest.param(
        "from roboscript import mission\n\n\nclass Go(mission):\n    pass\n",
        "m.py:4:1: error: 'mission' is a module of roboscript, not a class to extend (extend"
        " Mission, with a capital M: from roboscript import Mission, then class Go(Mission):)",
        id="lowercase-mission-as-the-base-class",
    ),
    pytest.param(
        "from roboscript import Mission\n\n\nclass Go(Mission):\n    pass\n\n\nGo().run()\n",
        "m.py:8:1: error: a mission has no run(): take this line away (roboscript run and"
        " python both run the mission a file defines; to say so in the file, write Go.main()"
        ' under if __name__ == "__main__":)',
        id="a-mission-run-by-its-own-file",
    ),
    pytest.param(
        "from roboscript import Behaviour\n",
        "m.py:1:1: error: roboscript has no 'Behaviour' to import (a behaviour of your own is a"
        " class that extends Action: write from roboscript import Action)",
        id="a-behaviour-imported-by-the-tutorials-word",
    ),
    pytest.param(
        "angle_deg = math.degrees(1.57)\n",
        "m.py:1:13: error: NameError: name 'math' is not defined (add 'import math' at the top"
        " of the file)",
        id="a-standard-module-used-without-import",
    ),
    pytest.param(
        "def near(self):\nreturn True\n",
        "m.py:2:1: error: expected an indented block after function definition on line 1"
        " (indent the lines that belong to it 4 spaces further than the line ending in ':')",
        id="a-def-without-its-indented-body",
    ),
    pytest.param(
        'DISTANCE = int(input("how far? "))\n',
        "m.py:1:16: error: the mission file asks for input() while it is loaded, and a mission"
        " runs with no one at the keyboard (write the value in the file instead, e.g."
        " distance_mm = 300)",
        id="input-while-loading",
    ),
    pytest.param(
        "from roboscript import Drive\n\nGO = Drive(distance_mm=50 cm)\n",
        "m.py:3:24: error: invalid syntax. Perhaps you forgot a comma? (a number in Python has"
        " no unit: for 50 cm write 500, as distance_mm is in mm)",
        id="a-number-with-its-unit-in-python",
    ),
    pytest.param(
        "def near(self):\n    return self.range.distance_cm < 20 cm\n",
        "m.py:2:40: error: invalid syntax (a number in Python has no unit: for 20 cm write 20,"
        " as distance_cm is in cm)",
        id="a-comparison-with-a-unit-in-python",
    ),
    pytest.param(
        "def far(n):\n    return far(n + 1)\n\n\nDISTANCE = far(1)\n",
        "m.py:2:12: error: 'far' calls itself again and again, more deeply than Python allows"
        " (give it a way to return a value without calling itself)",
        id="a-function-calling-itself-without-end",
    ),
    pytest.param(
        "def near(self):\n        return 1\n    return 2\n",
        "m.py:3:5: error: syntax error: unindent does not match any outer indentation level"
        " (line it up, with spaces, with the lines of the block it belongs to)",
        id="an-unindent-to-no-block",
    ),
]


@pytest.mark.parametrize(
    ("value", "hint"),
    [
        pytest.param(
            "duration_s=1:30",
            "a time is one number in its keyword's unit: for 1 min 30 s, write duration_s=90",
            id="minutes-and-seconds",
        ),
        pytest.param(
            "duration_s=1:00:00",
            "a time is one number in its keyword's unit: for 1 h, write duration_s=3600",
            id="hours-minutes-and-seconds",
        ),
        pytest.param(
            "duration_s=0:00",
            "a time is one number in its keyword's unit: write duration_s=0",
            id="no-time",
        ),
        pytest.param("distance_mm=010", "write 10, without the leading 0", id="leading-zero"),
        pytest.param("distance_mm=0_10", "write 10, without the leading 0", id="an-underscore"),
        pytest.param("distance_mm=-007", "write 7, without the leading 0", id="after-a-minus"),
    ],
)
def test_a_number_python_refuses_as_typed_is_read_by_the_rules_of_a_yaml_value(
    here: Path, value: str, hint: str
) -> None:
    # a clock's time and leading zeros are read as a YAML value's are (1:00:00 was read as
    # its first minutes and seconds, 60; a 0 before an _ was not seen)
    path = _write(here, "m.py", f"from roboscript import Drive, Wait\n\nGO = Wait({value})\n")
    with pytest.raises(MissionError) as info:
        import_student_file(path)
    assert info.value.hint == hint


@pytest.mark.parametrize(("text", "expected"), LOAD_TIME)
def test_a_mistake_at_load_time_is_told_at_the_students_line(
    here: Path, text: str, expected: str
) -> None:
    assert _message(_write(here, "m.py", text).name) == expected


@pytest.mark.parametrize(("text", "expected"), LOAD_TIME)
def test_a_mistake_is_told_at_the_same_column_on_a_python_that_keeps_none(
    here: Path, text: str, expected: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Python 3.10 keeps no column in a traceback: the column is found in the line itself
    monkeypatch.setattr(error_column, "python_column", lambda frame: None)
    assert _message(_write(here, "m.py", text).name) == expected


@pytest.mark.parametrize(
    ("go", "expected"),
    [
        ('state(Drive(distance_mm=500, speed_mm_s=-5), initial=True, on_done="end")', "5:16"),
        ('state(Drive(distnce_mm=500), initial=True, on_done="end")', "5:16"),
        ('state(Drive(distance_mm=500), "end")', "5:10"),
        ('state(Parallel(Drive(distance_mm=500), Rotate(angle_deg=90)), on_done="end")', "5:16"),
        ('state(Repeat(Rotate(angle_deg=90), times=0), initial=True, on_done="end")', "5:16"),
        ("state(Wait(duration_s=1), initial=True, on_done=self.end)", "5:58"),
        ('state(Drvie(distance_mm=500), initial=True, on_done="end")', "5:16"),
    ],
)
def test_a_mistake_in_a_state_call_is_told_at_its_column_on_a_python_that_keeps_none(
    here: Path, go: str, expected: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(error_column, "python_column", lambda frame: None)
    _write(here, "m.py", PYTHON_MISSION.format(go=go))
    assert _message("m.py").startswith(f"m.py:{expected}: error: ")


def test_a_behaviour_file_that_exits_is_called_a_behaviour_file(here: Path) -> None:
    _write(here, "b.py", "exit()\n")
    assert _message("b.py", kind="behaviour") == (
        "b.py:1:1: error: the behaviour file called exit() while it was loaded"
    )


def test_the_file_is_named_as_the_student_named_it(here: Path) -> None:
    # given by its full path, the file keeps that name in the message, even though Python
    # reports the mistake in the resolved file (which shown_path would shorten)
    path = _write(here, "m.py", "x = = 1\n")
    assert _message(path) == f"{path}:1:5: error: invalid syntax"


def test_a_mistake_in_a_file_beside_it_names_that_file(here: Path) -> None:
    _write(here, "sizes.py", "SIDE_MM = 1 / 0\n")
    _write(here, "m.py", "from sizes import SIDE_MM\n")
    assert _message(here / "m.py") == ("sizes.py:1:11: error: ZeroDivisionError: division by zero")


def test_a_class_imported_under_another_name_gets_no_borrowed_hint(here: Path) -> None:
    # the file holds the class as `Sq`: named as the student wrote it, with its own parameters
    # (roboscript has no `Square` to borrow any from)
    _write(here, "shapes.py", "class Square:\n    def __init__(self, side_mm):\n        pass\n")
    _write(here, "m.py", "from shapes import Square as Sq\n\nSq(sid_mm=1)\n")
    assert _message("m.py") == (
        "m.py:3:1: error: Sq() has no parameter 'sid_mm' (did you mean 'side_mm'?)"
    )


def test_a_syntax_error_in_a_file_beside_it_names_that_file(here: Path) -> None:
    _write(here, "shapes.py", "x = = 1\n")
    _write(here, "m.py", "import shapes\n")
    assert _message(here / "m.py") == "shapes.py:1:5: error: invalid syntax"


def test_a_name_missing_from_another_module_is_pythons_message(here: Path) -> None:
    sizes = _write(here, "sizes.py", "SIDE_MM = 1\n")
    _write(here, "m.py", "from sizes import SIDE\n")
    assert _message("m.py") == (
        f"m.py:1:1: error: ImportError: cannot import name 'SIDE' from 'sizes' ({sizes})"
    )


def test_a_file_that_cannot_be_read(here: Path) -> None:
    assert _message("nowhere.py") == (
        "nowhere.py: error: cannot read the file: No such file or directory"
    )


def test_a_file_that_is_not_python(here: Path) -> None:
    _write(here, "m.txt", "x = 1\n")
    assert _message("m.txt") == "m.txt: error: a mission file is a Python file ending in .py"
    assert _message("m.txt", kind="behaviour") == (
        "m.txt: error: a behaviour file is a Python file ending in .py"
    )


# ------------------------------------------------------------------------- load time: imports


def test_the_files_folder_comes_first_on_the_path_and_only_while_importing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a module of the same name earlier on sys.path must not shadow the student's own file
    decoy = tmp_path / "decoy"
    decoy.mkdir()
    _write(decoy, "issue16_sizes.py", "SIDE_MM = 1\n")
    student = tmp_path / "student"
    student.mkdir()
    _write(student, "issue16_sizes.py", "SIDE_MM = 420\n")
    path = _write(student, "m.py", "from issue16_sizes import SIDE_MM\n")
    monkeypatch.setattr(sys, "path", [str(decoy), *sys.path])
    monkeypatch.delitem(sys.modules, "issue16_sizes", raising=False)
    try:
        assert import_student_file(path).SIDE_MM == 420
    finally:
        sys.modules.pop("issue16_sizes", None)
    assert str(student) not in sys.path


def test_a_module_gets_a_name_of_its_own_per_file(tmp_path: Path) -> None:
    # two files with the same stem in two folders are two modules; dashes make a valid name
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first = _write(tmp_path / "a", "my-x.py", "N = 1\n")
    second = _write(tmp_path / "b", "my-x.py", "N = 2\n")
    one, two = import_student_file(first), import_student_file(second)
    assert (one.N, two.N) == (1, 2)
    for module, path in ((one, first), (two, second)):
        digest = hashlib.sha1(str(path.resolve()).encode("utf-8")).hexdigest()[:10]
        assert module.__name__ == f"_roboscript_mission_my_x_{digest}"
        assert sys.modules[module.__name__] is module


def test_files_of_the_same_size_and_time_are_still_different_files(tmp_path: Path) -> None:
    first = _write(tmp_path, "one.py", "N = 1\n")
    second = _write(tmp_path, "two.py", "N = 2\n")
    stamp = first.stat().st_mtime_ns
    os.utime(second, ns=(stamp, stamp))
    assert (import_student_file(first).N, import_student_file(second).N) == (1, 2)


def test_a_file_is_imported_once_per_version(tmp_path: Path) -> None:
    path = _write(tmp_path, "m.py", "class Spin:\n    pass\n")
    assert import_student_file(path).Spin is import_student_file(path).Spin


# ----------------------------------------------------------------------------- where it is stuck

STUCK = """\
import copy
import sys

from roboscript.mission.student_code import stuck_at

SEEN = []


class Probe:
    def __deepcopy__(self, memo):
        SEEN.append(stuck_at(sys._getframe(1)))
        return self


def through_the_library():
    copy.deepcopy(Probe())


def through_eval():
    SEEN.append(eval("stuck_at(sys._getframe())"))


through_the_library()
through_eval()
"""


def test_stuck_at_names_the_innermost_student_frame(here: Path) -> None:
    # asked from inside copy.deepcopy (the library), the student's line that called it counts;
    # code run by eval() is in no file, so the line that called eval() counts
    seen = import_student_file(_write(here, "stuck.py", STUCK)).SEEN
    assert seen == [
        CodePlace("stuck.py", 16, "through_the_library"),
        CodePlace("stuck.py", 20, "through_eval"),
    ]
    assert str(seen[0]) == "stuck.py:16 in through_the_library"


def test_stuck_at_nowhere_is_none() -> None:
    assert stuck_at(None) is None


LOOPS = """\
import itertools

while True:
    x = 1

def near(self):
    for side in range(4):
        while True:
            if side:
                pass
    return True

def ahead(self):
    while True:
        for step in range(3):
            step += 1

def count(self):
    for n in itertools.count():
        n += 1

def outer():
    while True:
        def inner():
            y = 2
            return y
        inner()

def straight():
    z = 3
    return z
"""


@pytest.mark.parametrize(
    ("line", "loop"),
    [
        pytest.param(3, 3, id="a-loop-at-the-top-of-the-file-on-its-own-first-line"),
        pytest.param(4, 3, id="a-loop-at-the-top-of-the-file"),
        pytest.param(9, 8, id="a-while-inside-a-for-that-ends"),
        pytest.param(10, 8, id="the-whiles-inner-line"),
        pytest.param(7, 7, id="the-for-around-a-while-on-its-own-line"),
        pytest.param(16, 14, id="a-short-for-inside-a-while-true"),
        pytest.param(15, 14, id="the-for-line-inside-the-while"),
        pytest.param(20, 19, id="a-for-with-no-while-around-it"),
        pytest.param(25, None, id="a-function-written-inside-a-loop-is-not-in-it"),
        pytest.param(27, 23, id="the-call-in-the-loop"),
        pytest.param(31, None, id="no-loop"),
    ],
)
def test_a_stopped_line_is_named_by_the_loop_it_runs_in(here: Path, line: int, loop: int) -> None:
    # Caught at any moment, an endless loop is on any of its lines: its first line is the one
    # that is the same every time (the line-by-line stop of the browser and Windows included).
    path = _write(here, "loops.py", LOOPS)
    assert loop_around(str(path), line) == loop


def test_a_file_that_cannot_be_read_names_no_loop(here: Path) -> None:
    assert loop_around(str(here / "gone.py"), 3) is None
    assert loop_around(str(_write(here, "bad.py", "while True:\n    x = (\n")), 2) is None


# A student who changes a built-in robot in their file would run the mission's side with the
# change and the simulated board (made from the robot's name alone) without it.
BUILT_IN_CHANGED = [
    pytest.param(
        """\
        from roboscript.profiles import get_profile

        mirto = get_profile("mirto")
        mirto.max_speed_mm_s = 600
        """,
        "m.py:4:1: error: a built-in robot profile cannot be changed (max_speed_mm_s): the"
        " simulated robot is made from the built-in robot as it is (a robot of your own is a"
        " profile file beside the mission, e.g. my_mirto.yaml holding 'extends: mirto' and"
        " 'max_speed_mm_s: ...'; then write robot = \"my_mirto.yaml\")",
        id="a-field-set",
    ),
    pytest.param(
        """\
        from roboscript.profiles import get_profile

        robot = get_profile("asip-basic")

        robot.gains["wheel_speed"] = (1.0, 0.0, 0.0)
        """,
        "m.py:5: error: this file changes the built-in robot 'asip-basic' (gains), and a"
        " built-in robot stays as it is built: the simulated robot would not have the change"
        " (a robot of your own is a profile file beside the mission, e.g. my_asip-basic.yaml"
        " holding 'extends: asip-basic' and 'gains: ...'; then write robot ="
        ' "my_asip-basic.yaml")',
        id="its-gains-changed-in-place",
    ),
    pytest.param(
        """\
        from roboscript.profiles import BUILTIN_PROFILES

        object.__setattr__(BUILTIN_PROFILES["mirto"], "firmware_pid", False)
        """,
        "m.py:3: error: this file changes the built-in robot 'mirto' (firmware_pid), and a"
        " built-in robot stays as it is built: the simulated robot would not have the change"
        " ('firmware_pid' is the board's own, which no profile file changes: keep 'mirto' as"
        " it is)",
        id="a-field-forced",
    ),
]


@pytest.mark.parametrize(("text", "expected"), BUILT_IN_CHANGED)
def test_a_file_that_changes_a_built_in_robot_is_refused_and_the_robot_kept_as_built(
    here: Path, text: str, expected: str
) -> None:
    # compared as values: a set put back holds the same names, maybe in another order
    before = {name: dataclasses.asdict(profile) for name, profile in BUILTIN_PROFILES.items()}
    assert _message(_write(here, "m.py", text).name) == expected
    assert {name: dataclasses.asdict(p) for name, p in BUILTIN_PROFILES.items()} == before


# ---------------------------------------------------------------------------------- run time


def test_the_sentence_for_a_student_code_error() -> None:
    assert str(StudentCodeError("condition 'close'", problem="returned None", where="m.py:3")) == (
        "your condition 'close' returned None (m.py:3)"
    )
    # the student's file and line, when known, beat the traceback's
    assert str(StudentCodeError("behaviour 'spin'", ValueError("bad"), where="spin.py:3")) == (
        "your behaviour 'spin' raised ValueError: bad (spin.py:3)"
    )
    # an exception never raised has no traceback, so no place
    assert str(StudentCodeError("behaviour 'spin'", ValueError("bad"))) == (
        "your behaviour 'spin' raised ValueError: bad"
    )
    # what it did instead is the sentence; the exception it came with is not repeated
    error = StudentCodeError("condition 'close'", TypeError("x"), problem="returned 'yes'")
    assert error.reason("go") == "your condition 'close' returned 'yes' in state 'go'"


SPIN = """\
from roboscript import Action


class Spin(Action):
    def update(self, ctx):
        return 1 / 0
"""


def test_a_behaviour_that_raises_is_named_with_its_state_and_line(
    here: Path, caplog: pytest.LogCaptureFixture
) -> None:
    spin_class = import_student_file(_write(here, "spin.py", SPIN), kind="behaviour").Spin
    with pytest.raises(ZeroDivisionError) as info:
        spin_class().update(None)
    expected = "your behaviour 'Spin' raised ZeroDivisionError in state 'go': division by zero"
    expected += " (spin.py:6)"
    with caplog.at_level(logging.DEBUG, logger="roboscript.mission.student_code"):
        assert student_fault(info.value, "go") == expected
    # the traceback goes to the debug log, under the same sentence
    (record,) = caplog.records
    assert record.getMessage() == expected
    assert record.exc_info is not None and record.exc_info[1] is info.value


ENDLESS = """\
from roboscript import Action


def ping(n):
    return pong(n)


def pong(n):
    return ping(n)


class Spin(Action):
    def update(self, ctx):
        return self.update(ctx)


class Twirl(Action):
    def update(self, ctx):
        return ping(ctx)
"""


def test_a_behaviour_that_calls_itself_without_end_is_told_at_the_call_that_repeats(
    here: Path,
) -> None:
    module = import_student_file(_write(here, "spin.py", ENDLESS), kind="behaviour")
    with pytest.raises(RecursionError) as info:
        module.Spin().update(None)
    assert student_fault(info.value, "go") == (
        "your behaviour 'Spin' never returned in state 'go': 'update' calls itself again and"
        " again, more deeply than Python allows; give it a way to return a value without"
        " calling itself (spin.py:14)"
    )
    with pytest.raises(RecursionError) as info:
        module.Twirl().update(None)
    assert student_fault(info.value, "go") == (
        "your behaviour 'Twirl' never returned in state 'go': 'ping' and 'pong' call each"
        " other again and again, more deeply than Python allows; give one of them a way to"
        " return a value without calling the other (spin.py:5)"
    )


def test_a_condition_that_calls_itself_without_end_ends_the_run_with_one_sentence(
    tmp_path: Path,
) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Drive, Mission, state\n\n\n"
        "class M(Mission):\n"
        '    go = state(Drive(distance_mm=300), initial=True, on_done="end", on_failed="end",\n'
        '               when=[("close", "end")])\n'
        '    end = state(final="success")\n\n'
        "    def close(self) -> bool:\n"
        "        return self.close()\n",
        encoding="utf-8",
    )
    result = run_cli("run", "m.py", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stdout + result.stderr
    assert (
        "failure: your condition 'close' never returned in state 'go': 'close' calls itself"
        " again and again, more deeply than Python allows; give it a way to return a value"
        " without calling itself (m.py:10)"
    ) in result.stdout + result.stderr


class _Broken(Action):
    name = "broken"

    def update(self, ctx: object) -> Result | None:
        raise AssertionError("not run")


def test_only_student_classes_are_blamed() -> None:
    assert is_student_class(_Broken)
    assert not is_student_class(Action)
    assert not is_student_class(type("Shim", (), {"__module__": "roboscript"}))
    assert student_fault(ValueError("no action ran"), "go") is None


def test_two_actions_given_to_one_state_say_how_to_write_them(tmp_path: Path) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Drive, Mission, Rotate, state\n\n\nclass M(Mission):\n"
        "    go = state(Drive(distance_mm=500), Rotate(angle_deg=90), initial=True,"
        ' on_done="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        (
            "m.py:5:10: error: a state runs one action, and this state(...) was given more (to"
            " do one thing after another, give each its own state and go on with"
            ' on_done="NEXT"; to do them at the same time, write state(Parallel([...]), ...))'
        ),
        "checked 1 file: 1 with errors",
    ]


PYTHON_MISSION = (
    "from roboscript import Drive, Mission, Parallel, PlayTone, Repeat, Rotate, Turn, Wait, state\n"
    "\n\nclass M(Mission):\n"
    "    go = {go}\n"
    '    end = state(final="success")\n'
)


@pytest.mark.parametrize(
    ("go", "expected"),
    [
        pytest.param(
            "state(Parallel(Drive(distance_mm=500), Rotate(angle_deg=90), Wait(duration_s=1)),"
            ' initial=True, on_done="end")',
            "m.py:5:16: error: parallel takes a list of actions, in [ ] (write Parallel(["
            "Drive(distance_mm=500), Rotate(angle_deg=90), Wait(duration_s=1)]))",
            id="parallel-of-three-without-brackets",
        ),
        pytest.param(
            'state(Parallel(Drive(distance_mm=500), PlayTone(frequency_hz=440), "any"),'
            ' initial=True, on_done="end")',
            "m.py:5:16: error: parallel takes a list of actions, in [ ] (write Parallel(["
            'Drive(distance_mm=500), PlayTone(frequency_hz=440)], mode="any"))',
            id="parallel-without-brackets-and-its-mode",
        ),
        pytest.param(
            "state(Repeat(Rotate(angle_deg=90), Drive(distance_mm=200)), initial=True,"
            ' on_done="end")',
            "m.py:5:16: error: repeat runs one action: to repeat several one after another,"
            " make them the states of a mission of their own, and repeat that (write"
            " Repeat(Steps, times=4), Steps being a Mission class with those states)",
            id="repeat-of-two-actions",
        ),
        pytest.param(
            'state(Repeat(Rotate(angle_deg=90), "4"), initial=True, on_done="end")',
            "m.py:5:16: error: repeat's times is a whole number, written without quotes (write"
            " Repeat(Rotate(angle_deg=90), times=4))",
            id="repeat-times-as-text",
        ),
        pytest.param(
            'state(Wait(duration_s=[2]), initial=True, on_done="end")',
            "m.py:5:16: error: wait duration: expected a time such as '200 ms', got [2]",
            id="a-time-in-a-list",
        ),
        pytest.param(
            'state(Turn(angle_deg=90), initial=True, on_done="end")',
            "m.py:5:16: error: Turn() has no parameter 'angle_deg' (turn is a walking robot's"
            " turn, by steps; a robot on wheels turns by an angle with rotate)",
            id="a-walking-turn-given-an-angle",
        ),
        pytest.param(
            'state(Drive(500, 150, 2, 9), initial=True, on_done="end")',
            "m.py:5:16: error: Drive() takes at most 3 values without their names, and was"
            " given 4 (name each value: write Drive(distance_mm=..., speed_mm_s=...,"
            " duration_s=...))",
            id="an-action-with-too-many-values",
        ),
        pytest.param(
            'state(Drive(distance_mm=500), True, "end")',
            "m.py:5:10: error: state() takes one action, and everything after it with its name"
            ' (write state(Drive(distance_mm=500), initial=True, on_done="end"))',
            id="state-with-its-next-state-without-on-done",
        ),
        pytest.param(
            'state(Drive(distance_cm=50), initial=True, on_done="end")',
            "m.py:5:16: error: Drive() has no parameter 'distance_cm' (write distance_mm=500,"
            " which is 50 cm)",
            id="a-distance-in-centimetres",
        ),
        pytest.param(
            'state(Wait(duration_ms=250), initial=True, on_done="end")',
            "m.py:5:16: error: Wait() has no parameter 'duration_ms' (write duration_s=0.25,"
            " which is 250 ms)",
            id="a-time-in-milliseconds",
        ),
        pytest.param(
            'state(Wait(seconds=2), initial=True, on_done="end")',
            "m.py:5:16: error: Wait() has no parameter 'seconds' (how long a wait lasts is its"
            " duration, with its unit: duration: 2 s, or duration_s=2 in Python)",
            id="a-parameter-like-none-of-its-own",
        ),
        pytest.param(
            "state(Wait(duration_s=1), initial=True, on_done=self.end)",
            "m.py:5:58: error: NameError: name 'self' is not defined (a state is named in"
            " quotes, without 'self.': write 'end')",
            id="a-state-named-with-self",
        ),
        pytest.param(
            'state(Drive(distance_mm=500), initial=True, on_done="end",'
            ' when=[(self.bumper.any, "end")])',
            "m.py:5:76: error: NameError: name 'self' is not defined (a condition written as text"
            " names the sensors without 'self.': write 'bumper.any')",
            id="a-sensor-read-with-self-in-the-class-body",
        ),
        pytest.param(
            "Drive(distance_mm=500)",
            "m.py:5:10: error: 'go' is an action, not a state: a state runs it (write"
            " go = state(Drive(distance_mm=500), ...))",
            id="an-action-without-its-state",
        ),
        pytest.param(
            'state(Drive(distance_mm=500), initial=True, on_done="end"),',
            "m.py:5:10: error: 'go = state(...),' is not a state: the comma at its end makes"
            " a tuple (remove the comma after state(...))",
            id="a-state-with-a-comma-at-its-end",
        ),
    ],
)
def test_a_beginners_mistake_in_a_call_is_answered_at_its_line_with_what_to_write(
    tmp_path: Path, go: str, expected: str
) -> None:
    (tmp_path / "m.py").write_text(PYTHON_MISSION.format(go=go), encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines() == [expected, "checked 1 file: 1 with errors"]


def test_an_action_kept_for_states_to_run_is_no_mistake(tmp_path: Path) -> None:
    kept = (
        "    turn = Rotate(angle_deg=90)\n"
        '    go = state(Repeat(turn, times=4), initial=True, on_done="end")\n'
    )
    text = PYTHON_MISSION.format(go="").replace("    go = \n", kept)
    (tmp_path / "m.py").write_text(text, encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.returncode == 0, result.stderr


def test_a_condition_method_named_with_self_in_the_class_body_is_named_in_quotes(
    tmp_path: Path,
) -> None:
    go = 'state(Drive(distance_mm=500), initial=True, on_done="end", when=[(self.hit, "end")])'
    text = PYTHON_MISSION.format(go=go) + "\n    def hit(self) -> bool:\n        return True\n"
    (tmp_path / "m.py").write_text(text, encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.stderr.splitlines()[0] == (
        "m.py:5:76: error: NameError: name 'self' is not defined (a condition is named in"
        " quotes, without 'self.': write 'hit')"
    )


def test_self_with_a_name_that_is_no_state_condition_or_sensor_gets_no_guess(
    tmp_path: Path,
) -> None:
    go = 'state(Drive(distance_mm=self.side), initial=True, on_done="end")'
    (tmp_path / "m.py").write_text(PYTHON_MISSION.format(go=go), encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert (
        result.stderr.splitlines()[0] == "m.py:5:34: error: NameError: name 'self' is not defined"
    )


@pytest.mark.parametrize(
    ("kept", "used"),
    [("turn = Rotate(angle_deg=90)", "turn"), ("side_mm = 500", "Drive(distance_mm=side_mm)")],
)
def test_an_action_or_value_kept_below_the_state_using_it_says_to_set_it_above(
    tmp_path: Path, kept: str, used: str
) -> None:
    go = f'state({used}, initial=True, on_done="end")'
    text = PYTHON_MISSION.format(go=go) + f"    {kept}\n"
    (tmp_path / "m.py").write_text(text, encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    name = kept.split(" ")[0]
    assert result.stderr.splitlines()[0].endswith(
        f"error: NameError: name '{name}' is not defined ('{name}' is set further down in the"
        " class, but Python runs a class from the top: set it above the line that uses it)"
    )


OWN_ACTION = """\
from roboscript import Action, Mission, Result, Rotate, state


class Spin(Action):
    name = "spin"

    def update(self, ctx):
        return Result.DONE


class M(Mission):
    go = state({used}, initial=True, on_done="end")
    end = state(final="success")
    turn = {kept}
"""


@pytest.mark.parametrize("kept", ["Rotate(angle_deg=90)", "Spin()"], ids=["roboscript", "own"])
def test_a_students_own_action_kept_below_its_state_says_to_set_it_above(
    tmp_path: Path, kept: str
) -> None:
    # an action of the student's own class is an action, as roboscript's are: not a state to
    # name in quotes
    (tmp_path / "m.py").write_text(OWN_ACTION.format(used="turn", kept=kept), encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.stderr.splitlines()[0] == (
        "m.py:12:16: error: NameError: name 'turn' is not defined ('turn' is set further down"
        " in the class, but Python runs a class from the top: set it above the line that uses"
        " it)"
    )


@pytest.mark.parametrize("kept", ["Rotate(angle_deg=90)", "Spin()"], ids=["roboscript", "own"])
def test_a_students_own_action_named_with_self_is_not_called_a_state(
    tmp_path: Path, kept: str
) -> None:
    text = OWN_ACTION.format(used="self.turn", kept=kept)
    (tmp_path / "m.py").write_text(text, encoding="utf-8")
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert (
        result.stderr.splitlines()[0] == "m.py:12:16: error: NameError: name 'self' is not defined"
    )


WRONG_RESULTS = """\
from roboscript import Action, Result


class Yes(Action):
    name = "yes"

    def update(self, ctx):
        return True


class Later(Action):
    name = "later"

    def update(self, ctx):
        return Result.failed
"""


def test_a_behaviour_that_returns_no_result_is_told_what_to_return_at_its_def(
    here: Path,
) -> None:
    module = import_student_file(_write(here, "acts.py", WRONG_RESULTS), kind="behaviour")
    with pytest.raises(TypeError) as info:
        module.Yes().update(None)
    assert student_fault(info.value, "go") == (
        "your behaviour 'yes' returned True instead of a Result in state 'go'; return"
        " Result.done() when it has finished, and None while it is still going (acts.py:7)"
    )
    with pytest.raises(TypeError) as info:
        module.Later().update(None)
    assert student_fault(info.value, "go") == (
        "your behaviour 'later' returned Result.failed without calling it in state 'go'; write"
        " return Result.failed(...) (acts.py:14)"
    )


def test_a_behaviour_returning_no_result_inside_a_parallel_ends_the_run_with_one_sentence(
    tmp_path: Path,
) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Action, Mission, Parallel, Wait, state\n\n\n"
        "class Yes(Action):\n"
        '    name = "yes"\n\n'
        "    def update(self, ctx):\n"
        "        return True\n\n\n"
        "class M(Mission):\n"
        "    go = state(Parallel([Yes(), Wait(duration_s=1)]), initial=True,"
        ' on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("run", "m.py", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    assert "Traceback" not in result.stdout + result.stderr
    assert "failure: your behaviour 'yes' returned True instead of a Result in state 'go';" in (
        result.stdout + result.stderr
    )


def test_a_behaviour_whose_update_forgets_self_is_refused_at_check(tmp_path: Path) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Action, Mission, Result, state\n\n\n"
        "class Spin(Action):\n"
        '    name = "spin"\n\n'
        "    def update(ctx):\n"
        "        return Result.done()\n\n\n"
        "class M(Mission):\n"
        '    go = state(Spin(), initial=True, on_done="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines()[0] == (
        "m.py:12:16: error: Spin.update must take self and ctx, as roboscript calls it with the"
        " robot's context (def update(self, ctx):)"
    )


@pytest.mark.parametrize(
    ("update", "written"),
    [
        ("    async def update(self, ctx):\n        return Result.done()\n", "async def"),
        ("    def update(self, ctx):\n        yield None\n", "yield"),
    ],
)
def test_a_behaviour_whose_update_waits_with_async_or_yield_is_refused_at_check(
    tmp_path: Path, update: str, written: str
) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Action, Mission, Result, state\n\n\n"
        "class Spin(Action):\n"
        '    name = "spin"\n\n'
        f"{update}\n\n"
        "class M(Mission):\n"
        '    go = state(Spin(), initial=True, on_done="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("check", "m.py", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.splitlines()[0] == (
        f"m.py:12:16: error: Spin.update is written with {written}, but roboscript calls it"
        " once every tick and does not wait for it, so it would never run (write def"
        " update(self, ctx): without await or yield, returning at once: None while it is still"
        " going, Result.done() when it has finished)"
    )


@pytest.mark.parametrize(
    ("read", "written"),
    [
        ("ctx.range.distance_cm", 'ctx.get("range").distance_mm() (mm, or None for no echo)'),
        ("ctx.bumper.any", 'ctx.get("bumper").pressed() (the set of pressed switches, e.g.'),
    ],
)
def test_a_behaviour_reading_a_sensor_as_a_condition_does_is_told_to_ask_ctx_get(
    tmp_path: Path, read: str, written: str
) -> None:
    (tmp_path / "m.py").write_text(
        "from roboscript import Action, Mission, Result, state\n\n\n"
        "class Look(Action):\n"
        '    name = "look"\n\n'
        "    def update(self, ctx):\n"
        f"        return Result.done() if {read} else None\n\n\n"
        "class M(Mission):\n"
        '    go = state(Look(), initial=True, on_done="end", on_failed="end")\n'
        '    end = state(final="success")\n',
        encoding="utf-8",
    )
    result = run_cli("run", "m.py", cwd=tmp_path)
    name = read.split(".")[1]
    assert "Traceback" not in result.stdout + result.stderr
    assert (
        f"'ActionContext' object has no attribute '{name}' (a behaviour reads the robot's"
        f' {name} with ctx.get("{name}"): write {written}'
    ) in result.stdout + result.stderr


class _Wheels:
    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        pass


class _Counting(Mission):
    go = state(final="success")


def test_a_missing_attribute_is_told_with_the_name_meant_or_that_it_was_never_set() -> None:
    try:
        _Wheels().set_speed  # type: ignore[attr-defined] # noqa: B018 - the mistake under test
    except AttributeError as exc:
        assert StudentCodeError("behaviour 'spin'", exc, where="s.py:3").reason("go") == (
            "your behaviour 'spin' raised AttributeError in state 'go': '_Wheels' object has no"
            " attribute 'set_speed' (did you mean 'set_wheel_speeds'?) (s.py:3)"
        )
    try:
        _Counting().count += 1  # type: ignore[attr-defined]
    except AttributeError as exc:
        assert StudentCodeError("condition 'counted'", exc, where="m.py:8").reason("go") == (
            "your condition 'counted' raised AttributeError in state 'go': '_Counting' object"
            " has no attribute 'count' (self.count is read before anything sets it: give it a"
            " first value in the class, count = 0) (m.py:8)"
        )


@pytest.mark.parametrize(
    ("first_line", "library", "whose"),
    [
        ("from pybricks.hubs import PrimeHub", "pybricks", "Pybricks"),
        ("import motor_pair", "motor_pair", "the LEGO SPIKE app"),
        ("from spike import PrimeHub, MotorPair", "spike", "the LEGO SPIKE app"),
        ("from hub import port", "hub", "the LEGO SPIKE app"),
        ("from vex import *", "vex", "VEXcode"),
        ("from ev3dev2.motor import MoveTank", "ev3dev2", "ev3dev (LEGO EV3)"),
        ("from microbit import *", "microbit", "the micro:bit"),
    ],
)
def test_code_copied_from_another_robots_examples_names_whose_library_it_imports(
    here: Path, first_line: str, library: str, whose: str
) -> None:
    _write(here, "m.py", f"{first_line}\n")
    message = _message("m.py")
    assert message.startswith(
        f"m.py:1:1: error: '{library}' is a library of {whose}, for code that runs on that"
        " robot's own software: a roboscript mission does not use it ("
    )
    assert "from roboscript import Drive, Mission, state" in message


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "from RoboScript import Mission\n",
            (
                "m.py:1:1: error: ModuleNotFoundError: No module named 'RoboScript' (write it in"
                " lower case, in one word: roboscript)"
            ),
        ),
        (
            "from robo_script import Mission\n",
            (
                "m.py:1:1: error: ModuleNotFoundError: No module named 'robo_script' (write it in"
                " lower case, in one word: roboscript)"
            ),
        ),
        (
            "from roboscript.mission import Mission, state\n",
            (
                "m.py:1:1: error: roboscript.mission has no 'Mission' to import (a mission imports"
                " from roboscript itself: write from roboscript import Mission)"
            ),
        ),
        (
            "void setup() {\n}\n",
            (
                "m.py:1:6: error: invalid syntax (this line is C or Arduino code: a roboscript"
                " mission is written in Python or YAML)"
            ),
        ),
        (
            "x = 1\nif x <> 2:\n    pass\n",
            "m.py:2:6: error: invalid syntax (Python writes 'is not equal to' as !=)",
        ),
        (
            "class M:\n    go = state(\n        def run(self):\n            return 1\n    )\n",
            (
                "m.py:3:9: error: invalid syntax (a def is a line of its own in the class, not a"
                " value inside state(...): write the method below the states, and name it in"
                ' quotes there, e.g. when=[("near", "end")])'
            ),
        ),
        (
            "from roboscript import Drive\n\nforward = Drive(distance_mm=50 * cm)\n",
            (
                "m.py:3:34: error: NameError: name 'cm' is not defined (a number in Python has no"
                " unit: for 50 cm write 500, as distance_mm is in mm)"
            ),
        ),
        (
            "distance_mm = 500L\n",
            (
                "m.py:1:17: error: syntax error: invalid decimal literal (a number in Python has no"
                " L at its end: write 500, not 500L)"
            ),
        ),
    ],
)
def test_roboscript_misspelt_imported_from_its_parts_or_code_of_another_language_is_told(
    here: Path, text: str, expected: str
) -> None:
    assert _message(_write(here, "m.py", text).name) == expected


_UNSHOWABLE = """\
from roboscript import Drive, Mission, state


class Gone(BaseException):
    def __str__(self):
        raise Gone()


class M(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

    def near(self):
        raise Gone()
"""


def test_a_base_exception_of_the_students_whose_str_raises_is_told_without_a_traceback(
    tmp_path: Path,
) -> None:
    loading = _write(tmp_path, "m.py", _UNSHOWABLE + "\n\nraise Gone()\n")
    checked = run_cli("check", str(loading), cwd=tmp_path)
    assert "Traceback" not in checked.stderr
    assert "m.py:17:1: error: Gone: (its message cannot be shown: its __str__ raised Gone)" in (
        checked.stderr
    )
    assert checked.returncode == 2
    running = _write(tmp_path, "r.py", _UNSHOWABLE)
    ran = run_cli("run", str(running), cwd=tmp_path)
    assert "Traceback" not in ran.stderr
    assert (
        "failure: your condition 'near' raised Gone in state 'go': (its message cannot be shown:"
        " its __str__ raised Gone) (r.py:14)" in ran.stderr
    )
    assert ran.returncode == 1


def test_a_file_that_raises_generator_exit_itself_is_its_error_at_its_line(
    tmp_path: Path,
) -> None:
    _write(tmp_path, "m.py", "x = 1\nraise GeneratorExit\n")
    done = run_cli("check", "m.py", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        2,
        "m.py:2:1: error: GeneratorExit\nchecked 1 file: 1 with errors\n",
    )


def test_a_condition_that_raises_generator_exit_itself_ends_the_run_with_one_sentence(
    tmp_path: Path,
) -> None:
    _write(
        tmp_path,
        "m.py",
        """\
        from roboscript import Drive, Mission, state


        class M(Mission):
            go = state(Drive(distance_mm=500), initial=True, on_done="end", when=[("near", "end")])
            end = state(final="success")

            def near(self):
                raise GeneratorExit
        """,
    )
    done = run_cli("run", "m.py", cwd=tmp_path)
    assert "Traceback" not in done.stderr
    assert "failure: your condition 'near' raised GeneratorExit in state 'go' (m.py:9)" in (
        done.stderr
    )
    assert done.returncode == 1


# ------------------------------------------ what a word processor writes for quotes and minus

WORD_PROCESSOR_YAML = """\
mission: m
initial: go
states:
  go:
    do: {drive: {distance: VALUE}}
    on: {done: end}
    when:
      - {if: CONDITION, goto: end}
  end: {final: success}
"""


@pytest.mark.parametrize(
    ("char", "told"),
    [pytest.param(quote, "curly quote", id=f"U+{ord(quote):04X}") for quote in CURLY_QUOTES]
    + [pytest.param(dash, "minus", id=f"U+{ord(dash):04X}") for dash in DASHES],
)
def test_each_quote_and_dash_of_a_word_processor_is_told_in_yaml_and_in_python(
    here: Path, char: str, told: str
) -> None:
    # one set of characters for every reader: the minus sign (U+2212) was told in a YAML
    # value and not in Python, „ ‚ « » in a YAML value and not in a condition or Python
    value = f"{char}50 cm{char}" if told == "curly quote" else f"{char}50 cm"
    number = f"{char}20{char}" if told == "curly quote" else f"{char}20"
    condition = f"range.distance_cm > {number}"
    yaml_text = WORD_PROCESSOR_YAML.replace("VALUE", f'"{value}"')
    with pytest.raises(MissionError) as in_value:
        parse_yaml_mission(yaml_text.replace("CONDITION", "bumper.any"), "m.yaml")
    with pytest.raises(MissionError) as in_condition:
        parse_yaml_mission(
            WORD_PROCESSOR_YAML.replace("VALUE", "50 cm").replace("CONDITION", f'"{condition}"'),
            "m.yaml",
        )
    path = _write(
        here, "m.py", f"from roboscript import Drive\n\nGO = Drive(distance_mm={number})\n"
    )
    with pytest.raises(MissionError) as in_python:
        import_student_file(path)
    for error in (in_value.value, in_condition.value, in_python.value):
        problem = getattr(error, "problems", [error])[0]
        assert told in f"{problem.message} ({problem.hint})", problem.format()
