"""The SPIKE Prime hub over Bluetooth Low Energy, as a non-blocking pyserial-like port.

``open_port("ble://NAME-OR-ADDRESS")`` scans for a hub advertising the SPIKE Prime service,
connects, and returns a port the :class:`~roboscript.transport.link.Link` reads and writes like
a serial line. bleak (the BLE library, an optional extra: ``pip install 'roboscript[ble]'``) is
asyncio-based, so a background thread runs its event loop and only moves bytes:

* **Writes** are queued and sent in order to the hub's RX characteristic with
  write-without-response, cut into pieces of the hub's max packet size (20 bytes, the ATT
  payload of BLE's default MTU, until the driver passes on the InfoResponse value with
  :meth:`BlePort.set_max_packet_size`).
* **Notifications** from the TX characteristic are appended to one receive buffer in arrival
  order, so a frame split across notifications is whole again for the codec, which finds the
  frames by their ``0x02`` delimiters. :meth:`BlePort.read` never blocks.

A lost connection makes the next read or write raise ``SerialException``, which the link
reports as :class:`~roboscript.errors.LinkClosedError`. Only the thread touches bleak; only
:meth:`BlePort.open` and :meth:`BlePort.flush` wait (for the connection, and for queued writes).
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import importlib
import logging
import re
import threading
from collections.abc import Awaitable, Callable
from typing import Any

from serial import SerialException

__all__ = [
    "DEFAULT_PACKET_SIZE",
    "RX_CHARACTERISTIC",
    "SERVICE_UUID",
    "TX_CHARACTERISTIC",
    "BleMissingError",
    "BlePort",
    "split_packets",
]

logger = logging.getLogger(__name__)

SERVICE_UUID = "0000fd02-0000-1000-8000-00805f9b34fb"
"""The SPIKE Prime hub's GATT service, included in its advertisements."""
RX_CHARACTERISTIC = "0000fd02-0001-1000-8000-00805f9b34fb"
"""The characteristic the hub receives on (write without response)."""
TX_CHARACTERISTIC = "0000fd02-0002-1000-8000-00805f9b34fb"
"""The characteristic the hub transmits on (notifications)."""
DEFAULT_PACKET_SIZE = 20
"""Write size before the hub has said its own: the ATT payload of the default 23-byte MTU."""

_ADDRESS = re.compile(r"^([0-9A-Fa-f]{2}:){5}[0-9A-Fa-f]{2}$|^[0-9A-Fa-f-]{36}$")
_STOP = object()

ClientFactory = Callable[[Any, Callable[[Any], None]], Any]
"""Builds a bleak-like client from a device and a disconnect callback."""
DeviceFinder = Callable[[str, float], Awaitable[Any]]
"""Finds a device by name or address within a timeout (seconds); ``None`` if not found."""


class BleMissingError(SerialException):
    """bleak, the optional BLE library, is not installed."""


def split_packets(data: bytes, packet_size: int) -> list[bytes]:
    """Cut ``data`` into writes of at most ``packet_size`` bytes, in order."""
    if packet_size < 1:
        raise ValueError(f"packet size must be at least 1, not {packet_size}")
    return [data[i : i + packet_size] for i in range(0, len(data), packet_size)]


def _import_bleak() -> Any:
    try:
        return importlib.import_module("bleak")
    except ImportError:
        raise BleMissingError(
            "BLE needs the bleak library: pip install 'roboscript[ble]'"
        ) from None


async def _find_with_bleak(target: str, timeout_s: float) -> Any:
    bleak = _import_bleak()
    if _ADDRESS.match(target):
        return await bleak.BleakScanner.find_device_by_address(target, timeout=timeout_s)
    wanted = target.casefold()

    def matches(device: Any, advertisement: Any) -> bool:
        uuids = [uuid.lower() for uuid in (advertisement.service_uuids or ())]
        names = {(device.name or "").casefold(), (advertisement.local_name or "").casefold()}
        return SERVICE_UUID in uuids and wanted in names

    return await bleak.BleakScanner.find_device_by_filter(matches, timeout=timeout_s)


def _bleak_client(device: Any, on_disconnect: Callable[[Any], None]) -> Any:
    return _import_bleak().BleakClient(device, disconnected_callback=on_disconnect)


class BlePort:
    """A SPIKE Prime hub reached over BLE (see the module docstring).

    Args:
        target: The hub's advertised name (case-insensitive) or its address.
        scan_timeout_s: How long to look for the hub, seconds.
        client_factory: Builds the BLE client (default: bleak's ``BleakClient``); tests pass a
            fake with bleak's ``connect``, ``start_notify``, ``write_gatt_char`` and
            ``disconnect`` coroutines.
        find_device: Finds the device (default: a bleak scan filtered on the SPIKE service).
    """

    def __init__(
        self,
        target: str,
        *,
        scan_timeout_s: float = 10.0,
        client_factory: ClientFactory | None = None,
        find_device: DeviceFinder | None = None,
    ) -> None:
        self.target = target
        self.scan_timeout_s = scan_timeout_s
        self.packet_size = DEFAULT_PACKET_SIZE
        self._client_factory = client_factory or _bleak_client
        self._find_device = find_device or _find_with_bleak
        self._received = bytearray()
        self._lock = threading.Lock()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._queue: asyncio.Queue[object] | None = None
        self._thread: threading.Thread | None = None
        self._connected = concurrent.futures.Future[None]()
        self._lost: str | None = None
        self.is_open = False

    # ---------------------------------------------------------------------------- open/close

    def open(self) -> None:
        """Find and connect to the hub; return once notifications are on.

        Raises:
            BleMissingError: bleak is not installed (with the install command).
            SerialException: No hub found, or the connection failed.
        """
        if self._client_factory is _bleak_client:
            _import_bleak()  # fail here, in the caller's thread, with the one-sentence message
        self._thread = threading.Thread(target=self._run, name=f"ble:{self.target}", daemon=True)
        self._thread.start()
        try:
            # The scan and the connection have their own timeouts; this bound is a backstop.
            self._connected.result(timeout=self.scan_timeout_s + 30.0)
        except concurrent.futures.TimeoutError:
            raise SerialException(f"connecting to {self.target!r} over BLE timed out") from None
        self.is_open = True

    def close(self) -> None:
        """Disconnect and stop the thread (safe to call twice)."""
        self.is_open = False
        loop, queue = self._loop, self._queue
        if loop is not None and queue is not None and not loop.is_closed():
            with contextlib.suppress(RuntimeError):  # the loop has just ended by itself
                loop.call_soon_threadsafe(queue.put_nowait, _STOP)
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=5.0)

    # ----------------------------------------------------------------------------- bytes

    def set_max_packet_size(self, size: int) -> None:
        """Use the hub's max packet size (from its InfoResponse) for later writes."""
        if size >= 1:
            self.packet_size = size

    @property
    def in_waiting(self) -> int:
        """Bytes received and not read yet."""
        with self._lock:
            return len(self._received)

    def read(self, size: int = 1) -> bytes:
        """Return up to ``size`` received bytes at once (never blocks).

        Raises:
            SerialException: The hub disconnected (after the bytes it sent are read).
        """
        with self._lock:
            data = bytes(self._received[:size])
            del self._received[:size]
        if not data:
            self._check_alive()
        return data

    def write(self, data: bytes, /) -> int:
        """Queue ``data`` for the hub; it is sent in packets in the background.

        Raises:
            SerialException: The port is closed or the hub disconnected.
        """
        self._check_alive()
        chunk = bytes(data)
        assert self._loop is not None and self._queue is not None
        self._loop.call_soon_threadsafe(self._queue.put_nowait, chunk)
        return len(chunk)

    def flush(self) -> None:
        """Wait until every queued write has been handed to the BLE stack."""
        self._check_alive()
        assert self._loop is not None and self._queue is not None
        done = concurrent.futures.Future[None]()
        self._loop.call_soon_threadsafe(self._queue.put_nowait, done)
        done.result(timeout=30.0)

    def _check_alive(self) -> None:
        if self._lost is not None:
            raise SerialException(self._lost)
        if not self.is_open or self._loop is None:
            raise SerialException("the BLE port is not open")

    # ------------------------------------------------------------------------ the thread

    def _run(self) -> None:
        try:
            asyncio.run(self._main())
        except Exception as exc:  # noqa: BLE001 - whatever ends the thread, the opener must hear it
            if not self._connected.done():
                self._connected.set_exception(_as_serial_error(exc))
            self._lost = self._lost or f"the BLE link to {self.target} failed: {exc}"

    async def _main(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._queue = asyncio.Queue()
        device = await self._find_device(self.target, self.scan_timeout_s)
        if device is None:
            raise SerialException(
                f"no SPIKE Prime hub called {self.target!r} found within "
                f"{self.scan_timeout_s:g} s (is it on, with its Bluetooth light blinking?)"
            )
        client = self._client_factory(device, self._on_disconnect)
        await client.connect()
        try:
            await client.start_notify(TX_CHARACTERISTIC, self._on_notify)
            self._connected.set_result(None)
            await self._pump(client)
        finally:
            try:
                await client.disconnect()
            except Exception as exc:  # noqa: BLE001 - bleak raises many kinds on a lost link
                logger.debug("BLE disconnect: %s", exc)

    async def _pump(self, client: Any) -> None:
        assert self._queue is not None
        while True:
            item = await self._queue.get()
            if item is _STOP:
                return
            if isinstance(item, concurrent.futures.Future):
                item.set_result(None)
                continue
            assert isinstance(item, bytes)
            for packet in split_packets(item, self.packet_size):
                await client.write_gatt_char(RX_CHARACTERISTIC, packet, response=False)

    def _on_notify(self, _sender: Any, data: bytearray) -> None:
        with self._lock:
            self._received += data

    def _on_disconnect(self, _client: Any) -> None:
        self._lost = f"the SPIKE hub {self.target!r} disconnected"
        loop, queue = self._loop, self._queue
        if loop is not None and queue is not None:
            with contextlib.suppress(RuntimeError):  # the loop has ended: nothing to stop
                loop.call_soon_threadsafe(queue.put_nowait, _STOP)


def _as_serial_error(exc: BaseException) -> SerialException:
    if isinstance(exc, SerialException):
        return exc
    return SerialException(f"cannot connect over BLE: {exc}")
