"""The ASIP probe set: every request roboscript's driver sends, and the parsers' error paths.

Each probe is sent to the real firmware (emulated) and to ``roboscript sim``'s board, one at a
time on one connection, and what each answers before the next probe is compared byte for byte.
The driver's requests are encoded by roboscript's own host codec, so the probe is exactly what
the driver writes.
"""

from __future__ import annotations

from dataclasses import dataclass

from roboscript.codec import Role
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec

SETTLE_S = 0.12
"""Time each probe is given: a reply is a few milliseconds of line time at 57600 baud."""
PARSE_WAIT_S = 1.2
"""Time for a probe on which the firmware waits out ``parseInt``'s 1000 ms timeout."""


@dataclass(frozen=True)
class Probe:
    """One request and how long to let both boards answer it."""

    name: str
    data: bytes
    settle_s: float = SETTLE_S


def _driver(name: str, message: object) -> Probe:
    return Probe(name, AsipCodec(Role.HOST).send(message))


DRIVER_PROBES: tuple[Probe, ...] = (
    _driver("version", m.VersionRequest()),
    _driver("service names", m.ServiceNamesRequest()),
    _driver("pin services", m.PinServicesRequest()),
    _driver("io events off", m.SetAutoEventInterval("I", 0)),
    _driver("encoder events on", m.EnableEncoderEvents(True)),
    _driver("encoder events off", m.EnableEncoderEvents(False)),
    _driver("bump events", m.SetAutoEventInterval("B", 50)),
    _driver("bump events off", m.SetAutoEventInterval("B", 0)),
    _driver("ir events", m.SetAutoEventInterval("R", 50)),
    _driver("ir events off", m.SetAutoEventInterval("R", 0)),
    _driver("distance events", m.SetAutoEventInterval("D", 100)),
    _driver("distance events off", m.SetAutoEventInterval("D", 0)),
    _driver("pixel count", m.PixelsInfoRequest(0)),
    _driver("tone", m.PlayTone(440, 100)),
    _driver("motors power", m.SetMotorsPower(40, -40)),
    _driver("motors stop", m.StopMotors()),
    _driver("motors power zero", m.SetMotorsPower(0, 0)),
    _driver("motor stop one", m.StopMotor(1)),
    _driver("motor rpm", m.SetMotorRpm(0, 30, 200)),
    _driver("motors rpm", m.SetMotorsRpm(30, 30, 200)),
    _driver("servo", m.ServoWrite(0, 45)),
    _driver("lcd clear", m.LcdClear()),
    _driver("lcd write", m.LcdWrite(1, "hello")),
    _driver("pixel set", m.PixelsSetRgb(0, ((2, (10, 20, 30)),))),
)
"""Every request :mod:`roboscript.drivers.asip.driver` sends, in its own encoding."""

ERROR_PROBES: tuple[Probe, ...] = (
    Probe("unknown service", b"X,?\n"),
    Probe("unknown service, long tail", b"X,abcdefghijklmnop\n"),
    Probe("service without comma", b"M;S,0\n"),
    Probe("unknown system tag", b"#,Z\n"),
    Probe("unknown io tag", b"I,Z\n"),
    Probe("unknown motor tag", b"M,Z,0\n"),
    Probe("unknown bump tag", b"B,Z\n"),
    Probe("unknown ir tag", b"R,Z\n"),
    Probe("unknown distance tag", b"D,Z\n"),
    Probe("unknown servo tag", b"S,Z\n"),
    Probe("unknown tone tag", b"T,Z\n"),
    Probe("unknown lcd tag", b"L,Z\n"),
    Probe("unknown pixels tag", b"P,Z\n"),
    Probe("io port map", b"I,M\n"),
    Probe("io analog map", b"I,m\n"),
    Probe("io pin modes", b"I,p\n"),
    Probe("io capabilities", b"I,c\n"),
    Probe("digital write on motor pin", b"I,d,8,1\n"),
    Probe("analog write on non-pwm pin", b"I,a,2,10\n"),
    Probe("analog write on pwm pin of a service", b"I,a,5,10\n"),
    Probe("pin mode on reserved pin", b"I,P,0,3\n"),
    Probe("pin mode unsupported", b"I,P,2,9\n"),
    Probe("pin mode input on service pin", b"I,P,18,2\n"),
    Probe("servo id out of range", b"S,W,5,45\n"),
    Probe("distance measure", b"D,M\n"),
    Probe("pixels strip info", b"P,I,0\n"),
    Probe("pixels clear", b"P,C,0\n"),
    Probe("pixels brightness", b"P,B,0,32\n"),
    Probe("pixels set packed", b"P,P,0,1,{0:255}\n"),
    Probe("pixels set range", b"P,S,0,1,0,{255}\n"),
    Probe("pixels set range without brace", b"P,S,0\n"),
    Probe("lcd long row", b"L,W,2,abcdefghijklmnopqrstuvwxyz\n"),
    Probe("lcd bar graph", b"L,G,1,{0:50}\n"),
    Probe("motors speed", b"M,c,10,200\n"),
    Probe("motors rotate", b"M,a,90,45\n"),
    Probe("encoder reset", b"M,E,0\n"),
    Probe("stop with no argument", b"M,S\n", PARSE_WAIT_S),
    Probe("request with no newline", b"M,M,0,0", PARSE_WAIT_S),
    Probe("two requests in one write", b"M,A,0M,M,0,0\n"),
    Probe("tone with zero duration", b"T,P,440,0\n"),
    Probe("version again", b"#,?\n"),
)
"""The parsers' error paths and the requests other clients send."""

_ALPHABET = b"abcdefghijklmnopqrstuvwxyz"

TIMING_PROBES: tuple[Probe, ...] = (
    Probe("reply then pixel request", b"#,N\nP,P,0,1,{0:255}\n"),
    Probe("pixel count after a reply", b"P,I,0\n"),
    Probe("three unknown services", b"X,1\nY,2\nZ,3\n"),
    Probe("unknown service, digits tail", b"X," + b"0123456789" * 8 + b"\n"),
    Probe("errors back to back", b"#,Z\n#,Y\n#,X\n#,W\n#,V\n#,U\n#,T\nI,M\n"),
    Probe("unknown pixels tag, long tail", b"P,Z," + _ALPHABET + b"\n"),
    Probe("pixel count, long tail", b"P,I,0," + _ALPHABET + b"\n"),
    Probe("pin services, then unknown", b"#,S\nQ," + _ALPHABET + b"\n"),
    Probe("capabilities, then unknown", b"I,c\nQ," + _ALPHABET + b"\n"),
    Probe("port map, then unknown", b"I,M\nQ," + _ALPHABET + b"0123456789\n"),
    Probe("unknown services, short lines", b"A,\nC,\nF,\nJ,\nK,\nN,\nO,\nQ,\n"),
    Probe("unknown services, CRLF", b"X,?\r\nX,?\r\n"),
    Probe("pixels rgb sequence", b"P,s,0,2,0,{1:2:3,4:5:6}\n"),
    Probe(
        "requests behind long replies",
        b"#,N\n#,N\n#,N\n" + b"".join(b"T,%02d\n" % i for i in range(30)) + b"X,1\n",
    ),
    Probe("unknown services behind long replies", b"#,S\n#,N\n" + b"Y,00\n" * 30),
    Probe("version at the end", b"#,?\n"),
)
"""What a UART board reads depends on when it reads: a request that arrives while the firmware
is still writing is read whole; an unknown service skips what has arrived once its error is
written, later when the transmit buffer is full; bytes that arrive while the receive buffer is
full (the firmware writing long replies) are lost."""

VALUE_PROBES: tuple[Probe, ...] = (
    Probe("motor id -1", b"M,m,-1,50\n"),
    Probe("motor id 256 is motor 0", b"M,m,256,0\n"),
    Probe("rpm of motor -1", b"M,r,-1,30,100\n"),
    Probe("rpm past 1000", b"M,r,0,2000,100\n"),
    Probe("stop motor -1", b"M,s,-1,0\n"),
    Probe("motors stop after rpm", b"M,S,0\n"),
    Probe("lcd row -1", b"L,W,-1,hi\n"),
    Probe("lcd write at row -1", b"L,w,-1,2,hi\n"),
    Probe("lcd write at column -1", b"L,w,2,-1,hi\n"),
    Probe("a number past a long", b"M,M,11111111111111111111,0\n"),
    Probe("a 400-digit number", b"M,M," + b"9" * 400 + b",0\nI,M\n", 0.3),
    Probe("a 400-digit tone, no newline", b"T,P," + b"9" * 400, PARSE_WAIT_S),
    Probe("a request during its second wait", b"#,?\n", PARSE_WAIT_S),
    Probe("lower-case service", b"m,M,0,0\n"),
    Probe("empty line", b"\n"),
    Probe("lone comma", b",\n"),
    Probe("version with arguments", b"#,?,1,2\n"),
    Probe("motors of letters", b"M,M,abc,def\n"),
    Probe("servo angle 200", b"S,W,0,200\n"),
    Probe("lcd row 5", b"L,W,5,hi\n"),
    Probe("digital write on pin 99", b"I,d,99,1\n"),
    Probe("a byte above 127 as a service", b"\xff,?\n"),
    Probe("version after a CR LF", b"#,?\r\n"),
    Probe("debug echo on a build without it", b"!hello\n"),
    Probe("wifi settings on a V1.1 board", b"$$,net,pw\n", PARSE_WAIT_S),
    Probe("an unknown strip's pixel count", b"P,I,-1\n"),
)
"""Numbers past what the firmware keeps them in (a ``byte`` id, a wrapping ``long``), rows
before the first, headers of builds the MIRTO sketch is not, and other malformed requests.
They come last: the timing probes' answers depend on when they run (see ``TIMING_PROBES``)."""

INT16_PROBES: tuple[Probe, ...] = (
    Probe("encoder events of 65536 are off", b"M,A,65536\n"),
    Probe("encoder events off again", b"M,A,0\n"),
    Probe("servo 65536 is servo 0", b"S,W,65536,45\n"),
    Probe("servo -65535 is servo 1", b"S,W,-65535,45\n"),
    Probe("lcd row 65537 is row 1", b"L,W,65537,hi\n"),
    Probe("lcd column 65537 is column 1", b"L,w,0,65537,hi\n"),
    Probe("lcd row 32768 is a row before the first", b"L,W,32768,hi\n"),
    Probe("pixel count of strip 65536", b"P,I,65536\n"),
    Probe("bump events every 65586 ms are every 50", b"B,A,65586\n"),
    Probe("bump events off after 65586", b"B,A,0\n"),
    Probe("bump events every 7 ms", b"B,A,7\n"),
    Probe("bump events off after 7 ms", b"B,A,0\n"),
    Probe("bump events every 2 ms", b"B,A,2\n"),
    Probe("bump events off after 2 ms", b"B,A,0\n"),
    Probe("bump events every -5 ms", b"B,A,-5\n"),
    Probe("bump events off after -5 ms", b"B,A,0\n", 0.3),
    Probe("motor rpm with a duration past an int", b"M,r,0,30,40000\n"),
    Probe("motors stop after a long duration", b"M,S,0\n"),
    Probe("version after the int probes", b"#,?\n"),
)
"""Values the MIRTO sketch keeps in an ATmega328P's 16-bit ``int`` (a motor request's
arguments, a servo id, an LCD row and column, a pixel strip) or ``unsigned int`` (an
auto-event interval, whose next due tick wraps: ``-5`` reports on every turn of ``loop()``,
as fast as the line takes the events)."""

EDGE_PROBES: tuple[Probe, ...] = (
    # requests cut short: each waits out parseInt where a number is missing
    Probe("partial: service and comma", b"M,\n"),
    Probe("partial: tag, no number", b"M,M,\n", PARSE_WAIT_S),
    Probe("partial: one number of two", b"M,M,10\n", PARSE_WAIT_S),
    Probe("partial: trailing comma", b"M,M,10,\n", PARSE_WAIT_S),
    Probe("partial: system header alone", b"#\n#,?\n"),
    Probe("partial: system comma only", b"#,\n#,?\n"),
    Probe("partial: three bytes", b"#,?"),
    Probe("partial: the newline later", b"\n"),
    # lines far past what a request holds
    Probe("long: 200 letters", b"Q" * 200 + b"\n"),
    Probe("long: 120 commas", b"," * 120 + b"\n"),
    Probe("long: lcd row of 100", b"L,W,0," + b"x" * 100 + b"\n"),
    Probe("long: version then 100 spaces", b"#,?" + b" " * 100 + b"\n"),
    Probe("long: lcd row from column 5", b"L,w,1,5," + _ALPHABET.upper() + b"\n"),
    Probe("long: lcd row of 20 digits and 4 more", b"L,W,3,12345678901234567890XYZW\n"),
    # bytes above 127
    Probe("high: four bytes above 127", b"\x80\x81\x82\x83\n"),
    Probe("high: tag above 127", b"M,\xff,1\n"),
    Probe("high: lcd text above 127", b"L,W,0,h\xe9llo\n"),
    Probe("high: number with a byte above 127", b"M,M,1\xb02,3\n"),
    Probe("high: 0xFF run", b"\xff" * 10 + b"\n"),
    # line ends
    Probe("crlf: CR only", b"#,?\r"),
    Probe("crlf: CR CR LF", b"#,?\r\r\n"),
    Probe("crlf: LF CR", b"#,?\n\r"),
    Probe("crlf: CRLF before", b"\r\n#,?\n"),
    Probe("crlf: motors CRLF", b"M,M,0,0\r\n"),
    Probe("crlf: lcd CRLF", b"L,W,1,ab\r\n"),
    Probe("crlf: NUL before", b"\x00#,?\n"),
    Probe("crlf: tab before", b"\t#,?\n"),
    # service and tag letters the sketch lacks
    Probe("unknown: lower-case services", b"a,\nb,\nc,\nd,\n"),
    Probe("unknown: io tags", b"I,x\nI,?\n"),
    Probe("unknown: motor tags", b"M,x,0\nM,?,0\n"),
    Probe("unknown: lower-case system tags", b"#,n\n#,s\n#,r\n"),
    # pins and ids past the board's
    Probe("range: digital write pin 20", b"I,d,20,1\n"),
    Probe("range: digital write pin -1", b"I,d,-1,1\n"),
    Probe("range: digital write pin 256", b"I,d,256,1\n"),
    Probe("range: pin mode 255", b"I,P,255,1\n"),
    Probe("range: input on an encoder pin", b"I,P,7,2\n"),
    Probe("range: output on an encoder pin", b"I,P,7,3\n"),
    Probe("range: analog write pin 261", b"I,a,261,10\n"),
    Probe("range: motor 2 power", b"M,m,2,50\n"),
    Probe("range: motor stop 2", b"M,s,2,0\n"),
    Probe("range: servo 1", b"S,W,1,90\n"),
    Probe("range: servo -1", b"S,W,-1,90\n"),
    Probe("range: servo -256 is servo 0", b"S,W,-256,90\n"),
    Probe("range: lcd column 20", b"L,w,0,20,hi\n"),
    Probe("range: lcd column 21", b"L,w,0,21,hi\n"),
    Probe("range: lcd bar on line 9", b"L,G,1,{9:50}\n"),
    Probe("range: pixel strip 1", b"P,I,1\n"),
    Probe("range: tone of 0 Hz", b"T,P,0,100\n"),
    Probe("range: tone of -5 ms", b"T,P,440,-5\n"),
    Probe("range: tone past an int", b"T,P,440,40000\n"),
    # one request in two writes
    Probe("split: header", b"M,", 0.01),
    Probe("split: rest", b"M,0,0\n"),
    Probe("split: number", b"M,M,0", 0.01),
    Probe("split: number rest", b",0\n"),
    # the cores' find and parseInt
    Probe("find: bar graph with a doubled comma", b"L,G,1,,{0:50}\n"),
    Probe("find: bar graph without brace", b"L,G,1,0:50\n", PARSE_WAIT_S),
    Probe("parse: double minus", b"M,M,--5,3\n"),
    Probe("parse: minus inside", b"M,M,5-3,2\n"),
    Probe("parse: plus sign", b"M,M,+5,+3\n"),
    Probe("parse: decimal point", b"M,M,1.5,2\n"),
    Probe("parse: spaces in numbers", b"M,M, 4 , 5\n"),
    Probe("parse: lone minus", b"M,M,-,0\n"),
    Probe("motors stopped after the edges", b"M,S,0\nM,M,0,0\n"),
    # a restart, and what it leaves
    Probe("system: restart", b"#,R\n"),
    Probe("system: version after restart", b"#,?\n"),
    Probe("system: pin modes after restart", b"I,p\n"),
)
"""Malformed and partial requests, long lines, bytes above 127, line ends, letters the sketch
lacks, pins and ids past the board's, requests written in two pieces, and where the Arduino
AVR core's ``Stream`` differs from the Teensy 3 core's (``readBytesUntil`` takes one byte
more, ``find`` walks back). Last: a restart changes what every later probe meets."""

PROBES = DRIVER_PROBES + ERROR_PROBES + TIMING_PROBES + VALUE_PROBES + INT16_PROBES + EDGE_PROBES
