"""PLEN2 replies, firmware 1.4.2: the device writes them, the host reads them.

Only the getters ``<JS``, ``<MO`` and ``<VI`` are answered. Replies are tab-indented JSON
printed line by line with CRLF line endings, and nothing marks their end (the framing is
:class:`~roboscript.drivers.plen.codec.PlenCodec`'s). :func:`encode_reply` prints a reply as the
firmware's ``println()`` dumps do; :func:`reply_from_json` turns a parsed JSON reply into its
message, inferring its type from its shape.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping, Sequence

from roboscript.drivers.plen.jsonfields import (
    apply_outputs,
    as_int,
    as_list,
    as_mapping,
    as_str,
    lowered,
    read_codes,
    require,
)
from roboscript.drivers.plen.messages import (
    JOINT_COUNT,
    NAME_LENGTH,
    JointSetting,
    JointSettingsReply,
    MotionReply,
    MotionReplyFrame,
    Reply,
    VersionReply,
)
from roboscript.errors import LocalProtocolError

__all__ = ["encode_reply", "reply_from_json"]

_EOL = "\r\n"

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
# Decoding replies from JSON values (host side)
# --------------------------------------------------------------------------------------------


def _joint_settings_from_json(items: list[object]) -> JointSettingsReply:
    by_joint: dict[int, JointSetting] = {}
    for position, item in enumerate(items):
        where = f"<JS entry {position}"
        entry = lowered(as_mapping(item, where))
        # 1.4.2 names the joint "@device"; the seed's form has no key and relies on order.
        joint = entry.get("@device", entry.get("device", entry.get("joint", position)))
        setting = JointSetting(
            joint=as_int(joint, f"{where} @device"),
            min_ddeg=as_int(require(entry, "min", where), f"{where} min"),
            max_ddeg=as_int(require(entry, "max", where), f"{where} max"),
            home_ddeg=as_int(require(entry, "home", where), f"{where} home"),
        )
        if setting.joint in by_joint:
            raise LocalProtocolError(f"<JS lists joint {setting.joint} twice")
        by_joint[setting.joint] = setting
    if len(by_joint) != JOINT_COUNT:
        raise LocalProtocolError(f"<JS lists {len(by_joint)} joints, not {JOINT_COUNT}")
    return JointSettingsReply(tuple(by_joint[joint] for joint in range(JOINT_COUNT)))


def _motion_reply_from_json(obj: Mapping[str, object]) -> MotionReply:
    entry = lowered(obj)
    slot = as_int(require(entry, "slot", "<MO"), "<MO slot")
    name = as_str(entry.get("name", ""), "<MO name").rstrip(" ")
    loop, jump = read_codes(entry.get("codes", []), "<MO")
    frames: list[MotionReplyFrame] = []
    values: tuple[int, ...] = (0,) * JOINT_COUNT
    for position, item in enumerate(as_list(require(entry, "frames", "<MO"), "<MO frames")):
        where = f"<MO frame {position}"
        frame = lowered(as_mapping(item, where))
        values = apply_outputs(frame.get("outputs", []), values, where)
        frames.append(
            MotionReplyFrame(
                index=as_int(frame.get("@index", position), f"{where} @index"),
                transition_time_ms=as_int(
                    require(frame, "transition_time_ms", where), f"{where} transition_time_ms"
                ),
                offsets_ddeg=values,
            )
        )
    declared = entry.get("@frame_length")
    if declared is not None and as_int(declared, "<MO @frame_length") != len(frames):
        raise LocalProtocolError(f"<MO @frame_length is {declared} but {len(frames)} frames follow")
    return MotionReply(slot=slot, name=name, frames=tuple(frames), loop=loop, jump=jump)


def _version_reply_from_json(obj: Mapping[str, object]) -> VersionReply:
    entry = lowered(obj)
    return VersionReply(
        device=as_str(require(entry, "device", "<VI"), "<VI device"),
        codename=as_str(require(entry, "codename", "<VI"), "<VI codename"),
        version=as_str(require(entry, "version", "<VI"), "<VI version"),
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
        keys = lowered(value)
        if "slot" in keys or "frames" in keys:
            return _motion_reply_from_json(value)
        if "version" in keys:
            return _version_reply_from_json(value)
    raise LocalProtocolError(f"not a PLEN2 reply: {value!r:.80}")
