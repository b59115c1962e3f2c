"""The driver and an ASIP board that resets when its port opens (an Arduino Uno's DTR).

The simulated board with ``reset=1`` is deaf while its sketch starts again, as the real one
is (``tests/firmware/test_asip_reset.py`` holds it to the firmware): the driver must wait for
it without losing a request or raising, and say in one sentence when it never answers.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from roboscript.drivers.asip.device import RESET_GREETING_S
from roboscript.errors import LinkTimeoutError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.robot_profile import RobotProfile
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
        assert robot.describe() == "Mirtle2017 on ATmega328P (ASIP 1.1)"


def test_a_board_that_never_finishes_booting_ends_the_connection_with_one_sentence() -> None:
    # a handshake bound shorter than the sketch's start-up: the board never answers in time
    impatient = dataclasses.replace(get_profile("mirto"), handshake_timeout_s=2.0)
    with pytest.raises(LinkTimeoutError) as raised:
        Robot.connect(impatient, port=RESETTING_UART_BOARD)
    message = str(raised.value)
    assert message.startswith(f"mirto did not answer on {RESETTING_UART_BOARD} within 2 s:")
    assert "\n" not in message
