"""Finding a class's submissions: who is who, and which mission runs in which test."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from helpers import MISSIONS

from roboscript.errors import InputError
from roboscript.grading.batch import (
    Submission,
    find_specs,
    find_submissions,
    grade_class,
    mission_for_test,
)
from roboscript.grading.spec import load_test_spec

SQUARE = MISSIONS / "square.yaml"


def _names(found: list[Submission]) -> dict[str, list[str]]:
    return {s.student: [Path(m).name for m in s.missions] for s in found}


def test_a_class_folder_has_file_students_and_folder_students(tmp_path: Path) -> None:
    shutil.copy(SQUARE, tmp_path / "alice.yaml")
    shutil.copy(MISSIONS / "square.py", tmp_path / "bob.py")
    (tmp_path / "helper.py").write_text("def helps():\n    return 1\n")  # not a mission
    shutil.copy(MISSIONS / "teacher" / "square" / "test.yaml", tmp_path / "test.yaml")  # a spec
    carol = tmp_path / "carol"
    (carol / "behaviours").mkdir(parents=True)
    shutil.copy(MISSIONS / "zigzag.yaml", carol / "zigzag.yaml")
    shutil.copy(MISSIONS / "behaviours" / "zigzag.py", carol / "behaviours" / "zigzag.py")
    assert _names(find_submissions([str(tmp_path)]).submissions) == {
        "alice": ["alice.yaml"],
        "bob": ["bob.py"],
        "carol": ["zigzag.yaml"],
    }


def test_a_glob_of_same_named_files_names_students_by_folder(tmp_path: Path) -> None:
    for student in ("dan", "eve"):
        (tmp_path / student).mkdir()
        shutil.copy(SQUARE, tmp_path / student / "square.yaml")
    found = find_submissions([str(tmp_path / "*" / "square.yaml")]).submissions
    assert list(_names(found)) == ["dan", "eve"]


def test_nothing_found_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no mission matches"):
        find_submissions([str(tmp_path / "*.yaml")])
    with pytest.raises(InputError, match="no mission files in the folder"):
        find_submissions([str(tmp_path)])


def test_a_student_with_several_missions_runs_the_one_named_after_the_test() -> None:
    spec = load_test_spec(MISSIONS / "teacher" / "square" / "test.yaml")
    both = Submission("amy", ("amy/square_50cm.yaml", "amy/corridor.yaml"))
    assert mission_for_test(both, spec) == "amy/square_50cm.yaml"
    assert mission_for_test(Submission("bo", ("bo/anything.yaml",)), spec) == "bo/anything.yaml"
    assert mission_for_test(Submission("cy", ("cy/a.yaml", "cy/b.yaml")), spec) is None


@pytest.mark.skipif(os.geteuid() != 0, reason="only root's jails need files others can read")
def test_a_submission_the_sandbox_cannot_read_is_one_error_before_any_run(tmp_path: Path) -> None:
    from roboscript.grading.sandbox import detect_isolation

    if not detect_isolation().complete:
        pytest.skip("needs bubblewrap's full isolation")
    mission = tmp_path / "ada.yaml"
    mission.write_text((MISSIONS / "square.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    mission.chmod(0o600)
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nexpect:\n  - outcome: success\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"cannot grade ada: .*chmod -R o\+rX"):
        grade_class(find_specs([str(spec)]), find_submissions([str(mission)]).submissions)


@pytest.mark.skipif(os.geteuid() != 0, reason="only root's jails need files others can read")
def test_one_submission_the_sandbox_cannot_read_is_that_students_result(tmp_path: Path) -> None:
    from helpers import run_cli

    from roboscript.grading.sandbox import detect_isolation

    if not detect_isolation().complete:
        pytest.skip("needs bubblewrap's full isolation")
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nworld: empty\nexpect:\n  - outcome: success\n", encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    for student in ("ada", "ben"):
        shutil.copy(MISSIONS / "teacher" / "square" / "good.yaml", folder / f"{student}.yaml")
    (folder / "ada.yaml").chmod(0o600)
    done = run_cli("grade", str(spec), "--mission", str(folder), "--json", "--hang-after", "30")
    runs = {r["student"]: r for r in json.loads(done.stdout)["runs"]}
    assert runs["ben"]["status"] == "passed", done.stderr
    assert runs["ada"]["status"] == "invalid"
    assert runs["ada"]["message"].startswith("the grader's sandbox cannot show this submission")
    assert str(tmp_path) not in runs["ada"]["message"]
