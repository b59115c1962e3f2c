"""Tests of the SPIKE Prime hub codec: roles, stream decoding, faults and priorities."""

from __future__ import annotations

import itertools
from collections.abc import Iterable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Codec, Role, drain
from roboscript.drivers.spike import cobs
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.messages import (
    DEVICE_MESSAGE_TYPES,
    MESSAGE_TYPES,
    BeginFirmwareUpdateRequest,
    BeginFirmwareUpdateResponse,
    ClearSlotRequest,
    ClearSlotResponse,
    ConsoleNotification,
    DeviceBattery,
    DeviceColor,
    DeviceDistance,
    DeviceForce,
    DeviceImu,
    DeviceMatrix3x3,
    DeviceMatrix5x5,
    DeviceMessage,
    DeviceMotor,
    DeviceNotification,
    DeviceNotificationRequest,
    DeviceNotificationResponse,
    DeviceUuidRequest,
    DeviceUuidResponse,
    GetHubNameRequest,
    GetHubNameResponse,
    HubFace,
    HubPort,
    InfoRequest,
    InfoResponse,
    Message,
    MessageKind,
    MotorDeviceType,
    ProgramAction,
    ProgramFlowNotification,
    ProgramFlowRequest,
    ProgramFlowResponse,
    ResponseStatus,
    SetHubNameRequest,
    SetHubNameResponse,
    StartFileUploadRequest,
    StartFileUploadResponse,
    StartFirmwareUploadRequest,
    StartFirmwareUploadResponse,
    TransferChunkRequest,
    TransferChunkResponse,
    TunnelMessage,
)
from roboscript.errors import LocalProtocolError, RemoteProtocolError

# ---------------------------------------------------------------------------- strategies

u8 = st.integers(0, 0xFF)
i8 = st.integers(-0x80, 0x7F)
u16 = st.integers(0, 0xFFFF)
i16 = st.integers(-0x8000, 0x7FFF)
u32 = st.integers(0, 0xFFFF_FFFF)
i32 = st.integers(-0x8000_0000, 0x7FFF_FFFF)
slots = st.integers(0, 19)
statuses = st.sampled_from(ResponseStatus)
actions = st.sampled_from(ProgramAction)
ports = st.sampled_from(HubPort)
faces = st.sampled_from(HubFace)
payloads = st.binary(max_size=300)
_chars = st.characters(codec="utf-8", exclude_characters="\x00")


def texts(size: int) -> st.SearchStrategy[str]:
    """Strings that fit a ``string[size]`` field (at most ``size - 1`` bytes of UTF-8)."""
    ascii_text = st.text(st.characters(min_codepoint=1, max_codepoint=0x7F), max_size=size - 1)
    return st.one_of(ascii_text, st.text(_chars, max_size=(size - 1) // 4))


def pixels(count: int) -> st.SearchStrategy[tuple[int, ...]]:
    return st.lists(u8, min_size=count, max_size=count).map(tuple)


DEVICE_STRATEGIES: dict[type[DeviceMessage], st.SearchStrategy[DeviceMessage]] = {
    DeviceBattery: st.builds(DeviceBattery, u8),
    DeviceImu: st.builds(DeviceImu, faces, faces, *([i16] * 9)),
    DeviceMatrix5x5: st.builds(DeviceMatrix5x5, pixels(25)),
    DeviceMotor: st.builds(
        DeviceMotor, ports, st.one_of(st.sampled_from(MotorDeviceType), u8), i16, i16, i8, i32
    ),
    DeviceForce: st.builds(DeviceForce, ports, u8, st.booleans()),
    DeviceColor: st.builds(DeviceColor, ports, i8, u16, u16, u16),
    DeviceDistance: st.builds(DeviceDistance, ports, i16),
    DeviceMatrix3x3: st.builds(DeviceMatrix3x3, ports, pixels(9)),
}
unparsed = st.one_of(
    st.just(b""),
    st.binary(min_size=1, max_size=8).filter(lambda data: data[0] not in DEVICE_MESSAGE_TYPES),
)

MESSAGE_STRATEGIES: dict[type[Message], st.SearchStrategy[Message]] = {
    InfoRequest: st.just(InfoRequest()),
    InfoResponse: st.builds(InfoResponse, u8, u8, u16, u8, u8, u16, u16, u16, u16, u16),
    StartFirmwareUploadRequest: st.builds(
        StartFirmwareUploadRequest, st.binary(min_size=20, max_size=20), u32
    ),
    StartFirmwareUploadResponse: st.builds(StartFirmwareUploadResponse, statuses, u32),
    StartFileUploadRequest: st.builds(StartFileUploadRequest, texts(32), slots, u32),
    StartFileUploadResponse: st.builds(StartFileUploadResponse, statuses),
    TransferChunkRequest: st.builds(TransferChunkRequest, u32, payloads),
    TransferChunkResponse: st.builds(TransferChunkResponse, statuses),
    BeginFirmwareUpdateRequest: st.builds(
        BeginFirmwareUpdateRequest, st.binary(min_size=20, max_size=20), u32
    ),
    BeginFirmwareUpdateResponse: st.builds(BeginFirmwareUpdateResponse, statuses),
    SetHubNameRequest: st.builds(SetHubNameRequest, texts(30)),
    SetHubNameResponse: st.builds(SetHubNameResponse, statuses),
    GetHubNameRequest: st.just(GetHubNameRequest()),
    GetHubNameResponse: st.builds(GetHubNameResponse, texts(30)),
    DeviceUuidRequest: st.just(DeviceUuidRequest()),
    DeviceUuidResponse: st.builds(DeviceUuidResponse, st.binary(min_size=16, max_size=16)),
    ProgramFlowRequest: st.builds(ProgramFlowRequest, actions, slots),
    ProgramFlowResponse: st.builds(ProgramFlowResponse, statuses),
    ProgramFlowNotification: st.builds(ProgramFlowNotification, actions),
    ConsoleNotification: st.builds(ConsoleNotification, texts(256)),
    DeviceNotificationRequest: st.builds(DeviceNotificationRequest, u16),
    DeviceNotificationResponse: st.builds(DeviceNotificationResponse, statuses),
    TunnelMessage: st.builds(TunnelMessage, payloads),
    DeviceNotification: st.builds(
        DeviceNotification,
        st.lists(st.one_of(*DEVICE_STRATEGIES.values()), max_size=12).map(tuple),
        unparsed,
    ),
    ClearSlotRequest: st.builds(ClearSlotRequest, slots),
    ClearSlotResponse: st.builds(ClearSlotResponse, statuses),
}


def _messages(*kinds: MessageKind) -> st.SearchStrategy[Message]:
    return st.one_of(*[s for cls, s in MESSAGE_STRATEGIES.items() if cls.kind in kinds])


host_messages = _messages(MessageKind.REQUEST, MessageKind.TUNNEL)
device_messages = _messages(MessageKind.RESPONSE, MessageKind.NOTIFICATION, MessageKind.TUNNEL)


# ---------------------------------------------------------------------------- helpers


def _codec_pair() -> tuple[SpikeCodec, SpikeCodec]:
    return SpikeCodec(Role.HOST), SpikeCodec(Role.DEVICE)


def _feed(codec: SpikeCodec, *chunks: bytes) -> list[Message | RemoteProtocolError]:
    out: list[Message | RemoteProtocolError] = []
    for chunk in chunks:
        codec.receive_data(chunk)
        out.extend(drain(codec))
    return out


def _kinds(items: Iterable[Message | RemoteProtocolError]) -> list[object]:
    return [item.kind if isinstance(item, RemoteProtocolError) else item for item in items]


def _split(data: bytes, cuts: Iterable[int]) -> list[bytes]:
    points = sorted({min(max(cut, 0), len(data)) for cut in cuts})
    bounds = [0, *points, len(data)]
    return [data[a:b] for a, b in itertools.pairwise(bounds)]


# ---------------------------------------------------------------------------- golden frames

GOLDEN = [
    pytest.param(InfoRequest(), b"\x00\x00\x02", id="InfoRequest"),
    pytest.param(GetHubNameRequest(), b"\x07\x1b\x02", id="GetHubNameRequest"),
    pytest.param(DeviceNotificationRequest(100), b"\x06\x2b\x67\x00\x02", id="DeviceNotif(100)"),
    pytest.param(
        ProgramFlowRequest(ProgramAction.START, 0), b"\x07\x1d\x00\x00\x02", id="ProgramFlow"
    ),
]


@pytest.mark.parametrize(("message", "frame"), GOLDEN)
def test_golden_frames_sent_by_host(message: Message, frame: bytes) -> None:
    assert SpikeCodec(Role.HOST).send(message) == frame


@pytest.mark.parametrize(("message", "frame"), GOLDEN)
def test_golden_frames_received_by_device(message: Message, frame: bytes) -> None:
    device = SpikeCodec(Role.DEVICE)
    device.receive_data(frame)
    assert device.next_message() == message
    assert device.next_message() is None
    assert device.stats.messages == 1
    assert not device.stats.faults


def test_golden_frame_high_priority() -> None:
    assert SpikeCodec(Role.HOST).send(InfoRequest(), high_priority=True) == b"\x01\x00\x00\x02"


def test_codec_satisfies_the_contract() -> None:
    codec: Codec[Message] = SpikeCodec(Role.HOST)
    assert codec.role is Role.HOST
    assert codec.next_message() is None


def test_strategies_cover_every_message() -> None:
    assert set(MESSAGE_STRATEGIES) == set(MESSAGE_TYPES.values())
    assert set(DEVICE_STRATEGIES) == set(DEVICE_MESSAGE_TYPES.values())


def test_rejects_tiny_frame_limit() -> None:
    with pytest.raises(ValueError):
        SpikeCodec(Role.HOST, max_frame_bytes=2)


# ---------------------------------------------------------------------------- roles


@settings(max_examples=300, deadline=None)
@given(host_messages, st.booleans())
def test_host_to_device_round_trip(message: Message, high_priority: bool) -> None:
    host, device = _codec_pair()
    frame = host.send(message, high_priority=high_priority)
    assert cobs.unpack(frame) == message.encode()
    assert _feed(device, frame) == [message]
    assert device.stats.messages == 1


@settings(max_examples=300, deadline=None)
@given(device_messages, st.booleans())
def test_device_to_host_round_trip(message: Message, high_priority: bool) -> None:
    host, device = _codec_pair()
    frame = device.send(message, high_priority=high_priority)
    assert _feed(host, frame) == [message]
    assert host.stats.messages == 1


@pytest.mark.parametrize("cls", [MESSAGE_TYPES[key] for key in sorted(MESSAGE_TYPES)])
@settings(max_examples=5, deadline=None)
@given(data=st.data())
def test_role_rules(cls: type[Message], data: st.DataObject) -> None:
    host, device = _codec_pair()
    message = data.draw(MESSAGE_STRATEGIES[cls])
    host_sends = cls.kind in (MessageKind.REQUEST, MessageKind.TUNNEL)
    device_sends = cls.kind is not MessageKind.REQUEST
    sender, receiver = (host, device) if host_sends else (device, host)
    frame = sender.send(message)
    assert _feed(receiver, frame) == [message]
    # The same side decoding its own kind of message is a remote fault.
    if not (host_sends and device_sends):
        other = host if sender is device else device
        with pytest.raises(LocalProtocolError):
            other.send(message)
        sender.receive_data(frame)
        with pytest.raises(RemoteProtocolError) as info:
            sender.next_message()
        assert info.value.kind == "wrong_role"
        assert sender.stats.faults == {"wrong_role": 1}
        assert sender.stats.dropped_bytes == len(frame)
        assert sender.next_message() is None


def test_tunnel_goes_both_ways() -> None:
    host, device = _codec_pair()
    message = TunnelMessage(b"\x00\x01\x02\x03 hello")
    assert _feed(device, host.send(message)) == [message]
    assert _feed(host, device.send(message)) == [message]


@pytest.mark.parametrize("thing", [b"\x00", "InfoRequest", None, DeviceBattery(5)])
def test_send_rejects_non_messages(thing: object) -> None:
    with pytest.raises(LocalProtocolError):
        SpikeCodec(Role.HOST).send(thing)


def test_send_rejects_overlong_frames() -> None:
    host = SpikeCodec(Role.HOST, max_frame_bytes=64)
    host.send(TunnelMessage(bytes(range(3, 60))))  # 57 + 3 bytes + code words: 62 bytes
    with pytest.raises(LocalProtocolError):
        host.send(TunnelMessage(bytes(range(3, 63))))


# ---------------------------------------------------------------------------- stream decoding


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.tuples(device_messages, st.booleans()), max_size=8),
    st.lists(st.integers(0, 4000), max_size=20),
)
def test_any_chunking_gives_the_same_messages(
    items: list[tuple[Message, bool]], cuts: list[int]
) -> None:
    device = SpikeCodec(Role.DEVICE)
    stream = b"".join(device.send(message, high_priority=hp) for message, hp in items)
    host = SpikeCodec(Role.HOST)
    assert _feed(host, *_split(stream, cuts)) == [message for message, _ in items]
    assert host.stats.messages == len(items)
    assert not host.stats.faults
    assert host.buffered_bytes == 0


def test_byte_by_byte() -> None:
    host, device = _codec_pair()
    messages = [
        InfoResponse(1, 0, 7, 1, 2, 3, 20, 1024, 512, 0),
        ConsoleNotification("hello\n"),
        DeviceNotification((DeviceBattery(90), DeviceDistance(HubPort.C, 123))),
    ]
    stream = b"".join(device.send(message) for message in messages)
    assert _feed(host, *(bytes([b]) for b in stream)) == messages


def test_empty_frames_are_ignored() -> None:
    device = SpikeCodec(Role.DEVICE)
    assert _feed(device, b"\x02\x02\x01\x02\x02" + b"\x00\x00\x02" + b"\x02") == [InfoRequest()]
    assert not device.stats.faults
    assert device.stats.dropped_bytes == 0


def test_garbage_between_frames_is_one_counted_fault() -> None:
    device = SpikeCodec(Role.DEVICE)
    garbage = b"\xaa\xbb"
    out = _feed(device, b"\x00\x00\x02" + garbage + b"\x02" + b"\x07\x1b\x02")
    assert _kinds(out) == [InfoRequest(), "bad_cobs", GetHubNameRequest()]
    assert device.stats.faults == {"bad_cobs": 1}
    assert device.stats.dropped_bytes == len(garbage) + 1
    assert device.stats.messages == 2
    fault = out[1]
    assert isinstance(fault, RemoteProtocolError)
    assert fault.data == garbage


def test_garbage_before_first_frame_spoils_only_that_frame() -> None:
    device = SpikeCodec(Role.DEVICE)
    out = _feed(device, b"\x55\x56" + b"\x00\x00\x02" + b"\x07\x1b\x02")
    assert _kinds(out)[1:] == [GetHubNameRequest()]
    assert isinstance(out[0], RemoteProtocolError)
    assert sum(device.stats.faults.values()) == 1


@pytest.mark.parametrize(
    ("data", "kind"),
    [
        pytest.param(b"\x99", "unknown_message", id="unknown-id"),
        pytest.param(b"", "bad_length", id="empty-message"),
        pytest.param(b"\x28\x64", "bad_length", id="short-payload"),
        pytest.param(b"\x28\x64\x00\x00", "bad_length", id="long-payload"),
        pytest.param(b"\x46\x14", "bad_value", id="slot-20"),
        pytest.param(b"\x01", "wrong_role", id="info-response-to-device"),
    ],
)
def test_bad_messages_are_counted_and_skipped(data: bytes, kind: str) -> None:
    device = SpikeCodec(Role.DEVICE)
    bad = cobs.pack(data)
    good = cobs.pack(b"\x46\x13")
    device.receive_data(bad + good)
    with pytest.raises(RemoteProtocolError) as info:
        device.next_message()
    assert info.value.kind == kind
    assert info.value.data == bad[:-1]
    assert device.next_message() == ClearSlotRequest(19)
    assert device.next_message() is None
    assert device.stats.faults == {kind: 1}
    assert device.stats.dropped_bytes == len(bad)


def test_bad_cobs_frame() -> None:
    device = SpikeCodec(Role.DEVICE)
    frame = bytes([5 ^ 3, 0x46 ^ 3]) + b"\x02"  # the block says 2 data bytes, holds 1
    assert _kinds(_feed(device, frame, b"\x00\x00\x02")) == ["bad_cobs", InfoRequest()]
    assert device.stats.faults == {"bad_cobs": 1}


# ---------------------------------------------------------------------------- limits


def test_frame_limit_is_inclusive() -> None:
    frame = b"\x06\x2b\x67\x00\x02"  # 5 bytes
    exact = SpikeCodec(Role.DEVICE, max_frame_bytes=5)
    assert _feed(exact, frame) == [DeviceNotificationRequest(100)]
    short = SpikeCodec(Role.DEVICE, max_frame_bytes=4)
    assert _kinds(_feed(short, frame, b"\x00\x00\x02")) == ["overlong", InfoRequest()]
    assert short.stats.faults == {"overlong": 1}
    assert short.stats.dropped_bytes == len(frame)


@pytest.mark.parametrize("chunk_size", [1, 7, 1000])
def test_overlong_frame_is_one_fault(chunk_size: int) -> None:
    big = SpikeCodec(Role.DEVICE, max_frame_bytes=1 << 16)
    frame = big.send(TunnelMessage(bytes(range(256)) * 2))
    host = SpikeCodec(Role.HOST, max_frame_bytes=64)
    stream = frame + big.send(ProgramFlowResponse(ResponseStatus.ACKNOWLEDGED))
    chunks = [stream[i : i + chunk_size] for i in range(0, len(stream), chunk_size)]
    out = _feed(host, *chunks)
    assert _kinds(out) == ["overlong", ProgramFlowResponse(ResponseStatus.ACKNOWLEDGED)]
    assert host.stats.faults == {"overlong": 1}
    assert host.stats.dropped_bytes == len(frame)


def test_endless_frame_stays_bounded() -> None:
    host = SpikeCodec(Role.HOST, max_frame_bytes=64)
    out: list[Message | RemoteProtocolError] = []
    for _ in range(100):
        out += _feed(host, b"\x55" * 1000)
        assert host.buffered_bytes < 64
    assert _kinds(out) == ["overlong"]
    assert host.stats.dropped_bytes == 100_000
    # The next 0x02 ends the bad frame; decoding then carries on.
    assert _feed(host, b"\x02" + cobs.pack(b"\x29\x00")) == [
        DeviceNotificationResponse(ResponseStatus.ACKNOWLEDGED)
    ]
    assert host.stats.dropped_bytes == 100_001


_noise = st.lists(
    st.one_of(st.sampled_from([0x00, 0x01, 0x02, 0x03, 0xFF]), st.integers(0, 255)),
    max_size=300,
).map(bytes)


@settings(max_examples=300, deadline=None)
@given(
    st.sampled_from([Role.HOST, Role.DEVICE]),
    st.sampled_from([4, 16, 64, 4096]),
    st.lists(_noise, max_size=8),
)
def test_arbitrary_bytes_only_raise_remote_errors(
    role: Role, limit: int, chunks: list[bytes]
) -> None:
    codec = SpikeCodec(role, max_frame_bytes=limit)
    for chunk in chunks:
        codec.receive_data(chunk)
        while True:
            try:
                message = codec.next_message()
            except RemoteProtocolError as exc:
                assert exc.kind in {
                    "bad_cobs",
                    "bad_length",
                    "bad_value",
                    "unknown_message",
                    "wrong_role",
                    "overlong",
                    "sync",
                }
                assert len(exc.data) <= 64
                continue
            if message is None:
                break
            assert isinstance(message, Message)
        # Both queues (low and high priority) are bounded by the frame limit.
        assert codec.buffered_bytes <= 2 * (limit - 1)
    # Whatever came before, 0x02 0x02 resynchronises.
    frame = b"\x00\x00\x02" if role is Role.DEVICE else cobs.pack(b"\x29\x00")
    out = _feed(codec, b"\x02\x02" + frame)
    assert out[-1] == (
        InfoRequest()
        if role is Role.DEVICE
        else DeviceNotificationResponse(ResponseStatus.ACKNOWLEDGED)
    )
    assert codec.buffered_bytes == 0
    assert codec.stats.messages >= 1


# ---------------------------------------------------------------------------- priorities


def _low_and_high() -> tuple[SpikeCodec, bytes, bytes, Message, Message]:
    device = SpikeCodec(Role.DEVICE)
    low = ConsoleNotification("a long line of program output\n")
    high = ProgramFlowNotification(ProgramAction.STOP)
    low_frame = device.send(low)
    high_frame = device.send(high, high_priority=True)
    return SpikeCodec(Role.HOST), low_frame, high_frame, low, high


def test_high_priority_interrupts_low_priority() -> None:
    host, low_frame, high_frame, low, high = _low_and_high()
    host.receive_data(low_frame[:10])
    assert host.next_message() is None
    host.receive_data(high_frame)
    # The high-priority message is delivered before the rest of the low one arrives.
    assert host.next_message() == high
    assert host.next_message() is None
    host.receive_data(low_frame[10:])
    assert host.next_message() == low
    assert not host.stats.faults


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 200), st.lists(st.integers(0, 300), max_size=6))
def test_high_priority_interleaving_any_split(where: int, cuts: list[int]) -> None:
    host, low_frame, high_frame, low, high = _low_and_high()
    where = min(where, len(low_frame) - 1)  # inside the low frame, before its 0x02
    stream = low_frame[:where] + high_frame + low_frame[where:]
    assert _feed(host, *_split(stream, cuts)) == [high, low]
    assert not host.stats.faults


def test_high_priority_between_frames() -> None:
    host, low_frame, high_frame, low, high = _low_and_high()
    assert _feed(host, high_frame + low_frame + high_frame) == [high, low, high]


def test_sync_error_clears_both_queues() -> None:
    host, low_frame, high_frame, low, high = _low_and_high()
    stream = low_frame[:10] + b"\x01\x55\x56" + high_frame + low_frame[10:]
    out = _feed(host, stream)
    assert _kinds(out)[:2] == ["sync", high]
    assert low not in out  # its first part was cleared by the sync error
    assert host.stats.faults["sync"] == 1
    sync = out[0]
    assert isinstance(sync, RemoteProtocolError)
    assert sync.data == b"\x55\x56"


def test_sync_error_then_clean_stream() -> None:
    host, low_frame, high_frame, low, high = _low_and_high()
    out = _feed(host, b"\x01" + high_frame, low_frame)
    assert _kinds(out) == ["sync", high, low]
    assert host.stats.faults == {"sync": 1}
    assert host.stats.dropped_bytes == 1


def test_overlong_high_priority_inside_low_priority() -> None:
    device = SpikeCodec(Role.DEVICE, max_frame_bytes=1 << 16)
    host = SpikeCodec(Role.HOST, max_frame_bytes=300)
    low = ConsoleNotification("resumes after the bad high-priority frame")
    low_frame = device.send(low)
    big_high = device.send(TunnelMessage(bytes(400)), high_priority=True)
    out = _feed(host, low_frame[:5] + big_high + low_frame[5:])
    assert _kinds(out) == ["overlong", low]
    assert host.stats.dropped_bytes == len(big_high)
