"""Property tests for the PLEN2 codec: round trips, chunking, arbitrary bytes."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Role
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.messages import (
    ANGLE_MAX_DDEG,
    ANGLE_MIN_DDEG,
    DIFF_LIMIT_DDEG,
    FRAME_LENGTH_MAX,
    JOINT_COUNT,
    NAME_LENGTH,
    SLOT_COUNT,
    TRANSITION_MAX_MS,
    TRANSITION_MIN_MS,
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
)
from roboscript.drivers.plen.motionfile import motion_from_json, motion_to_json
from roboscript.errors import RemoteProtocolError

EXAMPLES = 200
LONGEST_COMMAND = 3 + 104

Outcome = list[PlenMessage | tuple[str, bytes]]

joints = st.integers(0, JOINT_COUNT - 1)
angles = st.integers(ANGLE_MIN_DDEG, ANGLE_MAX_DDEG)
slots = st.integers(0, SLOT_COUNT - 1)
frame_indices = st.integers(0, FRAME_LENGTH_MAX - 1)
bytes8 = st.integers(0, 255)
int16 = st.integers(-32768, 32767)
offsets = st.tuples(*[int16] * JOINT_COUNT)
names = st.text(
    st.characters(min_codepoint=0x20, max_codepoint=0x7E, exclude_characters='"\\'),
    max_size=NAME_LENGTH,
).map(lambda name: name.rstrip(" "))

commands: st.SearchStrategy[Command] = st.one_of(
    st.builds(SetAngle, joints, angles),
    st.builds(SetAngleDiff, joints, st.integers(-DIFF_LIMIT_DDEG, DIFF_LIMIT_DDEG)),
    st.builds(PlayMotion, slots),
    st.just(StopMotion()),
    st.just(HomePosition()),
    st.builds(PushMotion, slots, bytes8),
    st.just(PopMotion()),
    st.just(ResetInterpreter()),
    st.builds(SetHome, joints, angles),
    st.builds(SetMax, joints, angles),
    st.builds(SetMin, joints, angles),
    st.just(ResetJointSettings()),
    st.builds(
        MotionHeader,
        slot=slots,
        name=names,
        frame_length=st.integers(1, FRAME_LENGTH_MAX),
        use_loop=st.booleans(),
        loop_begin=frame_indices,
        loop_end=frame_indices,
        loop_count=bytes8,
        use_jump=st.booleans(),
        jump_slot=slots,
        use_extra=st.booleans(),
    ),
    st.builds(
        MotionFrame,
        slots,
        frame_indices,
        st.integers(TRANSITION_MIN_MS, TRANSITION_MAX_MS),
        offsets,
    ),
    st.just(GetJointSettings()),
    st.builds(GetMotion, slots),
    st.just(GetVersion()),
)

any_text = st.text(max_size=12)
joint_settings = st.lists(
    st.tuples(int16, int16, int16), min_size=JOINT_COUNT, max_size=JOINT_COUNT
).map(
    lambda rows: JointSettingsReply(
        tuple(JointSetting(joint, *row) for joint, row in enumerate(rows))
    )
)
motion_frames = st.lists(st.tuples(st.integers(0, TRANSITION_MAX_MS), offsets), max_size=3).map(
    lambda rows: tuple(MotionReplyFrame(index, *row) for index, row in enumerate(rows))
)
replies: st.SearchStrategy[Reply] = st.one_of(
    st.builds(VersionReply, any_text, any_text, any_text),
    joint_settings,
    st.builds(
        MotionReply,
        slot=slots,
        name=st.text(max_size=NAME_LENGTH).map(lambda name: name.rstrip(" ")),
        frames=motion_frames,
        loop=st.none() | st.builds(LoopCode, bytes8, bytes8, bytes8),
        jump=st.none() | st.builds(JumpCode, bytes8),
    ),
)


def chunked(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({min(cut, len(data)) for cut in cuts})
    pieces = []
    start = 0
    for point in [*points, len(data)]:
        pieces.append(data[start:point])
        start = point
    return pieces


def feed(codec: PlenCodec, chunks: list[bytes], bound: int) -> Outcome:
    """Feed and drain chunk by chunk; only RemoteProtocolError may come out."""
    out: Outcome = []
    for chunk in chunks:
        codec.receive_data(chunk)
        while True:
            try:
                message = codec.next_message()
            except RemoteProtocolError as fault:
                out.append((fault.kind, fault.data))
                continue
            if message is None:
                break
            out.append(message)
        assert codec.pending_bytes() <= bound
    return out


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.lists(commands, max_size=8), st.lists(st.integers(0, 2000), max_size=10))
def test_commands_round_trip_in_any_chunks(batch: list[Command], cuts: list[int]) -> None:
    host = PlenCodec(Role.HOST)
    wire = b"".join(host.send(command) for command in batch)
    device = PlenCodec(Role.DEVICE)
    assert feed(device, chunked(wire, cuts), LONGEST_COMMAND) == batch
    assert device.stats.messages == len(batch)
    assert not device.stats.faults
    assert device.pending_bytes() == 0


@settings(max_examples=EXAMPLES, deadline=None)
@given(
    st.lists(replies, max_size=3),
    st.lists(st.sampled_from([b"", b"\r\n", b" ", b"\t\r\n"]), min_size=3, max_size=3),
    st.lists(st.integers(0, 20_000), max_size=10),
)
def test_replies_round_trip_in_any_chunks(
    batch: list[Reply], gaps: list[bytes], cuts: list[int]
) -> None:
    device = PlenCodec(Role.DEVICE)
    wire = b"".join(device.send(reply) + gap for reply, gap in zip(batch, gaps, strict=False))
    host = PlenCodec(Role.HOST)
    assert feed(host, chunked(wire, cuts), host.max_reply_bytes) == batch
    assert not host.stats.faults
    assert host.pending_bytes() == 0


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.binary(max_size=400), st.lists(st.integers(0, 400), max_size=8))
def test_device_survives_arbitrary_bytes(data: bytes, cuts: list[int]) -> None:
    whole = feed(PlenCodec(Role.DEVICE), [data], LONGEST_COMMAND)
    pieces = feed(PlenCodec(Role.DEVICE), chunked(data, cuts), LONGEST_COMMAND)
    assert pieces == whole


# Bytes that look like commands, so that arbitrary data reaches every parser state.
command_soup = st.lists(
    st.sampled_from([b"$", b"#", b">", b"<", b"an", b"MH", b"mf", b"pu", b"0a", b"f", b"\r\n"])
    | st.binary(max_size=4),
    max_size=60,
).map(b"".join)


@settings(max_examples=EXAMPLES, deadline=None)
@given(command_soup, st.lists(st.integers(0, 300), max_size=8))
def test_device_survives_command_like_bytes(data: bytes, cuts: list[int]) -> None:
    codec = PlenCodec(Role.DEVICE)
    whole = feed(codec, [data], LONGEST_COMMAND)
    assert feed(PlenCodec(Role.DEVICE), chunked(data, cuts), LONGEST_COMMAND) == whole
    faults = [item for item in whole if isinstance(item, tuple)]
    assert codec.stats.messages == len(whole) - len(faults)
    assert sum(codec.stats.faults.values()) == len(faults)
    assert codec.stats.dropped_bytes == sum(len(data) for _, data in faults)


json_soup = st.lists(
    st.sampled_from([b"{", b"}", b"[", b"]", b'"', b"\\", b",", b":", b"\r\n", b"\t", b"1"])
    | st.sampled_from([b'"device"', b'"version"', b'"slot"', b'"frames"', b'"PLEN2"'])
    | st.binary(max_size=3),
    max_size=80,
).map(b"".join)


@settings(max_examples=EXAMPLES, deadline=None)
@given(json_soup | st.binary(max_size=300), st.lists(st.integers(0, 300), max_size=8))
def test_host_survives_arbitrary_bytes(data: bytes, cuts: list[int]) -> None:
    limit = 64
    whole = feed(PlenCodec(Role.HOST, max_reply_bytes=limit), [data], limit)
    pieces = feed(PlenCodec(Role.HOST, max_reply_bytes=limit), chunked(data, cuts), limit)
    assert pieces == whole


@settings(max_examples=EXAMPLES, deadline=None)
@given(
    slots,
    names,
    st.lists(
        st.tuples(st.integers(TRANSITION_MIN_MS, TRANSITION_MAX_MS), offsets),
        min_size=1,
        max_size=4,
    ),
)
def test_motion_json_round_trip(
    slot: int, name: str, rows: list[tuple[int, tuple[int, ...]]]
) -> None:
    header = MotionHeader(slot, name, len(rows))
    frames = [MotionFrame(slot, index, *row) for index, row in enumerate(rows)]
    assert motion_from_json(motion_to_json(header, frames)) == (header, frames)
