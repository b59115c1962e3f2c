"""Reading a spec's ``expect``: units, places of mistakes, weights and run targets."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import (
    STOP_AT_WALL,
    _load,
    _north,
    _record,
    _rules_and_weights,
    _sim_changed,
    _spec,
    _stopped,
    _targets,
)

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    Expectation,
    FinalPose,
    FinalState,
    MaxDuration,
    Outcome,
    PathVisits,
    RunTargets,
    Turns,
    WallAhead,
    Waypoint,
    evaluate,
)
from roboscript.grading.spec import load_test_spec


def test_the_record_is_read_only() -> None:
    record = _record(_north(1.0))
    with pytest.raises(AttributeError):
        record.outcome = "success"  # type: ignore[misc]


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
    assert expectation.for_record(_sim_changed(record, seed=2)) == WallAhead(300.0)
    turned = _sim_changed(record, seed=2, path=((0.0, 102.0, 1.0, 90.0), *record.path[1:]))
    assert expectation.for_record(turned) == WallAhead(100.0)
    assert expectation.for_record(_sim_changed(record, seed=9)) == WallAhead(200.0)
    assert evaluate(expectation, turned).passed  # 10 cm from the front to the wall
    assert not evaluate(expectation, _sim_changed(record, seed=2)).passed


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
    # A generous hang limit: this judges the targets, not the grader's patience on a busy machine.
    results = [
        grade_run(spec, str(mission), variant, hang_after_s=60.0) for variant in spec.variants
    ]
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


@pytest.mark.parametrize(
    ("text", "wanted"),
    [
        (
            "expect:\n  - turns: {angle: 1, total: 0.5, tolerance: 5}\n",
            [(Turns(None, None, 1.0, 0.5, 5.0), 1.0)],
        ),
        ("expect:\n  - turns: {count: 2}\n", [(Turns(count=2), 1.0)]),
        ("expect:\n  - turns: {direction: left}\n", [(Turns(direction="left"), 1.0)]),
        (
            "world: square-room\nexpect:\n  - wall_ahead_at_end: {distance: 0, tolerance: 5}\n",
            [(WallAhead(0.0, 5.0), 1.0)],
        ),
        (
            (
                "expect:\n  - final_pose_within:"
                " {x: 300, y: -20, radius: 50, heading: 90, heading_tolerance: 5}\n"
            ),
            [(FinalPose(300.0, -20.0, 50.0, 90.0, 5.0, "world"), 1.0)],
        ),
        (
            "expect:\n  - final_pose_within: {x: 1, y: 1, radius: 1, relative_to: start}\n",
            [(FinalPose(1.0, 1.0, 1.0, None, 15.0, "start"), 1.0)],
        ),
        (
            "expect:\n  - path_visits: {waypoints: [start], tolerance: 30, in_order: false}\n",
            [(PathVisits((Waypoint(0.0, 0.0),), 30.0, in_order=False), 1.0)],
        ),
        (
            "expect:\n  - path_visits: [{left: 20, back: 30}, {right: 2 cm}]\n",
            [(PathVisits((Waypoint(-30.0, -20.0), Waypoint(0.0, 20.0))), 1.0)],
        ),
        ("expect:\n  - final_state: [a, b]\n", [(FinalState(("a", "b")), 1.0)]),
        ("expect:\n  - {outcome: success, weight: 0.5}\n", [(Outcome("success"), 0.5)]),
        ("expect:\n  - {outcome: success}\n", [(Outcome("success"), 1.0)]),
    ],
)
def test_bare_numbers_read_in_the_documented_unit(
    tmp_path: Path, text: str, wanted: list[tuple[object, float]]
) -> None:
    assert _rules_and_weights(tmp_path, text) == wanted


def test_where_an_expectation_was_written_is_kept(tmp_path: Path) -> None:
    spec = _load(tmp_path, "expect:\n  - outcome: success\n  - {weight: 2, max_duration: 5 s}\n")
    places = [(e.location.path, e.location.line, e.location.col) for e in spec.expectations]
    assert places == [(str(tmp_path / "spec.yaml"), 3, 5), (str(tmp_path / "spec.yaml"), 4, 17)]


def test_a_run_may_change_a_list_that_is_not_a_path(tmp_path: Path) -> None:
    targets = _targets(
        tmp_path,
        "runs:\n  - {seed: 1}\n  - {seed: 2, expect: {final_state: [c]}}\n"
        "expect:\n  - final_state: [a, b]\n",
    )
    assert [params for _, params in targets.runs] == [FinalState(("a", "b")), FinalState(("c",))]


def test_a_run_may_replace_a_short_path_and_keep_the_rest(tmp_path: Path) -> None:
    targets = _targets(
        tmp_path,
        "runs:\n  - {seed: 2, expect: {path_visits: [start]}}\n  - {seed: 3}\n"
        "expect:\n  - path_visits: [{forward: 1 m}]\n",
    )
    assert [params for _, params in targets.runs] == [
        PathVisits((Waypoint(0.0, 0.0),)),
        PathVisits((Waypoint(1000.0, 0.0),)),
    ]


def test_runs_50_mm_apart_are_different_runs(tmp_path: Path) -> None:
    targets = _targets(
        tmp_path,
        "runs:\n  - {seed: 1, start: {x: 50 mm}, expect: {max_duration: 20 s}}\n  - {seed: 1}\n"
        "expect:\n  - max_duration: 30 s\n",
    )
    assert [params for _, params in targets.runs] == [MaxDuration(20.0), MaxDuration(30.0)]


@pytest.mark.parametrize(
    ("text", "error"),
    [
        (
            "expect:\n  - check: lap\n",
            "3:12: error: check is written 'file.py:function' (a Python file beside the spec)",
        ),
        (
            "expect:\n  - check: 5\n",
            "3:12: error: check is written 'file.py:function' (a Python file beside the spec)",
        ),
        (
            "expect:\n  - check: 'laps.py:la p'\n",
            "3:12: error: 'la p' is not a Python function name",
        ),
        ("expect:\n  - check: 'laps.py:lap:'\n", "3:12: error: '' is not a Python function name"),
        (
            "expect:\n  - check: 'notes.txt:lap'\n",
            "3:12: error: no Python file 'notes.txt' next to the spec",
        ),
        (
            "expect:\n  - check: 'missing.py:lap'\n",
            "3:12: error: no Python file 'missing.py' next to the spec",
        ),
        (
            "expect:\n  - check: 'broken.py:lap'\n",
            "3:12: error: cannot read broken.py: invalid syntax (broken.py, line 1)",
        ),
        (
            "expect:\n  - check: 'laps.py:lop'\n",
            "3:12: error: laps.py has no function 'lop' (did you mean 'lap'?)",
        ),
        ("expect:\n  - turns: 5\n", "3:12: error: turns must be a mapping such as {turns: ...}"),
        (
            "expect:\n  - turns: {angle: 90, directon: left}\n",
            "3:24: error: unknown key 'directon' in turns (did you mean 'direction'?)",
        ),
        (
            "expect:\n  - turns: {tolerance: 5 deg}\n",
            (
                "3:12: error: turns needs at least one of: direction, count, angle, total, such as"
                " {direction: right, count: 4, angle: 90 deg}"
            ),
        ),
        (
            "expect:\n  - turns: {total: 0 deg}\n",
            (
                "3:20: error: 'total' is a size, more than 0; say which way with direction: left or"
                " right"
            ),
        ),
        (
            "world: corridor\nexpect:\n  - wall_distance: 5\n",
            "4:20: error: wall_distance must be a mapping such as {wall_distance: ...}",
        ),
        (
            "world: corridor\nexpect:\n  - wall_distance: {state: a, min: 1, sied: left}\n",
            "4:39: error: unknown key 'sied' in wall_distance (did you mean 'side'?)",
        ),
        (
            "world: square-room\nexpect:\n  - wall_ahead_at_end: 5\n",
            "4:24: error: wall_ahead_at_end must be a mapping such as {wall_ahead_at_end: ...}",
        ),
        (
            "world: square-room\nexpect:\n  - wall_ahead_at_end: {tolerance: 2 cm}\n",
            "4:24: error: wall_ahead_at_end needs 'distance'",
        ),
        (
            "world: square-room\nexpect:\n  - wall_ahead_at_end: {distance: -1 cm}\n",
            "4:35: error: 'distance' cannot be negative",
        ),
        (
            "expect:\n  - final_pose_within: 5\n",
            "3:24: error: final_pose_within must be a mapping such as {final_pose_within: ...}",
        ),
        (
            "expect:\n  - final_pose_within: {x: 1, y: 1, radius: 1, heading_tolerance: 5}\n",
            "3:48: error: heading_tolerance needs a heading to compare with",
        ),
        (
            "expect:\n  - final_pose_within: {x: 1, y: 1}\n",
            "3:24: error: final_pose_within needs 'radius'",
        ),
        (
            "expect:\n  - 5\n",
            "3:5: error: an expectation is KIND: VALUE, such as - outcome: success (got 5)",
        ),
        (
            "expect:\n  - {outcome: success, max_duration: 5 s}\n",
            (
                "3:5: error: an expectation has exactly one of: outcome, final_state,"
                " final_pose_within, regions_in_order, never_enter, no_collisions, tones,"
                " max_duration, wall_distance, path_visits, turns, wall_ahead_at_end, check"
            ),
        ),
        (
            "expect:\n  - {outcom: success}\n",
            "3:6: error: unknown expectation 'outcom' (did you mean 'outcome'?)",
        ),
        (
            "expect:\n  - {speed: 5}\n",
            (
                "3:6: error: unknown expectation 'speed' (expected one of: outcome, final_state,"
                " final_pose_within, regions_in_order, never_enter, no_collisions, tones,"
                " max_duration, wall_distance, path_visits, turns, wall_ahead_at_end, check)"
            ),
        ),
        (
            "expect:\n  - {outcome: success, weight: 0}\n",
            "3:32: error: weight must be a number above 0",
        ),
        (
            "expect:\n  - {outcome: success, weight: true}\n",
            "3:32: error: weight must be a number above 0",
        ),
        (
            "expect:\n  - {outcome: success, weight: '2'}\n",
            "3:32: error: weight must be a number above 0",
        ),
        (
            "expect:\n  - path_visits: {tolerance: 30}\n",
            "3:18: error: path_visits needs 'waypoints'",
        ),
        (
            "expect:\n  - path_visits: {waypoints: [start], in_order: 'no'}\n",
            "3:49: error: 'in_order' must be true or false (got 'no')",
        ),
        (
            "expect:\n  - path_visits: {waypoints: 5}\n",
            (
                "3:30: error: path_visits lists waypoints, such as [{forward: 50 cm},"
                " {forward: 50 cm, right: 50 cm}]"
            ),
        ),
        (
            "expect:\n  - path_visits: [{}]\n",
            "3:19: error: a waypoint needs forward, back, right or left (or write 'start')",
        ),
        (
            "expect:\n  - path_visits: [5]\n",
            (
                "3:19: error: a waypoint is written {forward: 50 cm, right: 20 cm} (or back, left),"
                " or 'start' (got 5)"
            ),
        ),
        (
            "expect:\n  - path_visits: [{right: 1, left: 2}]\n",
            "3:30: error: give either right or left, not both (a negative right is left)",
        ),
        (
            "expect:\n  - final_state: 5\n",
            "3:18: error: 'final_state' must be a name or a list of names such as [a, b]",
        ),
        (
            "world: square-room\nexpect:\n  - regions_in_order: [nowhere]\n",
            (
                "4:24: error: the world 'square-room' has no region 'nowhere' (its regions: centre,"
                " north-wall)"
            ),
        ),
        (
            "world: square-room\nexpect:\n  - regions_in_order: 5\n",
            "4:23: error: 'regions_in_order' must be a name or a list of names such as [a, b]",
        ),
        (
            "world: empty\nexpect:\n  - never_enter: [pit]\n",
            "4:19: error: the world 'empty' has no region 'pit' (its regions: none)",
        ),
        (
            "world: square-room\nexpect:\n  - never_enter: 5\n",
            "4:18: error: 'never_enter' must be a name or a list of names such as [a, b]",
        ),
        # a run's own targets
        (
            "runs:\n  - {seed: 2, expect: 5}\n  - {seed: 3}\nexpect:\n  - outcome: success\n",
            (
                "3:23: error: a run's expect changes the targets of the spec's expectations,"
                " such as expect: {final_pose_within: {x: 30 cm}}"
            ),
        ),
        (
            "runs:\n  - {seed: 2, expect: {}}\nexpect:\n  - outcome: success\n",
            (
                "3:23: error: a run's expect changes the targets of the spec's expectations,"
                " such as expect: {final_pose_within: {x: 30 cm}}"
            ),
        ),
        (
            "runs:\n  - {seed: 2, expect: {weight: 2}}\nexpect:\n  - outcome: success\n",
            "3:24: error: a run cannot change weights, only targets",
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {check: 'laps.py:lap'}}\n"
                "expect:\n  - check: 'laps.py:lap'\n"
            ),
            (
                "3:24: error: a run cannot change a check; your function gets the run's record"
                " (its seed, start and world) to judge by"
            ),
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {tones: {count: 1}}}\n"
                "expect:\n  - outcome: success\n  - max_duration: 5 s\n"
            ),
            (
                "3:24: error: the spec expects no 'tones' for this run to change (a run changes the"
                " targets of the spec's own expectations: outcome, max_duration)"
            ),
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {tone: {count: 1}}}\n"
                "expect:\n  - outcome: success\n  - max_duration: 5 s\n"
            ),
            (
                "3:24: error: the spec expects no 'tone' for this run to change (a run changes the"
                " targets of the spec's own expectations: outcome, max_duration)"
                " (did you mean 'tones'?)"
            ),
        ),
        (
            "runs:\n  - {seed: 2, expect: {max_duration: -5 s}}\nexpect:\n  - max_duration: 5 s\n",
            "3:38: error: 'max_duration' must be more than 0",
        ),
        (
            (
                "runs:\n  - {seed: 2, expect: {path_visits: {in_order: 'x'}}}\n"
                "expect:\n  - path_visits: [{forward: 1 m}]\n"
            ),
            "3:48: error: 'in_order' must be true or false (got 'x')",
        ),
        (
            (
                "runs:\n  - {seed: 1, start: {x: 40 mm}, expect: {max_duration: 20 s}}\n"
                "  - {seed: 1}\nexpect:\n  - max_duration: 30 s\n"
            ),
            (
                "3:42: error: runs 1 and 2 have the same world, seed and start, but different"
                " 'max_duration' targets; give them different seeds"
            ),
        ),
        (
            (
                "runs:\n  - {seed: 1}\n  - {seed: 1, expect: {max_duration: 20 s}}\n"
                "expect:\n  - max_duration: 30 s\n"
            ),
            (
                "4:23: error: runs 1 and 2 have the same world, seed and start, but different"
                " 'max_duration' targets; give them different seeds"
            ),
        ),
    ],
)
def test_each_mistake_is_one_located_line(folder: Path, text: str, error: str) -> None:
    with pytest.raises(SpecError) as caught:
        _load(folder, text)
    assert caught.value.format() == f"{folder / 'spec.yaml'}:{error}"


def test_a_record_gets_the_targets_of_the_run_whose_start_is_nearest() -> None:
    runs = (
        (("room", 2, (0.0, 0.0, 0.0)), WallAhead(100.0)),
        (("room", 2, (300.0, 0.0, 0.0)), WallAhead(200.0)),
        (("room", 2, (0.0, 300.0, 0.0)), WallAhead(300.0)),
        (("room", 2, (105.0, 0.0, 10.0)), WallAhead(400.0)),
    )
    expectation = Expectation(WallAhead(1.0), targets=RunTargets(WallAhead(1.0), runs))
    base = _sim_changed(_stopped(0.0, 500.0, 90.0), seed=2)
    chosen = []
    for start in ((290.0, 5.0, 0.0), (5.0, 290.0, 0.0), (0.0, 0.0, 10.0), (0.0, 0.0, 0.0)):
        record = _sim_changed(base, path=((0.0, *start), *base.path[1:]))
        rule = expectation.for_record(record)
        assert isinstance(rule, WallAhead)
        chosen.append(rule.distance_mm)
    # (0, 0, 10°) is 10° from the first start (100 at 10 mm a degree), 105 mm from the last
    assert chosen == [200.0, 300.0, 100.0, 100.0]
