"""PLEN2 motion files (plen-ControlServer's motion JSON) to and from ``>MH`` + ``>MF`` commands.

Motion files are not on the wire: roboscript's gait motions are stored in this format
(:mod:`roboscript.drivers.plen.gaits`) and installed with the commands they turn into.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from roboscript.drivers.plen.jsonfields import (
    apply_outputs,
    as_int,
    as_list,
    as_mapping,
    as_str,
    read_codes,
    require,
)
from roboscript.drivers.plen.messages import (
    JOINT_COUNT,
    JOINT_NAMES,
    MotionFrame,
    MotionHeader,
)
from roboscript.errors import LocalProtocolError

__all__ = ["motion_from_json", "motion_to_json"]


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
    entry = as_mapping(obj, "motion")
    slot = as_int(require(entry, "slot", "motion"), "motion slot")
    name = as_str(entry.get("name", ""), "motion name").rstrip(" ")
    loop, jump = read_codes(entry.get("codes", []), "motion")
    frame_items = as_list(require(entry, "frames", "motion"), "motion frames")
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
        frame = as_mapping(item, where)
        values = apply_outputs(frame.get("outputs", []), values, where)
        time_ms = as_int(require(frame, "transition_time_ms", where), f"{where} transition_time_ms")
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
