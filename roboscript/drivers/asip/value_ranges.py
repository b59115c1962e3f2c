"""The range of every number an ASIP board prints, from the types its firmware keeps it in.

A number outside its range is not a reading: it is line noise, a corrupted digit run or a
broken sketch. The host codec counts such a line as an ``"out_of_range"`` fault and skips it,
so a 400-digit encoder count never reaches arithmetic that would overflow; the device codec
refuses to send one (:class:`~roboscript.errors.LocalProtocolError`), so the simulated board
never prints what a real one cannot.

Sources are the V1.1 firmware (``michaelmargolis/ASIP-V1.1``) unless marked V1.2
(``michaelmargolis/ASIP-V1.2``); ``long`` is 32 bits on every ASIP board (AVR and Teensy 3).
"""

from __future__ import annotations

from collections.abc import Iterable

from roboscript.errors import LocalProtocolError

__all__ = [
    "ALTITUDE_M",
    "ANALOG_VALUE",
    "BUMP_LEVEL",
    "BYTE",
    "DISTANCE_CM",
    "ENCODER_COUNT",
    "ERRNO",
    "HEADING_DEG",
    "IMU_AXIS",
    "PARSE_INT",
    "PIXEL_COUNT",
    "PORT_MASK",
    "PRESSURE_MBAR",
    "TEMPERATURE_C",
    "OutOfRangeError",
    "check_range",
]

IntRange = tuple[int, int]
FloatRange = tuple[float, float]

_INT16: IntRange = (-32768, 32767)
_INT32: IntRange = (-2_147_483_648, 2_147_483_647)

BYTE: IntRange = (0, 255)
"""Pin, port, channel, pin mode, capability mask, version number, strip: bytes on the board."""
PORT_MASK: IntRange = (0, 0xFFFF_FFFF)
"""A port's bit mask (``@I,M``, ``@I,d``): Teensy 3 ports are 32 bits wide."""
ANALOG_VALUE: IntRange = (0, 1023)
"""``analogRead`` at the boards' default 10-bit resolution (``@I,a``, ``@R,e``)."""
BUMP_LEVEL: IntRange = (0, 1)
"""A bump switch's ``digitalRead`` level (``@B,e``), printed as ``"1"`` or ``"0"``."""
ENCODER_COUNT: IntRange = _INT32
"""``@M,e`` deltas and totals, ``@E,e`` pulse widths and counts: ``long`` in ``asipRobot.h``."""
DISTANCE_CM: IntRange = (-1, 16_777)
"""``@D,e``: -1 for an absent I2C sensor (V1.2); at most a 24-bit I2C reading / 1000 (V1.2
``readI2CSensor``); the V1.1 ultrasonic sensor stops at about 100 cm."""
IMU_AXIS: IntRange = _INT16
"""Raw accelerometer, gyro and magnetometer axes (``int16_t``, V1.2 ``asipIMU.cpp``)."""
HEADING_DEG: IntRange = (0, 360)
"""``@H,e``'s heading: ``atan2`` moved into 0..2π, in whole degrees."""
PIXEL_COUNT: IntRange = (0, 65535)
"""``@P,I``: pixels on a strip (``uint16_t`` in the NeoPixel library)."""
ERRNO: IntRange = BYTE
"""``~`` replies: ``asipErr_t`` numbers (0-9 in V1.1)."""
PARSE_INT: IntRange = _INT32
"""A number in a request: Arduino ``Stream::parseInt`` returns a ``long``."""
PRESSURE_MBAR: FloatRange = (0.0, 2000.0)
"""``@P,e`` pressure (V1.2 ``PressureClass``); barometers read 300-1100 mbar."""
TEMPERATURE_C: FloatRange = (-100.0, 200.0)
"""``@P,e`` temperature; the barometers' own range is -40..85 °C."""
ALTITUDE_M: FloatRange = (-10_000.0, 50_000.0)
"""``@P,e`` altitude, derived from the pressure: about -6 km at 2000 mbar, 44 km at 0."""


class OutOfRangeError(ValueError):
    """A well-formed number that the board's firmware cannot print (host side, internal)."""


def check_range(name: str, values: Iterable[float], bounds: tuple[float, float]) -> None:
    """Refuse a message to send whose values the firmware could not hold.

    Args:
        name: The field, for the message.
        values: The field's values.
        bounds: Lowest and highest value allowed, inclusive.

    Raises:
        LocalProtocolError: A value is outside ``bounds`` (or is NaN).
    """
    low, high = bounds
    for value in values:
        if not low <= value <= high:  # written this way round so that NaN fails too
            raise LocalProtocolError(f"{name} must be in {low}..{high}, got {value}")
