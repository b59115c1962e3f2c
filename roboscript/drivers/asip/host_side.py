"""The host's side of ASIP: requests written, the board's lines read.

:data:`HOST_ENCODERS` writes each request as ``svc,tag,args`` with no spaces (the framing adds
the newline). :func:`decode_line` reads one line of the board's output, already framed as text
by :class:`~roboscript.drivers.asip.framing.LineFramer`:

* ``@`` events and replies, in the firmware's form (``@S,t,`` with no spaces, found with one
  dict lookup on those five characters) or the seed's spaced form (``@I, d, 4, 10``); an event
  roboscript has no model for is kept as :class:`~roboscript.drivers.asip.messages.GenericEvent`;
* ``~`` errors: the firmware's ``~S,T,N{TEXT}``, where ``S`` and ``T`` are the bytes the board
  received, a comma included (``~,,?,1{INVALID_SERVICE}``), and the seed's ``~S,T,N,TEXT``;
* ``!`` info lines (the startup line among them), and any other line as sketch debug output.

A line that does not parse is a ``"malformed"`` fault; one with a number outside what the
firmware's types hold (:mod:`~roboscript.drivers.asip.value_ranges`) is an ``"out_of_range"``
fault. Both are counted and raised as :class:`~roboscript.errors.RemoteProtocolError`, never
anything else.
"""

from __future__ import annotations

from collections.abc import Callable

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
    PIXEL_COUNT,
    PORT_MASK,
    PRESSURE_MBAR,
    TEMPERATURE_C,
    OutOfRangeError,
)

__all__ = ["HOST_ENCODERS", "decode_line"]

IntRange = tuple[int, int]

_ERRNO_LOW, _ERRNO_HIGH = ERRNO

# ------------------------------------------------------------------------------------------
# Requests


def _enc_pixels_set(msg: m.PixelsSet) -> str:
    return f"P,P,{msg.strip},{format_body(len(msg.pixels), format_pairs(msg.pixels))}"


def _enc_pixels_set_rgb(msg: m.PixelsSetRgb) -> str:
    items = ",".join(f"{pixel}:{r}:{g}:{b}" for pixel, (r, g, b) in msg.pixels)
    return f"P,p,{msg.strip},{format_body(len(msg.pixels), items)}"


def _enc_pixels_sequence(msg: m.PixelsSequence) -> str:
    items = ",".join(str(color) for color in msg.colors)
    return f"P,S,{msg.strip},{len(msg.colors)},{msg.first},{{{items}}}"


def _enc_pixels_sequence_rgb(msg: m.PixelsSequenceRgb) -> str:
    items = ",".join(f"{r}:{g}:{b}" for r, g, b in msg.colors)
    return f"P,s,{msg.strip},{len(msg.colors)},{msg.first},{{{items}}}"


HOST_ENCODERS: dict[type, Callable[..., str]] = {
    m.VersionRequest: lambda msg: "#,?",
    m.ServiceNamesRequest: lambda msg: "#,N",
    m.PinServicesRequest: lambda msg: "#,S",
    m.RestartRequest: lambda msg: "#,R",
    m.DebugEchoRequest: lambda msg: f"!{msg.text}",
    m.WifiConfig: lambda msg: f"$$,{msg.ssid},{msg.password}",
    m.SetPinMode: lambda msg: f"I,P,{msg.pin},{int(msg.mode)}",
    m.DigitalWrite: lambda msg: f"I,d,{msg.pin},{msg.value}",
    m.AnalogWrite: lambda msg: f"I,a,{msg.pin},{msg.value}",
    m.PortMapRequest: lambda msg: "I,M",
    m.AnalogMapRequest: lambda msg: "I,m",
    m.PinModesRequest: lambda msg: "I,p",
    m.CapabilitiesRequest: lambda msg: "I,c",
    m.SetAutoEventInterval: lambda msg: f"{msg.service},A,{msg.interval_ms}",
    m.MeasureRequest: lambda msg: f"{msg.service},M",
    m.SetMotorPower: lambda msg: f"M,m,{msg.motor},{msg.power_pct}",
    m.SetMotorsPower: lambda msg: f"M,M,{msg.power0_pct},{msg.power1_pct}",
    m.SetMotorRpm: lambda msg: f"M,r,{msg.motor},{msg.rpm},{msg.duration_ms}",
    m.SetMotorsRpm: lambda msg: f"M,R,{msg.rpm0},{msg.rpm1},{msg.duration_ms}",
    m.SetRobotSpeed: lambda msg: f"M,c,{msg.speed_cm_s},{msg.duration_ms}",
    m.RotateRobot: lambda msg: f"M,a,{msg.turn_rate_deg_s},{msg.angle_deg}",
    # The firmware reads one number more than these tags use: send a dummy so a request
    # never swallows the next one's first number.
    m.StopMotor: lambda msg: f"M,s,{msg.motor},0",
    m.StopMotors: lambda msg: "M,S,0",
    m.ResetEncoders: lambda msg: "M,E,0",
    m.EnableEncoderEvents: lambda msg: f"M,A,{int(msg.enabled)}",
    m.ServoWrite: lambda msg: f"S,W,{msg.servo},{msg.angle_deg}",
    m.PlayTone: lambda msg: f"T,P,{msg.frequency_hz},{msg.duration_ms}",
    m.LcdWrite: lambda msg: f"L,W,{msg.line},{msg.text}",
    m.LcdWriteAt: lambda msg: f"L,w,{msg.line},{msg.column},{msg.text}",
    m.LcdBarGraph: lambda msg: f"L,G,{format_body(len(msg.bars), format_pairs(msg.bars))}",
    m.LcdClear: lambda msg: "L,C",
    m.PixelsSet: _enc_pixels_set,
    m.PixelsSetRgb: _enc_pixels_set_rgb,
    m.PixelsSequence: _enc_pixels_sequence,
    m.PixelsSequenceRgb: _enc_pixels_sequence_rgb,
    m.PixelsBrightness: lambda msg: f"P,B,{msg.strip},{msg.level}",
    m.PixelsInfoRequest: lambda msg: f"P,I,{msg.strip}",
    m.PixelsClear: lambda msg: f"P,C,{msg.strip}",
}
"""Request type -> its text on the wire, without the newline."""

# ------------------------------------------------------------------------------------------
# Reading the board's lines


def decode_line(text: str) -> m.AsipMessage:
    """Decode one line of the board's output (text, no line ending, not blank).

    Raises:
        OutOfRangeError: A number is outside what the firmware's types hold.
        ValueError: The line does not parse (``IndexError`` for some short lines).
    """
    head = text[0]
    if head == "@":
        # The firmware writes "@S,t," with no spaces: one slice finds the decoder.
        decoder = _EVENT_DECODERS_BY_HEAD.get(text[:5])
        if decoder is not None:
            return decoder(text[5:])
        return _decode_event(text)
    if head == "~":
        return _decode_error(text)
    if head == "!":
        return _decode_info(text[1:])
    return m.DebugLine(text)


def _out_of_range(low: float, high: float) -> OutOfRangeError:
    return OutOfRangeError(f"a value outside {low}..{high}")


def _in_range(value: int, bounds: IntRange) -> int:
    low, high = bounds
    if value < low or value > high:
        raise _out_of_range(low, high)
    return value


def _decode_error(text: str) -> m.ErrorReply:
    if len(text) > 4 and text[2] == text[4] == ",":
        # The firmware's form: the service and tag are the bytes it read, commas included.
        service, tag, rest = text[1], text[3], text[5:]
    else:  # the seed's spaced form
        service, tag, rest = (part.strip() for part in text[1:].split(",", 2))
    brace = rest.find("{")
    if brace >= 0:
        number = rest[:brace].strip().rstrip(",")
        message = rest[brace + 1 :].rstrip("}")
    else:  # the seed's form: number, then text in its own field
        number, _, message = rest.partition(",")
    errno = int(number)
    if errno < _ERRNO_LOW or errno > _ERRNO_HIGH:
        raise _out_of_range(_ERRNO_LOW, _ERRNO_HIGH)
    return m.ErrorReply(service, tag, errno, message.strip())


def _decode_event(text: str) -> m.AsipMessage:
    """The general path: the seed's spaced form (``@I, d, ...``) and unknown events."""
    parts = text[1:].split(",", 2)
    service = parts[0].strip()
    tag = parts[1].strip()
    rest = parts[2].strip() if len(parts) > 2 else ""
    decoder = _EVENT_DECODERS.get((service, tag))
    if decoder is None:
        return m.GenericEvent(service, tag, _split_fields(rest))
    return decoder(rest)


def _decode_info(text: str) -> m.StartupLine | m.InfoLine:
    sketch, running, rest = text.partition(" running on ")
    if running:
        chip, with_services, services = rest.partition(" with Services:")
        if with_services:
            return m.StartupLine(sketch.strip(), chip.strip(), tuple(services.split()))
    return m.InfoLine(text)


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
    # The firmware writes "n,{": one slice; the seed's "n, {" and a bare "{" take the long way.
    count = (
        rest[: start - 1] if start and rest[start - 1] == "," else rest[:start].rstrip().rstrip(",")
    )
    if count and int(count) != len(items):
        raise ValueError(f"body has {len(items)} fields, header says {count.strip()[:12]}")
    return items


def _body_items(rest: str) -> list[str]:
    """``n,{a, b}`` -> ``["a", "b"]``: text fields, stripped."""
    return [item.strip() for item in _body_fields(rest)]


def _int_items(rest: str, bounds: IntRange) -> tuple[int, ...]:
    low, high = bounds
    values = tuple(map(int, _body_fields(rest)))
    for value in values:
        if value < low or value > high:
            raise _out_of_range(low, high)
    return values


def _ints_decoder(
    build: Callable[[tuple[int, ...]], m.AsipMessage], bounds: IntRange
) -> Callable[[str], m.AsipMessage]:
    """A decoder of ``n,{v,...}`` into ``build(values)``, each value within ``bounds``."""
    low, high = bounds  # a closure's cells are the cheapest lookups on the hot path

    def decode(rest: str) -> m.AsipMessage:
        values = tuple(map(int, _body_fields(rest)))
        for value in values:
            if value < low or value > high:
                raise _out_of_range(low, high)
        return build(values)

    return decode


def _pairs_decoder(
    build: Callable[[tuple[tuple[int, int], ...]], m.AsipMessage],
    first_bounds: IntRange,
    second_bounds: IntRange,
    *,
    hex_second: bool = False,
) -> Callable[[str], m.AsipMessage]:
    """A decoder of ``n,{a:b,...}`` into ``build(pairs)``, each number within its bounds."""
    low1, high1 = first_bounds
    low2, high2 = second_bounds
    base = 16 if hex_second else 10

    def decode(rest: str) -> m.AsipMessage:
        pairs = []
        for item in _body_fields(rest):  # a loop: a comprehension costs a function call on 3.11
            first_text, second_text = item.split(":")
            first = int(first_text)
            second = int(second_text, base)
            if first < low1 or first > high1:
                raise _out_of_range(low1, high1)
            if second < low2 or second > high2:
                raise _out_of_range(low2, high2)
            pairs.append((first, second))
        return build(tuple(pairs))

    return decode


def _decode_version(rest: str) -> m.VersionReply:
    major, minor, chip, pins, sketch = rest.split(",", 4)
    # int() ignores the spaces the seed's examples put after commas; only text needs strip().
    return m.VersionReply(
        _in_range(int(major), BYTE),
        _in_range(int(minor), BYTE),
        chip.strip(),
        _in_range(int(pins), BYTE),
        sketch.strip(),
    )


def _decode_service_names(rest: str) -> m.ServiceNamesReply:
    pairs = []
    for item in _body_items(rest):
        service, _, name = item.partition(":")
        pairs.append((service.strip(), name.strip()))
    return m.ServiceNamesReply(tuple(pairs))


def _decode_distance_seed(rest: str) -> m.DistanceEvent:
    # The seed documents "@D,M,<cm>"; the firmware sends "@D,e,1,{cm}". Accept both.
    if "{" in rest:
        return m.DistanceEvent(_int_items(rest, DISTANCE_CM))
    return m.DistanceEvent((_in_range(int(rest), DISTANCE_CM),))


def _digital_decoder() -> Callable[[str], m.AsipMessage]:
    """The decoder of ``port,MASK`` (``@I,d``), its bounds in closure cells for speed."""
    port_low, port_high = BYTE
    mask_low, mask_high = PORT_MASK

    def decode(rest: str) -> m.AsipMessage:
        port_text, mask_text = rest.split(",")
        port = int(port_text)  # int() ignores surrounding spaces
        mask = int(mask_text, 16)
        if port < port_low or port > port_high:
            raise _out_of_range(port_low, port_high)
        if mask < mask_low or mask > mask_high:
            raise _out_of_range(mask_low, mask_high)
        return m.DigitalPortEvent(port, mask)

    return decode


def _decode_pixel_info(rest: str) -> m.PixelsInfoReply:
    fields = [int(field) for field in _split_fields(rest)]
    if len(fields) == 1:  # ASIP 0.4: "@P,I,count"
        return m.PixelsInfoReply(0, _in_range(fields[0], PIXEL_COUNT))
    return m.PixelsInfoReply(_in_range(fields[0], BYTE), _in_range(fields[1], PIXEL_COUNT))


def _decode_pressure(rest: str) -> m.PressureEvent:
    mbar, temp, alt = map(float, _body_fields(rest)[:3])
    for value, (low, high) in ((mbar, PRESSURE_MBAR), (temp, TEMPERATURE_C), (alt, ALTITUDE_M)):
        if not low <= value <= high:  # this way round NaN fails too
            raise _out_of_range(low, high)
    return m.PressureEvent(mbar, temp, alt)


def _decode_heading(rest: str) -> m.HeadingEvent:
    x, y, z, heading = _int_items(rest, IMU_AXIS)[:4]
    return m.HeadingEvent(x, y, z, _in_range(heading, HEADING_DEG))


def _decode_xyz(rest: str) -> tuple[int, int, int]:
    x, y, z = _int_items(rest, IMU_AXIS)[:3]
    return x, y, z


_EVENT_DECODERS: dict[tuple[str, str], Callable[[str], m.AsipMessage]] = {
    ("#", "?"): _decode_version,
    ("#", "N"): _decode_service_names,
    ("#", "S"): lambda rest: m.PinServicesReply(tuple(_body_items(rest))),
    ("I", "M"): _pairs_decoder(m.PortMapReply, BYTE, PORT_MASK, hex_second=True),
    ("I", "m"): _pairs_decoder(m.AnalogMapReply, BYTE, BYTE),
    ("I", "p"): _ints_decoder(m.PinModesReply, BYTE),
    ("I", "c"): _ints_decoder(m.CapabilitiesReply, BYTE),
    ("I", "d"): _digital_decoder(),
    ("I", "a"): _pairs_decoder(m.AnalogEvent, BYTE, ANALOG_VALUE),
    ("I", "A"): _pairs_decoder(m.AnalogEvent, BYTE, ANALOG_VALUE),  # the seed's tag
    ("M", "e"): _pairs_decoder(m.EncoderEvent, ENCODER_COUNT, ENCODER_COUNT),
    ("E", "e"): _pairs_decoder(m.LegacyEncoderEvent, ENCODER_COUNT, ENCODER_COUNT),
    ("B", "e"): _ints_decoder(m.BumpEvent, BUMP_LEVEL),
    ("R", "e"): _ints_decoder(m.IrEvent, ANALOG_VALUE),
    ("D", "e"): _ints_decoder(m.DistanceEvent, DISTANCE_CM),
    ("D", "M"): _decode_distance_seed,
    ("A", "e"): lambda rest: m.AccelerometerEvent(*_decode_xyz(rest)),
    ("G", "e"): lambda rest: m.GyroEvent(*_decode_xyz(rest)),
    ("H", "e"): _decode_heading,
    ("P", "e"): _decode_pressure,
    ("P", "I"): _decode_pixel_info,
}

_EVENT_DECODERS_BY_HEAD: dict[str, Callable[[str], m.AsipMessage]] = {
    f"@{service},{tag},": decoder for (service, tag), decoder in _EVENT_DECODERS.items()
}
