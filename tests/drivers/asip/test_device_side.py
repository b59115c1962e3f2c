"""The board's side of ASIP: requests read with hostile numbers, replies refused out of range.

A request number is read as Arduino ``parseInt`` reads it, into a 32-bit ``long`` that wraps:
every digit is read and the request goes on with the wrapped number, as on the board.
Whatever arrives, ``next_message`` raises only ``RemoteProtocolError`` and the buffer stays
bounded.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import CodecStats, Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.asip.device_side import DEFAULT_SERVICES, RequestReader
from roboscript.errors import LocalProtocolError, RemoteProtocolError

EXAMPLES = 300
INT32_MAX = 2_147_483_647
HUGE = "9" * 400


def reader(max_buffer_bytes: int = 4096) -> RequestReader:
    return RequestReader(CodecStats(), DEFAULT_SERVICES, max_buffer_bytes)


def feed(requests: RequestReader, *chunks: bytes, quiet: bool = False) -> list[object]:
    out: list[object] = []
    for chunk in chunks:
        requests.receive_data(chunk)
        out += drain(requests)  # type: ignore[arg-type]
    if quiet:
        requests.parse_timeout()
        out += drain(requests)  # type: ignore[arg-type]
    return [item.kind if isinstance(item, RemoteProtocolError) else item for item in out]


# ------------------------------------------------------------------------------------------
# The bound of a request number: a long


def test_a_request_number_at_the_bounds_of_a_long_is_read_then_kept_in_a_16_bit_int() -> None:
    got = feed(reader(), f"P,I,{INT32_MAX}\nP,I,{-INT32_MAX - 1}\nP,I,65537\n".encode())
    # the strip is an int, 16 bits on the 328P: 0x7FFFFFFF is -1, -0x80000000 is 0
    assert got == [m.PixelsInfoRequest(-1), m.PixelsInfoRequest(0), m.PixelsInfoRequest(1)]


def test_a_request_number_is_kept_whole_in_a_32_bit_boards_int() -> None:
    # a Teensy 3.1's int is its long: nothing is cut
    teensy = RequestReader(CodecStats(), DEFAULT_SERVICES, 4096, int_bits=32)
    got = feed(teensy, b"P,I,65537\nM,A,65536\nB,A,-5\n")
    assert got == [
        m.PixelsInfoRequest(65537),
        m.EnableEncoderEvents(True),
        m.SetAutoEventInterval("B", 0xFFFF_FFFB),
    ]


def test_a_board_int_is_16_or_32_bits() -> None:
    with pytest.raises(ValueError, match="16 or 32 bits"):
        RequestReader(CodecStats(), DEFAULT_SERVICES, 4096, int_bits=8)


def test_a_request_number_past_a_long_wraps_as_on_the_board_and_the_request_goes_on() -> None:
    # parseInt's `value * 10 + digit` wraps its 32-bit long; the board answers with the
    # wrapped number (the firmware tier's "a number past a long" probes)
    got = feed(reader(), b"P,I,2147483648\nP,I,-2147483649\nP,I,4294967299\nI,M\n")
    assert got == [  # then cut to the strip's 16-bit int
        m.PixelsInfoRequest(0),
        m.PixelsInfoRequest(-1),
        m.PixelsInfoRequest(3),
        m.PortMapRequest(),
    ]


def test_a_400_digit_request_number_is_read_whole_and_its_request_goes_on() -> None:
    requests = reader()
    got = feed(requests, f"M,M,{HUGE},5\nI,M\n".encode())
    assert len(got) == 2 and isinstance(got[0], m.SetMotorsPower)
    assert got[0].power1_pct == 5  # ",5" is the request's second number, not a new request
    assert got[1] == m.PortMapRequest()
    assert requests.stats.faults == {}


def test_a_400_digit_number_still_arriving_waits_for_the_rest_of_its_request() -> None:
    requests = reader()
    assert feed(requests, f"T,P,{HUGE}".encode()) == []
    requests.parse_timeout()  # the frequency's wait ends; the duration's begins
    assert feed(requests, b"#,?\n") == []  # no digit: the duration's wait goes on over it
    assert feed(requests, b"", quiet=True) == [m.UnknownRequest("T", "P", (-1, 0))]
    assert requests.pending_bytes() == 0
    assert requests.stats.faults == {}


def test_a_digit_run_longer_than_the_buffer_is_dropped_as_overlong() -> None:
    requests = reader(max_buffer_bytes=64)
    got = feed(requests, b"S,W,", b"7" * 100, b"7" * 100, b"\nI,M\n")
    assert got[0] == "overlong"
    assert got[-1] == m.PortMapRequest()
    assert requests.pending_bytes() == 0
    assert set(requests.stats.faults) <= {"overlong", "out_of_range"}


def test_values_in_a_long_but_out_of_the_request_range_are_read_as_the_firmware_does() -> None:
    # asipIO keeps the pin in a byte (300 is pin 44); a mode it lacks is its INVALID_MODE
    got = feed(reader(), b"I,P,300,1\nI,P,3,9\nM,r,1,30,-5\n")
    assert got == [
        m.SetPinMode(44, m.PinMode.INPUT),
        m.UnknownRequest("I", "P", (3, 9)),
        m.SetMotorRpm(1, 30, 2**31 - 1),  # the int -5 as an unsigned long: 49 days
    ]


# ------------------------------------------------------------------------------------------
# Replies: the device refuses exactly what the host would refuse

int_values = st.integers(-(2**40), 2**40) | st.integers(-(10**400), 10**400)


def replies_with_any_numbers() -> st.SearchStrategy[object]:
    pairs = st.lists(st.tuples(int_values, int_values), max_size=3).map(tuple)
    values = st.lists(int_values, max_size=3).map(tuple)
    floats = st.floats(allow_nan=True, allow_infinity=True, width=32)
    return st.one_of(
        st.builds(m.EncoderEvent, pairs),
        st.builds(m.LegacyEncoderEvent, pairs),
        st.builds(m.AnalogEvent, pairs),
        st.builds(m.PortMapReply, pairs),
        st.builds(m.AnalogMapReply, pairs),
        st.builds(m.BumpEvent, values),
        st.builds(m.IrEvent, values),
        st.builds(m.DistanceEvent, values),
        st.builds(m.PinModesReply, values),
        st.builds(m.CapabilitiesReply, values),
        st.builds(m.AccelerometerEvent, int_values, int_values, int_values),
        st.builds(m.GyroEvent, int_values, int_values, int_values),
        st.builds(m.HeadingEvent, int_values, int_values, int_values, int_values),
        st.builds(m.PressureEvent, floats, floats, floats),
        st.builds(m.PixelsInfoReply, int_values, int_values),
        st.builds(m.DigitalPortEvent, int_values, int_values),
        st.builds(m.ErrorReply, st.just("X"), st.just("?"), int_values, st.just("TEXT")),
        st.builds(
            m.VersionReply, int_values, int_values, st.just("chip"), int_values, st.just("s")
        ),
    )


def _rounded(message: object) -> object:
    # the board prints pressure with two decimals
    if isinstance(message, m.PressureEvent):
        return m.PressureEvent(
            *(
                float(f"{value:.2f}")
                for value in (message.pressure_mbar, message.temperature_c, message.altitude_m)
            )
        )
    return message


@settings(max_examples=EXAMPLES, deadline=None)
@given(replies_with_any_numbers())
def test_a_reply_the_device_sends_is_one_the_host_reads_back(message: object) -> None:
    device = AsipCodec(Role.DEVICE)
    host = AsipCodec(Role.HOST, max_line_bytes=1 << 16)
    try:
        wire = device.send(message)
    except LocalProtocolError:
        return  # refused: nothing went out
    host.receive_data(wire)
    got = list(drain(host))
    assert got == [_rounded(message)]
    assert not host.stats.faults


# ------------------------------------------------------------------------------------------
# Fuzzing the request reader: random and mutated requests, huge numbers


def _requests() -> st.SearchStrategy[bytes]:
    host = AsipCodec(Role.HOST)
    sample = [
        m.SetMotorsPower(30, -30),
        m.SetMotorsRpm(30, 30, 1000),
        m.PlayTone(440, 250),
        m.ServoWrite(0, 90),
        m.LcdWrite(0, "hi"),
        m.PixelsSet(0, ((0, 128), (2, 16))),
        m.LcdBarGraph(((1, 50),)),
        m.SetAutoEventInterval("D", 25),
    ]
    return st.sampled_from([host.send(message) for message in sample])


@st.composite
def hostile_requests(draw: st.DrawFn) -> bytes:
    """A real request with its numbers swapped for any size, or with bytes changed."""
    wire = draw(_requests())
    how = draw(st.sampled_from(["numbers", "replace", "insert", "strip-newline"]))
    if how == "numbers":
        text = wire.decode()
        out, number = [], ""
        for char in text + "\0":
            if char.isdigit():
                number += char
                continue
            if number:
                out.append(str(draw(st.integers(-(10**300), 10**300) | st.just(int(number)))))
                number = ""
            out.append(char)
        return "".join(out[:-1]).encode()
    index = draw(st.integers(0, len(wire) - 1))
    byte = bytes([draw(st.integers(0, 255))])
    if how == "replace":
        return wire[:index] + byte + wire[index + 1 :]
    if how == "insert":
        return wire[:index] + byte + wire[index:]
    return wire.rstrip(b"\n")


@settings(max_examples=EXAMPLES, deadline=None)
@given(
    st.lists(hostile_requests() | st.binary(max_size=24), max_size=10),
    st.integers(16, 512),
    st.integers(1, 64),
)
def test_hostile_request_streams_only_raise_remote_protocol_errors(
    parts: list[bytes], limit: int, chunk: int
) -> None:
    codec = AsipCodec(Role.DEVICE, max_buffer_bytes=limit)
    stream = b"".join(parts)
    got: list[object] = []
    for start in range(0, len(stream), chunk):
        codec.receive_data(stream[start : start + chunk])
        got += drain(codec)
        assert codec.pending_bytes() <= limit
    while codec.waiting:  # each timed read waits for its own timeout
        codec.parse_timeout()
        got += drain(codec)
    assert codec.pending_bytes() < 4  # after the timeouts only a too-short start is left
    faults = [item for item in got if isinstance(item, RemoteProtocolError)]
    assert {fault.kind for fault in faults} <= {"overlong", "malformed", "out_of_range"}
    assert sum(codec.stats.faults.values()) == len(faults)
    assert codec.stats.messages == len(got) - len(faults)
    assert codec.stats.dropped_bytes <= len(stream)
