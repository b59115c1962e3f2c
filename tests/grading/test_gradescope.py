"""``grade --gradescope``: the results.json Gradescope reads, its points, and what students see."""

from __future__ import annotations

import json
import shutil
import zipfile
from pathlib import Path
from typing import Any

import pytest
from hand_graded import HIDDEN_SECRETS, SPEC_TEXT, hand_report, one_student
from helpers import MISSIONS, run_cli

from roboscript.grading.batch import find_specs, find_submissions
from roboscript.grading.gradescope import (
    gradescope_results,
    no_submission_results,
    several_students,
)

# The fields of Gradescope's "Autograder Specifications" this writer uses, and their types.
TOP_FIELDS = {
    "score": float,
    "execution_time": int,
    "output": str,
    "output_format": str,
    "test_output_format": str,
    "visibility": str,
    "stdout_visibility": str,
    "tests": list,
}
TEST_FIELDS = {
    "name": str,
    "number": str,
    "score": float,
    "max_score": float,
    "status": str,
    "output": str,
    "visibility": str,
}
VISIBILITIES = {"hidden", "after_due_date", "after_published", "visible"}
FORMATS = {"text", "html", "simple_format", "md", "ansi"}


def assert_gradescope_shape(results: dict[str, Any]) -> None:
    """Every field is one Gradescope documents, of the type it reads."""
    assert set(results) == set(TOP_FIELDS)
    for key, kind in TOP_FIELDS.items():
        assert isinstance(results[key], int | float if kind is float else kind), key
    assert results["visibility"] in VISIBILITIES
    assert results["stdout_visibility"] in VISIBILITIES
    assert {results["output_format"], results["test_output_format"]} <= FORMATS
    numbers = [t["number"] for t in results["tests"]]
    assert len(set(numbers)) == len(numbers)
    for test in results["tests"]:
        assert set(test) == set(TEST_FIELDS)
        for key, kind in TEST_FIELDS.items():
            assert isinstance(test[key], int | float if kind is float else kind), key
        assert test["status"] in ("passed", "failed")
        assert test["visibility"] in VISIBILITIES
        assert 0 <= test["score"] <= test["max_score"]
    assert abs(results["score"] - sum(t["score"] for t in results["tests"])) < 1e-9
    json.dumps(results)  # and it is JSON


def student_visible_text(results: dict[str, Any]) -> str:
    """What a student can read before grades are published."""
    shown = [results["output"]]
    for test in results["tests"]:
        shown.append(test["name"])
        if test["visibility"] == "visible":
            shown.append(test["output"])
    return "\n".join(shown)


def test_one_test_per_run_with_its_share_of_the_points(tmp_path: Path) -> None:
    results = gradescope_results(one_student(hand_report(tmp_path), "Quentin"))
    assert_gradescope_shape(results)
    tests = results["tests"]
    assert [t["name"] for t in tests] == [
        "square-50cm: seed 1",
        "square-50cm: seed 2, start (300, -200) mm 0°",
        "square-50cm: hidden run 3",
    ]
    assert [t["number"] for t in tests] == ["1.1", "1.2", "1.3"]
    # points: 12 over three runs, 4 each, times each run's score (1, 0 crashed, 0.5)
    assert [(t["score"], t["max_score"], t["status"]) for t in tests] == [
        (4.0, 4.0, "passed"),
        (0.0, 4.0, "failed"),
        (2.0, 4.0, "failed"),
    ]
    assert results["score"] == 6.0
    assert sum(t["max_score"] for t in tests) == 12.0
    assert "Total: 6/12 points." in results["output"]
    assert results["stdout_visibility"] == "hidden"


def test_a_visible_run_tells_the_student_what_went_wrong(tmp_path: Path) -> None:
    crashed = gradescope_results(one_student(hand_report(tmp_path), "Quentin"))["tests"][1]
    assert crashed["visibility"] == "visible"
    assert crashed["output"].startswith("FAILED (crashed), 0 of 4 points")
    assert "ZeroDivisionError: division by zero (square.py:12)" in crashed["output"]
    assert "Traceback" not in crashed["output"]  # the debug field is the teacher's


def test_a_hidden_run_shows_pass_fail_and_the_reason_never_its_seed_or_start(
    tmp_path: Path,
) -> None:
    for student in ("Quentin", "Zelda"):
        results = gradescope_results(one_student(hand_report(tmp_path), student))
        hidden = results["tests"][2]
        assert hidden["visibility"] == "after_published"
        text = json.dumps(results, ensure_ascii=False)  # all of it, whenever it is shown
        for secret in HIDDEN_SECRETS:
            assert secret not in text, (student, secret)
    assert hidden["output"].startswith("PASSED, 4 of 4 points")
    failed = gradescope_results(one_student(hand_report(tmp_path), "Quentin"))["tests"][2]
    assert failed["output"].splitlines()[:2] == [
        "FAILED, 2 of 4 points, score 50%",
        "final_pose_within failed by 41.5 cm",
    ]


def test_no_mission_in_the_submission_still_writes_results(tmp_path: Path) -> None:
    report = hand_report(tmp_path)
    results = no_submission_results(report.specs, "no mission files in the folder sub")
    assert_gradescope_shape(results)
    assert results["score"] == 0.0
    assert sum(t["max_score"] for t in results["tests"]) == 12.0
    assert results["output"].startswith("no mission files in the folder sub.")
    assert results["tests"][2]["name"] == "square-50cm: hidden run 3"


def test_the_cli_writes_results_json_for_one_submission(tmp_path: Path) -> None:
    """As Gradescope's run_autograder runs it: one container, one submission."""
    tests = tmp_path / "source" / "tests"
    tests.mkdir(parents=True)
    # the hidden run starts where the others do, turned: bad.yaml fails it as it fails them
    spec = SPEC_TEXT.replace("seed: 7919, start: {x: 417 mm, y: -173 mm", "seed: 3, start: {x: 0")
    (tests / "square.yaml").write_text(spec, encoding="utf-8")
    submission = tmp_path / "submission"
    submission.mkdir()
    shutil.copy(MISSIONS / "teacher" / "square" / "bad.yaml", submission / "my_square.yaml")
    (submission / "notes.txt").write_text("not a mission\n", encoding="utf-8")
    results_json = tmp_path / "results" / "results.json"
    result = run_cli(
        "grade", str(tests), "--mission", str(submission), "--gradescope", str(results_json),
        "--jobs", "2",
    )  # fmt: skip
    assert result.returncode == 1, result.stderr
    results = json.loads(results_json.read_text(encoding="utf-8"))
    assert_gradescope_shape(results)
    assert [t["name"] for t in results["tests"]] == [
        "square-50cm: seed 1",
        "square-50cm: seed 2, start (300, -200) mm 0°",
        "square-50cm: hidden run 3",
    ]
    # bad.yaml stops after three sides: it ends well, but not where it started (4 × 1/2)
    assert [t["score"] for t in results["tests"]] == [2.0, 2.0, 2.0]
    assert results["score"] == 6.0
    assert [t["visibility"] for t in results["tests"]] == ["visible", "visible", "after_published"]
    text = json.dumps(results, ensure_ascii=False)
    for secret in ("seed 3", "33°", str(tests), "square.yaml"):
        assert secret not in text, secret
    assert results["tests"][2]["output"].splitlines()[1].startswith("final_pose_within failed by")
    assert "hidden run 3" in result.stderr and "seed 3" not in result.stderr  # the CI log
    assert result.stdout.startswith("student") and "\nsubmission  square-50cm" in result.stdout


def _graded_without_a_mission(submission: Path) -> dict[str, Any]:
    """The results.json ``grade --gradescope`` writes for a submission holding no mission
    (exit status 2: the input is refused, and the student still learns why)."""
    results_json = submission.parent / "results.json"
    result = run_cli(
        "grade", str(MISSIONS / "teacher" / "square" / "test.yaml"), "--mission",
        str(submission), "--gradescope", str(results_json),
    )  # fmt: skip
    assert result.returncode == 2
    results: dict[str, Any] = json.loads(results_json.read_text(encoding="utf-8"))
    assert_gradescope_shape(results)
    return results


def test_the_cli_writes_results_json_when_nothing_was_handed_in(tmp_path: Path) -> None:
    submission = tmp_path / "submission"
    submission.mkdir()
    (submission / "readme.txt").write_text("oops\n", encoding="utf-8")
    results = _graded_without_a_mission(submission)
    assert results["score"] == 0 and len(results["tests"]) == 3
    assert "no mission files in the folder" in results["output"]


def test_a_submission_handed_in_as_a_zip_is_told_to_hand_in_the_files_themselves(
    tmp_path: Path,
) -> None:
    submission = tmp_path / "submission"
    submission.mkdir()
    with zipfile.ZipFile(submission / "my robot.zip", "w") as archive:
        archive.write(MISSIONS / "teacher" / "square" / "good.yaml", "square.yaml")
    results = _graded_without_a_mission(submission)
    assert results["score"] == 0
    assert results["output"].startswith(
        "error: no mission files in the folder submission (it holds my robot.zip: a mission is a"
        " .yaml file with 'mission:', 'initial:' and 'states:', or a .py file defining a class"
        " based on Mission, handed in as it is, not in an archive)"
    )
    assert str(tmp_path) not in json.dumps(results)


@pytest.mark.parametrize("platform", ["--gradescope", "--prairielearn"])
def test_a_class_folder_for_a_platform_is_refused_in_one_sentence(
    tmp_path: Path, platform: str
) -> None:
    """Not graded as one student called after the folder, each report overwriting the last."""
    folder = tmp_path / "class"
    folder.mkdir()
    for name in ("ada", "bob", "cyd"):
        shutil.copy(MISSIONS / "teacher" / "square" / "good.yaml", folder / f"{name}.yaml")
    results_json = tmp_path / "results.json"
    result = run_cli(
        "grade", str(MISSIONS / "teacher" / "square" / "test.yaml"), "--mission", str(folder),
        platform, str(results_json),
    )  # fmt: skip
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.stderr
    assert "one student's, with one mission per test" in result.stderr
    assert "holds 3 (ada, bob, cyd)" in result.stderr
    assert result.stdout == ""  # nothing was graded
    results = json.loads(results_json.read_text(encoding="utf-8"))
    summary = results["output" if platform == "--gradescope" else "message"]
    assert results["score"] == 0 and "holds 3 (ada, bob, cyd)" in summary


def test_one_mission_per_test_is_one_gradescope_submission(tmp_path: Path) -> None:
    teacher = MISSIONS / "teacher"
    specs = find_specs([str(teacher / "square" / "test.yaml"), str(teacher / "corridor")])
    submission = tmp_path / "submission"
    submission.mkdir()
    shutil.copy(teacher / "square" / "good.yaml", submission / "square-50cm.yaml")
    shutil.copy(teacher / "corridor" / "good.yaml", submission / "corridor-wall-follow.yaml")
    assert several_students(find_submissions([str(submission)]).submissions, specs) is None
    shutil.copy(teacher / "square" / "bad.yaml", submission / "square-old.yaml")
    assert "holds 3" in (
        several_students(find_submissions([str(submission)]).submissions, specs) or ""
    )
