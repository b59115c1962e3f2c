"""One contract every driver meets, run against its simulated robot over real protocol bytes.

Add a profile to ``WHEELED`` (or ``WALKING``) when its driver and simulated device land.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers import run_cli

from roboscript.robot import Robot
from roboscript.transport.wirelog import read_wire_log

WHEELED = ["mirto", "asip-basic"]
WALKING: list[str] = []


@pytest.mark.parametrize("robot", WHEELED)
def test_wheels_hold_a_speed_and_stop(robot: str) -> None:
    with Robot.connect(robot, seed=3) as bot:
        base = bot.drive_base
        start = base.wheel_distances_mm()
        base.set_wheel_speeds(100.0, 100.0)
        bot.run_for(2.0)
        left, right = base.wheel_distances_mm()
        travelled = ((left - start[0]) + (right - start[1])) / 2
        assert 150.0 < travelled < 230.0, travelled
        base.stop()
        bot.run_for(0.5)
        settled = base.wheel_distances_mm()
        bot.run_for(0.5)
        assert base.wheel_distances_mm() == pytest.approx(settled, abs=1.0)


@pytest.mark.parametrize("robot", WHEELED)
def test_positive_turn_is_clockwise(robot: str) -> None:
    with Robot.connect(robot, seed=3) as bot:
        bot.drive_base.set_wheel_speeds(80.0, -80.0)
        bot.run_for(1.0)
        heading = bot.simulation.body.heading_deg
    assert 20.0 < heading < 90.0, heading


@pytest.mark.parametrize("robot", WHEELED)
def test_beep_reaches_the_simulated_speaker(robot: str) -> None:
    with Robot.connect(robot) as bot:
        bot.speaker.beep(523.0, 0.25)
        bot.run_for(0.1)
        tones = bot.simulation.log.tones
    assert [(f, d) for _, f, d in tones] == [(523.0, 0.25)]


@pytest.mark.parametrize("robot", WHEELED + WALKING)
def test_exit_sends_stop_while_the_link_is_writable(robot: str, tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    with pytest.raises(RuntimeError), Robot.connect(robot, wire_log=str(log)) as bot:
        if bot.has("drive_base"):
            bot.drive_base.set_wheel_speeds(150.0, 150.0)
        bot.run_for(0.3)
        raise RuntimeError("student code crashed")
    sent = [data for _, direction, data in read_wire_log(log) if direction == ">"]
    assert sent, "nothing was sent"
    assert all(abs(power) < 1e-9 for power in bot.simulation.body.power)


@pytest.mark.parametrize("robot", WHEELED)
def test_square_mission_succeeds(robot: str) -> None:
    result = run_cli("run", "missions/square.yaml", "--robot", robot, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["outcome"] == "success"
    assert len(summary["sim"]["tones"]) == 4
    pose = summary["sim"]["final_pose"]
    assert (pose["x_mm"] ** 2 + pose["y_mm"] ** 2) ** 0.5 < 80.0
