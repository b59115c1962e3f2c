"""A UART board's serial port as its firmware meets it: bytes arrive one byte time apart, and
writing takes the firmware time.

On a board whose firmware reads a UART (``transport: uart``, an ATmega328P), what a request
reads depends on *when* it reads: ``asip.cpp`` answers an unknown service and then skips only
the bytes that have arrived by the time its answer is written (``while (serial->available()
&& serial->read() != '\\n')``), and ``asipPixels.cpp`` reads the ``{`` of a pixel request with
a plain ``read()`` the moment the ``,`` before it has arrived. The simulated board keeps the
firmware's own clock with these two parts:

* :class:`ReceiveLine`: the host's bytes on their way, each arriving one byte time (10 bits,
  8N1) after the one before, a write starting when the line is free (a byte that arrives
  while the firmware's receive ring holds :data:`RECEIVE_RING_BYTES` unread is lost);
* :class:`Transmitter`: the firmware's time writing a reply: :data:`WRITE_BYTE_S` of its own
  per byte, and, once the transmit buffer (the core's 63-byte ring and the UART's data
  register) is full, a wait for the line to send a byte.

Everything is counted on the simulation's clock, so a run is the same for a seed however busy
the machine is.
"""

from __future__ import annotations

import math
from collections import deque

__all__ = [
    "BYTE_BITS",
    "RECEIVE_RING_BYTES",
    "TRANSMIT_QUEUE_BYTES",
    "WRITE_BYTE_S",
    "ReceiveLine",
    "Transmitter",
]

BYTE_BITS = 10
"""Bits a byte takes on the line: start bit, 8 data bits, stop bit (8N1)."""

WRITE_BYTE_S = 10.8e-6
"""The firmware's own time per byte of a reply, seconds: ``HardwareSerial::write`` through
``Print`` (and its number formatting) on a 16 MHz ATmega328P, about 170 cycles a byte.
Measured on the emulated firmware: ``~X,?,1{INVALID_SERVICE}`` (24 bytes) takes 260 us from
reading the ``X`` to skipping the rest of the line."""

TRANSMIT_QUEUE_BYTES = 63
"""Bytes that wait to be sent, besides the one on the line, before a write waits: the Arduino
core's 64-byte ring holds 63. (An ATmega328P's USART holds one more in its data register
while its shift register sends; the emulated UART the firmware tier checks against has no
such register, and the simulated board follows the emulated firmware, which it is checked
against byte for byte: on a real board a reply that fills the buffer ends a byte time
sooner.)"""

RECEIVE_RING_BYTES = 63
"""Bytes the Arduino core's 64-byte receive ring holds for the firmware: a byte that arrives
while it is full (the firmware busy writing, not reading) is lost."""


class ReceiveLine:
    """The host's bytes on the line to the board, each arriving one byte time after the last.

    Args:
        baud: The line's speed, bits per second.
    """

    def __init__(self, baud: int) -> None:
        self.byte_s = BYTE_BITS / baud
        """One byte's time on the line, seconds."""
        self._chunks: deque[tuple[float, bytes]] = deque()  # (first byte's arrival s, bytes)
        self._last_s = -math.inf  # when the last byte written arrives

    def send(self, data: bytes, now_s: float) -> None:
        """The host writes ``data`` at ``now_s``: it follows what is still on the line."""
        if not data:
            return
        start_s = max(now_s, self._last_s)
        self._chunks.append((start_s + self.byte_s, data))
        self._last_s = start_s + len(data) * self.byte_s

    def take_arrived(self, now_s: float) -> bytes:
        """The bytes that have arrived by ``now_s`` (taken off the line)."""
        chunks = self._chunks
        if not chunks:
            return b""  # nothing on the line: no buffer to build
        taken = bytearray()
        while chunks:
            first_s, data = chunks[0]
            # the epsilon keeps a byte due exactly now from slipping on float sums
            count = min(len(data), math.floor((now_s - first_s) / self.byte_s + 1e-6) + 1)
            if count <= 0:
                break
            taken += data[:count]
            if count < len(data):
                chunks[0] = (first_s + count * self.byte_s, data[count:])
                break
            chunks.popleft()
        return bytes(taken)

    def next_arrival_s(self) -> float:
        """When the next byte on the line arrives, seconds (infinity when there is none)."""
        return self._chunks[0][0] if self._chunks else math.inf

    def pending_bytes(self) -> int:
        """Bytes written and not yet arrived."""
        return sum(len(data) for _, data in self._chunks)

    def clear(self) -> None:
        """Drop what is on the line (a new connection)."""
        self._chunks.clear()


class Transmitter:
    """The board's transmit side: how long the firmware takes to write bytes.

    Args:
        baud: The line's speed, bits per second.
    """

    def __init__(self, baud: int) -> None:
        self.byte_s = BYTE_BITS / baud
        self._done_s = -math.inf  # when the last byte written has left the line

    def write(self, count: int, now_s: float) -> float:
        """The firmware writes ``count`` bytes from ``now_s``; returns when it is done, seconds."""
        byte_s = self.byte_s
        # The line sends a byte in far longer than the firmware takes to write one, so once
        # it is busy it stays busy: without a wait, the last byte leaves at this time.
        done_s = max(self._done_s, now_s + WRITE_BYTE_S) + count * byte_s
        clock_s = now_s + count * WRITE_BYTE_S
        if done_s - byte_s - clock_s <= TRANSMIT_QUEUE_BYTES * byte_s:
            self._done_s = done_s  # the buffer never filled: no byte waited
            return clock_s
        done_s = self._done_s
        clock_s = now_s
        for _ in range(count):
            clock_s += WRITE_BYTE_S
            # Bytes not yet sent: one on the line, the rest waiting in the buffer.
            if done_s - clock_s > TRANSMIT_QUEUE_BYTES * byte_s:
                clock_s = done_s - TRANSMIT_QUEUE_BYTES * byte_s  # wait for a free place
            done_s = max(done_s, clock_s) + byte_s
        self._done_s = done_s
        return clock_s
