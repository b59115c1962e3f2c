"""The teacher specs in missions/teacher/: the good solution passes every run, the bad one fails
every run, for the mistake it was written to show."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import MISSIONS, run_cli

TEACHER = MISSIONS / "teacher"

# test folder -> the expectation that catches the bad solution's mistake on its first run
MISTAKES = {
    "square": "final_pose_within",  # stops after three sides (visits.side >= 3)
    "corridor": "wall_distance",  # 'distance: 20' is 20 mm, not 20 cm: it scrapes the wall
    "line-track": "check: stays_on_line",  # drives a rectangle "by heart" instead of following
}


def test_every_teacher_test_has_a_good_and_a_bad_solution() -> None:
    folders = sorted(p.parent.name for p in TEACHER.glob("*/test.yaml"))
    assert folders == sorted(MISTAKES)
    for name in folders:
        assert (TEACHER / name / "good.yaml").is_file()
        assert (TEACHER / name / "bad.yaml").is_file()


def _grade(folder: str, solution: str) -> dict[str, object]:
    result = run_cli(
        "grade",
        str(TEACHER / folder / "test.yaml"),
        "--mission",
        str(TEACHER / folder / f"{solution}.yaml"),
        "--json",
    )
    assert result.returncode in (0, 1), result.stderr
    report: dict[str, object] = json.loads(result.stdout)
    return report


@pytest.mark.parametrize("folder", sorted(MISTAKES))
def test_the_good_solution_passes_every_run(folder: str) -> None:
    report = _grade(folder, "good")
    runs = report["runs"]
    assert isinstance(runs, list) and len(runs) >= 2
    assert [r["status"] for r in runs] == ["passed"] * len(runs), [r["message"] for r in runs]


@pytest.mark.parametrize("folder", sorted(MISTAKES))
def test_the_bad_solution_fails_every_run_for_its_mistake(folder: str) -> None:
    report = _grade(folder, "bad")
    runs = report["runs"]
    assert isinstance(runs, list)
    assert all(r["status"] == "failed" for r in runs)
    failed = [v["name"] for v in runs[0]["verdicts"] if not v["passed"]]
    assert MISTAKES[folder] in failed


def test_teacher_specs_are_not_examples_for_the_mission_tests() -> None:
    # tests/test_missions.py runs missions/*.yaml; the teacher folder must stay out of it.
    top_level = {p.name for p in MISSIONS.glob("*.yaml")}
    assert not any(Path(name).stem in {"test", "good", "bad"} for name in top_level)
