"""check, turns, wall_ahead_at_end, final_pose_within, path_visits, final_state and the
regions as a teacher writes them in a test spec, and a run's own targets: bare numbers in the
documented unit, and each mistake as the one whole line the teacher reads (place, sentence,
hint). Also the teacher's check function's answers and final_state's verdicts."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.test_expectations import _north, _record

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    CheckFunction,
    Expectation,
    FinalPose,
    FinalState,
    MaxDuration,
    NoCollisions,
    Outcome,
    PathVisits,
    RunTargets,
    Turns,
    WallAhead,
    Waypoint,
    evaluate,
)
from roboscript.grading.record import Verdict
from roboscript.grading.spec import TestSpec, load_test_spec


def _load(tmp_path: Path, text: str) -> TestSpec:
    path = tmp_path / "spec.yaml"
    path.write_text("test: t\n" + text, encoding="utf-8")
    return load_test_spec(path)


def _params(tmp_path: Path, text: str) -> list[tuple[object, float]]:
    return [(e.rule, e.weight) for e in _load(tmp_path, text).expectations]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    (tmp_path / "laps.py").write_text("def lap(record):\n    return True\n", encoding="utf-8")
    (tmp_path / "broken.py").write_text("def lap(:\n", encoding="utf-8")
    (tmp_path / "notes.txt").write_text("def lap(record):\n    return True\n", encoding="utf-8")
    return tmp_path


# ------------------------------------------------------------------- what is read, and how


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
    assert _params(tmp_path, text) == wanted


def test_a_check_is_found_beside_the_spec(folder: Path) -> None:
    params = _params(folder, "expect:\n  - check: 'laps.py:lap'\n")
    assert params == [(CheckFunction(str(folder / "laps.py"), "lap", "laps.py:lap"), 1.0)]


def test_where_an_expectation_was_written_is_kept(tmp_path: Path) -> None:
    spec = _load(tmp_path, "expect:\n  - outcome: success\n  - {weight: 2, max_duration: 5 s}\n")
    places = [(e.location.path, e.location.line, e.location.col) for e in spec.expectations]
    assert places == [(str(tmp_path / "spec.yaml"), 3, 5), (str(tmp_path / "spec.yaml"), 4, 17)]


# ------------------------------------------------------------------------- run targets


def _targets(tmp_path: Path, text: str) -> RunTargets:
    """The run targets of the spec's first expectation."""
    targets = _load(tmp_path, text).expectations[0].targets
    assert targets is not None
    return targets


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


# ---------------------------------------------------------------------- located mistakes


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
        ("expect:\n  - 5\n", "3:5: error: an expectation must be a mapping"),
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


# ----------------------------------------------------------------------------- verdicts


def test_final_state_verdicts_name_what_was_expected() -> None:
    record = _record(_north(5.0), final_state="home")
    wanted = Verdict("final_state", True, detail="ended in 'home' (expected 'home' or 'dock')")
    assert evaluate(Expectation(FinalState(("home", "dock"))), record) == wanted
    missed = evaluate(Expectation(FinalState(("dock",))), record)
    assert missed == Verdict(
        "final_state", False, first_violation_s=5.0, detail="ended in 'home' (expected 'dock')"
    )


def _check_answer(tmp_path: Path, body: str, *, calls: int = 1) -> Verdict:
    checks = tmp_path / "checks.py"
    checks.write_text(
        "import itertools\n"
        "from roboscript.grading.record import Verdict\n"
        "CALLS = itertools.count()\n\n"
        "def helper():\n"
        "    raise ValueError('no lap')\n\n"
        f"def judge(run):\n    calls = next(CALLS)\n    {body}\n",
        encoding="utf-8",
    )
    expectation = Expectation(CheckFunction(str(checks), "judge", "checks.py:judge"))
    verdicts = [evaluate(expectation, _record(_north(5.0))) for _ in range(calls)]
    return verdicts[-1]


FAULT = (
    "the teacher's check returned {}; it must return True/False, (True/False, message) or a Verdict"
)


@pytest.mark.parametrize(
    ("body", "wanted"),
    [
        ("return True", Verdict("check: judge", True)),
        ("return (False, 'too slow')", Verdict("check: judge", False, detail="too slow")),
        (
            "return Verdict('mine', False, 'failed by 2 laps', 1.5, 'one lap')",
            Verdict("check: judge", False, "failed by 2 laps", 1.5, "one lap"),
        ),
        (
            "return helper()",
            Verdict(
                "check: judge",
                False,
                detail="the teacher's check raised ValueError: no lap (checks.py:6)",
            ),
        ),
        ("return (True, 5)", Verdict("check: judge", False, detail=FAULT.format("tuple"))),
        ("return ('yes', 'ok')", Verdict("check: judge", False, detail=FAULT.format("tuple"))),
        ("return (True, 'a', 'b')", Verdict("check: judge", False, detail=FAULT.format("tuple"))),
        ("return [True, 'ok']", Verdict("check: judge", False, detail=FAULT.format("list"))),
    ],
)
def test_a_teachers_check_answers(tmp_path: Path, body: str, wanted: Verdict) -> None:
    assert _check_answer(tmp_path, body) == wanted


def test_a_check_module_is_imported_once_per_grading(tmp_path: Path) -> None:
    verdict = _check_answer(tmp_path, "return (True, f'call {calls}')", calls=3)
    assert verdict.detail == "call 2"  # its state carries from one run to the next


def test_a_check_that_is_no_function_or_no_python_fails_with_a_reason(tmp_path: Path) -> None:
    checks = tmp_path / "values.py"
    checks.write_text("judge = 5\n", encoding="utf-8")
    record = _record(_north(1.0))
    named = evaluate(Expectation(CheckFunction(str(checks), "judge", "x")), record)
    assert named.detail.startswith("the teacher's check raised TypeError: judge is not a function")
    text = tmp_path / "values.txt"
    text.write_text("judge = 5\n", encoding="utf-8")
    odd = evaluate(Expectation(CheckFunction(str(text), "judge", "x")), record)
    assert odd.detail.startswith(f"the teacher's check raised ImportError: cannot import {text}")


def test_outcome_and_no_collisions_read_as_written(tmp_path: Path) -> None:
    params = _params(tmp_path, "expect:\n  - outcome: failure\n  - no_collisions: true\n")
    assert params == [(Outcome("failure"), 1.0), (NoCollisions(), 1.0)]
    with pytest.raises(SpecError) as caught:
        _load(tmp_path, "expect:\n  - outcome: failur\n")
    assert caught.value.format() == (
        f"{tmp_path / 'spec.yaml'}:3:14: error: outcome must be success or failure"
        " (got 'failur') (did you mean 'failure'?)"
    )
