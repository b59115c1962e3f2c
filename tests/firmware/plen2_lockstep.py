"""PLEN2's own firmware as the simulator's device, its motion EEPROM attached, in lockstep.

:class:`EmulatedPlen2` is a :class:`~roboscript.sim.device.SimDevice`: where ``roboscript
sim`` puts its own model of the board, this puts the emulated ATmega32u4 running PLEN2
firmware 1.4.2 with a 24FC1025 on its I2C bus (the harness's own model of the part). The AVR
runs exactly the cycles of each mission tick, and bytes from the host reach its UART at the
simulated time they were written, so roboscript's driver installs, reads back and plays its
motions on the firmware's own code, deterministically.

What the firmware does with the servos is read from the firmware itself: each time its motion
controller finishes a 32 ms update (``MotionController::updateFrame`` clears
``JointController::m_1cycle_finished``), the harness takes a snapshot of
``JointController::m_pwms``, the 24 pulse widths the Timer 1 interrupt writes to ``OCR1A``-
``OCR1C`` in turn. The body does not move: the firmware has no model of its legs, and the
simulated PLEN2's walking model is checked separately against these servo outputs.
"""

from __future__ import annotations

import struct
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

from firmware.as_device import firmware_as_device
from firmware.avr import Board, build, symbol_address
from firmware.recipes import PLEN2_BAUD, PLEN2_EEPROM, PLEN2_F_CPU_HZ, PLEN2_MCU, plen2_32u4

import roboscript.sim.simulation as simulation_module
from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.device import Plen2Board
from roboscript.robot import DEFAULT_PERIOD_S

if TYPE_CHECKING:
    from pathlib import Path

    import pytest

    from roboscript.sim.body import Body

PWMS = "PLEN2::JointController::m_pwms"
UPDATE_DUE = "PLEN2::JointController::m_1cycle_finished"
ANGLE_MIN_DDEG, ANGLE_MAX_DDEG = -900, 900
"""``JointController.h``, PLEN2 (``TARGET_PLEN20``): the servos' range, tenths of a degree."""
PWM_MIN, PWM_MAX = 410, 884
"""``JointController.h``, PLEN2 branch: the Timer 1 compare values of those angles (10-bit
fast PWM, 4 µs a count); ``CLOCK_WISE`` is true for PLEN2, so ``PWM_MIN`` is ``ANGLE_MIN``."""


def servo_pwm(angle_ddeg: int) -> int:
    """The pulse width the firmware gives an absolute joint angle: Arduino's ``map()`` of
    ``JointController::setAngle`` (long arithmetic, the division truncating toward zero)."""
    numerator = (angle_ddeg - ANGLE_MIN_DDEG) * (PWM_MAX - PWM_MIN)
    span = ANGLE_MAX_DDEG - ANGLE_MIN_DDEG
    quotient = abs(numerator) // span
    return (quotient if numerator >= 0 else -quotient) + PWM_MIN


@dataclass(frozen=True)
class ServoUpdate:
    """One 32 ms update of the motion controller: when it ended and the 24 servo outputs."""

    time_s: float
    pwms: tuple[int, ...]


class EmulatedPlen2:
    """The emulated PLEN2 control board (a :class:`SimDevice`; see the module docstring).

    Attributes:
        board: The emulated AVR.
        sent: Every write from the host, as (simulated time, bytes).
        updates: Every motion-controller update so far.
    """

    def __init__(self, board: Board, elf: Path) -> None:
        self.board = board
        self.sent: list[tuple[float, bytes]] = []
        self.updates: list[ServoUpdate] = []
        self._out = bytearray()
        self._pwms = symbol_address(elf, PWMS)
        board.watch(symbol_address(elf, UPDATE_DUE), self._pwms, 2 * m.JOINT_COUNT)

    def connect(self, now_s: float) -> None:
        """The board has been running since power-on (time 0); it says nothing to a host."""
        self._advance(now_s)

    def receive(self, data: bytes, now_s: float) -> None:
        """Bytes from the host go down the UART from ``now_s``, one byte time apart."""
        self._advance(now_s)
        self.sent.append((now_s, data))
        self.board.write(data)

    def step(self, now_s: float) -> None:
        """Run the firmware to ``now_s`` once a mission tick has passed."""
        if now_s - self.board.time_s >= DEFAULT_PERIOD_S - 1e-9:
            self._advance(now_s)

    def pending_input_bytes(self) -> int:
        """Not known from outside the firmware: reported as none."""
        return 0

    def read_output(self) -> bytes:
        """What the firmware sent since the last call."""
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Power loss: nothing to cut here, the body does not move."""

    def servo_pwms(self) -> tuple[int, ...]:
        """The 24 servo outputs now."""
        return struct.unpack(f"<{m.JOINT_COUNT}H", self.board.peek(self._pwms, 2 * m.JOINT_COUNT))

    def _advance(self, now_s: float) -> None:
        if now_s <= self.board.time_s:
            return
        self._out += self.board.advance_to(now_s)
        for cycle, data in self.board.snapshots():
            pwms = struct.unpack(f"<{m.JOINT_COUNT}H", data)
            self.updates.append(ServoUpdate(cycle / self.board.f_cpu_hz, pwms))


def twin_updates(
    sent: list[tuple[float, bytes]], until_s: float, *, step_s: float = 0.001
) -> list[ServoUpdate]:
    """Play the same host writes, at the same times, into roboscript's simulated PLEN2, and
    record its servo outputs (its joint angles through :func:`servo_pwm`) after each of its
    motion-controller updates, stepping it every ``step_s``."""
    body = simulation_module.make_simulation("plen2").body
    twin = Plen2Board(body)
    twin.connect(0.0)
    updates: list[ServoUpdate] = []
    writes = iter(sent)
    pending = next(writes, None)
    tick = 0
    while (now_s := tick * step_s) <= until_s:
        while pending is not None and pending[0] <= now_s + 1e-9:
            twin.receive(pending[1], now_s)
            pending = next(writes, None)
        before = twin.update_count
        twin.step(now_s)
        if twin.update_count != before:
            pwms = tuple(servo_pwm(angle) for angle in twin.angles_ddeg)
            updates.append(ServoUpdate(now_s, pwms))
        tick += 1
    return updates


@contextmanager
def firmware_as_plen2(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[EmulatedPlen2]]:
    """Make every simulated PLEN2 in this test the emulated firmware; yields the boards."""
    elf = build(plen2_32u4())

    def make(body: Body) -> EmulatedPlen2:
        del body  # the firmware has no model of the legs: the body stays where it is
        board = Board(
            elf, PLEN2_MCU, PLEN2_F_CPU_HZ, uart="1", baud=PLEN2_BAUD, eeprom=PLEN2_EEPROM
        )
        return EmulatedPlen2(board, elf)

    with firmware_as_device(monkeypatch, lambda profile: profile.protocol == "plen", make) as built:
        yield built
