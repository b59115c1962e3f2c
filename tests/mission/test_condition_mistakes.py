"""Mistakes from other languages in a condition get a located message and the fix (issue 14).

The messages as a student sees them (with ``file:line:col``) are golden-tested with
docs/tutorial/common-mistakes.md; these pin the offset and the hint for each form.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import run_cli
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.mission.guards import GuardEnv, GuardError, compile_guard


@pytest.mark.parametrize(
    ("source", "offset", "message", "hint"),
    [
        (
            "range.distance_cm = 20",
            18,
            "'=' sets a value; a condition compares",
            "write '==' to compare: range.distance_cm == 20",
        ),
        (
            "bumper.left && bumper.right",
            12,
            "'&&' is not a condition word",
            "write 'and': bumper.left and bumper.right",
        ),
        (
            "bumper.left || line.any",
            12,
            "'||' is not a condition word",
            "write 'or': bumper.left or line.any",
        ),
        ("!bumper.any", 0, "'!' is not a condition word", "write 'not': not bumper.any"),
        (
            "elapsed =< 3",
            8,
            "'=<' is not a comparison",
            "write it the other way round: elapsed <= 3",
        ),
        (
            "range.distance_cm < 0,5",
            20,
            "a decimal comma in a condition",
            "write decimals with a point: range.distance_cm < 0.5",
        ),
        (
            "range.distance_cm less than 20",
            18,
            "'less than' is written '<' in a condition",
            "write range.distance_cm < 20",
        ),
        (
            "range.distance_cm is greater than 20",
            18,
            "'is greater than' is written '>' in a condition",
            "write range.distance_cm > 20",
        ),
        (
            "elapsed equals 3",
            8,
            "'equals' is written '==' in a condition",
            "write elapsed == 3",
        ),
        (
            "bumper.left and bumper.right or",
            29,
            "'or' at its end needs a condition after it",
            "finish it, or take away the last word",
        ),
        (
            "bumper.any AND range.distance_cm < 20",
            11,
            "'AND' is written in lower case",
            "write bumper.any and range.distance_cm < 20",
        ),
        (
            "Not bumper.left Or bumper.right",
            0,
            "'Not' is written in lower case",
            "write not bumper.left or bumper.right",
        ),
        (
            "range.distance_cm < 20 and > 5",
            27,
            "'and' joins two whole comparisons",
            "name the value again: range.distance_cm < 20 and range.distance_cm > 5",
        ),
        (
            "range.distance_cm between 5 and 20",
            18,
            "'between' is written with two '<'",
            "write 5 < range.distance_cm < 20",
        ),
        (
            "range.distance_cm < 20 kg",
            23,
            "'kg' is not a unit a condition knows",
            "use mm, cm, m, s, ms, min, deg or rad, e.g. range.distance < 20 cm",
        ),
    ],
)
def test_each_mistake_is_located_and_says_what_to_write(
    source: str, offset: int, message: str, hint: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert str(caught.value) == f"cannot read the condition '{source}': {message}"
    assert caught.value.offset == offset
    assert caught.value.hint == hint


@pytest.mark.parametrize(
    "source",
    ["bumper.left != bumper.right", "not bumper.any", "elapsed <= 3 and state_time >= 1"],
)
def test_the_right_forms_are_not_taken_for_mistakes(source: str) -> None:
    compile_guard(source)


@pytest.mark.parametrize("source", ["elapsed > > 3", "range.distance_cm < 20 cm <", "elapsed 2"])
def test_a_condition_that_breaks_otherwise_keeps_the_plain_message(source: str) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert str(caught.value) == f"cannot read the condition '{source}'"


@pytest.mark.parametrize(
    ("source", "offset", "message"),
    [
        ("elapsed > 3 and (", 16, "this '(' is never closed"),
        ("(range.distance_cm < 20", 0, "this '(' is never closed"),
        ("range.distance_cm < 20 cm)", 25, "this ')' closes no '('"),
        ("elapsed > 2 s or )", 17, "this ')' closes no '('"),
    ],
)
def test_a_bracket_left_open_or_never_opened_is_pointed_at(
    source: str, offset: int, message: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert str(caught.value) == f"cannot read the condition '{source}': {message}"
    assert caught.value.offset == offset


@pytest.mark.parametrize(
    ("source", "offset", "hint"),
    [
        ("bumper.left & bumper.right", 12, "write 'and': bumper.left and bumper.right"),
        ("bumper.left | line.any", 12, "write 'or': bumper.left or line.any"),
    ],
)
def test_one_ampersand_or_bar_is_told_as_and_or(source: str, offset: int, hint: str) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert caught.value.offset == offset
    assert caught.value.hint == hint


@pytest.mark.parametrize(
    ("source", "hint"),
    [
        ("visits(turn) > 2", "a state's visits are read with a '.': write visits.turn"),
        ("elapsed() > 2", "a value is read without brackets: write elapsed"),
        ("bumper.any()", "a value is read without brackets: write bumper.any"),
    ],
)
def test_a_call_in_a_condition_shows_the_value_it_meant(source: str, hint: str) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source, frozenset({"turn"}))
    assert caught.value.hint == hint


@pytest.mark.parametrize(
    ("source", "message", "hint"),
    [
        (
            "distance_cm < 20",
            "unknown name 'distance_cm' in a condition: a sensor's value is named with its sensor",
            "write 'range.distance_cm' or 'side_range.distance_cm'",
        ),
        (
            "distance < 20",
            (
                "unknown name 'distance' in a condition: a sensor's value is named with its sensor"
                " and its unit"
            ),
            "write 'range.distance_cm' or 'side_range.distance_cm'",
        ),
    ],
)
def test_a_sensors_value_without_its_sensor_names_the_sensors_that_have_it(
    source: str, message: str, hint: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert (str(caught.value), caught.value.offset, caught.value.hint) == (message, 0, hint)


def test_a_unit_of_the_wrong_kind_names_both_kinds() -> None:
    with pytest.raises(GuardError, match="'s' is a unit of time, but this is a distance"):
        compile_guard("range.distance_cm < 2 s")


class _Env(GuardEnv):
    def sensor(self, root: str, attr: str | None) -> float | bool:
        return False if root == "bumper" else 1.0

    def visits(self, state: str) -> int:
        return 0

    def in_region(self, name: str) -> bool:
        return name == "north-wall"


TOKENS = [
    "range.distance",
    "range.distance_cm",
    "driven.state_mm",
    "driven.total",
    "pose.x_mm",
    "pose.heading_deg",
    "in_region.north-wall",
    "in_region",
    "bumper.any",
    "20",
    "0,5",
    "20 cm",
    "1 m",
    "20kg",
    "=",
    "==",
    "=<",
    "&&",
    "||",
    "!",
    "!=",
    "<",
    "and",
    "not",
    "(",
    ")",
    "-",
]


@settings(max_examples=500, deadline=None)
@given(st.lists(st.sampled_from(TOKENS), min_size=1, max_size=8))
def test_new_names_and_mistakes_are_read_or_explained_never_crash(tokens: list[str]) -> None:
    source = " ".join(tokens)
    try:
        guard = compile_guard(source)
    except GuardError as exc:
        assert 0 <= exc.offset <= len(source)
        return
    assert isinstance(guard(_Env()), bool)


@pytest.mark.parametrize(
    ("condition", "name", "offset"),
    [
        ("bumper.any < 2 cm", "bumper.any", 13),
        ("visits.first > 1 s", "visits.first", 15),
        ("2 cm > line.left", "line.left", 0),
    ],
)
def test_a_unit_beside_a_value_without_one_is_refused_at_the_number(
    condition: str, name: str, offset: int
) -> None:
    """A switch, a count or a raw reading has no unit: '2 cm' beside one would silently be
    read as 20 (millimetres), so it is refused where the number is written."""
    with pytest.raises(GuardError) as caught:
        compile_guard(condition)
    assert str(caught.value) == (
        f"'{name}' has no unit, so it cannot be compared with a number that has one"
    )
    assert caught.value.offset == offset
    assert caught.value.hint == "write the number without a unit"


@pytest.mark.parametrize(
    ("source", "message", "hint"),
    [
        (
            "bumper.any is True",
            "'is' is not a comparison in a condition",
            "a switch is true or false by itself: write bumper.any",
        ),
        (
            "bumper.any is not True",
            "'is not' is not a comparison in a condition",
            "a switch is true or false by itself: write not bumper.any",
        ),
        (
            "bumper.left is False",
            "'is' is not a comparison in a condition",
            "a switch is true or false by itself: write not bumper.left",
        ),
        (
            "range.distance_cm < '20 cm'",
            "a condition compares numbers, not text",
            "write the number without quotes: range.distance_cm < 20 cm",
        ),
    ],
)
def test_python_and_text_forms_say_how_a_condition_writes_them(
    source: str, message: str, hint: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert (str(caught.value), caught.value.hint) == (message, hint)


@pytest.mark.parametrize(
    ("source", "message", "offset", "hint"),
    [
        (
            "self.close",
            "a condition written as text names things without 'self.'",
            0,
            "a condition method is named alone, in quotes: write 'close'",
        ),
        (
            "self.visits('turn') >= 4",
            "a condition cannot call functions",
            0,
            "a state's visits are read with a '.': write visits.turn",
        ),
        (
            "visits('turn') >= 4",
            "a condition cannot call functions",
            0,
            "a state's visits are read with a '.': write visits.turn",
        ),
    ],
)
def test_python_habits_in_a_condition_written_as_text_say_what_to_write(
    source: str, message: str, offset: int, hint: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert (str(caught.value), caught.value.offset, caught.value.hint) == (message, offset, hint)


@pytest.mark.parametrize(
    ("source", "word"), [("bumper.any == yes", "yes"), ("line.left == black", "black")]
)
def test_a_word_where_a_sensors_value_is_compared_says_what_a_value_is(
    source: str, word: str
) -> None:
    with pytest.raises(GuardError) as caught:
        compile_guard(source)
    assert str(caught.value) == f"'{word}' is not a value a condition knows"
    assert caught.value.offset == source.index(word)
    assert caught.value.hint == (
        "a sensor's value is a number or true/false: compare it with a number in the unit its"
        " name ends in, or with true or false"
    )


@pytest.mark.parametrize(
    ("source", "message", "hint"),
    [
        (
            "range.distance_cm < 0",
            (
                "the condition 'range.distance_cm < 0' can never be true: a distance sensor reads 0"
                " or more, never below 0"
            ),
            "compare with a distance it can read, e.g. range.distance_cm < 20",
        ),
        (
            "range.distance_cm < 20 and range.distance_cm > 30",
            (
                "the condition 'range.distance_cm < 20 and range.distance_cm > 30' can never be"
                " true: range.distance_cm is never below 20 and above 30 at once"
            ),
            "to go when either holds, write or: range.distance_cm < 20 or range.distance_cm > 30",
        ),
        (
            "20 < range.distance_cm < 10",
            (
                "the condition '20 < range.distance_cm < 10' can never be true:"
                " range.distance_cm is never below 10 and above 20 at once"
            ),
            None,
        ),
        (
            "range.distance_cm > 20 cm and range.distance_cm < 10 cm",
            (
                "the condition 'range.distance_cm > 20 cm and range.distance_cm < 10 cm' can"
                " never be true: range.distance_cm is never below 10 and above 20 at once"
            ),
            (
                "to go when either holds, write or: range.distance_cm > 20 cm or"
                " range.distance_cm < 10 cm"
            ),
        ),
        (
            "range.distance_cm > 200 mm and range.distance_cm < 10",
            (
                "the condition 'range.distance_cm > 200 mm and range.distance_cm < 10' can"
                " never be true: range.distance_cm is never below 10 and above 20 at once"
            ),
            (
                "to go when either holds, write or: range.distance_cm > 200 mm or"
                " range.distance_cm < 10"
            ),
        ),
        (
            "range.distance_cm < -5 cm",
            (
                "the condition 'range.distance_cm < -5 cm' can never be true: a distance sensor"
                " reads 0 or more, never below -5"
            ),
            "compare with a distance it can read, e.g. range.distance_cm < 20",
        ),
        (
            "elapsed > 2 min and elapsed < 100 s",
            (
                "the condition 'elapsed > 2 min and elapsed < 100 s' can never be true: elapsed"
                " is never below 100 and above 120 at once"
            ),
            "to go when either holds, write or: elapsed > 2 min or elapsed < 100 s",
        ),
    ],
)
def test_a_condition_no_reading_can_make_true_is_refused_with_what_was_meant(
    source: str, message: str, hint: str | None
) -> None:
    with pytest.raises(GuardError) as info:
        compile_guard(source, truth=True)
    assert (str(info.value), info.value.hint) == (message, hint)


@pytest.mark.parametrize(
    "source",
    [
        "range.distance_cm < 20 or range.distance_cm > 30",
        "range.distance_cm > 20 and range.distance_cm < 30",
        "range.distance_cm >= 20 and range.distance_cm <= 20",
        "range.distance_cm <= 0",
        "heading_deg < 0",
    ],
)
def test_a_condition_some_reading_makes_true_is_kept(source: str) -> None:
    compile_guard(source, truth=True)


@pytest.mark.parametrize("word", ["time", "timer", "seconds", "Time"])
def test_a_condition_reading_the_time_by_another_word_is_told_its_two_clocks(word: str) -> None:
    with pytest.raises(GuardError) as info:
        compile_guard(f"{word} > 5", truth=True)
    assert str(info.value) == f"unknown name '{word}' in a condition: a condition reads two clocks"
    assert info.value.hint == (
        "write elapsed, the seconds since the mission started, or state_time, the seconds since"
        " this state began: e.g. state_time > 5"
    )
    assert info.value.offset == 0


def test_check_refuses_a_condition_never_true_written_with_units_at_its_column(
    tmp_path: Path,
) -> None:
    mission = tmp_path / "m.yaml"
    mission.write_text(
        "mission: m\ninitial: go\nstates:\n  go:\n    do: {drive: {distance: 1 m}}\n"
        '    when:\n      - {if: "range.distance_cm > 30 cm and range.distance_cm < 10 cm",'
        " goto: end}\n    on: {done: end}\n  end: {final: success}\n",
        encoding="utf-8",
    )
    done = run_cli("check", "m.yaml", cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr.startswith(
        "m.yaml:7:45: error: the condition 'range.distance_cm > 30 cm and range.distance_cm <"
        " 10 cm' can never be true: range.distance_cm is never below 10 and above 30 at once"
    ), done.stderr
