"""The practice grade (the browser page's): the grader's runs in one process, judged the same."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers import MISSIONS

from roboscript.grading.cell import Cell
from roboscript.grading.practice import practice_grade, practice_run
from roboscript.grading.run import grade_run
from roboscript.grading.spec import load_test_spec

TEACHER = MISSIONS / "teacher"


@pytest.mark.parametrize(
    ("test", "mission"),
    [("square", "good.yaml"), ("square", "bad.yaml"), ("line-track", "bad.yaml")],
)
def test_a_practice_run_is_judged_as_the_grader_judges_it(test: str, mission: str) -> None:
    spec = load_test_spec(TEACHER / test / "test.yaml")
    path = str(TEACHER / test / mission)
    for variant in spec.variants:
        practised = practice_run(spec, path, variant).result
        graded = grade_run(spec, path, variant)
        assert graded.record is not None and practised.record is not None
        assert practised.record.to_dict() == graded.record.to_dict()
        assert [v.to_dict() for v in practised.verdicts] == [v.to_dict() for v in graded.verdicts]
        assert (practised.status, practised.message, practised.score) == (
            graded.status,
            graded.message,
            graded.score,
        )


def test_a_practice_grade_adds_up_the_points_as_the_class_report_does() -> None:
    spec = load_test_spec(TEACHER / "line-track" / "test.yaml")
    cell, runs = practice_grade(spec, str(TEACHER / "line-track" / "bad.yaml"), student="ada")
    assert isinstance(cell, Cell) and cell.student == "ada"
    assert [r.result.score for r in runs] == [0.8, 0.8, 0.0]
    assert cell.points == 1.6 and cell.max_points == 3.0
    assert all(r.recording is not None and r.recording.frames for r in runs)


def test_a_mission_that_does_not_load_is_invalid_on_every_run_and_tried_once(
    tmp_path: Path,
) -> None:
    spec = load_test_spec(TEACHER / "square" / "test.yaml")
    broken = tmp_path / "square.yaml"
    good = (TEACHER / "square" / "good.yaml").read_text(encoding="utf-8")
    broken.write_text(good.replace("rotate:", "rotat:", 1), encoding="utf-8")
    cell, runs = practice_grade(spec, str(broken))
    assert [r.result.status for r in runs] == ["invalid"] * len(spec.variants)
    assert runs[0].result.message.startswith(f"the mission has an error: {broken}:")
    assert "unknown action 'rotat'" in runs[0].result.message
    assert len({r.result.message for r in runs}) == 1
    assert all(r.recording is None for r in runs) and cell.points == 0.0


def test_a_mission_whose_code_raises_crashes_and_scores_zero(tmp_path: Path) -> None:
    spec = load_test_spec(TEACHER / "square" / "test.yaml")
    mission = tmp_path / "square.py"
    mission.write_text(
        "from roboscript import Drive, Mission, state\n"
        "class Square(Mission):\n"
        "    side = state(Drive(distance_mm=500), initial=True,\n"
        "                 on_done='finished', when=[('broken', 'finished')])\n"
        "    finished = state(final='success')\n"
        "    def broken(self) -> bool:\n"
        "        raise ValueError('no way')\n",
        encoding="utf-8",
    )
    result = practice_run(spec, str(mission), spec.variants[0]).result
    graded = grade_run(spec, str(mission), spec.variants[0])
    assert (result.status, result.score) == (graded.status, graded.score)
    assert result.status == "crashed" and result.score == 0.0
    assert "no way" in result.message
