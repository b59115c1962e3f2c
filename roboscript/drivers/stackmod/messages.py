"""StackMod messages: typed, validated values for every packet the codec reads or writes.

A StackMod packet is ``{<address><action><CMD><data>}<checksum>``:

* ``address`` is one byte, ``0x40``-``0x5F`` (``@``..``_``), the module spoken to;
* ``action`` is ``?`` (GET) or ``$`` (SET);
* ``CMD`` is one of the seven three-letter commands of :class:`Command`;
* ``data`` is a fixed-width ASCII field: a *selector* (which motor, servo, sensor, pin, ...)
  and, in a SET request or a GET reply, a *value*.

Three message classes cover the protocol, each with the same generic shape:

* :class:`Get` ``(address, command, selector)``: a ``?`` request such as ``{X?MTR2}``;
* :class:`Set` ``(address, command, selector, value)``: a ``$`` request such as
  ``{X$MTR2+025}``;
* :class:`GetReply` ``(address, command, selector, value)``: the device's echo of a GET with the
  value appended, such as ``{X?MTR2+078}``.

The seed answers nothing to a SET (and the reference firmware answers nothing at all), so there
is no SET acknowledgement message.

Data formats
------------

Only MTR and SRV are defined by the StackMod 0.9.1 document; the other five commands have no
format in the seed nor in the author's code, so roboscript defines them. Widths are in ASCII
characters; every number is zero-padded decimal.

=======  ====================================  ==============================================  ====
Command  Selector                              Value                                           SET
=======  ====================================  ==============================================  ====
MTR      1 digit: motor number 0-9             sign ``+``/``-`` and 3 digits: speed,           yes
                                               -100..+100 % of full power (seed)
SRV      1 digit: servo number 0-9             3 digits: position, 0..180 degrees (seed)       yes
ARM      1 digit: subsystem, 0 = whole module  1 digit: 0 = disarmed, 1 = armed                yes
         (**roboscript's format**)             (**roboscript's format**)
ULT      1 digit: ultrasonic sensor 0-9        3 digits: distance 000..400 cm, or 999 = no     no
         (**roboscript's format**)             echo (**roboscript's format**)
IRS      1 digit: IR sensor 0-9                4 digits: raw reading 0000..1023                no
         (**roboscript's format**)             (**roboscript's format**)
DGT      2 digits: pin 00..99                  1 digit: level 0 = low, 1 = high                yes
         (**roboscript's format**)             (**roboscript's format**)
ANL      1 digit: analog channel 0-9           4 digits: raw ADC reading 0000..1023            no
         (**roboscript's format**)             (**roboscript's format**)
=======  ====================================  ==============================================  ====

ARM follows the seed's command table ("Arm / Disarm System"), not a robot-arm joint. ULT, IRS
and ANL are sensors: a SET of them is illegal. On the wire a MTR value of zero is sent as
``+000``; ``-000`` is accepted on receipt and means 0.

Examples (seed checksum rule): ``{X?ULT0}`` asks sensor 0 of module ``X`` for its distance and
``{X?ULT0123}`` answers 123 cm; ``{X$DGT131}`` drives pin 13 high; ``{X$ARM01}`` arms the whole
module.

The reference code's two-address form
-------------------------------------

The author's Python host sends ``{<module><0x70 'p'>$MTR...}`` (a second address byte naming the
I2C master). :class:`Get` and :class:`Set` carry that byte as ``source`` (``None`` for the
seed's one-address form); see :mod:`roboscript.drivers.stackmod.codec` for how it is detected.

The author's firmware itself implements one packet only, a motor SET in PWM units, ±255, with
exactly 11 characters between the braces (``{Ep$MTR1+139}``): :class:`MotorPwm`. It answers
nothing, so there is no reply to it.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TypeAlias, TypeGuard

from roboscript.errors import LocalProtocolError

__all__ = [
    "ADDRESS_MAX",
    "ADDRESS_MIN",
    "FORMATS",
    "HOST_SOURCE",
    "PWM_MAX",
    "SOURCE_MAX",
    "SOURCE_MIN",
    "ULT_NO_ECHO",
    "Command",
    "DataFormat",
    "Get",
    "GetReply",
    "Message",
    "MotorPwm",
    "Request",
    "Set",
]

ADDRESS_MIN = 0x40
"""Lowest module address, ``@``."""
ADDRESS_MAX = 0x5F
"""Highest module address, ``_``."""
SOURCE_MIN = 0x60
"""Lowest source byte of the reference code's two-address form, `````."""
SOURCE_MAX = 0x7A
"""Highest source byte of the reference code's two-address form, ``z``."""
HOST_SOURCE = 0x70
"""``p``: the reference code's ``I2C_MASTER_ADDRESS``, the usual source byte."""
PWM_MAX = 255
"""Full power in the author's firmware: its motor value is an 8-bit PWM duty, sign apart."""
ULT_NO_ECHO = 999
"""The ULT distance (cm) that means "no echo" (roboscript's format)."""


class Command(enum.Enum):
    """The seven StackMod 0.9.1 commands; the value is the three ASCII letters on the wire."""

    ARM = "ARM"
    """Arm / disarm the system."""
    MTR = "MTR"
    """Motor speed."""
    SRV = "SRV"
    """Servo position."""
    ULT = "ULT"
    """Ultrasonic distance."""
    IRS = "IRS"
    """IR sensor value."""
    DGT = "DGT"
    """Digital pin."""
    ANL = "ANL"
    """Analog pin."""


@dataclass(frozen=True, slots=True)
class DataFormat:
    """The fixed-width data field of one command.

    Attributes:
        selector_digits: Width of the selector (motor, sensor, pin...) in decimal digits.
        value_digits: Width of the value's magnitude in decimal digits (without a sign).
        signed: Whether the value starts with a ``+`` or ``-`` sign character.
        value_min: Smallest legal value, in ``unit``.
        value_max: Largest legal value, in ``unit``.
        special_values: Legal values outside ``value_min..value_max`` (ULT's 999 = no echo).
        settable: Whether a SET request is legal (``False`` for read-only sensors).
        unit: The value's unit, for documentation and messages.
    """

    selector_digits: int
    value_digits: int
    signed: bool
    value_min: int
    value_max: int
    special_values: frozenset[int]
    settable: bool
    unit: str

    @property
    def selector_max(self) -> int:
        """The largest selector that fits in ``selector_digits`` digits."""
        return int("9" * self.selector_digits)

    @property
    def value_width(self) -> int:
        """Width of the value field in characters, sign included."""
        return self.value_digits + (1 if self.signed else 0)

    def value_ok(self, value: int) -> bool:
        """Return whether ``value`` (in ``unit``) is legal for this command."""
        return self.value_min <= value <= self.value_max or value in self.special_values

    def format_selector(self, selector: int) -> str:
        """Return the zero-padded selector field, e.g. ``"2"`` or ``"13"``."""
        return f"{selector:0{self.selector_digits}d}"

    def format_value(self, value: int) -> str:
        """Return the value field, e.g. ``"+078"`` (signed) or ``"038"``; zero is ``"+000"``."""
        if self.signed:
            sign = "-" if value < 0 else "+"
            return f"{sign}{abs(value):0{self.value_digits}d}"
        return f"{value:0{self.value_digits}d}"

    def parse_value(self, text: str) -> int | None:
        """Return the integer in a value field, or ``None`` if ``text`` is not well formed.

        Range is not checked here; see :meth:`value_ok`.
        """
        if len(text) != self.value_width:
            return None
        sign = 1
        if self.signed:
            if text[0] not in "+-":
                return None
            sign = -1 if text[0] == "-" else 1
            text = text[1:]
        if not (text.isascii() and text.isdigit()):
            return None
        return sign * int(text)


def _format(
    selector_digits: int,
    value_digits: int,
    value_min: int,
    value_max: int,
    *,
    unit: str,
    signed: bool = False,
    settable: bool = True,
    special: frozenset[int] = frozenset(),
) -> DataFormat:
    return DataFormat(
        selector_digits=selector_digits,
        value_digits=value_digits,
        signed=signed,
        value_min=value_min,
        value_max=value_max,
        special_values=special,
        settable=settable,
        unit=unit,
    )


FORMATS: Mapping[Command, DataFormat] = MappingProxyType(
    {
        Command.ARM: _format(1, 1, 0, 1, unit="0 = disarmed, 1 = armed"),
        Command.MTR: _format(1, 3, -100, 100, unit="% of full power", signed=True),
        Command.SRV: _format(1, 3, 0, 180, unit="degrees"),
        Command.ULT: _format(
            1, 3, 0, 400, unit="cm", settable=False, special=frozenset({ULT_NO_ECHO})
        ),
        Command.IRS: _format(1, 4, 0, 1023, unit="raw reading", settable=False),
        Command.DGT: _format(2, 1, 0, 1, unit="0 = low, 1 = high"),
        Command.ANL: _format(1, 4, 0, 1023, unit="raw ADC reading", settable=False),
    }
)
"""The data format of every command (see the module docstring)."""


def _is_int(value: object) -> TypeGuard[int]:
    return isinstance(value, int) and not isinstance(value, bool)


def _check_head(address: object, command: object, selector: object) -> DataFormat:
    """Validate the fields every message has and return the command's format.

    Raises:
        LocalProtocolError: A field has the wrong type or is out of range.
    """
    if not _is_int(address) or not ADDRESS_MIN <= address <= ADDRESS_MAX:
        raise LocalProtocolError(
            f"StackMod address must be an int 0x40..0x5F ('@'..'_'), got {address!r}"
        )
    if not isinstance(command, Command):
        raise LocalProtocolError(f"StackMod command must be a Command, got {command!r}")
    fmt = FORMATS[command]
    if not _is_int(selector) or not 0 <= selector <= fmt.selector_max:
        raise LocalProtocolError(
            f"{command.value} selector must be an int 0..{fmt.selector_max}, got {selector!r}"
        )
    return fmt


def _check_value(command: Command, fmt: DataFormat, value: object) -> None:
    """Validate a SET or reply value against the command's range.

    Raises:
        LocalProtocolError: ``value`` is not an int or is out of range.
    """
    if not _is_int(value) or not fmt.value_ok(value):
        extra = "".join(f" or {v}" for v in sorted(fmt.special_values))
        raise LocalProtocolError(
            f"{command.value} value must be an int {fmt.value_min}..{fmt.value_max}{extra}"
            f" ({fmt.unit}), got {value!r}"
        )


def _check_source(source: object) -> None:
    """Validate the optional second address byte of the reference code's form.

    Raises:
        LocalProtocolError: ``source`` is neither ``None`` nor an int 0x60..0x7A.
    """
    if source is None:
        return
    if not _is_int(source) or not SOURCE_MIN <= source <= SOURCE_MAX:
        raise LocalProtocolError(
            f"StackMod source must be None or an int 0x60..0x7A ('`'..'z'), got {source!r}"
        )


@dataclass(frozen=True, slots=True)
class Get:
    """A GET request (``?`` without a value), e.g. ``{X?MTR2}`` asks motor 2's speed.

    Sent by the host, received by the device.

    Attributes:
        address: Module address byte, 0x40..0x5F (``ord("X")`` for ``X``).
        command: What is read.
        selector: Which motor, servo, sensor, pin or channel (see the format table).
        source: The reference code's second address byte (0x60..0x7A, usually ``0x70``
            ``p``), or ``None`` for the seed's one-address form.

    Raises:
        LocalProtocolError: A field is out of range.
    """

    address: int
    command: Command
    selector: int
    source: int | None = None

    def __post_init__(self) -> None:
        _check_head(self.address, self.command, self.selector)
        _check_source(self.source)

    def reply(self, value: int) -> GetReply:
        """Return the device's answer to this request carrying ``value`` (in the command's unit).

        Raises:
            LocalProtocolError: ``value`` is out of range for the command.
        """
        return GetReply(self.address, self.command, self.selector, value)


@dataclass(frozen=True, slots=True)
class Set:
    """A SET request (``$``), e.g. ``{X$MTR2+025}`` sets motor 2 to +25 %.

    Sent by the host, received by the device; the device does not answer it.

    Attributes:
        address: Module address byte, 0x40..0x5F.
        command: What is written; ULT, IRS and ANL are read-only.
        selector: Which motor, servo, pin... (see the format table).
        value: The new value, in the command's unit (MTR: % -100..100; SRV: degrees 0..180;
            ARM: 0/1; DGT: 0/1).
        source: The reference code's second address byte, or ``None``.

    Raises:
        LocalProtocolError: A field is out of range or the command is read-only.
    """

    address: int
    command: Command
    selector: int
    value: int
    source: int | None = None

    def __post_init__(self) -> None:
        fmt = _check_head(self.address, self.command, self.selector)
        if not fmt.settable:
            raise LocalProtocolError(f"{self.command.value} is read-only: it cannot be SET")
        _check_value(self.command, fmt, self.value)
        _check_source(self.source)


@dataclass(frozen=True, slots=True)
class GetReply:
    """The device's answer to a GET: the request echoed with the value appended.

    E.g. ``{X?MTR2+078}`` says motor 2 runs at +78 %. Sent by the device, received by the host.

    Attributes:
        address: Module address byte, 0x40..0x5F.
        command: What was read.
        selector: Which motor, servo, sensor, pin or channel.
        value: The reading, in the command's unit (ULT: cm 0..400 or 999 = no echo; IRS and
            ANL: raw 0..1023).

    Raises:
        LocalProtocolError: A field is out of range.
    """

    address: int
    command: Command
    selector: int
    value: int

    def __post_init__(self) -> None:
        fmt = _check_head(self.address, self.command, self.selector)
        _check_value(self.command, fmt, self.value)


@dataclass(frozen=True, slots=True)
class MotorPwm:
    """The author's firmware's one packet: set a motor's PWM, e.g. ``{Ep$MTR1+139}``.

    Sent by the host, never answered. Between the braces it is always 11 characters: module
    address, source, ``$``, ``MTR``, one motor digit, a sign and three digits.

    Attributes:
        address: Module address byte, 0x40..0x5F (the author's module is ``E``, 0x45; its
            firmware does not check it).
        motor: Motor number, 1..9 (the firmware counts from 1 and ignores motor 0).
        pwm: PWM duty, -255..255; negative turns the motor backward, 0 stops it.
        source: The second address byte, 0x60..0x7A (the author's client sends ``p``, 0x70).

    Raises:
        LocalProtocolError: A field is out of range.
    """

    address: int
    motor: int
    pwm: int
    source: int = HOST_SOURCE

    def __post_init__(self) -> None:
        if not _is_int(self.address) or not ADDRESS_MIN <= self.address <= ADDRESS_MAX:
            raise LocalProtocolError(
                f"StackMod address must be an int 0x40..0x5F ('@'..'_'), got {self.address!r}"
            )
        if not _is_int(self.motor) or not 1 <= self.motor <= 9:
            raise LocalProtocolError(f"MTR motor must be an int 1..9, got {self.motor!r}")
        if not _is_int(self.pwm) or not -PWM_MAX <= self.pwm <= PWM_MAX:
            raise LocalProtocolError(
                f"MTR PWM must be an int -{PWM_MAX}..{PWM_MAX}, got {self.pwm!r}"
            )
        if self.source is None:
            raise LocalProtocolError("the author's firmware needs a source byte, got None")
        _check_source(self.source)


Request: TypeAlias = Get | Set
"""What the host sends and the device receives."""
Message: TypeAlias = Get | Set | GetReply
"""Every StackMod message."""
