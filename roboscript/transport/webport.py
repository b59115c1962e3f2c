"""Robots reached from a browser tab: Web Serial and Web Bluetooth ports, and the page's clock.

In the browser app (``roboscript web build``) a student picks a robot in the browser's own
chooser (a user's click must ask for it); the page hands the chosen port or device to
:func:`remember_chosen`, which answers a URL, ``webserial://1`` or ``webbluetooth://1``. Opened
with :func:`~roboscript.transport.open_port` like any other URL, it gives the
:class:`~roboscript.transport.link.Link` the port it knows: reads never block and return what
has arrived, writes go out in order. Drivers and missions do not know they are in a browser.

* **Web Serial** (ASIP, StackMod, PLEN2, a SPIKE hub on USB): a reader loop on the page's event
  loop appends what ``port.readable`` gives to one buffer; writes go to ``port.writable`` in
  order.
* **Web Bluetooth** (a SPIKE hub): the hub's GATT service as :mod:`roboscript.transport.ble`
  describes it; notifications fill the buffer, writes are cut into the hub's packets.

A browser tab has one thread, and the page runs only while Python waits. So each port brings
a :class:`PageClock` (:attr:`WebPort.clock`; the robot takes it, see
:meth:`~roboscript.robot.Robot.connect`): its waits hand the tab back to the browser with
Pyodide's ``run_sync`` (JavaScript Promise Integration, in every Chromium-family browser, the
only ones with Web Serial), and it is where the page's Stop button, the tab closing and a lost
link land, as :class:`~roboscript.interrupts.Interrupted`, exactly where Ctrl-C lands on the
command line; the run then stops the robot first, by its usual path. A lost link (the stream
ends for good, the device goes, a write fails) ends the run the same way, with
:data:`LOST_USB` or :data:`LOST_BLUETOOTH`, rather than by failing a read: where the line
still carries writes, the stop still reaches the robot. The ``js`` and ``pyodide`` modules
exist only in the browser and are imported only there.
"""

from __future__ import annotations

import asyncio
import contextlib
import importlib
import logging
import time
from collections import deque
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
    "PageClock",
    "WebBluetoothPort",
    "WebPort",
    "WebSerialPort",
    "chosen_robot",
    "interrupt_open_ports",
    "open_web_port",
    "remember_chosen",
]

logger = logging.getLogger(__name__)

LOST_USB = "the robot's USB connection was lost (was the cable pulled out?)"
LOST_BLUETOOTH = (
    "the Bluetooth connection to the hub was lost (is it still on, and near the computer?)"
)

CLOSE_WAIT_S = 2.0
"""How long closing a port waits for its queued writes (the stop) to be taken, seconds: a
device that takes nothing more must not keep the page from saying how the run ended."""

_CHOSEN_ROBOT = {
    "webserial": "the robot on the serial port you chose",
    "webbluetooth": "the Bluetooth robot you chose",
}
"""A chosen port's robot, named as the student chose it (a scheme's URL means nothing to them)."""

_chosen: dict[str, Any] = {}
"""URL -> the JavaScript ``SerialPort`` or ``BluetoothDevice`` the student chose."""
_open_ports: list[WebPort] = []
"""The ports open in this page, most recent last."""


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


def _absent(value: Any) -> bool:
    """JavaScript's ``null`` or ``undefined``, as Pyodide hands them to Python."""
    return value is None or type(value).__name__ == "JsNull"


def remember_chosen(scheme: str, device: Any) -> str:
    """Keep a port or device the student chose in the browser's chooser; return its URL.

    Args:
        scheme: ``"webserial"`` (a ``SerialPort``) or ``"webbluetooth"`` (a
            ``BluetoothDevice``).
        device: The JavaScript object the chooser gave.

    Raises:
        ValueError: Another scheme.
    """
    if scheme not in ("webserial", "webbluetooth"):
        raise ValueError(f"expected webserial or webbluetooth, got {scheme!r}")
    url = f"{scheme}://{len(_chosen) + 1}"
    _chosen[url] = device
    return url


def chosen_robot(url: str) -> str | None:
    """The robot at ``url`` as the student chose it in the page (``"the robot on the serial
    port you chose"``), or ``None`` for a URL that is not a page's port (``socket://...``)."""
    return _CHOSEN_ROBOT.get(url.partition("://")[0].lower())


def open_web_port(url: str, *, baudrate: int) -> WebPort:
    """Open a port the student chose in this page.

    Args:
        url: What :func:`remember_chosen` answered.
        baudrate: Line speed in bits per second (Web Serial only).

    Raises:
        LinkError: Not in a browser, no such port chosen, or it would not open.
    """
    js, ffi = _browser()
    device = _chosen.get(url)
    if device is None:
        raise LinkError("no robot is connected in this page: press Connect, then run again")
    port: WebPort
    if url.startswith("webserial://"):
        port = WebSerialPort(js, ffi, device, baudrate=baudrate)
    else:
        port = WebBluetoothPort(js, ffi, device)
    try:
        port.open()
    except Exception as exc:  # the browser rejects with many kinds of error
        raise LinkError(f"cannot reach {chosen_robot(url)}: {_why(exc)}") from exc
    _open_ports.append(port)
    return port


def interrupt_open_ports(reason: str) -> bool:
    """End every run on a port of this page at its next wait, for ``reason``.

    A run still shaking hands with its robot has no robot to stop yet; this reaches it too.

    Returns:
        Whether a port was open.
    """
    for port in _open_ports:
        port.clock.interrupt(reason)
    return bool(_open_ports)


def _why(exc: BaseException) -> str:
    """A browser's error in its own words (``NetworkError: Failed to open serial port.``)."""
    text = str(exc).strip()
    return text.splitlines()[-1] if text else type(exc).__name__


# --------------------------------------------------------------------------- the clock


class PageClock:
    """Real time in a browser tab, whose waits let the page run.

    :meth:`sleep_until` suspends Python (``run_sync``) until the deadline, or until
    :meth:`interrupt` wakes it; meanwhile the page reads its ports and answers clicks. It
    then raises :class:`~roboscript.interrupts.Interrupted` with the reason given, between
    two ticks, as Ctrl-C would.

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
        """Let the page run until ``deadline_s`` (at least one turn of its event loop).

        Raises:
            Interrupted: :meth:`interrupt` was called (once per call to it).
        """
        self._raise_if_interrupted()
        self._ffi.run_sync(self._wait(deadline_s - self.now()))
        self._raise_if_interrupted()

    async def _wait(self, seconds: float) -> None:
        loop = asyncio.get_event_loop()
        waker: asyncio.Future[None] = loop.create_future()
        self._waker = waker
        if self._reason is not None:  # asked between the call and this task's first step
            _settle(waker)
        # a timer even when late: the browser's other tasks (port reads, clicks) get a turn
        timer = loop.call_later(max(seconds, 0.0), _settle, waker)
        try:
            await waker
        finally:
            timer.cancel()
            self._waker = None

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
    """What every port in a page shares: the receive buffer, ordered writes, a lost link.

    Writes are started at once, from the caller (even from the page's ``pagehide``, when the
    tab is closing and no later task would run), one after the other: the next starts when
    the browser has taken the one before.

    Args:
        js: The ``js`` module.
        ffi: ``pyodide.ffi``.
        lost_reason: The sentence a lost link ends the run with.
    """

    def __init__(self, js: Any, ffi: Any, lost_reason: str) -> None:
        self._js = js
        self._ffi = ffi
        self.lost_reason = lost_reason
        self.clock = PageClock(ffi)
        """The page's clock; :meth:`~roboscript.robot.Robot.connect` runs the robot on it."""
        self.is_open = False
        self._received = bytearray()
        self._queue: deque[bytes] = deque()
        self._sending = False
        self._failed: str | None = None
        self._lost = False
        self._closing = False
        self._proxies: list[Any] = []
        self._listeners: list[tuple[Any, str, Any]] = []  # (target, event, proxy)
        self._closer: asyncio.Future[None] | None = None
        self._sent_proxy = self._proxy(self._sent)
        self._send_failed_proxy = self._proxy(self._send_failed)

    def _proxy(self, function: Any) -> Any:
        """A Python function the browser may call back until the port is closed."""
        proxy = self._ffi.create_proxy(function)
        self._proxies.append(proxy)
        return proxy

    def _listen(self, target: Any, event: str, function: Any) -> None:
        """Call ``function`` on ``target``'s ``event`` until the port is closed (then the
        listener is removed before its proxy goes, so a late event calls nothing)."""
        proxy = self._proxy(function)
        target.addEventListener(event, proxy)
        self._listeners.append((target, event, proxy))

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
        """Start sending ``data`` after what was written before.

        Raises:
            SerialException: The port is closed, or an earlier write failed.
        """
        if self._failed is not None:
            raise SerialException(self._failed)
        if not self.is_open:
            raise SerialException("the port is not open")
        chunk = bytes(data)
        self._queue.extend(self._packets(chunk))
        if not self._sending:
            self._send_next()
        return len(chunk)

    def flush(self) -> None:
        """Nothing to wait for: writes are on their way in order."""

    def close(self) -> None:
        """Let queued writes go out (the stop, first of all), then close (safe to call twice)."""
        if self._closing:
            return
        self._closing = True
        self.is_open = False
        if self in _open_ports:
            _open_ports.remove(self)
        if self._ffi.can_run_sync():
            self._ffi.run_sync(self._close_when_sent())
        else:  # called from the page (a closing tab): finish when the browser can
            self._closer = asyncio.ensure_future(self._close_when_sent())

    # ---------------------------------------------------------------- for subclasses

    def _packets(self, data: bytes) -> list[bytes]:
        return [data]

    def _start_write(self, packet: bytes) -> Any:
        """Hand one packet to the browser; return its promise."""
        raise NotImplementedError

    async def _shut(self) -> None:
        """Release the browser's port or device."""
        raise NotImplementedError

    def _received_data(self, data: bytes) -> None:
        self._received += data

    def _link_lost(self, *_: Any) -> None:
        """The browser says the device is gone: end the run, stop first."""
        if self._closing or self._lost:
            return
        self._lost = True
        logger.info("%s", self.lost_reason)
        self.clock.interrupt(self.lost_reason)

    # ------------------------------------------------------------------- the writes

    def _send_next(self) -> None:
        if not self._queue or self._failed is not None:
            self._sending = False
            return
        self._sending = True
        packet = self._queue.popleft()
        try:
            promise = self._start_write(packet)
        except Exception as exc:  # noqa: BLE001 - a browser's write throws many kinds
            self._send_failed(exc)
            return
        promise.then(self._sent_proxy, self._send_failed_proxy)

    def _sent(self, *_: Any) -> None:
        self._send_next()

    def _send_failed(self, error: Any) -> None:
        self._sending = False
        self._queue.clear()
        self._failed = f"{self.lost_reason}: {_why(Exception(str(error)))}"
        self._link_lost()

    async def _close_when_sent(self) -> None:
        give_up_s = time.monotonic() + CLOSE_WAIT_S
        while self._sending and self._failed is None and time.monotonic() < give_up_s:
            await asyncio.sleep(0.005)
        with contextlib.suppress(Exception):  # a port already gone cannot be closed twice
            await self._shut()
        for target, event, proxy in self._listeners:
            with contextlib.suppress(Exception):
                target.removeEventListener(event, proxy)
        self._listeners.clear()
        for proxy in self._proxies:
            with contextlib.suppress(Exception):
                proxy.destroy()
        self._proxies.clear()


class WebSerialPort(WebPort):
    """A ``SerialPort`` the student chose (Web Serial).

    Args:
        js: The ``js`` module.
        ffi: ``pyodide.ffi``.
        port: The JavaScript ``SerialPort``.
        baudrate: Line speed in bits per second.
    """

    def __init__(self, js: Any, ffi: Any, port: Any, *, baudrate: int) -> None:
        super().__init__(js, ffi, LOST_USB)
        self.port = port
        self.baudrate = baudrate
        self._writer: Any = None
        self._reader: Any = None
        self._pump: asyncio.Task[None] | None = None

    def open(self) -> None:
        """Open the port at :attr:`baudrate` and start reading."""
        options = self._ffi.to_js(
            {"baudRate": self.baudrate}, dict_converter=self._js.Object.fromEntries
        )
        self._ffi.run_sync(self.port.open(options))
        self._writer = self.port.writable.getWriter()
        self._listen(self.port, "disconnect", self._link_lost)
        self.is_open = True
        self._pump = asyncio.ensure_future(self._read_all())

    async def _read_all(self) -> None:
        """Fill the buffer from ``port.readable`` until the port closes or is lost.

        A framing or parity error, a break, an overrun ends one stream and the port gives a
        new one (as a UART goes on after garbage); a device that is gone gives none.
        """
        while not self._closing and not _absent(self.port.readable):
            self._reader = self.port.readable.getReader()
            try:
                while True:
                    result = await self._reader.read()
                    if result.done:
                        break
                    self._received_data(result.value.to_bytes())
            except Exception as exc:  # noqa: BLE001 - the stream's error, whatever its kind
                logger.debug("serial read: %s", exc)
            finally:
                with contextlib.suppress(Exception):
                    self._reader.releaseLock()
                self._reader = None
        self._link_lost()

    def _start_write(self, packet: bytes) -> Any:
        return self._writer.write(self._ffi.to_js(packet))

    async def _shut(self) -> None:
        with contextlib.suppress(Exception):
            await self._writer.close()  # resolves once every queued write has gone out
        if self._reader is not None:
            with contextlib.suppress(Exception):
                await self._reader.cancel()
        if self._pump is not None:
            with contextlib.suppress(Exception):
                await self._pump
        await self.port.close()


class WebBluetoothPort(WebPort):
    """A SPIKE Prime hub the student chose (Web Bluetooth), as :mod:`~roboscript.transport.ble`
    describes its service: notifications in, writes without response in packets.

    Args:
        js: The ``js`` module.
        ffi: ``pyodide.ffi``.
        device: The JavaScript ``BluetoothDevice``.
    """

    def __init__(self, js: Any, ffi: Any, device: Any) -> None:
        super().__init__(js, ffi, LOST_BLUETOOTH)
        self.device = device
        self.packet_size = DEFAULT_PACKET_SIZE
        self._rx: Any = None

    def open(self) -> None:
        """Connect to the hub and turn its notifications on."""
        run_sync = self._ffi.run_sync
        server = run_sync(self.device.gatt.connect())
        service = run_sync(server.getPrimaryService(SERVICE_UUID))
        self._rx = run_sync(service.getCharacteristic(RX_CHARACTERISTIC))
        tx = run_sync(service.getCharacteristic(TX_CHARACTERISTIC))
        self._listen(tx, "characteristicvaluechanged", self._notified)
        self._listen(self.device, "gattserverdisconnected", self._link_lost)
        run_sync(tx.startNotifications())
        self.is_open = True

    def set_max_packet_size(self, size: int) -> None:
        """Use the hub's max packet size (from its InfoResponse) for later writes."""
        if size >= 1:
            self.packet_size = size

    def _notified(self, event: Any) -> None:
        view = event.target.value  # a DataView on the notification's bytes
        data = self._js.Uint8Array.new(view.buffer, view.byteOffset, view.byteLength)
        self._received_data(data.to_bytes())

    def _packets(self, data: bytes) -> list[bytes]:
        return split_packets(data, self.packet_size)

    def _start_write(self, packet: bytes) -> Any:
        return self._rx.writeValueWithoutResponse(self._ffi.to_js(packet))

    async def _shut(self) -> None:
        if self.device.gatt.connected:
            self.device.gatt.disconnect()
