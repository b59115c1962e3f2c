"""How the device role parses requests: the V1.1 firmware's semantics (facts section 1.2).

The firmware waits for four buffered bytes, skips bytes up to ``' '`` between requests, needs a
``,`` after a known service id, reads numbers with Arduino ``parseInt`` (skip anything that is
not a digit or ``-``; wait up to 1 s for more, each wait on its own), so requests need no
newline and a short request swallows the next request's first number. Unknown service ids
get ``~<id>,?,1{INVALID_SERVICE}`` and the *received* rest of their line is dropped; of the
services, only pixels drops the received rest of its line after a request.
"""

from __future__ import annotations

import pytest

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec, DeviceAsipCodec
from roboscript.errors import RemoteProtocolError

Decoded = list[m.AsipMessage | RemoteProtocolError]

PY_ASIP_STREAM = (
    b"I,M\n I,A,0\n M,A,1M,A,1R,A,25R,A,25R,A,25B,A,25B,A,25D,A,25M,m,1,50M,m,0,-50"
    b"M,R,30,30,1000\n M,c,20,2000\n L,W,0,hi\n M,E,"
)
"""What py-asip's TCPMirtoRobot wrote to a fake board (facts 1.8): many requests lack a newline."""

PY_ASIP_REQUESTS = [
    m.PortMapRequest(),
    m.SetAutoEventInterval("I", 0),
    m.EnableEncoderEvents(True),
    m.EnableEncoderEvents(True),
    m.SetAutoEventInterval("R", 25),
    m.SetAutoEventInterval("R", 25),
    m.SetAutoEventInterval("R", 25),
    m.SetAutoEventInterval("B", 25),
    m.SetAutoEventInterval("B", 25),
    m.SetAutoEventInterval("D", 25),
    m.SetMotorPower(1, 50),  # py-asip swaps the motor index: this was its motor 0
    m.SetMotorPower(0, -50),
    m.SetMotorsRpm(30, 30, 1000),
    m.SetRobotSpeed(20, 2000),
    m.LcdWrite(0, "hi"),
]


def device(services: str | None = None) -> AsipCodec:
    return AsipCodec(Role.DEVICE) if services is None else AsipCodec(Role.DEVICE, services=services)


def feed(codec: AsipCodec, *chunks: bytes) -> Decoded:
    """Feed each chunk and drain after it; return everything that came out."""
    out: Decoded = []
    for chunk in chunks:
        codec.receive_data(chunk)
        out += drain(codec)
    return out


def timeout(codec: AsipCodec) -> Decoded:
    """The line went quiet for the firmware's 1 s timeout of the read it waits in."""
    codec.parse_timeout()
    return list(drain(codec))


def timeouts(codec: AsipCodec) -> Decoded:
    """The line stays quiet: every wait of the request runs out in turn."""
    out: Decoded = []
    while codec.waiting:
        out += timeout(codec)
    return out


def messages(items: Decoded) -> list[object]:
    return [item for item in items if not isinstance(item, RemoteProtocolError)]


# ------------------------------------------------------------------------------------------
# The py-asip byte stream


def test_py_asip_stream_decodes_in_order_and_waits_for_the_last_number() -> None:
    codec = device()
    assert feed(codec, PY_ASIP_STREAM) == PY_ASIP_REQUESTS
    assert codec.pending_bytes() == len(b"M,E,")  # M,E reads one number: wait for it
    assert timeout(codec) == [m.ResetEncoders()]
    assert codec.pending_bytes() == 0
    assert codec.stats.messages == len(PY_ASIP_REQUESTS) + 1
    assert not codec.stats.faults


def test_py_asip_stream_byte_by_byte_gives_the_same_requests() -> None:
    codec = device()
    got = feed(codec, *(PY_ASIP_STREAM[i : i + 1] for i in range(len(PY_ASIP_STREAM))))
    assert got == PY_ASIP_REQUESTS
    assert timeout(codec) == [m.ResetEncoders()]


def test_py_asip_trailing_reset_swallows_the_next_requests_first_number() -> None:
    # Without the timeout, the number M,E waits for is the next request's first one.
    codec = device()
    got = feed(codec, PY_ASIP_STREAM, b"M,m,1,50\n")
    # What is left, ",50\n", starts with ',' which is no service: the firmware answers
    # ~,,?,1{INVALID_SERVICE} and drops the line. The motor request is lost.
    assert got == [*PY_ASIP_REQUESTS, m.ResetEncoders(), m.InvalidServiceRequest(",")]
    assert codec.pending_bytes() == 0


# ------------------------------------------------------------------------------------------
# The motor argument quirk (facts 1.2)


def test_bare_stop_swallows_the_enable_flag_of_the_next_request() -> None:
    codec = device()
    assert feed(codec, b"M,S\nM,A,1\n") == [m.StopMotors()]  # the 1 is lost
    assert codec.pending_bytes() == 0
    assert timeout(codec) == []


def test_bare_reset_swallows_the_enable_flag_too() -> None:
    assert feed(device(), b"M,E\nM,A,1\n") == [m.ResetEncoders()]


def test_codec_bytes_for_stop_and_reset_keep_the_next_request() -> None:
    host = AsipCodec(Role.HOST)
    sent = [m.StopMotors(), m.EnableEncoderEvents(True), m.ResetEncoders(), m.StopMotor(1)]
    sent.append(m.SetMotorsPower(10, 10))
    wire = b"".join(host.send(message) for message in sent)
    assert feed(device(), wire) == sent


def test_stop_one_motor_reads_two_numbers() -> None:
    assert feed(device(), b"M,s,1,0\n") == [m.StopMotor(1)]
    codec = device()
    # "M,s,1" takes the 5 of the next request as its unused second number.
    assert feed(codec, b"M,s,1\nM,M,5,5\nI,M\n") == [
        m.StopMotor(1),
        m.InvalidServiceRequest(","),  # ",5\n" is left: ',' is no service
        m.PortMapRequest(),
    ]
    assert feed(device(), b"M,s,1", b"") == []
    codec = device()
    feed(codec, b"M,s,1")
    assert timeout(codec) == []  # the 1 is read; the unused number waits a second more
    assert codec.waiting
    assert timeout(codec) == [m.StopMotor(1)]
    assert not codec.waiting


def test_stop_all_takes_its_dummy_number() -> None:
    assert feed(device(), b"M,S,0\nM,A,1\n") == [m.StopMotors(), m.EnableEncoderEvents(True)]


def test_unknown_motor_tag_still_reads_two_numbers() -> None:
    assert feed(device(), b"M,Z,3,4\nI,M\n") == [
        m.UnknownRequest("M", "Z", (3, 4)),
        m.PortMapRequest(),
    ]


@pytest.mark.parametrize(
    ("wire", "message"),
    [
        pytest.param(b"M,m,0,150\n", m.SetMotorPower(0, 100), id="power-clamped-high"),
        pytest.param(b"M,M,-200,50\n", m.SetMotorsPower(-100, 50), id="powers-clamped-low"),
        pytest.param(b"M,A,7\n", m.EnableEncoderEvents(True), id="any-nonzero-enables"),
        # the int -5 becomes setMotorRPM's unsigned long: 49 days, past what a message holds
        pytest.param(b"M,r,0,30,-5\n", m.SetMotorRpm(0, 30, 2**31 - 1), id="negative-duration"),
        pytest.param(b"S,W,1,999\n", m.ServoWrite(1, 180), id="servo-clamped"),
        # setAutoreport keeps it in an unsigned int: 70000 is 4464
        pytest.param(b"I,A,70000\n", m.SetAutoEventInterval("I", 4464), id="interval-16-bits"),
    ],
)
def test_out_of_range_numbers_are_clamped_as_on_the_board(wire: bytes, message: object) -> None:
    assert feed(device(), wire) == [message]


# ------------------------------------------------------------------------------------------
# parseInt: numbers may grow until a non-digit or the timeout


def test_a_number_at_the_end_of_the_buffer_waits_for_more_digits() -> None:
    codec = device()
    assert feed(codec, b"I,A,2") == []
    assert feed(codec, b"0") == []
    assert feed(codec, b"0\n") == [m.SetAutoEventInterval("I", 200)]


def test_the_timeout_completes_a_request_with_the_digits_it_has() -> None:
    codec = device()
    assert feed(codec, b"I,A,2") == []
    assert timeout(codec) == [m.SetAutoEventInterval("I", 2)]


def test_the_timeout_gives_zero_for_missing_numbers() -> None:
    codec = device()
    assert feed(codec, b"M,m,1") == []
    assert timeout(codec) == []  # each parseInt waits its own second
    assert timeout(codec) == [m.SetMotorPower(1, 0)]
    codec = device()
    assert feed(codec, b"I,A,") == []
    assert timeout(codec) == [m.SetAutoEventInterval("I", 0)]


def test_the_timeout_applies_once() -> None:
    codec = device()
    feed(codec, b"I,A,2")
    assert timeout(codec) == [m.SetAutoEventInterval("I", 2)]
    assert feed(codec, b"I,A,3") == []  # new bytes wait again
    assert feed(codec, b"3\n") == [m.SetAutoEventInterval("I", 33)]


def test_numbers_need_no_separator_but_a_non_digit() -> None:
    assert feed(device(), b"I,A,5T,P,440,250\n") == [
        m.SetAutoEventInterval("I", 5),
        m.PlayTone(440, 250),
    ]


# ------------------------------------------------------------------------------------------
# The four-byte minimum and the bytes skipped between requests


@pytest.mark.parametrize("short", [b"I,M", b"#,?", b"L,C", b"!a\n", b"\r\nI,M", b" \t#,N"])
def test_fewer_than_four_request_bytes_wait_even_after_the_timeout(short: bytes) -> None:
    codec = device()
    assert feed(codec, short) == []
    assert timeout(codec) == []
    assert codec.pending_bytes() == len(short.lstrip())
    assert not codec.stats.faults


def test_the_fourth_byte_releases_the_request() -> None:
    codec = device()
    assert feed(codec, b"I,M") == []
    assert feed(codec, b"\n") == [m.PortMapRequest()]
    codec = device()
    assert feed(codec, b"#,?") == []
    assert feed(codec, b"#") == [m.VersionRequest()]  # the next request's byte counts too
    assert codec.pending_bytes() == 1


def test_control_bytes_and_spaces_between_requests_are_skipped() -> None:
    codec = device()
    got = feed(codec, b"\r\n\x00\x01 \t#,?\r\n\r\n  I,p\x1f\x7fI,c\n")
    assert got[:2] == [m.VersionRequest(), m.PinModesRequest()]
    # 0x7f is above ' ': the firmware takes it as a service id.
    assert got[2:] == [m.InvalidServiceRequest("\x7f")]
    assert codec.stats.messages == 3


# ------------------------------------------------------------------------------------------
# Unknown services and tags


def test_unknown_service_decodes_as_invalid_and_drops_the_rest_of_its_line() -> None:
    codec = device()
    assert feed(codec, b"X,?\nI,M\n") == [m.InvalidServiceRequest("X"), m.PortMapRequest()]
    assert feed(codec, b"X,1,2,M,A,1,L,C\nI,p\n") == [
        m.InvalidServiceRequest("X"),
        m.PinModesRequest(),
    ]
    assert not codec.stats.faults


def test_unknown_service_skips_only_what_has_arrived() -> None:
    codec = device()
    assert feed(codec, b"X,?,M,A") == [m.InvalidServiceRequest("X")]
    assert not codec.waiting
    assert feed(codec, b",1\nI,M\n") == [m.InvalidServiceRequest(","), m.PortMapRequest()]


def test_unknown_service_skips_what_has_arrived_by_the_time_it_has_answered() -> None:
    # The firmware writes the error first: bytes that arrive meanwhile are skipped too.
    codec = device()
    codec.receive_data(b"X,ab")
    assert codec.next_message() == m.InvalidServiceRequest("X")
    codec.receive_data(b"cd\nI,M\n")  # arrived while the board wrote its answer
    assert codec.next_message() == m.PortMapRequest()


def test_pixels_skip_what_has_arrived_by_the_time_the_request_is_done() -> None:
    codec = device()
    codec.receive_data(b"P,I,0,ab")
    assert codec.next_message() == m.PixelsInfoRequest(0)
    codec.receive_data(b"cd\nI,M\n")
    assert codec.next_message() == m.PortMapRequest()


def test_unknown_service_needs_no_comma() -> None:
    # The firmware looks the id up before it reads the separator.
    assert feed(device(), b"XY,1\nI,M\n") == [m.InvalidServiceRequest("X"), m.PortMapRequest()]


def test_services_the_board_does_not_run_are_invalid() -> None:
    codec = device(services="IM")
    assert feed(codec, b"L,W,0,hi\nT,P,440,250\nM,A,1\n") == [
        m.InvalidServiceRequest("L"),
        m.InvalidServiceRequest("T"),
        m.EnableEncoderEvents(True),
    ]


def test_a_non_ascii_service_byte_is_echoed_in_the_error() -> None:
    codec = device()
    assert feed(codec, b"\xff,x\nI,M\n") == [m.InvalidServiceRequest("\xff"), m.PortMapRequest()]
    # The firmware writes the id byte back as it came.
    error = m.ErrorReply("\xff", "?", int(m.ErrorCode.INVALID_SERVICE))
    assert codec.send(error) == b"~\xff,?,1{INVALID_SERVICE}\n"


@pytest.mark.parametrize(
    ("wire", "message"),
    [
        pytest.param(b"#,Z\n", m.UnknownRequest("#", "Z"), id="system"),
        pytest.param(b"I,Z\n", m.UnknownRequest("I", "Z"), id="io"),
        pytest.param(b"I,P,3,9\n", m.UnknownRequest("I", "P", (3, 9)), id="io-bad-mode"),
        pytest.param(b"I,d,3,2\n", m.DigitalWrite(3, 1), id="io-digital-2-is-high"),
        pytest.param(b"E,Z\n", m.UnknownRequest("E", "Z"), id="legacy-encoders"),
        pytest.param(b"B,M\n", m.UnknownRequest("B", "M"), id="bump-no-measure"),
        pytest.param(b"R,Z\n", m.UnknownRequest("R", "Z"), id="ir"),
        pytest.param(b"D,Z\n", m.UnknownRequest("D", "Z"), id="distance"),
        pytest.param(b"A,Z\n", m.UnknownRequest("A", "Z"), id="accel"),
        pytest.param(b"G,Z\n", m.UnknownRequest("G", "Z"), id="gyro"),
        pytest.param(b"H,Z\n", m.UnknownRequest("H", "Z"), id="heading"),
        pytest.param(b"S,Z\n", m.UnknownRequest("S", "Z"), id="servo"),
        pytest.param(b"S,W,-1,90\n", m.UnknownRequest("S", "W", (-1, 90)), id="servo-negative"),
        pytest.param(b"T,Z\n", m.UnknownRequest("T", "Z"), id="tone"),
        pytest.param(b"T,P,0,250\n", m.UnknownRequest("T", "P", (0, 250)), id="tone-zero"),
        pytest.param(b"L,Z\n", m.UnknownRequest("L", "Z"), id="lcd"),
        pytest.param(b"P,Z,1,2,3\n", m.UnknownRequest("P", "Z"), id="pixels"),
    ],
)
def test_unknown_tags(wire: bytes, message: object) -> None:
    codec = device()
    assert feed(codec, wire + b"I,M\n") == [message, m.PortMapRequest()]
    assert codec.pending_bytes() == 0
    assert not codec.stats.faults


def test_only_pixels_drops_the_rest_of_the_line_after_an_unknown_tag() -> None:
    # IO leaves ",3,4\n": ',' is then read as a service id, as on the board.
    assert feed(device(), b"I,Z,3,4\nI,M\n") == [
        m.UnknownRequest("I", "Z"),
        m.InvalidServiceRequest(","),
        m.PortMapRequest(),
    ]
    assert feed(device(), b"P,Z,3,4,M,A,1\nI,M\n") == [
        m.UnknownRequest("P", "Z"),
        m.PortMapRequest(),
    ]


def test_tag_spaces_are_skipped_but_tags_are_case_sensitive() -> None:
    assert feed(device(), b"I,   m\nI,m\n") == [m.AnalogMapRequest(), m.AnalogMapRequest()]
    assert feed(device(), b"#,n\n") == [m.UnknownRequest("#", "n")]


# ------------------------------------------------------------------------------------------
# Bad separators


def test_known_service_without_comma_is_an_invalid_service() -> None:
    # The service loop finds I, reads ';', finds no other I: ~I,?,1 and the line goes.
    codec = device()
    assert feed(codec, b"I;M\nI,p\n") == [m.InvalidServiceRequest("I"), m.PinModesRequest()]
    assert not codec.stats.faults
    # The byte read as the separator may be the newline: the next line goes too.
    assert feed(device(), b"M\nM,A,1\nI,p\n") == [
        m.InvalidServiceRequest("M"),
        m.PinModesRequest(),
    ]


def test_system_header_without_comma_is_a_fault() -> None:
    codec = device()
    got = feed(codec, b"#?\n\nI,M\n")
    assert isinstance(got[0], RemoteProtocolError)
    assert got[1:] == [m.PortMapRequest()]


# ------------------------------------------------------------------------------------------
# LCD text


@pytest.mark.parametrize(
    ("wire", "message"),
    [
        pytest.param(b"L,W,0,a,b,c\n", m.LcdWrite(0, "a,b,c"), id="commas"),
        pytest.param(b"L,W,1,,leading\n", m.LcdWrite(1, ",leading"), id="leading-comma"),
        pytest.param(b"L,W,2,42 is 6*7\n", m.LcdWrite(2, "42 is 6*7"), id="digits"),
        pytest.param(b"L,W,3,\n", m.LcdWrite(3, ""), id="empty"),
        pytest.param(b"L,W,4,crlf\r\n", m.LcdWrite(4, "crlf"), id="crlf"),
        pytest.param(b"L,w,1,2,x,y\n", m.LcdWriteAt(1, 2, "x,y"), id="at-commas"),
    ],
)
def test_lcd_text_runs_to_the_end_of_the_line(wire: bytes, message: object) -> None:
    codec = device()
    assert feed(codec, wire + b"L,C\n") == [message, m.LcdClear()]
    assert codec.pending_bytes() == 0


@pytest.mark.parametrize(
    ("int_bits", "next_service", "after_column_20"),
    # readBytesUntil(..., 21): the Teensy 3 core reads at most 20 bytes, the AVR core 21
    [(32, "U", "-"), (16, "V", "1")],
    ids=["teensy-core", "avr-core"],
)
def test_lcd_text_is_cut_at_twenty_characters(
    int_bits: int, next_service: str, after_column_20: str
) -> None:
    # the row shows 20; what the core has not read is a new request
    got = feed(AsipCodec(Role.DEVICE, int_bits=int_bits), b"L,W,0,abcdefghijklmnopqrstUVWX\n")
    assert got == [
        m.LcdWrite(0, "abcdefghijklmnopqrst"),
        m.InvalidServiceRequest(next_service),
    ]
    got = feed(AsipCodec(Role.DEVICE, int_bits=int_bits), b"L,w,0,20,-1\nI,M\n")
    assert got == [
        m.LcdWriteAt(0, 20, ""),
        m.InvalidServiceRequest(after_column_20),
        m.PortMapRequest(),
    ]


def test_lcd_line_past_the_fifth_leaves_its_text_to_be_read_as_requests() -> None:
    assert feed(device(), b"L,W,7,x\nI,M\n") == [
        m.UnknownRequest("L", "W", (7,)),
        m.InvalidServiceRequest(","),
        m.PortMapRequest(),
    ]


def test_lcd_text_waits_for_its_newline_or_the_timeout() -> None:
    codec = device()
    assert feed(codec, b"L,W,0,hel") == []
    assert feed(codec, b"lo\n") == [m.LcdWrite(0, "hello")]
    codec = device()
    feed(codec, b"L,W,0,hel")
    assert timeout(codec) == [m.LcdWrite(0, "hel")]


def test_lcd_bar_graph_leaves_its_closing_brace_like_the_board() -> None:
    # The firmware reads the numbers and stops: "}\n" is next read as service '}', which
    # the board answers with ~},?,1{INVALID_SERVICE}.
    codec = device()
    assert feed(codec, b"L,G,2,{1:50,3:75}\n") == [m.LcdBarGraph(((1, 50), (3, 75)))]
    assert codec.pending_bytes() == 2
    assert feed(codec, b"L,C\n") == [m.InvalidServiceRequest("}"), m.LcdClear()]


def test_lcd_bar_graph_reads_every_pair_it_announces() -> None:
    bars = ((0, 10), (1, 20), (2, 30), (3, 40), (4, 50), (0, 60))
    wire = AsipCodec(Role.HOST).send(m.LcdBarGraph(bars))
    assert feed(device(), wire + b"L,C\n") == [
        m.LcdBarGraph(bars),
        m.InvalidServiceRequest("}"),
        m.LcdClear(),
    ]


def test_lcd_bar_graph_clamps_values_and_refuses_bad_lines() -> None:
    assert feed(device(), b"L,G,1,{0:150}\n") == [m.LcdBarGraph(((0, 100),))]
    assert feed(device(), b"L,G,1,{9:50}\n") == [m.UnknownRequest("L", "G")]


# ------------------------------------------------------------------------------------------
# Pixels: braces and colons are just non-digits; the rest of the line is dropped


@pytest.mark.parametrize(
    ("wire", "message"),
    [
        pytest.param(b"P,P,0,2,{0:128,2:16}\n", m.PixelsSet(0, ((0, 128), (2, 16))), id="set"),
        pytest.param(
            b"P,p,0,2,{0:255:0:0,1:0:255:0}\n",
            m.PixelsSetRgb(0, ((0, (255, 0, 0)), (1, (0, 255, 0)))),
            id="set-rgb",
        ),
        pytest.param(
            b"P,S,0,3,4,{255,65280,16711680}\n",
            m.PixelsSequence(0, 4, (255, 65280, 16711680)),
            id="sequence",
        ),
        pytest.param(
            b"P,s,1,2,0,{1:2:3,4:5:6}\n",
            m.PixelsSequenceRgb(1, 0, ((1, 2, 3), (4, 5, 6))),
            id="sequence-rgb",
        ),
        pytest.param(b"P,B,0,300\n", m.PixelsBrightness(0, 44), id="brightness-byte"),
        pytest.param(b"P,I,0\n", m.PixelsInfoRequest(0), id="info"),
        pytest.param(b"P,C,0\n", m.PixelsClear(0), id="clear"),
        # The library keeps colours in 24 bits, pixel numbers in 16 and channels in 8.
        pytest.param(
            b"P,P,0,1,{0:99999999}\n", m.PixelsSet(0, ((0, 0xF5E0FF),)), id="colour-24-bits"
        ),
        pytest.param(
            b"P,P,0,1,{70000:5}\n", m.PixelsSet(0, ((4464, 5),)), id="pixel-index-16-bits"
        ),
        pytest.param(
            b"P,p,0,1,{0:300:-4:7}\n",
            m.PixelsSetRgb(0, ((0, (44, 252, 7)),)),
            id="rgb-channels-8-bits",
        ),
        # py-asip's NeoPixelService uses the pixel number as the strip index.
        pytest.param(
            b"P,p,3,1,{0:255,0,0}\n", m.PixelsSetRgb(3, ((0, (255, 0, 0)),)), id="py-asip"
        ),
        # java-asip's "clear" carries a pixel and a colour that V1.1 never reads.
        pytest.param(b"P,C,0,5,255,0,0\n", m.PixelsClear(0), id="java-asip-clear"),
    ],
)
def test_pixels_requests(wire: bytes, message: object) -> None:
    codec = device()
    assert feed(codec, wire + b"I,M\n") == [message, m.PortMapRequest()]
    assert codec.pending_bytes() == 0
    assert not codec.stats.faults


def test_pixels_drop_the_rest_of_their_line() -> None:
    assert feed(device(), b"P,P,0,1,{0:128},M,A,1,{junk}\nM,A,0\n") == [
        m.PixelsSet(0, ((0, 128),)),
        m.EnableEncoderEvents(False),
    ]


def test_pixels_need_their_brace_already_received() -> None:
    # ",{" is read with two plain reads: a brace still on its way is a missing one (on a
    # UART at 57600 baud it always is; over USB the line comes in one packet).
    codec = device()
    assert feed(codec, b"P,P,0,1,", b"{0:128}\nI,M\n") == [
        m.PixelsSet(0, ()),
        m.InvalidServiceRequest("{"),
        m.PortMapRequest(),
    ]


def test_pixels_skip_only_what_has_arrived_of_their_line() -> None:
    codec = device()
    assert feed(codec, b"P,C,0") == []  # parseInt waits for the byte after the 0
    assert feed(codec, b",junk") == [m.PixelsClear(0)]
    assert feed(codec, b"\n") == []


# ------------------------------------------------------------------------------------------
# Debug echo and WiFi config


def test_debug_echo_keeps_the_whole_line() -> None:
    assert feed(device(), b"!hello, board\n!,x\n#,?\n") == [
        m.DebugEchoRequest("hello, board"),
        m.DebugEchoRequest(",x"),
        m.VersionRequest(),
    ]


def test_wifi_config() -> None:
    assert feed(device(), b"$$,mirto-net,s3cret!\n") == [m.WifiConfig("mirto-net", "s3cret!")]
    assert feed(device(), b"$$,x,y\n") == [m.UnknownRequest("$", "$")]  # under 2 characters


# ------------------------------------------------------------------------------------------
# Values no message can hold are faults, consumed and counted


@pytest.mark.parametrize(
    "wire",
    [
        pytest.param(b"L,W,0,caf\xe9\n", id="lcd-non-ascii"),
        pytest.param(b"L,W,0,a\rb\n", id="lcd-inner-cr"),
        pytest.param(b"L,w,0,1,\xff\n", id="lcd-at-non-ascii"),
        pytest.param(b"!bad\rtext\n", id="echo-inner-cr"),
    ],
)
def test_unrepresentable_request_is_a_fault_and_the_next_request_decodes(wire: bytes) -> None:
    codec = device()
    got = feed(codec, wire + b"I,M\n")
    assert len(got) == 2
    assert isinstance(got[0], RemoteProtocolError)
    assert got[1] == m.PortMapRequest()
    assert sum(codec.stats.faults.values()) == 1
    assert codec.stats.messages == 1
    assert codec.pending_bytes() == 0


def test_buffer_overflow_is_one_counted_fault_then_parsing_resumes() -> None:
    codec = AsipCodec(Role.DEVICE, max_buffer_bytes=40)
    codec.receive_data(b"x" * 50 + b"\nI,M\n")  # the oldest 15 bytes go
    assert codec.pending_bytes() == 40
    got = list(drain(codec))
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == "overlong"
    assert got[1:] == [m.InvalidServiceRequest("x"), m.PortMapRequest()]
    assert codec.stats.faults == {"overlong": 1}
    assert codec.stats.dropped_bytes == 15


# ------------------------------------------------------------------------------------------
# Splitting requests at every byte boundary

SPLIT_STREAM = b"".join(
    [
        PY_ASIP_STREAM + b"0\n",  # completes M,E
        b"#,?\n#, N\nI,P,13,3\nI,d,13,1\nI,a,9,128\n",
        b"M, M, 30, -30\nM,a,180,90\nM,s,1,0\nM,S,0\n",
        b"L,W,0,a,b,c\nL,w,1,2,x\nL,G,2,{1:50,3:75}\nL,C\n",
        b"!echo\n$$,net,pass\nT,P,440,250\nS,W,0,90\n",
        b"I,M\n",
    ]
)
"""Requests in every form the firmware reads the same however they are split: none leaves
bytes that a skip of the received line would treat differently."""


SPLIT_REQUESTS = [
    *PY_ASIP_REQUESTS,
    m.ResetEncoders(),
    m.VersionRequest(),
    m.ServiceNamesRequest(),
    m.SetPinMode(13, m.PinMode.OUTPUT),
    m.DigitalWrite(13, 1),
    m.AnalogWrite(9, 128),
    m.SetMotorsPower(30, -30),
    m.RotateRobot(180, 90),
    m.StopMotor(1),
    m.StopMotors(),
    m.LcdWrite(0, "a,b,c"),
    m.LcdWriteAt(1, 2, "x"),
    m.LcdBarGraph(((1, 50), (3, 75))),
    m.InvalidServiceRequest("}"),
    m.LcdClear(),
    m.DebugEchoRequest("echo"),
    m.WifiConfig("net", "pass"),
    m.PlayTone(440, 250),
    m.ServoWrite(0, 90),
    m.PortMapRequest(),
]


def test_split_stream_decodes_to_the_expected_requests() -> None:
    codec = device()
    assert messages(feed(codec, SPLIT_STREAM)) == SPLIT_REQUESTS
    assert not codec.stats.faults
    assert codec.pending_bytes() == 0


def test_every_split_point_gives_the_same_requests() -> None:
    for cut in range(len(SPLIT_STREAM) + 1):
        codec = device()
        got = feed(codec, SPLIT_STREAM[:cut], SPLIT_STREAM[cut:])
        assert messages(got) == SPLIT_REQUESTS, cut
        assert not codec.stats.faults, cut
        assert codec.pending_bytes() == 0, cut


def test_byte_by_byte_gives_the_same_requests() -> None:
    codec = device()
    got = feed(codec, *(SPLIT_STREAM[i : i + 1] for i in range(len(SPLIT_STREAM))))
    assert messages(got) == SPLIT_REQUESTS
    assert not codec.stats.faults


def test_an_avr_boards_find_walks_back_to_the_match_a_byte_continues() -> None:
    # the AVR core's findMulti: ",," then "{" still holds ",{"; the Teensy 3 core restarts
    # the match without looking at the "{" again, and reads on to its timeout
    got = feed(AsipCodec(Role.DEVICE, int_bits=16), b"L,G,1,,{0:50}\n#,?\n")
    assert got == [m.LcdBarGraph(((0, 50),)), m.InvalidServiceRequest("}"), m.VersionRequest()]
    teensy = AsipCodec(Role.DEVICE, int_bits=32)
    assert feed(teensy, b"L,G,1,,{0:50}\n") == []
    assert teensy.waiting


def test_skipping_the_rest_of_a_request_line_is_the_device_codecs_alone() -> None:
    # the board skips what it has of a line after some answers; the host never does, so its
    # codec has no stand-in for it that could be called by mistake and do nothing
    assert type(AsipCodec(Role.DEVICE)) is DeviceAsipCodec
    device, host = AsipCodec(Role.DEVICE), AsipCodec(Role.HOST)
    for name in ("skip_pending", "skip_received", "end_skip"):
        assert hasattr(device, name) and not hasattr(host, name)
