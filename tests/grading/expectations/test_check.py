"""``check``: a teacher's own function, found beside the spec and run on the record."""

from __future__ import annotations

from pathlib import Path

import pytest
from grading.expectations.runs import FAULT, _check_answer, _north, _record, _rules_and_weights

from roboscript.grading.expectations import (
    CheckFunction,
    Expectation,
    evaluate,
)
from roboscript.grading.record import Verdict


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


def test_a_check_is_found_beside_the_spec(folder: Path) -> None:
    params = _rules_and_weights(folder, "expect:\n  - check: 'laps.py:lap'\n")
    assert params == [(CheckFunction(str(folder / "laps.py"), "lap", "laps.py:lap"), 1.0)]


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
                teachers_fault=True,
            ),
        ),
        (
            "return (True, 5)",
            Verdict("check: judge", False, detail=FAULT.format("tuple"), teachers_fault=True),
        ),
        (
            "return ('yes', 'ok')",
            Verdict("check: judge", False, detail=FAULT.format("tuple"), teachers_fault=True),
        ),
        (
            "return (True, 'a', 'b')",
            Verdict("check: judge", False, detail=FAULT.format("tuple"), teachers_fault=True),
        ),
        (
            "return [True, 'ok']",
            Verdict("check: judge", False, detail=FAULT.format("list"), teachers_fault=True),
        ),
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


def test_a_check_that_never_returns_is_stopped_and_fails_with_where(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A loop that never ends in the teacher's check used to stall the class's grading for good.
    monkeypatch.setattr("roboscript.grading.expectations.check.CHECK_LIMIT_S", 0.3)
    checks = tmp_path / "loops.py"
    checks.write_text("def judge(run):\n    while True:\n        pass\n", encoding="utf-8")
    verdict = evaluate(
        Expectation(CheckFunction(str(checks), "judge", "loops.py:judge")),
        _record(_north(5.0)),
    )
    assert not verdict.passed
    assert verdict.detail == (
        "the teacher's check did not return within 0.3 s (stopped at loops.py:2): is there a"
        " loop in it that never ends?"
    )
