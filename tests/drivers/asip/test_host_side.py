"""The host's side of ASIP: the board's lines read, hostile numbers and error forms included.

``decode_line`` raises only ``ValueError`` (``IndexError`` for some short lines) and
``OutOfRangeError``; through the codec each becomes one counted fault, and the next line reads.
"""

from __future__ import annotations

import contextlib
import string

from hypothesis import given, settings
from hypothesis import strategies as st

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.asip.host_side import HOST_ENCODERS, decode_line
from roboscript.drivers.asip.value_ranges import OutOfRangeError
from roboscript.errors import RemoteProtocolError

EXAMPLES = 300
SENTINEL = m.BumpEvent((1, 0))
SENTINEL_WIRE = b"@B,e,2,{1,0}\n"
HUGE = "9" * 400


def decode(wire: bytes, **options: int) -> tuple[list[object], AsipCodec]:
    host = AsipCodec(Role.HOST, **options)
    host.receive_data(wire + SENTINEL_WIRE)
    return list(drain(host)), host


# ------------------------------------------------------------------------------------------
# The overflow case: a well-formed event with a 400-digit count


def test_a_400_digit_encoder_count_is_one_counted_fault_and_the_next_line_reads() -> None:
    wire = f"@M,e,2,{{1:{HUGE},2:3}}\n".encode("ascii")
    got, host = decode(wire)
    assert len(got) == 2
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "out_of_range"
    assert "outside -2147483648..2147483647" in str(got[0])
    assert got[0].data == wire[:64]  # the fault sample, for the log
    assert got[1] == SENTINEL
    assert host.stats.faults == {"out_of_range": 1}
    assert host.stats.dropped_bytes == len(wire)
    assert host.stats.messages == 1


def test_a_400_digit_negative_count_and_a_400_digit_delta_are_faults_too() -> None:
    wire = f"@M,e,2,{{-{HUGE}:0,1:1}}\n@E,e,1,{{1:-{HUGE}}}\n".encode("ascii")
    got, host = decode(wire)
    assert [getattr(item, "kind", item) for item in got] == [
        "out_of_range",
        "out_of_range",
        SENTINEL,
    ]
    assert host.stats.faults == {"out_of_range": 2}


def test_a_400_digit_element_count_disagrees_with_its_body() -> None:
    got, host = decode(f"@M,e,{HUGE},{{1:1,2:2}}\n".encode("ascii"))
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "malformed"
    assert got[1] == SENTINEL
    assert host.stats.faults == {"malformed": 1}


def test_a_number_longer_than_int_reads_is_malformed_not_an_exception() -> None:
    # int() refuses over 4300 digits; a codec told to keep such long lines still only faults
    got, _ = decode(f"@D,e,1,{{{'7' * 5000}}}\n".encode("ascii"), max_line_bytes=10_000)
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "malformed"
    assert got[1] == SENTINEL


# ------------------------------------------------------------------------------------------
# Error lines: every form the firmware writes is a device error, not garbage

ERROR_FORMS = [
    (b"~X,?,1{INVALID_SERVICE}", m.ErrorReply("X", "?", 1, "INVALID_SERVICE")),
    # A leftover ",45" is read as a request for service ","
    (b"~,,?,1{INVALID_SERVICE}", m.ErrorReply(",", "?", 1, "INVALID_SERVICE")),
    # The system service echoes any tag byte, a comma included
    (b"~#,,,2{UNKNOWN_REQUEST}", m.ErrorReply("#", ",", 2, "UNKNOWN_REQUEST")),
    # "M, M" read by the firmware: the tag is the space
    (b"~M, ,2{UNKNOWN_REQUEST}", m.ErrorReply("M", " ", 2, "UNKNOWN_REQUEST")),
    (b"~S,W,7{INVALID_DEVICE_NUMBER}", m.ErrorReply("S", "W", 7, "INVALID_DEVICE_NUMBER")),
    (b"~I,a,6{WRONG_MODE}", m.ErrorReply("I", "a", 6, "WRONG_MODE")),
    (b"~V,?,1{INVALID_SERVICE}", m.ErrorReply("V", "?", 1, "INVALID_SERVICE")),
    (b"~A,M,9{I2C NOT ENABLED}", m.ErrorReply("A", "M", 9, "I2C NOT ENABLED")),
    (b"~X,?,1{}", m.ErrorReply("X", "?", 1, "INVALID_SERVICE")),  # no text: the errno's
    # Service and tag bytes that are not text: the board echoes what it received
    (b"~\xff,?,1{INVALID_SERVICE}", m.ErrorReply("\xff", "?", 1, "INVALID_SERVICE")),
    (b"~#,\x01,2{UNKNOWN_REQUEST}", m.ErrorReply("#", "\x01", 2, "UNKNOWN_REQUEST")),
    (b"~#,\r,2{UNKNOWN_REQUEST}\r", m.ErrorReply("#", "\r", 2, "UNKNOWN_REQUEST")),
    # The seed's forms
    (b"~I,d,6,WRONG_MODE", m.ErrorReply("I", "d", 6, "WRONG_MODE")),
    (b"~I, d, 6, WRONG_MODE", m.ErrorReply("I", "d", 6, "WRONG_MODE")),
]


def test_every_firmware_error_form_is_a_device_error() -> None:
    for wire, reply in ERROR_FORMS:
        got, host = decode(wire + b"\n")
        assert got == [reply, SENTINEL], wire
        assert not host.stats.faults, wire


def test_the_simulated_board_answers_a_leftover_comma_with_the_empty_service_error() -> None:
    board = AsipCodec(Role.DEVICE)
    board.receive_data(b",45\nI,M\n")
    requests = list(drain(board))
    assert requests == [m.InvalidServiceRequest(","), m.PortMapRequest()]
    reply = m.ErrorReply(",", "?", m.ErrorCode.INVALID_SERVICE)
    wire = board.send(reply)
    assert wire == b"~,,?,1{INVALID_SERVICE}\n"
    host = AsipCodec(Role.HOST)
    host.receive_data(wire)
    assert list(drain(host)) == [reply]


def test_an_error_line_with_non_text_elsewhere_is_still_garbage() -> None:
    for wire in (b"~X,?,1{\xff}\n", b"~\xff\xff,1{X}\n", b"@\xff,e,1,{1}\n", b"~X,?,1{\x00}\n"):
        got, host = decode(wire)
        assert isinstance(got[0], RemoteProtocolError), wire
        assert got[0].kind == "garbage"
        assert got[1] == SENTINEL
        assert host.stats.faults == {"garbage": 1}
        assert host.stats.dropped_bytes == len(wire)


def test_an_error_number_past_a_byte_is_out_of_range() -> None:
    got, host = decode(f"~X,?,{HUGE}{{INVALID_SERVICE}}\n".encode("ascii"))
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "out_of_range"
    assert host.stats.faults == {"out_of_range": 1}


def test_host_encoders_cover_exactly_the_requests() -> None:
    replies = {m.ErrorReply, m.VersionReply, m.EncoderEvent, m.DebugLine}
    assert not replies & set(HOST_ENCODERS)
    assert m.SetMotorsPower in HOST_ENCODERS


# ------------------------------------------------------------------------------------------
# Fuzzing decode_line on its own: only its documented exceptions

digits = st.text(string.digits, min_size=1, max_size=600)
numbers = st.one_of(
    st.integers(),
    st.integers(-(10**40), 10**40),
    st.builds(lambda sign, text: sign + text, st.sampled_from(["", "-", "+", " "]), digits),
    st.floats(allow_nan=True, allow_infinity=True),
).map(str)
HEADS = [
    *("@M,e,", "@E,e,", "@B,e,", "@R,e,", "@D,e,", "@D,M,", "@I,a,", "@I,d,", "@I,M,", "@I,m,"),
    *("@I,p,", "@I,c,", "@A,e,", "@G,e,", "@H,e,", "@P,e,", "@P,I,", "@#,?,", "@#,N,", "@#,S,"),
    *("@X,q,", "@M, e, ", "~X,?,", "~,,?,", "~I, d, ", "!", "text "),
]
heads = st.sampled_from(HEADS)
separators = st.sampled_from([",", ":", ", ", "{", "}", ",{", "},", ""])


@st.composite
def hostile_lines(draw: st.DrawFn) -> str:
    """An ASIP-looking line: a real head, then numbers of any size and separators."""
    parts = [draw(heads)]
    for _ in range(draw(st.integers(0, 8))):
        parts.append(draw(numbers))
        parts.append(draw(separators))
    return "".join(parts)


@settings(max_examples=EXAMPLES, deadline=None)
@given(hostile_lines() | st.text(string.printable.strip() + " \t", min_size=1, max_size=200))
def test_decode_line_raises_only_its_documented_errors(text: str) -> None:
    with contextlib.suppress(ValueError, IndexError):  # OutOfRangeError is a ValueError
        decode_line(text)


@settings(max_examples=EXAMPLES, deadline=None)
@given(hostile_lines())
def test_a_hostile_line_through_the_codec_is_a_message_or_one_counted_fault(text: str) -> None:
    wire = text.encode("ascii") + b"\n"
    got, host = decode(wire, max_line_bytes=8192)
    assert got[-1] == SENTINEL  # lines are independent
    if isinstance(got[0], RemoteProtocolError):
        assert got[0].kind in {"malformed", "out_of_range"}
        assert host.stats.dropped_bytes == len(wire)
        assert sum(host.stats.faults.values()) == 1
    else:
        assert host.stats.messages == 2
    try:
        decode_line(text)
    except OutOfRangeError:
        assert getattr(got[0], "kind", None) == "out_of_range"
    except (ValueError, IndexError):
        assert getattr(got[0], "kind", None) == "malformed"
