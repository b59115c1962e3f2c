"""A UART board's serial port: when bytes arrive, and how long the firmware takes to write."""

from __future__ import annotations

import math
import random

import pytest

from roboscript.drivers.asip.uart import (
    TRANSMIT_QUEUE_BYTES,
    WRITE_BYTE_S,
    ReceiveLine,
    Transmitter,
    avr_byte_s,
)

BYTE_S = 10 / 57600  # 8N1 at 57600 baud: 173.6 us a byte
BOARD_BYTE_S = 10 * 16 * 17 / 16e6  # a 16 MHz 328P's USART at 57600: UBRR 16, 170.0 us


def test_a_16_mhz_avr_asked_for_57600_baud_sends_at_58824() -> None:
    # HardwareSerial::begin's exception for 57600 at 16 MHz: normal speed, UBRR 16
    assert avr_byte_s(57600, 16_000_000) == pytest.approx(170.0e-6)
    assert avr_byte_s(57600, 16_000_000) == pytest.approx(BOARD_BYTE_S)


def test_an_avrs_byte_time_comes_from_its_double_speed_divisor() -> None:
    # U2X: UBRR 207 at 9600 (9615 baud), 16 at 115200 (117647 baud), 0 at 2 Mbaud (exact)
    assert avr_byte_s(9600, 16_000_000) == pytest.approx(10 * 8 * 208 / 16e6)
    assert avr_byte_s(115200, 16_000_000) == pytest.approx(85.0e-6)
    assert avr_byte_s(2_000_000, 16_000_000) == pytest.approx(5.0e-6)
    # at 8 MHz 57600 takes double speed too: UBRR 16, 8 cycles a step (58824 baud)
    assert avr_byte_s(57600, 8_000_000) == pytest.approx(170.0e-6)


def test_a_divisor_too_wide_for_double_speed_takes_normal_speed() -> None:
    # 300 baud at 16 MHz: U2X would need UBRR 6666 (> 4095); normal speed gives 3332
    assert avr_byte_s(300, 16_000_000) == pytest.approx(10 * 16 * 3333 / 16e6)


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
    transmitter = Transmitter(BOARD_BYTE_S)
    assert transmitter.write(bytes(24), 2.0) == pytest.approx(2.0 + 24 * WRITE_BYTE_S)


def test_a_reply_that_fills_the_transmit_buffer_waits_for_the_line() -> None:
    transmitter = Transmitter(BOARD_BYTE_S)
    done_s = transmitter.write(bytes(200), 0.0)
    # The line sends a byte a byte time; the firmware is done once the last byte has a place
    # in the buffer: the ring and the data register full behind the byte on the line, 135
    # bytes sent by then.
    sent = 200 - TRANSMIT_QUEUE_BYTES - 1
    assert done_s == pytest.approx(sent * BOARD_BYTE_S, abs=2 * WRITE_BYTE_S)
    # and a later reply waits behind it
    assert transmitter.write(b"\n", done_s) == pytest.approx(
        done_s + BOARD_BYTE_S, abs=2 * WRITE_BYTE_S
    )


def test_each_byte_goes_to_the_usart_once_the_byte_before_it_is_on_the_line() -> None:
    transmitter = Transmitter(BOARD_BYTE_S)
    transmitter.write(b"abcd", 1.0)
    # "a" goes on the line and "b" into the data register as they are written; "c" once "b"
    # has started on the line, a byte time after "a"
    assert transmitter.take_handed(1.0 + 2 * WRITE_BYTE_S) == b"ab"
    assert transmitter.take_handed(1.0 + WRITE_BYTE_S + BOARD_BYTE_S) == b"c"
    assert transmitter.take_handed(1.0 + WRITE_BYTE_S + 2 * BOARD_BYTE_S) == b"d"
    transmitter.clear()  # a reset loses what waits
    transmitter.write(b"ef", 2.0)
    assert transmitter.take_handed(2.0 + 2 * WRITE_BYTE_S) == b"ef"


def _per_byte(byte_s: float, writes: list[tuple[float, int]], takes: list[float]) -> list[object]:
    """The transmitter's rule followed a byte at a time: when each write is done, and the
    bytes handed to the USART by each time of ``takes``."""
    done_s, handed, found = -math.inf, [], []
    for now_s, count in writes:
        clock_s = max(now_s, found[-1] if found else -math.inf)
        for index in range(count):
            clock_s += WRITE_BYTE_S
            if done_s - clock_s > TRANSMIT_QUEUE_BYTES * byte_s:
                clock_s = done_s - TRANSMIT_QUEUE_BYTES * byte_s
            handed.append((max(clock_s, done_s - byte_s), index % 256))
            done_s = max(done_s, clock_s) + byte_s
        found.append(clock_s)
    found += [bytes(b for at_s, b in handed if at_s <= take_s + 1e-9) for take_s in takes]
    return found


@pytest.mark.parametrize("byte_s", [BOARD_BYTE_S, 5e-6, WRITE_BYTE_S, 1040e-6])
@pytest.mark.parametrize("seed", range(20))
def test_a_reply_is_timed_in_runs_as_its_bytes_are_one_by_one(byte_s: float, seed: int) -> None:
    # each write is timed, and handed on, a run at a time, not a byte at a time: the same
    # times, at any baud rate (a line faster or slower than the firmware writes)
    rng = random.Random(seed)
    writes = [(rng.uniform(0, 0.03), rng.choice([1, 3, 24, 64, 65, 200, 700])) for _ in range(6)]
    writes.sort()
    takes = [*sorted(rng.uniform(0, 0.3) for _ in range(40)), math.inf]
    expected = _per_byte(byte_s, writes, takes)
    transmitter = Transmitter(byte_s)
    found: list[object] = []
    for now_s, count in writes:
        start_s = max(now_s, found[-1]) if found else now_s
        found.append(transmitter.write(bytes(i % 256 for i in range(count)), start_s))
    taken = b""
    for take_s in takes:
        taken += transmitter.take_handed(take_s)
        found.append(taken)
    assert found[: len(writes)] == pytest.approx(expected[: len(writes)], abs=1e-9)
    assert found[len(writes) :] == expected[len(writes) :]
