"""Messages of the LEGO SPIKE Prime hub protocol (SPIKE App 3 firmware), as frozen dataclasses.

Every message is one byte of :class:`MessageId` followed by little-endian fields
(spike-docs ``messages.rst``). :meth:`Message.encode` gives those bytes and
:func:`decode_message` reads them back; framing (COBS, XOR, delimiters) is done by
:mod:`roboscript.drivers.spike.cobs`.

Conventions:

* Field names carry their unit (``interval_ms``, ``max_packet_size`` in bytes,
  ``distance_mm``). Where the docs give no unit the field has none either and is a raw value.
* Every field is checked when a message is built; a value out of range for its wire type
  (u8, i16, ...), a program slot outside 0..19, an unknown value of a closed enum, or a string
  too long for its ``string[n]`` field raises :class:`~roboscript.errors.LocalProtocolError`.
  The documented physical ranges (motor power ±10000, distance 40..2000 mm, ...) are not
  enforced, so that readings a real hub sends are never thrown away.
* Enum fields hold :class:`enum.IntEnum` members. Motor device type, colour and product group
  are *open*: a value without a member is kept as a plain ``int``.
* Strings are UTF-8 and NUL-terminated; ``string[n]`` holds at most ``n - 1`` bytes of text.
  They are sent fixed-width (padded with NULs to ``n`` bytes), except the file name of
  :class:`StartFileUploadRequest`, which is sent as LEGO's example client sends it: the text
  and one NUL (``string[32]`` is its largest size). When decoding, both forms are accepted
  for every string; the text ends at the first NUL. Bytes that are not UTF-8 are kept as lone
  surrogates (``errors="surrogateescape"``), so ``text.encode("utf-8", "surrogateescape")``
  gives the exact wire bytes back.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Callable, Mapping, Sequence
from dataclasses import Field, dataclass, field, fields
from typing import Any, ClassVar, Final

from roboscript.errors import LocalProtocolError, RemoteProtocolError

__all__ = [
    "DEVICE_MESSAGE_TYPES",
    "MESSAGE_TYPES",
    "SHA_BYTES",
    "SLOT_COUNT",
    "UUID_BYTES",
    "BeginFirmwareUpdateRequest",
    "BeginFirmwareUpdateResponse",
    "ClearSlotRequest",
    "ClearSlotResponse",
    "Color",
    "ConsoleNotification",
    "DeviceBattery",
    "DeviceColor",
    "DeviceDistance",
    "DeviceForce",
    "DeviceImu",
    "DeviceMatrix3x3",
    "DeviceMatrix5x5",
    "DeviceMessage",
    "DeviceMessageId",
    "DeviceMotor",
    "DeviceNotification",
    "DeviceNotificationRequest",
    "DeviceNotificationResponse",
    "DeviceUuidRequest",
    "DeviceUuidResponse",
    "GetHubNameRequest",
    "GetHubNameResponse",
    "HubFace",
    "HubPort",
    "InfoRequest",
    "InfoResponse",
    "Message",
    "MessageId",
    "MessageKind",
    "MotorDeviceType",
    "MotorEndState",
    "MotorMoveDirection",
    "ProductGroupDevice",
    "ProgramAction",
    "ProgramFlowNotification",
    "ProgramFlowRequest",
    "ProgramFlowResponse",
    "ResponseStatus",
    "SetHubNameRequest",
    "SetHubNameResponse",
    "StartFileUploadRequest",
    "StartFileUploadResponse",
    "StartFirmwareUploadRequest",
    "StartFirmwareUploadResponse",
    "TransferChunkRequest",
    "TransferChunkResponse",
    "TunnelMessage",
    "decode_message",
]

SLOT_COUNT: Final = 20
"""Program slots on the hub, numbered 0..19."""
SHA_BYTES: Final = 20
"""Length of a file SHA in firmware upload messages."""
UUID_BYTES: Final = 16
"""Length of the device UUID."""

_TEXT_ENCODING: Final = "utf-8"
_TEXT_ERRORS: Final = "surrogateescape"


# --------------------------------------------------------------------------------------------
# Enums (spike-docs ``enums.rst``)


class MessageId(enum.IntEnum):
    """The first byte of every message."""

    INFO_REQUEST = 0x00
    INFO_RESPONSE = 0x01
    START_FIRMWARE_UPLOAD_REQUEST = 0x0A
    START_FIRMWARE_UPLOAD_RESPONSE = 0x0B
    START_FILE_UPLOAD_REQUEST = 0x0C
    START_FILE_UPLOAD_RESPONSE = 0x0D
    TRANSFER_CHUNK_REQUEST = 0x10
    TRANSFER_CHUNK_RESPONSE = 0x11
    BEGIN_FIRMWARE_UPDATE_REQUEST = 0x14
    BEGIN_FIRMWARE_UPDATE_RESPONSE = 0x15
    SET_HUB_NAME_REQUEST = 0x16
    SET_HUB_NAME_RESPONSE = 0x17
    GET_HUB_NAME_REQUEST = 0x18
    GET_HUB_NAME_RESPONSE = 0x19
    DEVICE_UUID_REQUEST = 0x1A
    DEVICE_UUID_RESPONSE = 0x1B
    PROGRAM_FLOW_REQUEST = 0x1E
    PROGRAM_FLOW_RESPONSE = 0x1F
    PROGRAM_FLOW_NOTIFICATION = 0x20
    CONSOLE_NOTIFICATION = 0x21
    DEVICE_NOTIFICATION_REQUEST = 0x28
    DEVICE_NOTIFICATION_RESPONSE = 0x29
    TUNNEL_MESSAGE = 0x32
    DEVICE_NOTIFICATION = 0x3C
    CLEAR_SLOT_REQUEST = 0x46
    CLEAR_SLOT_RESPONSE = 0x47


class DeviceMessageId(enum.IntEnum):
    """The first byte of each device message inside a :class:`DeviceNotification`."""

    BATTERY = 0x00
    IMU = 0x01
    MATRIX_5X5 = 0x02
    MOTOR = 0x0A
    FORCE = 0x0B
    COLOR = 0x0C
    DISTANCE = 0x0D
    MATRIX_3X3 = 0x0E


class MessageKind(enum.Enum):
    """Who sends a message: the host (requests), the hub (responses, notifications) or both."""

    REQUEST = "request"
    """Sent by the host; the hub answers with the matching response."""
    RESPONSE = "response"
    """Sent by the hub in answer to a request."""
    NOTIFICATION = "notification"
    """Sent by the hub unprompted."""
    TUNNEL = "tunnel"
    """Sent either way (program ↔ app tunnel)."""


class ResponseStatus(enum.IntEnum):
    """Result of a request (uint8)."""

    ACKNOWLEDGED = 0x00
    NOT_ACKNOWLEDGED = 0x01


class ProgramAction(enum.IntEnum):
    """Start or stop a program (uint8)."""

    START = 0x00
    STOP = 0x01


class HubPort(enum.IntEnum):
    """The hub's device ports (uint8)."""

    A = 0x00
    B = 0x01
    C = 0x02
    D = 0x03
    E = 0x04
    F = 0x05


class HubFace(enum.IntEnum):
    """The faces of the hub (uint8)."""

    TOP = 0x00
    FRONT = 0x01
    RIGHT = 0x02
    BOTTOM = 0x03
    BACK = 0x04
    LEFT = 0x05


class MotorDeviceType(enum.IntEnum):
    """Motor types reported in :class:`DeviceMotor` (uint8). Other motors keep a plain int."""

    MEDIUM_MOTOR = 0x30
    LARGE_MOTOR = 0x31
    SMALL_MOTOR = 0x41


class Color(enum.IntEnum):
    """Colours reported by the colour sensor (int8; ``0xFF`` on the wire is ``NONE``, -1)."""

    NONE = -1
    BLACK = 0x00
    MAGENTA = 0x01
    PURPLE = 0x02
    BLUE = 0x03
    AZURE = 0x04
    TURQUOISE = 0x05
    GREEN = 0x06
    YELLOW = 0x07
    ORANGE = 0x08
    RED = 0x09
    WHITE = 0x0A


class ProductGroupDevice(enum.IntEnum):
    """Product reported in :class:`InfoResponse` (uint16). Others keep a plain int."""

    SPIKE_PRIME = 0x0000


class MotorEndState(enum.IntEnum):
    """How a motor stops (int8). Documented, but no documented message uses it."""

    DEFAULT = -1
    COAST = 0
    BRAKE = 1
    HOLD = 2
    CONTINUE = 3
    SMART_COAST = 4
    SMART_BRAKE = 5


class MotorMoveDirection(enum.IntEnum):
    """Which way a motor turns to a position (uint8). No documented message uses it."""

    CLOCKWISE = 0
    COUNTERCLOCKWISE = 1
    SHORTEST_PATH = 2
    LONGEST_PATH = 3


# --------------------------------------------------------------------------------------------
# Field specifications: how each dataclass field is checked and laid out on the wire

_INT_RANGES: Final[Mapping[str, tuple[int, int]]] = {
    "B": (0, 0xFF),
    "b": (-0x80, 0x7F),
    "H": (0, 0xFFFF),
    "h": (-0x8000, 0x7FFF),
    "I": (0, 0xFFFF_FFFF),
    "i": (-0x8000_0000, 0x7FFF_FFFF),
}
_U16: Final = struct.Struct("<H")


class _Kind(enum.Enum):
    INT = "int"  # struct integer code
    BOOL = "bool"  # uint8 0/1
    BYTES = "bytes"  # fixed number of raw bytes
    PIXELS = "pixels"  # fixed number of uint8 values, as a tuple of ints
    STRING = "string"  # string[n], NUL-terminated
    BLOB = "blob"  # uint16 size + that many bytes (last field only)
    DEVICES = "devices"  # DeviceNotification payload (custom layout)
    RAW = "raw"  # trailing bytes (custom layout)


@dataclass(frozen=True, slots=True)
class _Spec:
    kind: _Kind
    code: str = ""
    size: int = 0
    enum: type[enum.IntEnum] | None = None
    open_enum: bool = False
    low: int | None = None
    high: int | None = None
    variable: bool = False  # STRING: sent as text + one NUL instead of NUL-padded

    @property
    def wire_size(self) -> int | None:
        """Bytes on the wire, or ``None`` for a variable-size field."""
        if self.kind is _Kind.INT:
            return struct.calcsize("<" + self.code)
        if self.kind is _Kind.BOOL:
            return 1
        if self.kind in (_Kind.BYTES, _Kind.PIXELS):
            return self.size
        return None


_META_KEY: Final = "spike"


def _meta(spec: _Spec) -> Mapping[str, _Spec]:
    return {_META_KEY: spec}


def _int(
    code: str,
    *,
    enum_type: type[enum.IntEnum] | None = None,
    open_enum: bool = False,
    low: int | None = None,
    high: int | None = None,
) -> Mapping[str, _Spec]:
    return _meta(_Spec(_Kind.INT, code, enum=enum_type, open_enum=open_enum, low=low, high=high))


_U8: Final = _int("B")
_I8: Final = _int("b")
_U16_FIELD: Final = _int("H")
_I16: Final = _int("h")
_U32: Final = _int("I")
_I32: Final = _int("i")
_SLOT: Final = _int("B", high=SLOT_COUNT - 1)
_STATUS: Final = _int("B", enum_type=ResponseStatus)
_ACTION: Final = _int("B", enum_type=ProgramAction)
_PORT: Final = _int("B", enum_type=HubPort)
_FACE: Final = _int("B", enum_type=HubFace)
_BOOL: Final = _meta(_Spec(_Kind.BOOL))
_BLOB: Final = _meta(_Spec(_Kind.BLOB))


def _bytes(size: int) -> Mapping[str, _Spec]:
    return _meta(_Spec(_Kind.BYTES, size=size))


def _pixels(count: int) -> Mapping[str, _Spec]:
    return _meta(_Spec(_Kind.PIXELS, size=count))


def _string(size: int, *, variable: bool = False) -> Mapping[str, _Spec]:
    return _meta(_Spec(_Kind.STRING, size=size, variable=variable))


_Checker = Callable[[Any], Any]
"""Checks one field value: returns it (possibly converted), or raises TypeError or ValueError."""


def _int_checker(spec: _Spec) -> _Checker:
    low, high = _INT_RANGES[spec.code]
    if spec.low is not None:
        low = max(low, spec.low)
    if spec.high is not None:
        high = min(high, spec.high)
    enum_type = spec.enum
    open_enum = spec.open_enum

    def check(value: Any) -> Any:
        if not isinstance(value, int):
            raise TypeError(f"must be an int, not {value!r}")
        if not low <= value <= high:
            raise ValueError(f"must be in {low}..{high}, not {value}")
        if enum_type is None or type(value) is enum_type:
            return value
        try:
            return enum_type(value)
        except ValueError:
            if open_enum:
                return int(value)
            raise ValueError(f"must be a {enum_type.__name__}, not {value}") from None

    return check


def _bool_checker(value: Any) -> Any:
    if value is True or value is False:
        return value
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    raise ValueError(f"must be a bool, not {value!r}")


def _bytes_checker(size: int | None) -> _Checker:
    def check(value: Any) -> Any:
        if not isinstance(value, bytes | bytearray | memoryview):
            raise TypeError(f"must be bytes, not {type(value).__name__}")
        if type(value) is not bytes:
            value = bytes(value)
        if size is not None and len(value) != size:
            raise ValueError(f"must be {size} bytes, not {len(value)}")
        if size is None and len(value) > 0xFFFF:
            raise ValueError(f"must be at most 65535 bytes, not {len(value)}")
        return value

    return check


def _pixels_checker(count: int) -> _Checker:
    def check(value: Any) -> Any:
        if not isinstance(value, Sequence) or isinstance(value, str):
            raise TypeError(f"must be a sequence of ints, not {value!r}")
        if len(value) != count:
            raise ValueError(f"must hold {count} values, not {len(value)}")
        try:
            bytes(value)  # checks, in C, that every value is an int in 0..255
        except (TypeError, ValueError):
            raise ValueError(f"must hold ints in 0..255, not {value!r}") from None
        return value if type(value) is tuple else tuple(value)

    return check


def _string_checker(size: int) -> _Checker:
    def check(value: Any) -> Any:
        if not isinstance(value, str):
            raise TypeError(f"must be a str, not {type(value).__name__}")
        if "\x00" in value:
            raise ValueError("must not contain NUL")
        try:
            encoded = value.encode(_TEXT_ENCODING, _TEXT_ERRORS)
        except UnicodeEncodeError as exc:
            raise ValueError(f"cannot be encoded: {exc}") from None
        if len(encoded) > size - 1:
            raise ValueError(f"must be at most {size - 1} bytes of UTF-8, not {len(encoded)}")
        return value

    return check


def _devices_checker(value: Any) -> Any:
    if not isinstance(value, Sequence) or isinstance(value, str | bytes):
        raise TypeError(f"must be a tuple of device messages, not {value!r}")
    for item in value:
        if not isinstance(item, DeviceMessage):
            raise TypeError(f"must hold device messages only, not {item!r}")
    return value if type(value) is tuple else tuple(value)


def _checker(spec: _Spec) -> _Checker:
    if spec.kind is _Kind.INT:
        return _int_checker(spec)
    if spec.kind is _Kind.BOOL:
        return _bool_checker
    if spec.kind is _Kind.BYTES:
        return _bytes_checker(spec.size)
    if spec.kind in (_Kind.BLOB, _Kind.RAW):
        return _bytes_checker(None)
    if spec.kind is _Kind.PIXELS:
        return _pixels_checker(spec.size)
    if spec.kind is _Kind.STRING:
        return _string_checker(spec.size)
    return _devices_checker


@dataclass(frozen=True, slots=True)
class _Layout:
    names: tuple[str, ...]
    specs: tuple[_Spec, ...]
    checkers: tuple[_Checker, ...]
    tails: tuple[int, ...]  # for each field, the fixed wire size of the fields after it
    fixed: struct.Struct | None  # the whole payload, when every field has a fixed size
    converted: bool  # some field's value differs from its struct value (bool, pixels)
    # The checks a value unpacked from the wire still needs: struct already guarantees the
    # wire type's range, but not an enum's members or a narrower documented range.
    wire_checks: tuple[tuple[int, _Checker], ...] = ()


def _struct_code(spec: _Spec) -> str:
    if spec.kind is _Kind.INT:
        return spec.code
    if spec.kind is _Kind.BOOL:
        return "B"
    return f"{spec.size}s"


def _build_layout(cls: type[_Record]) -> _Layout:
    items = [(f.name, f.metadata[_META_KEY]) for f in fields(cls)]
    names = tuple(name for name, _ in items)
    specs: tuple[_Spec, ...] = tuple(spec for _, spec in items)
    sizes = [spec.wire_size for spec in specs]
    # The generic reader supports one variable-size field; classes with more override it.
    tails = [sum(size or 0 for size in sizes[index + 1 :]) for index in range(len(sizes))]
    fixed = None
    if None not in sizes:
        fixed = struct.Struct("<" + "".join(_struct_code(spec) for spec in specs))
    converted = any(spec.kind in (_Kind.BOOL, _Kind.PIXELS) for spec in specs)
    checkers = tuple(_checker(spec) for spec in specs)
    wire_checks = tuple(
        (index, checkers[index])
        for index, spec in enumerate(specs)
        if spec.kind is _Kind.INT
        and (spec.enum is not None or spec.low is not None or spec.high is not None)
    )
    return _Layout(names, specs, checkers, tuple(tails), fixed, converted, wire_checks)


_LAYOUTS: dict[type[_Record], _Layout] = {}


def _layout(cls: type[_Record]) -> _Layout:
    layout = _LAYOUTS.get(cls)
    if layout is None:
        layout = _LAYOUTS[cls] = _build_layout(cls)
    return layout


# --------------------------------------------------------------------------------------------
# Reading and writing the wire


def _remote(kind: str, message: str, data: bytes) -> RemoteProtocolError:
    return RemoteProtocolError(message, kind=kind, data=data)


def _string_to_wire(spec: _Spec, value: str) -> bytes:
    text = value.encode(_TEXT_ENCODING, _TEXT_ERRORS)
    return text + b"\x00" if spec.variable else text.ljust(spec.size, b"\x00")


def _string_from_wire(owner: str, spec: _Spec, raw: bytes) -> str:
    if len(raw) > spec.size:
        raise _remote("bad_length", f"{owner}: string[{spec.size}] holds {len(raw)} bytes", raw)
    text, nul, _ = raw.partition(b"\x00")
    if not nul and len(raw) == spec.size:
        raise _remote("bad_value", f"{owner}: string[{spec.size}] is not NUL-terminated", raw)
    return text.decode(_TEXT_ENCODING, _TEXT_ERRORS)


def _to_wire(spec: _Spec, value: Any) -> Any:
    if spec.kind is _Kind.BOOL:
        return int(value)
    if spec.kind is _Kind.PIXELS:
        return bytes(value)
    return value


def _from_wire(spec: _Spec, value: Any) -> Any:
    if spec.kind is _Kind.BOOL:
        return value != 0
    if spec.kind is _Kind.PIXELS:
        return tuple(value)
    return value


# --------------------------------------------------------------------------------------------
# Base classes


class _Record:
    """Validation and (de)serialisation shared by messages and device messages."""

    __slots__ = ()
    __dataclass_fields__: ClassVar[dict[str, Field[Any]]]

    def __post_init__(self) -> None:
        layout = _layout(type(self))
        for name, check in zip(layout.names, layout.checkers, strict=True):
            value = getattr(self, name)
            try:
                checked = check(value)
            except (TypeError, ValueError) as exc:
                raise LocalProtocolError(f"{type(self).__name__}.{name} {exc}") from None
            if checked is not value:
                object.__setattr__(self, name, checked)

    def _pack_fields(self) -> bytes:
        layout = _layout(type(self))
        values = [getattr(self, name) for name in layout.names]
        if layout.fixed is not None:
            if layout.converted:
                values = [_to_wire(s, v) for s, v in zip(layout.specs, values, strict=True)]
            return layout.fixed.pack(*values)
        out = bytearray()
        for spec, value in zip(layout.specs, values, strict=True):
            if spec.kind is _Kind.STRING:
                out += _string_to_wire(spec, value)
            elif spec.kind is _Kind.BLOB:
                out += _U16.pack(len(value)) + value
            else:
                out += struct.pack("<" + _struct_code(spec), _to_wire(spec, value))
        return bytes(out)

    @classmethod
    def _unpack_fields(cls, payload: bytes) -> _Record:
        layout = _layout(cls)
        owner = cls.__name__
        if layout.fixed is not None:
            if len(payload) != layout.fixed.size:
                raise _remote(
                    "bad_length",
                    f"{owner} needs {layout.fixed.size} bytes after its id, not {len(payload)}",
                    payload,
                )
            values: Sequence[Any] = layout.fixed.unpack(payload)
            if layout.converted:
                values = [_from_wire(s, v) for s, v in zip(layout.specs, values, strict=True)]
            if cls.__post_init__ is _Record.__post_init__:
                return cls._trusted(layout, list(values), payload)
        else:
            values = cls._read_fields(layout, payload)
        build: Callable[..., _Record] = cls
        try:
            return build(*values)
        except LocalProtocolError as exc:
            raise _remote("bad_value", str(exc), payload) from None

    @classmethod
    def _trusted(cls, layout: _Layout, values: list[Any], payload: bytes) -> _Record:
        """Build from unpacked wire values, running only the checks struct cannot make.

        Decoding a DeviceNotification builds several records per frame at the telemetry
        rate; re-checking what the struct format already guarantees cost about 20 µs a frame.
        """
        for index, check in layout.wire_checks:
            try:
                values[index] = check(values[index])
            except (TypeError, ValueError) as exc:
                name = layout.names[index]
                raise _remote("bad_value", f"{cls.__name__}.{name} {exc}", payload) from None
        record = object.__new__(cls)
        for name, value in zip(layout.names, values, strict=True):
            object.__setattr__(record, name, value)
        return record

    @classmethod
    def _read_fields(cls, layout: _Layout, payload: bytes) -> list[Any]:
        owner = cls.__name__
        values: list[Any] = []
        offset = 0
        for spec, tail in zip(layout.specs, layout.tails, strict=True):
            end = len(payload) - tail  # where this field must end at the latest
            if spec.kind is _Kind.STRING:
                if end < offset:
                    raise _remote("bad_length", f"{owner} is too short", payload)
                values.append(_string_from_wire(owner, spec, payload[offset:end]))
                offset = end
            elif spec.kind is _Kind.BLOB:
                if end - offset < _U16.size:
                    raise _remote("bad_length", f"{owner} is too short", payload)
                (size,) = _U16.unpack_from(payload, offset)
                offset += _U16.size
                if end - offset != size:
                    raise _remote(
                        "bad_length",
                        f"{owner} says {size} data bytes but holds {end - offset}",
                        payload,
                    )
                values.append(payload[offset:end])
                offset = end
            else:
                item = struct.Struct("<" + _struct_code(spec))
                if end - offset < item.size:
                    raise _remote("bad_length", f"{owner} is too short", payload)
                (value,) = item.unpack_from(payload, offset)
                values.append(_from_wire(spec, value))
                offset += item.size
        if offset != len(payload):
            raise _remote("bad_length", f"{owner} has {len(payload) - offset} extra bytes", payload)
        return values


class Message(_Record):
    """Base of every hub protocol message.

    Attributes:
        message_id: The message's id byte (class attribute).
        kind: Who sends the message (class attribute).
    """

    __slots__ = ()
    message_id: ClassVar[MessageId]
    kind: ClassVar[MessageKind]

    def encode(self) -> bytes:
        """Return the message bytes: the id byte, then the little-endian fields (unframed)."""
        return bytes((self.message_id,)) + self._pack_fields()

    @classmethod
    def decode_payload(cls, payload: bytes) -> Message:
        """Build this message from the bytes after its id byte.

        Args:
            payload: The message bytes without the id byte.

        Returns:
            The message, an instance of ``cls``.

        Raises:
            RemoteProtocolError: ``kind="bad_length"`` if the payload has the wrong size for the
                message, ``kind="bad_value"`` if a field is out of range.
        """
        message = cls._unpack_fields(payload)
        assert isinstance(message, Message)
        return message


class DeviceMessage(_Record):
    """Base of the device messages carried in a :class:`DeviceNotification`.

    Attributes:
        device_id: The device message's id byte (class attribute).
    """

    __slots__ = ()
    device_id: ClassVar[DeviceMessageId]

    @classmethod
    def wire_size(cls) -> int:
        """Return the size of this device message on the wire, in bytes, including its id."""
        layout = _layout(cls)
        assert layout.fixed is not None
        return 1 + layout.fixed.size

    def encode(self) -> bytes:
        """Return the device message bytes: the id byte, then its little-endian fields."""
        return bytes((self.device_id,)) + self._pack_fields()


# --------------------------------------------------------------------------------------------
# Messages (spike-docs ``messages.rst``)


@dataclass(frozen=True, slots=True)
class InfoRequest(Message):
    """Ask the hub for its versions and size limits; the first message of every session."""

    message_id: ClassVar[MessageId] = MessageId.INFO_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST


@dataclass(frozen=True, slots=True)
class InfoResponse(Message):
    """The hub's versions and size limits.

    Attributes:
        rpc_major: RPC protocol major version.
        rpc_minor: RPC protocol minor version.
        rpc_build: RPC protocol build number (u16).
        firmware_major: Firmware major version.
        firmware_minor: Firmware minor version.
        firmware_build: Firmware build number (u16).
        max_packet_size: Largest single BLE write to the hub's RX characteristic, in bytes.
        max_message_size: Largest message, in bytes.
        max_chunk_size: Largest ``TransferChunkRequest`` payload, in bytes.
        product_group_device: A :class:`ProductGroupDevice` (or a plain int if unknown).
    """

    message_id: ClassVar[MessageId] = MessageId.INFO_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    rpc_major: int = field(metadata=_U8)
    rpc_minor: int = field(metadata=_U8)
    rpc_build: int = field(metadata=_U16_FIELD)
    firmware_major: int = field(metadata=_U8)
    firmware_minor: int = field(metadata=_U8)
    firmware_build: int = field(metadata=_U16_FIELD)
    max_packet_size: int = field(metadata=_U16_FIELD)
    max_message_size: int = field(metadata=_U16_FIELD)
    max_chunk_size: int = field(metadata=_U16_FIELD)
    product_group_device: ProductGroupDevice | int = field(
        metadata=_int("H", enum_type=ProductGroupDevice, open_enum=True)
    )


@dataclass(frozen=True, slots=True)
class StartFirmwareUploadRequest(Message):
    """Start (or resume) uploading a firmware file.

    Attributes:
        file_sha: The file's SHA, 20 bytes.
        crc32: The file's CRC32 (see :func:`roboscript.drivers.spike.crc.crc32`).
    """

    message_id: ClassVar[MessageId] = MessageId.START_FIRMWARE_UPLOAD_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    file_sha: bytes = field(metadata=_bytes(SHA_BYTES))
    crc32: int = field(metadata=_U32)


@dataclass(frozen=True, slots=True)
class StartFirmwareUploadResponse(Message):
    """Answer to :class:`StartFirmwareUploadRequest`.

    Attributes:
        status: Whether the hub accepted the request.
        uploaded_bytes: Bytes of this file already uploaded, to resume an interrupted upload.
    """

    message_id: ClassVar[MessageId] = MessageId.START_FIRMWARE_UPLOAD_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)
    uploaded_bytes: int = field(metadata=_U32)


@dataclass(frozen=True, slots=True)
class StartFileUploadRequest(Message):
    """Start uploading a program file into a slot.

    On the wire the name is its UTF-8 bytes and one NUL, then the slot and the CRC, as LEGO's
    example client packs it (``string[32]`` is the largest size, not a fixed one): a hub that
    reads the name up to its NUL would take a padded name's NULs for the slot and the CRC.
    Both forms decode.

    Attributes:
        file_name: Name stored on the hub (at most 31 bytes of UTF-8).
        slot: Program slot, 0..19.
        crc32: The whole file's CRC32 (see :func:`roboscript.drivers.spike.crc.crc32`).
    """

    message_id: ClassVar[MessageId] = MessageId.START_FILE_UPLOAD_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    file_name: str = field(metadata=_string(32, variable=True))
    slot: int = field(metadata=_SLOT)
    crc32: int = field(metadata=_U32)


@dataclass(frozen=True, slots=True)
class StartFileUploadResponse(Message):
    """Answer to :class:`StartFileUploadRequest`.

    Attributes:
        status: Whether the hub accepted the request.
    """

    message_id: ClassVar[MessageId] = MessageId.START_FILE_UPLOAD_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class TransferChunkRequest(Message):
    """One chunk of a file upload.

    Attributes:
        running_crc32: CRC32 of everything sent so far, this chunk included.
        data: The chunk, at most ``InfoResponse.max_chunk_size`` bytes (and 65535 bytes).
    """

    message_id: ClassVar[MessageId] = MessageId.TRANSFER_CHUNK_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    running_crc32: int = field(metadata=_U32)
    data: bytes = field(metadata=_BLOB)


@dataclass(frozen=True, slots=True)
class TransferChunkResponse(Message):
    """Answer to :class:`TransferChunkRequest`.

    Attributes:
        status: Whether the hub accepted the chunk.
    """

    message_id: ClassVar[MessageId] = MessageId.TRANSFER_CHUNK_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class BeginFirmwareUpdateRequest(Message):
    """Install an uploaded firmware file.

    Attributes:
        file_sha: The file's SHA, 20 bytes.
        crc32: The file's CRC32.
    """

    message_id: ClassVar[MessageId] = MessageId.BEGIN_FIRMWARE_UPDATE_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    file_sha: bytes = field(metadata=_bytes(SHA_BYTES))
    crc32: int = field(metadata=_U32)


@dataclass(frozen=True, slots=True)
class BeginFirmwareUpdateResponse(Message):
    """Answer to :class:`BeginFirmwareUpdateRequest`.

    Attributes:
        status: Whether the hub accepted the request.
    """

    message_id: ClassVar[MessageId] = MessageId.BEGIN_FIRMWARE_UPDATE_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class SetHubNameRequest(Message):
    """Rename the hub.

    Attributes:
        name: The new name (``string[30]``: at most 29 bytes of UTF-8).
    """

    message_id: ClassVar[MessageId] = MessageId.SET_HUB_NAME_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    name: str = field(metadata=_string(30))


@dataclass(frozen=True, slots=True)
class SetHubNameResponse(Message):
    """Answer to :class:`SetHubNameRequest`.

    Attributes:
        status: Whether the hub accepted the request.
    """

    message_id: ClassVar[MessageId] = MessageId.SET_HUB_NAME_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class GetHubNameRequest(Message):
    """Ask for the hub's name."""

    message_id: ClassVar[MessageId] = MessageId.GET_HUB_NAME_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST


@dataclass(frozen=True, slots=True)
class GetHubNameResponse(Message):
    """The hub's name.

    Attributes:
        name: The name (``string[30]``: at most 29 bytes of UTF-8).
    """

    message_id: ClassVar[MessageId] = MessageId.GET_HUB_NAME_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    name: str = field(metadata=_string(30))


@dataclass(frozen=True, slots=True)
class DeviceUuidRequest(Message):
    """Ask for the hub's UUID."""

    message_id: ClassVar[MessageId] = MessageId.DEVICE_UUID_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST


@dataclass(frozen=True, slots=True)
class DeviceUuidResponse(Message):
    """The hub's UUID.

    Attributes:
        device_uuid: 16 raw bytes, in wire order.
    """

    message_id: ClassVar[MessageId] = MessageId.DEVICE_UUID_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    device_uuid: bytes = field(metadata=_bytes(UUID_BYTES))


@dataclass(frozen=True, slots=True)
class ProgramFlowRequest(Message):
    """Start or stop the program in a slot.

    Attributes:
        action: Start or stop.
        slot: Program slot, 0..19.
    """

    message_id: ClassVar[MessageId] = MessageId.PROGRAM_FLOW_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    action: ProgramAction = field(metadata=_ACTION)
    slot: int = field(metadata=_SLOT)


@dataclass(frozen=True, slots=True)
class ProgramFlowResponse(Message):
    """Answer to :class:`ProgramFlowRequest`.

    Attributes:
        status: Whether the hub accepted the request.
    """

    message_id: ClassVar[MessageId] = MessageId.PROGRAM_FLOW_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class ProgramFlowNotification(Message):
    """Sent by the hub when a program starts or stops (for example from its buttons).

    Attributes:
        action: Whether the program started or stopped.
    """

    message_id: ClassVar[MessageId] = MessageId.PROGRAM_FLOW_NOTIFICATION
    kind: ClassVar[MessageKind] = MessageKind.NOTIFICATION
    action: ProgramAction = field(metadata=_ACTION)


@dataclass(frozen=True, slots=True)
class ConsoleNotification(Message):
    """Text the running program printed.

    Attributes:
        text: The text (``string[256]``: at most 255 bytes of UTF-8), trailing NULs removed.
    """

    message_id: ClassVar[MessageId] = MessageId.CONSOLE_NOTIFICATION
    kind: ClassVar[MessageKind] = MessageKind.NOTIFICATION
    text: str = field(metadata=_string(256))


@dataclass(frozen=True, slots=True)
class DeviceNotificationRequest(Message):
    """Turn periodic :class:`DeviceNotification` messages on or off.

    Attributes:
        interval_ms: Time between notifications, in milliseconds (0 turns them off).
    """

    message_id: ClassVar[MessageId] = MessageId.DEVICE_NOTIFICATION_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    interval_ms: int = field(metadata=_U16_FIELD)


@dataclass(frozen=True, slots=True)
class DeviceNotificationResponse(Message):
    """Answer to :class:`DeviceNotificationRequest`.

    Attributes:
        status: Whether the hub accepted the request.
    """

    message_id: ClassVar[MessageId] = MessageId.DEVICE_NOTIFICATION_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


@dataclass(frozen=True, slots=True)
class TunnelMessage(Message):
    """Opaque data between the running program and the app; sent either way.

    Attributes:
        data: The payload, at most 65535 bytes (its format is not documented).
    """

    message_id: ClassVar[MessageId] = MessageId.TUNNEL_MESSAGE
    kind: ClassVar[MessageKind] = MessageKind.TUNNEL
    data: bytes = field(metadata=_BLOB)


@dataclass(frozen=True, slots=True)
class ClearSlotRequest(Message):
    """Delete the program in a slot.

    Attributes:
        slot: Program slot, 0..19.
    """

    message_id: ClassVar[MessageId] = MessageId.CLEAR_SLOT_REQUEST
    kind: ClassVar[MessageKind] = MessageKind.REQUEST
    slot: int = field(metadata=_SLOT)


@dataclass(frozen=True, slots=True)
class ClearSlotResponse(Message):
    """Answer to :class:`ClearSlotRequest`.

    Attributes:
        status: Whether the slot was cleared (the hub may refuse an empty slot).
    """

    message_id: ClassVar[MessageId] = MessageId.CLEAR_SLOT_RESPONSE
    kind: ClassVar[MessageKind] = MessageKind.RESPONSE
    status: ResponseStatus = field(metadata=_STATUS)


# --------------------------------------------------------------------------------------------
# Device messages (inside DeviceNotification)


@dataclass(frozen=True, slots=True)
class DeviceBattery(DeviceMessage):
    """Battery level (2 bytes on the wire).

    Attributes:
        level_percent: Charge, in percent (u8; documented 0..100).
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.BATTERY
    level_percent: int = field(metadata=_U8)


@dataclass(frozen=True, slots=True)
class DeviceImu(DeviceMessage):
    """The hub's motion sensor (21 bytes on the wire).

    The docs give no units for the angles and readings; they are passed on raw (i16).

    Attributes:
        face_up: The hub face pointing up.
        yaw_face: The hub face configured as the yaw face.
        yaw: Yaw, relative to the yaw face.
        pitch: Pitch, relative to the yaw face.
        roll: Roll, relative to the yaw face.
        accel_x: Accelerometer reading on the X axis.
        accel_y: Accelerometer reading on the Y axis.
        accel_z: Accelerometer reading on the Z axis.
        gyro_x: Gyroscope reading on the X axis.
        gyro_y: Gyroscope reading on the Y axis.
        gyro_z: Gyroscope reading on the Z axis.
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.IMU
    face_up: HubFace = field(metadata=_FACE)
    yaw_face: HubFace = field(metadata=_FACE)
    yaw: int = field(metadata=_I16)
    pitch: int = field(metadata=_I16)
    roll: int = field(metadata=_I16)
    accel_x: int = field(metadata=_I16)
    accel_y: int = field(metadata=_I16)
    accel_z: int = field(metadata=_I16)
    gyro_x: int = field(metadata=_I16)
    gyro_y: int = field(metadata=_I16)
    gyro_z: int = field(metadata=_I16)


@dataclass(frozen=True, slots=True)
class DeviceMatrix5x5(DeviceMessage):
    """The hub's 5x5 light matrix (26 bytes on the wire).

    Attributes:
        pixels: 25 pixel values (u8 each), in wire order.
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.MATRIX_5X5
    pixels: tuple[int, ...] = field(metadata=_pixels(25))


@dataclass(frozen=True, slots=True)
class DeviceMotor(DeviceMessage):
    """A motor on one port (12 bytes on the wire).

    Attributes:
        port: The port the motor is on.
        device_type: A :class:`MotorDeviceType` (or a plain int for other motors).
        absolute_position_deg: Absolute position, in degrees (documented -180..179).
        power: Applied power (i16; documented -10000..10000, unit not given).
        speed_percent: Speed, in percent (i8; documented -100..100).
        position_deg: Relative position, in degrees (i32).
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.MOTOR
    port: HubPort = field(metadata=_PORT)
    device_type: MotorDeviceType | int = field(
        metadata=_int("B", enum_type=MotorDeviceType, open_enum=True)
    )
    absolute_position_deg: int = field(metadata=_I16)
    power: int = field(metadata=_I16)
    speed_percent: int = field(metadata=_I8)
    position_deg: int = field(metadata=_I32)


@dataclass(frozen=True, slots=True)
class DeviceForce(DeviceMessage):
    """A force sensor on one port (4 bytes on the wire).

    Attributes:
        port: The port the sensor is on.
        force_percent: Measured force, in percent of full scale (u8; documented 0..100).
        pressed: Whether the sensor detects pressure.
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.FORCE
    port: HubPort = field(metadata=_PORT)
    force_percent: int = field(metadata=_U8)
    pressed: bool = field(metadata=_BOOL)


@dataclass(frozen=True, slots=True)
class DeviceColor(DeviceMessage):
    """A colour sensor on one port (9 bytes on the wire).

    Attributes:
        port: The port the sensor is on.
        color: The detected :class:`Color` (``Color.NONE``, -1, for none; a plain int if
            unknown).
        red: Raw red value (u16; documented 0..1023).
        green: Raw green value (u16; documented 0..1023).
        blue: Raw blue value (u16; documented 0..1023).
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.COLOR
    port: HubPort = field(metadata=_PORT)
    color: Color | int = field(metadata=_int("b", enum_type=Color, open_enum=True))
    red: int = field(metadata=_U16_FIELD)
    green: int = field(metadata=_U16_FIELD)
    blue: int = field(metadata=_U16_FIELD)


@dataclass(frozen=True, slots=True)
class DeviceDistance(DeviceMessage):
    """A distance sensor on one port (4 bytes on the wire).

    Attributes:
        port: The port the sensor is on.
        distance_mm: Measured distance, in millimetres (documented 40..2000), or -1 when
            no object is detected.
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.DISTANCE
    port: HubPort = field(metadata=_PORT)
    distance_mm: int = field(metadata=_I16)


@dataclass(frozen=True, slots=True)
class DeviceMatrix3x3(DeviceMessage):
    """A 3x3 colour light matrix on one port (11 bytes on the wire).

    Attributes:
        port: The port the matrix is on.
        pixels: 9 pixel values (u8 each): brightness in the high nibble, colour in the low.
    """

    device_id: ClassVar[DeviceMessageId] = DeviceMessageId.MATRIX_3X3
    port: HubPort = field(metadata=_PORT)
    pixels: tuple[int, ...] = field(metadata=_pixels(9))


DEVICE_MESSAGE_TYPES: Final[Mapping[int, type[DeviceMessage]]] = {
    cls.device_id: cls
    for cls in (
        DeviceBattery,
        DeviceImu,
        DeviceMatrix5x5,
        DeviceMotor,
        DeviceForce,
        DeviceColor,
        DeviceDistance,
        DeviceMatrix3x3,
    )
}
"""Device message classes by device message id."""


@dataclass(frozen=True, slots=True)
class DeviceNotification(Message):
    """Periodic readings of the hub and its devices (see :class:`DeviceNotificationRequest`).

    The docs do not say which device messages appear or in what order. Decoding reads device
    messages until the payload ends; if it meets a device id it does not know, the bytes from
    there on are kept in ``unparsed`` (their sizes are unknown, so they cannot be split).

    Attributes:
        devices: The device messages, in wire order.
        unparsed: Trailing bytes that start with an unknown device id (usually empty).
    """

    message_id: ClassVar[MessageId] = MessageId.DEVICE_NOTIFICATION
    kind: ClassVar[MessageKind] = MessageKind.NOTIFICATION
    devices: tuple[DeviceMessage, ...] = field(metadata=_meta(_Spec(_Kind.DEVICES)))
    unparsed: bytes = field(default=b"", metadata=_meta(_Spec(_Kind.RAW)))

    def __post_init__(self) -> None:
        """Check the fields, and that ``unparsed`` cannot be read as a known device message."""
        Message.__post_init__(self)
        if self.unparsed and self.unparsed[0] in DEVICE_MESSAGE_TYPES:
            raise LocalProtocolError(
                f"DeviceNotification.unparsed starts with known device id {self.unparsed[0]}"
            )
        size = sum(device.wire_size() for device in self.devices) + len(self.unparsed)
        if size > 0xFFFF:
            raise LocalProtocolError(f"DeviceNotification payload of {size} bytes is too long")

    def _pack_fields(self) -> bytes:
        body = b"".join(device.encode() for device in self.devices) + self.unparsed
        return _U16.pack(len(body)) + body

    @classmethod
    def _unpack_fields(cls, payload: bytes) -> _Record:
        if len(payload) < _U16.size:
            raise _remote("bad_length", "DeviceNotification is too short", payload)
        (size,) = _U16.unpack_from(payload)
        if len(payload) - _U16.size != size:
            raise _remote(
                "bad_length",
                f"DeviceNotification says {size} bytes but holds {len(payload) - _U16.size}",
                payload,
            )
        devices: list[DeviceMessage] = []
        offset = _U16.size
        while offset < len(payload):
            device_cls = DEVICE_MESSAGE_TYPES.get(payload[offset])
            if device_cls is None:
                break
            end = offset + device_cls.wire_size()
            if end > len(payload):
                raise _remote(
                    "bad_length", f"{device_cls.__name__} cut short in DeviceNotification", payload
                )
            device = device_cls._unpack_fields(payload[offset + 1 : end])
            assert isinstance(device, DeviceMessage)
            devices.append(device)
            offset = end
        return cls(tuple(devices), payload[offset:])


MESSAGE_TYPES: Final[Mapping[int, type[Message]]] = {
    cls.message_id: cls
    for cls in (
        InfoRequest,
        InfoResponse,
        StartFirmwareUploadRequest,
        StartFirmwareUploadResponse,
        StartFileUploadRequest,
        StartFileUploadResponse,
        TransferChunkRequest,
        TransferChunkResponse,
        BeginFirmwareUpdateRequest,
        BeginFirmwareUpdateResponse,
        SetHubNameRequest,
        SetHubNameResponse,
        GetHubNameRequest,
        GetHubNameResponse,
        DeviceUuidRequest,
        DeviceUuidResponse,
        ProgramFlowRequest,
        ProgramFlowResponse,
        ProgramFlowNotification,
        ConsoleNotification,
        DeviceNotificationRequest,
        DeviceNotificationResponse,
        TunnelMessage,
        DeviceNotification,
        ClearSlotRequest,
        ClearSlotResponse,
    )
}
"""Message classes by message id."""


def decode_message(data: bytes) -> Message:
    """Decode one unframed message (id byte first).

    Args:
        data: The message bytes, as returned by :func:`roboscript.drivers.spike.cobs.unpack`.

    Returns:
        The message.

    Raises:
        RemoteProtocolError: ``kind="bad_length"`` for an empty or wrongly sized message,
            ``kind="unknown_message"`` for an unknown id, ``kind="bad_value"`` for a field out
            of range.
    """
    if not data:
        raise _remote("bad_length", "empty message", data)
    cls = MESSAGE_TYPES.get(data[0])
    if cls is None:
        raise _remote("unknown_message", f"unknown message id 0x{data[0]:02x}", data)
    return cls.decode_payload(bytes(data[1:]))
