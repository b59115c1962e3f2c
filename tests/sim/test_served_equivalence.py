"""A mission run against ``roboscript sim --tcp`` behaves like one on the in-process simulator,
and a board without motor PID makes the host take over the wheels at run time."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from helpers import OUT_TURN_BEEP, run_cli, served_simulator

from roboscript.robot import Robot


def test_a_mission_over_tcp_matches_the_in_process_simulator(
    write_mission: Callable[..., Path],
) -> None:
    mission = write_mission(OUT_TURN_BEEP)
    local = json.loads(run_cli("run", str(mission), "--json").stdout)
    with served_simulator("mirto") as port:
        url = f"socket://127.0.0.1:{port}"
        remote_run = run_cli("run", str(mission), "--port", url, "--json")
    assert remote_run.returncode == 0, remote_run.stderr
    remote = json.loads(remote_run.stdout)
    assert remote["outcome"] == local["outcome"] == "success"
    assert [s for _, s in remote["states"]] == [s for _, s in local["states"]]
    for (t_remote, _), (t_local, _) in zip(remote["states"], local["states"], strict=True):
        assert abs(t_remote - t_local) < 0.5  # real time over TCP against simulated lockstep
    assert "sim" not in remote  # over a port roboscript cannot see the simulator's pose


def test_a_board_without_pid_hands_the_wheels_to_the_host() -> None:
    # The mirto profile expects firmware PID; this simulated board was built without it.
    with Robot.connect("mirto", port="sim://asip-basic?world=empty&seed=1") as bot:
        bot.drive_base.set_wheel_speeds(150.0, 150.0)
        bot.run_for(2.0)
        assert bot.driver.firmware_pid is False
        assert bot.driver.notices == [
            "this board's firmware has no motor PID: roboscript holds the wheel speeds itself"
        ]
        assert 200.0 < bot.simulation.body.y_mm < 330.0
