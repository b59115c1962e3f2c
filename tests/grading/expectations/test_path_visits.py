"""``path_visits``: waypoints relative to the start that the path comes near."""

from __future__ import annotations

import pytest
from grading.expectations.runs import (
    AHEAD,
    NO_PATH,
    SLANT,
    SQUARE,
    Samples,
    _judge,
    _north,
    _record,
    _same,
    _square,
    _verdict,
)

from roboscript.grading.expectations import (
    PathVisits,
    Waypoint,
)
from roboscript.grading.record import RunRecord, Verdict


def test_path_visits_a_right_square_in_order() -> None:
    verdict = _judge(SQUARE, _record(_square()))
    assert verdict.passed, verdict.detail
    assert verdict.margin == "passed by 4.0 cm"  # every corner exactly: the whole tolerance
    assert verdict.relative_margin == pytest.approx(1.0)
    assert "reached all 4 waypoints in order (4.6 s, 11.6 s, 18.6 s, 25.6 s)" in verdict.detail


def test_path_visits_right_is_not_left() -> None:
    # A left square goes to (-500, 500), a metre from the second corner it should reach.
    verdict = _judge(SQUARE, _record(_square(-90.0)))
    assert not verdict.passed
    assert verdict.detail.startswith(
        "missed waypoint 2 (50 cm forward, 50 cm right): the closest the robot came was 50.0 cm"
    )
    assert verdict.detail.endswith("after reaching waypoint 1 at 4.6 s")  # within 4 cm
    assert verdict.margin == "failed by 46.0 cm"
    assert verdict.first_violation_s is None  # never reaching a point has no moment
    mirrored = PathVisits(tuple(Waypoint(w.forward_mm, -w.right_mm) for w in SQUARE.waypoints))
    assert _judge(mirrored, _record(_square(-90.0))).passed


def test_path_visits_forward_is_not_back() -> None:
    ahead = _record(_north(5.0))  # 500 mm north, facing north
    assert _judge(PathVisits((Waypoint(500.0, 0.0),)), ahead).passed
    behind = _judge(PathVisits((Waypoint(-500.0, 0.0),)), ahead)
    assert not behind.passed
    assert behind.detail.startswith("missed waypoint 1 (50 cm back)")


def test_path_visits_is_in_the_start_frame() -> None:
    # Starting at (100, 0) facing east: ahead is east, the right-hand side is south.
    path = _square(start=(100.0, 0.0, 90.0))
    assert path[50][1:3] == (600.0, 0.0)  # the first corner, 50 cm east of the start
    verdict = _judge(SQUARE, _record(path))
    assert verdict.passed, verdict.detail
    # In world terms the square is (600, 0), (600, -500), (100, -500): nowhere near +y.
    world_frame = PathVisits((Waypoint(500.0, 0.0), Waypoint(500.0, -500.0)))
    assert not _judge(world_frame, _record(path)).passed


def test_path_visits_tolerance_is_inclusive() -> None:
    # North along x = 0: a waypoint 80 mm right of the track is 80 mm away, exactly.
    record = _record(_north(10.0))
    edge = _judge(PathVisits((Waypoint(500.0, 80.0),), 80.0), record)
    assert edge.passed
    assert edge.margin_value == pytest.approx(0.0)
    beyond = _judge(PathVisits((Waypoint(500.0, 81.0),), 80.0), record)
    assert not beyond.passed
    assert beyond.margin == "failed by 0.1 cm"
    assert "the closest the robot came was 8.1 cm, at 5.0 s (allowed 8.0 cm)" in beyond.detail


def test_path_visits_in_order_unless_told_otherwise() -> None:
    # North to y = 1000: it passes 50 cm ahead before 100 cm ahead, not after.
    backwards = (Waypoint(1000.0, 0.0), Waypoint(500.0, 0.0))
    record = _record(_north(10.0))
    verdict = _judge(PathVisits(backwards, 80.0), record)
    assert not verdict.passed
    # 100 cm ahead is within 8 cm from y = 920 on, so waypoint 2 is looked for from the
    # stretch of path that reaches it (y = 910 to 920): 41 cm from 50 cm ahead at best.
    assert verdict.detail.startswith("missed waypoint 2 (50 cm forward): the closest")
    assert verdict.margin == "failed by 33.0 cm"
    assert _judge(PathVisits(backwards, 80.0, in_order=False), record).passed


def test_path_visits_a_fast_robot_cannot_skip_a_waypoint_between_samples() -> None:
    # 2 m/s: samples 200 mm apart, the waypoint halfway between two of them.
    path = [(round(i * 0.1, 3), 0.0, i * 200.0, 0.0) for i in range(6)]
    verdict = _judge(PathVisits((Waypoint(330.0, 10.0),), 20.0), _record(path))
    assert verdict.passed
    assert verdict.margin == "passed by 1.0 cm"
    assert "at 0.2 s" in verdict.detail  # 330 mm at 2 m/s: 0.165 s, between two samples


def test_path_visits_margin_is_the_worst_waypoint() -> None:
    waypoints = (Waypoint(300.0, 10.0), Waypoint(600.0, 30.0))
    verdict = _judge(PathVisits(waypoints, 50.0), _record(_north(10.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 2.0 cm"
    assert "the farthest off was waypoint 2 (60 cm forward, 3 cm right), 3.0 cm away" in (
        verdict.detail
    )


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
    rule: PathVisits, path: Samples, detail: str
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
def test_waypoints_are_met_between_samples(rule: PathVisits, path: Samples, detail: str) -> None:
    assert _judge(rule, _record(path)).detail == detail
