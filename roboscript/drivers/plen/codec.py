"""Sans-IO codec of the PLEN2 serial protocol, firmware 1.4.2, for both roles.

Requests (host -> device) are fixed-length ASCII commands with no separator and no line ending:
a header character from ``$#><``, a two-letter command, then a fixed number of argument
characters. Numbers are zero-padded hex; 3-digit values are 12-bit two's complement
(``f9c`` = −100, ``fff`` = −1) and the 4-digit motion frame values are int16. The host encodes
command letters in upper case and hex digits in lower case, as plen-ControlServer does; the
device accepts either case.

Only the getters ``<JS``, ``<MO`` and ``<VI`` are answered. Replies are tab-indented JSON
printed line by line with CRLF line endings, and nothing marks their end.

DEVICE role (decodes commands, encodes replies) mirrors the firmware's parser, a fixed-length
state machine:

1. Between commands, CR and LF are dropped silently (not counted). Any other byte that is not
   a header character is garbage: a run of such bytes is one ``"garbage"`` fault, raised when
   the run ends (at the next header character or CR/LF), so fault counts do not depend on how
   the bytes were chunked.
2. The two command characters are read, then matched case-insensitively against the commands
   of that header; no match is a ``"bad_command"`` fault that consumes header and command.
3. The argument characters are read, all of them, whatever they are (a CR/LF inside a command
   is an argument character), and only then checked: they must be hex digits, except in
   ``>MH`` whose name is free text. A bad one is a ``"bad_argument"`` fault that consumes the
   whole command, just as the firmware resets to READY.
4. A well-formed command whose values our messages cannot hold is an ``"out_of_range"`` fault.
   The firmware ignores those too (a joint id above 23, a slot above 89, ``>HO``/``>MA``/``>MI``
   beyond ±900, a header with 0 or more than 20 frames) or stores values that are meaningless
   (a loop frame above 19, a transition under 32 ms, a name with control characters or ``"``).
   The exceptions are ``$AN`` and ``$AD``: the firmware clamps them, so they decode with the
   value clamped to ±900 (``$AN``) or ±1800 (``$AD``) and act exactly as on the robot; the seed's
   ``$an0a3e8`` (1000) decodes as ``SetAngle(10, 900)``.

HOST role (encodes commands, decodes replies): whitespace between replies is dropped; a reply
starts at ``{`` or ``[`` and ends when its brackets balance outside strings, then it is parsed
with :func:`json.loads`. Its type is **inferred from its shape** (an array is ``<JS``, an object
with ``slot``/``frames`` is ``<MO``, one with ``version`` is ``<VI``), so the codec keeps no
state about what was asked; since replies carry no request id, the driver keeps one getter in
flight at a time. Faults: ``"garbage"`` (bytes outside a reply), ``"overlong"`` (a reply longer
than ``max_reply_bytes``: its first ``max_reply_bytes`` are dropped with the fault and the rest
are dropped silently until its brackets balance), ``"bad_json"`` (not JSON, or nested deeper
than any reply), ``"bad_reply"`` (JSON that is not a valid reply).

Because a reply has no terminator, a truncated reply would swallow the next one. The timeout
belongs to the driver: when a getter's reply is late it checks :attr:`PlenCodec.in_progress`
or :meth:`PlenCodec.pending_bytes` and calls :meth:`PlenCodec.reset` to abandon the partial
reply (counted as an ``"abandoned"`` fault).
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import NoReturn

from roboscript.drivers.codec import CodecStats, Role
from roboscript.drivers.plen.messages import (
    ANGLE_MAX_DDEG,
    ANGLE_MIN_DDEG,
    DIFF_LIMIT_DDEG,
    JOINT_COUNT,
    JOINT_NAMES,
    NAME_LENGTH,
    Command,
    GetJointSettings,
    GetMotion,
    GetVersion,
    HomePosition,
    JointSetting,
    JointSettingsReply,
    JumpCode,
    LoopCode,
    MotionFrame,
    MotionHeader,
    MotionReply,
    MotionReplyFrame,
    PlayMotion,
    PlenMessage,
    PopMotion,
    PushMotion,
    Reply,
    ResetInterpreter,
    ResetJointSettings,
    SetAngle,
    SetAngleDiff,
    SetHome,
    SetMax,
    SetMin,
    StopMotion,
    VersionReply,
    joint_id,
)
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

__all__ = [
    "DEFAULT_MAX_REPLY_BYTES",
    "PlenCodec",
    "encode_command",
    "encode_reply",
    "motion_from_json",
    "motion_to_json",
    "reply_from_json",
]

DEFAULT_MAX_REPLY_BYTES = 65536
"""Default limit of one reply; a full 20-frame ``<MO`` dump is about 25 kB."""

_MAX_DEPTH = 16
"""Deepest bracket nesting accepted in a reply (a ``<MO`` dump nests 5 deep)."""

"""Most bytes kept in :attr:`RemoteProtocolError.data`."""

_EOL = "\r\n"

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
    return int(data, 16)


def _signed12(data: bytes) -> int:
    value = int(data, 16)
    return value - 0x1000 if value >= 0x800 else value


def _signed16(data: bytes) -> int:
    value = int(data, 16)
    return value - 0x10000 if value >= 0x8000 else value


_HEX_DIGITS = b"0123456789abcdefABCDEF"


def _is_hex(data: bytes) -> bool:
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
# Encoding replies (device side), formatted like the firmware's println() dumps
# --------------------------------------------------------------------------------------------


def _json_str(value: str) -> str:
    return json.dumps(value)


def _lines_to_bytes(lines: Iterable[str]) -> bytes:
    return "".join(line + _EOL for line in lines).encode("ascii")


def _object_lines(indent: int, items: Sequence[tuple[str, str]], last: bool) -> list[str]:
    """Lines of a JSON object whose values are already encoded, one key per line."""
    tabs = "\t" * indent
    lines = [tabs + "{"]
    for position, (key, value) in enumerate(items):
        comma = "," if position < len(items) - 1 else ""
        lines.append(f'{tabs}\t"{key}": {value}{comma}')
    lines.append(tabs + ("}" if last else "},"))
    return lines


def _joint_settings_lines(reply: JointSettingsReply) -> list[str]:
    lines = ["["]
    for entry in reply.joints:
        items = [
            ("@device", str(entry.joint)),
            ("max", str(entry.max_ddeg)),
            ("min", str(entry.min_ddeg)),
            ("home", str(entry.home_ddeg)),
        ]
        lines += _object_lines(1, items, last=entry.joint == JOINT_COUNT - 1)
    lines.append("]")
    return lines


def _motion_lines(reply: MotionReply) -> list[str]:
    lines = [
        "{",
        f'\t"slot": {reply.slot},',
        f'\t"name": {_json_str(reply.name.ljust(NAME_LENGTH))},',
        f'\t"@frame_length": {reply.frame_length},',
        '\t"codes": [',
    ]
    codes: list[list[tuple[str, str]]] = []
    if reply.loop is not None:
        loop = reply.loop
        arguments = f"[{loop.begin}, {loop.end}, {loop.count}]"
        codes.append([("method", '"loop"'), ("arguments", arguments)])
    if reply.jump is not None:
        codes.append([("method", '"jump"'), ("arguments", f"[{reply.jump.slot}]")])
    for position, code in enumerate(codes):
        lines += _object_lines(2, code, last=position == len(codes) - 1)
    lines += ["\t],", '\t"frames": [']
    for frame in reply.frames:
        lines += [
            "\t\t{",
            f'\t\t\t"@index": {frame.index},',
            f'\t\t\t"transition_time_ms": {frame.transition_time_ms},',
            '\t\t\t"outputs": [',
        ]
        for joint, value in enumerate(frame.offsets_ddeg):
            items = [("device", str(joint)), ("value", str(value))]
            lines += _object_lines(4, items, last=joint == JOINT_COUNT - 1)
        lines.append("\t\t\t]")
        lines.append("\t\t}" if frame.index == reply.frame_length - 1 else "\t\t},")
    lines += ["\t]", "}"]
    return lines


def _version_lines(reply: VersionReply) -> list[str]:
    return [
        "{",
        f'\t"device": {_json_str(reply.device)},',
        f'\t"codename": {_json_str(reply.codename)},',
        f'\t"version": {_json_str(reply.version)}',
        "}",
    ]


def encode_reply(reply: object) -> bytes:
    """Encode one getter reply the way firmware 1.4.2 prints it.

    Lines end in CRLF and are indented with tabs, keys and values separated by ``": "``, one
    key per line (``<MO`` prints each of the 24 outputs of a frame as its own object). The
    ``<MO`` name is printed padded to 20 characters as the firmware stores it. Strings are JSON
    escaped, where the firmware would print ``"`` raw; our messages never hold one.

    Args:
        reply: A :class:`JointSettingsReply`, :class:`MotionReply` or :class:`VersionReply`.

    Returns:
        The reply bytes, ending with the CRLF of the last ``println``.

    Raises:
        LocalProtocolError: ``reply`` is not a PLEN2 reply.
    """
    if isinstance(reply, JointSettingsReply):
        return _lines_to_bytes(_joint_settings_lines(reply))
    if isinstance(reply, MotionReply):
        return _lines_to_bytes(_motion_lines(reply))
    if isinstance(reply, VersionReply):
        return _lines_to_bytes(_version_lines(reply))
    raise LocalProtocolError(f"not a PLEN2 reply: {reply!r}")


# --------------------------------------------------------------------------------------------
# Decoding replies from JSON values (host side), and the motion file format
# --------------------------------------------------------------------------------------------


def _lowered(obj: Mapping[str, object]) -> dict[str, object]:
    return {key.lower(): value for key, value in obj.items()}


def _as_mapping(value: object, where: str) -> Mapping[str, object]:
    if not isinstance(value, Mapping):
        raise LocalProtocolError(f"{where} must be a JSON object, not {value!r}")
    return value


def _as_list(value: object, where: str) -> list[object]:
    if not isinstance(value, list):
        raise LocalProtocolError(f"{where} must be a JSON array, not {value!r}")
    return value


def _as_int(value: object, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise LocalProtocolError(f"{where} must be an integer, not {value!r}")
    return value


def _as_str(value: object, where: str) -> str:
    if not isinstance(value, str):
        raise LocalProtocolError(f"{where} must be a string, not {value!r}")
    return value


def _require(obj: Mapping[str, object], key: str, where: str) -> object:
    if key not in obj:
        raise LocalProtocolError(f"{where} lacks {key!r}")
    return obj[key]


def _first(obj: Mapping[str, object], keys: Sequence[str], where: str) -> object:
    for key in keys:
        if key in obj:
            return obj[key]
    raise LocalProtocolError(f"{where} lacks {keys[0]!r}")


def _apply_outputs(outputs: object, previous: Sequence[int], where: str) -> tuple[int, ...]:
    """Apply a frame's ``outputs`` to the previous frame's values (joints left out carry over).

    A ``device`` may be a joint name (motion file) or an integer id (``<MO`` dump).
    """
    values = list(previous)
    for position, output in enumerate(_as_list(outputs, f"{where} outputs")):
        entry = _as_mapping(output, f"{where} outputs[{position}]")
        device = _require(entry, "device", f"{where} outputs[{position}]")
        if isinstance(device, str):
            joint = joint_id(device)
        else:
            joint = _as_int(device, f"{where} outputs[{position}] device")
            if not 0 <= joint < JOINT_COUNT:
                raise LocalProtocolError(f"{where} outputs[{position}]: no joint id {joint}")
        values[joint] = _as_int(
            _require(entry, "value", f"{where} outputs[{position}]"),
            f"{where} outputs[{position}] value",
        )
    return tuple(values)


def _codes(codes: object, where: str) -> tuple[LoopCode | None, JumpCode | None]:
    """Read ``codes``: ``{"method"|"func": "loop"|"jump", "arguments"|"args": [...]}``."""
    loop: LoopCode | None = None
    jump: JumpCode | None = None
    for position, code in enumerate(_as_list(codes, f"{where} codes")):
        entry = _lowered(_as_mapping(code, f"{where} codes[{position}]"))
        method = _first(entry, ("method", "func"), f"{where} codes[{position}]")
        arguments = _as_list(
            _first(entry, ("arguments", "args"), f"{where} codes[{position}]"),
            f"{where} codes[{position}] arguments",
        )
        numbers = [_as_int(value, f"{where} codes[{position}] arguments") for value in arguments]
        if method == "loop":
            if len(numbers) < 3:
                raise LocalProtocolError(f"{where} loop needs [begin, end, count]")
            loop = LoopCode(numbers[0], numbers[1], numbers[2])
        elif method == "jump":
            if not numbers:
                raise LocalProtocolError(f"{where} jump needs [slot]")
            jump = JumpCode(numbers[0])
        else:
            raise LocalProtocolError(f"{where} codes[{position}]: unknown method {method!r}")
    return loop, jump


def _joint_settings_from_json(items: list[object]) -> JointSettingsReply:
    by_joint: dict[int, JointSetting] = {}
    for position, item in enumerate(items):
        where = f"<JS entry {position}"
        entry = _lowered(_as_mapping(item, where))
        # 1.4.2 names the joint "@device"; the seed's form has no key and relies on order.
        joint = entry.get("@device", entry.get("device", entry.get("joint", position)))
        setting = JointSetting(
            joint=_as_int(joint, f"{where} @device"),
            min_ddeg=_as_int(_require(entry, "min", where), f"{where} min"),
            max_ddeg=_as_int(_require(entry, "max", where), f"{where} max"),
            home_ddeg=_as_int(_require(entry, "home", where), f"{where} home"),
        )
        if setting.joint in by_joint:
            raise LocalProtocolError(f"<JS lists joint {setting.joint} twice")
        by_joint[setting.joint] = setting
    if len(by_joint) != JOINT_COUNT:
        raise LocalProtocolError(f"<JS lists {len(by_joint)} joints, not {JOINT_COUNT}")
    return JointSettingsReply(tuple(by_joint[joint] for joint in range(JOINT_COUNT)))


def _motion_reply_from_json(obj: Mapping[str, object]) -> MotionReply:
    entry = _lowered(obj)
    slot = _as_int(_require(entry, "slot", "<MO"), "<MO slot")
    name = _as_str(entry.get("name", ""), "<MO name").rstrip(" ")
    loop, jump = _codes(entry.get("codes", []), "<MO")
    frames: list[MotionReplyFrame] = []
    values: tuple[int, ...] = (0,) * JOINT_COUNT
    for position, item in enumerate(_as_list(_require(entry, "frames", "<MO"), "<MO frames")):
        where = f"<MO frame {position}"
        frame = _lowered(_as_mapping(item, where))
        values = _apply_outputs(frame.get("outputs", []), values, where)
        frames.append(
            MotionReplyFrame(
                index=_as_int(frame.get("@index", position), f"{where} @index"),
                transition_time_ms=_as_int(
                    _require(frame, "transition_time_ms", where), f"{where} transition_time_ms"
                ),
                offsets_ddeg=values,
            )
        )
    declared = entry.get("@frame_length")
    if declared is not None and _as_int(declared, "<MO @frame_length") != len(frames):
        raise LocalProtocolError(f"<MO @frame_length is {declared} but {len(frames)} frames follow")
    return MotionReply(slot=slot, name=name, frames=tuple(frames), loop=loop, jump=jump)


def _version_reply_from_json(obj: Mapping[str, object]) -> VersionReply:
    entry = _lowered(obj)
    return VersionReply(
        device=_as_str(_require(entry, "device", "<VI"), "<VI device"),
        codename=_as_str(_require(entry, "codename", "<VI"), "<VI codename"),
        version=_as_str(_require(entry, "version", "<VI"), "<VI version"),
    )


def reply_from_json(value: object) -> Reply:
    """Turn a parsed JSON reply into its message, inferring the type from the shape.

    An array is the ``<JS`` reply (entries with or without ``@device``); an object with
    ``slot`` or ``frames`` is ``<MO``; an object with ``version`` is ``<VI``. Keys are matched
    case-insensitively, and the older ``func``/``args`` code keys are accepted too.

    Raises:
        LocalProtocolError: ``value`` is not a valid reply.
    """
    if isinstance(value, list):
        return _joint_settings_from_json(value)
    if isinstance(value, Mapping):
        keys = _lowered(value)
        if "slot" in keys or "frames" in keys:
            return _motion_reply_from_json(value)
        if "version" in keys:
            return _version_reply_from_json(value)
    raise LocalProtocolError(f"not a PLEN2 reply: {value!r:.80}")


def motion_from_json(obj: Mapping[str, object]) -> tuple[MotionHeader, list[MotionFrame]]:
    """Convert a motion file (plen-ControlServer's motion JSON) to ``>MH`` + ``>MF`` commands.

    The file: ``{"slot", "name", "codes": [{"method": "loop"|"jump", "arguments": [...]}],
    "frames": [{"transition_time_ms", "outputs": [{"device": <joint name>, "value": <offset,
    tenths of a degree>}]}]}``. As in plen-ControlServer, a joint a frame leaves out keeps the
    previous frame's value (0 before the first frame), and the frame count is taken from
    ``frames`` (``@frame_length``, ``@index``, ``@metadata``, ``stop_flag`` and
    ``auto_balance`` are ignored). Integer device ids are accepted as well as names, and
    trailing spaces of the name are dropped (they are padding on the wire).

    Args:
        obj: The parsed JSON object.

    Returns:
        The header and the frames, in index order.

    Raises:
        LocalProtocolError: The motion is malformed or out of range.
    """
    entry = _as_mapping(obj, "motion")
    slot = _as_int(_require(entry, "slot", "motion"), "motion slot")
    name = _as_str(entry.get("name", ""), "motion name").rstrip(" ")
    loop, jump = _codes(entry.get("codes", []), "motion")
    frame_items = _as_list(_require(entry, "frames", "motion"), "motion frames")
    header = MotionHeader(
        slot=slot,
        name=name,
        frame_length=len(frame_items),
        use_loop=loop is not None,
        loop_begin=loop.begin if loop else 0,
        loop_end=loop.end if loop else 0,
        loop_count=loop.count if loop else 0,
        use_jump=jump is not None,
        jump_slot=jump.slot if jump else 0,
    )
    frames: list[MotionFrame] = []
    values: tuple[int, ...] = (0,) * JOINT_COUNT
    for index, item in enumerate(frame_items):
        where = f"motion frame {index}"
        frame = _as_mapping(item, where)
        values = _apply_outputs(frame.get("outputs", []), values, where)
        time_ms = _as_int(
            _require(frame, "transition_time_ms", where), f"{where} transition_time_ms"
        )
        frames.append(MotionFrame(slot, index, time_ms, values))
    return header, frames


def motion_to_json(header: MotionHeader, frames: Sequence[MotionFrame]) -> dict[str, object]:
    """Convert ``>MH`` + ``>MF`` commands to the motion file format.

    Every frame lists all 18 joints by name. An unused joint id (9–11, 21–23), which the file
    format cannot name, is listed by its integer id in the frames where its value changes
    (values carry over, starting at 0).

    Args:
        header: The motion header.
        frames: Its frames, in index order.

    Returns:
        A JSON-ready dict that :func:`motion_from_json` turns back into the same commands.

    Raises:
        LocalProtocolError: The frames do not match the header.
    """
    if len(frames) != header.frame_length:
        raise LocalProtocolError(f"header says {header.frame_length} frames, got {len(frames)}")
    codes: list[dict[str, object]] = []
    if header.use_loop:
        arguments = [header.loop_begin, header.loop_end, header.loop_count]
        codes.append({"method": "loop", "arguments": arguments})
    if header.use_jump:
        codes.append({"method": "jump", "arguments": [header.jump_slot]})
    frame_objs: list[dict[str, object]] = []
    previous: tuple[int, ...] = (0,) * JOINT_COUNT
    for index, frame in enumerate(frames):
        if frame.slot != header.slot or frame.index != index:
            raise LocalProtocolError(
                f"frame {index} must have slot {header.slot} and index {index}"
            )
        outputs: list[dict[str, object]] = []
        for joint, value in enumerate(frame.offsets_ddeg):
            if joint in JOINT_NAMES:
                outputs.append({"device": JOINT_NAMES[joint], "value": value})
            elif value != previous[joint]:
                outputs.append({"device": joint, "value": value})
        previous = frame.offsets_ddeg
        frame_objs.append(
            {"@index": index, "transition_time_ms": frame.transition_time_ms, "outputs": outputs}
        )
    return {
        "slot": header.slot,
        "name": header.name,
        "@frame_length": header.frame_length,
        "codes": codes,
        "frames": frame_objs,
    }


# --------------------------------------------------------------------------------------------
# Decoding commands (device side)
# --------------------------------------------------------------------------------------------


class _BadArgumentError(Exception):
    """An argument field the firmware would not read as intended."""


def _parse_set_angle(args: bytes) -> Command:
    angle = _clamp(_signed12(args[2:5]), ANGLE_MIN_DDEG, ANGLE_MAX_DDEG)
    return SetAngle(_unsigned(args[0:2]), angle)


def _parse_set_angle_diff(args: bytes) -> Command:
    diff = _clamp(_signed12(args[2:5]), -DIFF_LIMIT_DDEG, DIFF_LIMIT_DDEG)
    return SetAngleDiff(_unsigned(args[0:2]), diff)


def _parse_motion_header(args: bytes) -> Command:
    def number(start: int) -> int:
        field = args[start : start + 2]
        if not _is_hex(field):
            raise _BadArgumentError(f"non-hex characters {field!r} in >MH")
        return _unsigned(field)

    def flag(position: int) -> bool:
        return args[position] != ord("0")  # the firmware reads anything but '0' as set

    raw_name = args[2:22]
    if any(not 0x20 <= byte <= 0x7E or byte in b'"\\' for byte in raw_name):
        raise _BadArgumentError(f"motion name {raw_name!r} holds characters a name cannot hold")
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
    values = tuple(_signed16(args[start : start + 4]) for start in range(8, 104, 4))
    return MotionFrame(_unsigned(args[0:2]), _unsigned(args[2:4]), _unsigned(args[4:8]), values)


@dataclass(frozen=True, slots=True)
class _CommandSpec:
    name: str
    argc: int
    parse: Callable[[bytes], Command]
    free_text: bool = False


def _joint_value(factory: Callable[[int, int], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory(_unsigned(args[0:2]), _signed12(args[2:5]))


def _slot(factory: Callable[[int], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory(_unsigned(args[0:2]))


def _bare(factory: Callable[[], Command]) -> Callable[[bytes], Command]:
    return lambda args: factory()


_COMMANDS: dict[tuple[int, bytes], _CommandSpec] = {
    (ord(header), name.encode("ascii")): _CommandSpec(header + name, argc, parse, free)
    for header, name, argc, parse, free in (
        ("$", "AD", 5, _parse_set_angle_diff, False),
        ("$", "AN", 5, _parse_set_angle, False),
        ("$", "HP", 0, _bare(HomePosition), False),
        ("$", "MP", 2, _slot(PlayMotion), False),
        ("$", "MS", 0, _bare(StopMotion), False),
        ("$", "PM", 2, _slot(PlayMotion), False),
        ("$", "SM", 0, _bare(StopMotion), False),
        ("#", "PO", 0, _bare(PopMotion), False),
        ("#", "PU", 4, lambda a: PushMotion(_unsigned(a[0:2]), _unsigned(a[2:4])), False),
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

_DEVICE_START = re.compile(rb"[$#<>\r\n]")
_CRLF = b"\r\n"

# Host-side scanning of JSON replies.
_HOST_START = re.compile(rb"[ \t\r\n{\[]")
_NOT_SPACE = re.compile(rb"[^ \t\r\n]")
_STRUCTURE = re.compile(rb'["{}\[\]]')
_STRING_SPECIAL = re.compile(rb'["\\]')
_OPENERS = b"{["
_SPACE = b" \t\r\n"

_INCOMPLETE = -1
_TOO_DEEP = -2


def _reject_constant(name: str) -> object:
    raise ValueError(f"{name} is not JSON")


# --------------------------------------------------------------------------------------------
# The codec
# --------------------------------------------------------------------------------------------


class PlenCodec:
    """PLEN2 codec for one side of the link (sans-IO).

    ``Role.HOST`` encodes commands and decodes the three JSON replies; ``Role.DEVICE`` decodes
    commands (mirroring the firmware's parser) and encodes replies. See the module docstring
    for the fault kinds.

    Attributes:
        role: The side this codec speaks for.
        stats: Counts of decoded messages and faults.
        max_reply_bytes: Longest reply the host accepts, in bytes.
    """

    def __init__(self, role: Role, *, max_reply_bytes: int = DEFAULT_MAX_REPLY_BYTES) -> None:
        """Create a codec.

        Args:
            role: ``Role.HOST`` or ``Role.DEVICE``.
            max_reply_bytes: Longest reply the host accepts, in bytes (at least 2).

        Raises:
            ValueError: ``max_reply_bytes`` is below 2.
        """
        if max_reply_bytes < 2:
            raise ValueError(f"max_reply_bytes must be at least 2, not {max_reply_bytes}")
        self.role = role
        self.stats = CodecStats()
        self.max_reply_bytes = max_reply_bytes
        self._buffer = bytearray()
        # A run of garbage bytes waiting for its end (both roles).
        self._junk_count = 0
        self._junk_sample = bytearray()
        # Device: the command being read (header, command, arguments so far).
        self._attempt = bytearray()
        self._spec: _CommandSpec | None = None
        # Host: where the reply at the start of the buffer has been scanned to.
        self._in_reply = False
        self._skipping = False
        self._scan_pos = 0
        self._depth = 0
        self._in_string = False
        self._escape = False

    # ---------------------------------------------------------------------------- the verbs

    def send(self, message: object) -> bytes:
        """Encode ``message`` for the wire.

        The host sends commands (see :func:`encode_command`), the device sends replies (see
        :func:`encode_reply`).

        Raises:
            LocalProtocolError: ``message`` is not something this role sends.
        """
        if self.role is Role.HOST:
            if isinstance(message, (JointSettingsReply, MotionReply, VersionReply)):
                raise LocalProtocolError(f"the host does not send replies: {message!r}")
            return encode_command(message)
        return encode_reply(message)

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire; :meth:`next_message` decodes them.

        Once :meth:`next_message` has returned ``None``, at most one partial command (107
        bytes) or one partial reply (``max_reply_bytes``) stays buffered.
        """
        self._buffer += data

    def next_message(self) -> PlenMessage | None:
        """Return the next decoded message, or ``None`` if more bytes are needed.

        Raises:
            RemoteProtocolError: A bad command, reply or run of garbage was consumed; call
                again to continue after it.
        """
        if self.role is Role.HOST:
            return self._next_reply()
        return self._next_command()

    # ------------------------------------------------------------------- for the driver

    def pending_bytes(self) -> int:
        """Bytes received but not yet decoded or discarded (a partial command or reply)."""
        return len(self._buffer) + len(self._attempt)

    @property
    def in_progress(self) -> bool:
        """Whether a command (device) or reply (host) has started but not yet ended."""
        return bool(self._attempt) or self._in_reply or self._skipping

    def reset(self) -> int:
        """Abandon everything buffered: a partial reply the device will never finish, or a
        partial command.

        Abandoned bytes are counted as one ``"abandoned"`` fault, a pending run of garbage as
        one ``"garbage"`` fault; nothing is raised.

        Returns:
            The number of bytes discarded.
        """
        dropped = len(self._buffer) + len(self._attempt)
        if dropped:
            self.stats.fault("abandoned", dropped)
        junk = self._junk_count
        if junk:
            self.stats.fault("garbage", junk)
        self._buffer.clear()
        self._junk_count = 0
        self._junk_sample.clear()
        self._attempt.clear()
        self._spec = None
        self._end_reply()
        return dropped + junk

    # ------------------------------------------------------------------------- helpers

    def _fault(self, kind: str, message: str, data: bytes, dropped: int) -> NoReturn:
        self.stats.fault(kind, dropped)
        raise RemoteProtocolError(message, kind=kind, data=data)

    def _take_junk(self, count: int) -> None:
        """Discard ``count`` garbage bytes from the front of the buffer into the pending run."""
        room = FAULT_SAMPLE_BYTES - len(self._junk_sample)
        if room > 0:
            self._junk_sample += self._buffer[: min(room, count)]
        self._junk_count += count
        del self._buffer[:count]

    def _raise_junk(self) -> NoReturn:
        count = self._junk_count
        sample = bytes(self._junk_sample)
        self._junk_count = 0
        self._junk_sample.clear()
        self._fault("garbage", f"{count} stray byte(s) between messages", sample, count)

    # -------------------------------------------------------------------- device side

    def _next_command(self) -> Command | None:
        buffer = self._buffer
        attempt = self._attempt
        while True:
            if not attempt:
                # READY: look for a header character; drop CR/LF silently.
                if not buffer:
                    return None
                match = _DEVICE_START.search(buffer)
                end = match.start() if match else len(buffer)
                if end:
                    self._take_junk(end)
                if not buffer:
                    return None
                if self._junk_count:
                    self._raise_junk()
                byte = buffer[0]
                del buffer[0]
                if byte not in _CRLF:
                    attempt.append(byte)
                continue
            spec = self._spec
            if spec is None:
                # COMMAND: two characters, then match them.
                take = min(3 - len(attempt), len(buffer))
                attempt += buffer[:take]
                del buffer[:take]
                if len(attempt) < 3:
                    return None
                spec = _COMMANDS.get((attempt[0], bytes(attempt[1:3]).upper()))
                if spec is None:
                    self._fail("bad_command", f"unknown command {bytes(attempt)!r}")
                self._spec = spec
                if spec.argc == 0:
                    return self._finish(spec)
                continue
            # ARGUMENTS: read them all, then check them.
            take = min(3 + spec.argc - len(attempt), len(buffer))
            attempt += buffer[:take]
            del buffer[:take]
            if len(attempt) < 3 + spec.argc:
                return None
            return self._finish(spec)

    def _fail(self, kind: str, message: str) -> NoReturn:
        data = bytes(self._attempt)
        self._attempt.clear()
        self._spec = None
        self._fault(kind, message, data, len(data))

    def _finish(self, spec: _CommandSpec) -> Command:
        args = bytes(self._attempt[3:])
        if not spec.free_text and not _is_hex(args):
            self._fail("bad_argument", f"{spec.name} arguments {args!r} are not hex digits")
        try:
            command = spec.parse(args)
        except _BadArgumentError as exc:
            self._fail("bad_argument", f"{spec.name}: {exc}")
        except LocalProtocolError as exc:
            self._fail("out_of_range", f"{spec.name}: {exc}")
        self._attempt.clear()
        self._spec = None
        self.stats.messages += 1
        return command

    # ---------------------------------------------------------------------- host side

    def _end_reply(self) -> None:
        self._in_reply = False
        self._skipping = False
        self._scan_pos = 0
        self._depth = 0
        self._in_string = False
        self._escape = False

    def _scan(self, limit: int, check_depth: bool) -> int:
        """Scan the buffer up to ``limit`` bytes, tracking brackets outside strings.

        Returns:
            The end (exclusive) of the value when its brackets balance, ``_INCOMPLETE``, or
            ``_TOO_DEEP`` (``_scan_pos`` is then just past the offending bracket).
        """
        buffer = self._buffer
        stop = min(limit, len(buffer))
        pos = self._scan_pos
        while pos < stop:
            if self._escape:
                self._escape = False
                pos += 1
                continue
            if self._in_string:
                match = _STRING_SPECIAL.search(buffer, pos, stop)
                if match is None:
                    pos = stop
                    break
                pos = match.start()
                if buffer[pos] == ord("\\"):
                    self._escape = True
                else:
                    self._in_string = False
                pos += 1
                continue
            match = _STRUCTURE.search(buffer, pos, stop)
            if match is None:
                pos = stop
                break
            pos = match.start()
            char = buffer[pos]
            pos += 1
            if char == ord('"'):
                self._in_string = True
            elif char in _OPENERS:
                self._depth += 1
                if check_depth and self._depth > _MAX_DEPTH:
                    self._scan_pos = pos
                    return _TOO_DEEP
            else:
                self._depth -= 1
                if self._depth == 0:
                    self._scan_pos = pos
                    return pos
        self._scan_pos = pos
        return _INCOMPLETE

    def _next_reply(self) -> Reply | None:
        buffer = self._buffer
        while True:
            if self._skipping:
                # The rest of an overlong or too deep reply: drop it until it balances.
                end = self._scan(len(buffer), check_depth=False)
                if end == _INCOMPLETE:
                    self.stats.dropped_bytes += len(buffer)
                    buffer.clear()
                    self._scan_pos = 0
                    return None
                self.stats.dropped_bytes += end
                del buffer[:end]
                self._end_reply()
                continue
            if not self._in_reply:
                if not buffer:
                    return None
                match = _HOST_START.search(buffer)
                end = match.start() if match else len(buffer)
                if end:
                    self._take_junk(end)
                if not buffer:
                    return None
                if self._junk_count:
                    self._raise_junk()
                if buffer[0] in _SPACE:
                    match = _NOT_SPACE.search(buffer)
                    del buffer[: match.start() if match else len(buffer)]
                    continue
                self._in_reply = True
            end = self._scan(self.max_reply_bytes, check_depth=True)
            if end == _TOO_DEEP:
                dropped = self._scan_pos
                data = bytes(buffer[:dropped])
                del buffer[:dropped]
                self._scan_pos = 0
                self._in_reply = False
                self._skipping = True
                self._fault("bad_json", f"reply nested deeper than {_MAX_DEPTH}", data, dropped)
            if end == _INCOMPLETE:
                if len(buffer) <= self.max_reply_bytes:
                    return None
                dropped = self.max_reply_bytes
                data = bytes(buffer[:dropped])
                del buffer[:dropped]
                self._scan_pos = 0
                self._in_reply = False
                self._skipping = True
                self._fault("overlong", f"reply longer than {dropped} bytes", data, dropped)
            text = bytes(buffer[:end])
            del buffer[:end]
            self._end_reply()
            return self._parse_reply(text)

    def _parse_reply(self, text: bytes) -> Reply:
        try:
            value = json.loads(text.decode("utf-8"), parse_constant=_reject_constant)
        except (ValueError, RecursionError) as exc:
            self._fault("bad_json", f"reply is not JSON: {exc}", text, len(text))
        try:
            reply = reply_from_json(value)
        except (LookupError, TypeError, ValueError) as exc:
            self._fault("bad_reply", f"JSON is not a PLEN2 reply: {exc}", text, len(text))
        self.stats.messages += 1
        return reply
