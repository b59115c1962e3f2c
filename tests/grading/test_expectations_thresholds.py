"""Where each expectation's threshold lies, and what the verdict says: bounds that are
inclusive, the side the robot may err on, and the full sentence a student reads.

The records are hand-made, as in test_expectations.py.
"""

from __future__ import annotations

from dataclasses import replace

import pytest

from roboscript.grading.expectations import (
    Expectation,
    FinalPose,
    MaxDuration,
    NeverEnter,
    NoCollisions,
    Rule,
    Selection,
    Tones,
    Turns,
    WallDistance,
    evaluate,
    find_turns,
)
from roboscript.grading.record import Collision, RunRecord, Tone, Verdict
from roboscript.sim.geometry import Segment
from roboscript.sim.world import Region, World

ROOM = World("room", walls=(Segment(300, -200, 300, 3000), Segment(-300, -200, -300, 3000)))
CORRIDOR_SIDE = World("right-wall", walls=(Segment(300, -200, 300, 3000),))
"""One wall, 300 mm right of the robot's line: its right sensor (80 mm out) reads 220 mm."""


def _record(
    path: list[tuple[float, float, float, float]],
    *,
    tones: tuple[Tone, ...] = (),
    states: tuple[tuple[float, str], ...] = ((0.0, "go"),),
    world: World | None = ROOM,
) -> RunRecord:
    last = path[-1]
    return RunRecord(
        mission="m",
        robot="mirto",
        world_name=ROOM.name,
        seed=1,
        outcome="success",
        final_state="done",
        reason=None,
        duration_s=last[0],
        states=states,
        path=tuple(path),
        tones=tones,
        collisions=(),
        final_pose=(last[1], last[2], last[3]),
        world=world,
    )


def _north(t_end: float) -> list[tuple[float, float, float, float]]:
    """A robot driving north along x = 0 at 100 mm/s, sampled every 0.1 s."""
    steps = round(t_end / 0.1)
    return [(round(i * 0.1, 3), 0.0, round(i * 10.0, 1), 0.0) for i in range(steps + 1)]


def _tones(*pairs: tuple[float, float]) -> tuple[Tone, ...]:
    return tuple(Tone(t, f, 0.2) for t, f in pairs)


def _judge(rule: Rule, record: RunRecord) -> Verdict:
    return evaluate(Expectation(rule), record)


# ------------------------------------------------------------------------------- tones


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


# --------------------------------------------------------------------------- duration


def test_max_duration_passes_up_to_and_including_the_limit() -> None:
    on_time = _judge(MaxDuration(30.0), _record(_north(30.0)))
    assert on_time.passed is True
    assert on_time.first_violation_s is None
    early = _judge(MaxDuration(30.0), _record(_north(29.5)))
    assert early == Verdict(
        "max_duration",
        True,
        "passed by 0.50 s",
        None,
        "the mission took 29.5 s (allowed 30 s)",
        0.5,
        "s",
        0.5 / 30.0,
    )


# ------------------------------------------------------------------------- final pose


@pytest.mark.parametrize(("x", "passed"), [(80.0, True), (-80.0, True), (81.0, False)])
def test_the_final_pose_radius_counts_sideways_error_and_is_inclusive(
    x: float, passed: bool
) -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, x, 500.0, 0.0)])
    verdict = _judge(FinalPose(0.0, 500.0, 80.0), record)
    assert verdict.passed is passed
    assert verdict.first_violation_s == (None if passed else 5.0)


def test_the_final_pose_verdict_names_where_it_ended_and_what_was_allowed() -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 30.0, 540.0, 0.0)])
    verdict = _judge(FinalPose(0.0, 500.0, 80.0), record)
    assert verdict == Verdict(
        "final_pose_within",
        True,
        "passed by 3.0 cm",
        None,
        "ended at (30, 540) mm, 5.0 cm from the target (0, 500) mm (allowed 8.0 cm)",
        30.0,
        "mm",
        30.0 / 80.0,
    )


@pytest.mark.parametrize(("heading", "passed"), [(15.0, True), (345.0, True), (15.5, False)])
def test_the_final_heading_tolerance_is_inclusive(heading: float, passed: bool) -> None:
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 500.0, heading)])
    target = FinalPose(0.0, 500.0, 80.0, heading_deg=0.0, heading_tolerance_deg=15.0)
    assert _judge(target, record).passed is passed


def test_the_tighter_of_position_and_heading_gives_the_margin() -> None:
    # 6 cm inside an 8 cm radius (75 % spare) but 12 of 15 degrees off (20 % spare)
    record = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 520.0, 12.0)])
    target = FinalPose(0.0, 500.0, 80.0, heading_deg=0.0, heading_tolerance_deg=15.0)
    verdict = _judge(target, record)
    assert verdict.passed
    assert verdict.margin == "passed by 3.0°"
    assert (verdict.margin_value, verdict.margin_unit) == (3.0, "deg")
    assert verdict.relative_margin == pytest.approx(3.0 / 15.0)
    assert verdict.detail.endswith("; heading 12°, 12.0° off (allowed 15.0°)")
    assert verdict.detail.startswith("ended at (0, 520) mm")
    # heading well inside, position tight: the position's margin stays
    near = _record([(0.0, 0.0, 0.0, 0.0), (5.0, 0.0, 570.0, 1.0)])
    assert _judge(target, near).margin_unit == "mm"


# ---------------------------------------------------------------------- wall distance


def test_leaving_the_state_before_the_settling_time_fails_the_wall_distance() -> None:
    record = _record(_north(3.0), states=((0.0, "follow"), (0.8, "stop")))
    rule = WallDistance(
        side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="follow", settle_s=1.0)
    )
    assert _judge(rule, record) == Verdict(
        "wall_distance",
        False,
        "",
        None,
        "the robot never stayed in 'follow' longer than the 1 s it is given to settle",
    )


def test_the_wall_distance_is_measured_on_the_side_named() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    right = _judge(
        WallDistance(
            side="right", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
        ),
        record,
    )
    assert right.passed
    assert right.detail == (
        "in 'go' the right gap must stay between 15.0 cm and 25.0 cm;"
        " the worst was 22.0 cm at 0.0 s"  # the gap never changes: the first sample
    )
    left = _judge(
        WallDistance(
            side="left", min_mm=150.0, max_mm=250.0, selection=Selection(state="go", settle_s=0.0)
        ),
        record,
    )
    assert not left.passed
    assert left.first_violation_s == 0.0


def test_with_no_wall_in_sight_an_at_least_band_passes_and_an_at_most_band_fails() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    at_least = WallDistance(
        side="left", min_mm=150.0, selection=Selection(state="go", settle_s=0.0)
    )
    assert _judge(at_least, record) == Verdict(
        "wall_distance", True, "", None, "no left wall was ever closer than allowed"
    )
    at_most = WallDistance(side="left", max_mm=250.0, selection=Selection(state="go", settle_s=0.0))
    assert _judge(at_most, record) == Verdict(
        "wall_distance",
        False,
        "",
        0.0,
        "in 'go' the left gap must stay at most 25.0 cm; the worst was no wall in sight at 0.0 s",
    )


def test_one_sided_wall_bands_judge_the_side_they_bound() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)  # 220 mm on the right
    assert _judge(
        WallDistance(min_mm=200.0, selection=Selection(state="go", settle_s=0.0)), record
    ).passed
    too_far = _judge(
        WallDistance(max_mm=200.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert (too_far.passed, too_far.margin) == (False, "failed by 2.0 cm")
    assert too_far.relative_margin == pytest.approx(-20.0 / 200.0)
    too_close = _judge(
        WallDistance(min_mm=250.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert (too_close.passed, too_close.margin) == (False, "failed by 3.0 cm")
    assert "must stay at least 25.0 cm" in too_close.detail


def test_a_record_without_a_world_has_no_wall_to_be_near() -> None:
    record = replace(_record(_north(3.0)), world=None)
    verdict = _judge(
        WallDistance(min_mm=150.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed


# ------------------------------------------------------------------------------ turns


def _spin(
    headings: list[float], dt_s: float = 0.1, creep_mm: float = 50.0
) -> list[tuple[float, float, float, float]]:
    """Turning on the spot through ``headings``, one sample every ``dt_s``; between samples
    with the same heading the robot creeps ``creep_mm`` east, so turns a pause apart are
    driven apart too."""
    path = []
    x = 0.0
    for i, h in enumerate(headings):
        if i and h == headings[i - 1]:
            x += creep_mm
        path.append((round(i * dt_s, 3), x, 0.0, h % 360.0))
    return path


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


def _left_turns(n: int) -> list[tuple[float, float, float, float]]:
    """``n`` left turns of 90 degrees at 90 deg/s, each followed by a second standing still."""
    headings: list[float] = []
    for turn in range(n):
        headings += [-90.0 * turn - 9.0 * i for i in range(10)] + [-90.0 * (turn + 1)] * 10
    return _spin(headings)


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


# ------------------------------------------------------------------ regions and walls

YARD = World(
    "yard",
    walls=(Segment(300, -200, 300, 3000),),
    regions={
        "pit": Region(
            "pit", (600.0, 500.0), points=((500, 400), (700, 400), (700, 600), (500, 600))
        ),
        "pond": Region("pond", (-400.0, 300.0), radius_mm=100.0),
    },
)


def test_never_enter_names_the_first_region_entered_and_the_deepest_point() -> None:
    # east along y = 500 from x = 0 at 100 mm/s: into the pit (x > 500) after 5 s
    path = [(round(i * 0.1, 3), i * 10.0, 500.0, 90.0) for i in range(61)]
    verdict = _judge(NeverEnter(("pond", "pit")), _record(path, world=YARD))
    assert verdict == Verdict(
        "never_enter",
        False,
        "failed by 10.0 cm",
        5.1,
        "entered 'pit' at 5.1 s; the deepest was 10.0 cm inside 'pit'",
        -100.0,
        "mm",
    )


def test_never_enter_passes_by_the_closest_approach_to_any_of_its_regions() -> None:
    verdict = _judge(NeverEnter(("pit", "pond")), _record(_north(3.0), world=YARD))
    # x = 0 passes 30 cm from the pond's rim (centre 40 cm west, radius 10 cm)
    assert verdict == Verdict(
        "never_enter",
        True,
        "passed by 30.0 cm",
        None,
        "closest approach: 30.0 cm from 'pond'",
        300.0,
        "mm",
    )


def test_no_collisions_names_the_first_hit_and_counts_them_all() -> None:
    hits = (Collision(2.5, 200.0, 250.0, "left"), Collision(4.0, 210.0, 400.0, "right"))
    record = replace(_record(_north(5.0)), collisions=hits)
    assert _judge(NoCollisions(), record) == Verdict(
        "no_collisions",
        False,
        "failed by 2 collisions",
        2.5,
        "2 collisions; the first at 2.5 s on the left bumper, at (200, 250) mm",
        -2.0,
        "collisions",
    )


def test_no_collisions_passes_by_the_closest_the_body_came_to_a_wall() -> None:
    # the body (radius 100 mm) drifting east from x = 0 to x = 150, the wall at x = 300
    path = [(round(i * 0.1, 3), i * 5.0, i * 10.0, 0.0) for i in range(31)]
    assert _judge(NoCollisions(), _record(path, world=YARD)) == Verdict(
        "no_collisions",
        True,
        "passed by 5.0 cm",
        None,
        "no collisions; the closest the body came to a wall was 5.0 cm",
        50.0,
        "mm",
    )


def test_no_collisions_without_walls_passes_with_nothing_to_measure() -> None:
    record = replace(_record(_north(3.0)), world=None)
    assert _judge(NoCollisions(), record) == Verdict(
        "no_collisions", True, "", None, "no collisions"
    )


def test_a_record_without_a_path_never_moved_and_so_never_entered() -> None:
    record = replace(_record(_north(1.0), world=YARD), path=())
    assert _judge(NeverEnter(("pit",)), record) == Verdict(
        "never_enter", True, "", None, "the robot never moved"
    )


@pytest.mark.parametrize(("top_mm", "passed"), [(220.0, True), (220.5, True), (219.5, False)])
def test_the_edge_of_a_wall_band_is_inside_it(top_mm: float, passed: bool) -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)  # 220 mm on the right
    verdict = _judge(
        WallDistance(max_mm=top_mm, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed is passed
    assert (verdict.margin_value, verdict.margin_unit) == (top_mm - 220.0, "mm")


def test_an_at_least_0_band_has_no_share_to_give() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    verdict = _judge(
        WallDistance(min_mm=0.0, selection=Selection(state="go", settle_s=0.0)), record
    )
    assert verdict.passed
    assert verdict.relative_margin is None


def test_a_wall_distance_in_a_state_never_entered_fails_with_no_margin() -> None:
    record = _record(_north(3.0), world=CORRIDOR_SIDE)
    assert _judge(
        WallDistance(min_mm=150.0, selection=Selection(state="follow")), record
    ) == Verdict("wall_distance", False, "", None, "the mission never entered state 'follow'")
