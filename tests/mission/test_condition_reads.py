"""A Python condition that reads what is not there is refused at check, at its line.

Each case is a condition method a beginner writes; without the check each would end the run
with Python's AttributeError or NameError, or end the program (exit()), once the robot moves.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.python_loader import find_mission_class
from roboscript.mission.student_code import import_student_file

HEAD = """\
import sys

from roboscript import Mission, Wait, state


class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

"""
"""A mission whose condition ``near`` starts on line 10 of its file."""


def check(tmp_path: Path, method: str) -> list[str]:
    """What ``roboscript check`` says of the mission with ``method``: its errors, else []."""
    path = tmp_path / "lesson.py"
    path.write_text(HEAD + method, encoding="utf-8")
    cls = find_mission_class(import_student_file(path, kind="mission"), str(path))
    try:
        compile_mission(cls, path="lesson.py")
    except MissionError as error:
        return [p.format() for p in getattr(error, "problems", [error])]
    return []


@pytest.mark.parametrize(
    ("method", "expected"),
    [
        pytest.param(
            "    def near(self):\n        return self.bumpr.any\n",
            "lesson.py:11:16: error: Lesson has no 'bumpr' (did you mean 'bumper'?)",
            id="a-misspelt-sensor",
        ),
        pytest.param(
            "    def near(self):\n        return self.distance_cm < 20\n",
            "lesson.py:11:16: error: Lesson has no 'distance_cm' (did you mean"
            " self.range.distance_cm?)",
            id="a-sensor-value-without-its-sensor",
        ),
        pytest.param(
            "    def near(self):\n        self.drive(100)\n        return True\n",
            "lesson.py:11:9: error: Lesson has no 'drive' (a condition cannot make the robot act:"
            " run the action in a state of its own, e.g. turn = state(Rotate(angle_deg=90),"
            " ...), and go there when the condition holds)",
            id="an-action-called-as-a-method",
        ),
        pytest.param(
            "    def near(self):\n        return bumper.any\n",
            "lesson.py:11:16: error: name 'bumper' is not defined (inside a method, the mission's"
            " own values are read through self: self.bumper)",
            id="a-sensor-without-self",
        ),
        pytest.param(
            "    def near(self):\n        return math.isnan(self.elapsed)\n",
            "lesson.py:11:16: error: name 'math' is not defined (add 'import math' at the top of"
            " the file)",
            id="a-module-not-imported",
        ),
        pytest.param(
            "    def near(self):\n        return self.robot.range.distance_cm < 20\n",
            "lesson.py:11:16: error: self.robot is the name of the mission's robot, as text (the"
            " robot's sensors are read on self: self.range)",
            id="sensors-looked-for-on-self-robot",
        ),
        pytest.param(
            "    def near(self):\n        input('press enter')\n        return True\n",
            "lesson.py:11:9: error: input() waits for someone to type, and a running mission has"
            " no one at the keyboard (a condition reads the robot and returns at once, e.g."
            " return self.bumper.any)",
            id="input",
        ),
        pytest.param(
            "    def near(self):\n        if self.bumper.any:\n            sys.exit()\n"
            "        return False\n",
            "lesson.py:12:13: error: sys.exit() would end the whole program, not the mission (to"
            " end the mission, go to a final state when this condition holds: when=[('near',"
            " 'end')], with end = state(final=\"success\"))",
            id="sys-exit",
        ),
        pytest.param(
            "    def near(self):\n        return self.close()\n\n"
            "    def close(self):\n        return self.rnage.distance_cm < 20\n",
            "lesson.py:14:16: error: Lesson has no 'rnage' (did you mean 'range'?)",
            id="in-a-method-the-condition-calls",
        ),
        pytest.param(
            "    def near(self):\n        self.range = 5\n        return True\n",
            "lesson.py:11:9: error: self.range is a value roboscript gives the mission, and cannot"
            " be set (keep a value of your own under a name of its own: self.my_range = ...)",
            id="a-sensor-set",
        ),
    ],
)
def test_a_condition_reading_what_is_not_there_is_refused_at_its_line(
    tmp_path: Path, method: str, expected: str
) -> None:
    assert check(tmp_path, method) == [expected]


@pytest.mark.parametrize(
    "method",
    [
        pytest.param(
            "    def __init__(self):\n        super().__init__()\n        self.seen = 0\n\n"
            "    def near(self):\n        self.seen += 1\n        return self.seen > 3\n",
            id="a-value-the-mission-keeps-on-self",
        ),
        pytest.param(
            "    def near(self):\n        limit: Centimetres = 20\n"
            "        hits = [b for b in (self.bumper.left, self.bumper.right) if b]\n"
            "        try:\n            import math\n        except ImportError as missing:\n"
            "            raise missing\n"
            "        def twice(x):\n            return 2 * x\n"
            "        return twice(len(hits)) > 0 and math.isfinite(limit)\n",
            id="names-the-method-makes-itself",
        ),
        pytest.param(
            "    def near(self):\n        setattr(self, 'later', 1)\n"
            "        return self.later > 0\n",
            id="a-class-that-makes-attributes-at-run-time",
        ),
        pytest.param(
            "    LIMIT_CM = 20\n\n"
            "    def near(self, limit=LIMIT_CM):\n        return self.range.distance_cm < limit\n",
            id="a-class-value-as-a-default",
        ),
    ],
)
def test_what_a_condition_rightly_reads_is_no_mistake(tmp_path: Path, method: str) -> None:
    assert check(tmp_path, method) == []
