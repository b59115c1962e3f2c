"""Finding submissions without trusting them: who is who, what is refused, what a run reads.

``tests/grading/test_hostile_class.py`` grades a hostile class through the real command; these
check the rules one by one, without running anything.
"""

from __future__ import annotations

import os
from pathlib import Path

from helpers import FORWARD_50CM

from roboscript.grading.submissions import (
    MAX_ENTRIES,
    MAX_SOURCE_BYTES,
    find_submissions,
    visible_files,
)

MISSION_PY = """\
from roboscript import Mission, Wait, state


class Idle({base}):
    go = state(Wait(duration_s=0.5), initial=True, on_done="end")
    end = state(final="success")
"""


def _found(*patterns: Path) -> dict[str, tuple[list[str], str]]:
    return {
        s.student: ([Path(m).name for m in s.missions], s.problem)
        for s in find_submissions([str(p) for p in patterns]).submissions
    }


def test_a_python_mission_is_known_by_its_class_line_without_parsing_it(tmp_path: Path) -> None:
    deep = "X = " + "+".join(["1"] * 20_000) + "\n"  # ast.parse raises RecursionError on it
    (tmp_path / "deep.py").write_text(deep + MISSION_PY.format(base="Mission"), encoding="utf-8")
    (tmp_path / "dotted.py").write_text(MISSION_PY.format(base="roboscript.Mission"))
    (tmp_path / "helper.py").write_text(deep + "class Helper(Base):\n    pass\n")
    assert _found(tmp_path) == {"deep": (["deep.py"], ""), "dotted": (["dotted.py"], "")}


def test_a_mission_class_whose_base_is_imported_under_another_name_is_a_student(
    tmp_path: Path,
) -> None:
    aliased = MISSION_PY.format(base="M").replace("import Mission,", "import Mission as M,")
    (tmp_path / "aliased.py").write_text(aliased, encoding="utf-8")
    helper = "import roboscript as rs\n\nclass Helper(Base):\n    pass\n"
    (tmp_path / "helper.py").write_text(helper, encoding="utf-8")
    assert _found(tmp_path) == {"aliased": (["aliased.py"], "")}


def test_a_mission_kept_in_a_docstring_is_no_second_mission(tmp_path: Path) -> None:
    # old code kept in a triple-quoted string defines nothing: the student has one mission
    # (two would make them "missing" in a test named otherwise), and a file holding only
    # that is no mission at all
    ana = tmp_path / "class" / "ana"
    ana.mkdir(parents=True)
    (ana / "mission.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    old = MISSION_PY.format(base="Mission")
    (ana / "notes.py").write_text(f'"""My first try:\n\n{old}"""\n', encoding="utf-8")
    (ana / "later.py").write_text(f"X = 1\n'''\n{old}'''\n", encoding="utf-8")
    assert _found(tmp_path / "class") == {"ana": (["mission.yaml"], "")}


def test_two_missions_with_one_name_in_one_folder_are_two_students(tmp_path: Path) -> None:
    (tmp_path / "ana.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "ana.py").write_text(MISSION_PY.format(base="Mission"), encoding="utf-8")
    (tmp_path / "bo").mkdir()
    (tmp_path / "bo" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "bo.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    assert _found(tmp_path) == {
        "ana.py": (["ana.py"], ""),
        "ana.yaml": (["ana.yaml"], ""),
        "bo.yaml": (["bo.yaml"], ""),
        "bo/": (["forward.yaml"], ""),
    }


def test_names_are_cleaned_once_and_stay_unique(tmp_path: Path) -> None:
    for name in ("a\x01", "a\x02", "b\nc"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    assert sorted(_found(tmp_path)) == ["a�", "a�-2", "b�c"]


def test_a_file_too_big_to_read_makes_its_student_invalid(tmp_path: Path) -> None:
    folder = tmp_path / "ada"
    folder.mkdir()
    (folder / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    with open(folder / "big.yaml", "wb") as handle:
        handle.truncate(2 * 1024 * 1024)
    ((missions, problem),) = _found(tmp_path).values()
    assert missions == ["forward.yaml"]
    assert problem.startswith("big.yaml cannot be graded: the file is 2097152 bytes")


def test_a_folder_with_too_many_entries_is_refused_unread(tmp_path: Path) -> None:
    folder = tmp_path / "ada"
    folder.mkdir()
    (folder / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    for i in range(MAX_ENTRIES):
        (folder / f"{i}.txt").touch()
    ((_, problem),) = _found(tmp_path).values()
    assert problem.startswith(f"the folder holds more than {MAX_ENTRIES} files and folders")


def test_a_folder_with_too_much_code_to_look_into_is_refused_unread(tmp_path: Path) -> None:
    folder = tmp_path / "ada"
    folder.mkdir()
    (folder / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    for i in range(MAX_SOURCE_BYTES // (1024 * 1024)):  # each at the 1 MiB a file may have
        with open(folder / f"part{i}.py", "wb") as handle:
            handle.truncate(1024 * 1024)
    ((_, problem),) = _found(tmp_path).values()
    assert problem.startswith("the folder holds more than 16 MiB of .py and .yaml files")


def test_a_link_is_never_followed(tmp_path: Path) -> None:
    (tmp_path / "ada").mkdir()
    (tmp_path / "ada" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "ben").mkdir()
    os.symlink(tmp_path / "ada" / "forward.yaml", tmp_path / "ben" / "notes.txt")
    os.symlink("/", tmp_path / "cy")
    found = _found(tmp_path)
    assert found["ben"][1] == (
        "notes.txt is a symbolic link: a submission holds its own files, not links to others"
        " (hand in the file itself)"
    )
    assert found["cy"][1].startswith("cy is a symbolic link")


_SHARED = (
    " (a hard link, not a copy: each sees what the other hands in): one file cannot be the"
    " work of two students, so neither is graded; hand in a copy of your own"
)


def test_a_hard_link_to_a_classmates_file_refuses_both_naming_the_other(tmp_path: Path) -> None:
    # One file under two names: ben reads whatever ada hands in. Nothing says which name came
    # first, so both are refused with the other named; the teacher, who can ask, decides.
    for name in ("ada", "ben", "cy", "dee"):
        (tmp_path / name).mkdir()
    (tmp_path / "ada" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "ada" / "turns.py").write_text("X = 1\n", encoding="utf-8")
    (tmp_path / "ben" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    os.link(tmp_path / "ada" / "turns.py", tmp_path / "ben" / "mine.py")
    # the same text in two files is allowed: two students may write the same thing
    (tmp_path / "cy" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    # one's own file under two names of one's own is one's own
    (tmp_path / "dee" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    os.link(tmp_path / "dee" / "forward.yaml", tmp_path / "dee" / "backup.txt")
    found = _found(tmp_path)
    assert found["ada"][1] == "turns.py is the same file as ben's mine.py" + _SHARED
    assert found["ben"][1] == "mine.py is the same file as ada's turns.py" + _SHARED
    assert found["cy"][1] == found["dee"][1] == ""


def test_a_student_who_is_a_file_sharing_a_file_with_a_classmate_is_refused(
    tmp_path: Path,
) -> None:
    (tmp_path / "ada").mkdir()
    (tmp_path / "ada" / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    os.link(tmp_path / "ada" / "forward.yaml", tmp_path / "eve.yaml")
    (tmp_path / "fay.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    os.link(tmp_path / "fay.yaml", tmp_path / "gus.yaml")
    found = _found(tmp_path)
    assert found["eve"][1] == "eve.yaml is the same file as ada's forward.yaml" + _SHARED
    assert found["ada"][1] == "forward.yaml is the same file as eve's eve.yaml" + _SHARED
    assert found["fay"][1] == "fay.yaml is the same file as gus's gus.yaml" + _SHARED
    assert found["gus"][1] == "gus.yaml is the same file as fay's fay.yaml" + _SHARED


def test_a_student_in_a_shared_folder_sees_only_files_named_after_them(tmp_path: Path) -> None:
    names = ["alice.yaml", "alice_b.yaml", "alice_util.py", "alice_b_util.py", "alicex.py"]
    names += ["helpers.py", "grades.csv"]
    for name in names:
        text = FORWARD_50CM if name.endswith(".yaml") else "X = 1\n"
        (tmp_path / name).write_text(text, encoding="utf-8")
    os.symlink(tmp_path / "alice_b_util.py", tmp_path / "alice_link.py")
    naming = " ".join([*names, "alice_link.py"])
    for student in ("alice", "alice_b"):
        (tmp_path / f"{student}.yaml").write_text(FORWARD_50CM + f"# {naming}\n")
    submissions = {s.student: s for s in find_submissions([str(tmp_path)]).submissions}
    assert submissions["alice_link"].problem.startswith("alice_link.py is a symbolic link")
    seen = {
        name: sorted(p.name for p in visible_files(s, s.missions[0]))
        for name, s in submissions.items()
        if s.missions
    }
    assert seen == {
        "alice": ["alice.yaml", "alice_util.py"],
        "alice_b": ["alice_b.yaml", "alice_b_util.py"],
    }


def test_what_is_no_students_work_is_found_with_the_students(tmp_path: Path) -> None:
    (tmp_path / "alice.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "alice_helpers.py").write_text("X = 1\n", encoding="utf-8")  # alice's own
    (tmp_path / "bo.zip").write_bytes(b"PK")
    (tmp_path / "notes").mkdir()
    (tmp_path / ".git").mkdir()  # hidden: nobody's business
    found = find_submissions([str(tmp_path)])
    assert [s.student for s in found.submissions] == ["alice"]
    assert found.unclaimed == ("bo.zip", "notes/")
    # a file or a glob is no class folder: nothing in it is unclaimed
    assert find_submissions([str(tmp_path / "alice.yaml")]).unclaimed == ()


def test_a_student_named_after_an_earlier_report_sees_only_their_mission_files(
    tmp_path: Path,
) -> None:
    reports = ["grades.csv", "grades.jsonl", "results.jsonl", "index.html", "index_2.xml"]
    for name in reports:
        (tmp_path / name).write_text("student,score\nbea,SECRET\n", encoding="utf-8")
    naming = " ".join(reports)
    for student in ("grades", "results", "index"):
        (tmp_path / f"{student}.yaml").write_text(FORWARD_50CM + f"# {naming}\n")
    (tmp_path / "grades_turns.py").write_text("TURN_DEG = 90\n", encoding="utf-8")
    (tmp_path / "grades.yaml").write_text(FORWARD_50CM + f"# {naming} grades_turns.py\n")
    seen = {
        s.student: sorted(p.name for p in visible_files(s, s.missions[0]))
        for s in find_submissions([str(tmp_path)]).submissions
    }
    assert seen == {
        "grades": ["grades.yaml", "grades_turns.py"],
        "index": ["index.yaml"],
        "results": ["results.yaml"],
    }


def test_names_drawn_alike_by_a_ligature_or_full_width_letters_are_told_apart(
    tmp_path: Path,
) -> None:
    # "ﬁona" (one ligature character) and "ｂo" (a full-width b) look like "fiona" and "bo" in
    # every report: the plain name keeps it, the other is numbered and named in a warning.
    for name in ("ﬁona", "fiona", "ｂo", "bo"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "forward.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    found = find_submissions([str(tmp_path)])
    assert sorted(s.student for s in found.submissions) == ["bo", "fiona", "ﬁona-2", "ｂo-2"]
    told = sorted(found.lookalikes)
    assert len(told) == 2
    assert "'fiona' and 'ﬁona-2'" in told[1] and "\\ufb01ona" in told[1], told
