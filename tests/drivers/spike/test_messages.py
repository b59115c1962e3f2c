"""Tests of the SPIKE Prime hub message classes: wire bytes, validation and decoding."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import pytest

from roboscript.drivers.spike.messages import (
    DEVICE_MESSAGE_TYPES,
    MESSAGE_TYPES,
    BeginFirmwareUpdateRequest,
    BeginFirmwareUpdateResponse,
    ClearSlotRequest,
    ClearSlotResponse,
    Color,
    ConsoleNotification,
    DeviceBattery,
    DeviceColor,
    DeviceDistance,
    DeviceForce,
    DeviceImu,
    DeviceMatrix3x3,
    DeviceMatrix5x5,
    DeviceMessageId,
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
    MessageId,
    MessageKind,
    MotorDeviceType,
    ProductGroupDevice,
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
    decode_message,
)
from roboscript.errors import LocalProtocolError, RemoteProtocolError

ACK = ResponseStatus.ACKNOWLEDGED
NACK = ResponseStatus.NOT_ACKNOWLEDGED
SHA = bytes(range(20))

# One device message of every type, with its wire bytes (worked out by hand, little-endian).
DEVICES = [
    (DeviceBattery(87), "00 57"),
    (
        DeviceImu(HubFace.TOP, HubFace.FRONT, 10, -20, 30, -1, 2, 1000, 0, -32768, 32767),
        "01 00 01 0a00 ecff 1e00 ffff 0200 e803 0000 0080 ff7f",
    ),
    (DeviceMatrix5x5(tuple(range(25))), "02" + bytes(range(25)).hex()),
    (
        DeviceMotor(HubPort.A, MotorDeviceType.MEDIUM_MOTOR, 179, -10000, 100, -(2**31)),
        "0a 00 30 b300 f0d8 64 00000080",
    ),
    (DeviceForce(HubPort.B, 100, True), "0b 01 64 01"),
    (DeviceColor(HubPort.C, Color.NONE, 1023, 0, 512), "0c 02 ff ff03 0000 0002"),
    (DeviceDistance(HubPort.D, -1), "0d 03 ffff"),
    (DeviceMatrix3x3(HubPort.E, (0x9A,) * 9), "0e 04" + "9a" * 9),
]
ALL_DEVICES = DeviceNotification(tuple(device for device, _ in DEVICES))
ALL_DEVICES_HEX = "3c 5900" + "".join(wire for _, wire in DEVICES)

# One message of every type, with its wire bytes (hex, spaces ignored).
EXAMPLES: list[tuple[Message, str]] = [
    (InfoRequest(), "00"),
    (
        InfoResponse(1, 2, 0x0304, 3, 4, 0x0506, 20, 0x1000, 0x01F0, 0),
        "01 01 02 0403 03 04 0605 1400 0010 f001 0000",
    ),
    (StartFirmwareUploadRequest(SHA, 0x11223344), "0a" + SHA.hex() + "44332211"),
    (StartFirmwareUploadResponse(ACK, 1000), "0b 00 e8030000"),
    (
        StartFileUploadRequest("program.py", 0, 0xDEADBEEF),
        "0c" + b"program.py".hex() + "00" + "00 efbeadde",
    ),
    (StartFileUploadResponse(NACK), "0d 01"),
    (TransferChunkRequest(0x01020304, b"abc"), "10 04030201 0300 616263"),
    (TransferChunkResponse(ACK), "11 00"),
    (BeginFirmwareUpdateRequest(SHA, 7), "14" + SHA.hex() + "07000000"),
    (BeginFirmwareUpdateResponse(ACK), "15 00"),
    (SetHubNameRequest("Hub"), "16" + b"Hub".hex() + "00" * 27),
    (SetHubNameResponse(ACK), "17 00"),
    (GetHubNameRequest(), "18"),
    (GetHubNameResponse("Hub"), "19" + b"Hub".hex() + "00" * 27),
    (DeviceUuidRequest(), "1a"),
    (DeviceUuidResponse(bytes(range(16))), "1b" + bytes(range(16)).hex()),
    (ProgramFlowRequest(ProgramAction.START, 0), "1e 00 00"),
    (ProgramFlowResponse(ACK), "1f 00"),
    (ProgramFlowNotification(ProgramAction.STOP), "20 01"),
    (ConsoleNotification("hi\n"), "21 68690a" + "00" * 253),
    (DeviceNotificationRequest(100), "28 6400"),
    (DeviceNotificationResponse(ACK), "29 00"),
    (TunnelMessage(b"\x00\x01\x02"), "32 0300 000102"),
    (ALL_DEVICES, ALL_DEVICES_HEX),
    (ClearSlotRequest(5), "46 05"),
    (ClearSlotResponse(NACK), "47 01"),
]


EXAMPLE_PARAMS = [
    pytest.param(message, wire, id=type(message).__name__) for message, wire in EXAMPLES
]


def test_examples_cover_every_message() -> None:
    assert {type(message) for message, _ in EXAMPLES} == set(MESSAGE_TYPES.values())
    assert len(MESSAGE_TYPES) == 26
    assert {type(device) for device, _ in DEVICES} == set(DEVICE_MESSAGE_TYPES.values())


@pytest.mark.parametrize(("message", "wire"), EXAMPLE_PARAMS)
def test_encode(message: Message, wire: str) -> None:
    assert message.encode() == bytes.fromhex(wire)


@pytest.mark.parametrize(("message", "wire"), EXAMPLE_PARAMS)
def test_decode(message: Message, wire: str) -> None:
    decoded = decode_message(bytes.fromhex(wire))
    assert decoded == message
    assert type(decoded) is type(message)


def test_message_ids_and_kinds_follow_names() -> None:
    for message_id, cls in MESSAGE_TYPES.items():
        assert cls.message_id == message_id
        assert isinstance(cls.message_id, MessageId)
        name = cls.__name__
        if name.endswith("Request"):
            assert cls.kind is MessageKind.REQUEST
            response = MESSAGE_TYPES[message_id + 1]
            assert response.__name__ == name.removesuffix("Request") + "Response"
        elif name.endswith("Response"):
            assert cls.kind is MessageKind.RESPONSE
        elif name.endswith("Notification"):
            assert cls.kind is MessageKind.NOTIFICATION
        else:
            assert cls is TunnelMessage
            assert cls.kind is MessageKind.TUNNEL


def test_info_response_is_17_bytes() -> None:
    message = InfoResponse(1, 0, 0, 1, 0, 0, 20, 512, 256, ProductGroupDevice.SPIKE_PRIME)
    assert len(message.encode()) == 17
    decoded = decode_message(message.encode())
    assert isinstance(decoded, InfoResponse)
    assert decoded.product_group_device is ProductGroupDevice.SPIKE_PRIME


def test_device_notification_with_every_device() -> None:
    wire = ALL_DEVICES.encode()
    assert len(wire) == 3 + 89
    decoded = decode_message(wire)
    assert isinstance(decoded, DeviceNotification)
    assert decoded.devices == ALL_DEVICES.devices
    assert [type(d) for d in decoded.devices] == [type(d) for d, _ in DEVICES]
    assert decoded.unparsed == b""
    for device, device_wire in DEVICES:
        assert device.encode() == bytes.fromhex(device_wire)
        assert device.wire_size() == len(bytes.fromhex(device_wire))
        assert isinstance(device.device_id, DeviceMessageId)


def test_device_notification_empty() -> None:
    assert DeviceNotification(()).encode() == b"\x3c\x00\x00"
    assert decode_message(b"\x3c\x00\x00") == DeviceNotification(())


def test_device_notification_keeps_unknown_device_bytes() -> None:
    wire = bytes.fromhex("3c 0500 0057 7f0102")
    decoded = decode_message(wire)
    assert decoded == DeviceNotification((DeviceBattery(0x57),), unparsed=b"\x7f\x01\x02")
    assert decoded.encode() == wire


@pytest.mark.parametrize(
    "wire",
    [
        pytest.param("3c 00", id="no-size"),
        pytest.param("3c 0500 0057", id="size-too-large"),
        pytest.param("3c 0100 0057", id="size-too-small"),
        pytest.param("3c 0300 0a0030", id="device-cut-short"),
    ],
)
def test_device_notification_bad_length(wire: str) -> None:
    with pytest.raises(RemoteProtocolError) as info:
        decode_message(bytes.fromhex(wire))
    assert info.value.kind == "bad_length"


def test_colour_is_signed_and_open() -> None:
    none = decode_message(bytes.fromhex("3c 0900 0c 00 ff 0000 0000 0000"))
    assert isinstance(none, DeviceNotification)
    assert none.devices == (DeviceColor(HubPort.A, Color.NONE, 0, 0, 0),)
    device = none.devices[0]
    assert isinstance(device, DeviceColor)
    assert device.color is Color.NONE
    red = DeviceColor(HubPort.A, 9, 1, 2, 3)
    assert red.color is Color.RED
    other = DeviceColor(HubPort.A, 11, 1, 2, 3)
    assert other.color == 11
    assert not isinstance(other.color, Color)


def test_unknown_motor_type_is_kept() -> None:
    motor = DeviceMotor(HubPort.F, 0x4B, 0, 0, 0, 0)
    assert motor.device_type == 0x4B
    assert not isinstance(motor.device_type, MotorDeviceType)
    notification = DeviceNotification((motor,))
    assert decode_message(notification.encode()) == notification


def test_enum_fields_are_coerced() -> None:
    request = ProgramFlowRequest(1, 3)  # type: ignore[arg-type]
    assert request.action is ProgramAction.STOP
    force = DeviceForce(1, 5, 1)  # type: ignore[arg-type]
    assert force.port is HubPort.B
    assert force.pressed is True
    assert ClearSlotResponse(0).status is ACK  # type: ignore[arg-type]


def test_force_pressed_reads_nonzero_as_true() -> None:
    decoded = decode_message(bytes.fromhex("3c 0800 0b 02 32 02 0b 03 00 00"))
    assert isinstance(decoded, DeviceNotification)
    assert decoded.devices == (DeviceForce(HubPort.C, 50, True), DeviceForce(HubPort.D, 0, False))


def test_messages_are_frozen() -> None:
    request = ClearSlotRequest(1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        request.slot = 2  # type: ignore[misc]
    assert hash(request) == hash(ClearSlotRequest(1))


# ---------------------------------------------------------------------------- strings


def test_file_name_fixed_padded_form_still_decodes() -> None:
    message = StartFileUploadRequest("program.py", 0, 0xDEADBEEF)
    padded = bytes.fromhex("0c" + b"program.py".hex() + "00" * 22 + "00 efbeadde")
    assert decode_message(padded) == message
    assert len(message.encode()) == 1 + len("program.py") + 1 + 1 + 4


def test_file_name_of_31_bytes() -> None:
    name = "x" * 31
    message = StartFileUploadRequest(name, 19, 1)
    assert len(message.encode()) == 38
    assert decode_message(message.encode()) == message


@pytest.mark.parametrize(
    ("wire", "text"),
    [
        pytest.param(b"\x21hello\x00", "hello", id="variable"),
        pytest.param(b"\x21hello\x00\x00\x00", "hello", id="trailing-nuls"),
        pytest.param(b"\x21hello", "hello", id="no-nul"),
        pytest.param(b"\x21", "", id="empty"),
        pytest.param(b"\x21hi\x00junk\x00", "hi", id="ends-at-first-nul"),
        pytest.param("\x21grüße\x00".encode(), "grüße", id="utf-8"),
    ],
)
def test_console_text_forms(wire: bytes, text: str) -> None:
    assert decode_message(wire) == ConsoleNotification(text)


def test_non_utf8_text_keeps_its_bytes() -> None:
    decoded = decode_message(b"\x21\xff\xfeA\x00")
    assert isinstance(decoded, ConsoleNotification)
    assert decoded.text.encode("utf-8", "surrogateescape") == b"\xff\xfeA"
    assert decoded.encode().startswith(b"\x21\xff\xfeA\x00")
    assert decode_message(decoded.encode()) == decoded


@pytest.mark.parametrize(
    ("wire", "kind"),
    [
        pytest.param(b"\x19" + b"x" * 30, "bad_value", id="not-terminated"),
        pytest.param(b"\x19" + b"x" * 30 + b"\x00", "bad_length", id="too-long"),
        pytest.param(b"\x0c\x00\x00\x00\x00", "bad_length", id="upload-too-short"),
    ],
)
def test_bad_strings(wire: bytes, kind: str) -> None:
    with pytest.raises(RemoteProtocolError) as info:
        decode_message(wire)
    assert info.value.kind == kind


def test_string_limits() -> None:
    SetHubNameRequest("x" * 29)
    SetHubNameRequest("é" * 14)  # 28 bytes of UTF-8
    with pytest.raises(LocalProtocolError):
        SetHubNameRequest("x" * 30)
    with pytest.raises(LocalProtocolError):
        SetHubNameRequest("é" * 15)  # 30 bytes of UTF-8
    with pytest.raises(LocalProtocolError):
        SetHubNameRequest("a\x00b")
    with pytest.raises(LocalProtocolError):
        StartFileUploadRequest("x" * 32, 0, 0)
    ConsoleNotification("x" * 255)
    with pytest.raises(LocalProtocolError):
        ConsoleNotification("x" * 256)


# ---------------------------------------------------------------------------- validation


@pytest.mark.parametrize(
    ("cls", "args"),
    [
        pytest.param(ClearSlotRequest, (20,), id="slot-20"),
        pytest.param(ClearSlotRequest, (-1,), id="slot-negative"),
        pytest.param(ProgramFlowRequest, (ProgramAction.START, 20), id="flow-slot-20"),
        pytest.param(StartFileUploadRequest, ("a.py", 25, 0), id="upload-slot-25"),
        pytest.param(ClearSlotRequest, ("1",), id="slot-str"),
        pytest.param(DeviceNotificationRequest, (65536,), id="interval-u16"),
        pytest.param(DeviceNotificationRequest, (-1,), id="interval-negative"),
        pytest.param(ProgramFlowRequest, (2, 0), id="action-unknown"),
        pytest.param(ClearSlotResponse, (2,), id="status-unknown"),
        pytest.param(StartFirmwareUploadRequest, (bytes(19), 0), id="sha-length"),
        pytest.param(StartFirmwareUploadRequest, (SHA, 1 << 32), id="crc-u32"),
        pytest.param(StartFirmwareUploadRequest, ("x" * 20, 0), id="sha-str"),
        pytest.param(DeviceUuidResponse, (bytes(17),), id="uuid-length"),
        pytest.param(TransferChunkRequest, (0, bytes(65536)), id="chunk-too-long"),
        pytest.param(TunnelMessage, (bytes(65536),), id="tunnel-too-long"),
        pytest.param(InfoResponse, (256, 0, 0, 0, 0, 0, 0, 0, 0, 0), id="u8"),
        pytest.param(InfoResponse, (0, 0, 0, 0, 0, 0, 0, 0, 0, 65536), id="u16"),
        pytest.param(DeviceBattery, (256,), id="battery-u8"),
        pytest.param(DeviceImu, (6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0), id="imu-face"),
        pytest.param(DeviceImu, (0, 0, 32768, 0, 0, 0, 0, 0, 0, 0, 0), id="imu-i16"),
        pytest.param(DeviceMotor, (6, 0x30, 0, 0, 0, 0), id="motor-port"),
        pytest.param(DeviceMotor, (0, 256, 0, 0, 0, 0), id="motor-type-u8"),
        pytest.param(DeviceMotor, (0, 0x30, 0, 0, 128, 0), id="motor-speed-i8"),
        pytest.param(DeviceMotor, (0, 0x30, 0, 0, 0, 1 << 31), id="motor-position-i32"),
        pytest.param(DeviceForce, (0, 0, 2), id="force-pressed"),
        pytest.param(DeviceColor, (0, -129, 0, 0, 0), id="color-i8"),
        pytest.param(DeviceColor, (0, 0, -1, 0, 0), id="color-u16"),
        pytest.param(DeviceDistance, (0, -32769), id="distance-i16"),
        pytest.param(DeviceMatrix5x5, ((0,) * 24,), id="matrix-24"),
        pytest.param(DeviceMatrix5x5, ((256,) * 25,), id="matrix-u8"),
        pytest.param(DeviceMatrix3x3, (0, "abcdefghi"), id="matrix-str"),
        pytest.param(DeviceNotification, ((DeviceBattery(1), "x"),), id="not-a-device"),
        pytest.param(DeviceNotification, ((), b"\x00\x01"), id="unparsed-known"),
        pytest.param(DeviceNotification, (("x",),), id="device-str"),
        pytest.param(DeviceNotification, ((DeviceBattery(1),) * 40000,), id="too-long"),
    ],
)
def test_invalid_fields_raise_local_protocol_error(
    cls: Callable[..., object], args: tuple[object, ...]
) -> None:
    with pytest.raises(LocalProtocolError):
        cls(*args)


def test_documented_physical_ranges_are_not_enforced() -> None:
    # Readings outside the documented ranges still decode; only the wire types bound them.
    DeviceMotor(HubPort.A, MotorDeviceType.LARGE_MOTOR, 180, 20000, 127, 0)
    DeviceDistance(HubPort.A, 5)
    DeviceColor(HubPort.A, Color.RED, 4000, 0, 0)
    DeviceBattery(101)


@pytest.mark.parametrize(
    ("wire", "kind"),
    [
        pytest.param(b"", "bad_length", id="empty"),
        pytest.param(b"\x99", "unknown_message", id="unknown-id"),
        pytest.param(b"\x00\x00", "bad_length", id="info-request-extra"),
        pytest.param(b"\x1e\x00", "bad_length", id="flow-short"),
        pytest.param(b"\x1e\x00\x00\x00", "bad_length", id="flow-long"),
        pytest.param(b"\x1e\x00\x14", "bad_value", id="flow-slot-20"),
        pytest.param(b"\x1e\x02\x00", "bad_value", id="flow-action-2"),
        pytest.param(b"\x28\x64", "bad_length", id="interval-short"),
        pytest.param(b"\x1f\x05", "bad_value", id="status-5"),
        pytest.param(b"\x10\x00\x00\x00\x00\x02\x00a", "bad_length", id="chunk-size-mismatch"),
        pytest.param(b"\x10\x00\x00\x00\x00\x02", "bad_length", id="chunk-no-size"),
        pytest.param(b"\x32\x01\x00", "bad_length", id="tunnel-missing-data"),
        pytest.param(b"\x32\x00\x00\x00", "bad_length", id="tunnel-extra-data"),
        pytest.param(b"\x3c\x15\x00\x01\x06" + bytes(19), "bad_value", id="imu-face-6"),
    ],
)
def test_decode_faults(wire: bytes, kind: str) -> None:
    with pytest.raises(RemoteProtocolError) as info:
        decode_message(wire)
    assert info.value.kind == kind
