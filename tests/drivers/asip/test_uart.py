"""A UART board's serial port: when bytes arrive, and how long the firmware takes to write."""

from __future__ import annotations

import math

import pytest

from roboscript.drivers.asip.uart import (
    TRANSMIT_QUEUE_BYTES,
    WRITE_BYTE_S,
    ReceiveLine,
    Transmitter,
)

BYTE_S = 10 / 57600  # 8N1 at 57600 baud: 173.6 us a byte


def test_bytes_arrive_one_byte_time_apart_after_the_write() -> None:
    line = ReceiveLine(57600)
    assert line.byte_s == pytest.approx(BYTE_S)
    line.send(b"X,?\n", 1.0)
    assert line.take_arrived(1.0) == b""  # the first byte is still on the line
    assert line.next_arrival_s() == pytest.approx(1.0 + BYTE_S)
    assert line.take_arrived(1.0 + 2.5 * BYTE_S) == b"X,"
    assert line.pending_bytes() == 2
    assert line.take_arrived(1.0 + 4 * BYTE_S) == b"?\n"
    assert line.next_arrival_s() == math.inf


def test_a_write_while_the_line_is_busy_follows_the_bytes_on_it() -> None:
    line = ReceiveLine(57600)
    line.send(b"ab", 0.0)
    line.send(b"cd", BYTE_S / 2)  # the host wrote again before "a" arrived
    assert line.take_arrived(3 * BYTE_S) == b"abc"
    assert line.next_arrival_s() == pytest.approx(4 * BYTE_S)


def test_a_write_after_a_quiet_line_starts_when_it_is_written() -> None:
    line = ReceiveLine(57600)
    line.send(b"ab", 0.0)
    line.send(b"cd", 1.0)  # "ab" arrived long ago, though nobody has read it yet
    assert line.take_arrived(0.5) == b"ab"
    assert line.take_arrived(1.0 + 1.5 * BYTE_S) == b"c"


def test_a_reply_costs_the_firmware_its_own_time_while_the_buffer_has_room() -> None:
    transmitter = Transmitter(57600)
    assert transmitter.write(24, 2.0) == pytest.approx(2.0 + 24 * WRITE_BYTE_S)


def test_a_reply_that_fills_the_transmit_buffer_waits_for_the_line() -> None:
    transmitter = Transmitter(57600)
    done_s = transmitter.write(200, 0.0)
    # The line sends a byte a byte time; the firmware is done once the last byte has a place
    # in the buffer: the buffer full behind the byte on the line, 136 bytes sent by then.
    sent = 200 - TRANSMIT_QUEUE_BYTES - 1
    assert done_s == pytest.approx(sent * BYTE_S, abs=2 * WRITE_BYTE_S)
    # and a later reply waits behind it
    assert transmitter.write(1, done_s) == pytest.approx(done_s + BYTE_S, abs=2 * WRITE_BYTE_S)
