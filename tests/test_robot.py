"""The robot container: connection, capabilities, and stopping on every way out."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from fake_asip import FakeAsipBoard
from helpers import HANG_BOUND_S

import roboscript.robot as robot_module
from roboscript.drivers.asip.driver import AsipDriver
from roboscript.errors import CapabilityError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.transport.wirelog import WireLog, read_wire_log


def test_connect_to_the_default_simulator_and_read_capabilities() -> None:
    with Robot.connect("mirto") as robot:
        assert robot.describe() == "Mirtle2017 on ATmega328P (ASIP 1.1)"
        assert {"drive_base", "range", "bumper", "line", "speaker", "display"} <= set(
            robot.capabilities
        )
        with pytest.raises(CapabilityError, match="mirto has no heading"):
            robot.require("heading")


def _last_sent(log: Path) -> list[bytes]:
    return [data for _, direction, data in read_wire_log(log) if direction == ">"]


def test_leaving_the_block_by_an_exception_stops_the_motors(tmp_path: Path) -> None:
    log = tmp_path / "run.wire"
    with pytest.raises(ZeroDivisionError), Robot.connect("mirto", wire_log=str(log)) as robot:
        robot.drive_base.set_wheel_speeds(200, 200)
        robot.run_for(0.5)
        assert robot.simulation.body.wheel_speed_mm_s[0] > 100
        _ = 1 / 0
    sent = _last_sent(log)
    assert sent[-2:] == [b"M,S,0\n", b"M,M,0,0\n"]
    assert robot.simulation.body.power == [0.0, 0.0]


def test_keyboard_interrupt_inside_the_block_stops_the_motors(tmp_path: Path) -> None:
    log = tmp_path / "run.wire"
    with pytest.raises(KeyboardInterrupt), Robot.connect("mirto", wire_log=str(log)) as robot:
        robot.drive_base.set_wheel_speeds(200, -200)
        robot.run_for(0.3)
        raise KeyboardInterrupt
    assert _last_sent(log)[-2:] == [b"M,S,0\n", b"M,M,0,0\n"]
    assert robot.simulation.body.power == [0.0, 0.0]


def test_wheel_speeds_use_firmware_pid_on_mirto(tmp_path: Path) -> None:
    log = tmp_path / "run.wire"
    with Robot.connect("mirto", wire_log=str(log)) as robot:
        robot.drive_base.set_wheel_speeds(150, 150)
        robot.run_for(1.0)
        left, right = robot.drive_base.wheel_distances_mm()
    assert any(data.startswith(b"M,R,45,45,3000") for data in _last_sent(log))
    assert 100 < left < 160 and 100 < right < 160


def test_asip_basic_holds_wheel_speeds_on_the_host(tmp_path: Path) -> None:
    log = tmp_path / "run.wire"
    with Robot.connect("asip-basic", wire_log=str(log)) as robot:
        robot.drive_base.set_wheel_speeds(150, 150)
        robot.run_for(2.0)
        speeds = robot.driver.wheel_speeds_mm_s
    sent = b"".join(_last_sent(log))
    assert b"M,R," not in sent and b"M,M," in sent
    assert all(120 < speed < 180 for speed in speeds)


@pytest.mark.parametrize("robot", ["mirto", "asip-basic"])
def test_stopping_after_steering_leaves_the_motors_unpowered(robot: str) -> None:
    with Robot.connect(robot) as bot:
        base = bot.drive_base
        for step in range(50):  # a new setpoint every tick: steering, held by the host
            base.set_wheel_speeds(120.0 + step, 120.0 - step)
            bot.run_for(0.02)
        assert bot.simulation.body.power != [0.0, 0.0]
        base.stop()
        bot.run_for(1.0)
        assert bot.simulation.body.power == [0.0, 0.0]
        assert max(abs(s) for s in bot.simulation.body.wheel_speed_mm_s) < 1.0


def test_a_busy_machine_does_not_cost_a_robot_its_handshake(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A board that answers 1.5 s after the connection, to a host with a 0.5 s handshake limit
    # that this process spent waiting for a CPU (as the system reports it): that time was not
    # spent listening, so the board is given it again and is heard.
    reported = iter([0.0])
    monkeypatch.setattr(robot_module, "cpu_wait_s", lambda: next(reported, HANG_BOUND_S))
    profile = replace(get_profile("mirto"), handshake_timeout_s=0.5)
    board = FakeAsipBoard(answer_after_s=1.5)
    try:
        with Robot.connect(profile, board.url) as robot:
            assert robot.driver.ready
    finally:
        board.close()


@pytest.mark.parametrize("given_up", ["before its link", "after its link"])
def test_a_connection_given_up_closes_the_port_then_the_wire_log_even_if_a_signal_cuts_in(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, given_up: str
) -> None:
    # A signal lands while the robot connects (before the link exists, or during the
    # handshake), and another while its port closes: the wire log is closed after the port,
    # and still closed.
    closed: list[str] = []
    opening = robot_module.open_port

    def opened(url: str, **options: object) -> object:
        port = opening(url, **options)  # type: ignore[arg-type]
        close_port = port.close

        def close() -> None:
            closed.append("port")
            close_port()
            raise KeyboardInterrupt  # a second signal, while the port closes

        port.close = close  # type: ignore[method-assign]
        return port

    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    close_log = WireLog.close

    def logged_close(log: WireLog) -> None:
        closed.append("log")
        close_log(log)

    monkeypatch.setattr(robot_module, "open_port", opened)
    monkeypatch.setattr(WireLog, "close", logged_close)
    if given_up == "before its link":
        monkeypatch.setattr(AsipDriver, "make_codec", interrupted)
    else:
        monkeypatch.setattr(AsipDriver, "start", interrupted)
    log = tmp_path / "run.wire"
    with pytest.raises(KeyboardInterrupt):
        Robot.connect("mirto", wire_log=str(log))
    assert closed == ["port", "log"]
    assert log.exists()
