"""Scores a teacher can explain: partial credit only for a run that ended normally."""

from __future__ import annotations

from pathlib import Path

from roboscript.grading.record import Verdict
from roboscript.grading.run import grade_run, run_message, run_score
from roboscript.grading.spec import TestSpec, load_test_spec

SPEC = """\
test: scores
world: empty
robot: mirto
runs:
  - {seed: 1}
max_time: 10 s
expect:
  - outcome: success
  - no_collisions: true
"""


def _spec(tmp_path: Path, text: str = SPEC) -> TestSpec:
    path = tmp_path / "test.yaml"
    path.write_text(text, encoding="utf-8")
    return load_test_spec(path)


def _mission(tmp_path: Path, name: str, text: str) -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


GIVES_UP = """\
mission: gives-up
initial: go
states:
  go:
    do: {drive: {distance: 10 cm}}
    on: {done: gave_up}
  gave_up:
    final: failure
"""

NEVER_ENDS = """\
mission: never-ends
initial: wait
states:
  wait:
    do: {wait: {duration: 60 min}}
    on: {done: finished}
  finished:
    final: success
"""

RAISES = """\
from roboscript import Action, Mission, state


class Boom(Action):
    name = "boom"
    params = ()

    def update(self, ctx):
        return 1 / 0


class Crash(Mission):
    go = state(Boom(), initial=True, on_done="end")
    end = state(final="success")
"""


def test_a_mission_that_ends_in_its_own_failure_state_gets_partial_credit(
    tmp_path: Path,
) -> None:
    spec = _spec(tmp_path)
    result = grade_run(spec, _mission(tmp_path, "m.yaml", GIVES_UP), spec.variants[0])
    assert result.status == "failed"
    assert result.score == 0.5  # no_collisions held; outcome did not
    assert result.record is not None and result.record.final_state == "gave_up"


def test_a_mission_that_runs_out_of_time_scores_nothing(tmp_path: Path) -> None:
    spec = _spec(tmp_path)
    result = grade_run(spec, _mission(tmp_path, "m.yaml", NEVER_ENDS), spec.variants[0])
    assert result.status == "failed"
    assert result.score == 0.0
    assert [v.name for v in result.verdicts if v.passed] == ["no_collisions"]  # still shown
    assert result.record is not None
    assert result.record.reason == "the mission did not finish within 10 s"
    assert result.record.duration_s == 10.0  # its whole limit, to the tick at the limit


def test_a_run_out_of_time_that_meets_every_expectation_passes(tmp_path: Path) -> None:
    spec = _spec(tmp_path, SPEC.replace("  - outcome: success\n", ""))
    result = grade_run(spec, _mission(tmp_path, "m.yaml", NEVER_ENDS), spec.variants[0])
    assert (result.status, result.score) == ("passed", 1.0)


def test_a_mission_whose_own_code_raises_is_a_crash_scoring_nothing(tmp_path: Path) -> None:
    spec = _spec(tmp_path)
    result = grade_run(spec, _mission(tmp_path, "m.py", RAISES), spec.variants[0])
    assert (result.status, result.score) == ("crashed", 0.0)
    assert "ZeroDivisionError" in result.message
    assert "m.py:9" in result.message
    assert result.record is not None  # the teacher still sees what the robot did


def test_run_score_weighs_the_verdicts() -> None:
    verdicts = (Verdict("a", True, weight=3), Verdict("b", False, weight=1))
    assert run_score(verdicts) == 0.75
    assert run_score(()) == 0.0


def test_a_failed_required_verdict_scores_the_run_0() -> None:
    held = Verdict("outcome", True, weight=5)
    assert run_score((held, Verdict("path_visits", False, required=True))) == 0.0
    assert run_score((held, Verdict("path_visits", True, required=True))) == 1.0
    assert run_score((held, Verdict("tones", False))) == round(5 / 6, 4)


def test_the_message_names_the_failed_required_verdict_first() -> None:
    verdicts = (
        Verdict("tones", False, "failed by 1 tone"),
        Verdict("path_visits", False, "failed by 4.0 cm", required=True),
    )
    assert run_message(verdicts) == (
        "path_visits failed by 4.0 cm (required: without it the run scores 0)"
        " (and 1 more check failed)"
    )
    assert run_message(verdicts[:1]) == "tones failed by 1 tone"


def test_a_verdict_says_it_is_required_in_its_dictionary_only_when_it_is() -> None:
    plain = Verdict("tones", True)
    assert "required" not in plain.to_dict()
    required = Verdict("path_visits", False, required=True)
    assert required.to_dict()["required"] is True
    assert Verdict.from_dict(required.to_dict()) == required
    assert Verdict.from_dict(plain.to_dict()) == plain
