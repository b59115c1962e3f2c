"""Sans-IO codec of the PLEN2 serial protocol, firmware 1.4.2, for both roles: the framing.

Split the way h11 splits readers and writers: :mod:`~roboscript.drivers.plen.commands` writes
commands (host) and says how the firmware reads each one (device);
:mod:`~roboscript.drivers.plen.replies` writes replies (device) and reads them (host); this
module frames both byte streams and counts what it drops. Motion files, which never cross the
wire, are :mod:`~roboscript.drivers.plen.motionfile`'s.

Requests (host -> device) are fixed-length ASCII commands with no separator and no line ending:
a header character from ``$#><``, a two-letter command, then a fixed number of argument
characters. Numbers are zero-padded hex; 3-digit values are 12-bit two's complement
(``f9c`` = −100, ``fff`` = −1) and the 4-digit motion frame values are int16. The host encodes
command letters in upper case and hex digits in lower case, as plen-ControlServer does; the
device accepts either case.

Only the getters ``<JS``, ``<MO`` and ``<VI`` are answered. Replies are tab-indented JSON
printed line by line with CRLF line endings, and nothing marks their end.

DEVICE role (decodes commands, encodes replies) mirrors the firmware's parser, a fixed-length
state machine:

1. Between commands, CR and LF are dropped silently (not counted). Any other byte that is not
   a header character is garbage: a run of such bytes is one ``"garbage"`` fault, raised when
   the run ends (at the next header character or CR/LF), so fault counts do not depend on how
   the bytes were chunked.
2. The two command characters are read, then matched case-insensitively against the commands
   of that header; no match is a ``"bad_command"`` fault that consumes header and command.
3. The argument characters are read, all of them, whatever they are (a CR/LF inside a command
   is an argument character), and only then checked as the firmware's ``HexStringParser``
   checks them: the first and every one before the first NUL must be hex digits (the check
   stops at a NUL; the values are then read from every byte, as ``hexbytes2uint16`` reads
   them), except in ``>MH``, which the firmware does not check at all. A bad one is a
   ``"bad_argument"`` fault that consumes the whole command, just as the firmware resets to
   READY.
4. A well-formed command whose values our messages cannot hold is an ``"out_of_range"`` fault.
   The firmware ignores those too (a joint id above 23, a slot above 89, ``>HO``/``>MA``/``>MI``
   beyond ±900, a header with 0 or more than 20 frames) or stores values that are meaningless
   (a loop frame above 19, a transition under 32 ms, a name with control characters or ``"``).
   The exceptions are ``$AN`` and ``$AD``: the firmware clamps them, so they decode with the
   value clamped to ±900 (``$AN``) or ±1800 (``$AD``) and act exactly as on the robot; the seed's
   ``$an0a3e8`` (1000) decodes as ``SetAngle(10, 900)``.

HOST role (encodes commands, decodes replies): whitespace between replies is dropped; a reply
starts at ``{`` or ``[`` and ends when its brackets balance outside strings, then it is parsed
with :func:`json.loads`. Its type is **inferred from its shape** (an array is ``<JS``, an object
with ``slot``/``frames`` is ``<MO``, one with ``version`` is ``<VI``), so the codec keeps no
state about what was asked; since replies carry no request id, the driver keeps one getter in
flight at a time. Faults: ``"garbage"`` (bytes outside a reply), ``"overlong"`` (a reply longer
than ``max_reply_bytes``: its first ``max_reply_bytes`` are dropped with the fault and the rest
are dropped silently until its brackets balance), ``"bad_json"`` (not JSON, or nested deeper
than any reply), ``"bad_reply"`` (JSON that is not a valid reply).

Because a reply has no terminator, a truncated reply would swallow the next one. The timeout
belongs to the driver: when a getter's reply is late it checks :attr:`PlenCodec.in_progress`
or :meth:`PlenCodec.pending_bytes` and calls :meth:`PlenCodec.reset` to abandon the partial
reply (counted as an ``"abandoned"`` fault).
"""

from __future__ import annotations

import json
import re
from typing import NoReturn

from roboscript.codec import CodecStats, ProfileLike, Role
from roboscript.drivers.plen.commands import (
    COMMANDS,
    BadArgumentError,
    CommandSpec,
    encode_command,
    firmware_reads_as_hex,
)
from roboscript.drivers.plen.messages import (
    Command,
    JointSettingsReply,
    MotionReply,
    PlenMessage,
    Reply,
    VersionReply,
)
from roboscript.drivers.plen.replies import encode_reply, reply_from_json
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

__all__ = ["DEFAULT_MAX_REPLY_BYTES", "PlenCodec", "codec_for"]

DEFAULT_MAX_REPLY_BYTES = 65536
"""Default limit of one reply; a full 20-frame ``<MO`` dump is about 25 kB."""

_MAX_DEPTH = 16
"""Deepest bracket nesting accepted in a reply (a ``<MO`` dump nests 5 deep)."""


# --------------------------------------------------------------------------------------------
# Framing
# --------------------------------------------------------------------------------------------

_DEVICE_START = re.compile(rb"[$#<>\r\n]")
_CRLF = b"\r\n"

# Host-side scanning of JSON replies.
_HOST_START = re.compile(rb"[ \t\r\n{\[]")
_NOT_SPACE = re.compile(rb"[^ \t\r\n]")
_STRUCTURE = re.compile(rb'["{}\[\]]')
_STRING_SPECIAL = re.compile(rb'["\\]')
_OPENERS = b"{["
_SPACE = b" \t\r\n"

_INCOMPLETE = -1
_TOO_DEEP = -2


def _reject_constant(name: str) -> object:
    raise ValueError(f"{name} is not JSON")


# --------------------------------------------------------------------------------------------
# The codec
# --------------------------------------------------------------------------------------------


class PlenCodec:
    """PLEN2 codec for one side of the link (sans-IO).

    ``Role.HOST`` encodes commands and decodes the three JSON replies; ``Role.DEVICE`` decodes
    commands (mirroring the firmware's parser) and encodes replies. See the module docstring
    for the fault kinds.

    Attributes:
        role: The side this codec speaks for.
        stats: Counts of decoded messages and faults.
        max_reply_bytes: Longest reply the host accepts, in bytes.
    """

    def __init__(self, role: Role, *, max_reply_bytes: int = DEFAULT_MAX_REPLY_BYTES) -> None:
        """Create a codec.

        Args:
            role: ``Role.HOST`` or ``Role.DEVICE``.
            max_reply_bytes: Longest reply the host accepts, in bytes (at least 2).

        Raises:
            ValueError: ``max_reply_bytes`` is below 2.
        """
        if max_reply_bytes < 2:
            raise ValueError(f"max_reply_bytes must be at least 2, not {max_reply_bytes}")
        self.role = role
        self.stats = CodecStats()
        self.max_reply_bytes = max_reply_bytes
        self._buffer = bytearray()
        # A run of garbage bytes waiting for its end (both roles).
        self._junk_count = 0
        self._junk_sample = bytearray()
        # Device: the command being read (header, command, arguments so far).
        self._attempt = bytearray()
        self._spec: CommandSpec | None = None
        # Host: where the reply at the start of the buffer has been scanned to.
        self._in_reply = False
        self._skipping = False
        self._scan_pos = 0
        self._depth = 0
        self._in_string = False
        self._escape = False

    # ---------------------------------------------------------------------------- the verbs

    def send(self, message: object) -> bytes:
        """Encode ``message`` for the wire.

        The host sends commands (see :func:`encode_command`), the device sends replies (see
        :func:`encode_reply`).

        Raises:
            LocalProtocolError: ``message`` is not something this role sends.
        """
        if self.role is Role.HOST:
            if isinstance(message, (JointSettingsReply, MotionReply, VersionReply)):
                raise LocalProtocolError(f"the host does not send replies: {message!r}")
            return encode_command(message)
        return encode_reply(message)

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire; :meth:`next_message` decodes them.

        Once :meth:`next_message` has returned ``None``, at most one partial command (107
        bytes) or one partial reply (``max_reply_bytes``) stays buffered.
        """
        self._buffer += data

    def next_message(self) -> PlenMessage | None:
        """Return the next decoded message, or ``None`` if more bytes are needed.

        Raises:
            RemoteProtocolError: A bad command, reply or run of garbage was consumed; call
                again to continue after it.
        """
        if self.role is Role.HOST:
            return self._next_reply()
        return self._next_command()

    # ------------------------------------------------------------------- for the driver

    def pending_bytes(self) -> int:
        """Bytes received but not yet decoded or discarded (a partial command or reply)."""
        return len(self._buffer) + len(self._attempt)

    @property
    def unreadable_bytes(self) -> int:
        """Bytes received that belong to no message: those dropped so far, and the run of
        garbage still going (known as garbage the moment it arrives, though reported as a
        fault only when it ends)."""
        return self.stats.dropped_bytes + self._junk_count

    @property
    def in_progress(self) -> bool:
        """Whether a command (device) or reply (host) has started but not yet ended."""
        return bool(self._attempt) or self._in_reply or self._skipping

    def reset(self) -> int:
        """Abandon everything buffered: a partial reply the device will never finish, or a
        partial command.

        Abandoned bytes are counted as one ``"abandoned"`` fault, a pending run of garbage as
        one ``"garbage"`` fault; nothing is raised.

        Returns:
            The number of bytes discarded.
        """
        dropped = len(self._buffer) + len(self._attempt)
        if dropped:
            self.stats.fault("abandoned", dropped)
        junk = self._junk_count
        if junk:
            self.stats.fault("garbage", junk)
        self._buffer.clear()
        self._junk_count = 0
        self._junk_sample.clear()
        self._attempt.clear()
        self._spec = None
        self._end_reply()
        return dropped + junk

    # ------------------------------------------------------------------------- helpers

    def _fault(self, kind: str, message: str, data: bytes, dropped: int) -> NoReturn:
        self.stats.fault(kind, dropped)
        raise RemoteProtocolError(message, kind=kind, data=data)

    def _take_junk(self, count: int) -> None:
        """Discard ``count`` garbage bytes from the front of the buffer into the pending run."""
        room = FAULT_SAMPLE_BYTES - len(self._junk_sample)
        if room > 0:
            self._junk_sample += self._buffer[: min(room, count)]
        self._junk_count += count
        del self._buffer[:count]

    def _raise_junk(self) -> NoReturn:
        count = self._junk_count
        sample = bytes(self._junk_sample)
        self._junk_count = 0
        self._junk_sample.clear()
        self._fault("garbage", f"{count} stray byte(s) between messages", sample, count)

    # -------------------------------------------------------------------- device side

    def _next_command(self) -> Command | None:
        buffer = self._buffer
        attempt = self._attempt
        while True:
            if not attempt:
                # READY: look for a header character; drop CR/LF silently.
                if not buffer:
                    return None
                match = _DEVICE_START.search(buffer)
                end = match.start() if match else len(buffer)
                if end:
                    self._take_junk(end)
                if not buffer:
                    return None
                if self._junk_count:
                    self._raise_junk()
                byte = buffer[0]
                del buffer[0]
                if byte not in _CRLF:
                    attempt.append(byte)
                continue
            spec = self._spec
            if spec is None:
                # COMMAND: two characters, then match them.
                take = min(3 - len(attempt), len(buffer))
                attempt += buffer[:take]
                del buffer[:take]
                if len(attempt) < 3:
                    return None
                spec = COMMANDS.get((attempt[0], bytes(attempt[1:3]).upper()))
                if spec is None:
                    self._fail("bad_command", f"unknown command {bytes(attempt)!r}")
                self._spec = spec
                if spec.argc == 0:
                    return self._finish(spec)
                continue
            # ARGUMENTS: read them all, then check them.
            take = min(3 + spec.argc - len(attempt), len(buffer))
            attempt += buffer[:take]
            del buffer[:take]
            if len(attempt) < 3 + spec.argc:
                return None
            return self._finish(spec)

    def _fail(self, kind: str, message: str) -> NoReturn:
        data = bytes(self._attempt)
        self._attempt.clear()
        self._spec = None
        self._fault(kind, message, data, len(data))

    def _finish(self, spec: CommandSpec) -> Command:
        args = bytes(self._attempt[3:])
        if spec.argc and not spec.free_text and not firmware_reads_as_hex(args):
            self._fail("bad_argument", f"{spec.name} arguments {args!r} are not hex digits")
        try:
            command = spec.parse(args)
        except BadArgumentError as exc:
            self._fail("bad_argument", f"{spec.name}: {exc}")
        except LocalProtocolError as exc:
            self._fail("out_of_range", f"{spec.name}: {exc}")
        self._attempt.clear()
        self._spec = None
        self.stats.messages += 1
        return command

    # ---------------------------------------------------------------------- host side

    def _end_reply(self) -> None:
        self._in_reply = False
        self._skipping = False
        self._scan_pos = 0
        self._depth = 0
        self._in_string = False
        self._escape = False

    def _scan(self, limit: int, check_depth: bool) -> int:
        """Scan the buffer up to ``limit`` bytes, tracking brackets outside strings.

        Returns:
            The end (exclusive) of the value when its brackets balance, ``_INCOMPLETE``, or
            ``_TOO_DEEP`` (``_scan_pos`` is then just past the offending bracket).
        """
        buffer = self._buffer
        stop = min(limit, len(buffer))
        pos = self._scan_pos
        while pos < stop:
            if self._escape:
                self._escape = False
                pos += 1
                continue
            if self._in_string:
                match = _STRING_SPECIAL.search(buffer, pos, stop)
                if match is None:
                    pos = stop
                    break
                pos = match.start()
                if buffer[pos] == ord("\\"):
                    self._escape = True
                else:
                    self._in_string = False
                pos += 1
                continue
            match = _STRUCTURE.search(buffer, pos, stop)
            if match is None:
                pos = stop
                break
            pos = match.start()
            char = buffer[pos]
            pos += 1
            if char == ord('"'):
                self._in_string = True
            elif char in _OPENERS:
                self._depth += 1
                if check_depth and self._depth > _MAX_DEPTH:
                    self._scan_pos = pos
                    return _TOO_DEEP
            else:
                self._depth -= 1
                if self._depth == 0:
                    self._scan_pos = pos
                    return pos
        self._scan_pos = pos
        return _INCOMPLETE

    def _next_reply(self) -> Reply | None:
        buffer = self._buffer
        while True:
            if self._skipping:
                # The rest of an overlong or too deep reply: drop it until it balances.
                end = self._scan(len(buffer), check_depth=False)
                if end == _INCOMPLETE:
                    self.stats.dropped_bytes += len(buffer)
                    buffer.clear()
                    self._scan_pos = 0
                    return None
                self.stats.dropped_bytes += end
                del buffer[:end]
                self._end_reply()
                continue
            if not self._in_reply:
                if not buffer:
                    return None
                match = _HOST_START.search(buffer)
                end = match.start() if match else len(buffer)
                if end:
                    self._take_junk(end)
                if not buffer:
                    return None
                if self._junk_count:
                    self._raise_junk()
                if buffer[0] in _SPACE:
                    match = _NOT_SPACE.search(buffer)
                    del buffer[: match.start() if match else len(buffer)]
                    continue
                self._in_reply = True
            end = self._scan(self.max_reply_bytes, check_depth=True)
            if end == _TOO_DEEP:
                dropped = self._scan_pos
                data = bytes(buffer[:dropped])
                del buffer[:dropped]
                self._scan_pos = 0
                self._in_reply = False
                self._skipping = True
                self._fault("bad_json", f"reply nested deeper than {_MAX_DEPTH}", data, dropped)
            if end == _INCOMPLETE:
                if len(buffer) <= self.max_reply_bytes:
                    return None
                dropped = self.max_reply_bytes
                data = bytes(buffer[:dropped])
                del buffer[:dropped]
                self._scan_pos = 0
                self._in_reply = False
                self._skipping = True
                self._fault("overlong", f"reply longer than {dropped} bytes", data, dropped)
            text = bytes(buffer[:end])
            del buffer[:end]
            self._end_reply()
            return self._parse_reply(text)

    def _parse_reply(self, text: bytes) -> Reply:
        try:
            value = json.loads(text.decode("utf-8"), parse_constant=_reject_constant)
        except (ValueError, RecursionError) as exc:
            self._fault("bad_json", f"reply is not JSON: {exc}", text, len(text))
        try:
            reply = reply_from_json(value)
        except (LookupError, TypeError, ValueError) as exc:
            self._fault("bad_reply", f"JSON is not a PLEN2 reply: {exc}", text, len(text))
        self.stats.messages += 1
        return reply


def codec_for(role: Role, profile: ProfileLike) -> PlenCodec:
    """The PLEN2 codec in ``role`` (the protocol unit's codec factory; no profile options)."""
    del profile
    return PlenCodec(role)
