"""roboscript's StackMod twin against the StackMod author's own motor-module firmware.

The author's sketch (``stackmod.cpp``) and ``Stackmodio`` library run unchanged on an emulated
ATmega328P; each I2C write reaches the sketch's ``onReceive`` handler as the TWI interrupt
would hand it over, the moment it ends and at most 32 bytes of it (the stand-in ``Wire``
carries it on the UART). The firmware and ``roboscript sim``'s twin (:class:`ReferenceModule`)
get the same probes (``stackmod_probes.py``) in the same order; after each, the fifteen motor
registers the firmware keeps must equal the twin's, and after the probes that wait for the
sketch's 200 ms main loop, the motor outputs the firmware drives on its pins must be those the
twin gives the simulated body. Differences are listed in ``KNOWN_DIFFERENCES``, each with the
firmware line that decides it (docs/robots/stackmod.md lists them too); a listed difference
that goes away fails its test, so the list stays true.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

import pytest
from firmware.avr import Board, build, symbol_address
from firmware.recipes import STACKMOD_BAUD, stackmod_328p
from firmware.stackmod_probes import DRIVER_PROBES, PROBES, Probe

from roboscript.drivers.stackmod.reference_device import MOTOR_REGISTERS, ReferenceModule

BOOT_S = 0.1
"""``setup()``: Wire, ``Serial.begin(9600)``, pins; the first ``drive()`` runs straight after."""
LOOP_WAIT_S = 0.25
"""One run of the sketch's main loop (``drive(); delay(200);``) and a margin."""
_BRIDGE_BYTE_S = 10 / STACKMOD_BAUD
"""One byte on the stand-in ``Wire``'s UART (8N1); the real I2C bus is ten times faster."""

KNOWN_DIFFERENCES: dict[str, str] = {
    "value 300 drives": (
        "stackmod.cpp `analogWrite(M1, abs(left_speed))`: past 255, Timer 2's 8-bit OCR2B "
        "(M1, M4) takes the low byte while Timer 1's 16-bit OCR1A/OCR1B (M2, M3) take the "
        "whole value, so the two motors of one side get different duties; the twin drives "
        "the side at full power"
    ),
    "value -256 drives": (
        "the same `analogWrite` past 255: OCR2A (M4) takes 256's low byte, 0, and stops while "
        "OCR1B (M3) runs at full duty; the twin drives the side at full power in reverse"
    ),
}

# stackmod.cpp's pins: PWM M1 = 3 (OC2B), M2 = 9 (OC1A) drive the left wheels, M3 = 10
# (OC1B), M4 = 11 (OC2A) the right ones; LB_1 = 14, LF_1 = 16 high = left forward; RB_2 = 6,
# RF_2 = 8 high = right forward.
_PORTB, _PORTC, _PORTD = 0x25, 0x28, 0x2B
_TCCR1A, _OCR1AL, _OCR1BL = 0x80, 0x88, 0x8A
_TCCR2A, _OCR2A, _OCR2B = 0xB0, 0xB3, 0xB4


class _Body:
    def __init__(self) -> None:
        self.power = (0.0, 0.0)

    def set_power(self, left: float, right: float) -> None:
        self.power = (left, right)


def _channel(tccr: int, com_bit: int, ocr: int, level: bool) -> float:
    return ocr / 255 if tccr & com_bit else float(level)


def firmware_power(board: Board) -> tuple[float, float] | None:
    """The motor power the sketch drives on its pins, -1..1 for the left and right wheels, or
    None when the two motors of one side get different duties."""
    portb, portc, portd = board.peek(_PORTB)[0], board.peek(_PORTC)[0], board.peek(_PORTD)[0]
    tccr1a, tccr2a = board.peek(_TCCR1A)[0], board.peek(_TCCR2A)[0]
    ocr1a, ocr1b = struct.unpack("<2H", board.peek(_OCR1AL, 4))
    ocr2a, ocr2b = board.peek(_OCR2A)[0], board.peek(_OCR2B)[0]
    left_duty = _channel(tccr2a, 0x20, ocr2b, bool(portd & 0x08))  # M1, pin 3
    right_duty = _channel(tccr1a, 0x20, ocr1b, bool(portb & 0x04))  # M3, pin 10
    if left_duty != _channel(tccr1a, 0x80, ocr1a, bool(portb & 0x02)):  # M2, pin 9
        return None
    if right_duty != _channel(tccr2a, 0x80, ocr2a, bool(portb & 0x08)):  # M4, pin 11
        return None
    lb1, lb2 = bool(portc & 0x01), bool(portc & 0x02)
    rb1, rb2 = bool(portd & 0x20), bool(portd & 0x40)
    left = left_duty if lb1 and not lb2 else -left_duty if lb2 and not lb1 else 0.0
    right = right_duty if rb2 and not rb1 else -right_duty if rb1 and not rb2 else 0.0
    return left, right


@dataclass(frozen=True)
class Answer:
    """What one side holds after a probe."""

    registers: tuple[int, ...]
    power: tuple[float, float] | None
    """The wheels' power, for probes that wait for the main loop (else None)."""


def _settle_s(probe: Probe) -> float:
    sent = sum(len(data) + 1 for data in probe.writes)
    return sent * _BRIDGE_BYTE_S * 1.1 + 0.02 + (LOOP_WAIT_S if probe.drives else 0.0)


def reset(board: Board, twin: ReferenceModule) -> None:
    """Reset both once the bytes on the way have arrived: the firmware starts again from its
    first instruction (its registers cleared, its parser idle) and is given its start-up;
    the twin loses power."""
    board.advance(_settle_s(Probe("", ())))
    board.reset()
    board.advance(BOOT_S)
    twin.stop_all()


@dataclass(frozen=True)
class Run:
    """Both sides' answers, probe by probe, and every byte each wrote on its line."""

    answers: list[tuple[Answer, Answer]]
    firmware_sent: bytes
    twin_sent: bytes


@pytest.fixture(scope="module")
def run() -> Run:
    results: list[tuple[Answer, Answer]] = []
    body = _Body()
    twin = ReferenceModule(body)
    twin.connect(0.0)
    elf = build(stackmod_328p())
    registers = symbol_address(elf, "StackModIO::motors_reg")
    with Board(elf, "atmega328p", 16_000_000, baud=STACKMOD_BAUD) as board:
        board.advance_to(BOOT_S)
        now_s = BOOT_S
        for probe in PROBES:
            if probe.idle_s:
                board.advance(probe.idle_s)
                now_s += probe.idle_s
                twin.step(now_s)
            for index, data in enumerate(probe.writes):
                board.write(bytes([len(data)]) + data)
                twin.receive(data, now_s)
                if probe.reset_after == index + 1:
                    reset(board, twin)
                    now_s = board.time_s
            if probe.reset_after == 0:
                reset(board, twin)
                now_s = board.time_s
            settle_s = _settle_s(probe)
            board.advance(settle_s)
            now_s += settle_s
            twin.step(now_s)
            firmware = Answer(
                struct.unpack(f"<{MOTOR_REGISTERS}h", board.peek(registers, 2 * MOTOR_REGISTERS)),
                firmware_power(board) if probe.drives else None,
            )
            sim = Answer(
                tuple(value for value in twin.motor_registers),
                body.power if probe.drives else None,
            )
            results.append((firmware, sim))
        return Run(results, bytes(board.received), twin.read_output())


def test_neither_the_firmware_nor_the_twin_ever_writes_a_byte(run: Run) -> None:
    # stackmod.cpp: Serial.begin(9600), and every print is commented out or behind
    # SERIALDEBUG (false): nothing at start-up, nothing in answer to any probe
    assert len(run.answers) == len(PROBES)
    assert (run.firmware_sent, run.twin_sent) == (b"", b"")


@pytest.mark.parametrize("index", range(len(PROBES)), ids=[probe.name for probe in PROBES])
def test_the_twin_keeps_and_drives_the_motors_as_the_authors_firmware_does(
    index: int, run: Run
) -> None:
    probe = PROBES[index]
    firmware, twin = run.answers[index]
    assert twin.registers == firmware.registers, probe.writes
    if probe.name in KNOWN_DIFFERENCES:
        assert twin.power != firmware.power, f"no longer differs: drop {probe.name!r}"
    elif probe.drives:
        assert firmware.power is not None and twin.power is not None
        assert twin.power == pytest.approx(firmware.power, abs=1e-9), probe.writes


def test_every_packet_the_driver_writes_moves_the_firmwares_motors(run: Run) -> None:
    driver = [firmware.power for firmware, _ in run.answers[: len(DRIVER_PROBES)]]
    assert driver[0] == pytest.approx((96 / 255, 0.0))
    assert driver[3] == pytest.approx((-139 / 255, 1.0))


def test_a_reset_clears_the_firmwares_motors_and_a_half_packet(run: Run) -> None:
    names = [probe.name for probe in PROBES]
    before, after = (
        run.answers[names.index(name)][0]
        for name in ("motors set before a reset", "a reset stops the motors")
    )
    assert before.power == pytest.approx((90 / 255, -90 / 255))
    assert after.registers == (0,) * 15 and after.power == (0.0, 0.0)
    cut = run.answers[names.index("a packet cut by a reset")][0]
    assert cut.registers[1] == 0  # the half before the reset was forgotten with it
    burst = run.answers[names.index("a burst after a long idle")][0]
    assert burst.registers[:2] == (120, 121) and burst.power == pytest.approx(
        (120 / 255, 121 / 255)
    )
