"""Required expectations: read from a spec, with mistakes located, and carried by verdicts."""

from __future__ import annotations

from pathlib import Path

import pytest

from roboscript.errors import SpecError
from roboscript.grading.expectations import Expectation, Outcome, Tones, evaluate
from roboscript.grading.record import RunRecord, RunResult, Verdict
from roboscript.grading.spec import TestSpec, load_test_spec


def _load(tmp_path: Path, expect: str, runs: str = "") -> TestSpec:
    path = tmp_path / "spec.yaml"
    path.write_text(f"test: t\n{runs}expect:\n{expect}", encoding="utf-8")
    return load_test_spec(path)


def test_required_is_read_beside_the_kind_and_weight(tmp_path: Path) -> None:
    spec = _load(
        tmp_path,
        "  - {outcome: success, required: true}\n"
        "  - tones: {count: 4}\n"
        "    weight: 2\n"
        "    required: false\n"
        "  - max_duration: 5 s\n",
    )
    assert [(e.rule, e.weight, e.required) for e in spec.expectations[:2]] == [
        (Outcome("success"), 1.0, True),
        (Tones(count=4), 2.0, False),
    ]
    assert not spec.expectations[2].required


def test_a_required_verdict_carries_it() -> None:
    record = RunRecord.simulated(
        mission="m",
        robot="mirto",
        world_name="empty",
        seed=1,
        outcome="failure",
        final_state="x",
        reason=None,
        duration_s=1.0,
        states=(),
        path=(),
    )
    verdict = evaluate(Expectation(Outcome("success"), 2.0, required=True), record)
    assert (verdict.name, verdict.passed, verdict.weight, verdict.required) == (
        "outcome",
        False,
        2.0,
        True,
    )


@pytest.mark.parametrize(
    ("expect", "runs", "error"),
    [
        (
            "  - {outcome: success, required: yes}\n",
            "",
            (
                "3:34: error: 'required' must be true or false (got 'yes'); a run that fails a"
                " required expectation scores 0"
            ),
        ),
        (
            "  - {outcome: success, requird: true}\n",
            "",
            "3:24: error: unknown key 'requird' in an expectation (did you mean 'required'?)",
        ),
        (
            "  - {outcome: success, required: true}\n",
            "runs:\n  - {seed: 1, expect: {required: false}}\n",
            "3:24: error: a run cannot change what is required, only targets",
        ),
    ],
)
def test_mistakes_in_required_are_located(
    tmp_path: Path, expect: str, runs: str, error: str
) -> None:
    with pytest.raises(SpecError) as caught:
        _load(tmp_path, expect, runs)
    assert caught.value.format() == f"{tmp_path / 'spec.yaml'}:{error}"


def test_the_spec_summary_says_which_expectations_are_required(tmp_path: Path) -> None:
    spec = _load(tmp_path, "  - {outcome: success, required: true}\n  - max_duration: 5 s\n")
    assert spec.to_dict()["expect"] == [
        {"name": "outcome", "weight": 1.0, "required": True},
        {"name": "max_duration", "weight": 1.0},
    ]


def test_reports_show_the_failed_required_expectation_as_the_worst() -> None:
    result = RunResult(
        "amy",
        "t",
        0,
        "seed 1",
        1,
        "m.yaml",
        "failed",
        verdicts=(
            Verdict("final_pose_within", False, "failed by 4.0 cm"),
            Verdict("path_visits", False, "failed by 2.0 cm", required=True),
        ),
    )
    assert result.worst_verdict() == result.verdicts[1]
    plain = RunResult("amy", "t", 0, "seed 1", 1, "m.yaml", "failed", verdicts=result.verdicts[:1])
    assert plain.worst_verdict() == result.verdicts[0]
