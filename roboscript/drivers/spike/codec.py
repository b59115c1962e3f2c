"""Sans-IO codec of the LEGO SPIKE Prime hub protocol, for both roles.

:class:`SpikeCodec` follows the contract in :mod:`roboscript.codec`: ``send`` turns a
message into one complete frame, ``receive_data`` buffers bytes, and ``next_message`` returns
the next message or raises :class:`~roboscript.errors.RemoteProtocolError` for a bad frame it
has already consumed.

Roles: the host sends requests and decodes responses and notifications; the device (the hub,
or the simulated hub) does the opposite. :class:`~roboscript.drivers.spike.messages.TunnelMessage`
goes both ways.

Receiving follows the delimiter rules of spike-docs ``encoding.rst``:

========  ===================  =====================================================
Byte      Message in progress  Action
========  ===================  =====================================================
``0x01``  none or low          pause the low-priority message, start a high one
``0x01``  high                 sync error: clear both queues, start a high one
``0x02``  high                 deliver the high-priority message, resume the low one
``0x02``  none or low          deliver the low-priority message
========  ===================  =====================================================

Bytes outside any frame belong to the low-priority message in progress, so garbage ends up as
a bad frame at the next ``0x02`` and is counted once. An empty frame (a lone ``0x02``, or
``0x01 0x02``) is ignored: the docs allow ``0x02`` to start a message.

Fault kinds (``RemoteProtocolError.kind`` and keys of ``stats.faults``): ``"bad_cobs"``,
``"bad_length"``, ``"bad_value"`` (a field out of range), ``"unknown_message"``,
``"wrong_role"``, ``"overlong"`` and ``"sync"``. ``dropped_bytes`` counts the wire bytes of
each discarded frame, delimiters included.
"""

from __future__ import annotations

import re
from typing import Final, NoReturn

from roboscript.codec import CodecStats, ProfileLike, Role
from roboscript.drivers.spike import cobs
from roboscript.drivers.spike.messages import MESSAGE_TYPES, Message, MessageKind
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

__all__ = ["MIN_FRAME_BYTES", "SpikeCodec", "codec_for"]

MIN_FRAME_BYTES: Final = 3
"""The smallest ``max_frame_bytes`` a codec accepts (an InfoRequest frame is 3 bytes)."""

_DELIMITERS: Final = re.compile(rb"[\x01\x02]")

_SENDS: Final[dict[Role, frozenset[MessageKind]]] = {
    Role.HOST: frozenset({MessageKind.REQUEST, MessageKind.TUNNEL}),
    Role.DEVICE: frozenset({MessageKind.RESPONSE, MessageKind.NOTIFICATION, MessageKind.TUNNEL}),
}


class SpikeCodec:
    """Encode and decode SPIKE Prime hub frames for one side of the link.

    Attributes:
        role: Which side this codec speaks for.
        stats: Counts of decoded messages and of faults.
        max_frame_bytes: The largest frame sent or accepted, in bytes: the escaped body plus
            its ``0x02`` end (an optional ``0x01`` prefix is not counted).
    """

    def __init__(self, role: Role, *, max_frame_bytes: int = 4096) -> None:
        """Create a codec.

        Args:
            role: ``Role.HOST`` for roboscript's side, ``Role.DEVICE`` for the hub's side.
            max_frame_bytes: The largest frame, in bytes, that ``send`` produces and
                ``next_message`` accepts; each of the two receive queues (low and high
                priority) holds at most ``max_frame_bytes - 1`` bytes.

        Raises:
            ValueError: If ``max_frame_bytes`` is below :data:`MIN_FRAME_BYTES`.
        """
        if max_frame_bytes < MIN_FRAME_BYTES:
            raise ValueError(f"max_frame_bytes must be at least {MIN_FRAME_BYTES}")
        self.role = role
        self.stats = CodecStats()
        self.max_frame_bytes = max_frame_bytes
        self._sends = _SENDS[role]
        self._receives = _SENDS[Role.DEVICE if role is Role.HOST else Role.HOST]
        self._pending = bytearray()  # received, not yet looked at
        self._pos = 0  # bytes of _pending already consumed
        self._low = bytearray()
        self._low_skip = False  # the low-priority frame is overlong: drop it up to its 0x02
        self._high = bytearray()
        self._high_skip = False
        self._high_active = False

    @property
    def buffered_bytes(self) -> int:
        """Bytes held: received but not yet examined, plus partial frames in both queues."""
        return len(self._pending) - self._pos + len(self._low) + len(self._high)

    def send(self, message: object, *, high_priority: bool = False) -> bytes:
        """Encode ``message`` as one complete frame.

        Args:
            message: A :class:`~roboscript.drivers.spike.messages.Message` this role may send.
            high_priority: Prefix the frame with ``0x01`` (a high-priority message).

        Returns:
            The frame bytes, ending with ``0x02``.

        Raises:
            LocalProtocolError: If ``message`` is not a SPIKE message, is not one this role
                sends (the host sends requests, the device responses and notifications, both
                tunnel messages), or its frame would exceed ``max_frame_bytes``.
        """
        if not isinstance(message, Message):
            raise LocalProtocolError(f"not a SPIKE hub message: {message!r}")
        if message.kind not in self._sends:
            raise LocalProtocolError(
                f"{self.role.value} cannot send {type(message).__name__} ({message.kind.value})"
            )
        frame = cobs.pack(message.encode(), high_priority=high_priority)
        size = len(frame) - (1 if high_priority else 0)
        if size > self.max_frame_bytes:
            raise LocalProtocolError(
                f"{type(message).__name__} frame of {size} bytes exceeds "
                f"max_frame_bytes={self.max_frame_bytes}"
            )
        return frame

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire; call :meth:`next_message` to decode them.

        Args:
            data: Any number of bytes; frames may be split anywhere.
        """
        if self._pos:
            del self._pending[: self._pos]
            self._pos = 0
        self._pending += data

    def next_message(self) -> Message | None:
        """Return the next complete message, or ``None`` if more bytes are needed.

        High-priority messages are returned as soon as they end, before a low-priority message
        they interrupted.

        Returns:
            The next message, or ``None``.

        Raises:
            RemoteProtocolError: For a bad frame, already consumed and counted in ``stats``;
                call again to continue with the bytes after it.
        """
        data = self._pending
        while self._pos < len(data):
            start = self._pos
            match = _DELIMITERS.search(data, start)
            end = len(data) if match is None else match.start()
            if end > start:
                self._take(data, start, end)
            if match is None:
                break
            self._pos = end + 1
            if data[end] == cobs.HIGH_PRIORITY:
                self._start_high()
            else:
                message = self._end_frame()
                if message is not None:
                    return message
        data.clear()
        self._pos = 0
        return None

    def _take(self, data: bytearray, start: int, end: int) -> None:
        """Append ``data[start:end]`` (no delimiters) to the frame in progress."""
        self._pos = end
        count = end - start
        high = self._high_active
        if self._high_skip if high else self._low_skip:
            self.stats.dropped_bytes += count
            return
        queue = self._high if high else self._low
        if len(queue) + count < self.max_frame_bytes:
            queue += data[start:end]
            return
        # The body alone already reaches max_frame_bytes; with its 0x02 it would exceed it.
        sample = bytes(queue[:FAULT_SAMPLE_BYTES]) or bytes(
            data[start : start + FAULT_SAMPLE_BYTES]
        )
        dropped = len(queue) + count + (1 if high else 0)
        queue.clear()
        if high:
            self._high_skip = True
        else:
            self._low_skip = True
        self._fault("overlong", dropped, sample, f"frame longer than {self.max_frame_bytes} bytes")

    def _start_high(self) -> None:
        """Handle ``0x01``: start a high-priority message, or report a sync error."""
        if not self._high_active:
            self._high_active = True
            return
        sample = bytes(self._high[:FAULT_SAMPLE_BYTES])
        dropped = len(self._high) + len(self._low) + (0 if self._high_skip else 1)
        self._high.clear()
        self._low.clear()
        self._high_skip = self._low_skip = False
        self._fault("sync", dropped, sample, "0x01 inside a high-priority message")

    def _end_frame(self) -> Message | None:
        """Handle ``0x02``: finish the frame in progress and decode it."""
        if self._high_active:
            self._high_active = False
            body = bytes(self._high)
            self._high.clear()
            skipped, self._high_skip = self._high_skip, False
            prefix = 1
        else:
            body = bytes(self._low)
            self._low.clear()
            skipped, self._low_skip = self._low_skip, False
            prefix = 0
        if skipped:
            self.stats.dropped_bytes += 1
            return None
        if not body:
            return None
        return self._decode(body, prefix + len(body) + 1)

    def _decode(self, body: bytes, size: int) -> Message:
        """Decode one frame body of ``size`` wire bytes, or count and raise its fault."""
        try:
            data = cobs.unescape(body)
        except RemoteProtocolError as exc:
            self._fault(exc.kind, size, body, str(exc))
        if not data:
            self._fault("bad_length", size, body, "empty message")
        cls = MESSAGE_TYPES.get(data[0])
        if cls is None:
            self._fault("unknown_message", size, body, f"unknown message id 0x{data[0]:02x}")
        if cls.kind not in self._receives:
            self._fault(
                "wrong_role",
                size,
                body,
                f"{self.role.value} does not receive {cls.__name__} ({cls.kind.value})",
            )
        try:
            message = cls.decode_payload(data[1:])
        except RemoteProtocolError as exc:
            self._fault(exc.kind, size, body, str(exc))
        self.stats.messages += 1
        return message

    def _fault(self, kind: str, dropped: int, data: bytes, text: str) -> NoReturn:
        self.stats.fault(kind, dropped)
        raise RemoteProtocolError(text, kind=kind, data=data)


def codec_for(role: Role, profile: ProfileLike) -> SpikeCodec:
    """The SPIKE hub codec in ``role`` (the protocol unit's codec factory; no profile options)."""
    del profile
    return SpikeCodec(role)
