"""The tunnel format: roboscript's commands to its agent on the SPIKE hub, and the replies.

The hub protocol's :class:`~roboscript.drivers.spike.messages.TunnelMessage` carries opaque
bytes between the host and the program running on the hub. roboscript's agent program
(``roboscript/drivers/spike/agent/hub_agent.py``) and the simulated hub both read this format;
the host driver writes it. The agent cannot import this module (it runs under MicroPython on
the hub and is uploaded alone), so it has its own reader of the same bytes; the tests check
the two against each other.

Every **record** is::

    u8 op    u8 size    size bytes of arguments (little-endian)

A TunnelMessage holds one or more whole records. Sizes are fixed per op except for text.

Host -> hub (commands, op < 0x80):

====  ==================  ===================================  ==============================
op    record              arguments                            on the hub
====  ==================  ===================================  ==============================
0x01  VersionQuery        --                                   reply :class:`Version`
0x02  Configure           u8 left port, u8 right port (0..5)   ``motor_pair.pair``
0x03  Tank                i16 left, i16 right (deg/s),         ``motor_pair.move_tank``; stop
                          u16 acceleration (deg/s^2),          if no motion command comes
                          u16 watchdog (ms, 0 = none)          within the watchdog time
0x04  TankForDegrees      u8 seq, i32 degrees, i16 left,       ``move_tank_for_degrees``,
                          i16 right (deg/s)                    then reply :class:`MoveDone`
0x05  Power               i16 left, i16 right (-10000..10000   ``motor.set_duty_cycle``;
                          duty), u16 watchdog (ms)             watchdog as for Tank
0x06  Beep                u16 frequency (Hz), u16 duration     ``sound.beep``
                          (ms), u8 volume (0..100 %)
0x07  ShowText            UTF-8 text, 0..200 bytes             ``light_matrix.write``
0x08  ClearDisplay        --                                   ``light_matrix.clear``
0x09  Stop                --                                   brake both drive motors,
                                                               cancel a move
0x0A  Watch               u8 colour sensor port (0..5, 0xFF    reply :class:`Report` every
                          none), u16 interval (ms, 0 = off)    interval
0x0B  MotorRun            u8 port, i16 speed (deg/s), u16      ``motor.run``; watchdog as
                          watchdog (ms, 0 = none)              for Tank (a watchdog that
                                                               fires stops every motor)
0x0C  MotorForDegrees     u8 seq, u8 port, i32 degrees         ``motor.run_for_degrees``,
                          (signed), u16 speed (deg/s)          then reply :class:`MoveDone`
0x0D  MotorStop           u8 port                              ``motor.stop`` (brake)
====  ==================  ===================================  ==============================

Hub -> host (replies, op >= 0x80):

====  ==========  ============================================================
0x81  Version     UTF-8 version text, 1..64 bytes (the agent's ``AGENT_VERSION``)
0x82  MoveDone    u8 seq, u8 :class:`MoveStatus`
0x83  Report      u8 reflection (0..100 %, 0xFF none), u8 buttons (bit 0 left, bit 1 right)
0x8F  Refused     u8 op of the refused record, u8 :class:`RefuseReason`
====  ==========  ============================================================

Signs: wheel speeds, duties and degrees are positive **forward** for both wheels (the hub's
``motor_pair`` knows that the left motor of a driving base is mounted mirrored).

Decoding never raises anything but :class:`~roboscript.errors.RemoteProtocolError`, with
``kind`` one of ``"tunnel_unknown"`` (an op this side does not receive), ``"tunnel_length"``
(wrong size for the op, or a record cut short at the end of a message), ``"tunnel_value"``
(bad text or enum value) and ``"tunnel_role"`` (a command sent to the host or a reply sent
to the hub).

Example: ``Tank(300, 300, 5000, 1500)`` is ``03 08 2c 01 2c 01 88 13 dc 05``.
"""

from __future__ import annotations

import enum
import re
import struct
from collections.abc import Iterator
from dataclasses import astuple, dataclass
from typing import ClassVar, Final

from roboscript.codec import Role
from roboscript.errors import LocalProtocolError, RemoteProtocolError

__all__ = [
    "BUTTON_BITS",
    "COMMAND_TYPES",
    "MAX_TEXT_BYTES",
    "MAX_VERSION_BYTES",
    "MIN_WATCH_MS",
    "NO_PORT",
    "NO_REFLECTION",
    "PORT_COUNT",
    "REPLY_TYPES",
    "Beep",
    "ClearDisplay",
    "Configure",
    "MotorForDegrees",
    "MotorRun",
    "MotorStop",
    "MoveDone",
    "MoveStatus",
    "Power",
    "Record",
    "RefuseReason",
    "Refused",
    "Report",
    "ShowText",
    "Stop",
    "Tank",
    "TankForDegrees",
    "TunnelDecoder",
    "Version",
    "VersionQuery",
    "Watch",
    "agent_version_of",
    "decode_records",
    "encode",
]

PORT_COUNT: Final = 6
"""Hub ports A..F, numbered 0..5."""
MAX_TEXT_BYTES: Final = 200
"""Longest :class:`ShowText` text, in bytes of UTF-8."""
MAX_VERSION_BYTES: Final = 64
"""Longest :class:`Version` text, in bytes of UTF-8."""
MAX_DUTY: Final = 10000
"""Full duty in :class:`Power` (the hub's ``set_duty_cycle`` range)."""
NO_PORT: Final = 0xFF
""":class:`Watch` colour port meaning "no colour sensor"."""
NO_REFLECTION: Final = 0xFF
""":class:`Report` reflection meaning "no reading" (no sensor on the port, or none asked)."""
BUTTON_BITS: Final = {"left": 0x01, "right": 0x02}
"""The hub buttons a :class:`Report` carries, by bit. The centre button is not among them: on
App 3 firmware it stops the running program, so a program never sees it pressed."""
MIN_WATCH_MS: Final = 10
"""Shortest :class:`Watch` interval, ms."""

_HEADER: Final = 2
_AGENT_VERSION: Final = re.compile(rb'^AGENT_VERSION = "([^"\r\n]{1,64})"', re.MULTILINE)
_REPLY_BASE: Final = 0x80


class MoveStatus(enum.IntEnum):
    """How a :class:`TankForDegrees` move ended (the agent maps the firmware's constants)."""

    DONE = 0
    """The move reached its angle (``motor.READY``)."""
    STALLED = 1
    """A motor stalled (``motor.STALLED``)."""
    CANCELLED = 2
    """Another motion command or Stop interrupted it (``motor.CANCELED``)."""
    FAILED = 3
    """Any other firmware status (``motor.ERROR``, ``motor.DISCONNECTED``, ...)."""


class RefuseReason(enum.IntEnum):
    """Why the hub refused a record."""

    UNKNOWN_COMMAND = 1
    BAD_LENGTH = 2
    BAD_VALUE = 3
    NOT_CONFIGURED = 4
    """A motion command arrived before :class:`Configure`."""


class Record:
    """Base of every tunnel record (commands and replies).

    Attributes:
        op: The record's op byte (class attribute).
    """

    __slots__ = ()
    op: ClassVar[int]
    _layout: ClassVar[struct.Struct | None] = None  # None: the arguments are UTF-8 text

    def __post_init__(self) -> None:
        try:
            self._normalise()
            args = self._pack()
        except (struct.error, UnicodeEncodeError, TypeError, ValueError) as exc:
            raise LocalProtocolError(f"{type(self).__name__}: {exc}") from None
        problem = self._check(args)
        if problem:
            raise LocalProtocolError(f"{type(self).__name__}: {problem}")

    def _pack(self) -> bytes:
        layout = self._layout
        if layout is None:
            text = astuple(self)[0]  # type: ignore[call-overload]
            if not isinstance(text, str):
                raise TypeError(f"text must be a str, not {type(text).__name__}")
            return text.encode("utf-8")
        return layout.pack(*astuple(self))  # type: ignore[call-overload]

    def _normalise(self) -> None:
        """Convert field values to their types (enums); raise ValueError if impossible."""

    def _check(self, args: bytes) -> str | None:
        """Return what is wrong with the record beyond its struct ranges, or ``None``."""
        return None

    def encode(self) -> bytes:
        """Return the record's bytes: op, size, arguments."""
        args = self._pack()
        return bytes((self.op, len(args))) + args

    @classmethod
    def from_args(cls, args: bytes) -> Record:
        """Build the record from its argument bytes.

        Raises:
            RemoteProtocolError: ``tunnel_length`` or ``tunnel_value``.
        """
        layout = cls._layout
        if layout is not None and len(args) != layout.size:
            raise _remote(
                "tunnel_length",
                f"{cls.__name__} needs {layout.size} argument bytes, not {len(args)}",
                args,
            )
        try:
            text_or_fields = (args.decode("utf-8"),) if layout is None else layout.unpack(args)
            record = cls(*text_or_fields)
        except UnicodeDecodeError:
            raise _remote("tunnel_value", f"{cls.__name__} text is not UTF-8", args) from None
        except (LocalProtocolError, ValueError) as exc:
            raise _remote("tunnel_value", str(exc), args) from None
        return record


def _remote(kind: str, message: str, data: bytes) -> RemoteProtocolError:
    return RemoteProtocolError(message, kind=kind, data=data)


def _port_problem(*ports: int) -> str | None:
    bad = [port for port in ports if not 0 <= port < PORT_COUNT]
    return f"port {bad[0]} is not 0..{PORT_COUNT - 1}" if bad else None


# --------------------------------------------------------------------------------- commands


@dataclass(frozen=True, slots=True)
class VersionQuery(Record):
    """Ask the agent for its version."""

    op: ClassVar[int] = 0x01
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<")


@dataclass(frozen=True, slots=True)
class Configure(Record):
    """Pair the drive motors (``motor_pair.pair(PAIR_1, left, right)``).

    Attributes:
        left_port: Port of the left drive motor, 0..5 (A..F).
        right_port: Port of the right drive motor, 0..5.
    """

    op: ClassVar[int] = 0x02
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BB")
    left_port: int
    right_port: int

    def _check(self, args: bytes) -> str | None:
        if self.left_port == self.right_port:
            return "left and right motors must be on different ports"
        return _port_problem(self.left_port, self.right_port)


@dataclass(frozen=True, slots=True)
class Tank(Record):
    """Hold both wheel speeds with the hub's own speed control.

    Attributes:
        left_deg_s: Left wheel speed, motor degrees per second; positive forward.
        right_deg_s: Right wheel speed, degrees per second; positive forward.
        acceleration_deg_s2: Ramp to the new speeds, degrees per second squared (0..10000).
        watchdog_ms: Stop both motors if no motion command follows within this many
            milliseconds (0: never), so a host that dies cannot leave the robot driving.
    """

    op: ClassVar[int] = 0x03
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<hhHH")
    left_deg_s: int
    right_deg_s: int
    acceleration_deg_s2: int
    watchdog_ms: int

    def _check(self, args: bytes) -> str | None:
        if self.acceleration_deg_s2 > 10000:
            return f"acceleration {self.acceleration_deg_s2} is above 10000 deg/s^2"
        return None


@dataclass(frozen=True, slots=True)
class TankForDegrees(Record):
    """Turn the wheels by an angle at fixed speeds, then brake and report :class:`MoveDone`.

    Attributes:
        seq: Sequence number echoed in :class:`MoveDone`, 0..255.
        degrees: Motor degrees to turn, counted on the faster wheel; positive.
        left_deg_s: Left wheel speed, degrees per second; positive forward.
        right_deg_s: Right wheel speed, degrees per second; positive forward.
    """

    op: ClassVar[int] = 0x04
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<Bihh")
    seq: int
    degrees: int
    left_deg_s: int
    right_deg_s: int

    def _check(self, args: bytes) -> str | None:
        if self.degrees < 0:
            return "degrees must not be negative (reverse with negative speeds)"
        return None


@dataclass(frozen=True, slots=True)
class Power(Record):
    """Drive both motors at a duty, without speed control.

    Attributes:
        left_duty: Left motor duty, -10000..10000; positive forward.
        right_duty: Right motor duty, -10000..10000; positive forward.
        watchdog_ms: As for :class:`Tank`.
    """

    op: ClassVar[int] = 0x05
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<hhH")
    left_duty: int
    right_duty: int
    watchdog_ms: int

    def _check(self, args: bytes) -> str | None:
        if max(abs(self.left_duty), abs(self.right_duty)) > MAX_DUTY:
            return f"duty must be within -{MAX_DUTY}..{MAX_DUTY}"
        return None


@dataclass(frozen=True, slots=True)
class Beep(Record):
    """Play a tone on the hub's speaker.

    Attributes:
        frequency_hz: Pitch, hertz.
        duration_ms: Length, milliseconds.
        volume_percent: Loudness, 0..100.
    """

    op: ClassVar[int] = 0x06
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<HHB")
    frequency_hz: int
    duration_ms: int
    volume_percent: int

    def _check(self, args: bytes) -> str | None:
        if self.volume_percent > 100:
            return f"volume {self.volume_percent} is above 100 %"
        return None


@dataclass(frozen=True, slots=True)
class ShowText(Record):
    """Scroll text across the 5x5 light matrix.

    Attributes:
        text: The text, at most 200 bytes of UTF-8.
    """

    op: ClassVar[int] = 0x07
    text: str

    def _check(self, args: bytes) -> str | None:
        if len(args) > MAX_TEXT_BYTES:
            return f"text of {len(args)} bytes is longer than {MAX_TEXT_BYTES}"
        return None


@dataclass(frozen=True, slots=True)
class ClearDisplay(Record):
    """Blank the light matrix."""

    op: ClassVar[int] = 0x08
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<")


@dataclass(frozen=True, slots=True)
class Stop(Record):
    """Brake both drive motors now and cancel a :class:`TankForDegrees` move."""

    op: ClassVar[int] = 0x09
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<")


@dataclass(frozen=True, slots=True)
class Watch(Record):
    """Report the colour sensor's reflection and the hub buttons every ``interval_ms``.

    Attributes:
        color_port: Port of the colour sensor, 0..5, or :data:`NO_PORT` for none.
        interval_ms: Time between two :class:`Report` replies, ms (10..65535), or 0 to stop.
    """

    op: ClassVar[int] = 0x0A
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BH")
    color_port: int
    interval_ms: int

    def _check(self, args: bytes) -> str | None:
        if 0 < self.interval_ms < MIN_WATCH_MS:
            return f"interval {self.interval_ms} ms is below {MIN_WATCH_MS} ms"
        return None if self.color_port == NO_PORT else _port_problem(self.color_port)


@dataclass(frozen=True, slots=True)
class MotorRun(Record):
    """Run one motor (not a drive motor) at a speed until told otherwise (``motor.run``).

    Attributes:
        port: The motor's port, 0..5.
        speed_deg_s: Speed, degrees per second; positive turns the motor clockwise (seen
            from its face, as the hub counts).
        watchdog_ms: As for :class:`Tank`: every motor stops if no motion command follows
            within this many milliseconds (0: never).
    """

    op: ClassVar[int] = 0x0B
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BhH")
    port: int
    speed_deg_s: int
    watchdog_ms: int

    def _check(self, args: bytes) -> str | None:
        return _port_problem(self.port)


@dataclass(frozen=True, slots=True)
class MotorForDegrees(Record):
    """Turn one motor by an angle, then brake and report :class:`MoveDone`.

    Attributes:
        seq: Sequence number echoed in :class:`MoveDone`, 0..255 (shared with
            :class:`TankForDegrees`).
        port: The motor's port, 0..5.
        degrees: Angle to turn, degrees; negative turns the other way.
        speed_deg_s: Speed, degrees per second (positive).
    """

    op: ClassVar[int] = 0x0C
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BBiH")
    seq: int
    port: int
    degrees: int
    speed_deg_s: int

    def _check(self, args: bytes) -> str | None:
        if self.speed_deg_s == 0:
            return "speed must not be 0"
        return _port_problem(self.port)


@dataclass(frozen=True, slots=True)
class MotorStop(Record):
    """Brake one motor and cancel its :class:`MotorForDegrees` move.

    Attributes:
        port: The motor's port, 0..5.
    """

    op: ClassVar[int] = 0x0D
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<B")
    port: int

    def _check(self, args: bytes) -> str | None:
        return _port_problem(self.port)


# ---------------------------------------------------------------------------------- replies


@dataclass(frozen=True, slots=True)
class Version(Record):
    """The agent's version.

    Attributes:
        text: The agent's ``AGENT_VERSION``, 1..64 bytes of UTF-8.
    """

    op: ClassVar[int] = 0x81
    text: str

    def _check(self, args: bytes) -> str | None:
        if not 1 <= len(args) <= MAX_VERSION_BYTES:
            return f"version must be 1..{MAX_VERSION_BYTES} bytes, not {len(args)}"
        return None


@dataclass(frozen=True, slots=True)
class MoveDone(Record):
    """A :class:`TankForDegrees` move ended.

    Attributes:
        seq: The move's sequence number.
        status: How it ended.
    """

    op: ClassVar[int] = 0x82
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BB")
    seq: int
    status: MoveStatus

    def _normalise(self) -> None:
        object.__setattr__(self, "status", MoveStatus(self.status))


@dataclass(frozen=True, slots=True)
class Report(Record):
    """What the agent reads itself: the colour sensor's reflection and the hub buttons.

    The firmware's DeviceNotification carries the colour sensor's colour and RGB but not its
    reflection, and no hub buttons, so the agent reads those (``color_sensor.reflection``,
    ``button.pressed``) and sends them every :class:`Watch` interval.

    Attributes:
        reflection_percent: Light reflected by the floor, 0 (black) to 100 (white), or
            :data:`NO_REFLECTION`.
        buttons: Pressed buttons, a sum of :data:`BUTTON_BITS`.
    """

    op: ClassVar[int] = 0x83
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BB")
    reflection_percent: int
    buttons: int

    def _check(self, args: bytes) -> str | None:
        if self.reflection_percent > 100 and self.reflection_percent != NO_REFLECTION:
            return f"reflection {self.reflection_percent} is above 100 %"
        if self.buttons & ~sum(BUTTON_BITS.values()):
            return f"unknown button bits 0x{self.buttons:02x}"
        return None

    def pressed(self) -> frozenset[str]:
        """The names of the buttons pressed."""
        return frozenset(name for name, bit in BUTTON_BITS.items() if self.buttons & bit)


@dataclass(frozen=True, slots=True)
class Refused(Record):
    """The hub could not act on a record.

    Attributes:
        refused_op: The op byte of the refused record.
        reason: Why.
    """

    op: ClassVar[int] = 0x8F
    _layout: ClassVar[struct.Struct | None] = struct.Struct("<BB")
    refused_op: int
    reason: RefuseReason

    def _normalise(self) -> None:
        object.__setattr__(self, "reason", RefuseReason(self.reason))


COMMAND_TYPES: Final[dict[int, type[Record]]] = {
    cls.op: cls
    for cls in (
        VersionQuery,
        Configure,
        Tank,
        TankForDegrees,
        Power,
        Beep,
        ShowText,
        ClearDisplay,
        Stop,
        Watch,
        MotorRun,
        MotorForDegrees,
        MotorStop,
    )
}
"""Commands (host -> hub) by op."""
REPLY_TYPES: Final[dict[int, type[Record]]] = {
    cls.op: cls for cls in (Version, MoveDone, Report, Refused)
}
"""Replies (hub -> host) by op."""


def agent_version_of(source: bytes) -> str | None:
    """The ``AGENT_VERSION = "..."`` a program's source defines, or ``None`` if it has none.

    The host compares it with the hub's answer to :class:`VersionQuery`; the simulated hub
    uses it to recognise an uploaded agent.
    """
    match = _AGENT_VERSION.search(source)
    return None if match is None else match.group(1).decode("utf-8", "replace")


def encode(*records: Record) -> bytes:
    """Return the bytes of ``records``, in order, for one TunnelMessage."""
    return b"".join(record.encode() for record in records)


class TunnelDecoder:
    """Reads records from tunnel bytes for one side of the link.

    The host decodes replies, the hub decodes commands. Bytes may arrive split anywhere;
    :meth:`next_record` returns ``None`` until a whole record is buffered. At most one
    unfinished record (257 bytes) is ever held.

    Args:
        role: ``Role.HOST`` (decode replies) or ``Role.DEVICE`` (decode commands).
    """

    def __init__(self, role: Role) -> None:
        self.role = role
        self._types = REPLY_TYPES if role is Role.HOST else COMMAND_TYPES
        self._buffer = bytearray()
        self.last_op: int | None = None
        """The op byte of the last record consumed, good or bad (to refuse it by op)."""

    @property
    def pending_bytes(self) -> int:
        """Bytes of an unfinished record."""
        return len(self._buffer)

    def feed(self, data: bytes) -> None:
        """Buffer received tunnel bytes."""
        self._buffer += data

    def next_record(self) -> Record | None:
        """Return the next whole record, or ``None`` if more bytes are needed.

        Raises:
            RemoteProtocolError: For a bad record, which has been consumed: call again to
                continue after it.
        """
        buffer = self._buffer
        if len(buffer) < _HEADER:
            return None
        op, size = buffer[0], buffer[1]
        end = _HEADER + size
        if len(buffer) < end:
            return None
        args = bytes(buffer[_HEADER:end])
        del buffer[:end]
        self.last_op = op
        cls = self._types.get(op)
        if cls is None:
            if op in COMMAND_TYPES or op in REPLY_TYPES:
                raise _remote(
                    "tunnel_role", f"{self.role.value} does not receive op 0x{op:02x}", args
                )
            raise _remote("tunnel_unknown", f"unknown tunnel op 0x{op:02x}", args)
        return cls.from_args(args)

    def flush(self) -> RemoteProtocolError | None:
        """End of a message: drop an unfinished record and return it as a fault (or ``None``)."""
        if not self._buffer:
            return None
        data = bytes(self._buffer)
        self._buffer.clear()
        return _remote("tunnel_length", f"tunnel record cut short after {len(data)} bytes", data)


def decode_records(data: bytes, role: Role) -> Iterator[Record | RemoteProtocolError]:
    """Yield the records of one TunnelMessage payload, and each fault as its exception.

    Faults are yielded, not raised, so one bad record never hides the good ones after it; a
    record cut short by the end of ``data`` is a ``tunnel_length`` fault.

    Args:
        data: The TunnelMessage payload.
        role: The side reading it (see :class:`TunnelDecoder`).
    """
    decoder = TunnelDecoder(role)
    decoder.feed(data)
    while True:
        try:
            record = decoder.next_record()
        except RemoteProtocolError as fault:
            yield fault
            continue
        if record is None:
            break
        yield record
    cut_short = decoder.flush()
    if cut_short is not None:
        yield cut_short
