"""The harness's own parts, checked through the firmware that uses them."""

from __future__ import annotations

import itertools
import re

import pytest
from firmware.avr import Board, build
from firmware.recipes import MIRTLE_BAUD, MIRTLE_F_CPU_HZ, MIRTLE_MCU, mirtle_328p

# robot_pins.h, 328 branch: encoderPins {3, 7, 2, 4} = left A, B, right A, B (port D)
ENCODER_PINS = ((3, 7), (2, 4))
EVENT = re.compile(rb"@M,e,2,\{(-?\d+):(-?\d+),(-?\d+):(-?\d+)\}")


def _counts(board: Board) -> tuple[int, int]:
    """The encoder counts in the firmware's latest encoder event."""
    last = EVENT.findall(bytes(board.received))[-1]
    return int(last[1]), int(last[3])


def test_the_firmware_counts_every_encoder_step_fed_while_it_drives_its_port() -> None:
    # The MIRTO sketch writes PORTD (its motor lines) while the encoder lines on the same port
    # are inputs with pull-ups: the levels the harness drives must hold through those writes.
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        for wheel, (a, b) in enumerate(ENCODER_PINS):
            board.turn_encoder(wheel, "D", a, b, 0, 0)
        board.advance_to(4.0)
        board.exchange(b"M,A,1\nM,M,60,-60\n", 0.1)
        expected = [0, 0]
        for steps_per_tick in ((20, -20), (-20, 20), (5, -3), (-1, 1)):
            for _ in range(25):
                board.step(board.time_s + 0.02, steps_per_tick, 0x25, 1)
            board.advance(0.2)
            expected = [expected[w] + 25 * steps_per_tick[w] for w in (0, 1)]
            assert _counts(board) == tuple(expected), steps_per_tick


def _write_cycles(board: Board, request: bytes, span_s: float, step_cycles: int) -> list[int]:
    """The cycle (to ``step_cycles``) at which the firmware hands each byte of its answer to
    ``request`` to its USART."""
    board.write(request)
    cycles = []
    end = board.cycle + round(span_s * board.f_cpu_hz)
    while board.cycle < end:
        sent = board.advance_to((board.cycle + step_cycles) / board.f_cpu_hz)
        cycles += [board.cycle] * len(sent)
    return cycles


def test_the_emulated_usart_sends_ten_bits_a_byte_at_the_divisors_rate() -> None:
    # HardwareSerial::begin(57600) at 16 MHz: UBRR 16 without U2X, 16 * 17 = 272 cycles a bit;
    # an 8N1 byte is 10 bits (simavr 1.6 alone counts 11, a parity bit the frame lacks)
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        board.advance_to(4.0)
        cycles = _write_cycles(board, b"#,N\n", 0.02, 64)
    assert len(cycles) > 50
    gaps = [b - a for a, b in itertools.pairwise(cycles[1:])]
    assert sum(gaps) / len(gaps) == pytest.approx(2720, abs=2)


def test_the_emulated_usart_takes_a_byte_in_its_data_register_while_one_is_sent() -> None:
    # The USART's UDRn takes the second byte of an answer at once, while its shift register
    # sends the first; every later byte waits for the one before it to leave
    with Board(build(mirtle_328p()), MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD) as board:
        board.advance_to(4.0)
        cycles = _write_cycles(board, b"#,?\n", 0.002, 16)
    assert cycles[1] - cycles[0] < 272  # within the first byte's start bit
    assert all(b - a > 2600 for a, b in itertools.pairwise(cycles[1:]))
