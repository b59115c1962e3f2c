"""The StackMod codec: bytes <-> :mod:`~roboscript.drivers.stackmod.messages` (sans-IO).

One class, :class:`StackModCodec`, serves both roles: with ``Role.HOST`` it sends
:class:`~roboscript.drivers.stackmod.messages.Get` and
:class:`~roboscript.drivers.stackmod.messages.Set` and receives
:class:`~roboscript.drivers.stackmod.messages.GetReply`; with ``Role.DEVICE`` the mirror.

Checksums
---------

The checksum byte is ``(sum(byte - 32) % 95) + 32``, so anything from space to ``~``. Two rules
exist and the codec speaks either one (never both at once, so that a corrupted packet is not
given two chances to pass):

* ``"seed"`` (the default): the sum runs over every byte from ``{`` to ``}`` inclusive, as the
  StackMod 0.9.1 document says; all six of its examples use it.
* ``"braces_excluded"``: the author's Arduino and Python code leave ``{`` and ``}`` out. Every
  checksum then differs by 89 (mod 95) from the seed's.

Framing
-------

The checksum may itself be ``{`` or ``}``, so packets are parsed by structure, never by searching
for braces: ``{``, the address (``0x40``-``0x5F``), ``?`` or ``$``, three upper-case letters,
data characters (digits, ``+``, ``-``), ``}`` and then exactly one checksum byte, whatever it is.
A byte that breaks this structure ends the candidate packet at once.

Faults
------

Every fault is counted in :attr:`StackModCodec.stats` and raised as
:class:`~roboscript.errors.RemoteProtocolError` after its bytes are consumed. Kinds:

* ``"garbage"``: bytes outside any packet (before a ``{``). A run of stray bytes counts once,
  however it is split across reads.
* ``"malformed"``: a byte breaks the packet structure, or the data field does not fit the
  command's format (wrong length, a sign where a digit belongs...).
* ``"overlong"``: no ``}`` within ``max_packet_bytes`` bytes of the ``{`` (the limit counts the
  braces and the checksum).
* ``"bad_checksum"``: a complete packet whose checksum byte is wrong. The checksum is checked
  before anything else in a complete packet.
* ``"unknown_command"``: a complete packet, correct checksum, but not one of the seven commands.
* ``"wrong_role"``: a valid packet this role never receives (a request at the host, a reply at
  the device).
* ``"read_only"``: a SET of a read-only sensor command (ULT, IRS, ANL) at the device.
* ``"out_of_range"``: a well formed value outside the command's range (e.g. ``MTR`` +150).

After any fault the codec drops every following byte up to the next ``{`` silently (adding them
to ``stats.dropped_bytes``): they belong to the same stretch of bad input, so one corrupted
packet gives one fault. After a good packet, stray bytes are a new ``"garbage"`` fault. Because
every decision depends only on the bytes already seen, the same stream yields the same messages
and faults however it is split into reads.

Buffering
---------

Once :meth:`StackModCodec.next_message` has returned ``None`` the buffer holds less than
``max_packet_bytes`` bytes (only the start of one candidate packet). Call it until it returns
``None`` after each :meth:`StackModCodec.receive_data`, as
:func:`~roboscript.codec.drain` does, and memory stays bounded whatever arrives.

The reference code's two-address form
-------------------------------------

The author's Python host sends ``{<module><0x70 'p'>$MTR1+139}`` and the header comment of the
Arduino library documents ``<SRC><DEST>``; neither order is followed consistently by the code.
A ``Role.DEVICE`` codec therefore accepts a second address byte in either position when it is
unambiguous:

* the seed's form has ``?`` or ``$`` right after the address; neither can be an address byte, so
  a packet with no action byte there is a two-address candidate;
* exactly one of the two address bytes must be a module address (``0x40``-``0x5F``), which
  becomes ``address``; the other must be in ``0x60``-``0x7A`` (`````..``z``, which holds the
  reference master address ``p`` and never ``?``, ``$``, ``{`` or ``}``), which becomes
  ``source``. Two module-range bytes (``{AX?...``) are ambiguous and refused as malformed.

A host codec sends the two-address form, module first as the Python host does, when a request
has a ``source``; it never accepts it (the reference device sends nothing back). Note that the
reference code uses the ``"braces_excluded"`` checksum and MTR values up to ±255, which this
codec refuses as ``"out_of_range"`` in a :class:`~roboscript.drivers.stackmod.messages.Set`
(the seed's range is ±100). A host codec sends the author's own packet as a
:class:`~roboscript.drivers.stackmod.messages.MotorPwm` (±255), which nothing decodes here: the
author's firmware is simulated by its own parser (:mod:`.reference_device`).

I2C framing
-----------

With ``framing="serial"`` (the default) packets follow one another on a byte stream. The
author's firmware listens on I2C only, so with ``framing="i2c"`` every packet :meth:`send`
returns is one I2C write: the register byte ``0x32`` first (the author's client writes it; the
firmware skips it because it is not ``{``), then the packet, at most 32 bytes in all (the
firmware's and Arduino's receive buffers). The caller must write each returned chunk as one
transaction: the firmware forgets a half packet when a transaction ends. A device codec with
``framing="i2c"`` drops a register byte found right before a ``{`` without counting a fault.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal, NoReturn, TypeAlias

from roboscript.codec import CodecStats, Role
from roboscript.drivers.stackmod.messages import (
    ADDRESS_MAX,
    ADDRESS_MIN,
    FORMATS,
    SOURCE_MAX,
    SOURCE_MIN,
    Command,
    Get,
    GetReply,
    Message,
    MotorPwm,
    Set,
)
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

__all__ = [
    "CHECKSUM_RULES",
    "FRAMINGS",
    "I2C_REGISTER",
    "I2C_WRITE_MAX_BYTES",
    "LONGEST_PACKET_BYTES",
    "ChecksumRule",
    "Framing",
    "StackModCodec",
    "braces_excluded_checksum",
    "checksum",
    "seed_checksum",
]

ChecksumRule: TypeAlias = Literal["seed", "braces_excluded"]
"""The two checksum rules: the seed's (braces included) and the reference code's."""
Framing: TypeAlias = Literal["serial", "i2c"]
"""How packets travel: back to back on a serial line, or one I2C write each."""
FRAMINGS: tuple[Framing, ...] = ("serial", "i2c")
"""Every :data:`Framing`."""
I2C_REGISTER = 0x32
"""The register byte the author's client writes before each packet (``'2'``)."""
I2C_WRITE_MAX_BYTES = 32
"""Longest I2C write the author's module receives, register byte included (Arduino's buffer)."""

_OPEN = 0x7B  # "{"
_CLOSE = 0x7D  # "}"
_GET = 0x3F  # "?"
_SET = 0x24  # "$"
_ACTIONS = frozenset({_GET, _SET})
_DATA_CHARS = frozenset(b"0123456789+-")
"""At most this many offending bytes are kept in a RemoteProtocolError's ``data``."""

_WIDEST_DATA = max(f.selector_digits + f.value_width for f in FORMATS.values())
LONGEST_PACKET_BYTES = len("{Xp$MTR}C") + _WIDEST_DATA
"""Length in bytes of the longest valid packet (two-address form, widest data): 14."""


def seed_checksum(frame: bytes) -> int:
    """Return the seed's checksum byte for ``frame``.

    Args:
        frame: The packet from ``{`` to ``}`` inclusive, without the checksum.

    Returns:
        ``(sum(b - 32 for every byte) % 95) + 32``, a byte value 32..126.
    """
    return sum(b - 32 for b in frame) % 95 + 32


def braces_excluded_checksum(frame: bytes) -> int:
    """Return the reference code's checksum byte for ``frame``: the seed's sum without braces.

    Args:
        frame: The packet from ``{`` to ``}`` inclusive (or without them), without the checksum.

    Returns:
        ``(sum(b - 32 for every byte except { and }) % 95) + 32``, a byte value 32..126.
    """
    return sum(b - 32 for b in frame if b not in (_OPEN, _CLOSE)) % 95 + 32


CHECKSUM_RULES: Mapping[str, Callable[[bytes], int]] = MappingProxyType(
    {"seed": seed_checksum, "braces_excluded": braces_excluded_checksum}
)
"""The checksum function of each :data:`ChecksumRule`."""


def checksum(frame: bytes, rule: ChecksumRule = "seed") -> int:
    """Return the checksum byte value (32..126) of ``frame`` under ``rule``.

    Args:
        frame: The packet from ``{`` to ``}`` inclusive, without the checksum.
        rule: ``"seed"`` or ``"braces_excluded"``.

    Raises:
        ValueError: ``rule`` is not a known rule.
    """
    try:
        function = CHECKSUM_RULES[rule]
    except KeyError:
        raise ValueError(f"unknown StackMod checksum rule {rule!r}") from None
    return function(frame)


def _is_address(byte: int) -> bool:
    return ADDRESS_MIN <= byte <= ADDRESS_MAX


def _is_source(byte: int) -> bool:
    return SOURCE_MIN <= byte <= SOURCE_MAX


@dataclass(frozen=True, slots=True)
class _Frame:
    """A structurally complete packet at the start of the buffer."""

    end: int
    """Index of the closing ``}``; the checksum byte is at ``end + 1``."""
    address: int
    source: int | None
    action: int
    command_at: int
    """Index of the first command letter."""


@dataclass(frozen=True, slots=True)
class _Bad:
    """A candidate packet refused before it was complete."""

    kind: str
    consume: int
    reason: str


class _RefusedError(Exception):
    """A complete packet refused (internal: turned into a RemoteProtocolError)."""

    def __init__(self, kind: str, reason: str) -> None:
        super().__init__(reason)
        self.kind = kind
        self.reason = reason


class StackModCodec:
    """Sans-IO StackMod codec for either side of the link.

    Args:
        role: ``Role.HOST`` sends Get/Set and receives GetReply; ``Role.DEVICE`` the mirror.
        checksum: ``"seed"`` (braces included, as the 0.9.1 document) or
            ``"braces_excluded"`` (as the author's Arduino and Python code).
        max_packet_bytes: Longest packet accepted, in bytes, braces and checksum included.
            32 matches the reference firmware's buffer.
        framing: ``"serial"`` (packets back to back) or ``"i2c"`` (each sent packet is one
            I2C write led by :data:`I2C_REGISTER`; see the module docstring).

    Attributes:
        role: The side this codec speaks for.
        checksum: The checksum rule in use.
        max_packet_bytes: Longest packet accepted, in bytes.
        framing: How packets travel.
        stats: Counts of messages, faults by kind, and dropped bytes.

    Raises:
        TypeError: ``role`` is not a :class:`~roboscript.codec.Role`.
        ValueError: ``checksum`` or ``framing`` is unknown, or ``max_packet_bytes`` is
            smaller than the longest valid packet (:data:`LONGEST_PACKET_BYTES`).
    """

    def __init__(
        self,
        role: Role,
        *,
        checksum: ChecksumRule = "seed",
        max_packet_bytes: int = 32,
        framing: Framing = "serial",
    ) -> None:
        if not isinstance(role, Role):
            raise TypeError(f"role must be a Role, got {role!r}")
        if checksum not in CHECKSUM_RULES:
            raise ValueError(f"unknown StackMod checksum rule {checksum!r}")
        if framing not in FRAMINGS:
            raise ValueError(f"unknown StackMod framing {framing!r}")
        if max_packet_bytes < LONGEST_PACKET_BYTES:
            raise ValueError(
                f"max_packet_bytes must be at least {LONGEST_PACKET_BYTES}, got {max_packet_bytes}"
            )
        self.role = role
        self.checksum: ChecksumRule = checksum
        self.max_packet_bytes = max_packet_bytes
        self.framing: Framing = framing
        self.stats = CodecStats()
        self._checksum_of = CHECKSUM_RULES[checksum]
        self._buffer = bytearray()
        # True after a fault: stray bytes up to the next "{" belong to that fault.
        self._skipping = False

    def __repr__(self) -> str:
        return (
            f"StackModCodec({self.role}, checksum={self.checksum!r}, "
            f"max_packet_bytes={self.max_packet_bytes}, framing={self.framing!r})"
        )

    @property
    def buffered(self) -> int:
        """Bytes received but not yet decoded or dropped."""
        return len(self._buffer)

    # -- sending ----------------------------------------------------------------------------

    def send(self, message: object) -> bytes:
        """Encode one message for the wire.

        Args:
            message: A :class:`Get`, :class:`Set` or :class:`MotorPwm` for a host codec, a
                :class:`GetReply` for a device codec.

        Returns:
            The whole packet, checksum included, e.g. ``b"{X?MTR2}X"``; with I2C framing, led
            by the register byte: ``b"2{Ep$MTR1+139}t"``.

        Raises:
            LocalProtocolError: ``message`` is not a message this role sends.
        """
        if self.role is Role.HOST:
            if isinstance(message, MotorPwm):
                return self._frame(self._motor_pwm(message))
            if not isinstance(message, (Get, Set)):
                raise LocalProtocolError(
                    f"a StackMod host sends Get, Set or MotorPwm, not {type(message).__name__}"
                )
        elif not isinstance(message, GetReply):
            raise LocalProtocolError(
                f"a StackMod device sends GetReply, not {type(message).__name__}"
            )
        fmt = FORMATS[message.command]
        packet = bytearray((_OPEN, message.address))
        if not isinstance(message, GetReply) and message.source is not None:
            packet.append(message.source)
        packet.append(_SET if isinstance(message, Set) else _GET)
        packet += message.command.value.encode("ascii")
        packet += fmt.format_selector(message.selector).encode("ascii")
        if not isinstance(message, Get):
            packet += fmt.format_value(message.value).encode("ascii")
        packet.append(_CLOSE)
        packet.append(self._checksum_of(bytes(packet)))
        return self._frame(bytes(packet))

    def _motor_pwm(self, message: MotorPwm) -> bytes:
        sign = "-" if message.pwm < 0 else "+"
        packet = bytearray((_OPEN, message.address, message.source, _SET))
        packet += f"MTR{message.motor}{sign}{abs(message.pwm):03d}".encode("ascii")
        packet.append(_CLOSE)
        packet.append(self._checksum_of(bytes(packet)))
        return bytes(packet)

    def _frame(self, packet: bytes) -> bytes:
        """The bytes of one write: the packet, led by the register byte on I2C."""
        if self.framing == "i2c":
            # Packets are at most LONGEST_PACKET_BYTES (14), so one write always fits in 32.
            return bytes((I2C_REGISTER,)) + packet
        return packet

    # -- receiving --------------------------------------------------------------------------

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire; decode them with :meth:`next_message`.

        Args:
            data: Any bytes; an empty chunk does nothing.
        """
        self._buffer += data

    def next_message(self) -> Message | None:
        """Return the next decoded message, or ``None`` if more bytes are needed.

        Returns:
            A :class:`GetReply` for a host codec, a :class:`Get` or :class:`Set` for a device
            codec, or ``None``.

        Raises:
            RemoteProtocolError: The bytes at the head of the buffer are garbage or a bad
                packet. They have been consumed and counted; call again to continue.
        """
        buffer = self._buffer
        register = self.framing == "i2c" and self.role is Role.DEVICE
        while buffer:
            if register and buffer[0] == I2C_REGISTER:
                if len(buffer) < 2:
                    return None  # a register byte or a stray one: the next byte decides
                if buffer[1] == _OPEN:
                    del buffer[0]
                    continue
            if buffer[0] != _OPEN:
                start = buffer.find(_OPEN)
                stray = len(buffer) if start < 0 else start
                if self._skipping:
                    del buffer[:stray]
                    self.stats.dropped_bytes += stray
                    continue
                self._fail("garbage", stray, f"{stray} stray byte(s) outside a packet")
            scan = self._scan()
            if scan is None:
                return None
            if isinstance(scan, _Bad):
                self._fail(scan.kind, scan.consume, scan.reason)
            size = scan.end + 2
            frame = bytes(buffer[: scan.end + 1])
            try:
                message = self._decode(frame, buffer[scan.end + 1], scan)
            except _RefusedError as refused:
                self._fail(refused.kind, size, refused.reason)
            del buffer[:size]
            self._skipping = False
            self.stats.messages += 1
            return message
        return None

    def _fail(self, kind: str, consume: int, reason: str) -> NoReturn:
        """Consume ``consume`` bytes, count them as one ``kind`` fault, and raise it.

        Raises:
            RemoteProtocolError: Always.
        """
        data = bytes(self._buffer[: min(consume, FAULT_SAMPLE_BYTES)])
        del self._buffer[:consume]
        self._skipping = True
        self.stats.fault(kind, consume)
        raise RemoteProtocolError(f"StackMod {kind}: {reason}: {data!r}", kind=kind, data=data)

    def _bad_at(self, index: int, what: str) -> _Bad:
        """Refuse the candidate because of the byte at ``index`` (kept if it is a ``{``)."""
        byte = self._buffer[index]
        consume = index if byte == _OPEN else index + 1
        return _Bad("malformed", consume, f"expected {what} at offset {index}, got {byte:#04x}")

    def _scan(self) -> _Frame | _Bad | None:
        """Check the structure of the candidate packet at the head of the buffer.

        Returns:
            A :class:`_Frame` once the packet and its checksum byte have arrived, a :class:`_Bad`
            as soon as a byte breaks the structure or the packet gets too long, or ``None`` if
            more bytes are needed.
        """
        buffer = self._buffer
        size = len(buffer)
        device = self.role is Role.DEVICE
        if size < 2:
            return None
        first = buffer[1]
        source: int | None = None
        if _is_address(first):
            if size < 3:
                return None
            second = buffer[2]
            address = first
            if second in _ACTIONS:
                action_at = 2
            elif device and _is_source(second):
                source, action_at = second, 3
            else:
                return self._bad_at(2, "'?' or '$'")
        elif device and _is_source(first):
            if size < 3:
                return None
            if not _is_address(buffer[2]):
                return self._bad_at(2, "a module address 0x40..0x5F")
            address, source, action_at = buffer[2], first, 3
        else:
            return self._bad_at(1, "an address 0x40..0x5F")
        if action_at == 3:
            if size < 4:
                return None
            if buffer[3] not in _ACTIONS:
                return self._bad_at(3, "'?' or '$'")
        command_at = action_at + 1
        for index in range(command_at, command_at + 3):
            if size <= index:
                return None
            if not 0x41 <= buffer[index] <= 0x5A:
                return self._bad_at(index, "a command letter A..Z")
        index = command_at + 3
        while True:
            # '}' at ``index`` makes the packet index + 2 bytes long.
            if index + 2 > self.max_packet_bytes:
                return _Bad(
                    "overlong", index, f"no '}}' within {self.max_packet_bytes} bytes of '{{'"
                )
            if size <= index:
                return None
            byte = buffer[index]
            if byte == _CLOSE:
                break
            if byte not in _DATA_CHARS:
                return self._bad_at(index, "a data character (0-9, +, -) or '}'")
            index += 1
        if size <= index + 1:
            return None
        return _Frame(index, address, source, buffer[action_at], command_at)

    def _decode(self, frame: bytes, check: int, scan: _Frame) -> Message:
        """Turn a structurally complete packet into a message.

        Args:
            frame: The packet from ``{`` to ``}`` inclusive.
            check: The checksum byte received after ``}``.
            scan: Where the parts of ``frame`` are.

        Raises:
            _RefusedError: The packet is not acceptable (checksum, command, format, role, range).
        """
        expected = self._checksum_of(frame)
        if check != expected:
            raise _RefusedError(
                "bad_checksum",
                f"checksum {check:#04x} under the {self.checksum!r} rule should be "
                f"{expected:#04x} ({chr(expected)!r})",
            )
        name = frame[scan.command_at : scan.command_at + 3].decode("ascii")
        try:
            command = Command(name)
        except ValueError:
            raise _RefusedError("unknown_command", f"unknown command {name!r}") from None
        fmt = FORMATS[command]
        data = frame[scan.command_at + 3 : -1].decode("ascii")
        has_value = len(data) == fmt.selector_digits + fmt.value_width
        if not has_value and len(data) != fmt.selector_digits:
            raise _RefusedError("malformed", f"{name} data {data!r} has the wrong length")
        if scan.action == _SET:
            if not has_value:
                raise _RefusedError("malformed", f"{name} SET without a value")
            kind: type[Message] = Set
        else:
            kind = GetReply if has_value else Get
        expected_kinds = (GetReply,) if self.role is Role.HOST else (Get, Set)
        if kind not in expected_kinds:
            raise _RefusedError(
                "wrong_role", f"a {self.role.value} does not receive {kind.__name__}"
            )
        selector_text = data[: fmt.selector_digits]
        if not selector_text.isdigit():
            raise _RefusedError("malformed", f"{name} selector {selector_text!r} is not digits")
        selector = int(selector_text)
        if kind is Get:
            return Get(scan.address, command, selector, scan.source)
        value_text = data[fmt.selector_digits :]
        value = fmt.parse_value(value_text)
        if value is None:
            raise _RefusedError("malformed", f"{name} value {value_text!r} is malformed")
        if kind is Set and not fmt.settable:
            raise _RefusedError("read_only", f"{name} is read-only and cannot be SET")
        if not fmt.value_ok(value):
            raise _RefusedError("out_of_range", f"{name} value {value} is out of range")
        if kind is Set:
            return Set(scan.address, command, selector, value, scan.source)
        return GetReply(scan.address, command, selector, value)
