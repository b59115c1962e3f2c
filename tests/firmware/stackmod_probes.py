"""The StackMod probe set: every packet roboscript's driver writes, and the parser's edge cases.

Each probe is one or more I2C writes to the author's motor module. The firmware answers
nothing, so what is compared is what it keeps and does: its fifteen motor registers
(``StackModIO::motors_reg``) after every probe, and the motor outputs its main loop drives on
its pins after the probes marked ``drives``.
"""

from __future__ import annotations

from dataclasses import dataclass

from roboscript.codec import Role
from roboscript.drivers.stackmod import messages as sm
from roboscript.drivers.stackmod.codec import StackModCodec

REGISTER = b"2"
"""The register byte the author's Python client writes first (0x32), skipped by the parser."""


@dataclass(frozen=True)
class Probe:
    """One or more I2C writes, each delivered whole to the sketch's ``onReceive`` handler.

    Attributes:
        drives: Wait for the sketch's 200 ms main loop and compare the motor outputs too.
        idle_s: Time the module is left alone before the writes, seconds.
        reset_after: The number of writes after which the module is reset (its reset line
            pulled, or its supply dipping), then given time to start again; None: no reset.
    """

    name: str
    writes: tuple[bytes, ...]
    drives: bool = False
    idle_s: float = 0.0
    reset_after: int | None = None


def checksum(text: bytes) -> int:
    """The author's checksum of the text between the braces: ``(sum(c - 32) % 95) + 32``,
    with AVR's signed ``char`` and C's ``%`` (the remainder keeps the dividend's sign)."""
    total = sum((byte - 256 if byte > 0x7F else byte) - 32 for byte in text)
    remainder = abs(total) % 95
    return (-remainder if total < 0 else remainder) + 32


def packet(text: bytes, *, check: int | None = None, register: bool = True) -> bytes:
    """``{text}`` and its checksum byte (or ``check``), after the register byte."""
    byte = checksum(text) if check is None else check
    return (REGISTER if register else b"") + b"{" + text + b"}" + bytes([byte & 0xFF])


def _mtr(data: bytes) -> bytes:
    return packet(b"Ep$MTR" + data)


def _driver(name: str, motor: int, pwm: int) -> Probe:
    codec = StackModCodec(Role.HOST, checksum="braces_excluded", framing="i2c")
    return Probe(name, (codec.send(sm.MotorPwm(ord("E"), motor, pwm)),), drives=True)


DRIVER_PROBES: tuple[Probe, ...] = (
    _driver("MTR1 +96", 1, 96),
    _driver("MTR2 +96", 2, 96),
    _driver("MTR1 -139", 1, -139),
    _driver("MTR2 +255", 2, 255),
    _driver("MTR1 0", 1, 0),
    _driver("MTR2 -255", 2, -255),
    _driver("MTR2 0", 2, 0),
    _driver("MTR1 +1", 1, 1),
    _driver("MTR1 +254", 1, 254),
    _driver("MTR2 -1", 2, -1),
    _driver("MTR1 -255", 1, -255),
    _driver("both stopped again", 1, 0),
)
"""Packets :mod:`roboscript.drivers.stackmod.driver` writes to the author's module."""

_HIGH = b"\xc5p$MTR1+077"
"""A text with a byte above 0x7F: AVR's ``char`` is signed, so it counts negative."""

PARSER_PROBES: tuple[Probe, ...] = (
    Probe("0.9.1 document packet", (b"{M$MTR1+038}w",)),
    Probe("without the register byte", (packet(b"Ep$MTR2+011", register=False),)),
    Probe("bad checksum", (_mtr(b"1+096")[:-1] + b"k",)),
    Probe("checksum one too high", (packet(b"Ep$MTR1+050", check=checksum(b"Ep$MTR1+050") + 1),)),
    Probe("text one character long", (_mtr(b"1+0960"),)),
    Probe("text one character short", (_mtr(b"1+96"),)),
    Probe("packet split over two writes", (b"2{Ep$MTR", b"1+096}j")),
    Probe("checksum in the next write", (_mtr(b"2+033")[:-1], _mtr(b"2+033")[-1:])),
    Probe("two packets in one write", (_mtr(b"1+020") + _mtr(b"2-020")[1:],)),
    Probe("packet then junk in one write", (_mtr(b"1+021") + b"xyz",)),
    Probe("junk then packet in one write", (b"2abc" + _mtr(b"2+022")[1:],)),
    Probe("lower-case command", (packet(b"Ep$mtr1+023"),)),
    Probe("GET action", (packet(b"Ep?MTR1+024"),)),
    Probe("other action", (packet(b"Ep!MTR1+025"),)),
    Probe("GET without data", (packet(b"Ep?MTR1"),)),
    Probe("address bytes not checked", (packet(b"@@$MTR2+026"),)),
    Probe("motor 0", (_mtr(b"0+027"),)),
    Probe("motor 3", (_mtr(b"3+028"),)),
    Probe("motor 9", (_mtr(b"9-029"),)),
    Probe("motor 12", (_mtr(b"12+30"),)),
    Probe("motor 15", (_mtr(b"15-31"),)),
    Probe("motor 16", (_mtr(b"16+32"),)),
    Probe("motor 99", (_mtr(b"99+33"),)),
    Probe("motor 257 wraps to 1", (_mtr(b"257+9"),)),
    Probe("motor 258 wraps to 2", (_mtr(b"258-8"),)),
    Probe("motor 256 wraps to 0", (_mtr(b"256+7"),)),
    Probe("motor -1", (_mtr(b"-1+34"),)),
    Probe("motor with a plus sign", (_mtr(b"+1+35"),)),
    Probe("space before the value", (_mtr(b"1 -36"),)),
    Probe("tab before the value", (_mtr(b"1\t037"),)),
    Probe("space before the motor", (_mtr(b" 2+38"),)),
    Probe("value without a sign", (_mtr(b"1 999"),)),
    Probe("two signs", (_mtr(b"1+-39"),)),
    Probe("sign then space", (_mtr(b"1+ 40"),)),
    Probe("one number only", (_mtr(b"12345"),)),
    Probe("letter after the motor", (_mtr(b"1x041"),)),
    Probe("letter inside the value", (_mtr(b"1+0x6"),)),
    Probe("value +000", (_mtr(b"2+000"),)),
    Probe("value -000", (_mtr(b"1-000"),)),
    Probe("value 300", (_mtr(b"1+300"),)),
    Probe("value -999", (_mtr(b"2-999"),)),
    Probe("ARM set", (packet(b"Ep$ARM1"),)),
    Probe("SRV set of 11 characters", (packet(b"Ep$SRV1+090"),)),
    Probe("ULT get", (packet(b"Ep?ULT1"),)),
    Probe("unknown command", (packet(b"Ep$XYZ1+042"),)),
    Probe("MTR at the wrong place", (packet(b"Ep$$MTR1+43"),)),
    Probe("text of four characters", (packet(b"Ep$M"),)),
    Probe("empty packet", (packet(b""),)),
    Probe("close brace alone", (b"2}" + bytes([checksum(b"")]),)),
    Probe("open brace restarts the text", (b"2{Ep$" + _mtr(b"1+044")[1:],)),
    Probe("open brace restart, empty checksum", (b"2{Ep${Ep$MTR1+044} ",)),
    Probe("NUL inside a packet", (b"2{Ep$M\x00" + _mtr(b"2+045")[1:],)),
    Probe("NUL between packets", (_mtr(b"1+046") + b"\x00" + _mtr(b"2+046")[1:],)),
    Probe("byte above 0x7F in the text", (packet(_HIGH),)),
    Probe("byte above 0x7F, unsigned checksum", (packet(_HIGH, check=sum(_HIGH) % 95 + 32),)),
    Probe("checksum that is an open brace", (packet(b"!M$MTR1+053"),)),
    Probe("checksum that is a close brace", (packet(b"!N$MTR2+053"),)),
    Probe("write of exactly 32 bytes", (b"2" * 17 + _mtr(b"2+047")[1:],)),
    Probe("packet past byte 32 of a write", (b"2" * 18 + _mtr(b"2+048")[1:],)),
    Probe("long write, packet first", (_mtr(b"1+049") + b"x" * 40,)),
    Probe("empty write", (b"",)),
    Probe("31-character text", (packet(b"Ep$MTR1+050" + b"0" * 20),)),
    Probe("text past 31 characters", (b"{" + b"Ep$MTR1+051" * 3 + b"}j",)),
    Probe("register byte is an open brace", (b"{" + _mtr(b"2+052")[1:],)),
    Probe("many writes in a row", tuple(_mtr(b"%d+%03d" % (1 + i % 2, 60 + i)) for i in range(6))),
    Probe("close brace among the address bytes", (packet(b"E}$MTR1+054"),)),
    Probe("packet over three writes", (b"2{Ep", b"$MTR1+", b"055}" + _mtr(b"1+055")[-1:])),
    Probe("CR inside the value", (_mtr(b"1+05\r"),)),
    Probe("value -0 and spaces", (_mtr(b"1-0  "),)),
    Probe(
        "a text of NUL bytes",
        (b"2{" + b"\x00" * 11 + b"}" + bytes([checksum(b"\x00" * 11) & 0xFF]),),
    ),
    Probe("second packet of a write bad", (_mtr(b"1+061") + _mtr(b"2+062")[1:-1] + b"!",)),
    Probe("hex and exponent values", (_mtr(b"1+0x1"), _mtr(b"2+1e2"))),
    Probe("five-digit value", (packet(b"Ep$MTR1+32767"),)),
    Probe("a write of the register byte alone", (b"2", b"{", _mtr(b"2+063"))),
    Probe("close brace before a packet", (b"2}" + _mtr(b"1+064")[1:],)),
    Probe("DEL byte in the text", (packet(b"Ep$MTR1+\x7f65"),)),
    Probe("DEL byte as the checksum", (packet(b"Ep$MTR2+066", check=0x7F),)),
    Probe("NUL as the checksum", (packet(b"Ep$MTR2+067", check=0),)),
    Probe("0xFF as the checksum", (packet(b"Ep$MTR2+068", check=0xFF),)),
    Probe(
        "checksum counted with the braces",
        (_mtr(b"1+069")[:-1] + bytes([checksum(b"{Ep$MTR1+069}")]),),
    ),
    Probe("text of eleven spaces", (packet(b" " * 11),)),
    Probe("packet ending a 32-byte write", (b"2" * 18 + _mtr(b"1+070")[1:-1], _mtr(b"1+070")[-1:])),
    Probe("brace split from its text", (b"2{", b"Ep$MTR2+071}" + _mtr(b"2+071")[-1:])),
    Probe("a packet in 15 one-byte writes", tuple(bytes([b]) for b in _mtr(b"1+072"))),
    Probe("value at the byte's edges", (_mtr(b"1+256"), _mtr(b"2-255"))),
)
"""The parser's edge cases: framing, checksum, lengths, numbers, writes split and joined."""

DRIVE_PROBES: tuple[Probe, ...] = (
    Probe("left forward, right reverse", (_mtr(b"1+128"), _mtr(b"2-064")), drives=True),
    Probe("value 300 drives", (_mtr(b"1+300"),), drives=True),
    Probe("value -256 drives", (_mtr(b"1+000"), _mtr(b"2-256")), drives=True),
    Probe(
        "ten packets between two loops",
        tuple(_mtr(b"%d+%03d" % (1 + i % 2, 100 + i)) for i in range(10)),
        drives=True,
    ),
    Probe("all stopped", (_mtr(b"1+000"), _mtr(b"2+000")), drives=True),
)
"""Packets after which the motor outputs are compared too (besides :data:`DRIVER_PROBES`)."""

EDGE_PROBES: tuple[Probe, ...] = (
    Probe("CR LF after a packet", (_mtr(b"1+011") + b"\r\n",)),
    Probe("CR LF before a packet", (b"\r\n" + _mtr(b"2+012")[1:],)),
    Probe("LF inside the text", (packet(b"Ep$MTR1\n+13"),)),
    Probe("a write of bytes above 127 only", (bytes(range(0x80, 0xA0)),)),
    Probe("0xFF run, then a packet", (b"\xff" * 10 + _mtr(b"1+014")[1:],)),
    Probe("unknown command letters", (packet(b"Ep$QQQ1+015"),)),
    Probe("motor 1 at +255", (_mtr(b"1+255"),), drives=True),
    Probe("motor 2 at -255", (_mtr(b"2-255"),), drives=True),
    Probe("motor 4", (_mtr(b"4+016"),)),
    Probe("motor 255", (_mtr(b"255+1"),)),
    Probe("a packet in one-byte writes", tuple(bytes([b]) for b in _mtr(b"2+017"))),
    Probe(
        "two packets, the second split",
        (_mtr(b"1+018") + _mtr(b"2+019")[1:8], _mtr(b"2+019")[8:]),
    ),
    Probe("a 40-byte write", (b"2" * 26 + _mtr(b"1+020")[1:],)),
    Probe("both stopped", (_mtr(b"1+000"), _mtr(b"2+000")), drives=True),
)
"""Line ends around and inside packets, bytes above 127, unknown command letters, motors past
the module's, a packet in pieces and a write past the I2C buffer's 32 bytes."""

LIFE_PROBES: tuple[Probe, ...] = (
    Probe("motors set before a reset", (_mtr(b"1+090"), _mtr(b"2-090")), drives=True),
    Probe("a reset stops the motors", (), drives=True, reset_after=0),
    Probe("a packet after the reset", (_mtr(b"1+091"),), drives=True),
    Probe("a packet cut by a reset", (b"2{Ep$MTR", b"2+092}" + _mtr(b"2+092")[-1:]), reset_after=1),
    Probe(
        "a checksum cut off by a reset", (_mtr(b"2+093")[:-1], _mtr(b"2+093")[-1:]), reset_after=1
    ),
    Probe(
        "a burst after a long idle",
        tuple(_mtr(b"%d+%03d" % (1 + i % 2, 110 + i)) for i in range(12)),
        drives=True,
        idle_s=5.0,
    ),
    Probe("one byte after a long idle", (b"{",), idle_s=2.0),
    Probe("the packet after that byte", (_mtr(b"2+094"),), drives=True),
    Probe("stopped at the end", (_mtr(b"1+000"), _mtr(b"2+000")), drives=True),
)
"""A reset with the motors running and in the middle of a packet, and a module left alone for
seconds, then sent a burst of packets or a lone byte."""

PROBES = DRIVER_PROBES + PARSER_PROBES + EDGE_PROBES + DRIVE_PROBES + LIFE_PROBES
