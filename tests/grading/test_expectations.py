"""Each expectation judged on hand-made run records: pass or fail, signed margins, first times."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    CheckFunction,
    Expectation,
    FinalPose,
    FinalState,
    MaxDuration,
    NeverEnter,
    NoCollisions,
    Outcome,
    PathVisits,
    RegionsInOrder,
    Rule,
    RunTargets,
    Selection,
    Tones,
    Turns,
    WallAhead,
    WallDistance,
    Waypoint,
    evaluate,
    find_turns,
)
from roboscript.grading.record import Collision, RunRecord, Tone, Verdict
from roboscript.grading.spec import load_test_spec
from roboscript.sim.geometry import Segment, heading_vector
from roboscript.sim.world import Region, World

ROOM = World(
    "room",
    walls=(Segment(300, -200, 300, 3000), Segment(-300, -200, -300, 3000)),
    regions={
        "a": Region("a", (0.0, 500.0), radius_mm=100.0),
        "b": Region("b", (0.0, 1000.0), radius_mm=100.0),
        "pit": Region(
            "pit", (600.0, 500.0), points=((500, 400), (700, 400), (700, 600), (500, 600))
        ),
        "dot": Region("dot", (0.0, 2000.0), radius_mm=5.0),
    },
)


def _record(
    path: list[tuple[float, float, float, float]],
    *,
    states: tuple[tuple[float, str], ...] = ((0.0, "go"),),
    tones: tuple[Tone, ...] = (),
    collisions: tuple[Collision, ...] = (),
    outcome: str = "success",
    final_state: str = "done",
    reason: str | None = None,
) -> RunRecord:
    last = path[-1]
    return RunRecord(
        mission="m",
        robot="mirto",
        world_name=ROOM.name,
        seed=1,
        outcome=outcome,
        final_state=final_state,
        reason=reason,
        duration_s=last[0],
        states=states,
        path=tuple(path),
        tones=tones,
        collisions=collisions,
        final_pose=(last[1], last[2], last[3]),
        world=ROOM,
    )


def _north(t_end: float, x: float = 0.0, speed_mm_s: float = 100.0) -> list[tuple[float, ...]]:
    """A robot driving north along x at ``speed``, sampled every 0.1 s."""
    steps = round(t_end / 0.1)
    return [(round(i * 0.1, 3), x, round(i * 0.1 * speed_mm_s, 1), 0.0) for i in range(steps + 1)]


def _judge(rule: Rule, record: RunRecord) -> Verdict:
    return evaluate(Expectation(rule), record)


# ------------------------------------------------------------------------------- outcome


def test_outcome_names_the_reason_and_fails_at_the_end() -> None:
    record = _record(_north(3.0), outcome="failure", reason="state 'go' timed out after 3 s")
    verdict = _judge(Outcome("success"), record)
    assert not verdict.passed
    assert verdict.first_violation_s == 3.0
    assert verdict.detail == "the mission ended in failure: state 'go' timed out after 3 s"
    assert _judge(Outcome("failure"), record).passed


def test_final_state_accepts_any_of_several() -> None:
    record = _record(_north(1.0), final_state="home")
    assert _judge(FinalState(("home", "parked")), record).passed
    assert not _judge(FinalState(("parked",)), record).passed


# ---------------------------------------------------------------------------- final pose


def test_final_pose_margin_is_signed_in_centimetres() -> None:
    record = _record(_north(5.0))  # ends at (0, 500)
    near = _judge(FinalPose(0.0, 521.0, 80.0), record)
    assert near.passed
    assert near.margin == "passed by 5.9 cm"
    assert near.margin_value == pytest.approx(59.0)
    far = _judge(FinalPose(0.0, 600.0, 80.0), record)
    assert not far.passed
    assert far.margin == "failed by 2.0 cm"
    assert far.first_violation_s == 5.0


def test_final_pose_relative_to_the_start_follows_the_start_heading() -> None:
    # Start at (100, 0) facing east (90°): "50 cm ahead" is (600, 0) in the world.
    path = [(0.0, 100.0, 0.0, 90.0), (5.0, 600.0, 10.0, 90.0)]
    target = FinalPose(0.0, 500.0, 30.0, heading_deg=0.0, relative_to="start")
    verdict = _judge(target, _record(path))
    assert verdict.passed, verdict.detail
    assert verdict.margin == "passed by 2.0 cm"


def test_final_pose_heading_outside_its_tolerance_fails_in_degrees() -> None:
    path = [(0.0, 0.0, 0.0, 0.0), (2.0, 0.0, 0.0, 40.0)]
    verdict = _judge(FinalPose(0.0, 0.0, 50.0, 0.0, 15.0), _record(path))
    assert not verdict.passed
    assert verdict.margin == "failed by 25.0°"
    assert verdict.margin_unit == "deg"


# ------------------------------------------------------------------------------- regions


def test_regions_in_order_lists_when_each_was_reached() -> None:
    verdict = _judge(RegionsInOrder(("a", "b")), _record(_north(12.0)))
    assert verdict.passed
    assert verdict.detail == "reached 'a' at 4.0 s, 'b' at 9.0 s"


def test_regions_out_of_order_fail_by_the_closest_miss() -> None:
    # Drives north past a and b, so b-then-a never happens after b.
    verdict = _judge(RegionsInOrder(("b", "a")), _record(_north(12.0)))
    assert not verdict.passed
    assert verdict.detail.startswith("never reached 'a' after 'b' at 9.0 s")
    assert verdict.margin == "failed by 31.0 cm"  # just after b (y = 910 mm) to a's edge (600)
    assert verdict.first_violation_s is None  # never reaching has no moment


def test_a_fast_robot_cannot_slip_through_a_region_between_samples() -> None:
    # 1 m/s: samples 100 mm apart straddle the 10 mm wide region "dot" at y = 2000 +- 5.
    path = [(round(t * 0.1, 3), 0.0, 1950.0 + t * 100.0, 0.0) for t in range(3)]
    assert _judge(RegionsInOrder(("dot",)), _record(path)).passed


def test_never_enter_gives_the_first_entry_time_and_depth() -> None:
    # East at 100 mm/s along y = 500 from x = 0: on the pit's edge (x = 500) at 5.0 s, inside
    # from the next sample on.
    path = [(round(i * 0.1, 3), i * 10.0, 500.0, 90.0) for i in range(71)]
    verdict = _judge(NeverEnter(("pit",)), _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 5.1
    assert verdict.margin == "failed by 10.0 cm"  # deepest: x = 600, the pit's middle
    assert "entered 'pit' at 5.1 s" in verdict.detail


def test_never_enter_passes_by_the_closest_approach() -> None:
    verdict = _judge(NeverEnter(("pit",)), _record(_north(10.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 50.0 cm"  # x = 0 to the pit's west edge at 500


# ---------------------------------------------------------------------------- collisions


def test_no_collisions_fails_at_the_first_collision() -> None:
    hits = (Collision(2.5, 200.0, 250.0, "right"), Collision(4.0, 200.0, 400.0, "right"))
    verdict = _judge(NoCollisions(), _record(_north(5.0), collisions=hits))
    assert not verdict.passed
    assert verdict.first_violation_s == 2.5
    assert verdict.margin == "failed by 2 collisions"
    assert "the first at 2.5 s on the right bumper" in verdict.detail


def test_no_collisions_passes_by_the_clearance_to_the_nearest_wall() -> None:
    # Centre at x = 0, walls at +-300, body radius 100: 20 cm to spare.
    verdict = _judge(NoCollisions(), _record(_north(5.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 20.0 cm"


# ---------------------------------------------------------------------------------- tones


def _tones(*pairs: tuple[float, float]) -> tuple[Tone, ...]:
    return tuple(Tone(t, f, 0.2) for t, f in pairs)


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


# ------------------------------------------------------------------------------ duration


def test_max_duration_margin_in_seconds() -> None:
    assert _judge(MaxDuration(30.0), _record(_north(20.0))).margin == "passed by 10.0 s"
    late = _judge(MaxDuration(30.0), _record(_north(30.4)))
    assert not late.passed
    assert late.margin == "failed by 0.40 s"
    assert late.first_violation_s == 30.0


# -------------------------------------------------------------------------- wall distance


def _drifting_right() -> list[tuple[float, float, float, float]]:
    """North at x = 0 for 4 s, then drifting east at 50 mm/s towards the wall at x = 300."""
    path = []
    for i in range(81):
        t = round(i * 0.1, 3)
        x = 0.0 if t <= 4.0 else round((t - 4.0) * 50.0, 1)
        path.append((t, x, round(t * 100.0, 1), 0.0))
    return path


def test_wall_distance_measures_from_the_side_sensor_with_the_first_violation() -> None:
    # The side sensor sits 80 mm right of the centre: 220 mm from the wall while x = 0.
    states = ((0.0, "approach"), (1.0, "follow"))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    verdict = _judge(rule, _record(_drifting_right(), states=states))
    assert not verdict.passed
    # Below 150 mm once x > 70, i.e. after 5.4 s: the first sample past it is 5.5 s.
    assert verdict.first_violation_s == pytest.approx(5.5)
    # The worst: at 7.9 s (the last sample before the run ends), x = 195: a gap of 25 mm.
    assert verdict.margin == "failed by 12.5 cm"
    assert "the worst was 2.5 cm at 7.9 s" in verdict.detail


def test_wall_distance_passes_by_the_tightest_sample_after_settling() -> None:
    states = ((0.0, "follow"), (4.0, "stop"))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    verdict = _judge(rule, _record(_drifting_right(), states=states))
    assert verdict.passed
    assert verdict.margin == "passed by 3.0 cm"  # 220 mm: 30 mm inside the top of the band
    assert verdict.relative_margin == pytest.approx(30.0 / 50.0)


def test_wall_distance_skips_the_settling_time() -> None:
    # Far from the wall for the first 0.5 s of the state, then in the band.
    path = [(round(i * 0.1, 3), -200.0 if i < 5 else 0.0, i * 10.0, 0.0) for i in range(30)]
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.5)
    )
    assert _judge(rule, _record(path)).passed
    strict = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
    )
    verdict = _judge(strict, _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 0.0


def test_wall_distance_on_the_left_and_a_state_never_entered() -> None:
    rule = WallDistance(
        side="left", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
    )
    assert _judge(rule, _record(_north(3.0))).passed  # left wall: 220 mm
    missing = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow")
    )
    verdict = _judge(missing, _record(_north(3.0)))
    assert not verdict.passed
    assert verdict.detail == "the mission never entered state 'follow'"


# ------------------------------------------------------------------------- teacher check


@pytest.mark.parametrize(
    ("body", "passed", "detail"),
    [
        ("return run.duration_s < 10", True, ""),
        ("return (False, 'too slow on the straight')", False, "too slow on the straight"),
        (
            "return Verdict('mine', False, 'failed by 2 laps', 1.5, 'only one lap')",
            False,
            "only one lap",
        ),
        ("return 1 / 0", False, "the teacher's check raised ZeroDivisionError: division by zero"),
        ("return 'yes'", False, "the teacher's check returned str"),
    ],
)
def test_a_teacher_check_may_answer_in_three_ways(
    tmp_path: Path, body: str, passed: bool, detail: str
) -> None:
    checks = tmp_path / "checks.py"
    checks.write_text(
        f"from roboscript.grading.record import Verdict\n\ndef judge(run):\n    {body}\n",
        encoding="utf-8",
    )
    verdict = evaluate(
        Expectation(CheckFunction(str(checks), "judge", "checks.py:judge"), 2.0),
        _record(_north(5.0)),
    )
    assert verdict.passed is passed
    assert verdict.detail.startswith(detail)
    assert verdict.name == "check: judge"
    assert verdict.weight == 2.0


def test_the_record_is_read_only() -> None:
    record = _record(_north(1.0))
    with pytest.raises(AttributeError):
        record.outcome = "success"  # type: ignore[misc]


# ----------------------------------------------------------------------- shapes and turns

Pose = tuple[float, float, float]


def _square(
    turn_deg: float = 90.0,
    *,
    side_mm: float = 500.0,
    start: Pose = (0.0, 0.0, 0.0),
    sides: int = 4,
    rate_deg_s: float = 90.0,
    pause_s: float = 0.5,
) -> list[tuple[float, float, float, float]]:
    """A square driven at 100 mm/s, sampled every 0.1 s: a side, a pause, a turn on the spot of
    ``turn_deg`` (positive: right), a pause, and so on. Headings are recorded 0-360 like the
    simulator's, so a left turn from north reads 351, 342, ..."""
    x, y, h = start
    path = [(0.0, x, y, h % 360.0)]

    def sample() -> None:
        t = round(path[-1][0] + 0.1, 3)
        path.append((t, round(x, 3), round(y, 3), round(h % 360.0, 3)))

    for _ in range(sides):
        dx, dy = heading_vector(h)
        for _ in range(round(side_mm / 10.0)):
            x, y = x + dx * 10.0, y + dy * 10.0
            sample()
        for _ in range(round(pause_s / 0.1)):
            sample()
        steps = round(abs(turn_deg) / rate_deg_s / 0.1)
        for _ in range(steps):
            h += turn_deg / steps
            sample()
        for _ in range(round(pause_s / 0.1)):
            sample()
    return path


SQUARE = PathVisits(
    (Waypoint(500.0, 0.0), Waypoint(500.0, 500.0), Waypoint(0.0, 500.0), Waypoint(0.0, 0.0)),
    tolerance_mm=40.0,
)


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


def _spin(headings: list[float]) -> list[tuple[float, float, float, float]]:
    return [(round(i * 0.1, 3), 0.0, 0.0, h % 360.0) for i, h in enumerate(headings)]


def test_rotations_the_same_way_with_no_travel_between_are_one_turn() -> None:
    # Two 45° rotations at 90°/s on the spot, 0.1 s or 0.3 s (a beep) apart: one 90° corner
    # either way, so a run's corners are counted alike however long each pause happened to be.
    half = [9.0 * i for i in range(6)]  # 0 to 45 in 0.5 s
    short = _spin([*half, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0, 90.0])
    beep = _spin([*half, 45.0, 45.0, 45.0, *(45.0 + h for h in half[1:]), 90.0, 90.0, 90.0])
    assert [t.angle_deg for t in find_turns(short)] == [90.0]
    assert [(t.start_s, t.end_s, t.angle_deg) for t in find_turns(beep)] == [(0.0, 1.3, 90.0)]
    # Back the other way on the spot is a turn of its own.
    back = _spin([*half, 45.0, 45.0, 45.0, *(45.0 - h for h in half[1:]), 0.0, 0.0])
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


# ---------------------------------------------------------------------- wall ahead at end


def _stopped(x: float, y: float, heading: float) -> RunRecord:
    return _record([(0.0, 0.0, 0.0, 0.0), (5.0, x, y, heading)])


def test_wall_ahead_is_measured_from_the_front_of_the_body() -> None:
    # Facing east at x = 0, the wall at x = 300: the centre is 30 cm away, the body's front
    # (radius 10 cm) 20 cm.
    record = _stopped(0.0, 500.0, 90.0)
    verdict = _judge(WallAhead(200.0, 30.0), record)
    assert verdict.passed
    assert verdict.margin == "passed by 3.0 cm"
    assert verdict.detail.startswith("stopped 20.0 cm from the wall ahead")
    centre = _judge(WallAhead(300.0, 30.0), record)
    assert not centre.passed
    assert centre.margin == "failed by 7.0 cm"
    assert "(too close)" in centre.detail
    assert centre.first_violation_s == 5.0


def test_wall_ahead_follows_the_heading() -> None:
    # At x = 100: east, the wall is 20 cm from the centre (10 cm from the front); west, 40 cm
    # (30 cm); at 45° the ray meets x = 300 after 200 / sin 45° = 282.8 mm.
    assert _judge(WallAhead(100.0, 5.0), _stopped(100.0, 500.0, 90.0)).passed
    assert _judge(WallAhead(300.0, 5.0), _stopped(100.0, 500.0, 270.0)).passed
    slanted = _judge(WallAhead(182.8, 1.0), _stopped(100.0, 500.0, 45.0))
    assert slanted.margin_value == pytest.approx(1.0, abs=0.05)
    north = _judge(WallAhead(100.0, 5.0), _stopped(100.0, 500.0, 0.0))
    assert not north.passed
    assert north.detail.startswith("no wall straight ahead when the robot stopped (facing 0°)")


# ---------------------------------------------------------------------- per-run targets


def test_run_targets_are_chosen_by_seed_and_start() -> None:
    targets = RunTargets(
        WallAhead(200.0),
        (
            (("room", 1, (0.0, 0.0, 0.0)), WallAhead(200.0)),
            (("room", 2, (0.0, 0.0, 0.0)), WallAhead(300.0)),
            (("room", 2, (100.0, 0.0, 90.0)), WallAhead(100.0)),
        ),
    )
    expectation = Expectation(WallAhead(200.0), targets=targets)
    record = _stopped(100.0, 500.0, 90.0)  # started at (0, 0) facing north, seed 1
    assert expectation.for_record(record) == WallAhead(200.0)
    assert expectation.for_record(replace(record, seed=2)) == WallAhead(300.0)
    turned = replace(record, seed=2, path=((0.0, 102.0, 1.0, 90.0), *record.path[1:]))
    assert expectation.for_record(turned) == WallAhead(100.0)
    assert expectation.for_record(replace(record, seed=9)) == WallAhead(200.0)
    assert evaluate(expectation, turned).passed  # 10 cm from the front to the wall
    assert not evaluate(expectation, replace(record, seed=2)).passed


def _spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "spec.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_run_changes_only_the_targets_it_names(tmp_path: Path) -> None:
    spec = load_test_spec(
        _spec(
            tmp_path,
            "test: t\n"
            "world: square-room\n"
            "runs:\n"
            "  - {seed: 1}\n"
            "  - {seed: 2, start: {y: 300 mm}, expect: {wall_ahead_at_end: {distance: 50 cm}}}\n"
            "expect:\n"
            "  - outcome: success\n"
            "  - wall_ahead_at_end: {distance: 20 cm, tolerance: 2 cm}\n",
        )
    )
    assert spec.expectations[0].rule == Outcome("success")
    targets = spec.expectations[1].targets
    assert isinstance(targets, RunTargets)
    assert targets.default == WallAhead(200.0, 20.0)
    assert [params for _, params in targets.runs] == [
        WallAhead(200.0, 20.0),
        WallAhead(500.0, 20.0),
    ]
    assert [key for key, _ in targets.runs] == [
        ("square-room", 1, (0.0, 0.0, 0.0)),
        ("square-room", 2, (0.0, 300.0, 0.0)),
    ]


def test_a_run_may_change_the_tolerance_of_a_short_path_visits(tmp_path: Path) -> None:
    spec = load_test_spec(
        _spec(
            tmp_path,
            "test: t\n"
            "runs:\n"
            "  - {seed: 1}\n"
            "  - {seed: 2, expect: {path_visits: {tolerance: 2 cm}}}\n"
            "expect:\n"
            "  - path_visits: [{forward: 50 cm}, start]\n",
        )
    )
    targets = spec.expectations[0].targets
    assert isinstance(targets, RunTargets)
    waypoints = (Waypoint(500.0, 0.0), Waypoint(0.0, 0.0))
    assert [params for _, params in targets.runs] == [
        PathVisits(waypoints, 80.0),
        PathVisits(waypoints, 20.0),
    ]


def test_the_new_expectations_read_with_units_and_defaults(tmp_path: Path) -> None:
    spec = load_test_spec(
        _spec(
            tmp_path,
            "test: t\n"
            "world: square-room\n"
            "expect:\n"
            "  - path_visits: [{forward: 50 cm}, {forward: 500, left: 0.2 m}, start, {back: 1}]\n"
            "  - path_visits: {waypoints: [{right: 5 cm}], tolerance: 3 cm, in_order: false}\n"
            "  - turns: {direction: left, count: 4, angle: 0.25 rev, total: 360}\n"
            "  - wall_ahead_at_end: {distance: 200}\n",
        )
    )
    params = [e.rule for e in spec.expectations]
    assert params[0] == PathVisits(
        (Waypoint(500.0, 0.0), Waypoint(500.0, -200.0), Waypoint(0.0, 0.0), Waypoint(-1.0, 0.0))
    )
    assert params[0].tolerance_mm == 80.0
    assert params[1] == PathVisits((Waypoint(0.0, 50.0),), 30.0, in_order=False)
    assert params[2] == Turns("left", 4, 90.0, 360.0, 20.0)
    assert params[3] == WallAhead(200.0, 30.0)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "expect:\n  - path_visits: [{forwrd: 50 cm}]\n",
            "3:20: error: unknown key 'forwrd' in a waypoint (did you mean 'forward'?)",
        ),
        (
            "expect:\n  - path_visits: [{forward: 50 cm, back: 2 cm}]\n",
            "3:36: error: give either forward or back, not both (a negative forward is back)",
        ),
        (
            "expect:\n  - path_visits: [strat]\n",
            (
                "3:19: error: a waypoint is written {forward: 50 cm, right: 20 cm} (or back, left),"
                " or 'start' (got 'strat') (did you mean 'start'?)"
            ),
        ),
        ("expect:\n  - path_visits: []\n", "3:18: error: path_visits lists at least one waypoint"),
        (
            "expect:\n  - path_visits: {waypoints: [start], tolerence: 2 cm}\n",
            "3:39: error: unknown key 'tolerence' in path_visits (did you mean 'tolerance'?)",
        ),
        (
            "expect:\n  - path_visits: [{forward: 50 deg}]\n",
            "3:29: error: 'deg' is a unit of angle, but this is a distance",
        ),
        (
            "expect:\n  - turns: {direction: rigth}\n",
            (
                "3:24: error: 'direction' must be one of: right, left (got 'rigth')"
                " (did you mean 'right'?)"
            ),
        ),
        (
            "expect:\n  - turns: {angle: -90 deg}\n",
            "3:20: error: 'angle' is a size, more than 0; say which way with direction",
        ),
        ("expect:\n  - turns: {tolerance: 5 deg}\n", "3:12: error: turns needs at least one of"),
        (
            "expect:\n  - wall_ahead_at_end: {distance: 20 cm}\n",
            "3:24: error: the world 'empty' has no walls, so there is never a wall ahead",
        ),
        (
            "world: square-room\nexpect:\n  - wall_ahead_at_end: {distnce: 20 cm}\n",
            "4:25: error: unknown key 'distnce' in wall_ahead_at_end (did you mean 'distance'?)",
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {final_pose: {x: 1}}}\n"
                "expect:\n  - final_pose_within: {x: 0, y: 0, radius: 5 cm}\n"
            ),
            (
                "3:24: error: the spec expects no 'final_pose' for this run to change"
                " (a run changes the targets of the spec's own expectations: final_pose_within)"
                " (did you mean 'final_pose_within'?)"
            ),
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {final_pose_within: {radius: -1 cm}}}\n"
                "expect:\n  - final_pose_within: {x: 0, y: 0, radius: 5 cm}\n"
            ),
            "3:52: error: 'radius' must be more than 0",
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {tones: {count: 1}}}\n"
                "expect:\n  - {tones: {count: 4}}\n  - {tones: {max_count: 5}}\n"
            ),
            "3:24: error: the spec expects 'tones' 2 times, so a run cannot say which to change",
        ),
        (
            (
                "runs:\n  - {seed: 1, expect: {max_duration: 20 s}}\n  - {seed: 1}\n"
                "expect:\n  - max_duration: 30 s\n"
            ),
            (
                "3:23: error: runs 1 and 2 have the same world, seed and start, but different"
                " 'max_duration' targets; give them different seeds"
            ),
        ),
    ],
)
def test_mistakes_in_the_new_expectations_are_located(
    tmp_path: Path, text: str, expected: str
) -> None:
    path = _spec(tmp_path, "test: t\n" + text)
    with pytest.raises(SpecError) as caught:
        load_test_spec(path)
    assert caught.value.format().startswith(f"{path}:{expected}"), caught.value.format()


STOP_AT_WALL = """\
mission: stop-at-wall
initial: forward
states:
  forward:
    do: {drive: {distance: 3 m, speed: 15 cm/s}}
    timeout: 20 s
    on: {done: stop, failed: stop, timeout: stop}
    when:
      - {if: "range.distance_cm < 30", goto: stop}
  stop:
    do: {play_tone: {frequency: 660 Hz, duration: 300 ms}}
    final: success
"""


def test_wall_ahead_and_run_targets_through_the_grader(tmp_path: Path) -> None:
    from roboscript.grading.run import grade_run

    # The room's walls are 1 m from its middle. Stopping when the front sensor (1 cm behind
    # the body's front edge) reads under 30 cm leaves about 27 cm from the front to the wall.
    spec = load_test_spec(
        _spec(
            tmp_path,
            "test: stop-at-wall\n"
            "world: square-room\n"
            "runs:\n"
            "  - {seed: 1}\n"
            "  - {seed: 2, start: {x: 300 mm, y: -500 mm, heading: 90 deg},"
            " expect: {final_pose_within: {x: 63 cm, y: -50 cm}}}\n"
            "  - {seed: 3, expect: {wall_ahead_at_end: {distance: 40 cm}}}\n"
            "expect:\n"
            "  - outcome: success\n"
            "  - wall_ahead_at_end: {distance: 25 cm, tolerance: 3 cm}\n"
            "  - final_pose_within: {x: 0 mm, y: 63 cm, radius: 3 cm}\n",
        )
    )
    mission = tmp_path / "stop.yaml"
    mission.write_text(STOP_AT_WALL, encoding="utf-8")
    results = [grade_run(spec, str(mission), variant) for variant in spec.variants]
    assert [r.status for r in results] == ["passed", "passed", "failed"], [
        r.message for r in results
    ]
    first, second, third = (r.verdicts for r in results)
    assert first[1].detail.startswith("stopped 2")  # 2x cm: measured from the front edge
    assert "wanted 25.0 cm" in first[1].detail
    assert "from the target (630, -500) mm" in second[2].detail  # its own target
    assert not third[1].passed  # the same stop, judged by its own 40 cm
    assert "wanted 40.0 cm" in third[1].detail
    assert third[2].passed  # its other targets are the spec's
