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

The two directions run at different speeds. The host's bytes come at the rate the host's
serial adapter makes of the baud rate asked for (:class:`ReceiveLine` takes the nominal rate:
10 bits at 57600 baud, 173.6 us). The board sends at the rate its USART makes of it, a whole
number of clock cycles a bit (:func:`avr_byte_s`): a 16 MHz ATmega328P asked for 57600 baud
runs at 58824 (UBRR 16, no U2X) and sends a byte every 170.0 us.

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
    "avr_byte_s",
]

BYTE_BITS = 10
"""Bits a byte takes on the line: start bit, 8 data bits, stop bit (8N1)."""

WRITE_BYTE_S = 10.8e-6
"""The firmware's own time per byte of a reply, seconds: ``HardwareSerial::write`` through
``Print`` (and its number formatting) on a 16 MHz ATmega328P, about 170 cycles a byte.
Measured on the emulated firmware: ``~X,?,1{INVALID_SERVICE}`` (24 bytes) takes 260 us from
reading the ``X`` to skipping the rest of the line."""

TRANSMIT_QUEUE_BYTES = 64
"""Bytes that wait to be sent, besides the one on the line, before a write waits: the Arduino
core's 64-byte ring holds 63, and the USART's data register (UDRn) one more while its shift
register sends the byte before."""

RECEIVE_RING_BYTES = 63
"""Bytes the Arduino core's 64-byte receive ring holds for the firmware: a byte that arrives
while it is full (the firmware busy writing, not reading) is lost."""


def avr_byte_s(baud: int, f_cpu_hz: int) -> float:
    """The time an AVR's USART takes to send one 8N1 byte when its sketch asks for ``baud``,
    seconds: the divisor the Arduino AVR core's ``HardwareSerial::begin`` picks, in whole
    clock cycles a bit, so the real rate differs from the one asked for.

    The core tries double speed (U2X: 8 cycles a divisor step) with ``UBRR = (F_CPU / 4 /
    baud - 1) / 2``, in integer arithmetic; at 57600 baud on a 16 MHz part (for the old
    bootloaders' sake) and where that divisor would not fit in 12 bits it uses normal speed
    (16 cycles a step) with ``UBRR = (F_CPU / 8 / baud - 1) / 2``. A bit then takes
    ``steps * (UBRR + 1)`` cycles (the ATmega328P datasheet's baud-rate formula).

    Args:
        baud: The rate the sketch asks for (``Serial.begin``), bits per second.
        f_cpu_hz: The board's clock, hertz.

    Returns:
        Ten bit times (start, 8 data bits, stop), seconds: 170.0 us for 57600 baud at 16 MHz
        (58824 baud), 1040 us for 9600 (9615 baud), 5 us for 2000000 (exact).
    """
    divisor = (f_cpu_hz // 4 // baud - 1) // 2
    cycles_per_step = 8  # U2X
    if (f_cpu_hz == 16_000_000 and baud == 57600) or divisor > 4095:
        divisor = (f_cpu_hz // 8 // baud - 1) // 2
        cycles_per_step = 16
    return BYTE_BITS * cycles_per_step * (divisor + 1) / f_cpu_hz


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
    """The board's transmit side: how long the firmware takes to write bytes, and when each
    byte goes to the USART.

    Args:
        byte_s: One byte's time on the line as the board's USART sends it, seconds
            (:func:`avr_byte_s`).
    """

    def __init__(self, byte_s: float) -> None:
        self.byte_s = byte_s
        self._done_s = -math.inf  # when the last byte written has left the line
        # Runs of bytes handed to the USART at even steps: (first at s, step s, bytes, how
        # many of them are taken). A reply is a few runs, however long: writing and taking
        # cost a run, not a byte.
        self._handed: deque[tuple[float, float, bytes, int]] = deque()

    def write(self, data: bytes, now_s: float) -> float:
        """The firmware writes ``data`` from ``now_s``; returns when it is done, seconds.

        Each byte costs the firmware :data:`WRITE_BYTE_S`; once :data:`TRANSMIT_QUEUE_BYTES`
        wait besides the one on the line, the next waits for the line to send a byte. Each
        byte is handed to the USART (:meth:`take_handed`) when it is written and the byte
        before it has started on the line (its data register is then free).

        Byte after byte, the gap between the line's end and the firmware's clock changes by
        a byte time less a write time, so the bytes fall into at most four runs (line free;
        busy; a byte waiting; the buffer full), each counted at once."""
        byte_s, write_s = self.byte_s, WRITE_BYTE_S
        full_s = TRANSMIT_QUEUE_BYTES * byte_s
        drift_s = byte_s - write_s  # how the gap grows with each byte
        done_s = self._done_s
        clock_s = now_s
        at, total = 0, len(data)
        while at < total:
            left = total - at
            gap_s = done_s - (clock_s + write_s)  # the line's end ahead of this byte's write
            if gap_s > full_s:  # the buffer is full: each byte waits for the line
                count = left if drift_s > 0 else 1
                first_s, step_s = done_s - byte_s, byte_s
                clock_s = done_s + (count - 1) * byte_s - full_s
                done_s += count * byte_s
            elif gap_s <= 0:  # the line is free: the byte goes on it as it is written
                count = left if drift_s <= 0 else 1
                first_s, step_s = clock_s + write_s, write_s
                clock_s += count * write_s
                done_s = clock_s + byte_s
            else:  # the line is busy: the byte follows the one on it
                waits = gap_s > byte_s  # behind one not yet on the line
                edge_s = byte_s if waits else 0.0  # where the gap leaves this run
                if drift_s > 0:
                    room = math.floor(((full_s if waits else byte_s) - gap_s) / drift_s) + 1
                elif drift_s < 0:
                    room = math.ceil((gap_s - edge_s) / -drift_s)
                else:
                    room = left
                count = max(1, min(left, room))
                if waits:
                    first_s, step_s = done_s - byte_s, byte_s
                else:
                    first_s, step_s = clock_s + write_s, write_s
                clock_s += count * write_s
                done_s += count * byte_s
            self._handed.append((first_s, step_s, data[at : at + count], 0))
            at += count
        self._done_s = done_s
        return clock_s

    def take_handed(self, now_s: float) -> bytes:
        """The bytes handed to the USART by ``now_s`` (taken)."""
        handed = self._handed
        taken = b""
        until_s = now_s + 1e-9
        while handed:
            first_s, step_s, data, start = handed[0]
            due_s = first_s + start * step_s
            if due_s > until_s:
                break
            steps = (until_s - due_s) / step_s  # whole steps after the first due (inf: all)
            end = len(data) if steps >= len(data) - start else start + math.floor(steps) + 1
            taken += data[start:end]
            if end < len(data):
                handed[0] = (first_s, step_s, data, end)
                break
            handed.popleft()
        return taken

    def clear(self) -> None:
        """The board resets: what it had not yet handed to its USART is gone."""
        self._handed.clear()
        self._done_s = -math.inf
