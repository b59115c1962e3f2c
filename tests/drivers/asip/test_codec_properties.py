"""Property tests for the ASIP codec: chunking, arbitrary bytes, round trips, mutated lines."""

from __future__ import annotations

import itertools
import string
import typing

from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip import value_ranges as ranges
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.errors import RemoteProtocolError

EXAMPLES = 250
INT32 = 2_147_483_647
INT16 = 32_767
"""The largest ``int`` on the ATmega328P the simulated board is: the sketch keeps durations, tone
frequencies and strip numbers in one, so only these round-trip through it."""
Decoded = list[m.AsipMessage | RemoteProtocolError]

# ------------------------------------------------------------------------------------------
# Requests (host -> device), over each message's valid ranges

ascii_text = st.text(
    st.characters(min_codepoint=0, max_codepoint=0x7F, exclude_characters="\r\n"), max_size=24
)
pins = st.integers(0, 255)
motors = st.integers(0, 15)
percent = st.integers(-100, 100)
rpm = st.integers(-1000, 1000)
durations = st.integers(0, INT16)  # the sketch keeps them in a 328P's int
strips = st.integers(-INT16 - 1, INT16)
colors = st.integers(0, 0xFFFFFF)
rgb = st.tuples(st.integers(0, 255), st.integers(0, 255), st.integers(0, 255))
lcd_lines = st.integers(0, m.LCD_LINES - 1)


def lcd_text(column: int) -> st.SearchStrategy[str]:
    """Text that fits an LCD row from ``column``: the board reads no more of it."""
    return st.text(
        st.characters(min_codepoint=0, max_codepoint=0x7F, exclude_characters="\r\n"),
        max_size=m.LCD_COLUMNS - column,
    )


wifi_words = st.text(
    st.characters(min_codepoint=0, max_codepoint=0x7F, exclude_characters="\r\n,"),
    min_size=2,
    max_size=31,
)

REQUEST_STRATEGIES: dict[type, st.SearchStrategy[object]] = {
    m.VersionRequest: st.just(m.VersionRequest()),
    m.ServiceNamesRequest: st.just(m.ServiceNamesRequest()),
    m.PinServicesRequest: st.just(m.PinServicesRequest()),
    m.RestartRequest: st.just(m.RestartRequest()),
    m.DebugEchoRequest: st.builds(m.DebugEchoRequest, ascii_text),
    m.WifiConfig: st.builds(m.WifiConfig, wifi_words, wifi_words),
    m.SetPinMode: st.builds(m.SetPinMode, pins, st.sampled_from(list(m.PinMode))),
    m.DigitalWrite: st.builds(m.DigitalWrite, pins, st.integers(0, 1)),
    m.AnalogWrite: st.builds(m.AnalogWrite, pins, st.integers(0, 255)),
    m.PortMapRequest: st.just(m.PortMapRequest()),
    m.AnalogMapRequest: st.just(m.AnalogMapRequest()),
    m.PinModesRequest: st.just(m.PinModesRequest()),
    m.CapabilitiesRequest: st.just(m.CapabilitiesRequest()),
    m.SetAutoEventInterval: st.builds(
        m.SetAutoEventInterval,
        st.sampled_from(sorted(m.AUTO_EVENT_SERVICES)),
        st.integers(0, 65535),
    ),
    m.MeasureRequest: st.builds(m.MeasureRequest, st.sampled_from(sorted(m.MEASURE_SERVICES))),
    m.SetMotorPower: st.builds(m.SetMotorPower, motors, percent),
    m.SetMotorsPower: st.builds(m.SetMotorsPower, percent, percent),
    m.SetMotorRpm: st.builds(m.SetMotorRpm, motors, rpm, durations),
    m.SetMotorsRpm: st.builds(m.SetMotorsRpm, rpm, rpm, durations),
    m.SetRobotSpeed: st.builds(m.SetRobotSpeed, rpm, durations),
    m.RotateRobot: st.builds(m.RotateRobot, st.integers(1, 3600), st.integers(-32768, 32767)),
    m.StopMotor: st.builds(m.StopMotor, motors),
    m.StopMotors: st.just(m.StopMotors()),
    m.ResetEncoders: st.just(m.ResetEncoders()),
    m.EnableEncoderEvents: st.builds(m.EnableEncoderEvents, st.booleans()),
    m.ServoWrite: st.builds(m.ServoWrite, pins, st.integers(0, 180)),
    m.PlayTone: st.builds(m.PlayTone, st.integers(1, INT16), st.integers(1, INT16)),
    m.LcdWrite: st.builds(m.LcdWrite, lcd_lines, lcd_text(0)),
    m.LcdWriteAt: st.integers(0, m.LCD_COLUMNS).flatmap(
        lambda column: st.builds(m.LcdWriteAt, lcd_lines, st.just(column), lcd_text(column))
    ),
    m.LcdBarGraph: st.builds(
        m.LcdBarGraph,
        st.lists(st.tuples(lcd_lines, st.integers(0, 100)), max_size=8).map(tuple),
    ),
    m.LcdClear: st.just(m.LcdClear()),
    m.PixelsSet: st.builds(
        m.PixelsSet,
        strips,
        st.lists(st.tuples(st.integers(0, 65535), colors), max_size=8).map(tuple),
    ),
    m.PixelsSetRgb: st.builds(
        m.PixelsSetRgb,
        strips,
        st.lists(st.tuples(st.integers(0, 65535), rgb), max_size=8).map(tuple),
    ),
    m.PixelsSequence: st.builds(
        m.PixelsSequence, strips, strips, st.lists(colors, max_size=8).map(tuple)
    ),
    m.PixelsSequenceRgb: st.builds(
        m.PixelsSequenceRgb, strips, strips, st.lists(rgb, max_size=8).map(tuple)
    ),
    m.PixelsBrightness: st.builds(m.PixelsBrightness, strips, st.integers(0, 255)),
    m.PixelsInfoRequest: st.builds(m.PixelsInfoRequest, strips),
    m.PixelsClear: st.builds(m.PixelsClear, strips),
}
requests = st.one_of(*REQUEST_STRATEGIES.values())

# ------------------------------------------------------------------------------------------
# Replies (device -> host), over what the firmware can print

token = st.text(string.ascii_letters + string.digits + "._-", min_size=1, max_size=10)
words = st.lists(token, min_size=1, max_size=3).map(" ".join)
int16 = st.integers(-32768, 32767)
int32 = st.integers(-INT32 - 1, INT32)
bytes_ = st.integers(0, 255)


def hundredths(bounds: tuple[float, float]) -> st.SearchStrategy[float]:
    """Floats with two decimals within ``bounds``, as the board prints them."""
    low, high = (round(bound * 100) for bound in bounds)
    return st.integers(low, high).map(lambda n: n / 100)


service_ids = st.sampled_from(string.ascii_uppercase)
printable = st.characters(min_codepoint=0x21, max_codepoint=0x7E, exclude_characters=",")


def pairs(first: st.SearchStrategy[int], second: st.SearchStrategy[int]) -> st.SearchStrategy:
    return st.lists(st.tuples(first, second), max_size=8).map(tuple)


def ints(values: st.SearchStrategy[int]) -> st.SearchStrategy[tuple[int, ...]]:
    return st.lists(values, max_size=8).map(tuple)


REPLY_STRATEGIES: dict[type, st.SearchStrategy[object]] = {
    m.VersionReply: st.builds(m.VersionReply, bytes_, bytes_, token, bytes_, words),
    m.ServiceNamesReply: st.builds(
        m.ServiceNamesReply, st.lists(st.tuples(service_ids, words), max_size=8).map(tuple)
    ),
    m.PinServicesReply: st.builds(
        m.PinServicesReply,
        st.lists(st.sampled_from("@I" + string.ascii_uppercase), max_size=40).map(tuple),
    ),
    m.PortMapReply: st.builds(m.PortMapReply, pairs(bytes_, bytes_)),
    m.AnalogMapReply: st.builds(m.AnalogMapReply, pairs(bytes_, bytes_)),
    m.PinModesReply: st.builds(m.PinModesReply, ints(st.integers(0, 8))),
    m.CapabilitiesReply: st.builds(m.CapabilitiesReply, ints(st.integers(0, 7))),
    m.DigitalPortEvent: st.builds(m.DigitalPortEvent, bytes_, bytes_),
    m.AnalogEvent: st.builds(m.AnalogEvent, pairs(st.integers(0, 15), st.integers(0, 1023))),
    m.EncoderEvent: st.builds(m.EncoderEvent, pairs(int32, int32)),
    m.LegacyEncoderEvent: st.builds(m.LegacyEncoderEvent, pairs(int32, int32)),
    m.BumpEvent: st.builds(m.BumpEvent, ints(st.integers(0, 1))),
    m.IrEvent: st.builds(m.IrEvent, ints(st.integers(0, 1023))),
    m.DistanceEvent: st.builds(m.DistanceEvent, ints(st.integers(*ranges.DISTANCE_CM))),
    m.AccelerometerEvent: st.builds(m.AccelerometerEvent, int16, int16, int16),
    m.GyroEvent: st.builds(m.GyroEvent, int16, int16, int16),
    m.HeadingEvent: st.builds(m.HeadingEvent, int16, int16, int16, st.integers(0, 359)),
    m.PressureEvent: st.builds(
        m.PressureEvent,
        hundredths(ranges.PRESSURE_MBAR),
        hundredths(ranges.TEMPERATURE_C),
        hundredths(ranges.ALTITUDE_M),
    ),
    m.PixelsInfoReply: st.builds(m.PixelsInfoReply, bytes_, st.integers(0, 65535)),
    m.GenericEvent: st.builds(
        m.GenericEvent,
        st.sampled_from("XYZ"),  # services roboscript has no model for
        st.sampled_from("eqz"),
        st.lists(token, min_size=1, max_size=5).map(tuple),
    ),
    m.ErrorReply: st.builds(m.ErrorReply, service_ids | st.just("#"), printable, st.integers(0, 9))
    | st.builds(m.ErrorReply, service_ids, printable, st.integers(0, 99), words),
    m.StartupLine: st.builds(
        m.StartupLine, token, token, st.lists(service_ids, max_size=12).map(tuple)
    ),
    m.InfoLine: st.builds(m.InfoLine, words.filter(lambda text: " running on " not in text)),
    m.DebugLine: st.builds(m.DebugLine, words),  # words never start with @, ~ or !
}
replies = st.one_of(*REPLY_STRATEGIES.values())


def receives(role: Role) -> st.SearchStrategy[object]:
    """Messages a codec of ``role`` decodes."""
    return replies if role is Role.HOST else requests


# The pixel service reads the ``,{`` before a pixel list with plain reads, which do not wait:
# a split just before the brace makes the board read the list as missing, as on the real
# board (tests/conformance/test_asip.py). Only these requests depend on where bytes split.
_SPLIT_SENSITIVE = (m.PixelsSet, m.PixelsSetRgb, m.PixelsSequence, m.PixelsSequenceRgb)


def receives_split_free(role: Role) -> st.SearchStrategy[object]:
    """Messages ``role`` decodes the same whichever way their bytes are split."""
    return receives(role).filter(lambda message: not isinstance(message, _SPLIT_SENSITIVE))


def sender(role: Role) -> AsipCodec:
    """A codec of the other role, which sends what ``role`` receives."""
    return AsipCodec(Role.DEVICE if role is Role.HOST else Role.HOST)


# ------------------------------------------------------------------------------------------
# Helpers

SENTINEL = {Role.HOST: m.BumpEvent((1, 0)), Role.DEVICE: m.PortMapRequest()}


def split(data: bytes, cuts: list[int]) -> list[bytes]:
    points = sorted({min(cut, len(data)) for cut in cuts})
    bounds = [0, *points, len(data)]
    return [data[a:b] for a, b in itertools.pairwise(bounds)]


LINE_LIMIT = 512  # the codec's defaults
BUFFER_LIMIT = 4096


def feed(
    codec: AsipCodec, chunks: list[bytes], *, line: int = LINE_LIMIT, buffer: int = BUFFER_LIMIT
) -> Decoded:
    """Feed every chunk and drain after each, checking the buffer bound as we go.

    ``drain`` yields RemoteProtocolError and lets any other exception escape.
    """
    out: Decoded = []
    for chunk in chunks:
        codec.receive_data(chunk)
        out += drain(codec)
        assert codec.pending_bytes() <= (line if codec.role is Role.HOST else buffer)
    return out


def expected_requests(sent: list[object]) -> list[object]:
    """What the device decodes from ``sent``: the bar graph leaves ``}`` read as a service id."""
    out: list[object] = []
    for message in sent:
        out.append(message)
        if isinstance(message, m.LcdBarGraph):
            out.append(m.InvalidServiceRequest("}"))
    return out


def kinds(items: Decoded) -> list[object]:
    return [item.kind if isinstance(item, RemoteProtocolError) else item for item in items]


# ------------------------------------------------------------------------------------------
# Properties


def test_strategies_cover_every_message_type() -> None:
    # the device never sends these
    decoded_only = {
        m.InvalidServiceRequest,
        m.RefusedRequest,
        m.IgnoredRequest,
        m.UnknownRequest,
    }
    everything = set(typing.get_args(m.AsipMessage))
    assert set(REQUEST_STRATEGIES) | set(REPLY_STRATEGIES) | decoded_only == everything
    assert not set(REQUEST_STRATEGIES) & set(REPLY_STRATEGIES)


roles = st.sampled_from(list(Role))
cut_lists = st.lists(st.integers(0, 400), max_size=24)


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.data(), roles, cut_lists)
def test_round_trip_of_a_stream_in_any_chunking(
    data: st.DataObject, role: Role, cuts: list[int]
) -> None:
    sent = data.draw(st.lists(receives_split_free(role), max_size=8))
    sent.append(SENTINEL[role])  # a short last request waits for four bytes: close the stream
    encoder = sender(role)
    stream = b"".join(encoder.send(message) for message in sent)
    expected = sent if role is Role.HOST else expected_requests(sent)

    whole = AsipCodec(role)
    assert feed(whole, [stream]) == expected
    chunked = AsipCodec(role)
    assert feed(chunked, split(stream, cuts)) == expected
    for codec in (whole, chunked):
        assert codec.pending_bytes() == 0
        assert not codec.stats.faults
        assert codec.stats.messages == len(expected)


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.data(), roles)
def test_each_message_goes_out_as_one_line_without_spaces(data: st.DataObject, role: Role) -> None:
    message = data.draw(receives(role))
    wire = sender(role).send(message)
    assert wire.endswith(b"\n")
    assert wire.count(b"\n") == 1
    assert b"\r" not in wire
    free_text = (
        m.DebugEchoRequest,
        m.WifiConfig,
        m.LcdWrite,
        m.LcdWriteAt,
        m.VersionReply,
        m.ServiceNamesReply,
        m.ErrorReply,
        m.StartupLine,
        m.InfoLine,
        m.DebugLine,
    )
    if not isinstance(message, free_text):
        assert b" " not in wire


@settings(max_examples=EXAMPLES, deadline=None)
@given(
    roles,
    st.integers(16, 80),
    st.lists(
        st.binary(max_size=120) | st.sampled_from([b"\n", b"@", b"~", b"!", b",{"]), max_size=12
    ),
    st.booleans(),
)
def test_arbitrary_bytes_only_raise_remote_protocol_error(
    role: Role, limit: int, chunks: list[bytes], quiet: bool
) -> None:
    codec = AsipCodec(role, max_line_bytes=limit, max_buffer_bytes=limit * 2)
    got = feed(codec, chunks, line=limit, buffer=limit * 2)
    if quiet and role is Role.DEVICE:
        codec.parse_timeout()
        got += drain(codec)
    faults = [item for item in got if isinstance(item, RemoteProtocolError)]
    assert codec.stats.messages == len(got) - len(faults)
    assert sum(codec.stats.faults.values()) == len(faults)
    assert codec.stats.dropped_bytes <= sum(len(chunk) for chunk in chunks)


@settings(max_examples=EXAMPLES, deadline=None)
@given(
    st.data(),
    roles,
    st.integers(0, 255) | st.sampled_from(list(b",\n\r{}:-0 @~!\x80\xff")),
    st.sampled_from(["replace", "insert", "delete"]),
)
def test_mutated_line_only_raises_remote_protocol_error(
    data: st.DataObject, role: Role, byte: int, how: str
) -> None:
    line = sender(role).send(data.draw(receives(role)))
    index = data.draw(st.integers(0, len(line) - 1))
    if how == "replace":
        mutated = line[:index] + bytes([byte]) + line[index + 1 :]
    elif how == "insert":
        mutated = line[:index] + bytes([byte]) + line[index:]
    else:
        mutated = line[:index] + line[index + 1 :]
    sentinel = SENTINEL[role]
    codec = AsipCodec(role)
    got = feed(codec, [mutated + b"\n" + sender(role).send(sentinel)])
    if role is Role.DEVICE:
        codec.parse_timeout()
        got += drain(codec)
    else:
        # Lines are independent: whatever the mutation did, the next line decodes.
        assert got[-1] == sentinel
        assert codec.pending_bytes() == 0
    assert codec.stats.messages == sum(not isinstance(item, RemoteProtocolError) for item in got)


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.data(), cut_lists)
def test_device_chunking_of_noisy_streams_keeps_every_byte_accounted_for(
    data: st.DataObject, cuts: list[int]
) -> None:
    """Chunking may change what noise becomes: the firmware skips only the bytes it has
    received of a bad line (tests/conformance/test_asip.py), so a split inside one leaves
    the rest to be read as a request. Whatever the split, the reader ends in the same
    place once every wait has timed out, and only ever raises counted faults."""
    host = AsipCodec(Role.HOST)
    noise = st.binary(max_size=8) | st.lists(
        st.sampled_from(list(b"MIL,{}:-0 9\n\r")), max_size=8
    ).map(bytes)
    parts = data.draw(st.lists(st.builds(host.send, requests) | noise, max_size=8))
    stream = b"".join(parts)
    for pieces in ([stream], split(stream, cuts)):
        codec = AsipCodec(Role.DEVICE)
        got = feed(codec, pieces)
        while codec.waiting:
            codec.parse_timeout()
            got += drain(codec)
        faults = [item for item in got if isinstance(item, RemoteProtocolError)]
        assert codec.pending_bytes() < 4
        assert sum(codec.stats.faults.values()) == len(faults)
        assert codec.stats.messages == len(got) - len(faults)


@settings(max_examples=EXAMPLES, deadline=None)
@given(st.data(), cut_lists)
def test_host_chunking_of_noisy_streams_gives_the_same_result(
    data: st.DataObject, cuts: list[int]
) -> None:
    device = AsipCodec(Role.DEVICE)
    noise = st.binary(max_size=8) | st.lists(
        st.sampled_from(list(b"@~!,{}:I 9\n\r\xff")), max_size=8
    ).map(bytes)
    parts = data.draw(st.lists(st.builds(device.send, replies) | noise, max_size=8))
    stream = b"".join(parts)
    whole, chunked = AsipCodec(Role.HOST), AsipCodec(Role.HOST)
    expected = kinds(feed(whole, [stream]))
    assert kinds(feed(chunked, split(stream, cuts))) == expected
    assert chunked.pending_bytes() == whole.pending_bytes()
    assert chunked.stats.faults == whole.stats.faults
    assert chunked.stats.dropped_bytes == whole.stats.dropped_bytes
