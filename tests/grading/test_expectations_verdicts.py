"""Whole verdicts of turns, path_visits, regions_in_order and wall_ahead_at_end, as a student
reads them in a report: pass or fail, the margin in words and as a number, when it failed,
and the sentence. Each field is compared, so a verdict that says "passed" with the wrong
margin, or the right margin in the wrong unit, fails here.

The records are hand-made (the helpers of test_expectations.py).
"""

from __future__ import annotations

from dataclasses import replace

import pytest
from grading.test_expectations import SQUARE, _north, _record, _square, _stopped

from roboscript.grading.expectations import (
    Expectation,
    FinalPose,
    MaxDuration,
    Outcome,
    PathVisits,
    RegionsInOrder,
    Rule,
    RunTargets,
    Turns,
    WallAhead,
    Waypoint,
    evaluate,
    final_pose_target,
    find_turns,
)
from roboscript.grading.record import RunRecord, Verdict

Path = list[tuple[float, float, float, float]]


def _spin(headings: list[float]) -> Path:
    """Turning on the spot through ``headings``, one sample every 0.1 s; between samples with
    the same heading the robot creeps 5 cm east, so turns a pause apart are driven apart."""
    path = []
    x = 0.0
    for i, h in enumerate(headings):
        if i and h == headings[i - 1]:
            x += 50.0
        path.append((round(i * 0.1, 3), x, 0.0, h % 360.0))
    return path


def _verdict(
    name: str,
    passed: bool,
    margin: str = "",
    first_violation_s: float | None = None,
    detail: str = "",
    value: float | None = None,
    unit: str = "",
    relative: float | None = None,
) -> Verdict:
    return Verdict(name, passed, margin, first_violation_s, detail, value, unit, relative)


def _judge(rule: Rule, record: RunRecord) -> Verdict:
    return evaluate(Expectation(rule), record)


def _same(got: Verdict, wanted: Verdict) -> None:
    assert replace(got, relative_margin=None) == replace(wanted, relative_margin=None)
    if wanted.relative_margin is None:
        assert got.relative_margin is None
    else:
        assert got.relative_margin == pytest.approx(wanted.relative_margin)


NO_PATH = replace(_record(_north(1.0)), path=())
RIGHT_90_FROM_EAST = [90.0] * 3 + [90.0 + 9.0 * i for i in range(1, 11)] + [180.0] * 4
"""Facing east, a 90° right turn at 90°/s starting at 0.2 s, then still."""
FOUR_RIGHT = (
    "4 turns (90° right at 5.5 s, 90° right at 12.5 s, 90° right at 19.5 s, 90° right at 26.5 s)"
)
# One fast 90° right turn, then a slow drift of 200° to the left at 2°/s: too slow to be a
# turn, but the heading changed all the same.
DRIFT = [0.0, *(9.0 * i for i in range(1, 11)), 90.0, 90.0, 90.0]
DRIFT += [90.0 - 0.2 * i for i in range(1, 1001)] + [-110.0] * 3


# ------------------------------------------------------------------------------- turns


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


# ---------------------------------------------------------------------- wall ahead at end

WANTED = "measured from the front of the robot straight ahead; wanted"


@pytest.mark.parametrize(
    ("rule", "record", "wanted"),
    [
        pytest.param(
            WallAhead(200.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                True,
                "passed by 3.0 cm",
                None,
                f"stopped 20.0 cm from the wall ahead, {WANTED} 20.0 cm ± 3.0 cm",
                30.0,
                "mm",
                1.0,
            ),
            id="right on the distance",
        ),
        pytest.param(
            WallAhead(300.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 7.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too close), {WANTED} 30.0 cm ± 3.0 cm",
                -70.0,
                "mm",
                -70.0 / 30.0,
            ),
            id="too close",
        ),
        pytest.param(
            WallAhead(100.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 7.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too far), {WANTED} 10.0 cm ± 3.0 cm",
                -70.0,
                "mm",
                -70.0 / 30.0,
            ),
            id="too far",
        ),
        pytest.param(
            WallAhead(170.0, 30.0),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                True,
                "passed by 0.0 cm",
                None,
                f"stopped 20.0 cm from the wall ahead, {WANTED} 17.0 cm ± 3.0 cm",
                0.0,
                "mm",
                0.0,
            ),
            id="the edge of the tolerance passes",
        ),
        pytest.param(
            WallAhead(199.5, 0.2),
            _stopped(0.0, 500.0, 90.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "failed by 0.0 cm",
                5.0,
                f"stopped 20.0 cm from the wall ahead (too far), {WANTED} 19.9 cm ± 0.0 cm",
                pytest.approx(-0.3),  # type: ignore[arg-type]
                "mm",
                -1.5,
            ),
            id="half a millimetre too far is too far",
        ),
        pytest.param(
            WallAhead(200.0, 30.0),
            replace(_stopped(0.0, 500.0, 90.0), world=None),
            _verdict(
                "wall_ahead_at_end",
                False,
                "",
                5.0,
                "no wall straight ahead when the robot stopped (facing 90°);"
                " wanted 20.0 cm ± 3.0 cm",
            ),
            id="a record without a world has no wall",
        ),
        pytest.param(
            WallAhead(200.0, 30.0),
            _stopped(0.0, 500.0, 0.0),
            _verdict(
                "wall_ahead_at_end",
                False,
                "",
                5.0,
                "no wall straight ahead when the robot stopped (facing 0°);"
                " wanted 20.0 cm ± 3.0 cm",
            ),
            id="facing down the corridor",
        ),
    ],
)
def test_wall_ahead_verdicts(rule: WallAhead, record: RunRecord, wanted: Verdict) -> None:
    _same(_judge(rule, record), wanted)


# ----------------------------------------------------------------------- regions in order


@pytest.mark.parametrize(
    ("names", "record", "wanted"),
    [
        pytest.param(
            ("a", "b"),
            _record(_north(12.0)),
            _verdict("regions_in_order", True, detail="reached 'a' at 4.0 s, 'b' at 9.0 s"),
            id="both, in order",
        ),
        pytest.param(
            ("b", "a"),
            _record(_north(12.0)),
            _verdict(
                "regions_in_order",
                False,
                "failed by 31.0 cm",
                None,
                "never reached 'a' after 'b' at 9.0 s; the closest it came was 31.0 cm from its"
                " edge",
                -310.0,
                "mm",
            ),
            id="out of order: measured after the last one reached",
        ),
        pytest.param(
            ("a", "b"),
            _record(_north(8.0)),
            _verdict(
                "regions_in_order",
                False,
                "failed by 10.0 cm",
                None,
                "never reached 'b' after 'a' at 4.0 s; the closest it came was 10.0 cm from its"
                " edge",
                -100.0,
                "mm",
            ),
            id="stopped short",
        ),
        pytest.param(
            ("a", "b"),
            _record(_north(4.0)),
            _verdict("regions_in_order", False, detail="never reached 'b' after 'a' at 4.0 s"),
            id="the run ended as it reached the first: nothing to measure",
        ),
        pytest.param(
            ("a", "b"),
            replace(_record(_north(1.0)), path=()),
            _verdict("regions_in_order", False, detail="never reached 'a'"),
            id="no path",
        ),
    ],
)
def test_regions_in_order_verdicts(
    names: tuple[str, ...], record: RunRecord, wanted: Verdict
) -> None:
    _same(_judge(RegionsInOrder(names), record), wanted)


# ---------------------------------------------------------------------------- path visits

AHEAD = [Waypoint(500.0, 0.0), Waypoint(1500.0, 0.0), Waypoint(2000.0, 0.0)]


@pytest.mark.parametrize(
    ("rule", "record", "wanted"),
    [
        pytest.param(
            SQUARE,
            NO_PATH,
            _verdict("path_visits", False, detail="the run has no path"),
            id="no path",
        ),
        pytest.param(
            SQUARE,
            _record(_square()),
            _verdict(
                "path_visits",
                True,
                "passed by 4.0 cm",
                None,
                "reached all 4 waypoints in order (4.6 s, 11.6 s, 18.6 s, 25.6 s); the farthest"
                " off was waypoint 1 (50 cm forward), 0.0 cm away (allowed 4.0 cm)",
                40.0,
                "mm",
                1.0,
            ),
            id="a square",
        ),
        pytest.param(
            PathVisits((Waypoint(500.0, 0.0),), 40.0),
            _record(_north(10.0)),
            _verdict(
                "path_visits",
                True,
                "passed by 4.0 cm",
                None,
                "came within 0.0 cm of waypoint 1 (50 cm forward) at 5.0 s (allowed 4.0 cm)",
                40.0,
                "mm",
                1.0,
            ),
            id="one waypoint",
        ),
        pytest.param(
            PathVisits(tuple(AHEAD), 40.0),
            _record(_north(10.0)),
            _verdict(
                "path_visits",
                False,
                "failed by 46.0 cm",
                None,
                "missed waypoint 2 (150 cm forward): the closest the robot came was 50.0 cm, at"
                " 10.0 s (allowed 4.0 cm), after reaching waypoint 1 at 4.6 s",
                -460.0,
                "mm",
                -11.5,
            ),
            id="in order, the first missed ends the search",
        ),
        pytest.param(
            PathVisits((AHEAD[1], AHEAD[0], AHEAD[2]), 40.0, in_order=False),
            _record(_north(10.0)),
            _verdict(
                "path_visits",
                False,
                "failed by 96.0 cm",
                None,
                "missed waypoint 1 (150 cm forward): the closest the robot came was 50.0 cm, at"
                " 10.0 s (allowed 4.0 cm); 2 of 3 waypoints missed",
                -960.0,
                "mm",
                -24.0,
            ),
            id="in any order, every waypoint is looked for",
        ),
        pytest.param(
            PathVisits((AHEAD[0], Waypoint(900.0, 0.0), AHEAD[2]), 40.0),
            _record(_north(10.0)),
            _verdict(
                "path_visits",
                False,
                "failed by 96.0 cm",
                None,
                "missed waypoint 3 (200 cm forward): the closest the robot came was 100.0 cm, at"
                " 10.0 s (allowed 4.0 cm), after reaching waypoints 1 at 4.6 s, 2 at 8.6 s",
                -960.0,
                "mm",
                -24.0,
            ),
            id="the waypoints reached before the miss are listed",
        ),
        pytest.param(
            PathVisits((AHEAD[0], Waypoint(900.0, 0.0)), 40.0, in_order=False),
            _record(_north(10.0)),
            _verdict(
                "path_visits",
                True,
                "passed by 4.0 cm",
                None,
                "reached all 2 waypoints (4.6 s, 8.6 s); the farthest off was waypoint 1 (50 cm"
                " forward), 0.0 cm away (allowed 4.0 cm)",
                40.0,
                "mm",
                1.0,
            ),
            id="in any order, not said to be in order",
        ),
    ],
)
def test_path_visits_verdicts(rule: PathVisits, record: RunRecord, wanted: Verdict) -> None:
    _same(_judge(rule, record), wanted)


def test_the_farthest_waypoint_is_named_when_it_is_not_the_last() -> None:
    waypoints = (Waypoint(300.0, 30.0), Waypoint(600.0, 10.0))
    verdict = _judge(PathVisits(waypoints, 50.0), _record(_north(10.0)))
    assert verdict.margin == "passed by 2.0 cm"
    assert "the farthest off was waypoint 1 (30 cm forward, 3 cm right), 3.0 cm away" in (
        verdict.detail
    )


def test_a_waypoint_passed_twice_is_judged_on_the_visit_that_reached_it() -> None:
    # Out 1 m along x = 0, then back along x = 20: in order, waypoint 2 (50 cm) counts on the
    # way back, from 14.7 s (within 4 cm of it at y = 534.6), not on the way out at 4.6 s.
    out = [(round(i * 0.1, 3), 0.0, i * 10.0, 0.0) for i in range(101)]
    back = [(round(10.0 + i * 0.1, 3), 20.0, 1000.0 - i * 10.0, 180.0) for i in range(1, 101)]
    rule = PathVisits((Waypoint(1000.0, 0.0), Waypoint(500.0, 0.0)), 40.0)
    verdict = _judge(rule, _record(out + back))
    assert verdict.passed
    assert verdict.margin == "passed by 2.0 cm"
    assert verdict.detail == (
        "reached all 2 waypoints in order (9.6 s, 14.7 s); the farthest off was waypoint 2"
        " (50 cm forward), 2.0 cm away (allowed 4.0 cm)"
    )


@pytest.mark.parametrize(
    ("rule", "path", "detail"),
    [
        pytest.param(
            PathVisits((Waypoint(0.0, 0.0),), 40.0),
            _north(10.0),
            "came within 0.0 cm of waypoint 1 (the start) at 0.0 s (allowed 4.0 cm)",
            id="the start is looked for from the first stretch of the path",
        ),
        pytest.param(
            PathVisits((Waypoint(500.0, 0.0),), 40.0),
            _north(5.0),
            "came within 0.0 cm of waypoint 1 (50 cm forward) at 5.0 s (allowed 4.0 cm)",
            id="a visit that lasts to the end of the path counts to its last sample",
        ),
        pytest.param(
            PathVisits((Waypoint(500.0, 0.0),), 40.0),
            [(0.0, 0.0, 0.0, 0.0)]
            + [(round(0.1 * i, 3), 20.0, 10.0 * i, 0.0) for i in range(1, 101)]
            + [(round(10.0 + 0.1 * i, 3), 0.0, 1000.0 - 10.0 * i, 180.0) for i in range(1, 101)],
            "came within 2.0 cm of waypoint 1 (50 cm forward) at 5.0 s (allowed 4.0 cm)",
            id="judged on its first visit, not on a closer one later",
        ),
    ],
)
def test_path_visits_judges_the_visit_that_reached_the_waypoint(
    rule: PathVisits, path: Path, detail: str
) -> None:
    assert _judge(rule, _record(path)).detail == detail


@pytest.mark.parametrize(
    ("rule", "detail"),
    [
        (
            PathVisits((Waypoint(500.0, 0.0), Waypoint(1500.0, 0.0)), 40.0, in_order=False),
            (
                "missed waypoint 2 (150 cm forward): the closest the robot came was 50.0 cm, at"
                " 10.0 s (allowed 4.0 cm)"
            ),
        ),
        (
            PathVisits((Waypoint(-500.0, 0.0), Waypoint(500.0, 0.0)), 40.0),
            (
                "missed waypoint 1 (50 cm back): the closest the robot came was 50.0 cm, at 0.0 s"
                " (allowed 4.0 cm)"
            ),
        ),
    ],
)
def test_a_single_miss_says_nothing_of_other_waypoints(rule: PathVisits, detail: str) -> None:
    assert _judge(rule, _record(_north(10.0))).detail == detail


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
def test_a_total_never_reached_says_which_way_the_robot_went(path: Path, wanted: Verdict) -> None:
    _same(_judge(Turns(total_deg=90.0), _record(path)), wanted)


def test_a_turn_angle_is_kept_to_a_tenth_of_a_degree() -> None:
    turns = find_turns(_spin([0.0, 15.09, 30.18, 45.27, 45.27, 45.27, 45.27]))
    assert [t.angle_deg for t in turns] == [45.3]


def test_two_samples_at_the_same_time_do_not_break_the_turns() -> None:
    path = _spin([0.0, 9.0, 18.0, 27.0, 36.0, 45.0, 45.0, 45.0, 45.0])
    path.insert(3, (path[2][0], 0.0, 0.0, 22.0))  # a sample repeated at 0.2 s
    assert [(t.start_s, t.end_s, t.angle_deg) for t in find_turns(path)] == [(0.0, 0.5, 45.0)]


# --------------------------------------------------------------------- outcome, duration


def test_an_outcome_as_wanted_has_no_moment_of_failure() -> None:
    record = _record(_north(2.0), outcome="success", final_state="done")
    wanted = _verdict("outcome", True, "", None, "the mission ended in success in state 'done'")
    assert _judge(Outcome("success"), record) == wanted


def test_the_outcome_names_the_final_state_when_there_is_no_reason() -> None:
    record = _record(_north(2.0), outcome="failure", final_state="stuck")
    wanted = _verdict("outcome", False, "", 2.0, "the mission ended in failure in state 'stuck'")
    assert _judge(Outcome("success"), record) == wanted


@pytest.mark.parametrize(
    ("limit_s", "margin"), [(6.0, "passed by 1.0 s"), (5.5, "passed by 0.50 s")]
)
def test_a_margin_under_a_second_has_two_decimals(limit_s: float, margin: str) -> None:
    assert _judge(MaxDuration(limit_s), _record(_north(5.0))).margin == margin


def test_regions_need_a_world() -> None:
    record = replace(_record(_north(1.0)), world=None)
    with pytest.raises(ValueError, match=r"^this record has no world to find its regions in$"):
        _judge(RegionsInOrder(("a",)), record)


# ----------------------------------------------------------------------- per-run targets


def test_a_record_gets_the_targets_of_the_run_whose_start_is_nearest() -> None:
    runs = (
        (("room", 2, (0.0, 0.0, 0.0)), WallAhead(100.0)),
        (("room", 2, (300.0, 0.0, 0.0)), WallAhead(200.0)),
        (("room", 2, (0.0, 300.0, 0.0)), WallAhead(300.0)),
        (("room", 2, (105.0, 0.0, 10.0)), WallAhead(400.0)),
    )
    expectation = Expectation(WallAhead(1.0), targets=RunTargets(WallAhead(1.0), runs))
    base = replace(_stopped(0.0, 500.0, 90.0), seed=2)
    chosen = []
    for start in ((290.0, 5.0, 0.0), (5.0, 290.0, 0.0), (0.0, 0.0, 10.0), (0.0, 0.0, 0.0)):
        record = replace(base, path=((0.0, *start), *base.path[1:]))
        rule = expectation.for_record(record)
        assert isinstance(rule, WallAhead)
        chosen.append(rule.distance_mm)
    # (0, 0, 10°) is 10° from the first start (100 at 10 mm a degree), 105 mm from the last
    assert chosen == [200.0, 300.0, 100.0, 100.0]


# A fast robot sampled every 0.5 s, 50 cm apart, on a slant (3 right for 4 ahead): when it comes
# within reach of a waypoint, and where it passes nearest, lie between the samples.
SLANT = [(0.0, 0.0, 0.0, 0.0)] + [(0.5 * i, 300.0 * i, 400.0 * i, 36.87) for i in range(1, 5)]


@pytest.mark.parametrize(
    ("rule", "path", "detail"),
    [
        pytest.param(
            PathVisits((Waypoint(700.0, 500.0), Waypoint(1500.0, 1150.0)), 100.0),
            SLANT,
            "reached all 2 waypoints in order (0.8 s, 1.8 s); the farthest off was waypoint 1"
            " (70 cm forward, 50 cm right), 2.0 cm away (allowed 10.0 cm)",
            id="each reached where the slant first comes within 10 cm (0.76 s, 1.79 s)",
        ),
        pytest.param(
            PathVisits((Waypoint(700.0, 500.0),), 100.0),
            SLANT,
            "came within 2.0 cm of waypoint 1 (70 cm forward, 50 cm right) at 0.9 s"
            " (allowed 10.0 cm)",
            id="nearest at 86 cm along the slant, 0.86 s",
        ),
        pytest.param(
            PathVisits((Waypoint(20.0, 30.0),), 40.0),
            [(0.0, 0.0, 0.0, 0.0)],
            "came within 3.6 cm of waypoint 1 (2 cm forward, 3 cm right) at 0.0 s (allowed 4.0 cm)",
            id="a path of one sample",
        ),
        pytest.param(
            PathVisits((Waypoint(500.0, 0.0),), 40.0),
            [(0.0, 0.0, 0.0, 0.0), (1.0, 0.0, 1000.0, 0.0)],
            "came within 0.0 cm of waypoint 1 (50 cm forward) at 0.5 s (allowed 4.0 cm)",
            id="a path of two samples is a stretch, not two points",
        ),
    ],
)
def test_waypoints_are_met_between_samples(rule: PathVisits, path: Path, detail: str) -> None:
    assert _judge(rule, _record(path)).detail == detail


# --------------------------------------------------------------------- final pose targets


def test_a_target_relative_to_a_slanted_start_is_turned_with_it() -> None:
    # Start at (50, -20) facing 30°: 100 mm to its right and 200 mm ahead is (236.6, 103.2)
    # in the world, and 10° from its heading is 40°.
    record = _record([(0.0, 50.0, -20.0, 30.0), (5.0, 236.6, 103.2, 41.0)])
    target = FinalPose(100.0, 200.0, 50.0, 10.0, 15.0, "start")
    world = final_pose_target(target, record)
    assert (world.x_mm, world.y_mm, world.heading_deg) == (
        pytest.approx(236.603, abs=1e-3),
        pytest.approx(103.205, abs=1e-3),
        40.0,
    )
    assert (world.radius_mm, world.heading_tolerance_deg, world.relative_to) == (
        50.0,
        15.0,
        "world",
    )
    assert final_pose_target(replace(target, heading_deg=None), record).heading_deg is None
    verdict = _judge(target, record)
    assert verdict.detail == (
        "ended at (237, 103) mm, 0.0 cm from the target (237, 103) mm (allowed 5.0 cm);"
        " heading 41°, 1.0° off (allowed 15.0°)"
    )
