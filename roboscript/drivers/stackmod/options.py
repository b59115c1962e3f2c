"""How a StackMod robot is put together: module addresses, wiring, calibration and timing.

A StackMod robot is a set of modules on one serial line, each answering to its own address
byte. Which module sits at which address, which motor number drives which wheel, and how fast
a wheel turns per percent of motor power differ from robot to robot, so they are *profile
options* (:attr:`RobotProfile.options <roboscript.profiles.RobotProfile.options>`), read here
into a :class:`StackModOptions`. Both the host driver and the simulated modules use it, so the
simulator is wired the way the profile says.

A profile file changes only what differs::

    extends: stackmod-rover
    name: rover-7
    options:
      motor_address: X
      invert_right: true
      wheel_speed_mm_s_per_pct: 2.6

Every option and its default is a field of :class:`StackModOptions`. The built-in
``stackmod-reference`` profile sets ``firmware: reference``, ``checksum: braces_excluded``,
``framing: i2c`` and ``motor_address: E``: the StackMod author's own firmware and client.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal, TypeAlias, cast

from roboscript.codec import ProfileLike, Role
from roboscript.drivers.options import read_options
from roboscript.drivers.stackmod.codec import (
    CHECKSUM_RULES,
    FRAMINGS,
    ChecksumRule,
    Framing,
    StackModCodec,
)
from roboscript.drivers.stackmod.messages import ADDRESS_MAX, ADDRESS_MIN
from roboscript.errors import ProfileError

__all__ = ["FIRMWARES", "Firmware", "StackModOptions", "address_name", "codec_for"]

Firmware: TypeAlias = Literal["seed", "reference"]
"""What the modules run: firmware built on the 0.9.1 document (answers GETs, ``ARM``, sensors)
or the StackMod author's own (``74ls04/StackMod``: motor SETs only, answers nothing)."""
FIRMWARES: tuple[Firmware, ...] = ("seed", "reference")
"""Every :data:`Firmware`."""


def address_name(address: int) -> str:
    """A module address as users write it: ``'M' (0x4D)``."""
    return f"'{chr(address)}' ({address:#04X})".replace("0X", "0x")


@dataclass(frozen=True)
class StackModOptions:
    """The options of a StackMod robot profile (defaults: the ``stackmod-rover``).

    Addresses are bytes 0x40..0x5F; in a profile file write the character (``M``) or the
    number. Several roles may share one address when one module board does several jobs.

    Attributes:
        firmware: ``"seed"`` (modules built on the 0.9.1 document, with roboscript's formats
            for the commands it leaves open) or ``"reference"`` (the author's firmware: one
            motor module taking ``MTR`` SETs of ±255 PWM, with two address bytes, answering
            nothing, so no sensors and moves timed open-loop).
        framing: ``"serial"`` (packets back to back on the line) or ``"i2c"`` (each packet one
            I2C write led by the register byte 0x32, as the author's client writes them).
        motor_address: The dual motor driver module (MTR).
        servo_address: The servo module (SRV).
        ultrasonic_address: The ultrasonic ranger module (ULT sensor 0 faces forward,
            sensor 1 faces right, for following walls).
        ir_address: The IR line sensor module (IRS, sensors 0, 1, 2 = left, center, right).
        io_address: The module whose digital pins carry the bump switches and the buzzer
            (DGT). By default the IR board at the front of the rover.
        checksum: ``"seed"`` (the 0.9.1 document: braces included) or ``"braces_excluded"``
            (the author's Arduino and Python code; required with ``firmware: reference``).
            Host and modules must agree.
        left_motor: Motor number (0-9) of the left wheel on the motor module (1-9 with the
            reference firmware, which ignores motor 0).
        right_motor: Motor number (0-9) of the right wheel.
        invert_left: True if positive power turns the left wheel backward (motor mounted
            the other way round).
        invert_right: The same for the right wheel.
        servo_count: Servos on the servo module, numbered 1..servo_count on the wire.
        bumper_pins: Digital pins (0-99) of the left and right bump switches; a switch reads
            1 while pressed.
        buzzer_pin: Digital pin (0-99) of the active buzzer; 1 sounds it.
        buzzer_frequency_hz: The buzzer's one pitch, hertz (it cannot play others).
        wheel_speed_mm_s_per_pct: Calibration: wheel speed, mm/s, per percent of full motor
            power (full power is MTR 100 on the seed firmware, PWM 255 on the reference one,
            so a speed S measured at PWM P gives S * 2.55 / P). With no encoders, every
            distance and angle is estimated from it.
        min_power_pct: Smallest non-zero power sent, percent (1-100): below it the motors
            stall, so smaller commands are raised to it.
        get_timeout_s: How long to wait for the answer to a GET before sending it again,
            seconds (scheduler clock).
        get_retries: How many times a GET is sent again before the module is declared
            silent (0-10).
    """

    firmware: Firmware = "seed"
    framing: Framing = "serial"
    motor_address: int = ord("M")
    servo_address: int = ord("S")
    ultrasonic_address: int = ord("U")
    ir_address: int = ord("I")
    io_address: int = ord("I")
    checksum: ChecksumRule = "seed"
    left_motor: int = 1
    right_motor: int = 2
    invert_left: bool = False
    invert_right: bool = False
    servo_count: int = 1
    bumper_pins: tuple[int, int] = (2, 3)
    buzzer_pin: int = 8
    buzzer_frequency_hz: float = 2300.0
    # Tuned on the simulated rover: 400 mm/s at full power, less about 0.8 % mean wheel slip.
    wheel_speed_mm_s_per_pct: float = 3.968
    min_power_pct: int = 5
    get_timeout_s: float = 0.2
    get_retries: int = 2

    @classmethod
    def from_mapping(cls, options: Mapping[str, Any], *, profile: str) -> StackModOptions:
        """Read the options of a profile, checking every value.

        Args:
            options: Option name -> value, as written in the profile (unknown names refused).
            profile: The profile's name, for error messages.

        Raises:
            ProfileError: An unknown option or a bad value, naming both.
        """
        result = read_options(cls, options, profile=profile, family="StackMod", read=_read)
        result._check(profile)
        return result

    def _check(self, profile: str) -> None:
        if self.firmware == "reference":
            if self.checksum != "braces_excluded":
                raise ProfileError(
                    f"{profile}: the reference firmware sums its checksum without the braces: "
                    "set checksum: braces_excluded"
                )
            if 0 in (self.left_motor, self.right_motor):
                raise ProfileError(
                    f"{profile}: the reference firmware numbers its motors from 1: "
                    "left_motor and right_motor must be 1-9"
                )
        if self.left_motor == self.right_motor:
            raise ProfileError(f"{profile}: left_motor and right_motor must differ")
        pins = (*self.bumper_pins, self.buzzer_pin)
        if len(set(pins)) != len(pins):
            raise ProfileError(f"{profile}: bumper_pins and buzzer_pin must be different pins")

    @property
    def answers_get(self) -> bool:
        """Whether the modules answer GETs (the reference firmware answers nothing)."""
        return self.firmware == "seed"

    @property
    def module_roles(self) -> dict[int, tuple[str, ...]]:
        """Each module address -> the jobs it does (``("IR", "IO")``), in a stable order.

        The reference firmware is one motor module: it has no other role.
        """
        if self.firmware == "reference":
            return {self.motor_address: ("motor",)}
        roles: dict[int, tuple[str, ...]] = {}
        for role, address in (
            ("motor", self.motor_address),
            ("servo", self.servo_address),
            ("ultrasonic", self.ultrasonic_address),
            ("IR", self.ir_address),
            ("IO", self.io_address),
        ):
            roles[address] = (*roles.get(address, ()), role)
        return roles

    def describe_module(self, address: int) -> str:
        """The module at ``address`` in words: ``the motor module at 'M' (0x4D)``."""
        roles = "/".join(self.module_roles.get(address, ("unknown",)))
        return f"the {roles} module at {address_name(address)}"


def _fail(profile: str, name: str, expected: str, value: object) -> ProfileError:
    return ProfileError(f"{profile}: option '{name}' must be {expected}, got {value!r}")


def _int_in(value: object, low: int, high: int) -> int | None:
    if isinstance(value, int) and not isinstance(value, bool) and low <= value <= high:
        return value
    return None


def _read(name: str, value: object, profile: str) -> Any:
    """Check and convert one option value.

    Raises:
        ProfileError: The value does not fit the option.
    """
    if name.endswith("_address"):
        if isinstance(value, str) and len(value) == 1:
            value = ord(value)
        address = _int_in(value, ADDRESS_MIN, ADDRESS_MAX)
        if address is None:
            raise _fail(profile, name, "one character from '@' to '_' (0x40-0x5F)", value)
        return address
    if name == "firmware":
        if value not in FIRMWARES:
            raise _fail(profile, name, " or ".join(repr(f) for f in FIRMWARES), value)
        return value
    if name == "framing":
        if value not in FRAMINGS:
            raise _fail(profile, name, " or ".join(repr(f) for f in FRAMINGS), value)
        return value
    if name == "checksum":
        if value not in CHECKSUM_RULES:
            raise _fail(profile, name, " or ".join(repr(r) for r in CHECKSUM_RULES), value)
        return cast(ChecksumRule, value)
    if name.startswith("invert_"):
        if not isinstance(value, bool):
            raise _fail(profile, name, "true or false", value)
        return value
    if name == "bumper_pins":
        if isinstance(value, list | tuple) and len(value) == 2:
            pins = [_int_in(pin, 0, 99) for pin in value]
            if pins[0] is not None and pins[1] is not None:
                return (pins[0], pins[1])
        raise _fail(profile, name, "two pin numbers 0-99 (left, right)", value)
    limits = {
        "left_motor": (0, 9),
        "right_motor": (0, 9),
        "servo_count": (0, 9),
        "buzzer_pin": (0, 99),
        "min_power_pct": (1, 100),
        "get_retries": (0, 10),
    }
    if name in limits:
        low, high = limits[name]
        number = _int_in(value, low, high)
        if number is None:
            raise _fail(profile, name, f"a whole number {low}-{high}", value)
        return number
    if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
        raise _fail(profile, name, "a positive number", value)
    return float(value)


def codec_for(role: Role, profile: ProfileLike) -> StackModCodec:
    """The StackMod codec in ``role`` with the profile's checksum rule and framing (the
    protocol unit's codec factory).

    Raises:
        ProfileError: The profile's options are invalid.
    """
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    return StackModCodec(role, checksum=options.checksum, framing=options.framing)
