"""What a student reads of a run: no folder of the teacher's, the student's own paths whole."""

from __future__ import annotations

import pytest

from roboscript.grading.text import student_text


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ("cannot read /home/teacher/class/ana/x.py", "cannot read x.py"),
        ('File "/home/t/class/x.py", line 3', 'File "x.py", line 3'),
        ("raised here (/srv/grading/ana/turns.py:3)", "raised here (turns.py:3)"),
        ("error:/home/t/x.py", "error:x.py"),
        ("No such file: '/a/b/c'", "No such file: 'c'"),
    ],
)
def test_a_folder_of_the_teachers_computer_is_cut_from_what_students_read(
    text: str, shown: str
) -> None:
    assert student_text(text) == shown


@pytest.mark.parametrize(
    "text",
    [
        # a path inside the submission whose folders end in a dash or follow a cut
        "the folder nests folders more than 32 deep (deep-/deeper-/deepest-/x)",
        "my-stuff-/turns.py:3",
        "folder-in-a-…/folder-/folder-/x",
    ],
)
def test_a_path_inside_the_submission_is_kept_whole_whatever_its_folders_end_in(
    text: str,
) -> None:
    assert student_text(text) == text


def test_a_file_name_in_a_sentence_is_one_line_of_visible_text() -> None:
    from roboscript.grading.text import one_line

    assert one_line("\x1b]0;pwned\x07\nforged\u202erow\u200b.py") == "�]0;pwned��forged�row�.py"
    assert one_line(" kept as it is ") == " kept as it is "
