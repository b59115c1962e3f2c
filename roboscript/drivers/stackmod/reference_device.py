"""The StackMod author's motor module, simulated: parses bytes the way its firmware does.

The StackMod author's firmware (``74ls04/StackMod``: the Arduino ``Stackmodio`` library and the
``stackmod`` sketch) is far laxer and far smaller than the 0.9.1 document. This module is a
second implementation of its *behaviour*, written from reading it, so that a host which works
here works on that firmware. It never uses the codec: a codec that refused what the firmware
takes, or took what it drops, would hide the very mismatch this twin is for.

What the firmware does, and so what this twin does:

* **I2C only.** Bytes arrive in I2C writes (slave address 0x45); the sketch's serial reader is
  commented out. Each :meth:`ReferenceModule.receive` is one write: at most 32 bytes are kept
  (Arduino's receive buffer), and the end of the write resets the parser, so a packet split
  over two writes is lost. The client's register byte ``0x32`` is skipped like any byte
  outside a packet.
* **Packets** start at ``{`` and end at ``}`` followed by one checksum byte (whatever it is).
  The text between the braces is kept as a C string: at most 31 characters, a NUL byte resets
  the parser (as the end of a write does), and a ``{`` inside a packet starts again *without*
  rewinding the write position, so the restarted text begins with NULs and reads as empty.
* **Checksum**: ``(sum(c - 32) % 95) + 32`` over the text *between* the braces (C's ``%`` on
  a signed sum; bytes above 0x7F count negative, as AVR's ``char`` is signed).
* **Only ``MTR`` SET** is acted on, and only when the text is exactly 11 characters: two bytes
  the firmware does not check (the address check is commented out), ``$``, ``MTR``, then
  ``sscanf("%d%d")`` of the last five characters gives the motor number and the value
  (``1+139`` is motor 1, +139). The motor number is taken modulo 256 (a ``uint8_t``
  parameter: ``257+9`` sets motor 1); motors 1..15 are stored unclamped; every other packet,
  including every GET, is silently ignored. Nothing is ever sent back.
* **Motors** are applied by the sketch's main loop every 200 ms: motor 1 drives the left wheels
  and motor 2 the right ones at duty ``|value| / 255`` in the value's direction (values past
  ±255 are outside what the author's client sends; this twin treats them as full power).
"""

from __future__ import annotations

import logging
from collections import Counter
from typing import Protocol

from roboscript.drivers.stackmod.codec import I2C_WRITE_MAX_BYTES
from roboscript.drivers.stackmod.messages import PWM_MAX
from roboscript.drivers.stackmod.options import StackModOptions

__all__ = ["LOOP_PERIOD_S", "MOTOR_REGISTERS", "Motors", "ReferenceModule", "scan_int"]

logger = logging.getLogger(__name__)

LOOP_PERIOD_S = 0.2
"""The sketch's main loop applies the motor registers this often, seconds (``delay(200)``)."""
MOTOR_REGISTERS = 15
"""Motor registers the firmware keeps (motors 1..15); the sketch drives 1 and 2."""
_TEXT_BYTES = 32
"""The firmware's packet buffer, NUL terminator included."""
_MTR_TEXT_CHARS = 11
_OPEN = 0x7B
_CLOSE = 0x7D
_SET = 0x24
_COMMANDS = ("ARM", "MTR", "SRV", "ULT", "IRS", "DGT", "ANL")
_C_SPACE = frozenset(b" \t\n\v\f\r")


class Motors(Protocol):
    """What the module drives: the simulated body's two wheel motors.

    Only this, so that the firmware's model stays standard library only, like a codec.
    """

    def set_power(self, left: float, right: float) -> None:
        """Set each wheel's power, -1.0 (full reverse) to 1.0 (full forward)."""
        ...


def scan_int(text: bytes, at: int) -> tuple[int, int] | None:
    """Read one C ``%d`` from ``text`` at ``at``: spaces, an optional sign, then digits.

    Returns:
        ``(value, index after it)``, or ``None`` if no digit follows (the conversion fails).
    """
    index = at
    while index < len(text) and text[index] in _C_SPACE:
        index += 1
    sign = 1
    if index < len(text) and text[index] in b"+-":
        sign = -1 if text[index] == ord("-") else 1
        index += 1
    start = index
    while index < len(text) and 0x30 <= text[index] <= 0x39:
        index += 1
    if index == start:
        return None
    return sign * int(text[start:index]), index


def _c_checksum(text: bytes) -> int:
    """The firmware's checksum of the text between the braces, as its C computes it."""
    total = sum((b - 256 if b > 0x7F else b) - 32 for b in text)
    remainder = abs(total) % 95  # C's % keeps the sign of the dividend
    return (-remainder if total < 0 else remainder) + 32


class ReferenceModule:
    """The author's motor module on a simulated body (see the module docstring).

    Args:
        body: The simulated body whose wheels motors 1 (left) and 2 (right) drive.
        options: The profile's options (wheel inversion; the addresses are not checked, as
            the firmware does not check them).

    Attributes:
        motor_registers: The firmware's motor values, motor 1 first (unclamped, as stored).
        taken: Packets that set a motor.
        ignored: Packets with a correct checksum that did nothing, by reason.
        bad_checksums: Complete packets dropped for their checksum.
    """

    def __init__(self, body: Motors, options: StackModOptions | None = None) -> None:
        self.body = body
        self.options = options or StackModOptions(
            firmware="reference", checksum="braces_excluded", framing="i2c"
        )
        self.motor_registers = [0] * MOTOR_REGISTERS
        self.taken = 0
        self.ignored: Counter[str] = Counter()
        self.bad_checksums = 0
        self._text = bytearray(_TEXT_BYTES)
        self._index = 0
        self._receiving = False
        self._awaiting_checksum = False
        self._next_loop_s = 0.0

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """A host opened the bus: an I2C slave has no connection, so nothing changes."""
        del now_s

    def receive(self, data: bytes, now_s: float) -> None:
        """One I2C write from the host: its first 32 bytes, then the end-of-write reset."""
        del now_s
        for byte in data[:I2C_WRITE_MAX_BYTES]:
            self._byte(byte)
        self._byte(0)  # the sketch feeds a 0 when a write ends

    def step(self, now_s: float) -> None:
        """Run the sketch's main loop: apply the motor registers every 200 ms."""
        while now_s >= self._next_loop_s - 1e-9:
            self._drive()
            self._next_loop_s += LOOP_PERIOD_S

    def pending_input_bytes(self) -> int:
        """Always 0: each I2C write is a whole one (the sketch ends it with a 0)."""
        return 0

    def read_output(self) -> bytes:
        """The firmware never writes: always empty."""
        return b""

    def stop_all(self) -> None:
        """Power loss: the registers come back at 0 and the wheels stop."""
        self.motor_registers = [0] * MOTOR_REGISTERS
        self._reset()
        self._awaiting_checksum = False
        self._drive()

    # ----------------------------------------------------------------------------- parsing

    def _reset(self) -> None:
        self._text[:] = bytes(_TEXT_BYTES)
        self._receiving = False
        self._index = 0

    def _byte(self, byte: int) -> None:
        if byte == 0:
            self._reset()  # and, as in the firmware, the 0 may still be taken as a checksum
        if self._awaiting_checksum:
            self._awaiting_checksum = False
            text = bytes(self._text).split(b"\0", 1)[0]
            if _c_checksum(text) == byte:
                self._process(text)
            else:
                self.bad_checksums += 1
            return
        if self._receiving and byte != _OPEN:
            if byte != _CLOSE:
                # The firmware stops advancing at its last byte; a write of at most 32 bytes,
                # '{' included, never gets that far, so no clamp is needed here.
                self._text[self._index] = byte
                self._index += 1
            else:
                self._text[self._index] = 0
                self._index = 0
                self._receiving = False
                self._awaiting_checksum = True
        elif byte == _OPEN:
            # The firmware clears the text but keeps its write position here.
            self._receiving = True
            self._text[:] = bytes(_TEXT_BYTES)

    def _process(self, text: bytes) -> None:
        if len(text) < 5:
            self._ignore("shorter than 5 characters", text)
            return
        name = text[3:6].decode("latin-1")
        if name != "MTR":
            known = name in _COMMANDS
            self._ignore("a command the firmware does not act on" if known else "unknown", text)
            return
        if text[2] != _SET:
            self._ignore("MTR without '$' (the firmware answers no GET)", text)
            return
        if len(text) != _MTR_TEXT_CHARS:
            self._ignore(f"MTR SET of {len(text)} characters, not 11", text)
            return
        first = scan_int(text, 6)
        second = None if first is None else scan_int(text, first[1])
        if first is None or second is None:
            self._ignore("MTR data that sscanf cannot read as two numbers", text)
            return
        # setMotorSpeed takes the motor number as a uint8_t: 257 is motor 1.
        motor, value = first[0] & 0xFF, second[0]
        if not 0 < motor <= MOTOR_REGISTERS:
            self._ignore(f"motor {motor} (the firmware has motors 1-15)", text)
            return
        self.motor_registers[motor - 1] = value
        self.taken += 1

    def _ignore(self, reason: str, text: bytes) -> None:
        self.ignored[reason] += 1
        logger.debug("reference StackMod module ignored {%r}: %s", text, reason)

    # ------------------------------------------------------------------------------ motors

    def _drive(self) -> None:
        opts = self.options
        left, right = self.motor_registers[0], self.motor_registers[1]
        self.body.set_power(
            _duty(left) * (-1 if opts.invert_left else 1),
            _duty(right) * (-1 if opts.invert_right else 1),
        )


def _duty(value: int) -> float:
    """The fraction of full power a motor register gives, signed (the body saturates past
    ±1.0, so values past ±255 give full power)."""
    return value / PWM_MAX
