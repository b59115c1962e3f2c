"""Robots reached from the browser app: the page holds the port, its worker runs the mission.

In the browser app (``roboscript web build``) a student picks a robot in the browser's own
chooser (a user's click must ask for it). The ``SerialPort`` (Web Serial) or
``BluetoothDevice`` (Web Bluetooth) it gives lives in the page, and stays there: Web Bluetooth
exists in no worker. The page names it ``webserial://N`` or ``webbluetooth://N``
(:func:`port_url`), and a run on it goes on in the page's worker (``worker.js``), never on the
page's own thread, so a student's code that loops cannot keep the page from stopping the robot.
There :func:`~roboscript.transport.open_port` of such a URL gives a :class:`WebPort`, which
relays the protocol's bytes through the page in order, as messages:

* worker to page: ``{type: "port-open", url, baudRate, bluetooth: {service, rx, tx} | null}``,
  then ``{type: "port-write", data}`` for each write (a Bluetooth write already cut into the
  hub's packets, one message each), ``{type: "robot-ready", stop: [packets]}`` once the
  handshake is done (the robot's stop, which the page writes by itself when it must stop the
  robot without the worker), and ``{type: "port-close"}``;
* page to worker, through :func:`deliver`: ``opened``, ``failed`` (the browser's error),
  ``received`` (bytes), ``lost`` (the device went or a write failed) and ``interrupt`` (the
  page's Stop, with its reason).

Reads never block and return what has arrived; drivers and missions do not know they are in a
browser. Each port brings a :class:`PageClock` (:attr:`WebPort.clock`; the robot takes it, see
:meth:`~roboscript.robot.Robot.connect`): its waits hand the worker back to the browser with
Pyodide's ``run_sync`` (JavaScript Promise Integration, in every Chromium-family browser, the
only ones with Web Serial), so the page's messages are delivered, and it is where the page's
Stop and a lost link land, as :class:`~roboscript.interrupts.Interrupted`, exactly where Ctrl-C
lands on the command line; the run then stops the robot first, by its usual path. A lost link
ends the run with :data:`LOST_USB` or :data:`LOST_BLUETOOTH`. The ``js`` and ``pyodide``
modules exist only in the browser and are imported only there.
"""

from __future__ import annotations

import asyncio
import importlib
import logging
import time
from collections.abc import Callable, Iterable
from typing import Any

from serial import SerialException

from roboscript.errors import LinkError
from roboscript.interrupts import Interrupted
from roboscript.transport.ble import (
    DEFAULT_PACKET_SIZE,
    RX_CHARACTERISTIC,
    SERVICE_UUID,
    TX_CHARACTERISTIC,
    split_packets,
)

__all__ = [
    "LOST_BLUETOOTH",
    "LOST_USB",
    "PageClock",
    "WebBluetoothPort",
    "WebPort",
    "WebSerialPort",
    "chosen_robot",
    "deliver",
    "interrupt_open_ports",
    "open_web_port",
    "port_url",
]

logger = logging.getLogger(__name__)

LOST_USB = "the robot's USB connection was lost (was the cable pulled out?)"
LOST_BLUETOOTH = (
    "the Bluetooth connection to the hub was lost (is it still on, and near the computer?)"
)

_CHOSEN_ROBOT = {
    "webserial": "the robot on the serial port you chose",
    "webbluetooth": "the Bluetooth robot you chose",
}
"""A chosen port's robot, named as the student chose it (a scheme's URL means nothing to them)."""

_LONGEST_WAIT_S = 3600.0
"""A wait for the page's answer wakes when it comes; this only bounds one turn of it."""

_open_ports: list[WebPort] = []
"""The ports open (or opening) in this worker, most recent last."""


def _browser() -> tuple[Any, Any]:
    """The ``js`` module and ``pyodide.ffi``, which exist only in Pyodide.

    Raises:
        LinkError: Not running in a browser tab.
    """
    try:
        # imported by name: these modules exist only in Pyodide, never on a computer
        return importlib.import_module("js"), importlib.import_module("pyodide.ffi")
    except ImportError:
        raise LinkError(
            "webserial:// and webbluetooth:// ports exist only in roboscript's browser app "
            "(roboscript web build); on a computer use the port's name (roboscript ports)"
        ) from None


def port_url(scheme: str, number: int) -> str:
    """The URL of the ``number``-th port (``"webserial"``) or hub (``"webbluetooth"``) the
    student chose in the page.

    Raises:
        ValueError: Another scheme.
    """
    if scheme not in _CHOSEN_ROBOT:
        raise ValueError(f"expected webserial or webbluetooth, got {scheme!r}")
    return f"{scheme}://{number}"


def chosen_robot(url: str) -> str | None:
    """The robot at ``url`` as the student chose it in the page (``"the robot on the serial
    port you chose"``), or ``None`` for a URL that is not a page's port (``socket://...``)."""
    return _CHOSEN_ROBOT.get(url.partition("://")[0].lower())


def open_web_port(url: str, *, baudrate: int) -> WebPort:
    """Ask the page to open a port the student chose there, and wait for its answer.

    Args:
        url: What :func:`port_url` answered.
        baudrate: Line speed in bits per second (Web Serial only).

    Raises:
        LinkError: Not in a browser, no such port chosen, or it would not open.
        Interrupted: The page's Stop came first.
    """
    js, ffi = _browser()
    port: WebPort
    if url.startswith("webserial://"):
        port = WebSerialPort(js, ffi, url, baudrate=baudrate)
    else:
        port = WebBluetoothPort(js, ffi, url)
    _open_ports.append(port)
    try:
        port.open()
    except BaseException:
        _open_ports.remove(port)
        raise
    return port


def deliver(event: str, data: Any = None) -> None:
    """What the page says of the port it holds for this worker (see the module docstring).

    Args:
        event: ``opened``, ``failed``, ``received``, ``lost`` or ``interrupt``.
        data: The bytes received (a ``Uint8Array``, or ``bytes``), the browser's error, or the
            interrupt's reason (one plain sentence).
    """
    if event == "interrupt":
        interrupt_open_ports(str(data))
        return
    if not _open_ports:
        return  # a port closed already: what the page still had for it goes nowhere
    port = _open_ports[-1]
    if event == "received":
        port.received(data.to_bytes() if hasattr(data, "to_bytes") else bytes(data))
    elif event == "lost":
        port.link_lost(str(data or ""))
    else:
        port.answered(event, "" if data is None else str(data))


def interrupt_open_ports(reason: str) -> bool:
    """End every run on a port of this page at its next wait, for ``reason``.

    A run still shaking hands with its robot has no robot to stop yet; this reaches it too.

    Returns:
        Whether a port was open.
    """
    for port in _open_ports:
        port.clock.interrupt(reason)
    return bool(_open_ports)


# --------------------------------------------------------------------------- the clock


class PageClock:
    """Real time in a browser's worker, whose waits let the page's messages in.

    :meth:`sleep_until` suspends Python (``run_sync``) until the deadline, or until
    :meth:`interrupt` wakes it; meanwhile the worker takes the page's messages (bytes from the
    robot, Stop). It then raises :class:`~roboscript.interrupts.Interrupted` with the reason
    given, between two ticks, as Ctrl-C would.

    Args:
        ffi: ``pyodide.ffi``.
    """

    def __init__(self, ffi: Any) -> None:
        self._ffi = ffi
        self._origin = time.monotonic()
        self._waker: asyncio.Future[None] | None = None
        self._reason: str | None = None

    def now(self) -> float:
        """Seconds since this clock was made."""
        return time.monotonic() - self._origin

    def sleep_until(self, deadline_s: float) -> None:
        """Let the page's messages in until ``deadline_s`` (at least one turn of the loop).

        Raises:
            Interrupted: :meth:`interrupt` was called (once per call to it).
        """
        self._raise_if_interrupted()
        self._ffi.run_sync(self._wait(deadline_s - self.now()))
        self._raise_if_interrupted()

    def wait_until(self, done: Callable[[], bool]) -> None:
        """Let the page's messages in until ``done()`` is true (checked after each
        :meth:`wake`), or an interrupt comes.

        Raises:
            Interrupted: :meth:`interrupt` was called.
        """
        self._raise_if_interrupted()
        while not done():
            self._ffi.run_sync(self._wait(_LONGEST_WAIT_S, done))
            self._raise_if_interrupted()

    async def _wait(self, seconds: float, done: Callable[[], bool] | None = None) -> None:
        loop = asyncio.get_event_loop()
        waker: asyncio.Future[None] = loop.create_future()
        self._waker = waker
        # asked, or answered, between the call and this task's first step
        if self._reason is not None or (done is not None and done()):
            _settle(waker)
        # a timer even when late: the page's messages (bytes, Stop) get a turn
        timer = loop.call_later(max(seconds, 0.0), _settle, waker)
        try:
            await waker
        finally:
            timer.cancel()
            self._waker = None

    def wake(self) -> None:
        """End the wait under way now (the page answered what :meth:`wait_until` waits for)."""
        if self._waker is not None:
            _settle(self._waker)

    def interrupt(self, reason: str) -> None:
        """End the run at its next wait, for ``reason`` (one plain sentence); the first wins."""
        if self._reason is None:
            self._reason = reason
        if self._waker is not None:
            _settle(self._waker)

    def _raise_if_interrupted(self) -> None:
        reason, self._reason = self._reason, None
        if reason is not None:
            raise Interrupted(reason=reason)


def _settle(future: asyncio.Future[None]) -> None:
    if not future.done():
        future.set_result(None)


# ---------------------------------------------------------------------------- the ports


class WebPort:
    """A port the page holds, seen from the worker: bytes in and out as messages, in order.

    Args:
        js: The ``js`` module (the worker's global scope).
        ffi: ``pyodide.ffi``.
        url: The port's URL (:func:`port_url`).
        lost_reason: The sentence a lost link ends the run with.
    """

    def __init__(self, js: Any, ffi: Any, url: str, lost_reason: str) -> None:
        self._js = js
        self._ffi = ffi
        self.url = url
        self.lost_reason = lost_reason
        self.clock = PageClock(ffi)
        """The worker's clock; :meth:`~roboscript.robot.Robot.connect` runs the robot on it."""
        self.is_open = False
        self._received = bytearray()
        self._failed: str | None = None
        self._lost = False
        self._answered = False
        self._refused: str | None = None

    def _post(self, message: dict[str, Any]) -> None:
        """One message to the page (the worker's ``postMessage``)."""
        self._js.postMessage(self._ffi.to_js(message, dict_converter=self._js.Object.fromEntries))

    def _opening(self) -> dict[str, Any]:
        """What the page needs to open the port, besides its URL."""
        raise NotImplementedError

    def open(self) -> None:
        """Ask the page to open the port, and wait for its answer.

        Raises:
            LinkError: The browser would not open it (its own words, the robot as chosen).
            Interrupted: The page's Stop came first.
        """
        self._post({"type": "port-open", "url": self.url} | self._opening())
        self.clock.wait_until(lambda: self._answered)
        if self._refused is not None:
            raise LinkError(f"cannot reach {chosen_robot(self.url)}: {self._refused}")
        self.is_open = True

    def answered(self, event: str, why: str) -> None:
        """The page opened the port (``opened``) or could not (``failed``, the browser's words)."""
        if event == "failed":
            self._refused = why.strip().splitlines()[-1] if why.strip() else "it would not open"
        self._answered = True
        self.clock.wake()

    def ready(self, stop: bytes) -> None:
        """Tell the page the robot runs, and the bytes that stop it (see the module docstring)."""
        self._post({"type": "robot-ready", "stop": [*self._packets(stop)]})

    # ------------------------------------------------------------ what a link calls

    @property
    def in_waiting(self) -> int:
        """Bytes received and not read yet."""
        return len(self._received)

    def read(self, size: int = 1) -> bytes:
        """Return up to ``size`` received bytes at once (never blocks)."""
        data = bytes(self._received[:size])
        del self._received[:size]
        return data

    def write(self, data: bytes, /) -> int:
        """Hand ``data`` to the page, after what was written before.

        Raises:
            SerialException: The port is closed, or the link was lost.
        """
        if self._failed is not None:
            raise SerialException(self._failed)
        if not self.is_open:
            raise SerialException("the port is not open")
        chunk = bytes(data)
        for packet in self._packets(chunk):
            self._post({"type": "port-write", "data": packet})
        return len(chunk)

    def flush(self) -> None:
        """Nothing to wait for: writes are on their way in order."""

    def close(self) -> None:
        """Let the page close the port once what was written has gone out (safe twice)."""
        if self in _open_ports:
            _open_ports.remove(self)
        if self.is_open:
            self.is_open = False
            self._post({"type": "port-close"})

    # ---------------------------------------------------------------- from the page

    def received(self, data: bytes) -> None:
        """Bytes the robot sent, in order."""
        self._received += data

    def link_lost(self, detail: str = "") -> None:
        """The page says the device is gone, or a write failed: end the run, stop first."""
        if self._lost:
            return
        self._lost = True
        self._failed = f"{self.lost_reason}: {detail}" if detail else self.lost_reason
        logger.info("%s", self._failed)
        self.clock.interrupt(self.lost_reason)

    def _packets(self, data: bytes) -> Iterable[bytes]:
        return [data]


class WebSerialPort(WebPort):
    """A ``SerialPort`` the student chose (Web Serial), held by the page.

    Args:
        js: The ``js`` module.
        ffi: ``pyodide.ffi``.
        url: The port's URL.
        baudrate: Line speed in bits per second.
    """

    def __init__(self, js: Any, ffi: Any, url: str, *, baudrate: int) -> None:
        super().__init__(js, ffi, url, LOST_USB)
        self.baudrate = baudrate

    def _opening(self) -> dict[str, Any]:
        return {"baudRate": self.baudrate, "bluetooth": None}


class WebBluetoothPort(WebPort):
    """A SPIKE Prime hub the student chose (Web Bluetooth), held by the page: its service as
    :mod:`~roboscript.transport.ble` describes it, writes cut into the hub's packets here (the
    page writes each message as one packet).

    Args:
        js: The ``js`` module.
        ffi: ``pyodide.ffi``.
        url: The port's URL.
    """

    def __init__(self, js: Any, ffi: Any, url: str) -> None:
        super().__init__(js, ffi, url, LOST_BLUETOOTH)
        self.packet_size = DEFAULT_PACKET_SIZE

    def _opening(self) -> dict[str, Any]:
        service = {"service": SERVICE_UUID, "rx": RX_CHARACTERISTIC, "tx": TX_CHARACTERISTIC}
        return {"baudRate": None, "bluetooth": service}

    def set_max_packet_size(self, size: int) -> None:
        """Use the hub's max packet size (from its InfoResponse) for later writes."""
        if size >= 1:
            self.packet_size = size

    def _packets(self, data: bytes) -> Iterable[bytes]:
        return split_packets(data, self.packet_size)
