"""Which stretches of a run ``wall_distance`` judges: chosen from the world's record.

The records are hand-made (the helpers of ``runs.py``): a robot driving
north at 100 mm/s along x = 0 in a room whose right wall is at x = 300 mm, so the right side
sensor (80 mm right of the centre) reads 220 mm, inside a 15-25 cm band.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import _north, _record
from helpers import run_cli

from roboscript.grading.expectations import (
    Expectation,
    Selection,
    WallDistance,
    evaluate,
)
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.spec import load_test_spec

Path_ = list[tuple[float, float, float, float]]


def _leaves_the_band_at(t_s: float, t_end: float = 6.0) -> Path_:
    """North along x = 0, then from ``t_s`` on 20 cm further from the right wall (x = -200)."""
    return [(t, -200.0 if t >= t_s else x, y, h) for t, x, y, h in _north(t_end)]


def _judge(selection: Selection, record: RunRecord) -> Verdict:
    rule = WallDistance(min_mm=150.0, max_mm=250.0, selection=selection)
    return evaluate(Expectation(rule), record)


def test_the_whole_run_is_judged_whatever_the_mission_calls_its_states() -> None:
    # 'follow' for the first 3 s only: judged by the state's name, leaving the band after it
    # passes; judged by the world, it fails where the robot left the band.
    record = _record(_leaves_the_band_at(3.0), states=((0.0, "follow"), (3.0, "dash")))
    by_name = _judge(Selection(state="follow", settle_s=0.0), record)
    assert by_name.passed
    whole = _judge(Selection(settle_s=0.0), record)
    assert (whole.passed, whole.first_violation_s, whole.margin) == (
        False,
        3.0,
        "failed by 17.0 cm",
    )
    assert whole.detail == (
        "over the whole run the right gap must stay between 15.0 cm and 25.0 cm;"
        " the worst was 42.0 cm at 3.0 s"
    )


def test_the_whole_run_is_judged_after_its_settling_time() -> None:
    record = _record([(t, -200.0 if t < 1.0 else x, y, h) for t, x, y, h in _north(4.0)])
    assert _judge(Selection(settle_s=1.0), record).passed
    early = _judge(Selection(settle_s=0.9), record)
    assert (early.passed, early.first_violation_s) == (False, 0.9)


def test_a_run_shorter_than_its_settling_time_fails_saying_so() -> None:
    verdict = _judge(Selection(settle_s=5.0), _record(_north(2.0)))
    assert (verdict.passed, verdict.detail) == (
        False,
        "the run ended at 2.0 s, before the 5 s it is given to settle were over",
    )


@pytest.mark.parametrize(
    ("window", "passed", "first_violation_s"),
    [
        ((0.0, 3.0), True, None),  # the window ends as the robot leaves the band
        ((2.0, None), False, 3.0),
        ((None, 3.1), False, 3.0),
        ((3.5, 5.0), False, 3.5),
    ],
)
def test_a_time_window_judges_only_its_moments(
    window: tuple[float | None, float | None], passed: bool, first_violation_s: float | None
) -> None:
    record = _record(_leaves_the_band_at(3.0))
    verdict = _judge(Selection(from_s=window[0], to_s=window[1], settle_s=0.0), record)
    assert (verdict.passed, verdict.first_violation_s) == (passed, first_violation_s)


def test_a_window_after_the_end_of_the_run_fails_saying_so() -> None:
    verdict = _judge(Selection(from_s=8.0, settle_s=0.0), _record(_north(6.0)))
    assert (verdict.passed, verdict.detail) == (False, "the run ended at 6.0 s, before 8.0 s")


def test_a_stretch_of_the_path_is_chosen_by_the_distance_travelled() -> None:
    # 100 mm/s: 30 cm travelled at 3 s, where the robot jumps out of the band (20 cm sideways
    # travel counts too, so it is at 50 cm by the next sample).
    record = _record(_leaves_the_band_at(3.0))
    assert _judge(Selection(to_mm=290.0, settle_s=0.0), record).passed
    after = _judge(Selection(from_mm=100.0, settle_s=0.0), record)
    assert (after.passed, after.first_violation_s) == (False, 3.0)
    assert after.detail.startswith("from 10.0 cm on along its path the right gap must stay")


def test_a_stretch_of_the_path_never_reached_fails_saying_how_far_the_robot_went() -> None:
    verdict = _judge(Selection(from_mm=1000.0, settle_s=0.0), _record(_north(5.0)))
    assert (verdict.passed, verdict.detail) == (
        False,
        "the robot travelled 50.0 cm in all, never 100.0 cm",
    )


def test_a_region_judges_only_while_the_robot_is_inside_it() -> None:
    # Region 'a' is a 10 cm circle round (0, 50 cm), 'b' round (0, 1 m): the robot keeps the
    # band only while inside 'a' (4 s to 6 s).
    path = [(t, -200.0 if not 3.9 <= t <= 6.1 else x, y, h) for t, x, y, h in _north(12.0)]
    inside = _judge(Selection(regions=("a",), settle_s=0.0), _record(path))
    assert inside.passed
    assert inside.detail.startswith("inside 'a' the right gap must stay")
    # Out of the band, the robot is also out of the regions (20 cm west of them): put it back
    # on x = 0 inside 'b' (9 s to 11 s) but with a wall gap judged there too.
    either = [(t, 0.0 if 8.9 <= t <= 11.1 else x, y, h) for t, x, y, h in path]
    assert _judge(Selection(regions=("a", "b"), settle_s=0.0), _record(either)).passed
    late = [(t, -60.0 if t >= 10.0 else x, y, h) for t, x, y, h in either]  # 28 cm from it
    verdict = _judge(Selection(regions=("a", "b"), settle_s=0.0), _record(late))
    assert (verdict.passed, verdict.first_violation_s) == (False, 10.0)
    assert verdict.detail.startswith("inside 'a' or 'b' the right gap must stay")


def test_a_region_never_entered_fails_saying_so() -> None:
    verdict = _judge(Selection(regions=("dot",), settle_s=0.0), _record(_north(5.0)))
    assert (verdict.passed, verdict.detail) == (False, "the robot never entered 'dot'")


def test_selectors_given_together_must_all_hold() -> None:
    record = _record(_leaves_the_band_at(5.0, t_end=8.0))
    early = Selection(from_mm=100.0, to_s=5.0, settle_s=0.0)  # from 1 s to 5 s
    assert _judge(early, record).passed
    late = _judge(Selection(from_s=4.5, to_mm=900.0, settle_s=0.0), record)  # 4.5 s to 7.1 s
    assert (late.passed, late.first_violation_s) == (False, 5.0)
    assert late.detail.startswith("from 4.5 s on, until 90.0 cm along its path the right gap")


def _read(tmp_path: Path, body: str) -> Selection:
    path = tmp_path / "spec.yaml"
    path.write_text(
        f"test: t\nworld: corridor\nexpect:\n  - wall_distance: {{min: 12 cm, {body}}}\n",
        encoding="utf-8",
    )
    rule = load_test_spec(path).expectations[0].rule
    assert isinstance(rule, WallDistance)
    return rule.selection


def test_selectors_read_from_a_spec_with_units(tmp_path: Path) -> None:
    assert _read(tmp_path, "settle: 5 s") == Selection(settle_s=5.0)
    assert _read(tmp_path, "during: whole run") == Selection()
    assert _read(tmp_path, "during: {from: 2 s, to: 0.5 min}") == Selection(from_s=2.0, to_s=30.0)
    assert _read(tmp_path, "along: {from: 50 cm, to: 2.5 m}") == Selection(
        from_mm=500.0, to_mm=2500.0
    )
    assert _read(tmp_path, "in_region: [far-end, start-zone]") == Selection(
        regions=("far-end", "start-zone")
    )
    assert _read(tmp_path, "state: follow, during: {to: 9 s}, settle: 0 s") == Selection(
        to_s=9.0, state="follow", settle_s=0.0
    )


def test_check_locates_a_mistaken_selector_in_a_spec_with_a_suggestion(tmp_path: Path) -> None:
    spec = tmp_path / "corridor.yaml"
    spec.write_text(
        "test: corridor\n"
        "world: corridor\n"
        "expect:\n"
        "  - wall_distance: {min: 12 cm, durin: whole run}\n"
        "  - wall_distance: {min: 12 cm, in_region: far-edn}\n",
        encoding="utf-8",
    )
    result = run_cli("check", str(spec))
    assert result.returncode == 2
    assert f"{spec}:4:33: error: unknown key 'durin' in wall_distance (did you mean 'during'?)" in (
        result.stderr
    )
    assert "Traceback" not in result.stderr
