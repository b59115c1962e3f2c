"""The harness's own parts, checked through the firmware that uses them."""

from __future__ import annotations

import re

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
