"""Each expectation judged on hand-made run records: pass or fail, signed margins, first times."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.grading.expectations import (
    CheckFunction,
    Expectation,
    FinalPose,
    Tones,
    WallDistance,
    evaluate,
)
from roboscript.grading.record import Collision, RunRecord, Tone, Verdict
from roboscript.sim.geometry import Segment
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


def _judge(kind: str, params: object, record: RunRecord) -> Verdict:
    return evaluate(Expectation(kind, params), record)


# ------------------------------------------------------------------------------- outcome


def test_outcome_names_the_reason_and_fails_at_the_end() -> None:
    record = _record(_north(3.0), outcome="failure", reason="state 'go' timed out after 3 s")
    verdict = _judge("outcome", "success", record)
    assert not verdict.passed
    assert verdict.first_violation_s == 3.0
    assert verdict.detail == "the mission ended in failure: state 'go' timed out after 3 s"
    assert _judge("outcome", "failure", record).passed


def test_final_state_accepts_any_of_several() -> None:
    record = _record(_north(1.0), final_state="home")
    assert _judge("final_state", ("home", "parked"), record).passed
    assert not _judge("final_state", ("parked",), record).passed


# ---------------------------------------------------------------------------- final pose


def test_final_pose_margin_is_signed_in_centimetres() -> None:
    record = _record(_north(5.0))  # ends at (0, 500)
    near = _judge("final_pose_within", FinalPose(0.0, 521.0, 80.0), record)
    assert near.passed
    assert near.margin == "passed by 5.9 cm"
    assert near.margin_value == pytest.approx(59.0)
    far = _judge("final_pose_within", FinalPose(0.0, 600.0, 80.0), record)
    assert not far.passed
    assert far.margin == "failed by 2.0 cm"
    assert far.first_violation_s == 5.0


def test_final_pose_relative_to_the_start_follows_the_start_heading() -> None:
    # Start at (100, 0) facing east (90°): "50 cm ahead" is (600, 0) in the world.
    path = [(0.0, 100.0, 0.0, 90.0), (5.0, 600.0, 10.0, 90.0)]
    target = FinalPose(0.0, 500.0, 30.0, heading_deg=0.0, relative_to="start")
    verdict = _judge("final_pose_within", target, _record(path))
    assert verdict.passed, verdict.detail
    assert verdict.margin == "passed by 2.0 cm"


def test_final_pose_heading_outside_its_tolerance_fails_in_degrees() -> None:
    path = [(0.0, 0.0, 0.0, 0.0), (2.0, 0.0, 0.0, 40.0)]
    verdict = _judge("final_pose_within", FinalPose(0.0, 0.0, 50.0, 0.0, 15.0), _record(path))
    assert not verdict.passed
    assert verdict.margin == "failed by 25.0°"
    assert verdict.margin_unit == "deg"


# ------------------------------------------------------------------------------- regions


def test_regions_in_order_lists_when_each_was_reached() -> None:
    verdict = _judge("regions_in_order", ("a", "b"), _record(_north(12.0)))
    assert verdict.passed
    assert verdict.detail == "reached 'a' at 4.0 s, 'b' at 9.0 s"


def test_regions_out_of_order_fail_by_the_closest_miss() -> None:
    # Drives north past a and b, so b-then-a never happens after b.
    verdict = _judge("regions_in_order", ("b", "a"), _record(_north(12.0)))
    assert not verdict.passed
    assert verdict.detail.startswith("never reached 'a' after 'b' at 9.0 s")
    assert verdict.margin == "failed by 31.0 cm"  # just after b (y = 910 mm) to a's edge (600)
    assert verdict.first_violation_s is None  # never reaching has no moment


def test_a_fast_robot_cannot_slip_through_a_region_between_samples() -> None:
    # 1 m/s: samples 100 mm apart straddle the 10 mm wide region "dot" at y = 2000 +- 5.
    path = [(round(t * 0.1, 3), 0.0, 1950.0 + t * 100.0, 0.0) for t in range(3)]
    assert _judge("regions_in_order", ("dot",), _record(path)).passed


def test_never_enter_gives_the_first_entry_time_and_depth() -> None:
    # East at 100 mm/s along y = 500 from x = 0: on the pit's edge (x = 500) at 5.0 s, inside
    # from the next sample on.
    path = [(round(i * 0.1, 3), i * 10.0, 500.0, 90.0) for i in range(71)]
    verdict = _judge("never_enter", ("pit",), _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 5.1
    assert verdict.margin == "failed by 10.0 cm"  # deepest: x = 600, the pit's middle
    assert "entered 'pit' at 5.1 s" in verdict.detail


def test_never_enter_passes_by_the_closest_approach() -> None:
    verdict = _judge("never_enter", ("pit",), _record(_north(10.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 50.0 cm"  # x = 0 to the pit's west edge at 500


# ---------------------------------------------------------------------------- collisions


def test_no_collisions_fails_at_the_first_collision() -> None:
    hits = (Collision(2.5, 200.0, 250.0, "right"), Collision(4.0, 200.0, 400.0, "right"))
    verdict = _judge("no_collisions", True, _record(_north(5.0), collisions=hits))
    assert not verdict.passed
    assert verdict.first_violation_s == 2.5
    assert verdict.margin == "failed by 2 collisions"
    assert "the first at 2.5 s on the right bumper" in verdict.detail


def test_no_collisions_passes_by_the_clearance_to_the_nearest_wall() -> None:
    # Centre at x = 0, walls at +-300, body radius 100: 20 cm to spare.
    verdict = _judge("no_collisions", True, _record(_north(5.0)))
    assert verdict.passed
    assert verdict.margin == "passed by 20.0 cm"


# ---------------------------------------------------------------------------------- tones


def _tones(*pairs: tuple[float, float]) -> tuple[Tone, ...]:
    return tuple(Tone(t, f, 0.2) for t, f in pairs)


def test_tone_count_too_many_fails_when_the_extra_one_plays() -> None:
    played = _tones((1.0, 880), (2.0, 880), (3.0, 880))
    verdict = _judge("tones", Tones(count=2), _record(_north(5.0), tones=played))
    assert not verdict.passed
    assert verdict.first_violation_s == 3.0
    assert verdict.margin == "failed by 1 tone"


def test_tone_count_too_few_has_no_moment() -> None:
    verdict = _judge("tones", Tones(count=4), _record(_north(5.0), tones=_tones((1.0, 880))))
    assert not verdict.passed
    assert verdict.first_violation_s is None
    assert verdict.margin == "failed by 3 tones"
    assert verdict.detail.startswith("3 tones too few")


def test_tone_frequencies_in_order_within_tolerance() -> None:
    played = _tones((1.0, 440), (2.0, 882), (3.0, 660))
    record = _record(_north(5.0), tones=played)
    assert _judge("tones", Tones(frequencies_hz=(440.0, 880.0, 660.0)), record).passed
    wrong = _judge("tones", Tones(frequencies_hz=(440.0, 660.0, 880.0)), record)
    assert not wrong.passed
    assert wrong.first_violation_s == 2.0
    assert wrong.margin == "failed by 222 Hz"
    assert "tone 2 was 882 Hz, expected 660 Hz" in wrong.detail


def test_tone_min_and_max_count() -> None:
    record = _record(_north(5.0), tones=_tones((1.0, 880), (2.0, 880)))
    assert _judge("tones", Tones(min_count=1, max_count=3), record).passed
    assert not _judge("tones", Tones(min_count=3), record).passed


# ------------------------------------------------------------------------------ duration


def test_max_duration_margin_in_seconds() -> None:
    assert _judge("max_duration", 30.0, _record(_north(20.0))).margin == "passed by 10.0 s"
    late = _judge("max_duration", 30.0, _record(_north(30.4)))
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
    rule = WallDistance("follow", "right", 150.0, 250.0, settle_s=1.0)
    verdict = _judge("wall_distance", rule, _record(_drifting_right(), states=states))
    assert not verdict.passed
    # Below 150 mm once x > 70, i.e. after 5.4 s: the first sample past it is 5.5 s.
    assert verdict.first_violation_s == pytest.approx(5.5)
    # The worst: at 7.9 s (the last sample before the run ends), x = 195: a gap of 25 mm.
    assert verdict.margin == "failed by 12.5 cm"
    assert "the worst was 2.5 cm at 7.9 s" in verdict.detail


def test_wall_distance_passes_by_the_tightest_sample_after_settling() -> None:
    states = ((0.0, "follow"), (4.0, "stop"))
    rule = WallDistance("follow", "right", 150.0, 250.0, settle_s=1.0)
    verdict = _judge("wall_distance", rule, _record(_drifting_right(), states=states))
    assert verdict.passed
    assert verdict.margin == "passed by 3.0 cm"  # 220 mm: 30 mm inside the top of the band
    assert verdict.relative_margin == pytest.approx(30.0 / 50.0)


def test_wall_distance_skips_the_settling_time() -> None:
    # Far from the wall for the first 0.5 s of the state, then in the band.
    path = [(round(i * 0.1, 3), -200.0 if i < 5 else 0.0, i * 10.0, 0.0) for i in range(30)]
    rule = WallDistance("go", "right", 150.0, 250.0, settle_s=0.5)
    assert _judge("wall_distance", rule, _record(path)).passed
    strict = WallDistance("go", "right", 150.0, 250.0, settle_s=0.0)
    verdict = _judge("wall_distance", strict, _record(path))
    assert not verdict.passed
    assert verdict.first_violation_s == 0.0


def test_wall_distance_on_the_left_and_a_state_never_entered() -> None:
    rule = WallDistance("go", "left", 150.0, 250.0, settle_s=0.0)
    assert _judge("wall_distance", rule, _record(_north(3.0))).passed  # left wall: 220 mm
    missing = WallDistance("follow", "right", 150.0, 250.0)
    verdict = _judge("wall_distance", missing, _record(_north(3.0)))
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
        Expectation("check", CheckFunction(str(checks), "judge", "checks.py:judge"), 2.0),
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
