"""The real MIRTO firmware as the simulator's device, in lockstep with the mission clock.

:class:`EmulatedMirto` is a :class:`~roboscript.sim.device.SimDevice`: where ``roboscript
sim`` puts its own model of the board, this puts the emulated ATmega328P running the
``mirtle2017`` sketch. Every mission tick (20 ms), the AVR runs exactly the cycles of that
tick (16 000 cycles a millisecond), and bytes from the host reach its UART at the simulated
time they were written; the firmware's motor pins (direction lines and
Timer0's PWM) set the simulated body's motor power, and the body's wheels turn the
firmware's quadrature encoders, one Gray-code step per encoder tick, spread over the step. So
a whole mission runs against the real firmware and its PID, deterministically, however busy
the machine is.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from firmware.as_device import firmware_as_device
from firmware.avr import Board, build
from firmware.recipes import MIRTLE_BAUD, MIRTLE_F_CPU_HZ, MIRTLE_MCU, mirtle_328p

from roboscript.robot import DEFAULT_PERIOD_S

if TYPE_CHECKING:
    import pytest

    from roboscript.sim.body import Body

# ATmega328P data-space addresses (datasheet, register summary)
_PORTB, _PORTD, _TCCR0A, _OCR0A, _OCR0B = 0x25, 0x2B, 0x44, 0x47, 0x48
_FIRST, _LAST = _PORTB, _OCR0B
# robot_pins.h, 328 branch: motorPins {8, 11, 5, 12, 13, 6} = in1, in2, PWM per motor;
# encoderPins {3, 7, 2, 4} = left A, B, right A, B (all on port D)
_IN_PINS = ((0, 3), (4, 5))  # PORTB bits of (in1, in2): pins 8, 11 and 12, 13
_PWM = ((5, _OCR0B, 0x20), (6, _OCR0A, 0x80))  # (PORTD bit, OCR register, TCCR0A COM bit)
_ENCODERS = ((3, 7), (2, 4))  # PORTD bits of (A, B)
_FORWARD_IN2 = (True, True)
"""The in2 level of a wheel turning forward. ASIP's convention is that positive power drives
the robot forward; the firmware drives ``M,M,50,50`` as in1 low, in2 high on both motors
(``setMotorPwm`` with the sketch's direction modes), so that is forward for the body too."""
_ENCODER_SIGN = (1, 1)
"""Raw count direction of a forward-turning wheel: the firmware reports a forward wheel's
count going up (``encoderPos() = read() * motorDirectionMode``) when the raw count goes up."""


class EmulatedMirto:
    """The emulated MIRTO board driving ``body`` (a :class:`SimDevice`)."""

    def __init__(self, body: Body, board: Board) -> None:
        self.body = body
        self.board = board
        self._out = bytearray()
        self._ticks = list(body.ticks)
        for wheel, (a, b) in enumerate(_ENCODERS):
            board.turn_encoder(wheel, "D", a, b, 0, 0)  # wire the encoder: both lines low

    def connect(self, now_s: float) -> None:
        """The board has been running since power-on (time 0); it greets when its sketch does."""
        self._advance(now_s)

    def receive(self, data: bytes, now_s: float) -> None:
        """Bytes from the host go down the UART from ``now_s``, one byte time apart."""
        self._advance(now_s)
        self.board.write(data)

    def step(self, now_s: float) -> None:
        """Run the firmware to ``now_s`` once a mission tick has passed (the simulation steps
        its physics four times a tick), turning its encoders as the wheels turned meanwhile."""
        if now_s - self.board.time_s >= DEFAULT_PERIOD_S - 1e-9:
            self._advance(now_s)

    def read_output(self) -> bytes:
        """What the firmware sent since the last call."""
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Power loss: the motors stop whatever the firmware does."""
        self.body.set_power(0.0, 0.0)

    def _advance(self, now_s: float) -> None:
        if now_s <= self.board.time_s:
            return
        steps = [(self.body.ticks[w] - self._ticks[w]) * _ENCODER_SIGN[w] for w in (0, 1)]
        self._ticks = list(self.body.ticks)
        sent, registers = self.board.step(now_s, (steps[0], steps[1]), _FIRST, _LAST - _FIRST + 1)
        self._out += sent
        self.body.set_power(*motor_power(registers))


def motor_power(regs: bytes) -> tuple[float, float]:
    """Each motor's power as the firmware drives it, -1 (full reverse) to 1 (forward), from
    the registers ``PORTB`` .. ``OCR0B``."""
    portb, portd, tccr0a = regs[0], regs[_PORTD - _FIRST], regs[_TCCR0A - _FIRST]
    power = []
    for wheel in (0, 1):
        in1, in2 = (bool(portb >> bit & 1) for bit in _IN_PINS[wheel])
        pin_bit, ocr, com = _PWM[wheel]
        duty = regs[ocr - _FIRST] / 255 if tccr0a & com else float(portd >> pin_bit & 1)
        if in1 == in2:
            power.append(0.0)  # both lines equal: freewheel or brake
        else:
            power.append(duty if in2 == _FORWARD_IN2[wheel] else -duty)
    return power[0], power[1]


@contextmanager
def firmware_as_mirto(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[EmulatedMirto]]:
    """Make every simulated ``mirto`` in this test the emulated firmware; yields the boards."""
    elf = build(mirtle_328p())

    def make(body: Body) -> EmulatedMirto:
        return EmulatedMirto(body, Board(elf, MIRTLE_MCU, MIRTLE_F_CPU_HZ, baud=MIRTLE_BAUD))

    with firmware_as_device(monkeypatch, lambda profile: profile.name == "mirto", make) as built:
        yield built
