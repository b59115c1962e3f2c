"""PLEN2 commands on the wire, firmware 1.4.2: the host writes them, the device reads them.

A command is fixed-length ASCII with no separator and no line ending: a header character from
``$#><``, a two-letter command, then a fixed number of argument characters. Numbers are
zero-padded hex; 3-digit values are 12-bit two's complement (``f9c`` = −100, ``fff`` = −1) and
the 4-digit motion frame values are int16. :func:`encode_command` writes commands as
plen-ControlServer does (command letters upper case, hex digits lower case); :data:`COMMANDS`
says how the firmware reads each one (the framing, a fixed-length state machine, is
:class:`~roboscript.drivers.plen.codec.PlenCodec`'s).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from roboscript.drivers.plen.messages import (
    ANGLE_MAX_DDEG,
    ANGLE_MIN_DDEG,
    DIFF_LIMIT_DDEG,
    NAME_LENGTH,
    Command,
    GetJointSettings,
    GetMotion,
    GetVersion,
    HomePosition,
    MotionFrame,
    MotionHeader,
    PlayMotion,
    PopMotion,
    PushMotion,
    ResetInterpreter,
    ResetJointSettings,
    SetAngle,
    SetAngleDiff,
    SetHome,
    SetMax,
    SetMin,
    StopMotion,
)
from roboscript.errors import LocalProtocolError

__all__ = [
    "COMMANDS",
    "BadArgumentError",
    "CommandSpec",
    "encode_command",
    "firmware_reads_as_hex",
    "is_hex",
]

# --------------------------------------------------------------------------------------------
# Number formats
# --------------------------------------------------------------------------------------------


def _hex12(value: int) -> str:
    """Three hex digits, 12-bit two's complement."""
    return f"{value & 0xFFF:03x}"


def _hex16(value: int) -> str:
    """Four hex digits, 16-bit two's complement."""
    return f"{value & 0xFFFF:04x}"


def _unsigned(data: bytes) -> int:
    """The firmware's ``Utility::hexbytes2uint16`` (``Parser.cpp``) of any bytes: each
    character's value in base 16 as its C computes it, modulo 2**16. A hex digit reads as
    itself; other bytes read as the C arithmetic makes them (a NUL, which ends the firmware's
    check of an argument, reads 0; AVR's ``char`` is signed)."""
    result = 0
    for byte in data:
        digit = (byte - 256 if byte > 0x7F else byte) & 0xFFFF
        for floor, offset in ((0x61, 0x57), (0x41, 0x37), (0x30, 0x30)):
            if digit >= floor:
                digit = (digit - offset) & 0xFFFF
        result = (result * 16 + digit) & 0xFFFF
    return result


def _signed(data: bytes) -> int:
    """The firmware's ``Utility::hexbytes2int16``: ``len(data)`` digits, two's complement."""
    shift = (4 - len(data)) * 4
    value = (_unsigned(data) << shift) & 0xFFFF
    return (value - 0x10000 if value >= 0x8000 else value) >> shift


def _byte(data: bytes) -> int:
    """A field the firmware passes on as a ``uint8_t`` (joint ids, slots, frame indexes)."""
    return _unsigned(data) & 0xFF


def firmware_reads_as_hex(args: bytes) -> bool:
    """Whether the firmware's ``HexStringParser`` takes ``args``: its first byte and every
    byte before the first NUL are hex digits (the check stops at a NUL, as at the end of the
    buffer; the handler then reads every byte, the NUL included)."""
    checked = args.split(b"\0", 1)[0]
    return bool(checked) and is_hex(checked)


_HEX_DIGITS = b"0123456789abcdefABCDEF"


def is_hex(data: bytes) -> bool:
    return not data.translate(None, _HEX_DIGITS)


def _clamp(value: int, low: int, high: int) -> int:
    return max(low, min(high, value))


# --------------------------------------------------------------------------------------------
# Encoding commands
# --------------------------------------------------------------------------------------------


def encode_command(command: object) -> bytes:
    """Encode one command for the wire (no separator, no line ending).

    Args:
        command: One of the command messages of :mod:`roboscript.drivers.plen.messages`.

    Returns:
        The ASCII bytes, e.g. ``b"$AN0a384"`` for ``SetAngle(10, 900)``.

    Raises:
        LocalProtocolError: ``command`` is not a PLEN2 command.
    """
    text: str
    if isinstance(command, SetAngle):
        text = f"$AN{command.joint:02x}{_hex12(command.angle_ddeg)}"
    elif isinstance(command, SetAngleDiff):
        text = f"$AD{command.joint:02x}{_hex12(command.diff_ddeg)}"
    elif isinstance(command, PlayMotion):
        text = f"$PM{command.slot:02x}"
    elif isinstance(command, StopMotion):
        text = "$SM"
    elif isinstance(command, HomePosition):
        text = "$HP"
    elif isinstance(command, PushMotion):
        text = f"#PU{command.slot:02x}{command.play_count:02x}"
    elif isinstance(command, PopMotion):
        text = "#PO"
    elif isinstance(command, ResetInterpreter):
        text = "#RI"
    elif isinstance(command, SetHome):
        text = f">HO{command.joint:02x}{_hex12(command.angle_ddeg)}"
    elif isinstance(command, SetMax):
        text = f">MA{command.joint:02x}{_hex12(command.angle_ddeg)}"
    elif isinstance(command, SetMin):
        text = f">MI{command.joint:02x}{_hex12(command.angle_ddeg)}"
    elif isinstance(command, ResetJointSettings):
        text = ">JS"
    elif isinstance(command, MotionHeader):
        text = (
            f">MH{command.slot:02x}{command.name.ljust(NAME_LENGTH)}"
            f"{int(command.use_loop)}{command.loop_begin:02x}{command.loop_end:02x}"
            f"{command.loop_count:02x}{int(command.use_jump)}{command.jump_slot:02x}"
            f"{int(command.use_extra)}{command.frame_length:02x}"
        )
    elif isinstance(command, MotionFrame):
        values = "".join(_hex16(value) for value in command.offsets_ddeg)
        text = f">MF{command.slot:02x}{command.index:02x}{command.transition_time_ms:04x}{values}"
    elif isinstance(command, GetJointSettings):
        text = "<JS"
    elif isinstance(command, GetMotion):
        text = f"<MO{command.slot:02x}"
    elif isinstance(command, GetVersion):
        text = "<VI"
    else:
        raise LocalProtocolError(f"not a PLEN2 command: {command!r}")
    return text.encode("ascii")


# --------------------------------------------------------------------------------------------
# Decoding commands (device side)
# --------------------------------------------------------------------------------------------


class BadArgumentError(Exception):
    """An argument field the firmware would not read as intended."""


def _parse_set_angle(args: bytes) -> Command:
    angle = _clamp(_signed(args[2:5]), ANGLE_MIN_DDEG, ANGLE_MAX_DDEG)
    return SetAngle(_byte(args[0:2]), angle)


def _parse_set_angle_diff(args: bytes) -> Command:
    diff = _clamp(_signed(args[2:5]), -DIFF_LIMIT_DDEG, DIFF_LIMIT_DDEG)
    return SetAngleDiff(_byte(args[0:2]), diff)


def _parse_motion_header(args: bytes) -> Command:
    def number(start: int) -> int:
        # >MH is read with no check at all (Protocol.cpp: the nil parser): any bytes count
        return _byte(args[start : start + 2])

    def flag(position: int) -> bool:
        return args[position] != ord("0")  # the firmware reads anything but '0' as set

    raw_name = args[2:22]
    if any(not 0x20 <= byte <= 0x7E or byte in b'"\\' for byte in raw_name):
        raise BadArgumentError(f"motion name {raw_name!r} holds characters a name cannot hold")
    return MotionHeader(
        slot=number(0),
        name=raw_name.decode("ascii").rstrip(" "),
        use_loop=flag(22),
        loop_begin=number(23),
        loop_end=number(25),
        loop_count=number(27),
        use_jump=flag(29),
        jump_slot=number(30),
        use_extra=flag(32),
        frame_length=number(33),
    )


def _parse_motion_frame(args: bytes) -> Command:
    values = tuple(_signed(args[start : start + 4]) for start in range(8, 104, 4))
    return MotionFrame(_byte(args[0:2]), _byte(args[2:4]), _unsigned(args[4:8]), values)


@dataclass(frozen=True, slots=True)
class CommandSpec:
    name: str
    argc: int
    parse: Callable[[bytes], Command]
    free_text: bool = False


def _joint_value(factory: Callable[[int, int], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory(_byte(args[0:2]), _signed(args[2:5]))


def _slot(factory: Callable[[int], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory(_byte(args[0:2]))


def _bare(factory: Callable[[], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory()


COMMANDS: dict[tuple[int, bytes], CommandSpec] = {
    (ord(header), name.encode("ascii")): CommandSpec(header + name, argc, parse, free)
    for header, name, argc, parse, free in (
        ("$", "AD", 5, _parse_set_angle_diff, False),
        ("$", "AN", 5, _parse_set_angle, False),
        ("$", "HP", 0, _bare(HomePosition), False),
        ("$", "MP", 2, _slot(PlayMotion), False),
        ("$", "MS", 0, _bare(StopMotion), False),
        ("$", "PM", 2, _slot(PlayMotion), False),
        ("$", "SM", 0, _bare(StopMotion), False),
        ("#", "PO", 0, _bare(PopMotion), False),
        ("#", "PU", 4, lambda a: PushMotion(_byte(a[0:2]), _byte(a[2:4])), False),
        ("#", "RI", 0, _bare(ResetInterpreter), False),
        (">", "HO", 5, _joint_value(SetHome), False),
        (">", "JS", 0, _bare(ResetJointSettings), False),
        (">", "MA", 5, _joint_value(SetMax), False),
        (">", "MF", 104, _parse_motion_frame, False),
        (">", "MH", 35, _parse_motion_header, True),
        (">", "MI", 5, _joint_value(SetMin), False),
        ("<", "JS", 0, _bare(GetJointSettings), False),
        ("<", "MO", 2, _slot(GetMotion), False),
        ("<", "VI", 0, _bare(GetVersion), False),
    )
}
"""(header byte, upper-case command) -> how many argument characters and how to read them."""
