"""``grade --prairielearn``: PrairieLearn's external-grader results.json, its score and tests."""

from __future__ import annotations

import json
from pathlib import Path

from hand_graded import HIDDEN_SECRETS, hand_report, one_student
from helpers import MISSIONS, run_cli

from roboscript.grading.gradescope import gradescope_results, no_submission_results
from roboscript.grading.prairielearn import prairielearn_results


def test_the_score_is_the_share_of_points_and_each_run_is_a_test(tmp_path: Path) -> None:
    report = one_student(hand_report(tmp_path), "Quentin")
    results = prairielearn_results(report)
    gradescope = gradescope_results(report)
    assert results["gradable"] is True
    assert results["score"] == round(gradescope["score"] / 12, 4) and 0 <= results["score"] <= 1
    assert [t["max_points"] for t in results["tests"]] == [4.0, 4.0, 4.0]
    assert [t["points"] for t in results["tests"]] == [t["score"] for t in gradescope["tests"]]
    assert [t["message"] for t in results["tests"]] == [t["status"] for t in gradescope["tests"]]
    assert results["tests"][2]["name"] == "square-50cm: hidden run 3"
    assert results["message"] == gradescope["output"]


def test_no_hidden_detail_reaches_the_student(tmp_path: Path) -> None:
    text = json.dumps(prairielearn_results(one_student(hand_report(tmp_path), "Quentin")))
    for secret in HIDDEN_SECRETS:
        assert secret not in text, secret


def test_a_submission_without_points_scores_zero(tmp_path: Path) -> None:
    results = no_submission_results(hand_report(tmp_path).specs, "no mission")
    from_cli = tmp_path / "results.json"
    submission = tmp_path / "student"
    submission.mkdir()
    (submission / "notes.txt").write_text("nothing\n", encoding="utf-8")
    done = run_cli(
        "grade", str(MISSIONS / "teacher" / "square" / "test.yaml"), "--mission",
        str(submission), "--prairielearn", str(from_cli),
    )  # fmt: skip
    assert done.returncode == 2
    written = json.loads(from_cli.read_text(encoding="utf-8"))
    assert written["gradable"] is True and written["score"] == 0.0
    assert "no mission files in the folder" in written["message"]
    assert len(written["tests"]) == 3 and results["score"] == 0.0
