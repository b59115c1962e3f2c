"""The board's side of ASIP: requests read the way the firmware reads them, replies written.

Requests
    :class:`RequestReader` reads requests the way the V1.1 firmware (``asip.cpp``
    ``asipClass::service`` and each service's ``processRequestMsg``) does, on Arduino
    ``Stream`` semantics as the board's core implements them (the Teensy 3 core on the
    MIRTO's Teensy 3.1, the Arduino AVR core on an ATmega328P; they differ in
    ``readBytesUntil``, which reads one byte more on the AVR):

    * nothing starts before four bytes are buffered; bytes up to ``' '`` between requests are
      skipped; a known service letter must be followed by ``,``, otherwise (and for an
      unknown letter) the board answers ``~<letter>,?,1{INVALID_SERVICE}`` at once and then
      skips only the bytes received *by the time it has answered* (those there at the next
      :meth:`RequestReader.next_message`) up to a newline, never waiting for one;
    * numbers are read with ``parseInt``: skip anything that is not a digit or ``-``, read
      digits, then wait for the byte after the number. Requests need no newline
      (``M,A,1M,A,1R,A,25`` is three requests) and a short request swallows the next number
      (``M,S\\nM,A,1`` loses the ``1``);
    * every *timed* read (``parseInt``, ``find``, ``readBytesUntil``) waits up to 1 s for a
      byte; a plain ``read()`` returns -1 at once. While a timed read waits,
      :attr:`RequestReader.waiting` is true: the firmware is stuck inside the request and
      runs nothing else. The device calls :meth:`RequestReader.parse_timeout` when its clock
      says a wait ran out; each call ends one wait, as each ``timedPeek`` has its own second
      (``M,m,1`` takes two).

    Some requests are answered while they are read: the servo service refuses an id it does
    not have before reading the angle (``S,W,5`` then ``,45`` is left for the next request,
    which the board answers ``~,,?,1{INVALID_SERVICE}``). Such a request decodes as
    :class:`~roboscript.drivers.asip.messages.RefusedRequest` with the error the board sends.
    A number is kept in ``parseInt``'s 32-bit ``long``, which wraps as on the board (every
    digit is read), and then in the variable the firmware keeps it in: an ``int`` is the
    board's (``int_bits``): 16 bits on an ATmega328P (``M,A,65536`` turns encoder events off,
    ``L,W,65537,hi`` writes row 1), 32 on the MIRTO's Teensy 3.1 (the ``long`` itself); an
    ``unsigned int`` (an auto-event interval) as wide, unsigned; a ``byte`` 8. A known
    request whose values the board reads and then does nothing with (a motor id past the
    wheels as a ``byte``, an LCD row before the first) decodes as
    :class:`~roboscript.drivers.asip.messages.IgnoredRequest`; a value no message can hold
    otherwise is an ``"out_of_range"`` fault, and the request is dropped.

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

DEFAULT_SERVICES = "IMEBRDSTLPAGH!$"
"""Service ids a device-role codec accepts unless told otherwise, and the headers of two
optional builds: ``!`` (an ``ASIP_DEBUG`` build echoes the line to its debug stream) and ``$``
(ASIP 1.2's WiFi configuration). Without ``!`` the board reads the header and does nothing
more (``processDebugMsg`` is empty); without ``$`` it is an unknown service."""

_MIN_MSG_LEN = 4
_MAX_COUNT = 256  # bound on element counts read from a request (pixels, bars)
_PARSE_HIGH = PARSE_INT[1]
_LONG_MASK = 0xFFFF_FFFF  # parseInt's long: 32 bits on every ASIP board
_LCD_ROW_BYTES = m.LCD_COLUMNS + 1  # asipLCD's row buffer: 20 characters and the NUL
_NEWLINE = 0x0A
_LONGEST_MS = 2_147_483_647  # the longest duration a motor message holds (24.8 days)
_MAX_MOTOR_ID = 15  # the highest id a motor message holds; the board drives 0 and 1


class _NeedMoreError(Exception):
    """Internal: a timed read found the buffer empty; the board waits inside the request."""


class _Cursor:
    """Reads one request from a buffer with the firmware's ``Stream`` semantics.

    The reader parses a request again from its start whenever bytes arrive; timed reads are
    counted, and the ones that already ran out of time (``timed_out``, by their count) give
    -1 again, so a request read in pieces takes the same path as on the board.
    """

    __slots__ = ("buf", "int_bits", "pos", "skip_line_after", "timed_ops", "timed_out")

    def __init__(self, buf: bytearray, timed_out: frozenset[int], int_bits: int = 16) -> None:
        self.buf = buf
        self.pos = 0
        self.timed_ops = 0
        self.timed_out = timed_out
        self.skip_line_after = False
        self.int_bits = int_bits

    def read(self) -> int:
        """``Stream::read``: the next byte, or -1 at once when none has arrived."""
        if self.pos >= len(self.buf):
            return -1
        byte = self.buf[self.pos]
        self.pos += 1
        return byte

    def timed_peek(self) -> int:
        """``Stream::timedPeek``: the next byte, unread, or -1 once its wait ran out."""
        index = self.timed_ops
        self.timed_ops += 1
        if index in self.timed_out:
            return -1
        if self.pos >= len(self.buf):
            raise _NeedMoreError
        return self.buf[self.pos]

    def timed_read(self) -> int:
        """``Stream::timedRead``: the next byte, or -1 once its wait ran out."""
        byte = self.timed_peek()
        if byte >= 0:
            self.pos += 1
        return byte

    def parse_int(self) -> int:
        """``Stream::parseInt``: skip to a digit or ``-``, read digits, peek past them.

        The value is kept in a 32-bit ``long`` as on the board, whose ``value * 10 + digit``
        wraps: every digit is read, however many, and the request goes on with the wrapped
        number (``4294967299`` is 3).
        """
        while True:  # peekNextDigit
            byte = self.timed_peek()
            if byte < 0:
                return 0
            if byte == 0x2D or 0x30 <= byte <= 0x39:
                break
            self.pos += 1
        negative = False
        value = 0
        while True:
            if byte == 0x2D:
                negative = True
            else:
                value = (value * 10 + byte - 0x30) & _LONG_MASK
            self.pos += 1
            byte = self.timed_peek()
            if not 0x30 <= byte <= 0x39:
                break
        if negative:
            value = -value & _LONG_MASK
        return value - (_LONG_MASK + 1) if value > _PARSE_HIGH else value

    def parse_board_int(self) -> int:
        """``int x = parseInt()``: the ``long`` cut to the board's ``int`` (16 bits on an
        ATmega328P, 32 on a Teensy 3.1, where it is the ``long`` itself)."""
        bits = self.int_bits
        value = self.parse_int() & ((1 << bits) - 1)
        return value - (1 << bits) if value >> (bits - 1) else value

    def parse_board_uint(self) -> int:
        """``unsigned int x = parseInt()``: the ``long`` cut to the board's ``unsigned int``
        (16 bits on an ATmega328P: ``-5`` is 65531; 32 on a Teensy 3.1)."""
        return self.parse_int() & ((1 << self.int_bits) - 1)

    def ints(self, count: int) -> tuple[int, ...]:
        """``count`` numbers, each kept in the board's ``int``."""
        return tuple(self.parse_board_int() for _ in range(count))

    def find(self, target: bytes) -> bool:
        """``Stream::find``: read until ``target`` has been read; False on a timeout (or, in
        the Teensy 3 core, a NUL).

        Like the Teensy 3 core, a mismatch restarts the match without looking at the byte
        again; the AVR core's ``findMulti`` (a 16-bit board) walks back to the longest match
        that byte continues (``,,{`` holds ``,{``).
        """
        if self.int_bits == 16:
            return self._find_avr(target)
        index = 0
        while (byte := self.timed_read()) > 0:
            if byte == target[index]:
                index += 1
                if index == len(target):
                    return True
            else:
                index = 0
        return False

    def _find_avr(self, target: bytes) -> bool:
        """The AVR core's ``Stream::findMulti`` with one target: only a timeout ends it."""
        index = 0
        while (byte := self.timed_read()) >= 0:
            if byte == target[index]:
                index += 1
                if index == len(target):
                    return True
                continue
            matched = index
            while index:  # the longest shorter match that this byte continues
                index -= 1
                if byte == target[index]:
                    diff = matched - index
                    if all(target[i] == target[i + diff] for i in range(index)):
                        index += 1
                        break
        return False

    def read_bytes_until(self, terminator: int, length: int) -> str:
        """``Stream::readBytesUntil``: up to ``terminator`` (consumed, not kept) or a timeout,
        at most ``length - 1`` bytes in the Teensy 3 core (a 32-bit board), ``length`` in the
        Arduino AVR core (an ATmega328P, a 16-bit board)."""
        most = length if self.int_bits == 16 else length - 1
        text = bytearray()
        while len(text) < most:
            byte = self.timed_read()
            if byte == terminator or byte < 0:
                break
            text.append(byte)
        return text.decode("ascii", "replace")

    def skip_received_line_after_answer(self) -> None:
        """``while (available() && read() != '\\n')`` once the request is answered: the bytes
        that have arrived by then go, up to a newline; it never waits for one."""
        self.skip_line_after = True

    def line_or_timeout(self) -> str:
        """Bytes up to a newline (consumed, not returned) or a timeout; a CR before it goes."""
        text = bytearray()
        while (byte := self.timed_read()) >= 0 and byte != _NEWLINE:
            text.append(byte)
        return text.decode("ascii", "replace").rstrip("\r")


class RequestReader:
    """Reads requests from the host's byte stream with the firmware's semantics.

    Args:
        stats: Where messages and faults are counted.
        services: The service ids the board runs; a request for any other service decodes as
            :class:`~roboscript.drivers.asip.messages.InvalidServiceRequest`. ``!`` and ``$``
            in it: the board's build reads those headers (see :data:`DEFAULT_SERVICES`).
        max_buffer_bytes: Bound on buffered request bytes; the oldest go first.
        servo_count: How many servos the sketch declares, or None to read every ``S,W`` in
            full; with a count, ``S,W`` is refused the way the firmware refuses it (error 8
            with no servos before reading the id, error 7 for an id past the last before
            reading the angle).
        int_bits: The width of the board's ``int``, bits: 16 on an ATmega328P (``M,A,65536``
            turns encoder events off), 32 on the MIRTO's Teensy 3.1 (it turns them on).
    """

    def __init__(
        self,
        stats: CodecStats,
        services: str,
        max_buffer_bytes: int,
        servo_count: int | None = None,
        int_bits: int = 16,
    ) -> None:
        if int_bits not in (16, 32):
            raise ValueError(f"a board's int is 16 or 32 bits, not {int_bits}")
        self.stats = stats
        self.services = services
        self.servo_count = servo_count
        self.int_bits = int_bits
        self._max_buffer = max_buffer_bytes
        self._buf = bytearray()  # request bytes not yet parsed
        self._timed_out: set[int] = set()  # the timed reads of this request that ran out
        self._waiting_op: int | None = None  # the timed read the board is waiting in
        self._overflowed = 0  # bytes dropped by receive_data(), not yet reported
        self._skip_line = False  # the last request's line goes when the board reads next

    @property
    def waiting(self) -> bool:
        """True while a timed read waits inside a request: the board runs nothing else."""
        return self._waiting_op is not None

    def receive_data(self, data: bytes) -> None:
        """Add bytes read from the wire."""
        self._buf += data
        if len(self._buf) > self._max_buffer:
            # A request never needs this much; keep the newest bytes so parsing resynchronises.
            excess = len(self._buf) - self._max_buffer
            del self._buf[:excess]
            self._overflowed += excess  # counted and raised by the next next_message()
            self._timed_out.clear()
            self._waiting_op = None

    @property
    def skip_pending(self) -> bool:
        """True while the rest of the last request's line is still to be skipped."""
        return self._skip_line

    def skip_received(self) -> int:
        """Skip what has been received of the last request's line (``while (available() &&
        read() != '\\n')``, never waiting for more), through its newline.

        Returns:
            The bytes read and dropped, the newline among them; the skip is over once the
            newline is dropped, or when the caller finds nothing more has arrived (see
            :meth:`end_skip`).
        """
        if not self._skip_line:
            return 0
        buf = self._buf
        newline = buf.find(_NEWLINE)
        dropped = len(buf) if newline < 0 else newline + 1
        del buf[:dropped]
        if newline >= 0:
            self._skip_line = False
        return dropped

    def end_skip(self) -> None:
        """Nothing more has arrived: the skip ends (the firmware does not wait for the
        newline)."""
        self._skip_line = False

    def parse_timeout(self) -> None:
        """The timed read the board waits in ran out of time (1 s with no byte): it gives -1."""
        if self._waiting_op is not None:
            self._timed_out.add(self._waiting_op)

    def pending_bytes(self) -> int:
        """Bytes received and not yet parsed or dropped."""
        return len(self._buf)

    def next_message(self) -> m.AsipMessage | None:
        """The next complete request, or ``None`` when the board waits for more bytes.

        Raises:
            RemoteProtocolError: Bytes over the buffer bound (``"overlong"``), a system request
                without its ``,`` (``"malformed"``) or a value out of range
                (``"out_of_range"``), already consumed and counted.
        """
        if self._overflowed:
            dropped, self._overflowed = self._overflowed, 0
            self.stats.fault("overlong", dropped)
            raise RemoteProtocolError(f"{dropped} request bytes over the buffer", kind="overlong")
        buf = self._buf
        # The firmware skips the rest of the line after its answer: what has arrived by now (a
        # UART board has received more while it wrote), never waiting for more.
        self.skip_received()
        self.end_skip()
        # Bytes up to ' ' between requests are harmless.
        skip = 0
        while skip < len(buf) and buf[skip] <= 0x20:
            skip += 1
        if skip:
            del buf[:skip]
        if len(buf) < _MIN_MSG_LEN:
            return None
        cursor = _Cursor(buf, frozenset(self._timed_out), self.int_bits)
        try:
            message = self._parse_request(cursor)
        except _NeedMoreError:
            self._waiting_op = cursor.timed_ops - 1
            return None
        except RemoteProtocolError:
            self._request_done(max(cursor.pos, 1))
            raise
        except (LocalProtocolError, OutOfRangeError) as exc:
            # e.g. a negative tone duration wrapped past 2**31 ms, non-ASCII LCD text
            dropped = max(cursor.pos, 1)
            self._request_done(dropped)
            self.stats.fault("out_of_range", dropped)
            raise RemoteProtocolError(f"request out of range: {exc}", kind="out_of_range") from None
        self._request_done(cursor.pos)
        self._skip_line = cursor.skip_line_after
        self.stats.messages += 1
        return message

    def _request_done(self, consumed: int) -> None:
        del self._buf[:consumed]
        self._timed_out.clear()
        self._waiting_op = None

    def _parse_request(self, cur: _Cursor) -> m.AsipMessage:
        service = chr(cur.read())
        if service == "!":
            if "!" in self.services:  # an ASIP_DEBUG build echoes the line to its debug stream
                return m.DebugEchoRequest(cur.line_or_timeout())
            # asip.cpp takes the info header alone; the rest of the line is read as requests
            return m.IgnoredRequest("!", "")
        if service == "$" and "$" in self.services:
            return _parse_config(cur)
        if service == "#":
            if cur.read() != 0x2C:
                self.stats.fault("malformed", 2)
                raise RemoteProtocolError("system request not followed by ','", kind="malformed")
            return _parse_system(cur, _read_tag(cur))
        parser = _REQUEST_PARSERS.get(service) if service in self.services else None
        # The firmware reads the separator only for a service it runs; either way a
        # letter it cannot serve is answered at once and the received rest of its line goes.
        if parser is None or cur.read() != 0x2C:
            cur.skip_received_line_after_answer()
            return m.InvalidServiceRequest(service)
        tag = _read_tag(cur)
        if service == "S" and self.servo_count is not None:
            return _parse_servo_counted(cur, tag, self.servo_count)
        return parser(cur, tag)


def _read_tag(cur: _Cursor) -> str:
    """The request's tag byte (``char`` -1 when none has arrived, as on the board).

    Unlike the board, spaces before it are skipped: the seed's examples write
    ``M, M, 30, -30``, and the simulated board takes them.
    """
    byte = cur.read()
    while byte == 0x20:
        byte = cur.timed_read()
    return chr(byte & 0xFF)


def _parse_config(cur: _Cursor) -> m.AsipMessage:
    text = cur.line_or_timeout().lstrip("$").lstrip(",")
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
    if tag in "Pda":
        # asipIO reads both numbers first; the pin is a byte, a digital value any non-zero.
        number, value = cur.ints(2)
        pin = number & 0xFF
        if tag == "P":
            if not 0 <= value <= 8:
                return m.UnknownRequest("I", tag, (pin, value))  # an INVALID_MODE on the board
            return m.SetPinMode(pin, m.PinMode(value))
        if tag == "d":
            return m.DigitalWrite(pin, 1 if value & 0xFF else 0)
        return m.AnalogWrite(pin, max(0, min(value, 255)))
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
    # setAutoreport keeps the interval in an unsigned int: -5 is 65531 on a 328P
    return m.SetAutoEventInterval(service, cur.parse_board_uint())


def _parse_motor(cur: _Cursor, tag: str) -> m.AsipMessage:
    # processRequestMsg keeps its three arguments in ints
    first = cur.parse_board_int()
    if tag == "A":
        return m.EnableEncoderEvents(first != 0)
    if tag == "S":
        return m.StopMotors()
    if tag == "E":
        return m.ResetEncoders()
    second = cur.parse_board_int()
    third = cur.parse_board_int() if tag in "rR" else 0
    args = (first, second, third) if tag in "rR" else (first, second)
    # setMotorPower, setMotorRPM and stopMotor take the id as a byte (-1 is 255) and do
    # nothing for one past the wheels, without a word.
    if tag in "mrs":
        first &= 0xFF
        if first > _MAX_MOTOR_ID:
            return m.IgnoredRequest("M", tag, args)
    try:
        if tag == "m":
            return m.SetMotorPower(first, max(-100, min(second, 100)))
        if tag == "M":
            return m.SetMotorsPower(max(-100, min(first, 100)), max(-100, min(second, 100)))
        # the duration's int becomes setMotorRPM's unsigned long: -1 is 49 days (no run
        # lasts the 24 days a message holds)
        duration_ms = min(third & 0xFFFF_FFFF, _LONGEST_MS)
        if tag == "r":
            return m.SetMotorRpm(first, second, duration_ms)
        if tag == "R":
            return m.SetMotorsRpm(first, second, duration_ms)
        if tag == "c":
            return m.SetRobotSpeed(first, min(second & 0xFFFF_FFFF, _LONGEST_MS))
        if tag == "a":
            return m.RotateRobot(first, second)
        if tag == "s":
            return m.StopMotor(first)
    except LocalProtocolError:
        # a value no message holds (an rpm past 1000): the board never answers a known tag
        return m.IgnoredRequest("M", tag, args)
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


def _servo_angle(value: int) -> int:
    # write(byte servoId, byte angle): the angle is cut to a byte, then limited to 180.
    return min(value & 0xFF, 180)


def _parse_servo(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "W":
        servo, angle = cur.ints(2)
        if servo < 0:
            return m.UnknownRequest("S", tag, (servo, angle))
        return m.ServoWrite(min(servo, 255), _servo_angle(angle))
    return m.UnknownRequest("S", tag)


def _parse_servo_counted(cur: _Cursor, tag: str, count: int) -> m.AsipMessage:
    """``S,W`` as asipServos reads it on a sketch with ``count`` servos."""
    if tag != "W":
        return m.UnknownRequest("S", tag)
    if count == 0:
        return m.RefusedRequest("S", tag, int(m.ErrorCode.DEVICE_NOT_AVAILABLE))
    servo = cur.parse_board_int()
    if servo > count - 1:
        return m.RefusedRequest("S", tag, int(m.ErrorCode.INVALID_DEVICE_NUMBER))
    angle = cur.parse_board_int()
    # write(byte servoId, ...) takes the id's low byte: -1 is 255 (no servo moves), while
    # -256 is servo 0
    if servo & 0xFF > count - 1:
        return m.IgnoredRequest("S", tag, (servo, angle))
    return m.ServoWrite(servo & 0xFF, _servo_angle(angle))


def _parse_tone(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "P":
        # asipTone keeps both in ints: on a 328P a duration past 32767 ms is negative, and
        # the board plays nothing; tone() takes the pitch as 16 bits unsigned
        frequency, duration = cur.ints(2)
        if frequency > 0 and duration > 0:
            if not frequency & 0xFFFF:
                return m.IgnoredRequest("T", tag, (frequency, duration))
            return m.PlayTone(frequency & 0xFFFF, duration)
        return m.UnknownRequest("T", tag, (frequency, duration))
    return m.UnknownRequest("T", tag)


def _parse_lcd(cur: _Cursor, tag: str) -> m.AsipMessage:
    """asipLCD: a line past the fifth reads nothing more (its text is left for the next
    request); the text ends at a newline, a timeout or the row buffer's 20 characters."""
    if tag == "W":
        line = cur.parse_board_int()
        if line >= m.LCD_LINES or not cur.find(b","):
            return m.UnknownRequest("L", tag, (line,))
        if line < 0:
            # `line < nbrTextLines` lets it through: the text is read, and copied before the
            # first row's buffer, where no row shows it.
            cur.read_bytes_until(_NEWLINE, _LCD_ROW_BYTES)
            return m.IgnoredRequest("L", tag, (line,))
        # strlcpy shows 20 of the characters read (the AVR core reads 21); the CR of a CRLF
        # lands in the row too, where the font shows nothing: drop it.
        text = cur.read_bytes_until(_NEWLINE, _LCD_ROW_BYTES)[: m.LCD_COLUMNS]
        return m.LcdWrite(line, text.rstrip("\r"))
    if tag == "w":
        line = cur.parse_board_int()
        if line >= m.LCD_LINES or not cur.find(b","):
            return m.UnknownRequest("L", tag, (line,))
        column = cur.parse_board_int()
        if column >= _LCD_ROW_BYTES or cur.read() != 0x2C:
            return m.UnknownRequest("L", tag, (line, column))
        text = cur.read_bytes_until(_NEWLINE, _LCD_ROW_BYTES - column)[: m.LCD_COLUMNS - column]
        if line < 0 or column < 0:
            # read as the board reads it; it lands outside the row (this model shows nothing)
            return m.IgnoredRequest("L", tag, (line, column))
        return m.LcdWriteAt(line, column, text.rstrip("\r"))
    if tag == "G":
        count = min(cur.parse_board_int(), _MAX_COUNT)
        if not cur.find(b",{"):
            return m.UnknownRequest("L", tag)
        bars = tuple((line, max(0, min(value, 100))) for line, value in _pairs(cur, count))
        if all(0 <= line < m.LCD_LINES for line, _ in bars):
            return m.LcdBarGraph(bars)
        return m.UnknownRequest("L", tag)
    if tag == "C":
        return m.LcdClear()
    return m.UnknownRequest("L", tag)


def _pairs(cur: _Cursor, count: int, *, long_second: bool = False) -> tuple[tuple[int, int], ...]:
    """``count`` pairs of ``int``s (the second a ``long`` with ``long_second``)."""
    second = cur.parse_int if long_second else cur.parse_board_int
    return tuple((cur.parse_board_int(), second()) for _ in range(count))


def _rgb(cur: _Cursor) -> tuple[int, int, int]:
    # parseRGB keeps each channel in a uint8_t.
    r, g, b = (value & 0xFF for value in cur.ints(3))
    return r, g, b


def _open_brace(cur: _Cursor) -> bool:
    """``read() == ',' && read() == '{'``: plain reads, so a late brace is a missing one."""
    return cur.read() == 0x2C and cur.read() == 0x7B


def _parse_pixels_or_pressure(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag == "M":
        return m.MeasureRequest("P")
    if tag == "A":
        return _auto_event(cur, "P")
    message = _parse_pixels(cur, tag)
    cur.skip_received_line_after_answer()  # the pixels service drops what it has of the line
    return message


def _parse_pixels(cur: _Cursor, tag: str) -> m.AsipMessage:
    if tag not in "PpSsBIC":
        return m.UnknownRequest("P", tag)
    strip = cur.parse_board_int()
    if tag in "PpSs":
        # A negative count would loop for ever on the board; a huge one waits a second a pixel.
        count = max(0, min(cur.parse_board_int(), _MAX_COUNT))
        first = cur.parse_board_int() if tag in "Ss" else 0
        if not _open_brace(cur):
            count = 0  # nothing is set
        if tag == "P":
            pairs = tuple(
                (pixel & 0xFFFF, color & 0xFFFFFF)
                for pixel, color in _pairs(cur, count, long_second=True)
            )
            return m.PixelsSet(strip, pairs)
        if tag == "p":
            rgb_pairs = tuple((cur.parse_int() & 0xFFFF, _rgb(cur)) for _ in range(count))
            return m.PixelsSetRgb(strip, rgb_pairs)
        if tag == "S":
            colors = tuple(cur.parse_int() & 0xFFFFFF for _ in range(count))
            return m.PixelsSequence(strip, first, colors)
        return m.PixelsSequenceRgb(strip, first, tuple(_rgb(cur) for _ in range(count)))
    if tag == "B":
        return m.PixelsBrightness(strip, cur.parse_int() & 0xFF)
    if tag == "I":
        return m.PixelsInfoRequest(strip)
    return m.PixelsClear(strip)


_REQUEST_PARSERS: dict[str, _RequestParser] = {
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
