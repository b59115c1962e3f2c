"""``roboscript examples``: the missions every guide runs, written where the user is."""

from __future__ import annotations

from pathlib import Path

from helpers import MISSIONS, run_cli


def _example_files() -> dict[str, bytes]:
    return {
        str(path.relative_to(MISSIONS)): path.read_bytes()
        for path in MISSIONS.rglob("*")
        if path.is_file() and "__pycache__" not in path.parts
    }


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def test_examples_writes_the_guides_missions_so_the_quick_start_runs(tmp_path: Path) -> None:
    done = run_cli("examples", cwd=tmp_path)
    expected = _example_files()
    assert (done.returncode, done.stderr) == (
        0,
        (
            f"wrote {len(expected)} example files into missions: try roboscript run"
            " missions/square.yaml\n"
        ),
    )
    assert _files(tmp_path / "missions") == expected
    assert run_cli("run", "missions/square.yaml", "--quiet", cwd=tmp_path).returncode == 0
    grade = run_cli(
        "grade", "missions/teacher/square", "--mission", "missions/teacher/square", cwd=tmp_path
    )
    assert grade.returncode == 1, grade.stderr  # the good solution passes, the bad one fails
    assert "good     square-50cm  ✓ 3/3" in grade.stdout


def test_examples_never_write_over_a_students_own_file(tmp_path: Path) -> None:
    run_cli("examples", cwd=tmp_path)
    mine = tmp_path / "missions" / "square.yaml"
    mine.write_text("mission: mine\n", encoding="utf-8")
    (tmp_path / "missions" / "zigzag.yaml").unlink()
    done = run_cli("examples", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (
        0,
        (
            "kept your own missions/square.yaml (not the example's text: rename yours to get the"
            " example too)\nwrote 1 example file into missions: try roboscript run"
            " missions/square.yaml\n"
        ),
    )
    assert mine.read_text(encoding="utf-8") == "mission: mine\n"
    again = run_cli("examples", cwd=tmp_path)
    assert again.stderr.startswith("kept your own missions/square.yaml")
    mine.unlink()
    run_cli("examples", cwd=tmp_path)
    assert run_cli("examples", cwd=tmp_path).stderr == (
        "missions holds the examples already: nothing to write\n"
    )


def test_examples_go_into_the_folder_named(tmp_path: Path) -> None:
    done = run_cli("examples", "robot class/examples", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stderr.endswith('try roboscript run "robot class/examples/square.yaml"\n')
    assert _files(tmp_path / "robot class" / "examples") == _example_files()


def test_examples_where_a_file_is_are_refused_before_anything_is_written(tmp_path: Path) -> None:
    (tmp_path / "missions").write_text("notes\n", encoding="utf-8")
    done = run_cli("examples", cwd=tmp_path)
    assert (done.returncode, done.stderr) == (2, "error: cannot write missions: it is a file\n")
    assert (tmp_path / "missions").read_text(encoding="utf-8") == "notes\n"


def test_examples_in_the_roboscript_folder_leave_its_missions_as_they_are() -> None:
    before = _example_files()
    done = run_cli("examples")  # in the roboscript folder, whose missions/ they come from
    assert (done.returncode, done.stderr) == (
        0,
        "missions holds the examples already (it is where they come from)\n",
    )
    assert _example_files() == before
