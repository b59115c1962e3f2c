"""PLEN2 message types: joint table, factory values and host-side range checks."""

from __future__ import annotations

import pytest

from roboscript.drivers.plen.messages import (
    FACTORY_HOME_DDEG,
    JOINT_COUNT,
    JOINT_IDS,
    JOINT_NAMES,
    GetMotion,
    JointSetting,
    JointSettingsReply,
    JumpCode,
    LoopCode,
    MotionFrame,
    MotionHeader,
    MotionReply,
    MotionReplyFrame,
    PlayMotion,
    PushMotion,
    SetAngle,
    SetAngleDiff,
    SetHome,
    SetMax,
    SetMin,
    VersionReply,
    factory_joint_settings,
    joint_id,
)
from roboscript.errors import LocalProtocolError

ZEROS = (0,) * JOINT_COUNT


def test_joint_table_has_the_18_wired_joints() -> None:
    assert len(JOINT_NAMES) == 18
    assert set(JOINT_NAMES) == set(range(9)) | set(range(12, 21))
    assert JOINT_NAMES[0] == "left_shoulder_pitch"
    assert JOINT_NAMES[6] == "left_knee_pitch"
    assert JOINT_NAMES[20] == "right_foot_roll"
    for joint, name in JOINT_NAMES.items():
        assert JOINT_IDS[name] == joint
        assert joint_id(name) == joint
        # Each right joint sits 12 ids after its left twin.
        if name.startswith("left_"):
            assert JOINT_NAMES[joint + 12] == "right_" + name.removeprefix("left_")


def test_unknown_joint_name() -> None:
    with pytest.raises(LocalProtocolError, match="unknown PLEN2 joint"):
        joint_id("left_tail")


def test_factory_home_values() -> None:
    assert len(FACTORY_HOME_DDEG) == JOINT_COUNT
    assert FACTORY_HOME_DDEG[:9] == (-200, 50, 375, 250, -470, -220, 500, 200, 220)
    assert FACTORY_HOME_DDEG[12:21] == (200, -50, -375, -250, 470, 220, -500, -200, -220)
    assert FACTORY_HOME_DDEG[9:12] == (0, 0, 0)
    assert FACTORY_HOME_DDEG[21:] == (0, 0, 0)
    settings = factory_joint_settings()
    assert [entry.home_ddeg for entry in settings.joints] == list(FACTORY_HOME_DDEG)
    assert {(entry.min_ddeg, entry.max_ddeg) for entry in settings.joints} == {(-900, 900)}


@pytest.mark.parametrize("cls", [SetAngle, SetHome, SetMax, SetMin])
def test_absolute_angles_are_limited_to_900(cls: type[SetAngle]) -> None:
    assert cls(0, -900).angle_ddeg == -900
    assert cls(23, 900).joint == 23
    for bad_angle in (-901, 901, 1000):
        with pytest.raises(LocalProtocolError, match="angle_ddeg"):
            cls(0, bad_angle)
    for bad_joint in (-1, 24):
        with pytest.raises(LocalProtocolError, match="joint"):
            cls(bad_joint, 0)


def test_diff_is_limited_to_1800() -> None:
    assert SetAngleDiff(4, -1800).diff_ddeg == -1800
    assert SetAngleDiff(4, 1800).diff_ddeg == 1800
    with pytest.raises(LocalProtocolError):
        SetAngleDiff(4, 1801)


def test_types_are_checked() -> None:
    with pytest.raises(LocalProtocolError, match="must be an int"):
        SetAngle(True, 0)
    with pytest.raises(LocalProtocolError, match="must be an int"):
        SetAngle(0, 1.5)  # type: ignore[arg-type]
    with pytest.raises(LocalProtocolError, match="must be a bool"):
        MotionHeader(0, "x", 1, use_loop=1)  # type: ignore[arg-type]


def test_slots() -> None:
    assert PlayMotion(89).slot == 89
    assert GetMotion(0).slot == 0
    for cls in (PlayMotion, GetMotion):
        with pytest.raises(LocalProtocolError, match="slot"):
            cls(90)


def test_push_motion_count() -> None:
    assert PushMotion(10).play_count == 1
    assert PushMotion(10, 0).play_count == 0  # the firmware's loop-forever
    assert PushMotion(10, 255).play_count == 255
    with pytest.raises(LocalProtocolError):
        PushMotion(10, 256)


def test_motion_header_checks() -> None:
    header = MotionHeader(5, "Walk forward", 4, use_loop=True, loop_begin=1, loop_end=3)
    assert header.loop_count == 0
    assert MotionHeader(0, "x" * 20, 20).frame_length == 20
    assert MotionHeader(0, "", 1).name == ""
    bad: list[dict[str, object]] = [
        {"name": "x" * 21},
        {"name": "caf\u00e9"},
        {"name": 'say "hi"'},
        {"name": "back\\slash"},
        {"name": "tab\there"},
        {"name": "padded "},
        {"frame_length": 0},
        {"frame_length": 21},
        {"loop_begin": 20},
        {"loop_end": 20},
        {"loop_count": 256},
        {"jump_slot": 90},
        {"slot": 90},
    ]
    for change in bad:
        fields: dict[str, object] = {"slot": 0, "name": "x", "frame_length": 2, **change}
        with pytest.raises(LocalProtocolError):
            MotionHeader(**fields)  # type: ignore[arg-type]


def test_motion_frame_checks() -> None:
    frame = MotionFrame(0, 19, 32, [1] * JOINT_COUNT)  # type: ignore[arg-type]
    assert frame.offsets_ddeg == (1,) * JOINT_COUNT  # a list is stored as a tuple
    assert hash(frame) == hash(MotionFrame(0, 19, 32, (1,) * JOINT_COUNT))
    assert MotionFrame(0, 0, 65535, (-32768,) * JOINT_COUNT).transition_time_ms == 65535
    with pytest.raises(LocalProtocolError, match="transition_time_ms"):
        MotionFrame(0, 0, 31, ZEROS)
    with pytest.raises(LocalProtocolError, match="index"):
        MotionFrame(0, 20, 100, ZEROS)
    with pytest.raises(LocalProtocolError, match="24 values"):
        MotionFrame(0, 0, 100, ZEROS[:23])
    with pytest.raises(LocalProtocolError, match="offsets_ddeg"):
        MotionFrame(0, 0, 100, (32768, *ZEROS[1:]))


def test_joint_settings_reply_needs_24_in_order() -> None:
    entries = factory_joint_settings().joints
    with pytest.raises(LocalProtocolError, match="24 entries"):
        JointSettingsReply(entries[:23])
    with pytest.raises(LocalProtocolError, match="joints\\[0\\]"):
        JointSettingsReply((entries[1], entries[0], *entries[2:]))
    assert JointSettingsReply(list(entries)).joints == entries  # type: ignore[arg-type]
    with pytest.raises(LocalProtocolError):
        JointSetting(24, 0, 0, 0)


def test_motion_reply_install_round_trip() -> None:
    header = MotionHeader(
        3, "Bow", 2, use_loop=True, loop_end=1, loop_count=255, use_jump=True, jump_slot=4
    )
    frames = [MotionFrame(3, 0, 100, (5,) * 24), MotionFrame(3, 1, 200, (-5,) * 24)]
    reply = MotionReply.from_install(header, frames)
    assert reply.frame_length == 2
    assert reply.loop == LoopCode(0, 1, 255)
    assert reply.jump == JumpCode(4)
    assert reply.frames[1] == MotionReplyFrame(1, 200, (-5,) * 24)
    assert reply.to_install() == (header, frames)
    with pytest.raises(LocalProtocolError, match="2 frames"):
        MotionReply.from_install(header, frames[:1])
    with pytest.raises(LocalProtocolError, match="index 1"):
        MotionReply.from_install(header, [frames[0], frames[0]])


def test_motion_reply_is_loose_but_to_install_is_strict() -> None:
    reply = MotionReply(7, "odd", (MotionReplyFrame(0, 0, ZEROS),))
    assert reply.loop is None and reply.jump is None
    with pytest.raises(LocalProtocolError, match="transition_time_ms"):
        reply.to_install()
    with pytest.raises(LocalProtocolError, match="frames\\[0\\]"):
        MotionReply(7, "odd", (MotionReplyFrame(1, 100, ZEROS),))


def test_version_reply_defaults() -> None:
    assert VersionReply() == VersionReply("PLEN2", "Cytisus", "1.4.2")
    with pytest.raises(LocalProtocolError):
        VersionReply(version=142)  # type: ignore[arg-type]
