"""``outcome`` and ``final_state``: how the mission says it ended."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import _judge, _load, _north, _record, _rules_and_weights, _verdict

from roboscript.errors import SpecError
from roboscript.grading.expectations import (
    Expectation,
    FinalState,
    NoCollisions,
    Outcome,
    evaluate,
)
from roboscript.grading.record import Verdict


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


def test_final_state_verdicts_name_what_was_expected() -> None:
    record = _record(_north(5.0), final_state="home")
    wanted = Verdict("final_state", True, detail="ended in 'home' (expected 'home' or 'dock')")
    assert evaluate(Expectation(FinalState(("home", "dock"))), record) == wanted
    missed = evaluate(Expectation(FinalState(("dock",))), record)
    assert missed == Verdict(
        "final_state", False, first_violation_s=5.0, detail="ended in 'home' (expected 'dock')"
    )


def test_an_outcome_as_wanted_has_no_moment_of_failure() -> None:
    record = _record(_north(2.0), outcome="success", final_state="done")
    wanted = _verdict("outcome", True, "", None, "the mission ended in success in state 'done'")
    assert _judge(Outcome("success"), record) == wanted


def test_the_outcome_names_the_final_state_when_there_is_no_reason() -> None:
    record = _record(_north(2.0), outcome="failure", final_state="stuck")
    wanted = _verdict("outcome", False, "", 2.0, "the mission ended in failure in state 'stuck'")
    assert _judge(Outcome("success"), record) == wanted


def test_outcome_and_no_collisions_read_as_written(tmp_path: Path) -> None:
    params = _rules_and_weights(
        tmp_path, "expect:\n  - outcome: failure\n  - no_collisions: true\n"
    )
    assert params == [(Outcome("failure"), 1.0), (NoCollisions(), 1.0)]
    with pytest.raises(SpecError) as caught:
        _load(tmp_path, "expect:\n  - outcome: failur\n")
    assert caught.value.format() == (
        f"{tmp_path / 'spec.yaml'}:3:14: error: outcome must be success or failure"
        " (got 'failur') (did you mean 'failure'?)"
    )
