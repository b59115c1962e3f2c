"""The board's side of ASIP: requests read the way the firmware reads them, replies written.

Requests
    :class:`RequestReader` parses requests the way the V1.1 firmware does: nothing starts
    before four bytes are buffered, bytes up to ``' '`` between requests are skipped, the
    service letter must be followed by ``,``, and numbers are read with Arduino ``parseInt``
    semantics (skip anything that is not a digit or ``-``), so requests need no newline
    (``M,A,1M,A,1R,A,25`` is three requests) and a short request swallows the next number
    (``M,S\\nM,A,1`` loses the ``1``). ``parseInt`` waits up to a second for a digit: the device
    calls :meth:`RequestReader.parse_timeout` when its clock says the line went quiet, and the
    pending request completes with the digits it has (0 if none), as on the board. A number
    beyond the ``long`` that ``parseInt`` returns, or a value no message can hold, is an
    ``"out_of_range"`` fault; the request is dropped.

Replies
    :data:`DEVICE_ENCODERS` writes events, replies, errors and info lines in the firmware's
    exact forms (no spaces; errors as ``~S,T,N{TEXT}``), and refuses a value outside what the
    firmware's types hold (:mod:`~roboscript.drivers.asip.value_ranges`), so the simulated board
    never prints a line a real one could not.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from roboscript.codec import CodecStats
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.framing import format_body, format_pairs
from roboscript.drivers.asip.value_ranges import (
    ALTITUDE_M,
    ANALOG_VALUE,
    BUMP_LEVEL,
    BYTE,
    DISTANCE_CM,
    ENCODER_COUNT,
    ERRNO,
    HEADING_DEG,
    IMU_AXIS,
    PARSE_INT,
    PIXEL_COUNT,
    PORT_MASK,
    PRESSURE_MBAR,
    TEMPERATURE_C,
    OutOfRangeError,
    check_range,
)
from roboscript.errors import LocalProtocolError, RemoteProtocolError

__all__ = ["DEFAULT_SERVICES", "DEVICE_ENCODERS", "RequestReader"]

DEFAULT_SERVICES = "IMEBRDSTLPAGH"
"""Service ids a device-role codec accepts unless told otherwise."""

_MIN_MSG_LEN = 4
_MAX_COUNT = 256  # bound on element counts read from a request (pixels, bars)
_PARSE_LOW, _PARSE_HIGH = PARSE_INT
_PARSE_CAP = _PARSE_HIGH + 2  # past the bound whatever the sign


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
        """Arduino ``Stream::parseInt``: skip to a digit or ``-``, then read digits.

        Raises:
            OutOfRangeError: The number does not fit the ``long`` that ``parseInt`` returns.
        """
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
                # Past the bound the value stays just past it: a run of digits as long as
                # the buffer costs no big-number arithmetic.
                value = min(value * 10 + byte - 0x30, _PARSE_CAP)
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
        if negative:
            value = -value
        if value < _PARSE_LOW or value > _PARSE_HIGH:
            raise OutOfRangeError(f"a number outside {_PARSE_LOW}..{_PARSE_HIGH}")
        return value

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


class RequestReader:
    """Reads requests from the host's byte stream with the firmware's semantics.

    Args:
        stats: Where messages and faults are counted.
        services: The service ids the board runs; a request for any other service decodes as
            :class:`~roboscript.drivers.asip.messages.InvalidServiceRequest`.
        max_buffer_bytes: Bound on buffered request bytes; the oldest go first.
    """

    def __init__(self, stats: CodecStats, services: str, max_buffer_bytes: int) -> None:
        self.stats = stats
        self.services = services
        self._max_buffer = max_buffer_bytes
        self._buf = bytearray()  # request bytes not yet parsed
        self._timed_out = False
        self._overflowed = 0  # bytes dropped by receive_data(), not yet reported

    def receive_data(self, data: bytes) -> None:
        """Add bytes read from the wire."""
        self._buf += data
        if len(self._buf) > self._max_buffer:
            # A request never needs this much; keep the newest bytes so parsing resynchronises.
            excess = len(self._buf) - self._max_buffer
            del self._buf[:excess]
            self._overflowed += excess  # counted and raised by the next next_message()

    def parse_timeout(self) -> None:
        """The line was quiet for the board's 1 s read timeout: complete a request cut short."""
        self._timed_out = True

    def pending_bytes(self) -> int:
        """Bytes received and not yet parsed or dropped."""
        return len(self._buf)

    def next_message(self) -> m.AsipMessage | None:
        """The next complete request, or ``None`` when more bytes (or the timeout) are needed.

        Raises:
            RemoteProtocolError: Bytes over the buffer bound (``"overlong"``), a service id
                without its ``,`` (``"malformed"``) or a value out of range
                (``"out_of_range"``), already consumed and counted.
        """
        if self._overflowed:
            dropped, self._overflowed = self._overflowed, 0
            self.stats.fault("overlong", dropped)
            raise RemoteProtocolError(f"{dropped} request bytes over the buffer", kind="overlong")
        buf = self._buf
        # Bytes up to ' ' between requests are harmless.
        skip = 0
        while skip < len(buf) and buf[skip] <= 0x20:
            skip += 1
        if skip:
            del buf[:skip]
        if len(buf) < _MIN_MSG_LEN:
            self._timed_out = False
            return None
        # After the timeout every buffered byte is final until the buffer runs dry.
        cursor = _Cursor(buf, self._timed_out)
        try:
            message = self._parse_request(cursor)
        except _NeedMoreError:
            self._timed_out = False
            return None
        except RemoteProtocolError:
            del buf[: max(cursor.pos, 1)]
            raise
        except (LocalProtocolError, OutOfRangeError) as exc:
            # e.g. a 400-digit number, a tone over 2**31 ms, non-ASCII LCD text
            dropped = max(cursor.pos, 1)
            del buf[:dropped]
            self.stats.fault("out_of_range", dropped)
            raise RemoteProtocolError(f"request out of range: {exc}", kind="out_of_range") from None
        del buf[: cursor.pos]
        self.stats.messages += 1
        return message

    def _parse_request(self, cur: _Cursor) -> m.AsipMessage:
        service = chr(cur.read())
        if service == "!":
            return m.DebugEchoRequest(cur.rest_of_line(skip_comma=False))
        if service == "$":
            return _parse_config(cur)
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
        return parser(cur, tag)


def _parse_config(cur: _Cursor) -> m.AsipMessage:
    text = cur.rest_of_line().lstrip("$").lstrip(",")
    ssid, _, password = text.partition(",")
    try:
        return m.WifiConfig(ssid, password)
    except LocalProtocolError:
        return m.UnknownRequest("$", "$")


# ------------------------------------------------------------------------------------------
# How each service reads its requests


_RequestParser = Callable[[_Cursor, str], m.AsipMessage]


def _parse_system(cur: _Cursor, tag: str) -> m.AsipMessage:
    simple: dict[str, m.AsipMessage] = {
        "?": m.VersionRequest(),
        "N": m.ServiceNamesRequest(),
        "S": m.PinServicesRequest(),
        "R": m.RestartRequest(),
    }
    return simple.get(tag) or m.UnknownRequest("#", tag)


def _parse_io(cur: _Cursor, tag: str) -> m.AsipMessage:
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


def _parse_motor(cur: _Cursor, tag: str) -> m.AsipMessage:
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
    def parse(cur: _Cursor, tag: str) -> m.AsipMessage:
        if tag == "A":
            return _auto_event(cur, service)
        return m.UnknownRequest(service, tag)

    return parse


def _parse_measuring(service: str) -> _RequestParser:
    def parse(cur: _Cursor, tag: str) -> m.AsipMessage:
        if tag == "A":
            return _auto_event(cur, service)
        if tag == "M":
            return m.MeasureRequest(service)
        return m.UnknownRequest(service, tag)

    return parse


def _parse_servo(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "W":
        servo, angle = cur.ints(2)
        if servo < 0:
            return m.UnknownRequest("S", tag, (servo, angle))
        return m.ServoWrite(min(servo, 255), max(0, min(angle, 180)))  # the board clamps
    return m.UnknownRequest("S", tag)


def _parse_tone(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "P":
        frequency, duration = cur.ints(2)
        if frequency > 0 and duration > 0:
            return m.PlayTone(min(frequency, 65535), duration)
        return m.UnknownRequest("T", tag, (frequency, duration))
    return m.UnknownRequest("T", tag)


def _parse_lcd(cur: _Cursor, tag: str) -> m.AsipMessage:
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


def _parse_pixels_or_pressure(cur: _Cursor, tag: str) -> m.AsipMessage:
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
# Replies


def _enc_ints(service: str, tag: str, values: Iterable[int]) -> str:
    items = [str(value) for value in values]
    return f"@{service},{tag},{format_body(len(items), ','.join(items))}"


def _enc_pairs(
    service: str,
    tag: str,
    name: str,
    pairs: tuple[tuple[int, int], ...],
    bounds: tuple[tuple[int, int], tuple[int, int]],
    *,
    hex_second: bool = False,
) -> str:
    check_range(name, (first for first, _ in pairs), bounds[0])
    check_range(name, (second for _, second in pairs), bounds[1])
    body = format_body(len(pairs), format_pairs(pairs, hex_second=hex_second))
    return f"@{service},{tag},{body}"


def _enc_version(msg: m.VersionReply) -> str:
    check_range("version", (msg.major, msg.minor, msg.pin_count), BYTE)
    return f"@#,?,{msg.major},{msg.minor},{msg.chip},{msg.pin_count},{msg.sketch}"


def _enc_service_names(msg: m.ServiceNamesReply) -> str:
    items = ",".join(f"{sid}:{name}" for sid, name in msg.services)
    return f"@#,N,{format_body(len(msg.services), items)}"


def _enc_pin_modes(msg: m.PinModesReply) -> str:
    check_range("pin mode", msg.modes, BYTE)
    return _enc_ints("I", "p", msg.modes)


def _enc_capabilities(msg: m.CapabilitiesReply) -> str:
    check_range("capabilities", msg.capabilities, BYTE)
    return _enc_ints("I", "c", msg.capabilities)


def _enc_digital(msg: m.DigitalPortEvent) -> str:
    check_range("port", (msg.port,), BYTE)
    check_range("mask", (msg.mask,), PORT_MASK)
    return f"@I,d,{msg.port},{msg.mask:X}"


def _enc_bump(msg: m.BumpEvent) -> str:
    check_range("bump level", msg.raw, BUMP_LEVEL)
    return _enc_ints("B", "e", msg.raw)


def _enc_ir(msg: m.IrEvent) -> str:
    check_range("IR value", msg.values, ANALOG_VALUE)
    return _enc_ints("R", "e", msg.values)


def _enc_distance(msg: m.DistanceEvent) -> str:
    check_range("distance_cm", msg.distances_cm, DISTANCE_CM)
    return _enc_ints("D", "e", msg.distances_cm)


def _enc_axes(service: str, axes: tuple[int, ...]) -> str:
    check_range("axis", axes, IMU_AXIS)
    return _enc_ints(service, "e", axes)


def _enc_heading(msg: m.HeadingEvent) -> str:
    check_range("heading_deg", (msg.heading_deg,), HEADING_DEG)
    return _enc_axes("H", (msg.x, msg.y, msg.z, msg.heading_deg))


def _enc_pressure(msg: m.PressureEvent) -> str:
    check_range("pressure_mbar", (msg.pressure_mbar,), PRESSURE_MBAR)
    check_range("temperature_c", (msg.temperature_c,), TEMPERATURE_C)
    check_range("altitude_m", (msg.altitude_m,), ALTITUDE_M)
    return f"@P,e,3,{{{msg.pressure_mbar:.2f},{msg.temperature_c:.2f},{msg.altitude_m:.2f}}}"


def _enc_pixel_info(msg: m.PixelsInfoReply) -> str:
    check_range("strip", (msg.strip,), BYTE)
    check_range("count", (msg.count,), PIXEL_COUNT)
    return f"@P,I,{msg.strip},{msg.count}"


def _enc_error(msg: m.ErrorReply) -> str:
    check_range("errno", (msg.errno,), ERRNO)
    return f"~{msg.service},{msg.tag},{msg.errno}{{{msg.text}}}"


def _enc_startup(msg: m.StartupLine) -> str:
    # Each id is followed by a space, so the line ends with one, as on the board.
    services = "".join(f"{service} " for service in msg.services)
    return f"!{msg.sketch} running on {msg.chip} with Services: {services}"


_COUNTS = (ENCODER_COUNT, ENCODER_COUNT)

DEVICE_ENCODERS: dict[type, Callable[..., str]] = {
    m.VersionReply: _enc_version,
    m.ServiceNamesReply: _enc_service_names,
    m.PinServicesReply: lambda msg: (
        f"@#,S,{format_body(len(msg.services), ','.join(msg.services))}"
    ),
    m.PortMapReply: lambda msg: _enc_pairs(
        "I", "M", "port map", msg.ports, (BYTE, PORT_MASK), hex_second=True
    ),
    m.AnalogMapReply: lambda msg: _enc_pairs("I", "m", "analog map", msg.pairs, (BYTE, BYTE)),
    m.PinModesReply: _enc_pin_modes,
    m.CapabilitiesReply: _enc_capabilities,
    m.DigitalPortEvent: _enc_digital,
    m.AnalogEvent: lambda msg: _enc_pairs("I", "a", "analog", msg.values, (BYTE, ANALOG_VALUE)),
    m.EncoderEvent: lambda msg: _enc_pairs("M", "e", "encoder count", msg.counts, _COUNTS),
    m.LegacyEncoderEvent: lambda msg: _enc_pairs("E", "e", "encoder value", msg.values, _COUNTS),
    m.BumpEvent: _enc_bump,
    m.IrEvent: _enc_ir,
    m.DistanceEvent: _enc_distance,
    m.AccelerometerEvent: lambda msg: _enc_axes("A", (msg.x, msg.y, msg.z)),
    m.GyroEvent: lambda msg: _enc_axes("G", (msg.x, msg.y, msg.z)),
    m.HeadingEvent: _enc_heading,
    m.PressureEvent: _enc_pressure,
    m.PixelsInfoReply: _enc_pixel_info,
    m.GenericEvent: lambda msg: f"@{msg.service},{msg.tag},{','.join(msg.fields)}",
    m.ErrorReply: _enc_error,
    m.StartupLine: _enc_startup,
    m.InfoLine: lambda msg: f"!{msg.text}",
    m.DebugLine: lambda msg: msg.text,
}
"""Reply type -> its text on the wire, without the newline."""
