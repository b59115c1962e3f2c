"""Byte-exact ASIP examples: every request and reply example of the seed and the facts.

Sources: ``shared/seeds/asip-v1.1-reference.txt`` (the seed; its examples have spaces after
commas and a few PDF artefacts, written here as the evidently intended bytes) and
``shared/reference/protocols.md`` section 1 (the V1.1 firmware's exact formats, no spaces).

Each table pairs a message with its exact bytes (pybricksdev style) and is checked in every
direction that applies: the host sends requests and decodes replies, the device decodes
requests and sends replies.
"""

from __future__ import annotations

import typing

import pytest

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.errors import LocalProtocolError, RemoteProtocolError

Decoded = list[m.AsipMessage | RemoteProtocolError]


def decode(role: Role, wire: bytes, *, timeout: bool = False) -> tuple[Decoded, AsipCodec]:
    """Feed ``wire`` to a fresh codec of ``role``; drain it (after a parse timeout if asked)."""
    codec = AsipCodec(role)
    codec.receive_data(wire)
    out: Decoded = list(drain(codec))
    if timeout:
        codec.parse_timeout()
        out += drain(codec)
    return out, codec


# ------------------------------------------------------------------------------------------
# Requests: host send gives exactly these bytes; the device decodes them back.

UNO_PORT_MAP = (
    b"{4:1,4:2,4:4,4:8,4:10,4:20,4:40,4:80,2:1,2:2,2:4,2:8,2:10,2:20,3:1,3:2,3:4,3:8,3:10,3:20}"
)

REQUESTS = [
    # System (seed: "#,?\n", "#, S\n", "#, N\n"; facts: "#,R" restart).
    pytest.param(m.VersionRequest(), b"#,?\n", id="seed-version"),
    pytest.param(m.PinServicesRequest(), b"#,S\n", id="seed-pin-services"),
    pytest.param(m.ServiceNamesRequest(), b"#,N\n", id="seed-service-names"),
    pytest.param(m.RestartRequest(), b"#,R\n", id="facts-restart"),
    pytest.param(m.DebugEchoRequest("hello board"), b"!hello board\n", id="facts-debug-echo"),
    pytest.param(m.WifiConfig("mirto-net", "s3cret!"), b"$$,mirto-net,s3cret!\n", id="v12-config"),
    # IO service (seed examples).
    pytest.param(m.SetPinMode(13, m.PinMode.OUTPUT), b"I,P,13,3\n", id="seed-pin-mode"),
    pytest.param(m.SetPinMode(2, m.PinMode.INPUT_PULLUP), b"I,P,2,2\n", id="pin-mode-pullup"),
    pytest.param(m.DigitalWrite(13, 1), b"I,d,13,1\n", id="seed-digital-write"),
    pytest.param(m.AnalogWrite(9, 128), b"I,a,9,128\n", id="seed-analog-write"),
    pytest.param(m.PortMapRequest(), b"I,M\n", id="seed-port-map"),
    pytest.param(m.AnalogMapRequest(), b"I,m\n", id="seed-analog-map"),
    pytest.param(m.PinModesRequest(), b"I,p\n", id="seed-pin-modes"),
    pytest.param(m.CapabilitiesRequest(), b"I,c\n", id="seed-capabilities"),
    pytest.param(m.SetAutoEventInterval("I", 20), b"I,A,20\n", id="seed-io-auto-20"),
    pytest.param(m.SetAutoEventInterval("I", 0), b"I,A,0\n", id="seed-io-auto-off"),
    pytest.param(m.SetAutoEventInterval("I", 100), b"I,A,100\n", id="py-asip-serial-auto"),
    pytest.param(m.SetAutoEventInterval("I", 65535), b"I,A,65535\n", id="auto-max"),
    # Sensor services.
    pytest.param(m.MeasureRequest("D"), b"D,M\n", id="seed-distance-measure"),
    pytest.param(m.SetAutoEventInterval("D", 25), b"D,A,25\n", id="py-asip-distance-auto"),
    pytest.param(m.SetAutoEventInterval("B", 25), b"B,A,25\n", id="py-asip-bump-auto"),
    pytest.param(m.SetAutoEventInterval("R", 25), b"R,A,25\n", id="py-asip-ir-auto"),
    pytest.param(m.SetAutoEventInterval("E", 100), b"E,A,100\n", id="legacy-encoder-auto"),
    pytest.param(m.MeasureRequest("A"), b"A,M\n", id="seed-accel-measure"),
    pytest.param(m.SetAutoEventInterval("A", 50), b"A,A,50\n", id="seed-accel-auto"),
    pytest.param(m.MeasureRequest("G"), b"G,M\n", id="seed-gyro-measure"),
    pytest.param(m.SetAutoEventInterval("G", 50), b"G,A,50\n", id="seed-gyro-auto"),
    pytest.param(m.MeasureRequest("H"), b"H,M\n", id="seed-heading-measure"),
    pytest.param(m.SetAutoEventInterval("H", 50), b"H,A,50\n", id="seed-heading-auto"),
    pytest.param(m.MeasureRequest("P"), b"P,M\n", id="seed-pressure-measure"),
    pytest.param(m.SetAutoEventInterval("P", 1000), b"P,A,1000\n", id="seed-pressure-auto"),
    # Servo and tone (seed: "S, W, 0, 90\n", "T,P,440,250\n").
    pytest.param(m.ServoWrite(0, 90), b"S,W,0,90\n", id="seed-servo"),
    pytest.param(m.PlayTone(440, 250), b"T,P,440,250\n", id="seed-tone"),
    # Motors (seed examples, with the firmware's rate-first order for "a").
    pytest.param(m.SetMotorPower(0, 50), b"M,m,0,50\n", id="seed-motor-0-50"),
    pytest.param(m.SetMotorPower(1, -50), b"M,m,1,-50\n", id="seed-motor-1-minus-50"),
    pytest.param(m.SetMotorPower(0, 0), b"M,m,0,0\n", id="seed-motor-0-stop"),
    pytest.param(m.SetMotorsPower(30, -30), b"M,M,30,-30\n", id="seed-motors-30-minus-30"),
    pytest.param(m.SetMotorsPower(0, 0), b"M,M,0,0\n", id="seed-motors-stop"),
    pytest.param(m.SetMotorRpm(1, 30, 2000), b"M,r,1,30,2000\n", id="seed-motor-rpm"),
    pytest.param(m.SetMotorsRpm(30, 30, 1000), b"M,R,30,30,1000\n", id="seed-motors-rpm"),
    pytest.param(m.SetRobotSpeed(-20, 2000), b"M,c,-20,2000\n", id="seed-robot-speed"),
    pytest.param(m.SetRobotSpeed(20, 2000), b"M,c,20,2000\n", id="py-asip-robot-speed"),
    pytest.param(m.RotateRobot(180, 90), b"M,a,180,90\n", id="seed-rotate"),
    pytest.param(m.RotateRobot(90, -45), b"M,a,90,-45\n", id="rotate-left"),
    pytest.param(m.EnableEncoderEvents(True), b"M,A,1\n", id="seed-encoder-events-on"),
    pytest.param(m.EnableEncoderEvents(False), b"M,A,0\n", id="encoder-events-off"),
    # The firmware reads one number more than these use: the codec sends a dummy 0.
    pytest.param(m.ResetEncoders(), b"M,E,0\n", id="seed-reset-encoders-dummy"),
    pytest.param(m.StopMotors(), b"M,S,0\n", id="stop-motors-dummy"),
    pytest.param(m.StopMotor(1), b"M,s,1,0\n", id="stop-motor-dummy"),
    # LCD (seed: "L, W, 0, Hello World\n", "L, w, 0, 6, again\n", "L, G, 2, {1:50, 3:75}\n").
    pytest.param(m.LcdWrite(0, "Hello World"), b"L,W,0,Hello World\n", id="seed-lcd-write"),
    pytest.param(m.LcdWrite(0, "hi"), b"L,W,0,hi\n", id="py-asip-lcd-write"),
    pytest.param(m.LcdWriteAt(0, 6, "again"), b"L,w,0,6,again\n", id="seed-lcd-write-at"),
    pytest.param(m.LcdBarGraph(((1, 50), (3, 75))), b"L,G,2,{1:50,3:75}\n", id="seed-lcd-graph"),
    pytest.param(m.LcdClear(), b"L,C\n", id="seed-lcd-clear"),
    # Pixels, V1.1 forms with a strip index (seed: "P,P,0,2,{0:128,2:16}\n").
    pytest.param(
        m.PixelsSet(0, ((0, 128), (2, 16))), b"P,P,0,2,{0:128,2:16}\n", id="seed-pixels-set"
    ),
    pytest.param(m.PixelsSet(0, ((0, 65280),)), b"P,P,0,1,{0:65280}\n", id="seed-pixel-green"),
    pytest.param(
        m.PixelsSetRgb(0, ((0, (255, 0, 0)),)), b"P,p,0,1,{0:255:0:0}\n", id="seed-pixel-red-rgb"
    ),
    pytest.param(
        m.PixelsSequence(0, 4, (255, 65280, 16711680)),
        b"P,S,0,3,4,{255,65280,16711680}\n",
        id="seed-pixels-sequence",
    ),
    pytest.param(
        m.PixelsSequenceRgb(1, 0, ((1, 2, 3), (4, 5, 6))),
        b"P,s,1,2,0,{1:2:3,4:5:6}\n",
        id="facts-pixels-sequence-rgb",
    ),
    pytest.param(m.PixelsBrightness(0, 64), b"P,B,0,64\n", id="seed-pixels-brightness"),
    pytest.param(m.PixelsInfoRequest(0), b"P,I,0\n", id="seed-pixels-info"),
    pytest.param(m.PixelsClear(2), b"P,C,2\n", id="facts-pixels-clear"),
]


@pytest.mark.parametrize(("message", "wire"), REQUESTS)
def test_host_sends_exact_request_bytes(message: object, wire: bytes) -> None:
    assert AsipCodec(Role.HOST).send(message) == wire


def leftover(message: object) -> list[object]:
    """What the firmware makes of the bytes a request leaves unread.

    The bar graph handler stops after its last number, so ``}`` is next read as a service id,
    which the board answers with ``~},?,1{INVALID_SERVICE}`` (the ``\n`` is then dropped).
    """
    return [m.InvalidServiceRequest("}")] if isinstance(message, m.LcdBarGraph) else []


@pytest.mark.parametrize(("message", "wire"), REQUESTS)
def test_device_decodes_exact_request_bytes(message: object, wire: bytes) -> None:
    got, codec = decode(Role.DEVICE, wire + b"I,M\n")
    assert got == [message, *leftover(message), m.PortMapRequest()]
    assert codec.pending_bytes() == 0
    assert codec.stats.messages == len(got)
    assert not codec.stats.faults


def test_host_request_bytes_have_no_spaces_and_one_newline() -> None:
    host = AsipCodec(Role.HOST)
    for param in REQUESTS:
        message, _ = param.values
        if isinstance(message, m.LcdWrite | m.LcdWriteAt | m.DebugEchoRequest):
            continue  # free text may hold spaces
        sent = host.send(message)
        assert b" " not in sent
        assert sent.count(b"\n") == 1
        assert sent.endswith(b"\n")
        assert b"\r" not in sent


# ------------------------------------------------------------------------------------------
# The seed's spaced request forms, decoded by the device role.
#
# The seed writes "M, M, 30, -30" with spaces and often without a newline. The codec skips the
# spaces before the tag; parseInt skips them before each number. Without a newline the last
# number could still grow, so the request completes only after the 1 s parse timeout.

SEED_SPACED_REQUESTS = [
    pytest.param(b"#, S\n", m.PinServicesRequest(), id="pin-services"),
    pytest.param(b"#, N\n", m.ServiceNamesRequest(), id="service-names"),
    pytest.param(b"I, M\n", m.PortMapRequest(), id="port-map"),
    pytest.param(b"I, m\n", m.AnalogMapRequest(), id="analog-map"),
    pytest.param(b"I, c\n", m.CapabilitiesRequest(), id="capabilities"),
    pytest.param(b"S, W, 0, 90\n", m.ServoWrite(0, 90), id="servo"),
    pytest.param(b"T, P, 440, 250\n", m.PlayTone(440, 250), id="tone"),
    pytest.param(b"M, m, 0, 50", m.SetMotorPower(0, 50), id="motor-0-50"),
    pytest.param(b"M, m, 1, -50", m.SetMotorPower(1, -50), id="motor-1-minus-50"),
    pytest.param(b"M, m, 0, 0", m.SetMotorPower(0, 0), id="motor-0-stop"),
    pytest.param(b"M, M, 30, -30", m.SetMotorsPower(30, -30), id="motors-30-minus-30"),
    pytest.param(b"M, M, 0, 0", m.SetMotorsPower(0, 0), id="motors-stop"),  # seed: "O, O"
    pytest.param(b"M, r, 1, 30, 2000", m.SetMotorRpm(1, 30, 2000), id="motor-rpm"),
    pytest.param(b"M, R, 30, 30, 1000", m.SetMotorsRpm(30, 30, 1000), id="motors-rpm"),
    pytest.param(b"M, c, -20, 2000", m.SetRobotSpeed(-20, 2000), id="robot-speed"),
    pytest.param(b"M, a, 180, 90", m.RotateRobot(180, 90), id="rotate-rate-first"),
    pytest.param(b"M, A, 1\n", m.EnableEncoderEvents(True), id="encoder-events"),
    # The firmware skips to the comma and keeps what follows, the seed's space included.
    pytest.param(b"L, W, 0, Hello World\n", m.LcdWrite(0, " Hello World"), id="lcd-write"),
    pytest.param(b"L, w, 0, 6, again\n", m.LcdWriteAt(0, 6, " again"), id="lcd-write-at"),
]


@pytest.mark.parametrize(("wire", "message"), SEED_SPACED_REQUESTS)
def test_device_decodes_seed_spaced_request(wire: bytes, message: object) -> None:
    got, codec = decode(Role.DEVICE, wire)
    if wire.endswith(b"\n"):
        assert got == [message]
    else:
        assert got == []  # the last number may go on: wait for more bytes or the timeout
        assert codec.pending_bytes() == len(wire)
        codec.parse_timeout()
        assert list(drain(codec)) == [message]
    assert codec.pending_bytes() == (2 if leftover(message) else 0)
    assert not codec.stats.faults


@pytest.mark.parametrize(("wire", "message"), SEED_SPACED_REQUESTS)
def test_device_decodes_seed_spaced_request_with_newline_at_once(
    wire: bytes, message: object
) -> None:
    line = wire if wire.endswith(b"\n") else wire + b"\n"
    got, codec = decode(Role.DEVICE, line + b"#,?\n")
    assert got == [message, *leftover(message), m.VersionRequest()]
    assert codec.pending_bytes() == 0


def test_seed_reset_encoders_without_argument_waits_for_the_parse_timeout() -> None:
    # "M, E\n": the firmware reads one number it does not use, so it waits up to 1 s.
    got, codec = decode(Role.DEVICE, b"M, E\n")
    assert got == []
    assert codec.pending_bytes() == 5
    codec.parse_timeout()
    assert list(drain(codec)) == [m.ResetEncoders()]
    assert codec.pending_bytes() == 0


@pytest.mark.parametrize(
    ("wire", "message"),
    [
        # The seed's second pixels section is the ASIP 0.4 form (no strip index). V1.1 reads
        # the count as the strip and stops at the first number in braces: nothing is set.
        pytest.param(b"P, P, 1, {0:65280}\n", m.PixelsSet(1, ()), id="set"),
        pytest.param(b"P,p,1,{0:255:0:0}\n", m.PixelsSetRgb(1, ()), id="set-rgb"),
    ],
)
def test_device_reads_seed_asip_04_pixel_forms_the_v11_way(wire: bytes, message: object) -> None:
    got, codec = decode(Role.DEVICE, wire + b"I,M\n")
    assert got == [message, m.PortMapRequest()]  # the rest of the pixel line was dropped
    assert codec.pending_bytes() == 0


# ------------------------------------------------------------------------------------------
# Replies: the device sends exactly these bytes (the firmware's formats); the host decodes them.

REPLIES = [
    # System.
    pytest.param(
        m.VersionReply(1, 1, "ATmega328P", 20, "TestIO"),
        b"@#,?,1,1,ATmega328P,20,TestIO\n",
        id="facts-version",
    ),
    pytest.param(
        m.VersionReply(0, 2, "ATmega328P", 20, "TestIO"),
        b"@#,?,0,2,ATmega328P,20,TestIO\n",
        id="seed-version",
    ),
    pytest.param(
        m.VersionReply(1, 1, "Teensy3.1", 38, "mirtle2017"),
        b"@#,?,1,1,Teensy3.1,38,mirtle2017\n",
        id="facts-version-teensy",
    ),
    pytest.param(
        m.ServiceNamesReply((("I", "ASIP core IO"), ("S", "Servos"), ("D", "Distance"))),
        b"@#,N,3,{I:ASIP core IO,S:Servos,D:Distance}\n",
        id="seed-service-names",
    ),
    pytest.param(
        m.ServiceNamesReply(
            (
                ("I", "ASIP core IO"),
                ("M", "Motors"),
                ("B", "Bump Sensors"),
                ("R", "IR Sensors"),
                ("D", "Distance"),
                ("L", "LCD"),
            )
        ),
        b"@#,N,6,{I:ASIP core IO,M:Motors,B:Bump Sensors,R:IR Sensors,D:Distance,L:LCD}\n",
        id="facts-service-names-mirto",
    ),
    pytest.param(
        # Seed: pins 0 and 1 reserved, 18 the servo's, 19 the distance sensor's.
        m.PinServicesReply(tuple("@@" + "I" * 16 + "SD")),
        b"@#,S,20,{@,@,I,I,I,I,I,I,I,I,I,I,I,I,I,I,I,I,S,D}\n",
        id="seed-pin-services",
    ),
    # IO service.
    pytest.param(
        m.PortMapReply(
            tuple((4, 1 << bit) for bit in range(8))
            + tuple((2, 1 << bit) for bit in range(6))
            + tuple((3, 1 << bit) for bit in range(6))
        ),
        b"@I,M,20," + UNO_PORT_MAP + b"\n",
        id="seed-port-map-uno",
    ),
    pytest.param(
        m.PortMapReply(((4, 0x80), (0, 0), (11, 0xAB))),
        b"@I,M,3,{4:80,0:0,11:AB}\n",  # port decimal, mask upper-case hex, 0:0 not digital
        id="facts-port-map-hex-and-non-digital",
    ),
    pytest.param(
        m.AnalogMapReply(((14, 0), (15, 1), (16, 2), (17, 3), (18, 4), (19, 5))),
        b"@I,m,6,{14:0,15:1,16:2,17:3,18:4,19:5}\n",
        id="seed-analog-map",
    ),
    pytest.param(
        # Seed: pins 0 and 1 reserved, 4 and 5 used by a service, the rest free.
        m.PinModesReply((6, 6, 0, 0, 7, 7, *([0] * 14))),
        b"@I,p,20,{6,6,0,0,7,7,0,0,0,0,0,0,0,0,0,0,0,0,0,0}\n",
        id="seed-pin-modes",
    ),
    pytest.param(
        m.CapabilitiesReply((1, 1, 1, 5, 1, 5, 5, 1, 1, 5, 5, 5, 1, 1, 3, 3, 3, 3, 3, 3)),
        b"@I,c,20,{1,1,1,5,1,5,5,1,1,5,5,5,1,1,3,3,3,3,3,3}\n",
        id="seed-capabilities",
    ),
    pytest.param(m.DigitalPortEvent(4, 0x10), b"@I,d,4,10\n", id="seed-digital-pin-4"),
    pytest.param(m.DigitalPortEvent(4, 0xF), b"@I,d,4,F\n", id="seed-digital-pins-4-7"),
    pytest.param(m.DigitalPortEvent(2, 0x11), b"@I,d,2,11\n", id="seed-digital-pins-8-11"),
    pytest.param(m.DigitalPortEvent(3, 0), b"@I,d,3,0\n", id="digital-all-low"),
    pytest.param(
        m.AnalogEvent(((0, 512), (1, 0), (5, 1023))),
        b"@I,a,3,{0:512,1:0,5:1023}\n",
        id="facts-analog-autoevent",
    ),
    # Robot services.
    pytest.param(
        m.EncoderEvent(((10, 100), (12, 120))),
        b"@M,e,2,{10:100,12:120}\n",
        id="facts-encoders",
    ),
    pytest.param(
        m.EncoderEvent(((-3, -1629), (4, 1636))),
        b"@M,e,2,{-3:-1629,4:1636}\n",
        id="encoders-backwards",
    ),
    pytest.param(
        m.LegacyEncoderEvent(((3000, 11), (3100, 12))),
        b"@E,e,2,{3000:11,3100:12}\n",
        id="facts-legacy-encoders",
    ),
    pytest.param(m.BumpEvent((1, 0)), b"@B,e,2,{1,0}\n", id="facts-bump"),
    pytest.param(m.IrEvent((100, 200, 300)), b"@R,e,3,{100,200,300}\n", id="facts-ir"),
    pytest.param(m.DistanceEvent((25,)), b"@D,e,1,{25}\n", id="facts-distance"),
    pytest.param(m.DistanceEvent((0,)), b"@D,e,1,{0}\n", id="facts-distance-no-echo"),
    pytest.param(m.DistanceEvent((-1,)), b"@D,e,1,{-1}\n", id="facts-distance-v12-absent"),
    # IMU services.
    pytest.param(
        m.AccelerometerEvent(-120, 45, 16384), b"@A,e,3,{-120,45,16384}\n", id="facts-accel"
    ),
    pytest.param(m.GyroEvent(1, -2, 32767), b"@G,e,3,{1,-2,32767}\n", id="facts-gyro"),
    pytest.param(
        m.HeadingEvent(120, -40, 300, 275), b"@H,e,4,{120,-40,300,275}\n", id="facts-heading"
    ),
    pytest.param(
        m.PressureEvent(1013.25, 21.5, 110.75),
        b"@P,e,3,{1013.25,21.50,110.75}\n",
        id="facts-pressure-two-decimals",
    ),
    pytest.param(
        m.PressureEvent(998.0, -3.25, -12.5),
        b"@P,e,3,{998.00,-3.25,-12.50}\n",
        id="pressure-negative",
    ),
    pytest.param(m.PixelsInfoReply(0, 16), b"@P,I,0,16\n", id="facts-pixel-info"),
    pytest.param(m.PixelsInfoReply(2, 60), b"@P,I,2,60\n", id="pixel-info-strip-2"),
    # Errors: number then braces, no comma.
    pytest.param(m.ErrorReply("X", "?", 1), b"~X,?,1{INVALID_SERVICE}\n", id="facts-error-x"),
    pytest.param(m.ErrorReply("#", "Z", 2), b"~#,Z,2{UNKNOWN_REQUEST}\n", id="system-unknown"),
    pytest.param(m.ErrorReply("I", "d", 6), b"~I,d,6{WRONG_MODE}\n", id="facts-io-wrong-mode"),
    pytest.param(m.ErrorReply("A", "M", 9), b"~A,M,9{I2C NOT ENABLED}\n", id="facts-errno-9"),
    # Info lines.
    pytest.param(
        m.StartupLine("mirtle2017", "ATmega328P", ("I", "M", "B", "R", "D", "L")),
        b"!mirtle2017 running on ATmega328P with Services: I M B R D L \n",
        id="facts-startup-trailing-space",
    ),
    pytest.param(
        m.StartupLine("TestIO", "Teensy3.1", ("I",)),
        b"!TestIO running on Teensy3.1 with Services: I \n",
        id="startup-one-service",
    ),
    pytest.param(m.InfoLine("Resetting services"), b"!Resetting services\n", id="facts-info"),
    # Unprefixed sketch output (the firmware ends it with CRLF; the codec writes LF).
    pytest.param(m.DebugLine("Motors is service M"), b"Motors is service M\n", id="debug-line"),
    pytest.param(m.GenericEvent("X", "e", ("1", "2")), b"@X,e,1,2\n", id="generic-event"),
]


@pytest.mark.parametrize(("message", "wire"), REPLIES)
def test_device_sends_exact_reply_bytes(message: object, wire: bytes) -> None:
    assert AsipCodec(Role.DEVICE).send(message) == wire


@pytest.mark.parametrize(("message", "wire"), REPLIES)
def test_host_decodes_exact_reply_bytes(message: object, wire: bytes) -> None:
    got, codec = decode(Role.HOST, wire)
    assert got == [message]
    assert codec.pending_bytes() == 0
    assert codec.stats.messages == 1
    assert not codec.stats.faults


@pytest.mark.parametrize(("message", "wire"), REPLIES)
def test_host_decodes_reply_with_crlf(message: object, wire: bytes) -> None:
    got, _ = decode(Role.HOST, wire[:-1] + b"\r\n")
    assert got == [message]


def test_firmware_reply_formats_have_no_spaces() -> None:
    device = AsipCodec(Role.DEVICE)
    for param in REPLIES:
        message, _ = param.values
        if isinstance(message, m.ServiceNamesReply | m.StartupLine | m.InfoLine | m.DebugLine):
            continue  # names and free text hold spaces
        if isinstance(message, m.ErrorReply) and message.errno == 9:
            continue  # "I2C NOT ENABLED"
        assert b" " not in device.send(message)


@pytest.mark.parametrize("code", list(m.ErrorCode))
def test_every_error_number_has_the_firmware_text(code: m.ErrorCode) -> None:
    text = "I2C NOT ENABLED" if code is m.ErrorCode.I2C_NOT_ENABLED else code.name
    wire = f"~S,W,{int(code)}{{{text}}}\n".encode("ascii")
    reply = m.ErrorReply("S", "W", int(code))
    assert reply.text == text
    assert AsipCodec(Role.DEVICE).send(reply) == wire
    got, _ = decode(Role.HOST, wire)
    assert got == [reply]


# ------------------------------------------------------------------------------------------
# Host-only decoding: the seed's spaced replies and the forms the firmware does not send.

HOST_ONLY_REPLIES = [
    pytest.param(b"@I, d, 4, 10\n", m.DigitalPortEvent(4, 0x10), id="seed-digital-4-10"),
    pytest.param(b"@I, d, 4, F\n", m.DigitalPortEvent(4, 0x0F), id="seed-digital-4-F"),
    pytest.param(b"@I, d, 2, 11\n", m.DigitalPortEvent(2, 0x11), id="seed-digital-2-11"),
    pytest.param(
        b"@M, e, 2, {10:100,11:120}\n",
        m.EncoderEvent(((10, 100), (11, 120))),
        id="seed-encoders",
    ),
    pytest.param(
        b"@I, M, 20, " + UNO_PORT_MAP + b"\n",
        m.PortMapReply(
            tuple((4, 1 << bit) for bit in range(8))
            + tuple((2, 1 << bit) for bit in range(6))
            + tuple((3, 1 << bit) for bit in range(6))
        ),
        id="seed-port-map",
    ),
    pytest.param(
        b"@I,M,3{4:1,4:2,0:0}\n",  # no comma before the brace: clients accept it
        m.PortMapReply(((4, 1), (4, 2), (0, 0))),
        id="facts-port-map-no-comma",
    ),
    pytest.param(
        b"@I, m, 6, {14:0, 15:1, 16:2, 17:3, 18:4, 19:5}\n",
        m.AnalogMapReply(((14, 0), (15, 1), (16, 2), (17, 3), (18, 4), (19, 5))),
        id="seed-analog-map",
    ),
    pytest.param(
        b"@I,A,2,{0:512,3:17}\n",  # the seed's tag for the IO autoevent
        m.AnalogEvent(((0, 512), (3, 17))),
        id="seed-io-autoevent-tag",
    ),
    pytest.param(b"@D,M,25\n", m.DistanceEvent((25,)), id="seed-distance"),
    pytest.param(b"@D, M, 25\n", m.DistanceEvent((25,)), id="seed-distance-spaced"),
    pytest.param(b"@P,I,16\n", m.PixelsInfoReply(0, 16), id="seed-asip-04-pixel-info"),
    pytest.param(
        b"~I,d,6,WRONG_MODE\n", m.ErrorReply("I", "d", 6, "WRONG_MODE"), id="seed-error-form"
    ),
    pytest.param(
        b"~I, d, 6, WRONG_MODE\n",
        m.ErrorReply("I", "d", 6, "WRONG_MODE"),
        id="seed-error-form-spaced",
    ),
    pytest.param(
        b"Motors is service M\r\n", m.DebugLine("Motors is service M"), id="facts-sketch-crlf"
    ),
    pytest.param(
        b"processing request P\r\n", m.DebugLine("processing request P"), id="facts-v12-pixels"
    ),
    pytest.param(
        b"!mirtle2017 running on ATmega328P with Services: I M B R D L \r\n",
        m.StartupLine("mirtle2017", "ATmega328P", ("I", "M", "B", "R", "D", "L")),
        id="startup-crlf",
    ),
]


@pytest.mark.parametrize(("wire", "message"), HOST_ONLY_REPLIES)
def test_host_decodes_seed_and_legacy_reply_forms(wire: bytes, message: object) -> None:
    got, codec = decode(Role.HOST, wire)
    assert got == [message]
    assert codec.pending_bytes() == 0
    assert not codec.stats.faults


def test_host_decodes_the_mirtle_startup_burst_in_order() -> None:
    # What mirtle2017's setup() prints: startup line, pin modes, port map, CRLF debug lines.
    burst = (
        b"!mirtle2017 running on ATmega328P with Services: I M B R \n"
        b"@I,p,4,{6,6,7,0}\n"
        b"@I,M,4,{4:1,4:2,4:4,0:0}\n"
        b"Motors is service M\r\n"
        b"Bump Sensors is service B\r\n"
        b"\r\n"
        b"@I,a,1,{0:12}\n"
    )
    got, codec = decode(Role.HOST, burst)
    assert got == [
        m.StartupLine("mirtle2017", "ATmega328P", ("I", "M", "B", "R")),
        m.PinModesReply((6, 6, 7, 0)),
        m.PortMapReply(((4, 1), (4, 2), (4, 4), (0, 0))),
        m.DebugLine("Motors is service M"),
        m.DebugLine("Bump Sensors is service B"),
        m.AnalogEvent(((0, 12),)),
    ]
    assert codec.stats.messages == 6
    assert codec.pending_bytes() == 0


def test_info_line_that_is_not_a_startup_line() -> None:
    got, _ = decode(Role.HOST, b"!running on empty\n")
    assert got == [m.InfoLine("running on empty")]


@pytest.mark.parametrize(
    ("wire", "kind"),
    [
        pytest.param(b"@M,e,2,{10:100}\n", "malformed", id="count-mismatch"),
        pytest.param(b"@I,d,4\n", "malformed", id="digital-missing-mask"),
        pytest.param(b"@A,e,3,{1,2}\n", "malformed", id="accel-two-axes"),
        pytest.param(b"~X,?\n", "malformed", id="error-without-number"),
        pytest.param(b"@I,d,4,\xff\n", "garbage", id="not-ascii"),
        pytest.param(b"@I,d,4,1\x00\n", "garbage", id="control-byte"),
    ],
)
def test_host_bad_line_is_a_counted_fault_and_the_next_line_decodes(wire: bytes, kind: str) -> None:
    got, codec = decode(Role.HOST, wire + b"@B,e,2,{1,0}\n")
    assert len(got) == 2
    assert isinstance(got[0], RemoteProtocolError)
    assert got[0].kind == kind
    assert got[1] == m.BumpEvent((1, 0))
    assert codec.stats.faults == {kind: 1}
    assert codec.stats.dropped_bytes == len(wire)


def test_tables_hold_every_message_type() -> None:
    requests = {type(param.values[0]) for param in REQUESTS}
    replies = {type(param.values[0]) for param in REPLIES}
    # the device never sends these
    decoded_only = {
        m.InvalidServiceRequest,
        m.RefusedRequest,
        m.IgnoredRequest,
        m.UnknownRequest,
    }
    assert requests | replies | decoded_only == set(typing.get_args(m.AsipMessage))


# ------------------------------------------------------------------------------------------
# Roles: each side only sends its own messages.


@pytest.mark.parametrize(
    "message", [m.VersionReply(1, 1, "x", 1, "y"), m.ErrorReply("X", "?", 1), m.DebugLine("x")]
)
def test_host_refuses_to_send_replies(message: object) -> None:
    with pytest.raises(LocalProtocolError):
        AsipCodec(Role.HOST).send(message)


@pytest.mark.parametrize("message", [m.VersionRequest(), m.SetMotorsPower(0, 0), m.LcdClear()])
def test_device_refuses_to_send_requests(message: object) -> None:
    with pytest.raises(LocalProtocolError):
        AsipCodec(Role.DEVICE).send(message)


@pytest.mark.parametrize("role", list(Role))
def test_non_messages_are_refused(role: Role) -> None:
    with pytest.raises(LocalProtocolError):
        AsipCodec(role).send(b"I,M\n")
    with pytest.raises(LocalProtocolError):
        AsipCodec(role).send(m.InvalidServiceRequest("X"))


def test_host_keeps_tabs_and_del_as_text_but_not_other_control_bytes() -> None:
    got, codec = decode(
        Role.HOST, b"sketch\tsays hi\x7f\n@I,d,4,1\x1b\n@#,?, 1, 1, ATmega328P, 20, mirto\n"
    )
    assert got[0] == m.DebugLine("sketch\tsays hi\x7f")
    assert isinstance(got[1], RemoteProtocolError) and got[1].kind == "garbage"
    assert got[2] == m.VersionReply(1, 1, "ATmega328P", 20, "mirto")  # the seed's spaced form
    assert codec.stats.faults == {"garbage": 1}


def test_sending_the_other_roles_message_names_who_sends_it() -> None:
    with pytest.raises(LocalProtocolError, match="sent by the device, not the host"):
        AsipCodec(Role.HOST).send(m.VersionReply(1, 1, "x", 1, "y"))
