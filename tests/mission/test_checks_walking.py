"""Wheel actions on a walking robot, and gait actions on a wheeled one, are refused at load time."""

from __future__ import annotations

from helpers import run_cli

DRIVE_ERROR = (
    "missions/square.yaml:6:10: error: 'drive' needs drive_base (two driven wheels with"
    " encoders or timing), which plen2 does not have (use walk/turn on a walking robot)"
)


def test_check_refuses_a_wheeled_mission_for_the_plen2() -> None:
    result = run_cli("check", "missions/square.yaml", "--robot", "plen2")
    assert result.returncode == 2
    lines = result.stderr.splitlines()
    assert lines[0] == DRIVE_ERROR
    # The tone has no suggestion: the PLEN2 has no display to signal with either.
    assert (
        "missions/square.yaml:15:10: error: 'play_tone' needs speaker (a tone generator),"
        " which plen2 does not have"
    ) in lines


def test_run_refuses_it_before_connecting() -> None:
    result = run_cli("run", "missions/square.yaml", "--robot", "plen2", "--json")
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.splitlines()[0] == DRIVE_ERROR


def test_a_walking_mission_on_a_wheeled_robot_suggests_drive_and_rotate() -> None:
    result = run_cli("check", "missions/plen_walk.yaml", "--robot", "mirto")
    assert result.returncode == 2
    assert (
        "'walk' needs walker (legs that walk by gait motions), which mirto does not have"
        " (use drive/rotate on a wheeled robot)"
    ) in result.stderr


def test_the_walking_example_checks_clean_for_its_own_robot() -> None:
    assert run_cli("check", "missions/plen_walk.yaml").returncode == 0
