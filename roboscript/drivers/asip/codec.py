"""ASIP codec: sans-IO, standard library only, host and device roles.

Host role
    :meth:`AsipCodec.send` writes requests as ``svc,tag,args\\n`` with no spaces;
    :meth:`AsipCodec.next_message` reads the board's lines. It accepts CRLF, spaces after
    commas (the seed's examples), lines with no ASIP prefix (sketch debug output, returned as
    :class:`DebugLine`), and skips garbage: lines that are not printable ASCII and lines over
    ``max_line_bytes`` are counted in :attr:`stats` and raised as
    :class:`~roboscript.errors.RemoteProtocolError` after being consumed.

Device role
    Requests are parsed the way the V1.1 firmware parses them: nothing starts before four
    bytes are buffered, bytes up to ``' '`` between requests are skipped, the service letter
    must be followed by ``,``, and numbers are read with Arduino ``parseInt`` semantics (skip
    anything that is not a digit or ``-``), so requests need no newline
    (``M,A,1M,A,1R,A,25`` is three requests) and a short request swallows the next number
    (``M,S\\nM,A,1`` loses the ``1``). ``parseInt`` waits up to a second for a digit: the
    device calls :meth:`AsipCodec.parse_timeout` when its clock says the line went quiet, and
    the pending request completes with the digits it has (0 if none), as on the board.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable

from roboscript.codec import CodecStats, ProfileLike, Role
from roboscript.drivers.asip import messages as m
from roboscript.errors import FAULT_SAMPLE_BYTES, LocalProtocolError, RemoteProtocolError

__all__ = ["DEFAULT_SERVICES", "AsipCodec", "codec_for"]

DEFAULT_SERVICES = "IMEBRDSTLPAGH"
"""Service ids a device-role codec accepts unless told otherwise."""

_MIN_MSG_LEN = 4
_MAX_COUNT = 256  # bound on element counts read from a request (pixels, bars)
_TEXT_BYTES = b"\t" + bytes(range(0x20, 0x80))  # printable ASCII and tab: what a line may hold


class _NeedMoreError(Exception):
    """Internal: the buffer ends inside a request."""


class _Cursor:
    """Reads one request from a buffer with the firmware's ``Stream`` semantics."""

    __slots__ = ("buf", "final", "pos")

    def __init__(self, buf: bytearray, final: bool) -> None:
        self.buf = buf
        self.pos = 0
        self.final = final

    def read(self) -> int:
        if self.pos >= len(self.buf):
            raise _NeedMoreError
        byte = self.buf[self.pos]
        self.pos += 1
        return byte

    def peek(self) -> int | None:
        return self.buf[self.pos] if self.pos < len(self.buf) else None

    def parse_int(self) -> int:
        """Arduino ``Stream::parseInt``: skip to a digit or ``-``, then read digits."""
        while True:
            byte = self.peek()
            if byte is None:
                if self.final:
                    return 0
                raise _NeedMoreError
            if byte == 0x2D or 0x30 <= byte <= 0x39:
                break
            self.pos += 1
        negative = False
        value = 0
        while True:
            byte = self.peek()
            if byte == 0x2D and not negative and value == 0:
                negative = True
            elif byte is not None and 0x30 <= byte <= 0x39:
                value = value * 10 + byte - 0x30
            else:
                break
            self.pos += 1
            following = self.peek()
            if following is None:
                if self.final:
                    break
                raise _NeedMoreError
            if not 0x30 <= following <= 0x39:
                break
        return -value if negative else value

    def rest_of_line(self, *, skip_comma: bool = True) -> str:
        """Text up to the newline (consumed, not returned); a comma right here may be skipped."""
        if skip_comma and self.peek() == 0x2C:
            self.pos += 1
        end = self.buf.find(b"\n", self.pos)
        if end < 0:
            if not self.final:
                raise _NeedMoreError
            end = len(self.buf)
        text = bytes(self.buf[self.pos : end]).decode("ascii", "replace").rstrip("\r")
        self.pos = min(end + 1, len(self.buf))
        return text

    def discard_line(self) -> None:
        end = self.buf.find(b"\n", self.pos)
        if end < 0:
            if not self.final:
                raise _NeedMoreError
            self.pos = len(self.buf)
        else:
            self.pos = end + 1

    def ints(self, count: int) -> tuple[int, ...]:
        return tuple(self.parse_int() for _ in range(count))


def _fmt_pairs(pairs: Iterable[tuple[int, int]], *, hex_second: bool = False) -> str:
    if hex_second:
        return ",".join(f"{a}:{b:X}" for a, b in pairs)
    return ",".join(f"{a}:{b}" for a, b in pairs)


def _body(count: int, items: str) -> str:
    return f"{count},{{{items}}}"


class AsipCodec:
    """ASIP 1.1 codec for one end of a link.

    Args:
        role: ``Role.HOST`` for roboscript's driver, ``Role.DEVICE`` for a simulated board.
        services: Device role only: the service ids the board runs; a request for any other
            service decodes as :class:`~roboscript.drivers.asip.messages.InvalidServiceRequest`.
        max_line_bytes: Host role: longer lines are dropped as garbage.
        max_buffer_bytes: Device role: bound on buffered request bytes.

    Example:
        >>> host = AsipCodec(Role.HOST)
        >>> host.send(m.SetMotorsPower(30, -30))
        b'M,M,30,-30\\n'
        >>> host.receive_data(b"@M,e,2,{10:100,12:120}\\n")
        >>> host.next_message()
        EncoderEvent(counts=((10, 100), (12, 120)))
    """

    def __init__(
        self,
        role: Role,
        *,
        services: str = DEFAULT_SERVICES,
        max_line_bytes: int = 512,
        max_buffer_bytes: int = 4096,
    ) -> None:
        self.role = role
        self._host = role is Role.HOST  # looked up on every received chunk and message
        self._encoders = _ROLE_ENCODERS[role]
        self.services = services
        self.stats = CodecStats()
        self._max_line = max_line_bytes
        self._max_buffer = max_buffer_bytes
        self._buf = bytearray()  # device role: request bytes not yet parsed
        # Host role: complete lines (and faults, in wire order) waiting for next_message(),
        # and the start of the line still arriving.
        self._lines: deque[bytes | RemoteProtocolError] = deque()
        self._tail = b""
        self._skipping_overlong = False
        self._timed_out = False
        self._overflowed = 0  # device role: bytes dropped by receive_data, not yet reported

    # ----------------------------------------------------------------------------- receiving

    def receive_data(self, data: bytes) -> None:
        """Buffer bytes read from the wire."""
        if not self._host:
            self._receive_requests(data)
            return
        # Host role (the hot path, so not a method of its own): bytes.split() frames a whole
        # read in C; complete lines wait in a queue, the start of the next line in _tail.
        if self._tail:
            data = self._tail + data
        lines = data.split(b"\n")
        tail = lines.pop()
        if lines:
            if self._skipping_overlong:  # the end of a line already dropped as overlong
                self._skipping_overlong = False
                self.stats.dropped_bytes += len(lines[0]) + 1
                del lines[0]
            self._lines.extend(lines)
        if len(tail) > self._max_line:
            # Never buffer more than a line's worth: drop it, and its end when it comes.
            if self._skipping_overlong:
                self.stats.dropped_bytes += len(tail)
            else:
                self._skipping_overlong = True
                self.stats.fault("overlong", len(tail))
                self._lines.append(
                    RemoteProtocolError(f"line longer than {self._max_line} bytes", kind="overlong")
                )
            tail = b""
        self._tail = tail

    def _receive_requests(self, data: bytes) -> None:
        self._buf += data
        if len(self._buf) > self._max_buffer:
            # A request never needs this much; keep the newest bytes so parsing resynchronises.
            excess = len(self._buf) - self._max_buffer
            del self._buf[:excess]
            self._overflowed += excess  # counted and raised by the next next_message()

    def parse_timeout(self) -> None:
        """Tell a device-role codec that the line was quiet for the board's 1 s read timeout.

        The next :meth:`next_message` completes a request cut short, as ``parseInt`` does.
        """
        self._timed_out = True

    def pending_bytes(self) -> int:
        """Number of buffered bytes not yet decoded."""
        if self._host:
            lines = (len(line) + 1 for line in self._lines if isinstance(line, bytes))
            return sum(lines) + len(self._tail)
        return len(self._buf)

    def next_message(self) -> m.AsipMessage | None:
        """Return the next complete message, or ``None`` when more bytes are needed.

        Raises:
            RemoteProtocolError: For a bad line or request, already consumed.
        """
        if not self._host:
            return self._next_request_or_overflow()
        lines = self._lines
        while lines:
            line = lines.popleft()
            if isinstance(line, RemoteProtocolError):
                raise line  # a fault found while framing, in its place among the lines
            if len(line) > self._max_line:
                self.stats.fault("overlong", len(line) + 1)
                raise RemoteProtocolError(
                    f"line longer than {self._max_line} bytes", kind="overlong", data=line
                )
            if line.endswith(b"\r"):
                line = line.rstrip(b"\r")
            if not line or line.isspace():
                continue
            message = self._decode_line(line)
            self.stats.messages += 1
            return message
        return None

    def _next_request_or_overflow(self) -> m.AsipMessage | None:
        if self._overflowed:
            dropped, self._overflowed = self._overflowed, 0
            self.stats.fault("overlong", dropped)
            raise RemoteProtocolError(f"{dropped} request bytes over the buffer", kind="overlong")
        return self._next_request()

    # ------------------------------------------------------------------ host: decode replies

    def _bad(self, line: bytes, why: str, kind: str = "malformed") -> RemoteProtocolError:
        self.stats.fault(kind, len(line) + 1)
        return RemoteProtocolError(f"{why}: {line[:FAULT_SAMPLE_BYTES]!r}", kind=kind, data=line)

    def _decode_line(self, line: bytes) -> m.AsipMessage:
        # All in C: isascii() and isprintable() pass a normal line without copying it; only a
        # line with a tab or a control byte pays for translate(), which deletes allowed bytes.
        if not line.isascii():
            raise self._bad(line, "not ASCII text", kind="garbage")
        text = line.decode("ascii")
        if not text.isprintable() and line.translate(None, _TEXT_BYTES):
            raise self._bad(line, "not ASCII text", kind="garbage")
        head = text[0]
        try:
            if head == "@":
                # The firmware writes "@S,t," with no spaces: one slice finds the decoder.
                decoder = _EVENT_DECODERS_BY_HEAD.get(text[:5])
                if decoder is not None:
                    return decoder(text[5:])
                return self._decode_event(text)
            if head == "~":
                return self._decode_error(text)
        except (ValueError, IndexError) as exc:
            raise self._bad(line, f"unreadable {head} line ({exc})") from None
        if head == "!":
            return _decode_info(text[1:])
        return m.DebugLine(text)

    def _decode_error(self, text: str) -> m.ErrorReply:
        service, tag, rest = (part.strip() for part in text[1:].split(",", 2))
        brace = rest.find("{")
        if brace >= 0:
            errno = int(rest[:brace].strip().rstrip(","))
            message = rest[brace + 1 :].rstrip("}").strip()
        else:  # the seed's form: number, then text in its own field
            number, _, message = rest.partition(",")
            errno = int(number)
        return m.ErrorReply(service, tag, errno, message.strip())

    def _decode_event(self, text: str) -> m.AsipMessage:
        """The general path: the seed's spaced form (``@I, d, ...``) and unknown events."""
        parts = text[1:].split(",", 2)
        service = parts[0].strip()
        tag = parts[1].strip()
        rest = parts[2].strip() if len(parts) > 2 else ""
        decoder = _EVENT_DECODERS.get((service, tag))
        if decoder is None:
            return m.GenericEvent(service, tag, _split_fields(rest))
        return decoder(rest)

    # -------------------------------------------------------------- device: decode requests

    def _next_request(self) -> m.AsipMessage | None:
        final = self._timed_out
        while True:
            # Bytes up to ' ' between requests are harmless.
            skip = 0
            while skip < len(self._buf) and self._buf[skip] <= 0x20:
                skip += 1
            if skip:
                del self._buf[:skip]
            if len(self._buf) < _MIN_MSG_LEN:
                self._timed_out = False
                return None
            cursor = _Cursor(self._buf, final)
            try:
                message = self._parse_request(cursor)
            except _NeedMoreError:
                self._timed_out = False
                return None
            except RemoteProtocolError:
                del self._buf[: max(cursor.pos, 1)]
                raise
            except LocalProtocolError as exc:  # e.g. a tone over 2**31 ms, non-ASCII LCD text
                dropped = max(cursor.pos, 1)
                del self._buf[:dropped]
                self.stats.fault("out_of_range", dropped)
                raise RemoteProtocolError(
                    f"request out of range: {exc}", kind="out_of_range"
                ) from None
            del self._buf[: cursor.pos]
            if message is not None:
                self.stats.messages += 1
                return message

    def _parse_request(self, cur: _Cursor) -> m.AsipMessage | None:
        service = chr(cur.read())
        if service == "!":
            return m.DebugEchoRequest(cur.rest_of_line(skip_comma=False))
        if service == "$":
            return self._parse_config(cur)
        if service != "#" and service not in self.services:
            cur.discard_line()  # the firmware looks the id up before it reads the separator
            return m.InvalidServiceRequest(service)
        separator = cur.read()
        if separator != 0x2C:
            self.stats.fault("malformed", 2)
            raise RemoteProtocolError(f"request {service!r} not followed by ','", kind="malformed")
        tag = chr(cur.read())
        while tag == " ":  # the seed writes "M, M, 30, -30"
            tag = chr(cur.read())
        parser = _REQUEST_PARSERS.get(service)
        if parser is None:
            cur.discard_line()
            return m.InvalidServiceRequest(service)
        return parser(self, cur, tag)

    def _parse_config(self, cur: _Cursor) -> m.AsipMessage:
        text = cur.rest_of_line().lstrip("$").lstrip(",")
        ssid, _, password = text.partition(",")
        try:
            return m.WifiConfig(ssid, password)
        except LocalProtocolError:
            return m.UnknownRequest("$", "$")

    # ------------------------------------------------------------------------------ sending

    def send(self, message: object) -> bytes:
        """Encode one message for the wire.

        Raises:
            LocalProtocolError: The message is not one this role sends.
        """
        encode = self._encoders.get(type(message))
        if encode is None:
            other = _ENCODERS.get(type(message))
            if other is None:
                raise LocalProtocolError(f"{type(message).__name__} is not an ASIP message")
            raise LocalProtocolError(
                f"{type(message).__name__} is sent by the {other[0].value}, "
                f"not the {self.role.value}"
            )
        try:  # latin-1: a service or tag byte read from the wire goes back out unchanged
            return (encode(message) + "\n").encode("latin-1")
        except UnicodeEncodeError as exc:
            raise LocalProtocolError(f"{type(message).__name__} has a non-byte character") from exc


# ------------------------------------------------------------------------------------------
# Host-side event decoding


def _split_fields(rest: str) -> tuple[str, ...]:
    return tuple(field.strip() for field in rest.split(",")) if rest else ()


def _body_fields(rest: str) -> list[str]:
    """``n,{a,b,c}`` -> ``["a", "b", "c"]`` unstripped (the count may be absent).

    Numbers need no ``strip()``: ``int()`` and ``float()`` ignore the spaces the seed's
    examples put after commas.
    """
    start = rest.find("{")
    end = rest.rfind("}")
    if start < 0 or end < start:
        raise ValueError("missing {...} body")
    inner = rest[start + 1 : end]
    if not inner or inner.isspace():
        return []
    items = inner.split(",")
    count = rest[:start].rstrip().rstrip(",")
    if count and int(count) != len(items):
        raise ValueError(f"body has {len(items)} fields, header says {count.strip()}")
    return items


def _body_items(rest: str) -> list[str]:
    """``n,{a, b}`` -> ``["a", "b"]``: text fields, stripped."""
    return [item.strip() for item in _body_fields(rest)]


def _int_items(rest: str) -> tuple[int, ...]:
    return tuple(map(int, _body_fields(rest)))


def _pair_items(rest: str, *, hex_second: bool = False) -> tuple[tuple[int, int], ...]:
    base = 16 if hex_second else 10
    pairs = []
    for item in _body_fields(rest):  # a loop: a comprehension costs a function call on 3.11
        first, second = item.split(":")
        pairs.append((int(first), int(second, base)))
    return tuple(pairs)


def _xyz(rest: str) -> tuple[int, int, int]:
    x, y, z = _int_items(rest)[:3]
    return x, y, z


def _decode_version(rest: str) -> m.VersionReply:
    major, minor, chip, pins, sketch = rest.split(",", 4)
    # int() ignores the spaces the seed's examples put after commas; only text needs strip().
    return m.VersionReply(int(major), int(minor), chip.strip(), int(pins), sketch.strip())


def _decode_service_names(rest: str) -> m.ServiceNamesReply:
    pairs = []
    for item in _body_items(rest):
        service, _, name = item.partition(":")
        pairs.append((service.strip(), name.strip()))
    return m.ServiceNamesReply(tuple(pairs))


def _decode_distance(rest: str) -> m.DistanceEvent:
    return m.DistanceEvent(_int_items(rest))


def _decode_distance_seed(rest: str) -> m.DistanceEvent:
    # The seed documents "@D,M,<cm>"; the firmware sends "@D,e,1,{cm}". Accept both.
    if "{" in rest:
        return m.DistanceEvent(_int_items(rest))
    return m.DistanceEvent((int(rest),))


def _decode_digital(rest: str) -> m.DigitalPortEvent:
    port, mask = rest.split(",")
    return m.DigitalPortEvent(int(port), int(mask, 16))  # int() ignores surrounding spaces


def _decode_pixel_info(rest: str) -> m.PixelsInfoReply:
    fields = [int(field) for field in _split_fields(rest)]
    if len(fields) == 1:  # ASIP 0.4: "@P,I,count"
        return m.PixelsInfoReply(0, fields[0])
    return m.PixelsInfoReply(fields[0], fields[1])


def _decode_pressure(rest: str) -> m.PressureEvent:
    mbar, temp, alt = map(float, _body_fields(rest)[:3])
    return m.PressureEvent(mbar, temp, alt)


def _decode_heading(rest: str) -> m.HeadingEvent:
    x, y, z, heading = _int_items(rest)[:4]
    return m.HeadingEvent(x, y, z, heading)


_EVENT_DECODERS: dict[tuple[str, str], Callable[[str], m.AsipMessage]] = {
    ("#", "?"): _decode_version,
    ("#", "N"): _decode_service_names,
    ("#", "S"): lambda rest: m.PinServicesReply(tuple(_body_items(rest))),
    ("I", "M"): lambda rest: m.PortMapReply(_pair_items(rest, hex_second=True)),
    ("I", "m"): lambda rest: m.AnalogMapReply(_pair_items(rest)),
    ("I", "p"): lambda rest: m.PinModesReply(_int_items(rest)),
    ("I", "c"): lambda rest: m.CapabilitiesReply(_int_items(rest)),
    ("I", "d"): _decode_digital,
    ("I", "a"): lambda rest: m.AnalogEvent(_pair_items(rest)),
    ("I", "A"): lambda rest: m.AnalogEvent(_pair_items(rest)),  # the seed's tag
    ("M", "e"): lambda rest: m.EncoderEvent(_pair_items(rest)),
    ("E", "e"): lambda rest: m.LegacyEncoderEvent(_pair_items(rest)),
    ("B", "e"): lambda rest: m.BumpEvent(_int_items(rest)),
    ("R", "e"): lambda rest: m.IrEvent(_int_items(rest)),
    ("D", "e"): _decode_distance,
    ("D", "M"): _decode_distance_seed,
    ("A", "e"): lambda rest: m.AccelerometerEvent(*_xyz(rest)),
    ("G", "e"): lambda rest: m.GyroEvent(*_xyz(rest)),
    ("H", "e"): _decode_heading,
    ("P", "e"): _decode_pressure,
    ("P", "I"): _decode_pixel_info,
}


_EVENT_DECODERS_BY_HEAD: dict[str, Callable[[str], m.AsipMessage]] = {
    f"@{service},{tag},": decoder for (service, tag), decoder in _EVENT_DECODERS.items()
}


def _decode_info(text: str) -> m.StartupLine | m.InfoLine:
    sketch, running, rest = text.partition(" running on ")
    if running:
        chip, with_services, services = rest.partition(" with Services:")
        if with_services:
            return m.StartupLine(sketch.strip(), chip.strip(), tuple(services.split()))
    return m.InfoLine(text)


# ------------------------------------------------------------------------------------------
# Device-side request parsing (firmware semantics)

_RequestParser = Callable[[AsipCodec, _Cursor, str], "m.AsipMessage | None"]


def _parse_system(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    simple: dict[str, m.AsipMessage] = {
        "?": m.VersionRequest(),
        "N": m.ServiceNamesRequest(),
        "S": m.PinServicesRequest(),
        "R": m.RestartRequest(),
    }
    return simple.get(tag) or m.UnknownRequest("#", tag)


def _parse_io(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "P":
        pin, mode = cur.ints(2)
        if not 0 <= pin <= 255 or not 0 <= mode <= 8:
            return m.UnknownRequest("I", tag, (pin, mode))
        return m.SetPinMode(pin, m.PinMode(mode))
    if tag in "da":
        pin, value = cur.ints(2)
        try:
            return m.DigitalWrite(pin, value) if tag == "d" else m.AnalogWrite(pin, value)
        except LocalProtocolError:
            return m.UnknownRequest("I", tag, (pin, value))
    if tag == "A":
        return _auto_event(cur, "I")
    simple: dict[str, m.AsipMessage] = {
        "M": m.PortMapRequest(),
        "m": m.AnalogMapRequest(),
        "p": m.PinModesRequest(),
        "c": m.CapabilitiesRequest(),
    }
    return simple.get(tag) or m.UnknownRequest("I", tag)


def _auto_event(cur: _Cursor, service: str) -> m.AsipMessage:
    interval = cur.parse_int()
    return m.SetAutoEventInterval(service, max(0, min(interval, 65535)))


def _parse_motor(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    first = cur.parse_int()
    if tag == "A":
        return m.EnableEncoderEvents(first != 0)
    if tag == "S":
        return m.StopMotors()
    if tag == "E":
        return m.ResetEncoders()
    second = cur.parse_int()
    third = cur.parse_int() if tag in "rR" else 0
    try:
        if tag == "m":
            return m.SetMotorPower(first, max(-100, min(second, 100)))
        if tag == "M":
            return m.SetMotorsPower(max(-100, min(first, 100)), max(-100, min(second, 100)))
        if tag == "r":
            return m.SetMotorRpm(first, second, max(third, 0))
        if tag == "R":
            return m.SetMotorsRpm(first, second, max(third, 0))
        if tag == "c":
            return m.SetRobotSpeed(first, max(second, 0))
        if tag == "a":
            return m.RotateRobot(first, second)
        if tag == "s":
            return m.StopMotor(first)
    except LocalProtocolError:
        pass
    args = (first, second, third) if tag in "rR" else (first, second)
    return m.UnknownRequest("M", tag, args)


def _parse_auto_only(service: str) -> _RequestParser:
    def parse(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
        if tag == "A":
            return _auto_event(cur, service)
        return m.UnknownRequest(service, tag)

    return parse


def _parse_measuring(service: str) -> _RequestParser:
    def parse(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
        if tag == "A":
            return _auto_event(cur, service)
        if tag == "M":
            return m.MeasureRequest(service)
        return m.UnknownRequest(service, tag)

    return parse


def _parse_servo(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "W":
        servo, angle = cur.ints(2)
        if servo < 0:
            return m.UnknownRequest("S", tag, (servo, angle))
        return m.ServoWrite(min(servo, 255), max(0, min(angle, 180)))  # the board clamps
    return m.UnknownRequest("S", tag)


def _parse_tone(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "P":
        frequency, duration = cur.ints(2)
        if frequency > 0 and duration > 0:
            return m.PlayTone(min(frequency, 65535), duration)
        return m.UnknownRequest("T", tag, (frequency, duration))
    return m.UnknownRequest("T", tag)


def _parse_lcd(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "W":
        line = cur.parse_int()
        text = cur.rest_of_line()
        if 0 <= line < m.LCD_LINES:
            return m.LcdWrite(line, text)
        return m.UnknownRequest("L", tag, (line,))
    if tag == "w":
        line, column = cur.ints(2)
        text = cur.rest_of_line()
        if 0 <= line < m.LCD_LINES and 0 <= column < m.LCD_COLUMNS:
            return m.LcdWriteAt(line, column, text)
        return m.UnknownRequest("L", tag, (line, column))
    if tag == "G":
        count = min(max(cur.parse_int(), 0), _MAX_COUNT)
        bars = tuple((line, max(0, min(value, 100))) for line, value in _pairs(cur, count))
        if all(0 <= line < m.LCD_LINES for line, _ in bars):
            return m.LcdBarGraph(bars)
        return m.UnknownRequest("L", tag)
    if tag == "C":
        return m.LcdClear()
    return m.UnknownRequest("L", tag)


def _pairs(cur: _Cursor, count: int) -> tuple[tuple[int, int], ...]:
    return tuple((cur.parse_int(), cur.parse_int()) for _ in range(count))


def _rgb(cur: _Cursor) -> tuple[int, int, int]:
    r, g, b = (max(0, min(value, 255)) for value in cur.ints(3))
    return r, g, b


def _parse_pixels_or_pressure(codec: AsipCodec, cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "M":
        return m.MeasureRequest("P")
    if tag == "A":
        return _auto_event(cur, "P")
    message: m.AsipMessage
    if tag in "PpSsBIC":
        strip = cur.parse_int()
        if tag == "P":
            count = min(max(cur.parse_int(), 0), _MAX_COUNT)
            pairs = tuple(
                (max(0, min(pixel, 0xFFFF)), max(0, min(color, 0xFFFFFF)))
                for pixel, color in _pairs(cur, count)
            )
            message = m.PixelsSet(strip, pairs)
        elif tag == "p":
            count = min(max(cur.parse_int(), 0), _MAX_COUNT)
            message = m.PixelsSetRgb(
                strip,
                tuple((max(0, min(cur.parse_int(), 0xFFFF)), _rgb(cur)) for _ in range(count)),
            )
        elif tag == "S":
            count = min(max(cur.parse_int(), 0), _MAX_COUNT)
            first = cur.parse_int()
            colors = tuple(max(0, min(cur.parse_int(), 0xFFFFFF)) for _ in range(count))
            message = m.PixelsSequence(strip, first, colors)
        elif tag == "s":
            count = min(max(cur.parse_int(), 0), _MAX_COUNT)
            first = cur.parse_int()
            message = m.PixelsSequenceRgb(strip, first, tuple(_rgb(cur) for _ in range(count)))
        elif tag == "B":
            message = m.PixelsBrightness(strip, max(0, min(cur.parse_int(), 255)))
        elif tag == "I":
            message = m.PixelsInfoRequest(strip)
        else:
            message = m.PixelsClear(strip)
    else:
        message = m.UnknownRequest("P", tag)
    cur.discard_line()  # the pixels service drops the rest of the line
    return message


_REQUEST_PARSERS: dict[str, _RequestParser] = {
    "#": _parse_system,
    "I": _parse_io,
    "M": _parse_motor,
    "E": _parse_auto_only("E"),
    "B": _parse_auto_only("B"),
    "R": _parse_auto_only("R"),
    "D": _parse_measuring("D"),
    "A": _parse_measuring("A"),
    "G": _parse_measuring("G"),
    "H": _parse_measuring("H"),
    "S": _parse_servo,
    "T": _parse_tone,
    "L": _parse_lcd,
    "P": _parse_pixels_or_pressure,
}


# ------------------------------------------------------------------------------------------
# Encoders (one per message type, tagged with the role that sends it)


def _enc_pixels_set(msg: m.PixelsSet) -> str:
    return f"P,P,{msg.strip},{_body(len(msg.pixels), _fmt_pairs(msg.pixels))}"


def _enc_pixels_set_rgb(msg: m.PixelsSetRgb) -> str:
    items = ",".join(f"{pixel}:{r}:{g}:{b}" for pixel, (r, g, b) in msg.pixels)
    return f"P,p,{msg.strip},{_body(len(msg.pixels), items)}"


def _enc_pixels_sequence(msg: m.PixelsSequence) -> str:
    items = ",".join(str(color) for color in msg.colors)
    return f"P,S,{msg.strip},{len(msg.colors)},{msg.first},{{{items}}}"


def _enc_pixels_sequence_rgb(msg: m.PixelsSequenceRgb) -> str:
    items = ",".join(f"{r}:{g}:{b}" for r, g, b in msg.colors)
    return f"P,s,{msg.strip},{len(msg.colors)},{msg.first},{{{items}}}"


def _enc_error(msg: m.ErrorReply) -> str:
    return f"~{msg.service},{msg.tag},{msg.errno}{{{msg.text}}}"


def _enc_startup(msg: m.StartupLine) -> str:
    # Each id is followed by a space, so the line ends with one, as on the board.
    services = "".join(f"{service} " for service in msg.services)
    return f"!{msg.sketch} running on {msg.chip} with Services: {services}"


def _enc_bump(msg: m.BumpEvent) -> str:
    return f"@B,e,{_body(len(msg.raw), ','.join(map(str, msg.raw)))}"


def _enc_ints(service: str, tag: str, values: Iterable[int]) -> str:
    items = [str(value) for value in values]
    return f"@{service},{tag},{_body(len(items), ','.join(items))}"


_H = Role.HOST
_D = Role.DEVICE

_ENCODER_TABLE: list[tuple[type, Role, Callable[..., str]]] = [
    (m.VersionRequest, _H, lambda msg: "#,?"),
    (m.ServiceNamesRequest, _H, lambda msg: "#,N"),
    (m.PinServicesRequest, _H, lambda msg: "#,S"),
    (m.RestartRequest, _H, lambda msg: "#,R"),
    (m.DebugEchoRequest, _H, lambda msg: f"!{msg.text}"),
    (m.WifiConfig, _H, lambda msg: f"$$,{msg.ssid},{msg.password}"),
    (m.SetPinMode, _H, lambda msg: f"I,P,{msg.pin},{int(msg.mode)}"),
    (m.DigitalWrite, _H, lambda msg: f"I,d,{msg.pin},{msg.value}"),
    (m.AnalogWrite, _H, lambda msg: f"I,a,{msg.pin},{msg.value}"),
    (m.PortMapRequest, _H, lambda msg: "I,M"),
    (m.AnalogMapRequest, _H, lambda msg: "I,m"),
    (m.PinModesRequest, _H, lambda msg: "I,p"),
    (m.CapabilitiesRequest, _H, lambda msg: "I,c"),
    (m.SetAutoEventInterval, _H, lambda msg: f"{msg.service},A,{msg.interval_ms}"),
    (m.MeasureRequest, _H, lambda msg: f"{msg.service},M"),
    (m.SetMotorPower, _H, lambda msg: f"M,m,{msg.motor},{msg.power_pct}"),
    (m.SetMotorsPower, _H, lambda msg: f"M,M,{msg.power0_pct},{msg.power1_pct}"),
    (m.SetMotorRpm, _H, lambda msg: f"M,r,{msg.motor},{msg.rpm},{msg.duration_ms}"),
    (m.SetMotorsRpm, _H, lambda msg: f"M,R,{msg.rpm0},{msg.rpm1},{msg.duration_ms}"),
    (m.SetRobotSpeed, _H, lambda msg: f"M,c,{msg.speed_cm_s},{msg.duration_ms}"),
    (m.RotateRobot, _H, lambda msg: f"M,a,{msg.turn_rate_deg_s},{msg.angle_deg}"),
    # The firmware reads one number more than these tags use: send a dummy so a request
    # never swallows the next one's first number.
    (m.StopMotor, _H, lambda msg: f"M,s,{msg.motor},0"),
    (m.StopMotors, _H, lambda msg: "M,S,0"),
    (m.ResetEncoders, _H, lambda msg: "M,E,0"),
    (m.EnableEncoderEvents, _H, lambda msg: f"M,A,{int(msg.enabled)}"),
    (m.ServoWrite, _H, lambda msg: f"S,W,{msg.servo},{msg.angle_deg}"),
    (m.PlayTone, _H, lambda msg: f"T,P,{msg.frequency_hz},{msg.duration_ms}"),
    (m.LcdWrite, _H, lambda msg: f"L,W,{msg.line},{msg.text}"),
    (m.LcdWriteAt, _H, lambda msg: f"L,w,{msg.line},{msg.column},{msg.text}"),
    (m.LcdBarGraph, _H, lambda msg: f"L,G,{_body(len(msg.bars), _fmt_pairs(msg.bars))}"),
    (m.LcdClear, _H, lambda msg: "L,C"),
    (m.PixelsSet, _H, _enc_pixels_set),
    (m.PixelsSetRgb, _H, _enc_pixels_set_rgb),
    (m.PixelsSequence, _H, _enc_pixels_sequence),
    (m.PixelsSequenceRgb, _H, _enc_pixels_sequence_rgb),
    (m.PixelsBrightness, _H, lambda msg: f"P,B,{msg.strip},{msg.level}"),
    (m.PixelsInfoRequest, _H, lambda msg: f"P,I,{msg.strip}"),
    (m.PixelsClear, _H, lambda msg: f"P,C,{msg.strip}"),
    (
        m.VersionReply,
        _D,
        lambda msg: f"@#,?,{msg.major},{msg.minor},{msg.chip},{msg.pin_count},{msg.sketch}",
    ),
    (
        m.ServiceNamesReply,
        _D,
        lambda msg: (
            "@#,N,"
            + _body(len(msg.services), ",".join(f"{sid}:{name}" for sid, name in msg.services))
        ),
    ),
    (
        m.PinServicesReply,
        _D,
        lambda msg: f"@#,S,{_body(len(msg.services), ','.join(msg.services))}",
    ),
    (
        m.PortMapReply,
        _D,
        lambda msg: f"@I,M,{_body(len(msg.ports), _fmt_pairs(msg.ports, hex_second=True))}",
    ),
    (m.AnalogMapReply, _D, lambda msg: f"@I,m,{_body(len(msg.pairs), _fmt_pairs(msg.pairs))}"),
    (m.PinModesReply, _D, lambda msg: _enc_ints("I", "p", msg.modes)),
    (m.CapabilitiesReply, _D, lambda msg: _enc_ints("I", "c", msg.capabilities)),
    (m.DigitalPortEvent, _D, lambda msg: f"@I,d,{msg.port},{msg.mask:X}"),
    (m.AnalogEvent, _D, lambda msg: f"@I,a,{_body(len(msg.values), _fmt_pairs(msg.values))}"),
    (m.EncoderEvent, _D, lambda msg: f"@M,e,{_body(len(msg.counts), _fmt_pairs(msg.counts))}"),
    (
        m.LegacyEncoderEvent,
        _D,
        lambda msg: f"@E,e,{_body(len(msg.values), _fmt_pairs(msg.values))}",
    ),
    (m.BumpEvent, _D, _enc_bump),
    (m.IrEvent, _D, lambda msg: _enc_ints("R", "e", msg.values)),
    (m.DistanceEvent, _D, lambda msg: _enc_ints("D", "e", msg.distances_cm)),
    (m.AccelerometerEvent, _D, lambda msg: _enc_ints("A", "e", (msg.x, msg.y, msg.z))),
    (m.GyroEvent, _D, lambda msg: _enc_ints("G", "e", (msg.x, msg.y, msg.z))),
    (
        m.HeadingEvent,
        _D,
        lambda msg: _enc_ints("H", "e", (msg.x, msg.y, msg.z, msg.heading_deg)),
    ),
    (
        m.PressureEvent,
        _D,
        lambda msg: (
            f"@P,e,3,{{{msg.pressure_mbar:.2f},{msg.temperature_c:.2f},{msg.altitude_m:.2f}}}"
        ),
    ),
    (m.PixelsInfoReply, _D, lambda msg: f"@P,I,{msg.strip},{msg.count}"),
    (m.GenericEvent, _D, lambda msg: f"@{msg.service},{msg.tag},{','.join(msg.fields)}"),
    (m.ErrorReply, _D, _enc_error),
    (m.StartupLine, _D, _enc_startup),
    (m.InfoLine, _D, lambda msg: f"!{msg.text}"),
    (m.DebugLine, _D, lambda msg: msg.text),
]

_ENCODERS: dict[type, tuple[Role, Callable[..., str]]] = {
    cls: (role, encode) for cls, role, encode in _ENCODER_TABLE
}
_ROLE_ENCODERS: dict[Role, dict[type, Callable[..., str]]] = {
    role: {cls: encode for cls, (sender, encode) in _ENCODERS.items() if sender is role}
    for role in Role
}


def codec_for(role: Role, profile: ProfileLike) -> AsipCodec:
    """The ASIP codec in ``role`` (the protocol unit's codec factory; no profile options)."""
    del profile
    return AsipCodec(role)
