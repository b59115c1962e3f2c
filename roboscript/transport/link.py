"""A link joins a port and a protocol codec: bytes in, messages out, and back.

The link never blocks and has no thread: the scheduler calls :meth:`Link.poll` every tick. A
read takes everything the port has in one large chunk and the codec frames it in Python (no
``readline()`` on the hot path: it costs a system call per byte). Garbage on the wire is
counted by kind and skipped; each kind is logged once, so a noisy cable cannot flood the log.
"""

from __future__ import annotations

import logging
from collections import Counter
from typing import Any, Protocol

import serial

from roboscript.clock import Clock
from roboscript.codec import Codec
from roboscript.errors import LinkClosedError, RemoteProtocolError
from roboscript.transport.wirelog import WireLog

__all__ = ["Link", "PortLike", "close_port"]

logger = logging.getLogger(__name__)

_READ_CHUNK = 65536

HEARD_BYTES = 4096
"""How many of the first bytes a port sends a link keeps (:attr:`Link.heard`)."""


class PortLike(Protocol):
    """The part of pyserial's port API a link uses."""

    def read(self, size: int = 1) -> bytes: ...

    def write(self, data: bytes, /) -> int | None: ...

    def close(self) -> None: ...


def close_port(port: PortLike, name: str) -> None:
    """Close ``port``; one that fails to close is only logged: it is of no use either way.

    Args:
        port: The port.
        name: The port's name, for the log.
    """
    try:
        port.close()
    except (serial.SerialException, OSError) as exc:
        logger.debug("closing %s: %s", name, exc)


class Link:
    """Pumps bytes between a port and a codec.

    Args:
        port: An open, non-blocking port (see :func:`~roboscript.transport.open_port`).
        codec: The protocol codec, in the host role.
        clock: Timestamps for the wire log and :attr:`last_receive_s`.
        wire_log: Where to record every byte, or ``None``.
        name: The port's name, for messages.
    """

    def __init__(
        self,
        port: PortLike,
        codec: Codec[Any],
        *,
        clock: Clock,
        wire_log: WireLog | None = None,
        name: str = "the robot",
    ) -> None:
        self.port = port
        self.codec = codec
        self.clock = clock
        self.wire_log = wire_log
        self.name = name
        self.faults: Counter[str] = Counter()
        self.last_receive_s: float | None = None
        self.bytes_received = 0
        self.bytes_sent = 0
        self.closed = False
        self._port_open = True
        self.heard = bytearray()
        """The first :data:`HEARD_BYTES` bytes received: a failed handshake names the
        protocol they are in (:mod:`roboscript.drivers.recognise`)."""

    def poll(self) -> list[Any]:
        """Read what has arrived and return the complete messages in order.

        Raises:
            LinkClosedError: The device disconnected.
        """
        if self.closed:
            raise LinkClosedError(f"the link to {self.name} is closed")
        try:
            data = self.port.read(_READ_CHUNK)
        except (serial.SerialException, OSError) as exc:
            self.closed = True
            raise LinkClosedError(f"the connection to {self.name} was lost") from exc
        if not data:
            return []
        now = self.clock.now()
        self.last_receive_s = now
        self.bytes_received += len(data)
        if len(self.heard) < HEARD_BYTES:
            self.heard += data[: HEARD_BYTES - len(self.heard)]
        if self.wire_log is not None:
            self.wire_log.record(now, "<", data)
        self.codec.receive_data(data)
        # drain() inlined: this runs once per received chunk on every round trip, and the
        # generator cost about 0.3 µs of a ~15 µs loopback round trip (tests/bench).
        messages: list[Any] = []
        next_message = self.codec.next_message
        while True:
            try:
                message = next_message()
            except RemoteProtocolError as fault:
                self._fault(fault)  # one bad frame never hides the good ones after it
                continue
            if message is None:
                return messages
            messages.append(message)

    def send(self, message: object) -> None:
        """Encode and write one message.

        Raises:
            LocalProtocolError: The message is illegal (nothing is written).
            LinkClosedError: The device disconnected.
        """
        self.write(self.codec.send(message))

    def write(self, data: bytes) -> None:
        """Write raw bytes.

        Raises:
            LinkClosedError: The device disconnected.
        """
        if self.closed:
            raise LinkClosedError(f"the link to {self.name} is closed")
        try:
            self.port.write(data)
        except (serial.SerialException, OSError) as exc:
            self.closed = True
            raise LinkClosedError(f"the connection to {self.name} was lost") from exc
        self.bytes_sent += len(data)
        if self.wire_log is not None:
            self.wire_log.record(self.clock.now(), ">", data)

    def close(self) -> None:
        """Close the port, then the wire log (safe to call twice).

        The port is closed even when the connection was lost, and the wire log even when
        closing the port is cut short (a signal).
        """
        self.closed = True
        port, self._port_open = (self.port if self._port_open else None), False
        Link.close_port_and_log(port, self.wire_log, self.name)

    @staticmethod
    def close_port_and_log(port: PortLike | None, wire_log: WireLog | None, name: str) -> None:
        """Close ``port``, then ``wire_log`` (either may be ``None``): how a link ends.

        The port goes first, so the log holds every byte that went out; the log is closed even
        when closing the port is cut short (a signal), so it is never left unflushed. For a
        port and log that never got their link as well (a connection given up half-made).

        Args:
            port: The port, or ``None`` when it is closed already or was never opened.
            wire_log: The wire log, or ``None``.
            name: The port's name, for the log.
        """
        try:
            if port is not None:
                close_port(port, name)
        finally:
            if wire_log is not None:
                wire_log.close()

    def _fault(self, fault: RemoteProtocolError) -> None:
        if not self.faults[fault.kind]:
            logger.warning(
                "%s sent bytes roboscript cannot read (%s); skipping them", self.name, fault
            )
        self.faults[fault.kind] += 1
