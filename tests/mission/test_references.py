"""Files and names a mission refers to: the robot, the world, inner missions, behaviours."""

from __future__ import annotations

import dataclasses
import sys
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
WORLD = Path(__file__).resolve().parents[2] / "roboscript" / "sim" / "worlds" / "empty.yaml"


def write(folder: Path, header: str, name: str = "m.yaml") -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(DRIVE.replace("HEADER", header), encoding="utf-8")
    return path


def report(path: Path) -> list[str]:
    """What ``roboscript check`` prints for ``path``: its errors, or else its warnings."""
    try:
        _spec, _profile, warnings = mission_for_robot(path)
    except MissionError as exc:
        found = getattr(exc, "problems", [exc])
    else:
        found = warnings
    return [p.format().replace(str(path), "M") for p in found]


@pytest.mark.parametrize("world", ["squre-room", "squre"])
def test_a_misspelt_world_gets_a_did_you_mean(tmp_path: Path, world: str) -> None:
    write(tmp_path, "", "square.yaml")  # a mission beside it, named like the world, is no world
    assert report(write(tmp_path, f"world: {world}")) == [
        (
            f"M:2:8: error: there is no world called '{world}' (built-in worlds: corridor, empty,"
            " line-track, maze, square-room) (did you mean 'square-room'?)"
        )
    ]


def test_a_misspelt_world_file_nearby_gets_a_did_you_mean(tmp_path: Path) -> None:
    (tmp_path / "arena.yaml").write_text(WORLD.read_text(encoding="utf-8"), encoding="utf-8")
    assert report(write(tmp_path, "world: arena.yml")) == [
        (
            "M:2:8: error: there is no world file 'arena.yml' beside the mission"
            " (did you mean 'arena.yaml'?)"
        )
    ]
    assert report(write(tmp_path, "world: arenna")) == [
        (
            "M:2:8: error: there is no world called 'arenna' (built-in worlds: corridor, empty,"
            " line-track, maze, square-room) (did you mean 'arena.yaml'?)"
        )
    ]


def test_a_misspelt_robot_is_offered_a_profile_file_beside_it_not_a_mission(
    tmp_path: Path,
) -> None:
    write(tmp_path, "", "squard.yaml")  # another mission, named like the robot
    (tmp_path / "squared.yaml").write_text("extends: mirto\ntrack_mm: 120\n", encoding="utf-8")
    assert report(write(tmp_path, "robot: squard")) == [
        (
            "M:2:8: error: there is no robot called 'squard' (built-in robots: mirto,"
            " asip-basic, stackmod-rover, stackmod-reference, spike-prime, plen2)"
            " (did you mean 'squared.yaml'?)"
        )
    ]


def test_a_world_file_beside_the_mission_is_found_from_any_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "rooms").mkdir()
    (tmp_path / "rooms" / "arena.yaml").write_text(WORLD.read_text(encoding="utf-8"))
    path = write(tmp_path, "world: rooms/arena.yaml")
    monkeypatch.chdir("/")
    spec, _profile, warnings = mission_for_robot(path)
    assert warnings == []
    assert spec.world == str((tmp_path / "rooms" / "arena.yaml").resolve())


def test_a_world_outside_the_mission_folder_or_not_a_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "arena.yaml").write_text(WORLD.read_text(encoding="utf-8"), encoding="utf-8")
    inner = tmp_path / "student"
    assert report(write(inner, "world: ../arena.yaml")) == [
        (
            "M:2:8: error: the world file '../arena.yaml' is outside the mission's folder"
            " (put it in the folder of the mission (student) or below, and name it from there)"
        )
    ]
    (inner / "dir.yaml").mkdir()
    assert report(write(inner, "world: dir.yaml")) == [
        "M:2:8: error: the world file 'dir.yaml' is not a regular file"
    ]
    (inner / "link.yaml").symlink_to(tmp_path / "arena.yaml")
    assert report(write(inner, "world: link.yaml")) == [
        (
            "M:2:8: error: the world file 'link.yaml' is outside the mission's folder"
            " (put it in the folder of the mission (student) or below, and name it from there)"
        )
    ]


def test_an_unknown_robot_is_reported_where_the_mission_names_it(tmp_path: Path) -> None:
    assert report(write(tmp_path, "robot: mirot")) == [
        (
            "M:2:8: error: there is no robot called 'mirot' (built-in robots: mirto, asip-basic,"
            " stackmod-rover, stackmod-reference, spike-prime, plen2) (did you mean 'mirto'?)"
        )
    ]


@pytest.mark.parametrize(
    ("written", "meant"),
    [
        ("SPIKE Prime", "spike-prime"),
        ("LEGO SPIKE Prime", "spike-prime"),
        ("spike_prime", "spike-prime"),
        ("StackMod Rover", "stackmod-rover"),
    ],
)
def test_a_robot_named_as_its_maker_writes_it_is_offered_roboscripts_name(
    tmp_path: Path, written: str, meant: str
) -> None:
    assert report(write(tmp_path, f"robot: {written}"))[0].endswith(f"(did you mean '{meant}'?)")


def test_a_robot_profile_file_beside_the_mission_sets_its_limits(tmp_path: Path) -> None:
    (tmp_path / "slow-bot.yaml").write_text("extends: mirto\nname: slow-bot\nmax_speed_mm_s: 200\n")
    assert report(write(tmp_path, "robot: slow-bot.yaml")) == [
        (
            "M:5:42: warning: drive speed: 250 mm/s is faster than slow-bot can drive, so it will"
            " drive at its top speed of 200 mm/s (write speed: 200 mm/s or less)"
        )
    ]
    assert report(write(tmp_path, "robot: slow-bott.yaml")) == [
        (
            "M:2:8: error: there is no robot profile file 'slow-bott.yaml' beside the mission"
            " (did you mean 'slow-bot.yaml'?)"
        )
    ]
    assert report(write(tmp_path / "sub", "robot: ../slow-bot.yaml")) == [
        (
            "M:2:8: error: the robot profile file '../slow-bot.yaml' is outside the mission's"
            " folder (put it in the folder of the mission (sub) or below, and name it from there)"
        )
    ]


def test_an_inner_mission_must_exist_beside_the_mission(tmp_path: Path) -> None:
    path = tmp_path / "outer.yaml"
    path.write_text(
        """\
mission: outer
states:
  go:
    do: {mission: patrl.yaml}
    on: {done: up, failed: up}
  up:
    do: {mission: ../elsewhere.yaml}
    on: {done: end, failed: end}
  end:
    final: success
""",
        encoding="utf-8",
    )
    write(tmp_path, "", "patrol.yaml")
    (tmp_path.parent / "elsewhere.yaml").write_text(DRIVE.replace("HEADER", ""))
    assert report(path) == [
        (
            "M:4:19: error: there is no mission file 'patrl.yaml' beside the mission"
            " (did you mean 'patrol.yaml'?)"
        ),
        (
            "M:7:19: error: the mission file '../elsewhere.yaml' is outside the mission's folder"
            f" (put it in the folder of the mission ({tmp_path.name}) or below, and name it from"
            " there)"
        ),
    ]


def test_a_behaviour_outside_the_mission_folder_is_refused_before_import(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    this_py = Path(sys.modules["os"].__file__ or "").parent / "this.py"
    assert this_py.is_file()
    path = write(tmp_path, f"behaviours: [{this_py}]")
    assert report(path) == [
        (
            f"M:2:14: error: the behaviour file '{this_py}' is outside the mission's folder"
            f" (put it in the folder of the mission ({tmp_path.name}) or below, and name it from"
            " there)"
        )
    ]
    # this.py prints the Zen of Python when it is imported: it never was.
    assert "Beautiful is better than ugly" not in capsys.readouterr().out


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
    assert report(write(tmp_path, f'robot: "{written}"')) == [
        f"M:2:8: error: there is no robot profile file '{shown}' beside the mission"
    ]


def test_a_robot_name_like_nothing_gets_the_profile_file_hint(tmp_path: Path) -> None:
    assert report(write(tmp_path, "robot: zzzzqqq")) == [
        (
            "M:2:8: error: there is no robot called 'zzzzqqq' (built-in robots: mirto,"
            " asip-basic, stackmod-rover, stackmod-reference, spike-prime, plen2) (or name a"
            " profile file beside the mission, e.g. robot: my-robot.yaml)"
        )
    ]


def test_a_world_name_like_nothing_gets_the_world_file_hint(tmp_path: Path) -> None:
    assert report(write(tmp_path, "world: zzzzqqq")) == [
        (
            "M:2:8: error: there is no world called 'zzzzqqq' (built-in worlds: corridor, empty,"
            " line-track, maze, square-room) (or name a world file beside the mission,"
            " e.g. world: my-room.yaml)"
        )
    ]


def test_a_misspelt_world_file_in_a_folder_below_gets_a_did_you_mean(tmp_path: Path) -> None:
    (tmp_path / "rooms").mkdir()
    (tmp_path / "rooms" / "kitchen.yaml").write_text("name: kitchen\n", encoding="utf-8")
    assert report(write(tmp_path, "world: rooms/kitchn.yaml")) == [
        (
            "M:2:8: error: there is no world file 'rooms/kitchn.yaml' beside the mission"
            " (did you mean 'rooms/kitchen.yaml'?)"
        )
    ]


def test_only_yaml_files_are_offered_for_a_missing_world_file(tmp_path: Path) -> None:
    (tmp_path / "kitchen.txt").write_text("notes\n", encoding="utf-8")
    (tmp_path / "kitchen.yml.d").mkdir()
    assert report(write(tmp_path, "world: kitchen.yml")) == [
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
