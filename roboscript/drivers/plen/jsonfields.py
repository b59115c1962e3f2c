"""Checked readers of the JSON values PLEN2 speaks: ``<MO``/``<JS``/``<VI`` dumps and motion files.

Each reader raises :class:`~roboscript.errors.LocalProtocolError` naming where in the value
the problem is (``<MO frame 3 outputs[2] value must be an integer``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from roboscript.drivers.plen.messages import (
    JOINT_COUNT,
    JumpCode,
    LoopCode,
    joint_id,
)
from roboscript.errors import LocalProtocolError

__all__ = [
    "apply_outputs",
    "as_int",
    "as_list",
    "as_mapping",
    "as_str",
    "first",
    "lowered",
    "read_codes",
    "require",
]


def lowered(obj: Mapping[str, object]) -> dict[str, object]:
    return {key.lower(): value for key, value in obj.items()}


def as_mapping(value: object, where: str) -> Mapping[str, object]:
    if not isinstance(value, Mapping):
        raise LocalProtocolError(f"{where} must be a JSON object, not {value!r}")
    return value


def as_list(value: object, where: str) -> list[object]:
    if not isinstance(value, list):
        raise LocalProtocolError(f"{where} must be a JSON array, not {value!r}")
    return value


def as_int(value: object, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise LocalProtocolError(f"{where} must be an integer, not {value!r}")
    return value


def as_str(value: object, where: str) -> str:
    if not isinstance(value, str):
        raise LocalProtocolError(f"{where} must be a string, not {value!r}")
    return value


def require(obj: Mapping[str, object], key: str, where: str) -> object:
    if key not in obj:
        raise LocalProtocolError(f"{where} lacks {key!r}")
    return obj[key]


def first(obj: Mapping[str, object], keys: Sequence[str], where: str) -> object:
    for key in keys:
        if key in obj:
            return obj[key]
    raise LocalProtocolError(f"{where} lacks {keys[0]!r}")


def apply_outputs(outputs: object, previous: Sequence[int], where: str) -> tuple[int, ...]:
    """Apply a frame's ``outputs`` to the previous frame's values (joints left out carry over).

    A ``device`` may be a joint name (motion file) or an integer id (``<MO`` dump).
    """
    values = list(previous)
    for position, output in enumerate(as_list(outputs, f"{where} outputs")):
        entry = as_mapping(output, f"{where} outputs[{position}]")
        device = require(entry, "device", f"{where} outputs[{position}]")
        if isinstance(device, str):
            joint = joint_id(device)
        else:
            joint = as_int(device, f"{where} outputs[{position}] device")
            if not 0 <= joint < JOINT_COUNT:
                raise LocalProtocolError(f"{where} outputs[{position}]: no joint id {joint}")
        values[joint] = as_int(
            require(entry, "value", f"{where} outputs[{position}]"),
            f"{where} outputs[{position}] value",
        )
    return tuple(values)


def read_codes(codes: object, where: str) -> tuple[LoopCode | None, JumpCode | None]:
    """Read ``codes``: ``{"method"|"func": "loop"|"jump", "arguments"|"args": [...]}``."""
    loop: LoopCode | None = None
    jump: JumpCode | None = None
    for position, code in enumerate(as_list(codes, f"{where} codes")):
        entry = lowered(as_mapping(code, f"{where} codes[{position}]"))
        method = first(entry, ("method", "func"), f"{where} codes[{position}]")
        arguments = as_list(
            first(entry, ("arguments", "args"), f"{where} codes[{position}]"),
            f"{where} codes[{position}] arguments",
        )
        numbers = [as_int(value, f"{where} codes[{position}] arguments") for value in arguments]
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
