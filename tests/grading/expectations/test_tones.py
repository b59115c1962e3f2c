"""``tones``: how many tones, and which frequencies."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import _judge, _mistake, _north, _params, _record, _tones

from roboscript.grading.expectations import Tones
from roboscript.grading.record import Verdict


def test_tone_count_too_many_fails_when_the_extra_one_plays() -> None:
    played = _tones((1.0, 880), (2.0, 880), (3.0, 880))
    verdict = _judge(Tones(count=2), _record(_north(5.0), tones=played))
    assert not verdict.passed
    assert verdict.first_violation_s == 3.0
    assert verdict.margin == "failed by 1 tone"


def test_tone_count_too_few_has_no_moment() -> None:
    verdict = _judge(Tones(count=4), _record(_north(5.0), tones=_tones((1.0, 880))))
    assert not verdict.passed
    assert verdict.first_violation_s is None
    assert verdict.margin == "failed by 3 tones"
    assert verdict.detail.startswith("3 tones too few")


def test_tone_frequencies_in_order_within_tolerance() -> None:
    played = _tones((1.0, 440), (2.0, 882), (3.0, 660))
    record = _record(_north(5.0), tones=played)
    assert _judge(Tones(frequencies_hz=(440.0, 880.0, 660.0)), record).passed
    wrong = _judge(Tones(frequencies_hz=(440.0, 660.0, 880.0)), record)
    assert not wrong.passed
    assert wrong.first_violation_s == 2.0
    assert wrong.margin == "failed by 222 Hz"
    assert "tone 2 was 882 Hz, expected 660 Hz" in wrong.detail


def test_tone_min_and_max_count() -> None:
    record = _record(_north(5.0), tones=_tones((1.0, 880), (2.0, 880)))
    assert _judge(Tones(min_count=1, max_count=3), record).passed
    assert not _judge(Tones(min_count=3), record).passed


@pytest.mark.parametrize(
    ("expect", "tones"),
    [
        ("tones: {count: 3}", Tones(count=3)),
        ("tones: {min_count: 1, max_count: 4}", Tones(min_count=1, max_count=4)),
        (
            "tones: {frequencies: [440 Hz, 0.66 kHz, 880]}",
            Tones(frequencies_hz=(440.0, 660.0, 880.0)),
        ),
        (
            "tones: {count: 2, frequencies: [440, 660]}",
            Tones(count=2, frequencies_hz=(440.0, 660.0)),
        ),
        (
            "tones: {frequency: 523 Hz, tolerance: 10 Hz}",
            Tones(frequency_hz=523.0, tolerance_hz=10.0),
        ),
    ],
)
def test_tones_read_with_units(tmp_path: Path, expect: str, tones: Tones) -> None:
    assert _params(tmp_path, expect) == tones


def test_the_tone_tolerance_defaults_to_5_hz(tmp_path: Path) -> None:
    tones = _params(tmp_path, "tones: {frequency: 440 Hz}")
    assert isinstance(tones, Tones)
    assert tones.tolerance_hz == 5.0
    assert (tones.count, tones.min_count, tones.max_count, tones.frequencies_hz) == (
        None,
        None,
        None,
        None,
    )


@pytest.mark.parametrize(
    ("expect", "error"),
    [
        ("tones: {}", "4:12: error: tones needs at least one of: count, min_count, max_count, ..."),
        (
            "tones: {count: 2, max_count: 3}",
            "4:13: error: give either count or min_count/max_count, not both",
        ),
        (
            "tones: {count: 2, min_count: 1}",
            "4:13: error: give either count or min_count/max_count, not both",
        ),
        (
            "tones: {frequencies: [440], frequency: 440}",
            "4:33: error: give either frequencies (a list, in order) or frequency (every tone)",
        ),
        ("tones: {min_count: 3, max_count: 2}", "4:13: error: min_count is more than max_count"),
        ("tones: {frequencies: []}", "4:26: error: frequencies lists at least one"),
        (
            "tones: {count: 3, frequencies: [440, 660]}",
            "4:13: error: count is 3 but frequencies lists 2",
        ),
        (
            "tones: {frequencies: [440, 5 cm]}",
            "4:32: error: 'cm' is a unit of distance, but this is a frequency (use hz, khz)",
        ),
        ("tones: {frequency: -440 Hz}", "4:24: error: 'frequency' must be more than 0"),
        ("tones: {count: 1, tolerance: 0 Hz}", "4:34: error: 'tolerance' must be more than 0"),
        ("tones: {cuont: 1}", "4:13: error: unknown key 'cuont' in tones (did you mean 'count'?)"),
        ("tones: 3", "4:12: error: tones must be a mapping"),
        ("tones: {frequencies: 440}", "4:26: error: frequencies must be a list"),
    ],
)
def test_mistakes_in_tones_are_located(tmp_path: Path, expect: str, error: str) -> None:
    assert _mistake(tmp_path, expect).startswith(error)


def test_a_silent_robot_can_be_asked_for(tmp_path: Path) -> None:
    assert _params(tmp_path, "tones: {max_count: 0}") == Tones(max_count=0)


def test_min_count_may_equal_max_count(tmp_path: Path) -> None:
    assert _params(tmp_path, "tones: {min_count: 2, max_count: 2}") == Tones(
        min_count=2, max_count=2
    )


@pytest.mark.parametrize(("frequency", "passed"), [(445.0, True), (435.0, True), (445.5, False)])
def test_the_tone_tolerance_is_inclusive(frequency: float, passed: bool) -> None:
    record = _record(_north(3.0), tones=_tones((1.0, frequency)))
    verdict = _judge(Tones(frequency_hz=440.0, tolerance_hz=5.0), record)
    assert verdict.passed is passed


def test_a_passing_tone_verdict_lists_what_was_heard() -> None:
    record = _record(_north(3.0), tones=_tones((1.0, 440), (2.0, 660)))
    assert _judge(Tones(count=2), record) == Verdict(
        "tones", True, "", None, "2 tones played (440 Hz, 660 Hz)"
    )


def test_a_long_tune_lists_its_first_eight_tones() -> None:
    played = _tones(*((float(i), 400.0 + i) for i in range(1, 10)))
    verdict = _judge(Tones(min_count=1), _record(_north(10.0), tones=played))
    heard = ", ".join(f"{400 + i} Hz" for i in range(1, 9))
    assert verdict.detail == f"9 tones played ({heard} ...)"
    eight = _judge(Tones(min_count=1), _record(_north(10.0), tones=played[:8]))
    assert eight.detail == f"8 tones played ({heard})"


def test_no_tone_at_all_says_so_without_a_list() -> None:
    verdict = _judge(Tones(count=1), _record(_north(3.0)))
    assert verdict.detail == "1 tone too few: 0 tones played"


def test_a_wrong_frequency_fails_by_its_distance_in_hertz() -> None:
    record = _record(_north(3.0), tones=_tones((1.0, 440), (2.0, 700)))
    verdict = _judge(Tones(frequencies_hz=(440.0, 660.0)), record)
    assert verdict == Verdict(
        "tones",
        False,
        "failed by 40 Hz",
        2.0,
        "tone 2 was 700 Hz, expected 660 Hz: 2 tones played (440 Hz, 700 Hz)",
        -40.0,
        "Hz",
    )


def test_a_list_of_frequencies_also_wants_that_many_tones() -> None:
    wanted = Tones(frequencies_hz=(440.0, 660.0))
    three = _record(_north(5.0), tones=_tones((1.0, 440), (2.0, 660), (3.0, 660)))
    extra = _judge(wanted, three)
    assert not extra.passed
    assert (extra.margin, extra.first_violation_s) == ("failed by 1 tone", 3.0)
    assert extra.detail.startswith("1 tone too many: ")
    assert (extra.margin_value, extra.margin_unit) == (-1, "tones")
    one = _judge(wanted, _record(_north(5.0), tones=_tones((1.0, 440))))
    assert not one.passed
    assert one.detail.startswith("1 tone too few: ")


def test_an_explicit_count_wins_over_the_length_of_the_list() -> None:
    record = _record(_north(5.0), tones=_tones((1.0, 440)))
    assert _judge(Tones(count=1, frequencies_hz=(440.0, 660.0)), record).passed


def test_the_first_problem_in_time_is_reported_before_one_only_known_at_the_end() -> None:
    # two wanted, one wrong at 2 s, and one missing (known only at the end)
    record = _record(_north(5.0), tones=_tones((1.0, 440), (2.0, 700)))
    verdict = _judge(Tones(frequencies_hz=(440.0, 660.0, 880.0)), record)
    assert verdict.detail.startswith("tone 2 was 700 Hz, expected 660 Hz")
    assert verdict.first_violation_s == 2.0


def test_too_many_tones_over_a_maximum_fail_when_the_extra_one_plays() -> None:
    record = _record(_north(5.0), tones=_tones((1.0, 440), (2.0, 440), (3.0, 440), (4.0, 440)))
    verdict = _judge(Tones(max_count=2), record)
    assert not verdict.passed
    assert verdict.first_violation_s == 3.0
    assert verdict.detail.startswith("2 tones too many: ")
