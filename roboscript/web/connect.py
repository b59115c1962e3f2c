"""A real robot from the browser app: the port the student chose, the run on it, and its stop.

The page's Connect buttons open the browser's chooser (Web Serial for a USB cable, Web
Bluetooth for a SPIKE hub); the page keeps what the student chose and names it with
:func:`remember`. A run on the robot is :func:`roboscript.web.bridge.run_text` with that URL,
in the page's worker, in real time, with a wire log like ``roboscript run --wire-log``; the
page relays the port's bytes (:mod:`roboscript.transport.webport`, and :func:`from_page` for
what the page says). Once the handshake is done the worker hands the page the robot's stop
(:func:`stop_bytes`): Stop, a closing tab or a worker that no longer answers make the page
write it by itself, while the run, if its worker still answers, ends at its next wait with the
reason the page gave, as after Ctrl-C on the command line.
"""

from __future__ import annotations

import contextlib
import json
import logging
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from roboscript.drivers import protocol_unit
from roboscript.drivers.recognise import RobotPicker, robots_picked_with
from roboscript.errors import RoboscriptError
from roboscript.profiles import RobotProfile, get_profile
from roboscript.robot import Robot
from roboscript.transport.ble import SERVICE_UUID
from roboscript.transport.webport import WebPort, chosen_robot, deliver, port_url

__all__ = [
    "ROBOT_LIST",
    "RobotRun",
    "bluetooth_options",
    "from_page",
    "on_robot",
    "remember",
    "serial_filters",
    "stop_bytes",
]

logger = logging.getLogger(__name__)

from_page = deliver
"""What the page says of the port it holds for a run (:func:`roboscript.transport.webport.
deliver`): the worker calls it with each of the page's messages."""

ROBOT_LIST = RobotPicker(
    "choose {robot} in the Robot list, and run again", "choose it in the Robot list", chosen_robot
)
"""The page's own control for the robot (its Robot list), which a failed handshake's hints
name: a student in the page cannot give ``--robot``; and the robot named as the student chose
it ("the robot on the serial port you chose"), not by a ``webserial://1`` they never saw."""


def remember(scheme: str, number: int) -> str:
    """The URL of the ``number``-th port (``"webserial"``) or hub (``"webbluetooth"``) the
    student chose in the page (the page keeps the browser's object under it)."""
    return port_url(scheme, number)


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

    On a page's port (``webserial://``, ``webbluetooth://``) the robot's stop
    (:func:`stop_bytes`) is worked out before the port opens, so that once the handshake is
    done the page has it at once: from then on the page hears from the worker all the while,
    and a worker busy working it out would look like one that no longer answers.

    Attributes:
        options: Keyword arguments for :func:`~roboscript.session.run_session`.
        wire_log: The path of the run's wire log, or ``None`` on the simulator.
    """

    def __init__(self, port: str, folder: Path, profile: RobotProfile | None = None) -> None:
        self.wire_log = folder / "wire.log" if port else None
        self.options: dict[str, Any] = {}
        self._stop = _stop_of(profile) if port and profile and chosen_robot(port) else b""
        if port:
            self.options = {
                "port": port,
                "wire_log": str(self.wire_log),
                "on_connected": self._connected,
            }

    def _connected(self, robot: Robot) -> None:
        """The handshake is done: the page gets the robot's stop, and says the mission runs."""
        port = robot.driver.link.port
        if isinstance(port, WebPort):
            port.ready(self._stop or _stop_of(robot.profile))

    def answer(self) -> dict[str, str]:
        """What the page is told besides the run's summary: ``{"wire_log": its text}`` after
        a run on a robot (as ``roboscript run --wire-log`` writes it), else nothing."""
        if self.wire_log is None or not self.wire_log.is_file():
            return {}
        return {"wire_log": self.wire_log.read_text(encoding="utf-8")}


class _Tap:
    """A port that keeps a copy of what is written through it."""

    def __init__(self, port: Any) -> None:
        self.port = port
        self.written = bytearray()

    def __getattr__(self, name: str) -> Any:
        return getattr(self.port, name)

    def read(self, size: int = 1) -> bytes:
        data: bytes = self.port.read(size)
        return data

    def close(self) -> None:
        self.port.close()

    def write(self, data: bytes, /) -> int | None:
        self.written += data
        written: int | None = self.port.write(data)
        return written


def stop_bytes(profile: RobotProfile) -> bytes:
    """What the robot's driver sends to stop every actuator, just after its handshake.

    Taken from the driver's own stop (:meth:`roboscript.robot.Robot.stop`), on the in-process
    simulator of ``profile``, which speaks the real protocol: the page writes these bytes by
    itself when it must stop the robot without the run's help.
    """
    with Robot.connect(profile) as robot:
        link = robot.driver.link
        tap = _Tap(link.port)
        link.port = tap
        try:
            robot.stop()
        finally:
            link.port = tap.port
    return bytes(tap.written)


def _stop_of(profile: RobotProfile) -> bytes:
    """:func:`stop_bytes`, or none for a robot whose simulator cannot be had (the page then
    leaves the stop to the run, as on the command line): the run goes on either way."""
    try:
        return stop_bytes(profile)
    except RoboscriptError as exc:
        logger.warning("the page cannot stop %s by itself: %s", profile.name, exc)
        return b""


@contextlib.contextmanager
def on_robot(port: str, folder: Path, profile: RobotProfile | None = None) -> Iterator[RobotRun]:
    """A run on the robot at ``port`` (``""``: on the simulator).

    A handshake that fails names the page's Robot list (:data:`ROBOT_LIST`), not ``--robot``,
    and the robot as the student chose it, not by its port's URL.

    Args:
        port: A URL :func:`remember` gave, or ``""``.
        folder: Where the wire log is written.
        profile: The robot the run is for (its stop is worked out before the port opens).
    """
    with robots_picked_with(ROBOT_LIST):
        yield RobotRun(port, folder, profile)
