"""The driver and an ASIP board that resets when its port opens (an Arduino Uno's DTR).

The simulated board with ``reset=1`` is deaf while its sketch starts again, as the real one
is (``tests/firmware/test_asip_reset.py`` holds it to the firmware): the driver must wait for
it without losing a request or raising, and say in one sentence when it never answers.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from helpers import ROOT

from roboscript.drivers.asip.device import (
    OPTIBOOT_EXIT_S,
    OPTIBOOT_FLASHES_S,
    OPTIBOOT_WAIT_S,
    RESET_GREETING_S,
)
from roboscript.errors import LinkTimeoutError
from roboscript.mission import load_mission
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.robot_profile import RobotProfile
from roboscript.session import Session, run_session
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.transport.wirelog import read_wire_log

RESETTING_UART_BOARD = "sim://mirto?reset=1"


def _uno_style_mirto() -> RobotProfile:
    """A profile file's robot: ``extends: mirto``, a UART board that resets on connect."""
    mirto = get_profile("mirto")
    options = {**mirto.options, "transport": "uart", "reset_on_connect": True}
    return dataclasses.replace(mirto, name="mirto-uno", options=options)


def test_the_driver_waits_for_a_board_that_resets_when_its_port_opens(tmp_path: Path) -> None:
    log = tmp_path / "run.wire"
    with Robot.connect(_uno_style_mirto(), wire_log=str(log)) as robot:
        assert robot.driver.ready_s is not None
        assert robot.driver.ready_s >= RESET_GREETING_S  # it was waited for, not assumed
        assert robot.driver.device_errors == []
        assert robot.simulation is not None
        board = robot.simulation.device
        assert board.config.resets_on_connect  # type: ignore[attr-defined]
        assert not board.config.whole_lines  # type: ignore[attr-defined]  # a UART board
        robot.display.show_text("hello")  # the first requests after the handshake
        robot.drive_base.set_wheel_speeds(150, 150)
        robot.run_for(1.0)
        assert robot.simulation.body.wheel_speed_mm_s[0] > 100
        assert board.state.lcd_rows[0] == "hello"  # type: ignore[attr-defined]
        assert robot.driver.device_errors == []
    received = b"".join(data for _, direction, data in read_wire_log(log) if direction == "<")
    assert received.startswith(b"!Mirtle2017 running on ATmega328P")


def test_a_sim_url_with_reset_is_waited_for_too() -> None:
    with Robot.connect("mirto", port=RESETTING_UART_BOARD) as robot:
        assert robot.driver.ready_s is not None
        assert robot.driver.ready_s >= RESET_GREETING_S
        # named by its start-up line, or by its version reply when a probe of the driver's
        # reached its receive ring in the 0.2 s between its UART opening and its greeting
        assert robot.describe().startswith("Mirtle2017 on ATmega328P (ASIP")


def test_a_board_that_never_finishes_booting_ends_the_connection_with_one_sentence() -> None:
    # a handshake bound shorter than the sketch's start-up: the board never answers in time
    impatient = dataclasses.replace(get_profile("mirto"), handshake_timeout_s=2.0)
    with pytest.raises(LinkTimeoutError) as raised:
        Robot.connect(impatient, port=RESETTING_UART_BOARD)
    message = str(raised.value)
    assert message.startswith(f"mirto did not answer on {RESETTING_UART_BOARD} within 2 s:")
    assert "\n" not in message


def _uno_board(*, written_at_open: bytes) -> tuple[Simulation, float]:
    """A Uno-style MIRTO opened at 0 s (``written_at_open`` written at once, as a host
    would): the simulation and when its start-up line came, seconds."""
    simulation = make_simulation("mirto", "empty", 1, options=_uno_style_mirto().options)
    simulation.connect()
    simulation.write(written_at_open)
    for step in range(1, 1200):
        simulation.tick(step * 0.005, 0.005)
        if simulation.read(simulation.in_waiting).startswith(b"!Mirtle2017"):
            return simulation, step * 0.005
    raise AssertionError("it never greeted")


def test_a_board_opened_in_silence_waits_out_its_bootloader_before_the_sketch_starts() -> None:
    # optiboot flashes its LED (374.8 ms), waits 1 s for an upload, then starts the sketch
    _, greeted_s = _uno_board(written_at_open=b"")
    expected_s = OPTIBOOT_FLASHES_S + OPTIBOOT_WAIT_S + RESET_GREETING_S
    assert expected_s <= greeted_s < expected_s + 0.005


def test_the_hosts_first_bytes_end_the_bootloader_and_are_lost() -> None:
    # two bytes that are no upload's make optiboot start the sketch 16 ms later
    simulation, greeted_s = _uno_board(written_at_open=b"#,?\n")
    expected_s = OPTIBOOT_FLASHES_S + OPTIBOOT_EXIT_S + RESET_GREETING_S
    assert expected_s <= greeted_s < expected_s + 0.005
    simulation.tick(greeted_s + 0.2, 0.2)
    assert b"@#,?" not in simulation.read(simulation.in_waiting)  # the bootloader took it


def test_a_uno_style_board_is_ready_within_the_handshakes_bound_however_it_is_opened() -> None:
    with Robot.connect(_uno_style_mirto()) as robot:
        ready_s = robot.driver.ready_s
    assert ready_s is not None
    assert OPTIBOOT_FLASHES_S + RESET_GREETING_S < ready_s < _uno_style_mirto().handshake_timeout_s


def _run_reset_mid_mission(
    profile: RobotProfile, reset_after_s: float
) -> tuple[Session, Simulation]:
    """Run ``missions/square.yaml``; the simulated board resets ``reset_after_s`` after the
    handshake (its supply dipping, or another program opening its port)."""
    spec, _ = load_mission(ROOT / "missions" / "square.yaml", profile)
    reset: list[float] = []

    def maybe_reset(runner: object, robot: Robot) -> None:
        driver, simulation = robot.driver, robot.simulation
        assert driver.ready_s is not None and simulation is not None
        if not reset and simulation.time_s >= driver.ready_s + reset_after_s:
            assert any(abs(power) > 0.1 for power in simulation.body.power)  # driving
            simulation.device.reset(simulation.time_s)  # type: ignore[attr-defined]
            reset.append(simulation.time_s)

    session = run_session(spec, profile, max_time_s=60.0, on_tick=maybe_reset)
    assert reset
    simulation = session.simulation
    assert isinstance(simulation, Simulation)
    return session, simulation


@pytest.mark.parametrize("reset_on_connect", [True, False])
def test_a_board_that_resets_mid_mission_ends_the_run_and_its_motors_stay_off(
    reset_on_connect: bool,
) -> None:
    profile = _uno_style_mirto()
    profile = dataclasses.replace(
        profile, options={**profile.options, "reset_on_connect": reset_on_connect}
    )
    session, simulation = _run_reset_mid_mission(profile, 1.0)
    result = session.result
    assert result.outcome == "error", (result.outcome, result.reason)
    # the sketch is silent for 3.2 s while it starts again: the silence limit ends the run
    assert (result.reason or "").startswith("the robot stopped responding "), result.reason
    # the board comes back and reads what reached it once its UART was open: nothing of the
    # mission may start its motors again
    for _ in range(round(6.0 / 0.02)):
        simulation.tick(simulation.time_s + 0.02, 0.02)
        assert all(abs(power) < 1e-9 for power in simulation.body.power)
    assert simulation.device._booting is None  # type: ignore[attr-defined]  # it did come back
