"""``ble://NAME-OR-ADDRESS[?timeout=SECONDS]``: a SPIKE Prime hub over Bluetooth Low Energy.

pyserial finds this module by name (``protocol_ble``) once ``open_port`` has registered the
package. The work is done by :class:`roboscript.transport.ble.BlePort`; this class only gives
it pyserial's shape. ``timeout`` is how long to scan for the hub (default 10 s).
"""

from __future__ import annotations

import urllib.parse
from typing import TYPE_CHECKING

from serial.serialutil import PortNotOpenError, SerialBase, SerialException

from roboscript.transport.ble import BlePort

if TYPE_CHECKING:
    from _typeshed import ReadableBuffer

__all__ = ["Serial", "parse_ble_url"]


def parse_ble_url(url: str) -> tuple[str, float]:
    """Split a ``ble://`` URL into (hub name or address, scan timeout in seconds).

    Raises:
        ValueError: Not a ``ble://`` URL, no hub named, or a bad timeout.
    """
    scheme, sep, rest = url.partition("://")
    if scheme != "ble" or not sep:
        raise ValueError(f"expected a ble:// URL, got {url!r}")
    target, _, query = rest.partition("?")
    target = urllib.parse.unquote(target).strip("/")
    if not target:
        raise ValueError("name the hub: ble://NAME or ble://ADDRESS")
    values = urllib.parse.parse_qs(query)
    try:
        timeout_s = float(values.get("timeout", ["10"])[-1])
    except ValueError:
        raise ValueError(f"bad timeout in {url!r}") from None
    return target, timeout_s


class Serial(SerialBase):
    """A pyserial port backed by a :class:`~roboscript.transport.ble.BlePort`."""

    ble: BlePort | None = None

    def open(self) -> None:
        """Scan for the hub and connect."""
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        try:
            target, timeout_s = parse_ble_url(str(self.port))
        except ValueError as exc:
            raise SerialException(str(exc)) from exc
        ble = BlePort(target, scan_timeout_s=timeout_s)
        ble.open()
        self.ble = ble
        self.is_open = True

    def close(self) -> None:
        """Disconnect from the hub."""
        if self.ble is not None:
            self.ble.close()
        self.is_open = False

    def _reconfigure_port(self) -> None:
        """Baud rate and framing mean nothing over BLE."""

    def set_max_packet_size(self, size: int) -> None:
        """Write in pieces of ``size`` bytes (the hub's InfoResponse max packet size)."""
        self._ble().set_max_packet_size(size)

    @property
    def in_waiting(self) -> int:
        """Bytes the hub has sent and the host has not read."""
        return self._ble().in_waiting

    def read(self, size: int = 1) -> bytes:
        """Return up to ``size`` bytes the hub has sent (never blocks)."""
        return self._ble().read(size)

    def write(self, data: ReadableBuffer, /) -> int:
        """Queue bytes for the hub."""
        return self._ble().write(memoryview(data).tobytes())

    def flush(self) -> None:
        """Wait until queued writes have gone out."""
        self._ble().flush()

    def reset_input_buffer(self) -> None:
        """Discard bytes waiting for the host."""
        ble = self._ble()
        ble.read(ble.in_waiting)

    def reset_output_buffer(self) -> None:
        """Queued writes cannot be recalled."""

    def _ble(self) -> BlePort:
        if not self.is_open or self.ble is None:
            raise PortNotOpenError()
        return self.ble
