"""What an ASIP robot's sketch carries: servos, pixels and the LCD's width (profile options).

ASIP cannot say how many servos a sketch declares, and the LCD service never says how wide
it is, so they are *profile options* (:attr:`RobotProfile.options
<roboscript.profiles.RobotProfile.options>`), read here into an :class:`AsipOptions`. The host
driver offers that many servos and cuts display rows to that width; the simulated board is
built with the same servos and pixels. The defaults are the MIRTO sketch ``mirtle2017`` of the
V1.1 firmware (``michaelmargolis/ASIP-V1.1``): one servo, nine pixels, 20 characters a row.

A profile file changes only what differs::

    extends: mirto
    name: mirto-two-servos
    options:
      servo_count: 2
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from roboscript.drivers.asip.messages import LCD_COLUMNS
from roboscript.drivers.options import read_options
from roboscript.errors import ProfileError

__all__ = ["AsipOptions"]

_LIMITS = {"servo_count": (0, 16), "pixel_count": (0, 1024), "lcd_columns": (1, LCD_COLUMNS)}
TRANSPORTS = ("uart", "usb")
"""How the board's line reaches the firmware: ``uart`` (an ATmega328P's serial port: the
firmware sees a request a byte at a time, as the bytes arrive) or ``usb`` (a Teensy's USB
serial: a line the host wrote at once is there at once)."""


@dataclass(frozen=True)
class AsipOptions:
    """The options of an ASIP robot profile (defaults: the ``mirtle2017`` sketch).

    Attributes:
        servo_count: Servos the sketch declares (``NBR_SERVOS``), numbered from 0 on the wire.
        pixel_count: Pixels on the sketch's strip 0 (``MAX_PIXELS``); the driver asks the
            board (``P,I,0``), the simulated board answers this.
        lcd_columns: Characters a display row holds (1-20; the firmware keeps at most 20).
        transport: ``usb`` (the MIRTO's Teensy 3.1) or ``uart`` (an ATmega328P board such as
            the MIRTO 328 V2, or a Teensy on its serial pins), see :data:`TRANSPORTS`. On a
            UART board the firmware
            cannot read pixel requests (``asipPixels.cpp`` reads ``,{`` with two plain
            ``read()`` calls straight after ``parseInt()``, before the ``{`` has arrived),
            so the driver offers no LEDs there.
        reset_on_connect: Whether opening the port resets the board (an Arduino Uno-style
            board, whose USB chip's DTR line drives the reset): the sketch then starts
            again and answers nothing for its start-up, about 3.2 s for ``mirtle2017``.
            The driver waits for the board either way; the simulated board follows it.
    """

    servo_count: int = 1
    pixel_count: int = 9
    lcd_columns: int = LCD_COLUMNS
    transport: str = "usb"
    reset_on_connect: bool = False

    @property
    def int_bits(self) -> int:
        """The width of the firmware's ``int``, bits: 16 on a ``uart`` board (an
        ATmega328P), 32 on the ``usb`` board (the MIRTO's Teensy 3.1, an ARM)."""
        return 16 if self.transport == "uart" else 32

    @property
    def longest_tone_ms(self) -> int:
        """The longest tone the firmware plays, milliseconds: ``asipTone.cpp`` keeps the
        duration in an ``int``, so 32767 on a ``uart`` board (a longer one wraps: it is cut
        short, or, as a negative number, not played at all) and 2**31 - 1 on the ``usb``
        board."""
        return (1 << (self.int_bits - 1)) - 1

    @property
    def whole_lines(self) -> bool:
        """Whether the firmware sees a written line at once (USB) rather than byte by byte."""
        return self.transport == "usb"

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any], *, profile: str) -> AsipOptions:
        """Read the options of a profile, checking every value.

        Raises:
            ProfileError: An unknown option or a bad value, naming both.
        """
        return read_options(cls, options, profile=profile, family="ASIP", read=_read)


def _read(name: str, value: object, profile: str) -> int | str | bool:
    if name == "reset_on_connect":
        if not isinstance(value, bool):
            raise ProfileError(f"{profile}: ASIP option 'reset_on_connect' must be true or false")
        return value
    if name == "transport":
        if value not in TRANSPORTS:
            raise ProfileError(
                f"{profile}: ASIP option 'transport' must be one of {', '.join(TRANSPORTS)}"
            )
        return str(value)
    low, high = _LIMITS[name]
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ProfileError(f"{profile}: ASIP option '{name}' must be a whole number {low}-{high}")
    return value
