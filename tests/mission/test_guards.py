"""The guard language: what it accepts, what it refuses, and that nothing executes."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import guards
from roboscript.mission.guards import (
    COLOR_NAMES,
    RGB_NAMES,
    GuardEnv,
    GuardError,
    compile_guard,
    guard_names,
)
from roboscript.mission.python_compiler import compile_mission
from roboscript.mission.python_loader import find_mission_class
from roboscript.mission.student_code import import_student_file


@pytest.mark.parametrize(
    ("source", "values", "expected"),
    [
        ("range.distance_cm < 20", {"range.distance_cm": 15.0}, True),
        ("range.distance_cm < 20", {"range.distance_cm": float("inf")}, False),
        ("range.distance_cm < 200 mm", {"range.distance_cm": 15.0}, True),
        ("range.distance_mm < 20 cm", {"range.distance_mm": 250.0}, False),
        ("bumper.left or bumper.right", {"bumper.left": False, "bumper.right": True}, True),
        ("not bumper.any", {"bumper.any": False}, True),
        ("visits.side >= 4", {"visits.side": 4}, True),
        ("elapsed > 1.5 s and state_time < 500 ms", {"elapsed": 2.0, "state_time": 0.4}, True),
        ("heading_deg > 80 deg", {"heading_deg": 85.0}, True),
        ("10 < line.center <= 600", {"line.center": 600.0}, True),
        ("line.center - line.left > 100", {"line.center": 700.0, "line.left": 500.0}, True),
        ("true", {}, True),
    ],
)
def test_guards_evaluate(source: str, values: dict[str, float | bool], expected: bool) -> None:
    assert compile_guard(source, frozenset({"side"}))(Env(**values)) is expected


@pytest.mark.parametrize(
    "source",
    [
        "__import__('os').system('touch /tmp/roboscript-guard')",
        "range.__class__",
        "range.distance_cm.__class__ < 1",
        "[x for x in ()]",
        "lambda: 1",
        "range['distance_cm']",
        "open('/etc/passwd')",
        "'text' == 'text'",
        "(1).__class__",
        "bumper",
        "",
        "range.distance_cm <",
    ],
)
def test_anything_outside_the_language_is_refused(source: str) -> None:
    with pytest.raises(GuardError):
        compile_guard(source)


def test_guard_reports_the_capabilities_it_reads() -> None:
    guard = compile_guard("range.distance_cm < 20 and not bumper.any and elapsed > 1")
    assert guard.capabilities == {"range", "bumper"}


# -------- Refusals whole, and what each accepted condition reads
#
# Conditions, pinned where mutation testing found changes no other test noticed.
#
# Every refusal is checked whole, as ``roboscript check`` shows it: the message, the column it
# points at and the hint. Every accepted condition is checked for the value it reads, the unit
# a number is converted to, and what it needs from the robot.


STATES = frozenset({"first", "second"})


class Env(GuardEnv):
    """Sensor values by guard name (``range.distance_mm``, ``elapsed``)."""

    def __init__(self, regions: frozenset[str] = frozenset(), /, **values: float | bool) -> None:
        self.values = values
        self.regions = regions

    def sensor(self, root: str, attr: str | None) -> float | bool:
        return self.values[f"{root}.{attr}" if attr else root]

    def visits(self, state: str) -> int:
        return int(self.values[f"visits.{state}"])

    def in_region(self, name: str) -> bool:
        return name in self.regions


def refusal(source: str) -> tuple[str, int, str | None]:
    with pytest.raises(GuardError) as info:
        compile_guard(source, STATES)
    return str(info.value), info.value.offset, info.value.hint


NAMES_HINT = (
    "names: heading_deg, elapsed, state_time, range.distance_mm, range.distance_cm,"
    " side_range.distance_mm, side_range.distance_cm, bumper.left, ..."
)


@pytest.mark.parametrize(
    ("source", "message", "offset", "hint"),
    [
        ("~bumper.any", "only 'not' and '-' can stand before a value", 0, None),
        (
            "elapsed > 2 ** 3",
            "a condition cannot raise to a power ('**'); only + - * / are allowed",
            10,
            "write the number itself, at most 1e+09",
        ),
        ("elapsed % 2 > 0", "only + - * / are allowed in a condition", 0, None),
        ("range.distance_mm < 'a'", "a condition compares numbers, not text", 20, None),
        ("elapsed > abs(1)", "a condition cannot call functions", 10, None),
        ("elapsed > [1]", "this is not allowed in a condition", 10, None),
        (
            "range.distance_mm < 1e400",
            "the number infinity is too large for a condition (at most 1e+09)",
            20,
            "compare with a number a sensor can read, e.g. range.distance_cm < 20",
        ),
        (
            "elapsed > 2000000000",
            "the number 2000000000 is too large for a condition (at most 1e+09)",
            10,
            "compare with a number a sensor can read, e.g. range.distance_cm < 20",
        ),
        (
            "elapsed > 2000000000 s",
            "the number 2e+09 is too large for a condition (at most 1e+09)",
            10,
            "compare with a number a sensor can read, e.g. range.distance_cm < 20",
        ),
        (
            "elapsed is 3",
            "'is' is not a comparison in a condition",
            0,
            "compare numbers with == or !=",
        ),
        (
            "elapsed > 1 and 2 cm",
            "a number with a unit must be compared with a sensor value",
            16,
            None,
        ),
        ("range", "'range' needs a '.' and a name after it", 0, "write range.distance_cm < 20"),
        (
            "visits > 1",
            "'visits' needs a '.' and a name after it",
            0,
            "e.g. visits.STATE >= 2, with the name of one of your states",
        ),
        (
            "in_region",
            "'in_region' needs a '.' and a name after it",
            0,
            "e.g. in_region.REGION, with the name of one of the world's regions",
        ),
        ("visits.nope > 1", "'visits.nope': there is no state 'nope'", 7, None),
        (
            "visits.fist > 1",
            "'visits.fist': there is no state 'fist'",
            7,
            "did you mean 'visits.first'?",
        ),
        (
            "range.distance < 20",
            (
                "'range.distance' needs its unit in the name: 'range.distance_cm' or"
                " 'range.distance_mm'"
            ),
            6,
            "e.g. range.distance_cm < 20, or give the number a unit: range.distance < 2 cm",
        ),
        (
            "range.distnce_mm < 3",
            "'range' has no 'distnce_mm' (it has distance_cm, distance_mm)",
            6,
            "did you mean 'range.distance_mm'?",
        ),
        ("range.qqq < 3", "'range' has no 'qqq' (it has distance_cm, distance_mm)", 6, None),
        (
            "buttons.center",
            "'buttons' has no 'center' (it has any, left, right)",
            8,
            (
                "the hub's centre button stops the program, so a mission never sees it pressed;"
                " use buttons.left or buttons.right"
            ),
        ),
        ("a.b.c", "a name has at most one '.'", 4, None),
        ("bumpr.any", "unknown name 'bumpr' in a condition", 0, "did you mean 'bumper'?"),
        ("elapsd > 1", "unknown name 'elapsd' in a condition", 0, "did you mean 'elapsed'?"),
        ("zzzzqqq", "unknown name 'zzzzqqq' in a condition", 0, NAMES_HINT),
        ("visit.first > 1", "unknown name 'visit' in a condition", 0, "did you mean 'visits'?"),
        (
            "elapsed > 1 and elapsed is 3",
            "'is' is not a comparison in a condition",
            16,
            "compare numbers with == or !=",
        ),
        ("elapsed > > 1", "cannot read the condition 'elapsed > > 1'", 10, None),
        ("elapsed > 1 and elapsed % 2 > 0", "only + - * / are allowed in a condition", 16, None),
        ("elapsed > 1 and (elapsed, state_time)", "a condition has no ','", 16, None),
        ("elapsed > 1 and ~bumper.any", "only 'not' and '-' can stand before a value", 16, None),
        (
            "elapsed > 1 and range",
            "'range' needs a '.' and a name after it",
            16,
            "write range.distance_cm < 20",
        ),
        ("elapsed > 1 and zzzzqqq", "unknown name 'zzzzqqq' in a condition", 16, NAMES_HINT),
        ("in_regon.goal", "unknown name 'in_regon' in a condition", 0, "did you mean 'in_region'?"),
        (
            "elapsed > 1 and bumpr.any",
            "unknown name 'bumpr' in a condition",
            16,
            "did you mean 'bumper'?",
        ),
        (
            "heading_deg > 20 cm",
            "'cm' is a unit of distance, but this is an angle (use deg, degrees, rad, rev)",
            14,
            None,
        ),
        (
            "elapsed > 2 deg",
            "'deg' is a unit of angle, but this is a time (use s, sec, ms, min)",
            10,
            None,
        ),
        ("", "a condition cannot be empty", 0, None),
    ],
)
def test_a_refused_condition_says_what_and_where(
    source: str, message: str, offset: int, hint: str | None
) -> None:
    assert refusal(source) == (message, offset, hint)


@pytest.mark.parametrize(
    ("source", "values", "expected"),
    [
        # a number's unit is converted to the unit of the name it is compared with
        ("range.distance_cm < 200 mm", {"range.distance_cm": 19.9}, True),
        ("range.distance_cm < 200 mm", {"range.distance_cm": 20.0}, False),
        ("range.distance_mm >= 2 cm", {"range.distance_mm": 20.0}, True),
        ("range.distance_mm >= 2 cm", {"range.distance_mm": 19.9}, False),
        ("range.distance_mm > 0.5 m", {"range.distance_mm": 500.1}, True),
        ("side_range.distance_cm <= 0.5 m", {"side_range.distance_cm": 50.0}, True),
        ("elapsed > 1500 ms", {"elapsed": 1.6}, True),
        ("elapsed > 1500 ms", {"elapsed": 1.5}, False),
        ("elapsed >= 1 min", {"elapsed": 60.0}, True),
        ("elapsed >= 1 min", {"elapsed": 59.9}, False),
        ("state_time < 2 sec", {"state_time": 1.9}, True),
        ("heading_deg > 1 rad", {"heading_deg": 57.3}, True),
        ("heading_deg > 1 rad", {"heading_deg": 57.2}, False),
        ("pose.heading_deg > 45 °", {"pose.heading_deg": 46.0}, True),
        ("driven.total_cm >= 1 m", {"driven.total_cm": 100.0}, True),
        ("driven.total_cm >= 1 m", {"driven.total_cm": 99.9}, False),
        ("driven.state_mm > 5 cm", {"driven.state_mm": 50.1}, True),
        ("pose.x_mm > 1 cm", {"pose.x_mm": 10.1}, True),
        ("pose.y_mm < 1 cm", {"pose.y_mm": 10.0}, False),
        # a name without its unit takes the number's ('range.distance < 20 cm' is in mm)
        ("range.distance < 20 cm", {"range.distance_mm": 199.0}, True),
        ("range.distance < 20 cm", {"range.distance_mm": 200.0}, False),
        ("driven.total > 1 m", {"driven.total_mm": 1000.5}, True),
        # minutes and radians convert to the name's seconds and degrees
        ("elapsed < 1 min", {"elapsed": 59.9}, True),
        ("elapsed < 1 min", {"elapsed": 60.0}, False),
        # the operators, chains and arithmetic
        ("-elapsed < -1", {"elapsed": 1.5}, True),
        ("-elapsed < -1", {"elapsed": 0.5}, False),
        ("elapsed > 1 or state_time > 1", {"elapsed": 0.0, "state_time": 2.0}, True),
        ("elapsed > 1 and state_time > 1", {"elapsed": 2.0, "state_time": 0.0}, False),
        ("1 < elapsed < 3 < state_time", {"elapsed": 2.0, "state_time": 4.0}, True),
        ("1 < elapsed < 3 < state_time", {"elapsed": 2.0, "state_time": 3.0}, False),
        ("1 < elapsed < 3 < state_time", {"elapsed": 0.5, "state_time": 4.0}, False),
        ("elapsed == 2 and state_time != 2", {"elapsed": 2.0, "state_time": 1.0}, True),
        ("elapsed * 2 - 1 == state_time + 2", {"elapsed": 2.0, "state_time": 1.0}, True),
        ("elapsed / state_time > 1000000", {"elapsed": 1.0, "state_time": 0.0}, True),
        ("elapsed / state_time < -1000000", {"elapsed": -1.0, "state_time": 0.0}, True),
        ("elapsed / state_time < -1000000", {"elapsed": 1.0, "state_time": -0.0}, True),
        (
            "elapsed / state_time == elapsed / state_time",
            {"elapsed": 0.0, "state_time": 0.0},
            False,
        ),
        ("elapsed / state_time == 0.5", {"elapsed": 1.0, "state_time": 2.0}, True),
        ("elapsed < 1000000000", {"elapsed": 5.0}, True),  # the largest number allowed
        ("elapsed > -1000000000", {"elapsed": 5.0}, True),
        ("elapsed > 1 s and state_time < 2 s", {"elapsed": 1.5, "state_time": 1.5}, True),
        # a negative number keeps its unit ('10 cm to the left')
        ("pose.x_mm < -10 cm", {"pose.x_mm": -100.5}, True),
        ("pose.x_mm < -10 cm", {"pose.x_mm": -99.5}, False),
        ("pose.heading_deg <= -90 °", {"pose.heading_deg": -90.0}, True),
        ("-1 min < elapsed", {"elapsed": -59.0}, True),
        ("driven.state_cm > -10 mm", {"driven.state_cm": -5.0}, False),
        ("true and not false", {}, True),
        ("false or false", {}, False),
    ],
)
def test_a_condition_reads_its_values_in_the_units_written(
    source: str, values: dict[str, float | bool], expected: bool
) -> None:
    assert compile_guard(source, STATES)(Env(**values)) is expected


@pytest.mark.parametrize(
    ("source", "needs"),
    [
        ("range.distance_cm < 20", {"range"}),
        ("side_range.distance_mm < 20", {"side_range"}),
        ("bumper.left and line.any", {"bumper", "line"}),
        ("color.black or buttons.any", {"color", "buttons"}),
        ("heading_deg > 10 and driven.total_mm > 10 and pose.x_mm > 0", {"drive_base"}),
        ("elapsed > 1 and state_time > 1 and visits.first > 1", set()),
        ("in_region.goal", {"drive_base"}),
    ],
)
def test_a_condition_names_the_parts_of_the_robot_it_needs(source: str, needs: set[str]) -> None:
    assert compile_guard(source, STATES).capabilities == needs


def test_a_condition_names_the_states_and_regions_it_reads() -> None:
    guard = compile_guard(
        "visits.first > 1 and in_region.north-wall and not in_region.goal", STATES
    )
    assert guard.states == {"first"}
    assert guard.regions == {"north-wall", "goal"}
    assert guard(Env(frozenset({"north-wall"}), **{"visits.first": 2})) is True
    assert guard(Env(frozenset({"north-wall", "goal"}), **{"visits.first": 2})) is False
    assert guard(Env(frozenset(), **{"visits.first": 2})) is False


def test_visits_of_any_state_are_read_when_the_states_are_not_known() -> None:
    guard = compile_guard("visits.later >= 2")
    assert guard.states == {"later"}
    assert guard(Env(**{"visits.later": 2})) is True


def test_a_nan_reading_compares_false_every_way() -> None:
    for op in ("<", "<=", ">", ">=", "=="):
        assert compile_guard(f"elapsed {op} 1")(Env(elapsed=math.nan)) is False


def test_the_names_listed_for_the_docs_are_the_names_a_condition_reads() -> None:
    """``guard_names()`` feeds the reference page and a Python mission's capability check:
    each name it lists compiles, and needs exactly the part of the robot it says."""
    names = guard_names()
    colours = [f"color.{c}" for c in ("reflection", *COLOR_NAMES, *RGB_NAMES)]
    assert list(names) == [
        "heading_deg",
        "elapsed",
        "state_time",
        "range.distance_mm",
        "range.distance_cm",
        "side_range.distance_mm",
        "side_range.distance_cm",
        "bumper.left",
        "bumper.right",
        "bumper.any",
        "line.left",
        "line.center",
        "line.right",
        "line.any",
        *colours,
        "buttons.left",
        "buttons.right",
        "buttons.any",
        "driven.total_mm",
        "driven.total_cm",
        "driven.state_mm",
        "driven.state_cm",
        "pose.x_mm",
        "pose.y_mm",
        "pose.heading_deg",
        "visits.STATE",
        "in_region.NAME",
    ]
    assert names["visits.STATE"] is None and names["elapsed"] is None  # nothing needed
    for name, needs in names.items():
        source = name.replace("STATE", "first").replace("NAME", "goal")
        assert compile_guard(source, STATES).capabilities == ({needs} if needs else set()), name


@pytest.mark.parametrize("root", sorted(guards._ATTRS))
def test_a_sensor_named_without_its_value_gets_conditions_that_compile(root: str) -> None:
    with pytest.raises(GuardError) as info:
        compile_guard(root)
    hint = info.value.hint or ""
    assert hint.startswith("write "), hint
    for example in hint.removeprefix("write ").replace(" or ", ", ").split(", "):
        compile_guard(example)  # every suggestion is itself a valid condition
        assert example.startswith(f"{root}.")


# --------------------------------------------------- a condition no reading can make true

NEVER_TRUE_MISSION = """\
from roboscript import Mission, Wait, state


class Lesson(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("near", "end")])
    end = state(final="success")

    def near(self):
        return CONDITION
"""


@pytest.mark.parametrize(
    ("condition", "hint"),
    [
        pytest.param(
            "range.distance_cm < 0",
            "compare with a distance it can read, e.g. range.distance_cm < 20",
            id="a-distance-below-zero",
        ),
        pytest.param(
            "range.distance_cm < 20 and range.distance_cm > 30",
            "to go when either holds, write or: range.distance_cm < 20 or range.distance_cm > 30",
            id="two-bounds-apart",
        ),
        pytest.param("20 < range.distance_cm < 10", None, id="a-chain-apart"),
        pytest.param(
            "range.distance_cm > 5 and range.distance_cm < 20 and range.distance_cm > 30",
            None,
            id="three-bounds-apart",
        ),
    ],
)
def test_a_condition_never_true_has_one_hint_in_yaml_and_python(
    tmp_path: Path, condition: str, hint: str | None
) -> None:
    with pytest.raises(GuardError) as info:
        compile_guard(condition, truth=True)
    path = tmp_path / "lesson.py"
    method = condition.replace("range.", "self.range.")
    path.write_text(NEVER_TRUE_MISSION.replace("CONDITION", method), encoding="utf-8")
    cls = find_mission_class(import_student_file(path, kind="mission"), str(path))
    with pytest.raises(MissionError) as error:
        compile_mission(cls, path="lesson.py")
    told = [p.hint for p in error.value.problems if "can never be true" in p.message]
    in_python = hint.replace("range.", "self.range.") if hint else None
    assert (info.value.hint, told) == (hint, [in_python])
