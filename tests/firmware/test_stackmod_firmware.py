"""roboscript's StackMod twin against the StackMod author's own motor-module firmware.

The author's sketch (``stackmod.cpp``) and ``Stackmodio`` library run unchanged on an emulated
ATmega328P; each I2C write reaches the sketch's ``onReceive`` handler as the TWI interrupt
would hand it over (the stand-in ``Wire`` carries it on the UART). After each write both the
firmware and ``roboscript sim``'s twin (:class:`ReferenceModule`) get 0.5 s, two runs of the
sketch's 200 ms motor loop, and the motor outputs the firmware drives on its pins must be
those the twin gives the simulated body.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from firmware.avr import Board, build
from firmware.recipes import STACKMOD_BAUD, stackmod_328p

from roboscript.codec import Role
from roboscript.drivers.stackmod import messages as sm
from roboscript.drivers.stackmod.codec import StackModCodec
from roboscript.drivers.stackmod.reference_device import ReferenceModule

SETTLE_S = 0.5

# stackmod.cpp's pins: PWM M1 = 3 (OC2B), M2 = 9 (OC1A) drive the left wheels, M3 = 10
# (OC1B), M4 = 11 (OC2A) the right ones; LB_1 = 14, LF_1 = 16 high = left forward; RB_2 = 6,
# RF_2 = 8 high = right forward.
_PORTB, _PORTC, _PORTD = 0x25, 0x28, 0x2B
_TCCR1A, _OCR1AL, _OCR1BL = 0x80, 0x88, 0x8A
_TCCR2A, _OCR2A, _OCR2B = 0xB0, 0xB3, 0xB4


def _driver_writes() -> list[tuple[str, bytes]]:
    codec = StackModCodec(Role.HOST, checksum="braces_excluded", framing="i2c")
    writes = []
    for motor, pwm in [(1, 96), (2, 96), (1, -139), (2, 255), (1, 0), (2, -255), (2, 0)]:
        message = sm.MotorPwm(ord("E"), motor, pwm)
        writes.append((f"MTR{motor} {pwm:+d}", codec.send(message)))
    return writes


OTHER_WRITES = [
    ("0.9.1 document packet", b"{M$MTR1+038}w"),
    ("bad checksum", b"2{Ep$MTR1+096}k"),
    ("packet one character long", b"2{Ep$MTR1+0960}j"),
    ("packet split over two writes", b"2{Ep$MTR"),
    ("its second half", b"1+096}j"),
]
WRITES = _driver_writes() + OTHER_WRITES


class _Body:
    def __init__(self) -> None:
        self.power = (0.0, 0.0)

    def set_power(self, left: float, right: float) -> None:
        self.power = (left, right)


def _channel(tccr: int, com_bit: int, ocr: int, level: bool) -> float:
    return ocr / 255 if tccr & com_bit else float(level)


def firmware_power(board: Board) -> tuple[float, float]:
    """The motor power the sketch drives on its pins, -1..1 for the left and right wheels."""
    portb, portc, portd = board.peek(_PORTB)[0], board.peek(_PORTC)[0], board.peek(_PORTD)[0]
    tccr1a, tccr2a = board.peek(_TCCR1A)[0], board.peek(_TCCR2A)[0]
    ocr1a, ocr1b = board.peek(_OCR1AL)[0], board.peek(_OCR1BL)[0]
    ocr2a, ocr2b = board.peek(_OCR2A)[0], board.peek(_OCR2B)[0]
    left_duty = _channel(tccr2a, 0x20, ocr2b, bool(portd & 0x08))  # M1, pin 3
    assert left_duty == _channel(tccr1a, 0x80, ocr1a, bool(portb & 0x02))  # M2, pin 9
    right_duty = _channel(tccr1a, 0x20, ocr1b, bool(portb & 0x04))  # M3, pin 10
    assert right_duty == _channel(tccr2a, 0x80, ocr2a, bool(portb & 0x08))  # M4, pin 11
    lb1, lb2 = bool(portc & 0x01), bool(portc & 0x02)
    rb1, rb2 = bool(portd & 0x20), bool(portd & 0x40)
    left = left_duty if lb1 and not lb2 else -left_duty if lb2 and not lb1 else 0.0
    right = right_duty if rb2 and not rb1 else -right_duty if rb1 and not rb2 else 0.0
    return left, right


@pytest.fixture(scope="module")
def answers() -> Iterator[list[tuple[tuple[float, float], tuple[float, float]]]]:
    results = []
    body = _Body()
    twin = ReferenceModule(body)
    twin.connect(0.0)
    with Board(build(stackmod_328p()), "atmega328p", 16_000_000, baud=STACKMOD_BAUD) as board:
        board.advance_to(1.0)  # setup(): Wire.begin, Serial.begin(9600), pins
        now_s = 1.0
        for _, data in WRITES:
            board.write(bytes([len(data)]) + data)
            board.advance(SETTLE_S)
            twin.receive(data, now_s)
            now_s += SETTLE_S
            twin.step(now_s)
            results.append((firmware_power(board), body.power))
    yield results


@pytest.mark.parametrize("index", range(len(WRITES)), ids=[name for name, _ in WRITES])
def test_the_twin_drives_the_motors_as_the_authors_firmware_does(
    index: int, answers: list[tuple[tuple[float, float], tuple[float, float]]]
) -> None:
    firmware, twin = answers[index]
    assert twin == pytest.approx(firmware, abs=1e-9), WRITES[index]


def test_every_packet_the_driver_writes_moves_the_firmwares_motors(
    answers: list[tuple[tuple[float, float], tuple[float, float]]],
) -> None:
    driver = answers[: len(_driver_writes())]
    assert driver[0][0] == pytest.approx((96 / 255, 0.0))
    assert driver[3][0] == pytest.approx((-139 / 255, 1.0))
