"""One contract every driver meets, run against its simulated robot over real protocol bytes.

The profiles come from the protocol units (``PROTOCOL.contract`` in each
``roboscript/drivers/<protocol>/__init__.py``): a protocol lists its profiles there, not here.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest
from helpers import ROOT, run_cli

from roboscript.drivers import contract_cases
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.session import Session, run_session
from roboscript.transport.wirelog import read_wire_log

WHEELED = list(contract_cases().wheeled)
WALKING = list(contract_cases().walking)
OPEN_LOOP = list(contract_cases().open_loop)


@pytest.mark.parametrize("robot", WHEELED + OPEN_LOOP)
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


@pytest.mark.parametrize("robot", WHEELED + OPEN_LOOP)
def test_positive_turn_is_clockwise(robot: str) -> None:
    with Robot.connect(robot, seed=3) as bot:
        bot.drive_base.set_wheel_speeds(80.0, -80.0)
        bot.run_for(1.0)
        heading = bot.simulation.body.heading_deg
    assert 20.0 < heading < 90.0, heading


@pytest.mark.parametrize("robot", WHEELED)
def test_beep_reaches_the_simulated_speaker(robot: str) -> None:
    with Robot.connect(robot) as bot:
        if getattr(bot.speaker, "fixed_frequency_hz", None) is not None:
            pytest.skip("a one-pitch buzzer cannot play 523 Hz (see its driver's own tests)")
        bot.speaker.beep(523.0, 0.25)
        bot.run_for(0.1)
        tones = bot.simulation.log.tones
    assert [(f, d) for _, f, d in tones] == [(523.0, 0.25)]


@pytest.mark.parametrize("robot", WHEELED)
def test_exit_sends_stop_while_the_link_is_writable(robot: str) -> None:
    with pytest.raises(RuntimeError), Robot.connect(robot) as bot:
        bot.drive_base.set_wheel_speeds(150.0, 150.0)
        bot.run_for(0.3)
        assert any(abs(power) > 0.1 for power in bot.simulation.body.power)
        raise RuntimeError("student code crashed")
    # No tick ran after the crash: only the stop sent on the way out can have cut the power.
    assert all(abs(power) < 1e-9 for power in bot.simulation.body.power)


@pytest.mark.parametrize("robot", WALKING)
def test_walking_two_steps_moves_about_two_strides_forward(robot: str) -> None:
    with Robot.connect(robot, seed=3) as bot:
        walker = bot.capabilities["walker"]
        walker.walk(2)
        assert walker.busy()
        assert bot.scheduler.run(until=lambda: not walker.busy(), max_duration_s=30.0)
        body = bot.simulation.body
    assert 1.6 * walker.stride_mm < body.y_mm < 2.4 * walker.stride_mm, body.y_mm
    assert abs(body.x_mm) < 0.2 * walker.stride_mm


@pytest.mark.parametrize("robot", WALKING)
def test_turning_two_steps_right_is_clockwise(robot: str) -> None:
    with Robot.connect(robot, seed=3) as bot:
        walker = bot.capabilities["walker"]
        walker.turn(2)
        assert bot.scheduler.run(until=lambda: not walker.busy(), max_duration_s=30.0)
        heading = bot.simulation.body.heading_deg
    assert 1.6 * walker.turn_step_deg < heading < 2.4 * walker.turn_step_deg, heading


@pytest.mark.parametrize("robot", WALKING)
def test_exit_while_walking_stops_within_a_step(robot: str, tmp_path: Path) -> None:
    log = tmp_path / "wire.log"
    with pytest.raises(RuntimeError), Robot.connect(robot, wire_log=str(log)) as bot:
        walker = bot.capabilities["walker"]
        walker.walk(10)
        bot.run_for(1.5)
        raise RuntimeError("student code crashed")
    sent = b"".join(data for _, direction, data in read_wire_log(log) if direction == ">")
    assert sent.endswith(b"$SM"), sent[-40:]  # the stop went out last, on the way out
    sim = bot.simulation
    sim.tick(sim.time_s + 15.0, 15.0)  # the robot's own firmware runs on, undriven
    assert sim.body.y_mm < 3.0 * walker.stride_mm, sim.body.y_mm


@pytest.mark.parametrize("robot", WHEELED)
def test_square_mission_succeeds(robot: str) -> None:
    result = run_cli("run", "missions/square.yaml", "--robot", robot, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["outcome"] == "success"
    assert len(summary["sim"]["tones"]) == 4
    pose = summary["sim"]["final_pose"]
    assert (pose["x_mm"] ** 2 + pose["y_mm"] ** 2) ** 0.5 < 80.0


# ------------------------------------------------------------------------- silence and loss


class _FailingPort:
    """The simulated robot's port, made to fall silent or be lost at a scheduler time.

    Silent: the robot still hears the host but says nothing. Lost: every read and write fails
    the way a pulled USB cable does (``OSError``), so the real :class:`Link` sees it.
    """

    def __init__(self, port: Any, clock: Any, *, silent_from_s: float, lost: bool) -> None:
        self.port = port
        self.clock = clock
        self.from_s = silent_from_s
        self.lost = lost
        self.written_after = bytearray()

    def _failed(self) -> bool:
        return bool(self.clock.now() >= self.from_s)

    def read(self, size: int = 1) -> bytes:
        data: bytes = self.port.read(size)
        if not self._failed():
            return data
        if self.lost:
            raise OSError("device disconnected")
        return b""

    def write(self, data: bytes, /) -> int | None:
        if self._failed():
            if self.lost:
                raise OSError("device disconnected")
            self.written_after += data
        written: int | None = self.port.write(data)
        return written

    def close(self) -> None:
        self.port.close()


def _mission_for(robot: str) -> Path:
    return ROOT / "missions" / ("plen_walk.yaml" if robot in WALKING else "square.yaml")


def _run_failing(robot: str, *, after_s: float, lost: bool) -> tuple[Session, _FailingPort]:
    profile = get_profile(robot)
    spec, _ = load_mission(_mission_for(robot), profile)
    ports: list[_FailingPort] = []

    def fail_later(bot: Robot) -> None:
        link = bot.driver.link
        port = _FailingPort(
            link.port, link.clock, silent_from_s=link.clock.now() + after_s, lost=lost
        )
        link.port = port
        ports.append(port)

    session = run_session(spec, profile, max_time_s=120.0, on_connected=fail_later)
    return session, ports[0]


def _seconds_after_connecting(reason: str) -> float:
    match = re.search(r" ([0-9.]+) s after connecting", reason)
    assert match, reason
    return float(match.group(1))


@pytest.mark.parametrize("robot", WHEELED + WALKING)
def test_a_robot_silent_right_after_the_handshake_fails_the_mission(robot: str) -> None:
    session, port = _run_failing(robot, after_s=0.0, lost=False)
    result = session.result
    assert result.outcome == "error", (result.outcome, result.reason)
    reason = result.reason or ""
    assert reason.startswith("the robot stopped responding "), reason
    assert "None" not in reason
    connected = session.robot.driver.ready_s - session.robot.driver.connected_s
    # Noticed within a few seconds of the silence, not at the mission's time limit.
    assert connected <= _seconds_after_connecting(reason) <= connected + 3.0, reason
    assert port.written_after  # the host kept talking (and sent its stop) into the silence


@pytest.mark.parametrize("robot", WHEELED + WALKING)
def test_a_robot_silent_mid_mission_stops_and_fails(robot: str) -> None:
    session, _ = _run_failing(robot, after_s=2.0, lost=False)
    result = session.result
    assert result.outcome == "error", (result.outcome, result.reason)
    assert (result.reason or "").startswith("the robot stopped responding "), result.reason
    sim = session.simulation
    assert all(abs(power) < 1e-9 for power in getattr(sim.body, "power", (0.0,)))


@pytest.mark.parametrize("robot", WHEELED + WALKING)
def test_a_link_lost_mid_mission_says_what_and_when(robot: str) -> None:
    session, _ = _run_failing(robot, after_s=1.5, lost=True)
    result = session.result
    assert result.outcome == "error", (result.outcome, result.reason)
    reason = result.reason or ""
    url = session.robot.url
    assert reason.startswith(f"the connection to {url} was lost "), reason
    driver = session.robot.driver
    lost_at = driver.ready_s - driver.connected_s + 1.5
    assert lost_at - 0.05 <= _seconds_after_connecting(reason) <= lost_at + 0.1, reason
