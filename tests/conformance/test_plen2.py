"""PLEN2 motion installs, pinned to what plen-ControlServer (the official host) sends.

The expected bytes are built here from the official host's rules, written out piece by piece,
never from roboscript's own encoder, so the encoder and the simulated PLEN2 cannot agree on a
layout the robot's firmware does not use.
"""

from __future__ import annotations

from typing import Any

import pytest

from roboscript.drivers.plen.commands import encode_command
from roboscript.drivers.plen.motionfile import motion_from_json


def _install(motion: dict[str, Any]) -> bytes:
    header, frames = motion_from_json(motion)
    return b"".join(encode_command(command) for command in (header, *frames))


def _frame(slot: int, index: int, time_ms: int, values: dict[int, int]) -> str:
    """One ``>MF``: slot, index, time, then all 24 joint values as 16-bit two's complement."""
    joints = "".join(f"{values.get(joint, 0) & 0xFFFF:04x}" for joint in range(24))
    return f">MF{slot:02x}{index:02x}{time_ms:04x}{joints}"


WAVE: dict[str, Any] = {
    "slot": 5,
    "name": "wave",
    "codes": [{"method": "loop", "arguments": [0, 1, 3]}],
    "frames": [
        {
            "transition_time_ms": 300,
            "outputs": [
                {"device": "left_shoulder_pitch", "value": -300},
                {"device": "right_elbow_roll", "value": 150},
            ],
        },
        {"transition_time_ms": 200, "outputs": [{"device": "left_thigh_yaw", "value": 25}]},
    ],
}


def test_an_install_is_a_header_then_one_frame_command_per_frame() -> None:
    """The official host sends ``>MH`` (slot, name padded to 20 with spaces, loop code
    ``1`` + begin/end/count, jump code ``000`` when unused, one extra digit, frame count), then
    one ``>MF`` per frame with every joint's value in the device-map order (left joints 0-8,
    right joints 12-20), negative angles as 16-bit two's complement, lower-case hex."""
    header = ">MH05" + "wave".ljust(20) + "1000103" + "000" + "0" + "02"
    first = _frame(5, 0, 300, {0: -300, 15: 150})
    assert first.startswith(">MF0500012cfed4")
    expected = header + first + _frame(5, 1, 200, {0: -300, 1: 25, 15: 150})

    assert _install(WAVE) == expected.encode("ascii")


def test_a_joint_a_frame_leaves_out_keeps_its_last_value() -> None:
    """The official host keeps one 24-value table while it encodes a motion: a frame that names
    only some joints sends the others as the previous frame left them, not as zero."""
    second = _install(WAVE).split(b">MF")[2]
    joints = second[8:]
    assert joints[0:4] == b"fed4"  # left_shoulder_pitch from frame 0
    assert joints[4:8] == b"0019"  # left_thigh_yaw set here
    assert joints[60:64] == b"0096"  # right_elbow_roll from frame 0


def test_a_jump_code_and_a_full_length_name() -> None:
    """A 20-character name fills the header's name field exactly; a jump writes ``1`` and the
    target slot in the three characters after the loop code."""
    motion = {
        "slot": 0x2A,
        "name": "a name of twenty chr",
        "codes": [{"method": "jump", "arguments": [7]}],
        "frames": [{"transition_time_ms": 100, "outputs": []}],
    }
    header = ">MH2a" + "a name of twenty chr" + "0000000" + "107" + "0" + "01"
    assert _install(motion) == (header + _frame(0x2A, 0, 100, {})).encode("ascii")


@pytest.mark.parametrize("value", [-1, -900, 900])
def test_joint_values_use_sixteen_bit_twos_complement(value: int) -> None:
    """Angles in tenths of a degree go out as ``c_ushort(value)``: -1 is ``ffff``."""
    motion = {
        "slot": 1,
        "name": "x",
        "codes": [],
        "frames": [
            {"transition_time_ms": 32, "outputs": [{"device": "right_foot_roll", "value": value}]}
        ],
    }
    joints = _install(motion).split(b">MF")[1][8:]
    assert joints[80:84] == f"{value & 0xFFFF:04x}".encode("ascii")


@pytest.mark.parametrize(
    ("field", "value"),
    [("name", "twenty-one characters"), ("transition_time_ms", 31), ("slot", 90)],
)
def test_what_the_official_validator_refuses_is_refused(field: str, value: object) -> None:
    """plen-ControlServer validates a motion before it installs one: a name of at most 20
    characters, transitions of 32-65535 ms, slots 0-89. A motion it would refuse never reaches
    the wire from roboscript either (a clear error instead of a cut name or a wrapped time)."""
    motion: dict[str, Any] = {**WAVE, "frames": [dict(frame) for frame in WAVE["frames"]]}
    if field == "transition_time_ms":
        motion["frames"][0]["transition_time_ms"] = value
    else:
        motion[field] = value
    with pytest.raises(ValueError, match=field):
        _install(motion)
