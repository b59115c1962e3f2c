"""The robot and world a mission names, each mistake read as the student reads it (issue 16).

Pinned whole: which names are taken for files (a ``/`` or a ``\\`` as well as a ``.yaml``
ending), the hint when nothing is close, the "did you mean" over the files in the folders just
below the mission (and only its YAML files), and the place named for a mission built in code.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from roboscript.errors import MissionError
from roboscript.mission import mission_for_robot
from roboscript.mission.references import mission_robot, with_world_checked
from roboscript.mission.yaml_loader import parse_yaml_mission

DRIVE = """\
mission: m
HEADER
states:
  go:
    do: {drive: {distance: 50 cm, speed: 25 cm/s}}
    on: {done: end, failed: end}
  end:
    final: success
"""


def report(folder: Path, header: str) -> list[str]:
    """What ``roboscript check`` prints for a mission in ``folder`` with ``header``."""
    path = folder / "m.yaml"
    path.write_text(DRIVE.replace("HEADER", header), encoding="utf-8")
    with pytest.raises(MissionError) as info:
        mission_for_robot(path)
    found = getattr(info.value, "problems", [info.value])
    return [p.format().replace(str(path), "M") for p in found]


@pytest.mark.parametrize(
    ("written", "shown"),
    [
        ("robots/mine", "robots/mine"),  # a folder, no ending: still a file
        ("robots\\\\mine", "robots\\mine"),  # the same, written the Windows way
        ("Mine.YAML", "Mine.YAML"),
    ],
)
def test_a_robot_written_as_a_path_is_looked_for_as_a_file(
    tmp_path: Path, written: str, shown: str
) -> None:
    assert report(tmp_path, f'robot: "{written}"') == [
        f"M:2:8: error: there is no robot profile file '{shown}' beside the mission"
    ]


def test_a_robot_name_like_nothing_gets_the_profile_file_hint(tmp_path: Path) -> None:
    assert report(tmp_path, "robot: zzzzqqq") == [
        (
            "M:2:8: error: there is no robot called 'zzzzqqq' (built-in robots: mirto,"
            " asip-basic, stackmod-rover, stackmod-reference, spike-prime, plen2) (or name a"
            " profile file beside the mission, e.g. robot: my-robot.yaml)"
        )
    ]


def test_a_world_name_like_nothing_gets_the_world_file_hint(tmp_path: Path) -> None:
    assert report(tmp_path, "world: zzzzqqq") == [
        (
            "M:2:8: error: there is no world called 'zzzzqqq' (built-in worlds: corridor, empty,"
            " line-track, maze, square-room) (or name a world file beside the mission,"
            " e.g. world: my-room.yaml)"
        )
    ]


def test_a_misspelt_world_file_in_a_folder_below_gets_a_did_you_mean(tmp_path: Path) -> None:
    (tmp_path / "rooms").mkdir()
    (tmp_path / "rooms" / "kitchen.yaml").write_text("name: kitchen\n", encoding="utf-8")
    assert report(tmp_path, "world: rooms/kitchn.yaml") == [
        (
            "M:2:8: error: there is no world file 'rooms/kitchn.yaml' beside the mission"
            " (did you mean 'rooms/kitchen.yaml'?)"
        )
    ]


def test_only_yaml_files_are_offered_for_a_missing_world_file(tmp_path: Path) -> None:
    (tmp_path / "kitchen.txt").write_text("notes\n", encoding="utf-8")
    (tmp_path / "kitchen.yml.d").mkdir()
    assert report(tmp_path, "world: kitchen.yml") == [
        "M:2:8: error: there is no world file 'kitchen.yml' beside the mission"
    ]


def test_a_mission_built_in_code_is_reported_as_the_mission(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """No file, no line: the message still says which mission it is about."""
    monkeypatch.chdir(tmp_path)  # its files are looked for from here
    spec, _ = parse_yaml_mission(DRIVE.replace("HEADER", ""))
    with pytest.raises(MissionError) as info:
        mission_robot(dataclasses.replace(spec, robot="zzzzqqq"))
    assert info.value.format().startswith("<mission>: error: there is no robot called 'zzzzqqq'")
    _, problems = with_world_checked(dataclasses.replace(spec, world="rooms/none.yaml"))
    assert [p.format() for p in problems] == [
        "<mission>: error: there is no world file 'rooms/none.yaml' beside the mission"
    ]
