"""The simulated MIRTO board pinned to the ASIP V1.1 firmware (``michaelmargolis/ASIP-V1.1``).

Every test sends byte literals to the simulated board and compares the bytes it answers with
what the firmware's own code does with them (``asip.cpp`` ``asipClass::service``, each
service's ``processRequestMsg``, and the Teensy 3 core's ``Stream``), so the host driver and
the simulator cannot agree on something the real board does not do. The docstrings say what
the firmware does, in our words; ``docs/robots/mirto.md`` says how each fact was checked.
"""

from __future__ import annotations

from roboscript.codec import Role, drain
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.sim.simulation import Simulation, make_simulation

PY_ASIP_STREAM = (
    b"I,M\n I,A,0\n M,A,1M,A,1R,A,25R,A,25R,A,25B,A,25B,A,25D,A,25M,m,1,50M,m,0,-50"
    b"M,R,30,30,1000\n M,c,20,2000\n L,W,0,hi\n M,E,"
)
"""What python-asip-client 1.0.9's TCPMirtoRobot writes at start-up: most requests have no
newline (``../shared/reference/protocols.md``, section 1.8)."""


class Board:
    """The simulated MIRTO, fed bytes, on a clock stepped 10 ms at a time."""

    def __init__(self) -> None:
        self.sim: Simulation = make_simulation("mirto", "empty", seed=1)
        self.now = 0.0
        self.sim.connect()
        self.lines()  # the greeting

    def run(self, seconds: float) -> None:
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.now = round(self.now + 0.01, 6)
            self.sim.tick(self.now, 0.01)

    def send(self, data: bytes) -> None:
        self.sim.write(data)

    def raw(self) -> bytes:
        return self.sim.read(self.sim.in_waiting)

    def lines(self) -> list[str]:
        return [line for line in self.raw().decode("latin-1").split("\n") if line]

    @property
    def state(self) -> object:
        return self.sim.device.state  # type: ignore[attr-defined]


def quiet_board() -> Board:
    """A board with its 50 ms analog stream off and encoder events on (every 33 ms)."""
    board = Board()
    board.send(b"I,A,0\nM,A,1\n")
    board.run(0.1)
    board.lines()
    return board


# ------------------------------------------------------------------------------------------
# Parse waits


def test_a_number_without_terminator_stops_the_board_for_a_second() -> None:
    """``parseInt`` peeks for the byte after the last digit and waits up to 1000 ms for it.
    The firmware's loop is inside that call, so in that second it sends no event and runs
    no PID frame; the tone starts when the wait gives up, and events resume."""
    board = quiet_board()
    board.send(b"T,P,440,250")
    board.run(0.95)
    assert board.raw() == b""
    assert board.sim.log.tones == []
    board.run(0.1)
    assert [(f, d) for _, f, d in board.sim.log.tones] == [(440.0, 0.25)]
    board.run(0.1)
    assert any(line.startswith("@M,e,2,{") for line in board.lines())


def test_each_timed_read_waits_its_own_second() -> None:
    """``M,m,1`` reads the motor number, waits 1 s for the byte after it, then ``parseInt``
    for the power skips to a digit and waits another second: two seconds of silence, then
    the motor gets power 0."""
    board = quiet_board()
    board.send(b"M,m,1")
    board.run(1.9)
    assert board.raw() == b""
    board.run(0.2)
    assert board.lines()[0].startswith("@M,e,2,{")


def test_the_pid_does_not_run_while_the_board_waits() -> None:
    """The motor service's PID runs from the same loop as events: while ``parseInt`` waits,
    the wheel power the PID set last stays as it is, however far the speed is off."""
    board = quiet_board()
    board.send(b"M,R,60,60,5000\n")
    board.run(0.1)
    wheel = board.state.wheels[0]  # type: ignore[attr-defined]
    board.send(b"I,A,5")
    held = wheel.pwm
    for _ in range(9):
        board.run(0.1)
        assert wheel.pwm == held
    board.run(0.3)
    assert wheel.pwm != held


def test_a_byte_arriving_during_the_wait_continues_the_request() -> None:
    """A wait ends as soon as its byte arrives: ``B,A,2`` then ``0`` then a newline is one
    request for a 20 ms interval, not a 2 ms one."""
    board = Board()
    board.send(b"B,A,2")
    board.run(0.5)
    board.send(b"0\n")
    board.run(0.2)
    bumps = [line for line in board.lines() if line.startswith("@B,e,")]
    assert 9 <= len(bumps) <= 11  # every 20 ms over 200 ms


# ------------------------------------------------------------------------------------------
# Unknown services and what a request leaves unread


def test_an_unknown_service_is_answered_at_once_and_a_later_request_is_served() -> None:
    """The service loop answers a letter it does not run with ``INVALID_SERVICE`` straight
    away, then drops only the bytes already received up to a newline: it never waits for
    the newline, so the next request is read normally."""
    board = quiet_board()
    board.send(b"X,?,junk")
    assert board.lines() == ["~X,?,1{INVALID_SERVICE}"]
    board.send(b"#,?\n")
    assert board.lines() == ["@#,?,1,1,ATmega328P,20,Mirtle2017"]


def test_a_known_service_without_its_comma_is_an_invalid_service() -> None:
    """The loop finds the letter, reads one byte, and when that byte is not ``,`` it goes on
    looking and reports the letter as an invalid service."""
    board = quiet_board()
    board.send(b"T;P,440,250\n#,?\n")
    assert board.lines() == ["~T,?,1{INVALID_SERVICE}", "@#,?,1,1,ATmega328P,20,Mirtle2017"]


def test_a_leftover_number_is_answered_as_a_service_named_comma() -> None:
    """``S,W`` on a servo the sketch lacks is refused before the angle is read; the
    ``,45`` left over starts the next request, whose service byte is ``,``."""
    board = quiet_board()
    board.send(b"S,W,5,45\n")
    assert board.raw() == b"~S,W,7{INVALID_DEVICE_NUMBER}\n~,,?,1{INVALID_SERVICE}\n"
    board.send(b",45\n")
    assert board.raw() == b"~,,?,1{INVALID_SERVICE}\n"


def test_the_host_codec_reads_every_error_line_the_firmware_sends() -> None:
    """``sendErrorMessage`` writes the service and tag bytes it was given, whatever they
    are: a comma, a byte over 127, or a newline (``I,`` then a newline as the tag)."""
    host = AsipCodec(Role.HOST)
    host.receive_data(
        b"~,,?,1{INVALID_SERVICE}\n~\xff,?,1{INVALID_SERVICE}\n~I,\n,2{UNKNOWN_REQUEST}\n"
        b"~A,M,9{I2C NOT ENABLED}\n~S,W,8{DEVICE_NOT_AVAILABLE}\n"
    )
    assert list(drain(host)) == [
        m.ErrorReply(",", "?", 1, "INVALID_SERVICE"),
        m.ErrorReply("\xff", "?", 1, "INVALID_SERVICE"),
        m.ErrorReply("I", "\n", 2, "UNKNOWN_REQUEST"),
        m.ErrorReply("A", "M", 9, "I2C NOT ENABLED"),
        m.ErrorReply("S", "W", 8, "DEVICE_NOT_AVAILABLE"),
    ]


def test_an_unknown_io_tag_after_a_newline_is_echoed_with_the_newline() -> None:
    """The IO service reads its tag with a plain ``read()``: ``I,`` then a newline makes
    the newline the tag, echoed in the error line."""
    board = quiet_board()
    board.send(b"I,\nM,A,0\n")
    assert board.raw() == b"~I,\n,2{UNKNOWN_REQUEST}\n"


# ------------------------------------------------------------------------------------------
# IO


def test_analog_write_on_a_pwm_pin_of_another_service_is_wrong_mode() -> None:
    """``AnalogWrite``: a pin that cannot do PWM is ``INVALID_PIN`` (3); a PWM pin that is
    reserved or owned by another service (pin 3 drives a motor) is ``WRONG_MODE`` (6)."""
    board = quiet_board()
    board.send(b"I,a,3,128\nI,a,18,128\n")
    assert board.lines() == ["~I,a,6{WRONG_MODE}", "~I,a,3{INVALID_PIN}"]


def test_a_pullup_input_reports_only_ports_with_a_report_mask() -> None:
    """After ``I,P`` with mode 1 or 2, ``sendDigitalPortChanges`` reports every port whose
    report mask is not zero; here only bump pin 9's port (2, bit 1, pulled up), reported before
    the pin, which the bump service owns, is refused."""
    board = quiet_board()
    board.send(b"I,P,9,2\n")
    assert board.raw() == b"@I,d,2,2\n~I,P,4{MODE_UNAVAILABLE}\n"


# ------------------------------------------------------------------------------------------
# Pixels and the LCD


def test_a_pixel_sequence_without_its_brace_drops_the_next_line() -> None:
    """``P,S`` reads strip, count and first pixel, then needs ``,{`` from two plain reads.
    Here the newline is read instead, and the service's final skip drops the received
    bytes up to the next newline: exactly the following line (``M,A,1``) is lost."""
    board = Board()
    board.send(b"I,A,0\nP,S,0,1,0\nM,A,1\nI,m\n")
    assert board.lines() == ["@I,m,6,{14:0,15:1,16:2,17:3,18:4,19:5}"]
    board.run(0.2)
    assert board.lines() == []  # encoder events were never turned on


def test_a_bare_pixel_show_reads_the_next_line_as_its_numbers() -> None:
    """java-asip's ``P,S,0`` has no count: ``parseInt`` skips the newline and the next
    line's letters, so ``M,M,30,30`` becomes count and first pixel (the motors do not
    move), and the line after it is dropped by the skip."""
    board = Board()
    board.send(b"I,A,0\nP,S,0\nM,M,30,30\nM,A,1\nI,m\n")
    assert board.lines() == ["@I,m,6,{14:0,15:1,16:2,17:3,18:4,19:5}"]
    assert board.sim.body.power == [0.0, 0.0]


def test_the_lcd_keeps_twenty_characters_and_reads_the_rest_as_requests() -> None:
    """``L,W`` reads at most 20 characters into its 21-byte row (``readBytesUntil`` keeps
    one byte for the NUL); the 21st starts a new request."""
    board = quiet_board()
    board.send(b"L,W,0,ABCDEFGHIJKLMNOPQRSTV,?\n")
    assert board.lines() == ["~V,?,1{INVALID_SERVICE}"]
    assert board.state.lcd_rows[0] == "ABCDEFGHIJKLMNOPQRST"  # type: ignore[attr-defined]


def test_the_sketch_has_one_servo_and_nine_pixels() -> None:
    """``mirtle2017`` declares ``NBR_SERVOS = 1`` and ``MAX_PIXELS = 9``."""
    board = quiet_board()
    board.send(b"P,I,0\nS,W,0,45\nS,W,1\n")
    assert board.lines() == ["@P,I,0,9", "~S,W,7{INVALID_DEVICE_NUMBER}"]
    assert board.state.servos_deg == [45]  # type: ignore[attr-defined]


# ------------------------------------------------------------------------------------------
# python-asip-client


def test_python_asip_client_requests_without_newlines_take_effect() -> None:
    """Its requests run together (``M,A,1M,A,1R,A,25...``): the firmware splits them at
    the first non-digit after each number, and the trailing ``M,E,`` completes when its
    wait gives up."""
    board = Board()
    board.send(PY_ASIP_STREAM)
    assert board.lines()[0].startswith("@I,M,20,{")
    state = board.state
    assert state.encoder_events  # type: ignore[attr-defined]
    assert state.auto["R"].interval_ms == state.auto["B"].interval_ms == 25  # type: ignore[attr-defined]
    assert board.sim.log.display == "hi"
    assert board.sim.device.codec.waiting  # type: ignore[attr-defined]
    board.run(1.05)
    assert not board.sim.device.codec.waiting  # type: ignore[attr-defined]
    assert any(line.startswith("@R,e,3,{") for line in board.lines())
