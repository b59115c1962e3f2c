"""A real robot from the browser app: the port the student chose, the run on it, and its stop.

The page's Connect buttons open the browser's chooser (Web Serial for a USB cable, Web
Bluetooth for a SPIKE hub) and hand the choice to :func:`remember`; a run on the robot is
:func:`roboscript.web.bridge.run_text` with the URL it answered, in real time, with a wire log
like ``roboscript run --wire-log``. While it runs, :func:`stop_robot` is what the page's Stop
button, its tab closing and a lost link call: the robot's own stop goes out at once, by the
robot's usual path (:meth:`roboscript.robot.Robot.stop`), and the run then ends at its next
wait with that reason, as after Ctrl-C on the command line.
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from roboscript.drivers import protocol_unit
from roboscript.drivers.recognise import RobotPicker, robots_picked_with
from roboscript.errors import LinkError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.transport.ble import SERVICE_UUID
from roboscript.transport.webport import chosen_robot, interrupt_open_ports, remember_chosen

__all__ = [
    "ROBOT_LIST",
    "RobotRun",
    "bluetooth_options",
    "on_robot",
    "remember",
    "robot_ready",
    "serial_filters",
    "stop_robot",
]

_running: Robot | None = None
"""The robot a run in this page is driving, while it runs."""

ROBOT_LIST = RobotPicker(
    "choose {robot} in the Robot list, and run again", "choose it in the Robot list", chosen_robot
)
"""The page's own control for the robot (its Robot list), which a failed handshake's hints
name: a student in the page cannot give ``--robot``; and the robot named as the student chose
it ("the robot on the serial port you chose"), not by a ``webserial://1`` they never saw."""


def remember(scheme: str, device: Any) -> str:
    """The URL of a port (``"webserial"``) or hub (``"webbluetooth"``) the student chose."""
    return remember_chosen(scheme, device)


def serial_filters(robot: str) -> str:
    """The USB boards the browser's chooser lists for ``robot``, as Web Serial's filters.

    Returns:
        JSON ``[{"usbVendorId": V, "usbProductId": P}, ...]`` (no product: any of the
        vendor's), from the robot's protocol (:attr:`ProtocolUnit.usb
        <roboscript.drivers.unit.ProtocolUnit.usb>`); ``[]`` lists every port.
    """
    filters: list[dict[str, int]] = []
    for vendor, product, _board in protocol_unit(get_profile(robot).protocol).usb:
        found = {"usbVendorId": vendor}
        if product is not None:
            found["usbProductId"] = product
        filters.append(found)
    return json.dumps(filters)


def bluetooth_options() -> str:
    """Web Bluetooth's ``requestDevice`` options: hubs advertising the SPIKE Prime service."""
    return json.dumps({"filters": [{"services": [SERVICE_UUID]}]})


class RobotRun:
    """What :func:`on_robot` gives a run: its options, then its wire log.

    Attributes:
        options: Keyword arguments for :func:`~roboscript.session.run_session`.
        wire_log: The path of the run's wire log, or ``None`` on the simulator.
    """

    def __init__(self, port: str, folder: Path) -> None:
        self.wire_log = folder / "wire.log" if port else None
        self.options: dict[str, Any] = {}
        if port:
            self.options = {
                "port": port,
                "wire_log": str(self.wire_log),
                "on_connected": _connected,
            }

    def answer(self) -> dict[str, str]:
        """What the page is told besides the run's summary: ``{"wire_log": its text}`` after
        a run on a robot (as ``roboscript run --wire-log`` writes it), else nothing."""
        if self.wire_log is None or not self.wire_log.is_file():
            return {}
        return {"wire_log": self.wire_log.read_text(encoding="utf-8")}


def _connected(robot: Robot) -> None:
    global _running
    _running = robot


@contextlib.contextmanager
def on_robot(port: str, folder: Path) -> Iterator[RobotRun]:
    """A run on the robot at ``port`` (``""``: on the simulator); the robot is forgotten after.

    A handshake that fails names the page's Robot list (:data:`ROBOT_LIST`), not ``--robot``,
    and the robot as the student chose it, not by its port's URL.

    Args:
        port: A URL :func:`remember` gave, or ``""``.
        folder: Where the wire log is written.
    """
    global _running
    try:
        with robots_picked_with(ROBOT_LIST):
            yield RobotRun(port, folder)
    finally:
        _running = None


def robot_ready() -> bool:
    """Whether the run has reached its robot (the handshake is done) and runs the mission."""
    return _running is not None


def stop_robot(reason: str) -> bool:
    """Stop the robot now, and end its run with ``reason`` (one plain sentence).

    Called by the page while the run waits (its Stop button, ``pagehide``): the stop command
    goes out before anything else, and the run ends at its next wait, stopping the robot
    again on its way out as every run does. A run still shaking hands ends too (the handshake
    stops the robot as it gives up).

    Returns:
        Whether a run on a robot was going on.
    """
    robot = _running
    if robot is not None:
        with contextlib.suppress(LinkError):  # a link already gone: the run says so itself
            robot.stop()
    return interrupt_open_ports(reason) or robot is not None
