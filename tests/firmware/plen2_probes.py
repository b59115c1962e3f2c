"""The PLEN2 probe set: every command roboscript's driver sends, and the parser's error paths.

Each probe is sent to PLEN2's own firmware (emulated) and to ``roboscript sim``'s PLEN2, one
after the other on one connection; what each answers before the next probe, and the 24 servo
outputs each drives after it, are compared. The driver's commands are encoded by roboscript's
own host codec, so the probe is exactly what the driver writes.
"""

from __future__ import annotations

from dataclasses import dataclass

from roboscript.codec import Role
from roboscript.drivers.plen import messages as m
from roboscript.drivers.plen.codec import PlenCodec
from roboscript.drivers.plen.driver import CHUNK_BYTES, CHUNK_GAP_S

SETTLE_S = 0.04
"""Time each probe is given: a setter writes the board's EEPROM (3.3 ms a byte pair)."""
GETTER_S = 0.15
"""Time for ``<JS`` (about 2 KB at 2 Mbaud) or a one-frame ``<MO``."""
MOTION_S = 0.6
"""Time for a short motion to play out (a few 32 ms updates) and its dump to be read."""


@dataclass(frozen=True)
class Probe:
    """Bytes written one after the other (each write one host ``write()``, ``gap_s`` apart),
    and how long to let both boards answer them after the last."""

    name: str
    writes: tuple[bytes, ...]
    settle_s: float = SETTLE_S
    gap_s: float = 0.001
    idle_s: float = 0.0
    """Time the board is left alone before the first write, seconds."""
    reset_after: int | None = None
    """The number of writes after which the board is reset (its reset line pulled, or its
    supply dipping under the servos' load); None: no reset."""


def probe(name: str, *writes: bytes, settle_s: float = SETTLE_S) -> Probe:
    return Probe(name, writes, settle_s)


def paced(name: str, data: bytes, settle_s: float = SETTLE_S) -> Probe:
    """``data`` written as the driver writes: in chunks of 32 bytes, 50 ms apart (the
    firmware reads a byte per turn of its loop and drops what overflows its 64-byte ring)."""
    chunks = tuple(data[i : i + CHUNK_BYTES] for i in range(0, len(data), CHUNK_BYTES))
    return Probe(name, chunks, settle_s, CHUNK_GAP_S)


def _driver(name: str, message: object, settle_s: float = SETTLE_S) -> Probe:
    """A command as the driver writes it: in chunks of 32 bytes, 50 ms apart."""
    return paced(name, PlenCodec(Role.HOST).send(message), settle_s)


_ZERO = (0,) * m.JOINT_COUNT
_WAVE = tuple((j * 37) % 200 - 100 for j in range(m.JOINT_COUNT))

DRIVER_PROBES: tuple[Probe, ...] = (
    _driver("version", m.GetVersion(), GETTER_S),
    _driver("joint settings", m.GetJointSettings(), GETTER_S),
    _driver("set an angle", m.SetAngle(10, 900)),
    _driver("set a negative angle", m.SetAngle(0, -100)),
    _driver("set an angle difference", m.SetAngleDiff(1, 50)),
    _driver("set a negative difference", m.SetAngleDiff(13, -70)),
    _driver("home position", m.HomePosition()),
    _driver("set a home position", m.SetHome(0, 16)),
    _driver("set a max", m.SetMax(2, 800)),
    _driver("set a min", m.SetMin(2, -800)),
    _driver("joint settings after setters", m.GetJointSettings(), GETTER_S),
    _driver("factory joint settings", m.ResetJointSettings()),
    _driver("joint settings restored", m.GetJointSettings(), GETTER_S),
    _driver(
        "motion header",
        m.MotionHeader(slot=3, name="probe", frame_length=2),
    ),
    _driver("motion frame 0", m.MotionFrame(3, 0, 64, _WAVE)),
    _driver("motion frame 1", m.MotionFrame(3, 1, 96, _ZERO)),
    _driver("motion dump", m.GetMotion(3), GETTER_S),
    _driver("play motion", m.PlayMotion(3), MOTION_S),
    _driver("stop motion", m.StopMotion()),
    _driver("push motion", m.PushMotion(3, 2)),
    _driver("pop motion", m.PopMotion(), MOTION_S),
    _driver("reset interpreter", m.ResetInterpreter()),
    _driver(
        "looping header",
        m.MotionHeader(
            slot=4, name="loop", frame_length=1, use_loop=True, loop_end=0, loop_count=2
        ),
    ),
    _driver("looping frame", m.MotionFrame(4, 0, 64, _WAVE)),
    _driver("looping dump", m.GetMotion(4), GETTER_S),
    _driver("play the loop", m.PlayMotion(4), MOTION_S),
    _driver(
        "jumping header",
        m.MotionHeader(slot=5, name="jump", frame_length=1, use_jump=True, jump_slot=3),
    ),
    _driver("jumping frame", m.MotionFrame(5, 0, 32, _ZERO)),
    _driver("jumping dump", m.GetMotion(5), GETTER_S),
    _driver("play the jump", m.PlayMotion(5), MOTION_S),
    _driver("a slow frame's header", m.MotionHeader(slot=6, name="slow", frame_length=1)),
    _driver("a frame of 10.24 s", m.MotionFrame(6, 0, 10240, _WAVE)),
    # MotionController.h: the update count is a uint8_t, 320 updates wrap to 64 (2.1 s)
    _driver("play the slow frame", m.PlayMotion(6), 2.4),
    _driver("home after it", m.HomePosition()),
)
"""Every command :mod:`roboscript.drivers.plen.driver` sends, in its own encoding."""

ERROR_PROBES: tuple[Probe, ...] = (
    probe("lower-case getter", b"<vi", settle_s=GETTER_S),
    probe("mixed-case getter", b"<vI", settle_s=GETTER_S),
    probe("lower-case hex", b"$an0aFFF"),
    probe("upper-case hex", b"$AN0AF9C"),
    probe("junk before a command", b"xyz 123<VI", settle_s=GETTER_S),
    probe("CR LF between commands", b"<VI\r\n<VI\r\n", settle_s=GETTER_S),
    probe("unknown command, then a getter", b"$AE<VI", settle_s=GETTER_S),
    probe("unknown command eats the header after it", b"$H<VI", settle_s=GETTER_S),
    probe("half a getter eats the next", b"<V<VI", settle_s=GETTER_S),
    probe("getter under another header", b"#VI<VI", settle_s=GETTER_S),
    probe("setter under the getter header", b"<MA<VI", settle_s=GETTER_S),
    probe("unknown interpreter command", b"#ZZ<VI", settle_s=GETTER_S),
    probe("unknown setter command", b">ZZ<VI", settle_s=GETTER_S),
    probe("unknown getter command", b"<ZZ<VI", settle_s=GETTER_S),
    probe("between two commands", b"#PP<VI", settle_s=GETTER_S),
    probe("between two setters", b">HP<VI", settle_s=GETTER_S),
    probe("between two getters", b"<KK<VI", settle_s=GETTER_S),
    probe("NUL bytes as a command", b"<\x00\x00<VI", settle_s=GETTER_S),
    probe("NUL ends an argument early", b"$AN0\x00384"),
    probe("NUL as the first argument", b"$AN\x000384<VI", settle_s=GETTER_S),
    probe("setter 6 past the table", b">PO<VI", settle_s=GETTER_S),
    probe("non-hex argument", b"$PMzz<VI", settle_s=GETTER_S),
    probe("short argument eats a header", b"$PM0<VI", settle_s=GETTER_S),
    probe("non-hex angle", b"$AN01xyz<VI", settle_s=GETTER_S),
    probe("joint 24", b"$AN18000"),
    probe("joint 255", b"$ANff100"),
    probe("angle 2047 clamps", b"$AN027ff"),
    probe("angle -2048 clamps", b"$AN02800"),
    probe("difference 2047 clamps", b"$AD037ff"),
    probe("difference -2048 clamps", b"$AD04800"),
    probe("home beyond max", b">HO00400<JS", settle_s=GETTER_S),
    probe("home below min", b">HO00a00<JS", settle_s=GETTER_S),
    probe("home on joint 24", b">HO18010<JS", settle_s=GETTER_S),
    probe("max 900", b">MA05384<JS", settle_s=GETTER_S),
    probe("max 901", b">MA05385<JS", settle_s=GETTER_S),
    probe("max below min", b">MA05c00<JS", settle_s=GETTER_S),
    probe("min -900", b">MI05c7c<JS", settle_s=GETTER_S),
    probe("min -901", b">MI05c7b<JS", settle_s=GETTER_S),
    probe("min above max", b">MI05300<JS", settle_s=GETTER_S),
    probe("narrow range", b">MI06000>MA06001$AN06384<JS", settle_s=GETTER_S),
    probe("angle outside a narrow range", b"$AD06c00"),
    probe("factory settings again", b">JS"),
    probe("play slot 90", b"$PM5a"),
    probe("play slot 255", b"$PMff"),
    probe("stop with nothing playing", b"$SM"),
    probe("old play alias", b"$MP03", settle_s=MOTION_S),
    probe("old stop alias", b"$MS"),
    probe("pop an empty queue", b"#PO"),
    probe("push then reset", b"#PU0302#RI"),
    probe("push slot 90, then a motion, pop both", b"#PU5a02#PU0301#PO#PO", settle_s=MOTION_S),
    probe("push with count 0, pop, stop", b"#PU0300#PO$SM", settle_s=MOTION_S),
    probe("dump slot 90", b"<MO5a", settle_s=GETTER_S),
    probe("dump slot 255", b"<MOff", settle_s=GETTER_S),
    paced("header of 0 frames", b">MH06zero                0000000000000<MO03", settle_s=GETTER_S),
    paced("header of 21 frames", b">MH06big                 0000000000015<MO03", settle_s=GETTER_S),
    paced("header in slot 90", b">MH5ahigh                0000000000001<MO03", settle_s=GETTER_S),
    paced("frame 20", b">MF0314" + b"0040" + b"0" * 96 + b"<MO03", settle_s=GETTER_S),
    paced("frame in slot 90", b">MF5a00" + b"0040" + b"0" * 96),
    paced("frame with a non-hex value", b">MF0300" + b"0040" + b"0" * 95 + b"x<MO03", GETTER_S),
    paced("non-hex slot in a header", b">MH0gTest                0000000000001<MO10", GETTER_S),
    paced("header flags other than 1", b">MH07flags               x000102x03y01<MO07", GETTER_S),
    probe("command split over two writes", b"<V", b"I", settle_s=GETTER_S),
    probe("arguments split over writes", b"$AN0", b"b1", b"00"),
    probe("getters back to back", b"<VI<VI", settle_s=GETTER_S),
    probe("setter then getter in one write", b">HO01064<JS", settle_s=GETTER_S),
    probe("factory settings at the end", b">JS<JS", settle_s=GETTER_S),
    probe("lower-case commands of every header", b"$hp#ri>js<js", settle_s=GETTER_S),
    probe("a header lookalike", b"%VI!VI<VI", settle_s=GETTER_S),
    probe("unused joints move", b"$AN09100$AN17f00$AD0b050"),
    probe("difference after a new home", b">HO04000$AD04064"),
    probe("angle above a lowered max", b">MA04100$AN04200"),
    probe("min equal to max", b">MI04064<JS", settle_s=GETTER_S),
    probe("max equal to min", b">MI04000>MA04000<JS", settle_s=GETTER_S),
    probe("home equal to min and max", b">HO04000>HO04064<JS", settle_s=GETTER_S),
    probe("home position after new homes", b"$HP"),
    _driver("a header alone", m.MotionHeader(slot=8, name="alone", frame_length=2)),
    probe("its frames were never written", b"<MO08", settle_s=GETTER_S),
    probe("stop a looping motion", b"$PM04$SM", settle_s=MOTION_S),
    probe("reset during a motion", b"$PM03#RI", settle_s=MOTION_S),
    probe("factory settings to end", b">JS$HP"),
)
"""The parser's error paths, upper and lower case, and commands split and joined."""

OUTSIDE_TABLE_PROBES: tuple[Probe, ...] = (
    probe("controller command before AD", b"$AA<VI", settle_s=GETTER_S),
    probe("controller command of digits", b"$12<VI", settle_s=GETTER_S),
    probe("lower-case command before AD", b"$ac<VI", settle_s=GETTER_S),
    probe("controller command past SM", b"$ZZ<VI", settle_s=GETTER_S),
    probe("controller command just past SM", b"$sn<VI", settle_s=GETTER_S),
    probe("half a controller command before AD", b"$A<VI", settle_s=GETTER_S),
    probe("interpreter command before PO", b"#AA<VI", settle_s=GETTER_S),
    probe("setter command before HO", b">AA<VI", settle_s=GETTER_S),
    probe("setter command of digits", b">12<VI", settle_s=GETTER_S),
    probe("getter command before JS", b"<AA<VI", settle_s=GETTER_S),
    probe("getter command of digits", b"<12<VI", settle_s=GETTER_S),
    probe("lower-case getter before JS", b"<aa<VI", settle_s=GETTER_S),
    probe("getter command past VI", b"<zz<VI", settle_s=GETTER_S),
    probe("a doubled getter header", b"<<VI<VI", settle_s=GETTER_S),
    probe("a doubled controller header", b"$$HP<VI", settle_s=GETTER_S),
    probe("LF after a header", b"<\nVI<VI", settle_s=GETTER_S),
    probe("LF inside a command", b"$A\nN0a064<VI", settle_s=GETTER_S),
)
"""Commands a binary search with ``uint8_t`` bounds (``StringGroupParser::parse``) looks for
outside its table: one that sorts before a header's first command wraps ``end`` to 255 and
reads a pointer 254 bytes past the table, one past a header's last command reads the pointer
after it. On this build both lead above the 2.5 KB of RAM, where the board reads 0 (the
harness's data space): the command matches nothing and is dropped."""

ARGUMENT_PROBES: tuple[Probe, ...] = (
    probe("a dump of one hex digit", b"<MO5<VI", settle_s=GETTER_S),
    probe("a dump of a space and a digit", b"<MO 3<VI", settle_s=GETTER_S),
    probe("a dump of slot -1", b"<MO-1<VI", settle_s=GETTER_S),
    probe("a dump of a non-hex first digit", b"<MOg0<VI", settle_s=GETTER_S),
    probe("a dump of a NUL and a slot", b"<MO\x0003<VI", settle_s=GETTER_S),
    probe("a lower-case dump", b"<mo03", settle_s=GETTER_S),
    probe("a play of one hex digit", b"$PM3<VI", settle_s=GETTER_S),
    probe("a play of non-hex digits", b"$PMgg<VI", settle_s=GETTER_S),
    probe("a push of a short count", b"#PU03<VI", settle_s=GETTER_S),
    probe("a push of non-hex count", b"#PU03zz<VI", settle_s=GETTER_S),
    probe("a short motion header", b">MH03abc<VI", settle_s=GETTER_S),
    probe("digits after a getter", b"<JS00<VI", settle_s=GETTER_S),
    probe("digits after the version", b"<VI00", settle_s=GETTER_S),
    probe("more digits than an angle takes", b"$AN0a0640000<VI", settle_s=GETTER_S),
    probe("lower-case angle", b"$an0a064"),
    probe("lower-case difference", b"$ad0b064"),
    probe("lower-case max and min", b">ma01100>mi01f00<js", settle_s=GETTER_S),
    probe("lower-case factory settings", b">js"),
    probe("CR inside a getter", b"<V\rI<VI", settle_s=GETTER_S),
    probe("junk between header and command", b"x<xVI<VI", settle_s=GETTER_S),
    probe("junk right after a getter", b"<VIx<VI", settle_s=GETTER_S),
    probe("CR LF inside an angle", b"$AN0a\r\n64<VI", settle_s=GETTER_S),
    probe("tab and space before a getter", b"\t <VI", settle_s=GETTER_S),
    probe("bytes above 127", b"\x80\xfe<VI<\xffI<VI", settle_s=GETTER_S),
    probe("a getter ending a long line", b"<VI" + b"y" * 50 + b"\r\n", settle_s=GETTER_S),
    probe("a getter a byte a write", b"<", b"V", b"I", settle_s=GETTER_S),
    probe("an angle in four writes", b"$", b"AN", b"0a", b"000"),
    probe("a dump split in its slot", b"<MO0", b"3", settle_s=GETTER_S),
)
"""Short, odd and garbage arguments, lower case, junk inside and around commands, long lines
and commands written in pieces."""

_FRAME = b">MF03010060" + b"0010" * m.JOINT_COUNT


def _frame(slot: int, index: int) -> bytes:
    """A frame of 64 ms setting every joint to 16 (0x10), as a setter writes it."""
    return b">MF%02x%02x0040" % (slot, index) + b"0010" * m.JOINT_COUNT


SLOT_PROBES: tuple[Probe, ...] = (
    probe("play an erased slot", b"$PM0a", settle_s=MOTION_S),
    probe("stop the erased slot's motion", b"$SM"),
    probe("home after the erased slot", b"$HP"),
    probe("push an erased slot and pop it", b"#PU0a01#PO", settle_s=MOTION_S),
    probe("stop the popped erased slot", b"$SM$HP"),
    probe("play the last slot, erased", b"$PM59", settle_s=MOTION_S),
    probe("stop the last slot", b"$SM$HP"),
    probe("play slot -1", b"$PM-1<VI", settle_s=GETTER_S),
    probe("push slot 90 alone, pop it", b"#PU5a01#PO<VI", settle_s=GETTER_S),
    paced("a header of 3 frames", b">MH0bthree               0000000000003"),
    paced("only its first frame", _frame(11, 0)),
    probe("dump a motion missing frames", b"<MO0b", settle_s=GETTER_S),
    probe("play a motion missing frames", b"$PM0b", settle_s=MOTION_S),
    probe("stop the motion missing frames", b"$SM$HP"),
    paced("a header of 2 frames", b">MH0ctwo                 0000000000002"),
    paced("only its second frame", _frame(12, 1)),
    probe("dump a motion missing its first frame", b"<MO0c", settle_s=GETTER_S),
    probe("play a motion missing its first frame", b"$PM0c", settle_s=MOTION_S),
    probe("stop the motion missing its first frame", b"$SM$HP"),
    paced("a frame in a slot with no header", _frame(13, 0)),
    probe("play a slot with a frame and no header", b"$PM0d", settle_s=MOTION_S),
    probe("stop the slot with no header", b"$SM$HP"),
    paced("a header rewritten shorter", b">MH0bshorter             0000000000001"),
    probe("dump the shortened motion", b"<MO0b", settle_s=GETTER_S),
)
"""Motion slots at their edges: a slot never written (the EEPROM erased, 0xFF) played and
pushed, the last slot and the ones past it, motions whose header and frames were written in
part (a header without all its frames, frames without a header, a header rewritten)."""


def timed_frame(slot: int, index: int, time_ms: int, value: int) -> bytes:
    """A frame of ``time_ms`` setting every joint to ``value``, as a setter writes it."""
    return b">MF%02x%02x%04x" % (slot, index, time_ms) + b"%04x" % (value & 0xFFFF) * 24


EDGE_PROBES: tuple[Probe, ...] = (
    probe("long: 500 junk bytes, then a getter", b"q" * 500 + b"<VI", settle_s=GETTER_S),
    probe("long: 1000 headers", b"<" * 1000 + b"<VI", settle_s=GETTER_S),
    probe("high: a byte above 127 in an angle", b"$AN0a\x8064<VI", settle_s=GETTER_S),
    probe("high: 0xFF as a header", b"\xffVI<VI", settle_s=GETTER_S),
    paced("high: a name above 127", b">MH0ecaf\xe9               0000000000001<MO0e", GETTER_S),
    probe("crlf: CR around a getter", b"\r<VI\r", settle_s=GETTER_S),
    probe("crlf: LF LF around a getter", b"\n\n<VI\n\n", settle_s=GETTER_S),
    probe("crlf: CRLF inside a setter", b">HO0\r\n1064<JS", settle_s=GETTER_S),
    probe("unknown: header lookalikes", b"!VI@VI&VI*VI<VI", settle_s=GETTER_S),
    probe("range: joint 23", b"$AN17100"),
    probe("range: joint 25", b"$AN19100"),
    probe("range: home again", b"$HP"),
    Probe("split: 100 ms apart", (b"$AN0", b"a064"), 0.04, 0.1),
    Probe("split: a getter 300 ms apart", (b"<V", b"I"), GETTER_S, 0.3),
    probe("split: an empty write between", b"<", b"", b"V", b"I", settle_s=GETTER_S),
    probe("burst: 20 getters", b"<VI" * 20, settle_s=0.3),
    probe("burst: home after it", b"$HP"),
)
"""Long runs, bytes above 127, line ends, header lookalikes, joints at their edges, a frame of
8192 ms (its count of updates is 0 in a ``uint8_t``: ``MotionController``
divides by zero, and avr-gcc's division gives -1), commands in pieces far apart, bursts."""

TIMING_PROBES: tuple[Probe, ...] = (
    probe("stray bytes ahead of a getter", b"x" * 60 + b"<VI", settle_s=GETTER_S),
    probe("a getter kept behind a long reply", b"<JS" + b"x" * 40 + b"<VI", settle_s=GETTER_S),
    probe("a getter lost behind a long reply", b"<JS" + b"x" * 100 + b"<VI", settle_s=GETTER_S),
    probe("a frame written at once", _FRAME + b"<VI", settle_s=GETTER_S),
    probe("a frame in two halves", _FRAME[:60], _FRAME[60:] + b"<MO03", settle_s=GETTER_S),
    probe("a header then a getter at once", b">MH03probe               0000000000002<VI<VI"),
    probe("home position then getters", b"$HP" + b"<VI" * 12, settle_s=GETTER_S),
    probe("version at the end", b"<VI", settle_s=GETTER_S),
    # last: what the ring lets through of its end may leave half a command in the parser
    probe("a long run of stray bytes", b"x" * 300 + b"<VI", settle_s=GETTER_S),
)
"""What a 2 Mbaud board reads depends on when it reads: the firmware takes a byte a turn of its
loop (about 29 us, while the line brings one every 5 us) and none while a command runs (a
reply, an EEPROM write); what arrives while its 64-byte receive ring is full is lost."""

LIFE_PROBES: tuple[Probe, ...] = (
    probe("a home moved before a reset", b">HO04032$AN04100"),
    Probe("a reset during a motion", (b"$PM03",), MOTION_S, reset_after=1),
    probe("the settings after the reset", b"<JS", settle_s=GETTER_S),
    probe("a motion after the reset", b"<MO03", settle_s=GETTER_S),
    probe("a motion played after the reset", b"$PM03", settle_s=MOTION_S),
    Probe("a reset inside a command", (b"$AN0", b"a064<VI"), GETTER_S, reset_after=1),
    Probe("a reset while it answers", (b"<JS",), GETTER_S, gap_s=0.003, reset_after=1),
    Probe("a getter after a long idle", (b"<VI",), GETTER_S, idle_s=3.0),
    probe("factory settings after the resets", b">JS$HP"),
    Probe(
        "a burst of 6 angles after a long idle", (b"$AN0a064" * 6 + b"<VI" * 8,), 0.3, idle_s=2.0
    ),
    # last: what the ring lets through of its end may leave half a command in the parser
    Probe(
        "a burst of 8 angles after a long idle", (b"$AN0a064" * 8 + b"<VI" * 8,), 0.3, idle_s=2.0
    ),
)
"""The board's life: resets with a motion playing, inside a command and inside a reply (what
it keeps in EEPROM stays, nothing else does), and seconds left alone, then a getter or a
burst past its receive ring."""

PROBES = (
    DRIVER_PROBES
    + ERROR_PROBES
    + OUTSIDE_TABLE_PROBES
    + ARGUMENT_PROBES
    + EDGE_PROBES
    + SLOT_PROBES
    + TIMING_PROBES
    + LIFE_PROBES
)
