"""A student's file that changes roboscript's own classes or names is refused, and the change
is put back, so a mission loaded after it in the same program sees roboscript as it is."""

from __future__ import annotations

from pathlib import Path

import pytest

import roboscript
from roboscript import Drive
from roboscript.errors import MissionError
from roboscript.mission.student_code import import_student_file

HEAD = "import roboscript\nfrom roboscript import Drive, Mission, state\n\n\n"


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ("Drive.update = lambda self, ctx: None", "this changes roboscript's own Drive (update)"),
        ("Drive.speed_limit = 5", "this changes roboscript's own Drive (speed_limit)"),
        ("del Drive.conflicts", "this changes roboscript's own Drive (conflicts)"),
        ("roboscript.Drive = int", "in the place of roboscript's 'Drive'"),
        ("roboscript.Wait = int", "in the place of roboscript's 'Wait'"),
    ],
)
def test_a_change_to_roboscript_is_refused_at_its_line_and_put_back(
    tmp_path: Path, change: str, message: str
) -> None:
    update, conflicts = vars(Drive)["update"], vars(Drive)["conflicts"]
    wait = roboscript.Wait
    path = tmp_path / "m.py"
    path.write_text(HEAD + change + "\n", encoding="utf-8")
    with pytest.raises(MissionError) as refused:
        import_student_file(path)
    assert message in refused.value.message
    assert (refused.value.line, refused.value.col) == (5, 1)
    assert vars(Drive)["update"] is update and vars(Drive)["conflicts"] is conflicts
    assert "speed_limit" not in vars(Drive)
    assert roboscript.Drive is Drive and roboscript.Wait is wait


def test_a_subclass_of_its_own_may_change_what_it_likes(tmp_path: Path) -> None:
    path = tmp_path / "m.py"
    path.write_text(
        HEAD + "class MyDrive(Drive):\n    pass\n\n\nMyDrive.speed_limit = 5\n", encoding="utf-8"
    )
    module = import_student_file(path)
    assert module.MyDrive.speed_limit == 5
    assert "speed_limit" not in vars(Drive)
