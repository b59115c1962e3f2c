"""``roboscript autograder``: each package is run as its platform runs it, in a fresh folder laid
out like the platform's, in a fresh venv, with no network, and grades a submission."""

from __future__ import annotations

import functools
import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import Any

import pytest
import yaml
from helpers import HANG_BOUND_S, OUT_TURN_BEEP, run_cli

from roboscript.grading.autograder import classroom_files, gradescope_zip, spec_files
from roboscript.grading.batch import find_specs

SPEC = """\
test: out-and-turn
description: Drive 20 cm, turn left, beep.
world: arena.yaml
runs:
  - {seed: 1}
  - {seed: 2, start: {x: 100 mm, y: 0 mm}, hidden: true}
points: 10
max_time: 20 s
expect:
  - outcome: success
  - final_pose_within: {x: 0 mm, y: 200 mm, radius: 60 mm}
  - check: turned.py:turned_left
"""
ARENA = """\
world: arena
start: {x: 0 mm, y: 0 mm, heading: 0 deg}
"""
CHECK = """\
def turned_left(run):
    return run.final_pose[2] > 45, f"heading {run.final_pose[2]:.0f} deg"
"""
# From the hidden run's start the mission ends 10 cm past the target: it fails that run only.
MISSION = OUT_TURN_BEEP


@pytest.fixture
def specs_folder(tmp_path: Path) -> Path:
    folder = tmp_path / "teacher" / "robot-tests"
    folder.mkdir(parents=True)
    (folder / "test.yaml").write_text(SPEC, encoding="utf-8")
    (folder / "arena.yaml").write_text(ARENA, encoding="utf-8")
    (folder / "turned.py").write_text(CHECK, encoding="utf-8")
    (folder / "solution.yaml").write_text(MISSION, encoding="utf-8")  # never packed
    return folder


@functools.cache
def _offline_prefix() -> tuple[str, ...]:
    """A command prefix with no network at all (a new network namespace), where allowed."""
    unshare = shutil.which("unshare")
    if unshare is None:
        return ()
    tried = subprocess.run([unshare, "-n", "true"], capture_output=True, check=False)
    return (unshare, "-n") if tried.returncode == 0 else ()


def _offline(command: list[str], **kwargs: Any) -> subprocess.CompletedProcess[str]:
    """Run as the platform would, without network: pip could not reach an index if it tried."""
    env = {
        "PATH": f"{Path(sys.executable).parent}:/usr/bin:/bin",
        "HOME": str(kwargs.pop("home")),
        "PIP_INDEX_URL": "http://127.0.0.1:9/simple",  # nothing listens there
        "PIP_NO_CACHE_DIR": "1",
        **kwargs.pop("env", {}),
    }
    return subprocess.run(
        [*_offline_prefix(), *command],
        capture_output=True,
        text=True,
        env=env,
        timeout=HANG_BOUND_S,
        check=False,
        **kwargs,
    )


def test_the_same_specs_make_the_same_zip_byte_for_byte(specs_folder: Path) -> None:
    first = run_cli("autograder", "gradescope", str(specs_folder), "-o", "a.zip", cwd=specs_folder)
    assert first.returncode == 0, first.stderr
    second = run_cli("autograder", "gradescope", str(specs_folder), "-o", "b.zip", cwd=specs_folder)
    assert (specs_folder / "a.zip").read_bytes() == (specs_folder / "b.zip").read_bytes()
    assert "no package index" in second.stderr
    with zipfile.ZipFile(specs_folder / "a.zip") as archive:
        names = archive.namelist()
        infos = archive.infolist()
    assert names == sorted(names)
    assert {i.date_time for i in infos} == {(1980, 1, 1, 0, 0, 0)}
    assert {"setup.sh", "run_autograder", "tests/test.yaml", "tests/arena.yaml"} <= set(names)
    assert "tests/turned.py" in names and "tests/solution.yaml" not in names
    wheels = {n.split("/")[1].split("-")[0].lower() for n in names if n.startswith("wheels/")}
    assert wheels == {"roboscript", "pyyaml", "pyserial", "simple_pid", "transitions", "six"}


def test_spec_files_keep_worlds_outside_the_spec_folder(tmp_path: Path) -> None:
    (tmp_path / "worlds").mkdir()
    (tmp_path / "worlds" / "arena.yaml").write_text(ARENA, encoding="utf-8")
    (tmp_path / "tests").mkdir()
    spec = SPEC.replace("world: arena.yaml", "world: ../worlds/arena.yaml")
    spec = spec.replace("  - check: turned.py:turned_left\n", "")
    (tmp_path / "tests" / "test.yaml").write_text(spec, encoding="utf-8")
    files = spec_files(find_specs([str(tmp_path / "tests")]))
    assert sorted(files) == ["tests/test.yaml", "worlds/arena.yaml"]


def _results(path: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    return data


@pytest.mark.slow
@pytest.mark.timeout(900)  # a venv and an install, then a grading, on a loaded machine
def test_the_gradescope_zip_grades_a_submission_as_gradescope_does(
    specs_folder: Path, tmp_path: Path
) -> None:
    made = run_cli("autograder", "gradescope", str(specs_folder), "-o", str(tmp_path / "ag.zip"))
    assert made.returncode == 0, made.stderr
    root = tmp_path / "autograder"  # Gradescope's /autograder
    (root / "submission").mkdir(parents=True)
    with zipfile.ZipFile(tmp_path / "ag.zip") as archive:
        archive.extractall(root / "source")
    for script in ("setup.sh", "run_autograder"):  # zipfile drops modes; Gradescope keeps them
        (root / "source" / script).chmod(0o755)
    env = {"ROBOSCRIPT_VENV": str(tmp_path / "opt-roboscript"), "AUTOGRADER_ROOT": str(root)}
    setup = _offline(
        ["bash", str(root / "source" / "setup.sh")], cwd=root / "source", home=tmp_path, env=env
    )
    assert setup.returncode == 0, setup.stdout + setup.stderr
    venv_python = str(tmp_path / "opt-roboscript/bin/python")
    pure = _offline([venv_python, "-c", "import yaml; print(yaml.__with_libyaml__)"], home=tmp_path)
    assert pure.stdout.strip() == "False"
    (root / "submission" / "mine.yaml").write_text(MISSION, encoding="utf-8")
    # The harness runs its copy, /autograder/run_autograder, in /autograder.
    shutil.copy2(root / "source" / "run_autograder", root / "run_autograder")
    graded = _offline([str(root / "run_autograder")], cwd=root, home=tmp_path, env=env)
    assert graded.returncode == 0, graded.stderr
    results = _results(root / "results" / "results.json")
    names = [t["name"] for t in results["tests"]]
    assert names == ["out-and-turn: seed 1", "out-and-turn: hidden run 2"]
    assert [t["max_score"] for t in results["tests"]] == [5.0, 5.0]
    assert [t["visibility"] for t in results["tests"]] == ["visible", "after_published"]
    assert results["tests"][0]["status"] == "passed" and results["tests"][0]["score"] == 5.0
    assert results["tests"][1]["status"] == "failed" and results["score"] < 10.0
    assert "seed 2" not in json.dumps(results) and "100, 0" not in json.dumps(results)


def _run_workflow(workflow: dict[str, Any], workspace: Path, tests: Path, tmp: Path) -> str:
    """The workflow's steps in order, as a GitHub runner takes them; returns the log."""
    log = []
    venv = tmp / "setup-python"
    env = {"RUNNER_TEMP": str(tmp / "runner-temp"), "GITHUB_ACTOR": "octo-student"}
    (tmp / "runner-temp").mkdir()
    for step in workflow["jobs"]["grade"]["steps"]:
        uses = step.get("uses", "")
        if uses.startswith("actions/checkout") and "repository" in step.get("with", {}):
            shutil.copytree(tests, workspace / step["with"]["path"])
        elif uses.startswith("actions/setup-python"):  # a fresh Python on the PATH
            subprocess.run(
                [sys.executable, "-m", "venv", str(venv)], check=True, timeout=HANG_BOUND_S
            )
            env["PATH"] = f"{venv}/bin:/usr/bin:/bin"
        elif uses.startswith("actions/upload-artifact"):
            assert (workspace / step["with"]["path"]).is_file()
        elif "run" in step:
            script = step["run"].replace("${{ github.actor }}", env["GITHUB_ACTOR"])
            step_env = {
                k: str(v).replace("${{ github.actor }}", env["GITHUB_ACTOR"])
                for k, v in step.get("env", {}).items()
            }
            done = _offline(
                ["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c", script],
                cwd=workspace,
                home=tmp,
                env={**env, **step_env},
            )
            log.append(done.stdout + done.stderr)
            if done.returncode != 0:
                log.append(f"step failed: exit {done.returncode}")
                break
    return "\n".join(log)


@pytest.mark.slow
@pytest.mark.timeout(900)  # a venv and an install, then a grading, on a loaded machine
def test_the_classroom_template_grades_a_push_as_a_github_runner_does(
    specs_folder: Path, tmp_path: Path
) -> None:
    out = tmp_path / "classroom"
    made = run_cli("autograder", "classroom", str(specs_folder), "-o", str(out),
                   "--tests-repo", "my-school/robot-tests")  # fmt: skip
    assert made.returncode == 0, made.stderr
    # a student who edits the workflow can print the private tests: the teacher is told
    assert "warning: out-and-turn has hidden runs: on GitHub Classroom a student" in made.stderr
    workflow_file = out / "student-template" / ".github" / "workflows" / "roboscript.yml"
    workflow = yaml.safe_load(workflow_file.read_text(encoding="utf-8"))
    checkout = [s for s in workflow["jobs"]["grade"]["steps"] if "repository" in s.get("with", {})]
    assert checkout[0]["with"]["repository"] == "my-school/robot-tests"
    workspace = tmp_path / "student-repo"  # the template, as the student pushed it
    shutil.copytree(out / "student-template", workspace)
    (workspace / "robot" / "mission.yaml").write_text(MISSION, encoding="utf-8")
    log = _run_workflow(workflow, workspace, out / "private-tests", tmp_path)
    # the hidden run fails, so the job fails: the student sees a red cross and the table
    assert "step failed: exit 1" in log
    assert "octo-student  out-and-turn  ✗ 1/2" in log
    assert "hidden run 2" in log and "seed 2" not in log
    assert 'tests="2" failures="1"' in (workspace / "grade.xml").read_text(encoding="utf-8")


@pytest.mark.slow
@pytest.mark.timeout(900)  # a venv and an install, then a grading, on a loaded machine
def test_the_prairielearn_grader_writes_results_as_prairielearn_reads_them(
    specs_folder: Path, tmp_path: Path
) -> None:
    out = tmp_path / "course"
    made = run_cli("autograder", "prairielearn", str(specs_folder), "-o", str(out),
                   "--question", "robot-turn")  # fmt: skip
    assert made.returncode == 0, made.stderr
    info = json.loads((out / "questions/robot-turn/info.json").read_text(encoding="utf-8"))
    options = info["externalGradingOptions"]
    assert options["entrypoint"] == "/grade/serverFilesCourse/roboscript/run.sh"
    grade = tmp_path / "grade"  # PrairieLearn's /grade
    shutil.copytree(out / "serverFilesCourse", grade / "serverFilesCourse")
    shutil.copytree(out / "questions/robot-turn/tests", grade / "tests")
    (grade / "student").mkdir()
    (grade / "student" / "out-and-turn.yaml").write_text(MISSION, encoding="utf-8")
    entrypoint = grade / options["entrypoint"].removeprefix("/grade/")
    env = {"GRADE_ROOT": str(grade), "TMPDIR": str(tmp_path)}
    done = _offline(
        ["bash", "-c", f"chmod +x {entrypoint} && {entrypoint}"], home=tmp_path, env=env
    )
    assert done.returncode == 0, done.stderr
    results = _results(grade / "results" / "results.json")
    assert results["gradable"] is True and 0 < results["score"] < 1
    assert [t["max_points"] for t in results["tests"]] == [5.0, 5.0]
    assert [t["message"] for t in results["tests"]] == ["passed", "failed"]
    assert results["tests"][1]["name"] == "out-and-turn: hidden run 2"
    assert results["score"] == round(sum(t["points"] for t in results["tests"]) / 10, 4)


def test_a_classroom_folder_is_never_written_over(specs_folder: Path, tmp_path: Path) -> None:
    out = tmp_path / "classroom"
    out.mkdir()
    (out / "mine.txt").write_text("keep\n", encoding="utf-8")
    made = run_cli("autograder", "classroom", str(specs_folder), "-o", str(out))
    assert made.returncode == 2 and "already holds files: give -o a new or empty" in made.stderr
    assert os.listdir(out) == ["mine.txt"]
    files = classroom_files(find_specs([str(specs_folder)]), [], "me/tests")
    assert "private-tests/specs/test.yaml" in files and "student-template/robot/README.md" in files
    assert gradescope_zip(find_specs([str(specs_folder)]), []).startswith(b"PK")


@pytest.mark.parametrize(
    ("platform", "options", "said"),
    [
        ("gradescope", ["-o", "test.yaml"], "the Gradescope autograder is a zip"),
        ("gradescope", ["-o", "notes.zip"], "notes.zip exists and is not a zip"),
        ("gradescope", ["-o", "a.zip", "--wheels", "no-such-folder"], "there is no such folder"),
        ("classroom", ["-o", "out", "--tests-repo", "me/tests\n  evil: true"], "OWNER/NAME"),
        ("classroom", ["-o", "out", "--tests-repo", "my tests"], "OWNER/NAME"),
        ("prairielearn", ["-o", "out", "--question", "../../escape"], "a folder name"),
        ("prairielearn", ["-o", "out", "--question", "/abs"], "a folder name"),
        ("classroom", ["-o", "notes.zip"], "notes.zip is a file, and this autograder is a folder"),
        ("prairielearn", ["-o", "test.yaml"], "test.yaml is a file, and this autograder is a"),
        ("classroom", ["-o", "notes.zip/out"], "notes.zip is a file, not a folder"),
    ],
)
def test_autograder_options_that_would_overwrite_or_escape_are_refused_first(
    specs_folder: Path, platform: str, options: list[str], said: str
) -> None:
    (specs_folder / "notes.zip").write_text("my notes\n", encoding="utf-8")
    before = {p: p.read_bytes() for p in specs_folder.rglob("*") if p.is_file()}
    made = run_cli("autograder", platform, "test.yaml", *options, cwd=specs_folder)
    assert made.returncode == 2, made.stderr
    assert made.stderr.startswith("error: ") and said in made.stderr
    assert made.stderr.count("\n") == 1
    after = {p: p.read_bytes() for p in specs_folder.rglob("*") if p.is_file()}
    assert after == before  # nothing written, nothing replaced


def test_a_prairielearn_question_named_after_its_test_stays_in_questions(
    specs_folder: Path, tmp_path: Path
) -> None:
    spec = specs_folder / "test.yaml"
    spec.write_text(SPEC.replace("test: out-and-turn", 'test: "../../out and turn"'), "utf-8")
    out = tmp_path / "course"
    made = run_cli("autograder", "prairielearn", str(spec), "-o", str(out))
    assert made.returncode == 0, made.stderr
    assert os.listdir(out / "questions") == ["roboscript-out-and-turn"]
    assert sorted(os.listdir(out)) == ["questions", "serverFilesCourse"]
