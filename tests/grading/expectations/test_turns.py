"""``turns``: what counts as one turn, and how turns are judged."""

from __future__ import annotations

import pytest
from grading.expectations.runs import (
    DRIFT,
    FOUR_RIGHT,
    NO_PATH,
    RIGHT_90_FROM_EAST,
    Samples,
    _judge,
    _left_turns,
    _north,
    _record,
    _same,
    _spin,
    _spin_in_place,
    _square,
    _verdict,
)

from roboscript.grading.expectations import (
    Turns,
    find_turns,
)
from roboscript.grading.record import RunRecord, Verdict


def test_turns_are_found_with_their_direction() -> None:
    turns = find_turns(_square())
    assert [(t.start_s, t.angle_deg) for t in turns] == [
        (5.5, 90.0),
        (12.5, 90.0),
        (19.5, 90.0),
        (26.5, 90.0),
    ]
    assert [t.direction for t in turns] == ["right"] * 4
    # Left turns, recorded as 351, 342, ... from north, are negative, not +351.
    assert [t.angle_deg for t in find_turns(_square(-90.0))] == [-90.0] * 4


def test_a_right_turn_through_north_is_not_a_left_turn() -> None:
    headings = [350.0, 355.0, 0.0, 5.0, 10.0, 10.0, 10.0, 10.0]
    path = [(round(i * 0.1, 3), 0.0, 0.0, h) for i, h in enumerate(headings)]
    assert [t.angle_deg for t in find_turns(path)] == [20.0]


def test_turns_direction_fails_at_the_first_wrong_turn() -> None:
    rule = Turns(direction="right", count=4, angle_deg=90.0)
    assert _judge(rule, _record(_square())).passed
    verdict = _judge(rule, _record(_square(-90.0)))
    assert not verdict.passed
    assert verdict.first_violation_s == 5.5
    assert verdict.margin == "failed by 90.0°"
    assert verdict.detail.startswith(
        "turned 90° left at 5.5 s; this test wants right turns only; 4 turns (90° left at 5.5 s,"
    )
    assert _judge(Turns(direction="left"), _record(_square(-90.0))).passed


def test_turns_count_too_many_fails_when_the_extra_turn_starts() -> None:
    verdict = _judge(Turns(count=3), _record(_square()))
    assert not verdict.passed
    assert verdict.first_violation_s == 26.5  # the fourth turn starts
    assert verdict.margin == "failed by 1 turn"
    few = _judge(Turns(count=5), _record(_square()))
    assert not few.passed
    assert few.first_violation_s is None
    assert few.detail.startswith("4 turns, expected 5")


def test_turns_angle_tolerance_is_inclusive() -> None:
    record = _record(_square(100.0))
    assert _judge(Turns(angle_deg=90.0, tolerance_deg=10.0), record).passed
    verdict = _judge(Turns(angle_deg=89.5, tolerance_deg=10.0), record)
    assert not verdict.passed
    assert verdict.margin == "failed by 0.5°"
    assert verdict.first_violation_s == 6.6  # the end of the first turn
    assert verdict.detail.startswith("turn 1 was 100° right at 5.5 s, expected 89.5° ± 10°")


def test_turns_total_counts_whole_turns_and_their_direction() -> None:
    assert _judge(Turns(direction="right", total_deg=360.0), _record(_square())).passed
    left = _judge(Turns(direction="right", total_deg=360.0), _record(_square(-90.0)))
    assert not left.passed
    spun = _judge(Turns(total_deg=360.0), _record(_square(-90.0)))
    assert spun.passed  # no direction asked: 360° either way
    three = _judge(Turns(total_deg=360.0), _record(_square(sides=3)))
    assert not three.passed
    assert three.margin == "failed by 70.0°"
    assert three.first_violation_s == 21.0  # the end of the run


def test_rotations_the_same_way_with_no_travel_between_are_one_turn() -> None:
    # Two 45° rotations at 90°/s on the spot, 0.1 s or 0.3 s (a beep) apart: one 90° corner
    # either way, so a run's corners are counted alike however long each pause happened to be.
    half = [9.0 * i for i in range(6)]  # 0 to 45 in 0.5 s
    short = _spin_in_place([*half, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0, 90.0])
    beep = _spin_in_place(
        [*half, 45.0, 45.0, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0, 90.0]
    )
    assert [t.angle_deg for t in find_turns(short)] == [90.0]
    assert [(t.start_s, t.end_s, t.angle_deg) for t in find_turns(beep)] == [(0.0, 1.3, 90.0)]
    # Back the other way on the spot is a turn of its own.
    back = _spin_in_place([*half, 45.0, 45.0, 45.0, *(45.0 - h for h in half[1:]), 0.0, 0.0])
    assert [t.angle_deg for t in find_turns(back)] == [45.0, -45.0]


def test_a_wobble_is_not_a_turn() -> None:
    # Driving north, a 5° correction left and back: no turns, so "right only" still holds.
    headings = [0, 0, 355, 355, 0, 0, 0] + [0] * 5
    path = [(round(i * 0.1, 3), 0.0, i * 10.0, float(h)) for i, h in enumerate(headings)]
    assert find_turns(path) == []
    path += _square(start=(0.0, 110.0, 0.0))[1:]
    path = [(round(i * 0.1, 3), x, y, h) for i, (_, x, y, h) in enumerate(path)]
    assert _judge(Turns(direction="right", count=4), _record(path)).passed


def test_turns_never_turning_fails() -> None:
    verdict = _judge(Turns(direction="right"), _record(_north(5.0)))
    assert not verdict.passed
    assert verdict.detail == "the robot never turned"


def test_a_10_degree_turn_is_a_turn_but_9_5_degrees_is_a_wobble() -> None:
    assert [t.angle_deg for t in find_turns(_spin([0.0, 5.0, 10.0, 10.0, 10.0]))] == [10.0]
    assert find_turns(_spin([0.0, 4.75, 9.5, 9.5, 9.5])) == []


def test_turning_at_3_deg_s_is_turning_but_slower_is_drifting() -> None:
    slow = _spin([1.5 * i for i in range(21)] + [30.0] * 3, dt_s=0.5)  # 3 deg/s for 10 s
    assert [(t.start_s, t.end_s, t.angle_deg) for t in find_turns(slow)] == [(0.0, 10.0, 30.0)]
    slower = _spin([1.4 * i for i in range(21)] + [28.0] * 3, dt_s=0.5)
    assert find_turns(slower) == []


def test_a_pause_of_0_2_s_with_travel_splits_a_turn_in_two() -> None:
    half = [9.0 * i for i in range(6)]  # 0 to 45 in 0.5 s
    paused = _spin([*half, 45.0, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0])
    assert [(t.start_s, t.angle_deg) for t in find_turns(paused)] == [(0.0, 45.0), (0.7, 45.0)]
    # Without the travel, the same pause leaves one turn.
    still = _spin([*half, 45.0, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0], creep_mm=0.0)
    assert [(t.start_s, t.angle_deg) for t in find_turns(still)] == [(0.0, 90.0)]


@pytest.mark.parametrize(("travel_mm", "turns"), [(19.9, [90.0]), (20.0, [45.0, 45.0])])
def test_turns_the_same_way_less_than_2_cm_apart_are_one_turn(
    travel_mm: float, turns: list[float]
) -> None:
    half = [9.0 * i for i in range(6)]  # 0 to 45 in 0.5 s
    headings = [*half, 45.0, 45.0, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0]
    path = _spin(headings, creep_mm=travel_mm / 3)  # three creeps between the turns
    assert [t.angle_deg for t in find_turns(path)] == turns


def test_a_total_to_the_left_is_judged_with_its_direction() -> None:
    record = _record(_left_turns(4))
    assert _judge(Turns(direction="left", total_deg=360.0), record).passed
    half = _judge(Turns(direction="left", total_deg=180.0), record)
    assert not half.passed
    assert half.detail.startswith("turned 360° left in all, expected 180° left ± 20°")
    assert half.margin == "failed by 160.0°"


def test_a_total_passes_up_to_its_tolerance_with_its_share_as_the_margin() -> None:
    record = _record(_left_turns(4))
    edge = _judge(Turns(total_deg=340.0), record)
    assert edge.passed
    assert (edge.margin_value, edge.margin_unit, edge.relative_margin) == (0.0, "deg", 0.0)
    assert edge.detail == (
        "4 turns (90° left at 0.0 s, 90° left at 2.0 s, 90° left at 4.0 s, 90° left at 6.0 s),"
        " 360° left in all"
    )
    assert edge.first_violation_s is None
    room = _judge(Turns(total_deg=350.0), record)
    assert room.relative_margin == pytest.approx(10.0 / 20.0)


def test_too_few_turns_fail_by_the_turns_missing() -> None:
    few = _judge(Turns(count=6), _record(_left_turns(4)))
    assert (few.passed, few.margin, few.margin_value, few.margin_unit) == (
        False,
        "failed by 2 turns",
        -2.0,
        "turns",
    )
    assert few.first_violation_s is None


def test_a_long_list_of_turns_shows_the_first_six() -> None:
    verdict = _judge(Turns(count=7), _record(_left_turns(7)))
    assert verdict.passed
    assert verdict.detail.startswith("7 turns (90° left at 0.0 s, ")
    assert verdict.detail.endswith("90° left at 10.0 s ...), 630° left in all")
    six = _judge(Turns(count=6), _record(_left_turns(6)))
    assert "90° left at 10.0 s), 540° left in all" in six.detail


@pytest.mark.parametrize(
    ("rule", "record", "wanted"),
    [
        pytest.param(
            Turns(count=0),
            NO_PATH,
            _verdict("turns", True, detail="0 turns, 0° right in all"),
            id="no path: no turns, and nothing turned",
        ),
        pytest.param(
            Turns(angle_deg=90.0),
            _record(_north(2.0)),
            _verdict("turns", False, detail="the robot never turned"),
            id="an angle with no turn at all",
        ),
        pytest.param(
            Turns(direction="right", total_deg=90.0),
            _record(_spin(RIGHT_90_FROM_EAST)),
            _verdict(
                "turns",
                True,
                "passed by 20.0°",
                detail="1 turn (90° right at 0.2 s), 90° right in all",
                value=20.0,
                unit="deg",
                relative=1.0,
            ),
            id="the total is counted from the start heading, not from north",
        ),
        pytest.param(
            Turns(total_deg=95.0),
            _record(_spin([*RIGHT_90_FROM_EAST, 185.0])),
            _verdict(
                "turns",
                True,
                "passed by 20.0°",
                detail="1 turn (90° right at 0.2 s), 95° right in all",
                value=20.0,
                unit="deg",
                relative=1.0,
            ),
            id="the total runs to the very last sample",
        ),
        pytest.param(
            Turns(angle_deg=90.0, tolerance_deg=20.0),
            _record(
                _spin(
                    [10.0 * i for i in range(11)]
                    + [100.0] * 5
                    + [100.0 + 9.0 * i for i in range(1, 11)]
                    + [190.0] * 5
                )
            ),
            _verdict(
                "turns",
                True,
                "passed by 10.0°",
                detail="2 turns (100° right at 0.0 s, 90° right at 1.5 s), 190° right in all",
                value=10.0,
                unit="deg",
                relative=0.5,
            ),
            id="the margin is the worst turn's, even when it is not the last",
        ),
        pytest.param(
            Turns(angle_deg=90.0, tolerance_deg=20.0),
            _record(
                _spin(
                    [11.0 * i for i in range(11)]
                    + [110.0] * 5
                    + [110.0 + 11.5 * i for i in range(1, 11)]
                    + [225.0] * 5
                )
            ),
            _verdict(
                "turns",
                False,
                "failed by 5.0°",
                2.5,
                "turn 2 was 115° right at 1.5 s, expected 90° ± 20°; 2 turns (110° right at"
                " 0.0 s, 115° right at 1.5 s), 225° right in all",
                -5.0,
                "deg",
                -0.25,
            ),
            id="a turn exactly at the tolerance is not the one named",
        ),
        pytest.param(
            Turns(direction="right", total_deg=90.0),
            _record(_spin(DRIFT)),
            _verdict(
                "turns",
                False,
                "failed by 180.0°",
                101.6,
                "turned 110° left in all, expected 90° right ± 20°; 1 turn (90° right at"
                " 0.0 s), 110° left in all",
                -180.0,
                "deg",
                -9.0,
            ),
            id="a slow drift the other way counts in a total to the right",
        ),
        pytest.param(
            Turns(direction="left", total_deg=90.0),
            _record(_spin([-h for h in DRIFT])),
            _verdict(
                "turns",
                False,
                "failed by 180.0°",
                101.6,
                "turned 110° right in all, expected 90° left ± 20°; 1 turn (90° left at"
                " 0.0 s), 110° right in all",
                -180.0,
                "deg",
                -9.0,
            ),
            id="the same to the left",
        ),
        pytest.param(
            Turns(total_deg=180.0),
            _record(_square()),
            _verdict(
                "turns",
                False,
                "failed by 160.0°",
                28.0,
                f"turned 360° right in all, expected 180° ± 20°; {FOUR_RIGHT}, 360° right in all",
                -160.0,
                "deg",
                -8.0,
            ),
            id="a total with no direction names none",
        ),
        pytest.param(
            Turns(direction="right"),
            _record(_square()),
            _verdict("turns", True, detail=f"{FOUR_RIGHT}, 360° right in all"),
            id="a direction alone has no margin",
        ),
        pytest.param(
            Turns(angle_deg=90.0, total_deg=350.0),
            _record(_square()),
            _verdict(
                "turns",
                True,
                "passed by 10.0°",
                detail=f"{FOUR_RIGHT}, 360° right in all",
                value=10.0,
                unit="deg",
                relative=0.5,
            ),
            id="the tighter of angle and total gives the margin",
        ),
        pytest.param(
            Turns(count=4, direction="right"),
            _record(_square(-90.0)),
            _verdict(
                "turns",
                False,
                "failed by 90.0°",
                5.5,
                "turned 90° left at 5.5 s; this test wants right turns only; 4 turns (90° left"
                " at 5.5 s, 90° left at 12.5 s, 90° left at 19.5 s, 90° left at 26.5 s),"
                " 360° left in all",
                -90.0,
                "deg",
            ),
            id="the wrong way fails in degrees",
        ),
        pytest.param(
            Turns(count=3),
            _record(_square()),
            _verdict(
                "turns",
                False,
                "failed by 1 turn",
                26.5,
                f"4 turns, expected 3; {FOUR_RIGHT}, 360° right in all",
                -1.0,
                "turns",
            ),
            id="one turn too many",
        ),
        pytest.param(
            Turns(total_deg=10.0, tolerance_deg=10.0),
            _record(_spin([0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5])),
            _verdict(
                "turns",
                True,
                "passed by 0.5°",
                detail="0 turns, 0° right in all",
                value=0.5,
                unit="deg",
                relative=0.05,
            ),
            id="half a degree to the right is to the right",
        ),
    ],
)
def test_turns_verdicts(rule: Turns, record: RunRecord, wanted: Verdict) -> None:
    _same(_judge(rule, record), wanted)


def test_a_drift_of_under_a_degree_to_the_left_is_to_the_left() -> None:
    record = _record(_spin([0.0, 0.0, 0.0, -0.1, -0.2, -0.3, -0.4, -0.5]))
    verdict = _judge(Turns(total_deg=10.0), record)
    assert verdict.detail == "0 turns, 0° left in all"


@pytest.mark.parametrize(
    ("path", "wanted"),
    [
        (
            _north(2.0),
            _verdict(
                "turns",
                False,
                "failed by 70.0°",
                2.0,
                "turned 0° right in all, expected 90° ± 20°",
                -70.0,
                "deg",
                -3.5,
            ),
        ),
        (
            _spin([0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5]),
            _verdict(
                "turns",
                False,
                "failed by 69.5°",
                0.7,
                "turned 0° right in all, expected 90° ± 20°",
                -69.5,
                "deg",
                -3.475,
            ),
        ),
    ],
)
def test_a_total_never_reached_says_which_way_the_robot_went(
    path: Samples, wanted: Verdict
) -> None:
    _same(_judge(Turns(total_deg=90.0), _record(path)), wanted)


def test_a_turn_angle_is_kept_to_a_tenth_of_a_degree() -> None:
    turns = find_turns(_spin([0.0, 15.09, 30.18, 45.27, 45.27, 45.27, 45.27]))
    assert [t.angle_deg for t in turns] == [45.3]


def test_two_samples_at_the_same_time_do_not_break_the_turns() -> None:
    path = _spin([0.0, 9.0, 18.0, 27.0, 36.0, 45.0, 45.0, 45.0, 45.0])
    path.insert(3, (path[2][0], 0.0, 0.0, 22.0))  # a sample repeated at 0.2 s
    assert [(t.start_s, t.end_s, t.angle_deg) for t in find_turns(path)] == [(0.0, 0.5, 45.0)]
