"""The simulated MIRTO board, driven through raw ASIP bytes as the firmware would be."""

from __future__ import annotations

import dataclasses

import pytest

from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation, make_simulation
from roboscript.sim.world import load_world


class Board:
    """A simulated board plus a clock, speaking bytes."""

    def __init__(self, robot: str = "mirto", world: str = "empty", *, uart: bool = False) -> None:
        self.sim: Simulation = make_simulation(robot, world, seed=1)
        if uart:  # a 328P board: the firmware sees each byte as it arrives
            profile = get_profile(robot)
            uart_profile = dataclasses.replace(
                profile, options={**profile.options, "transport": "uart"}
            )
            self.sim = Simulation(load_world(world), uart_profile, seed=1)
        self.now = 0.0
        self.sim.connect()

    def run(self, seconds: float) -> None:
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.now = round(self.now + 0.01, 6)
            self.sim.tick(self.now, 0.01)

    def send(self, data: bytes) -> None:
        self.sim.write(data)

    def lines(self) -> list[str]:
        text = self.sim.read(self.sim.in_waiting).decode("latin-1")
        return [line for line in text.split("\n") if line]


def quiet_board(*, uart: bool) -> Board:
    """A board with its analog stream off and its greeting read (a UART board waits while it
    writes the greeting: 60 ms)."""
    board = Board(uart=uart)
    board.send(b"I,A,0\n")
    board.run(0.1)
    board.lines()
    return board


def test_greeting_has_the_startup_line_modes_map_and_unprefixed_lines() -> None:
    board = Board()
    lines = board.lines()
    # mirtle2017's setup(): the banner lists services[] in order, then one line per entry
    assert lines[0] == "!Mirtle2017 running on ATmega328P with Services: I M B R T S D L P "
    assert lines[1] == "@I,p,20,{6,6,7,7,7,7,7,7,7,7,7,7,7,7,7,7,7,7,6,6}"
    assert lines[2].startswith("@I,M,20,{4:1,4:2,4:4,4:8,4:10,4:20,4:40,4:80,2:1,")
    assert lines[3:] == [
        f"{name} is service {service}\r"
        for name, service in [
            ("ASIP core IO", "I"),
            ("Motors", "M"),
            ("Bump Sensors", "B"),
            ("IR Sensors", "R"),
            ("Tone", "T"),
            ("Servos", "S"),
            ("Distance", "D"),
            ("LCD", "L"),
            ("Pixels", "P"),
        ]
    ]


def test_no_analog_stream_when_every_analog_pin_belongs_to_a_service() -> None:
    # IR 14-17, and the LCD's 18-19: asipIO.begin() finds no free analog pin to report
    board = Board()
    board.lines()
    board.run(1.0)
    assert not [line for line in board.lines() if line.startswith("@I,a")]


def test_encoder_events_every_33_ms_only_when_enabled() -> None:
    board = Board()
    board.send(b"I,A,0\n")
    board.run(0.5)
    assert not [x for x in board.lines() if x.startswith("@M,e")]
    board.send(b"M,A,1\n")
    board.run(0.99)
    events = [x for x in board.lines() if x.startswith("@M,e")]
    assert len(events) == 30
    assert events[0] == "@M,e,2,{0:0,0:0}"


def test_firmware_pid_holds_rpm_and_stops_after_the_duration() -> None:
    board = Board()
    board.send(b"I,A,0\nM,A,1\nM,R,40,40,1500\n")
    board.run(1.2)
    events = [x for x in board.lines() if x.startswith("@M,e")]
    delta = int(events[-1].split("{")[1].split(":")[0])
    target = 40 * 1632 / 60 * 0.033  # ticks per 33 ms frame at 40 rpm
    assert delta == pytest.approx(target, rel=0.15)
    board.run(1.0)
    board.lines()
    board.run(0.5)
    still = [x for x in board.lines() if x.startswith("@M,e")]
    assert all(x.startswith("@M,e,2,{0:") for x in still[-3:])


def test_pid_stops_after_two_seconds_without_an_encoder_pulse() -> None:
    board = Board(world="square-room")
    body = board.sim.body
    body.y_mm = 1000.0 - 101.0  # nose at the north wall: the wheels cannot turn
    board.send(b"I,A,0\nM,R,40,40,10000\n")
    board.run(1.0)
    assert board.sim.device.state.wheels[0].pid_active  # type: ignore[attr-defined]
    board.run(1.5)
    assert not board.sim.device.state.wheels[0].pid_active  # type: ignore[attr-defined]
    assert body.power == [0.0, 0.0]


def test_board_without_pid_refuses_the_pid_tags() -> None:
    board = Board("asip-basic")
    board.lines()
    board.send(b"M,R,30,30,1000\nM,r,0,30,1000\nM,c,10,1000\nM,a,90,90\n")
    assert board.lines() == [
        "~M,R,2{UNKNOWN_REQUEST}",
        "~M,r,2{UNKNOWN_REQUEST}",
        "~M,c,2{UNKNOWN_REQUEST}",
        "~M,a,2{UNKNOWN_REQUEST}",
    ]


@pytest.mark.parametrize(
    ("request_bytes", "reply"),
    [
        (b"X,?\n", "~X,?,1{INVALID_SERVICE}"),
        (b"X,W,0,90\n", "~X,?,1{INVALID_SERVICE}"),  # the rest of the line is skipped
        (b"S,W,5\n", "~S,W,7{INVALID_DEVICE_NUMBER}"),  # mirtle2017 has servo 0 only
        (b"P,I,0\n", "@P,I,0,9"),  # and nine pixels
        (b"P,B,3,10\n", "~P,B,7{INVALID_DEVICE_NUMBER}"),
        (b"M,z,1,2\n", "~M,z,2{UNKNOWN_REQUEST}"),
        (b"#,Q\n", "~#,Q,2{UNKNOWN_REQUEST}"),
        (b"I,P,0,1\n", "~I,P,4{MODE_UNAVAILABLE}"),
        (b"I,P,9,5\n", "~I,P,4{MODE_UNAVAILABLE}"),  # a bump pin
        (b"I,P,13,5\n", "~I,P,5{INVALID_MODE}"),  # 13 cannot do PWM
        (b"I,d,18,1\n", "~I,d,6{WRONG_MODE}"),
        (b"I,a,18,100\n", "~I,a,3{INVALID_PIN}"),
        (b"I,a,3,100\n", "~I,a,6{WRONG_MODE}"),  # a PWM pin the motor service owns
        (b"I,d,30,1\n", "~I,d,3{INVALID_PIN}"),
        (b"I,P,30,1\n", "~I,P,5{INVALID_MODE}"),  # no such pin: no mode fits it
        (b"#,?\n", "@#,?,1,1,ATmega328P,20,Mirtle2017"),
        (
            b"#,N\n",
            (
                "@#,N,9,{I:ASIP core IO,M:Motors,B:Bump Sensors,R:IR Sensors,T:Tone,S:Servos,"
                "D:Distance,L:LCD,P:Pixels}"
            ),
        ),
        (b"I,m\n", "@I,m,6,{14:0,15:1,16:2,17:3,18:4,19:5}"),
        (b"D,M\n", "@D,e,2,{0,0}"),  # front and right sensors; 0 = no echo
    ],
)
def test_replies_and_errors_match_the_firmware(request_bytes: bytes, reply: str) -> None:
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(request_bytes)
    assert board.lines() == [reply]


def test_tone_and_lcd_ignore_unknown_tags_silently() -> None:
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(b"T,Z\nL,Z\n")
    assert board.lines() == []


def test_a_motor_id_past_the_wheels_and_an_lcd_row_before_the_first_get_no_answer() -> None:
    # the firmware keeps a motor id in a byte (-1 is 255, 256 is 0) and lets a negative LCD
    # row through `line < nbrTextLines`; it answers none of them (firmware tier probes)
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(b"M,m,-1,50\nM,r,300,30,100\nM,s,-1,0\nM,r,0,2000,100\nL,W,-1,hi\nL,w,-1,2,hi\n")
    board.send(b"L,w,2,-1,hi\n#,?\n")
    assert board.lines() == ["@#,?,1,1,ATmega328P,20,Mirtle2017"]
    board.send(b"M,m,256,50\n")  # motor 0
    board.run(0.2)
    assert board.lines() == []
    assert board.sim.device.state.wheels[0].pwm != 0  # type: ignore[attr-defined]


def test_the_mirto_sketch_reads_no_debug_echo_and_no_wifi_settings() -> None:
    # mirtle2017 is a V1.1 build without ASIP_DEBUG: `!` is taken alone and the rest of the
    # line read as requests; `$` is an unknown service (firmware tier probes)
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(b"!hello\n$$,net,pw\n#,?\n")
    assert board.lines() == [
        "~h,?,1{INVALID_SERVICE}",
        "~$,?,1{INVALID_SERVICE}",
        "@#,?,1,1,ATmega328P,20,Mirtle2017",
    ]


def test_pullup_input_reports_its_port_at_once_then_on_changes_only() -> None:
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(b"I,P,9,2\n")  # a bump pin, pulled up: reported, then refused
    assert board.lines() == ["@I,d,2,2", "~I,P,4{MODE_UNAVAILABLE}"]
    board.run(0.5)
    assert board.lines() == []
    board.send(b"I,P,10,1\n")  # a second input on the port: the port again, with both pins
    assert board.lines() == ["@I,d,2,6", "~I,P,4{MODE_UNAVAILABLE}"]


def test_a_refused_input_request_on_a_bump_pin_still_reports_the_bumper() -> None:
    # PinMode sets the report mask before registering the pin, so the refusal comes after
    # the port report, and the bumper's level changes are reported from then on.
    board = Board()
    board.send(b"I,A,0\n")
    board.lines()
    board.send(b"I,P,9,1\n")
    assert board.lines() == ["@I,d,2,2", "~I,P,4{MODE_UNAVAILABLE}"]
    board.sim.body.bumpers_pressed = lambda: (True, False)  # type: ignore[method-assign]
    board.run(0.05)
    assert board.lines() == ["@I,d,2,0"]  # once, on the change


@pytest.mark.parametrize("uart", [False, True], ids=["usb", "uart"])
def test_request_without_newline_completes_after_the_parse_timeout(uart: bool) -> None:
    board = Board(uart=uart)
    board.run(0.1)
    board.send(b"T,P,440,250")
    board.run(0.5)
    assert board.sim.log.tones == []
    board.run(0.6)
    [(started_s, frequency_hz, duration_s)] = board.sim.log.tones
    assert (frequency_hz, duration_s) == (440.0, 0.25)
    # a second after the last byte arrived (on a UART, 11 byte times after the write)
    last_byte_s = 0.1 + (11 * 10 / 57600 if uart else 0.0)
    assert started_s == pytest.approx(last_byte_s + 1.0, abs=0.005)


def test_restart_zeroes_every_auto_report() -> None:
    board = Board()
    board.send(b"M,A,1\nB,A,20\n")
    board.run(0.2)
    board.send(b"#,R\n")
    board.lines()
    board.run(0.5)
    assert board.lines() == []


def test_distance_is_reported_in_cm_towards_a_wall() -> None:
    sim = Simulation(load_world("square-room"), get_profile("mirto"), seed=1)
    sim.connect()
    sim.write(b"D,M\n")
    text = sim.read(sim.in_waiting).decode()
    front, right = text.strip().splitlines()[-1].split("{")[1].rstrip("}").split(",")
    reading = int(front)
    # centre of a 2 m room, sensor 90 mm ahead of the centre: about 91 cm to the wall
    assert 88 <= reading <= 93
    assert 88 <= int(right) <= 93  # the right sensor sits 80 mm right of the centre


def test_servo_and_pixel_requests_change_the_boards_state() -> None:
    board = Board()
    board.send(b"S,W,0,45\nP,P,0,2,{0:16711680,7:255}\nP,p,0,1,{3:1:2:3}\nP,B,0,200\n")
    state = board.sim.device.state  # type: ignore[attr-defined]
    assert state.servos_deg == [45]
    assert state.pixels[0] == (255, 0, 0) and state.pixels[7] == (0, 0, 255)
    assert state.pixels[3] == (1, 2, 3) and state.brightness == 200
    board.send(b"P,C,0\n")
    assert state.pixels == [(0, 0, 0)] * 9


@pytest.mark.parametrize(
    ("uart", "answer", "pixel"),
    [
        # asipPixels.cpp reads ",{" with plain read()s right after parseInt(): on a UART the
        # "{" has not arrived yet, so the request is dropped and its tail parses as garbage
        (True, ["~{,?,1{INVALID_SERVICE}"], (0, 0, 0)),
        (False, [], (0, 0, 255)),  # over USB the line is there at once
    ],
    ids=["uart-drops-it", "usb-reads-it"],
)
def test_a_pixel_request_on_a_uart_and_on_a_usb_board(
    uart: bool, answer: list[str], pixel: tuple[int, int, int]
) -> None:
    board = quiet_board(uart=uart)
    board.send(b"P,P,0,1,{0:255}\n")
    board.run(0.05)  # a UART carries the 16 bytes in 2.8 ms
    assert board.lines()[: len(answer) or None] == answer
    assert board.sim.device.state.pixels[0] == pixel  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("uart", "answer"),
    [
        # asip.cpp writes the error, then skips what has arrived by then: one byte more than
        # it had when it began, so the rest comes back as new requests (as on the emulated
        # firmware, tests/firmware)
        (True, ["~X,?,1{INVALID_SERVICE}", *(f"~{c},?,1{{INVALID_SERVICE}}" for c in "din")]),
        (False, ["~X,?,1{INVALID_SERVICE}"]),  # over USB the whole line has arrived
    ],
    ids=["uart", "usb"],
)
def test_an_unknown_service_skips_what_has_arrived_once_its_error_is_written(
    uart: bool, answer: list[str]
) -> None:
    board = quiet_board(uart=uart)
    board.send(b"X,abcdefghijklmnop\n")
    board.run(0.05)
    assert board.lines() == answer


def test_a_uart_board_reads_a_pixel_request_whole_when_it_arrives_while_the_board_writes() -> None:
    board = quiet_board(uart=True)
    # the service names fill the transmit buffer: the board writes for 6 ms, and the pixel
    # request (3.5 ms of line time) is all there when it reads it
    board.send(b"#,N\nP,P,0,1,{0:255}\n")
    board.run(0.05)
    assert board.lines()[0].startswith("@#,N,9,{I:ASIP core IO,")
    assert board.sim.device.state.pixels[0] == (0, 0, 255)  # type: ignore[attr-defined]


def test_a_uart_board_answers_once_the_request_has_crossed_the_line() -> None:
    board = Board(uart=True)
    board.run(0.1)
    board.lines()
    board.send(b"#,?\n")
    assert board.lines() == []  # the bytes are still on the line
    board.run(0.01)
    assert board.lines() == ["@#,?,1,1,ATmega328P,20,Mirtle2017"]


def test_a_uart_board_loses_what_arrives_while_its_receive_buffer_is_full() -> None:
    board = quiet_board(uart=True)
    # three long replies keep the board writing for 40 ms: 63 bytes of the 100 behind them
    # fit its receive buffer, the rest are lost (each answer keeps it writing a while longer)
    board.send(b"#,N\n#,N\n#,N\n" + b"#,?\n" * 25)
    board.run(0.2)
    lines = board.lines()
    assert [line for line in lines if line.startswith("@#,N")] == [lines[0]] * 3
    answered = [line for line in lines if line.startswith("@#,?")]
    assert 0 < len(answered) < 25
    assert len(lines) == 3 + len(answered)  # whole requests only: no leftovers answered


def test_a_uart_board_reads_a_request_after_quiet_steps_that_followed_an_unknown_service() -> None:
    # The board answers "X" and skips the rest of its line at its next read; the quiet steps
    # that follow (nothing on the line, nothing to read) must not carry a skip over onto the
    # next request.
    board = quiet_board(uart=True)
    board.send(b"X,?\n")
    board.run(0.2)
    assert board.lines() == ["~X,?,1{INVALID_SERVICE}"]
    board.send(b"#,?\n")
    board.run(0.05)
    assert board.lines() == ["@#,?,1,1,ATmega328P,20,Mirtle2017"]


def _bump_events(board: Board, seconds: float) -> int:
    board.run(seconds)
    return sum(line.startswith("@B,e") for line in board.lines())


def test_an_auto_event_interval_is_an_unsigned_16_bit_int_as_on_the_board() -> None:
    board = quiet_board(uart=True)
    board.send(b"B,A,65586\n")  # 65586 is 50 in 16 bits
    # read once its 10 bytes have crossed the line: the first at 51 ms, the last at 951 ms
    assert _bump_events(board, 1.0) == 19


@pytest.mark.parametrize(
    ("uart", "events"),
    # a 328P's unsigned int keeps 65586's low 16 bits, 50; a Teensy 3.1's all 32
    [(True, 19), (False, 0)],
    ids=["uart-328p-16-bits", "usb-teensy-32-bits"],
)
def test_an_auto_event_interval_is_the_boards_unsigned_int(uart: bool, events: int) -> None:
    board = quiet_board(uart=uart)
    board.send(b"B,A,65586\n")
    assert _bump_events(board, 1.0) == events


@pytest.mark.parametrize(
    ("uart", "sent", "state"),
    [
        # int 16 bits: 65536 is 0, 65537 is 1
        (True, b"M,A,1\nM,A,65536\n", ("encoder events", False)),
        (True, b"S,W,65536,45\n", ("servo", 45)),
        (True, b"L,W,65537,hi\n", ("row 1", "hi")),
        # int 32 bits: each number is itself
        (False, b"M,A,1\nM,A,65536\n", ("encoder events", True)),
        (False, b"S,W,65536,45\n", ("servo", 90)),
        (False, b"L,W,65537,hi\n", ("row 1", "")),
    ],
    ids=[
        "uart-encoders-off",
        "uart-servo-0",
        "uart-row-1",
        "usb-encoders-on",
        "usb-no-servo-65536",
        "usb-no-row-65537",
    ],
)
def test_a_request_number_is_kept_in_the_boards_int(
    uart: bool, sent: bytes, state: tuple[str, object]
) -> None:
    board = quiet_board(uart=uart)
    device = board.sim.device
    board.send(sent)
    board.run(0.05)
    held = {
        "encoder events": device.state.encoder_events,  # type: ignore[attr-defined]
        "servo": device.state.servos_deg[0],  # type: ignore[attr-defined]
        "row 1": device.state.lcd_rows[1],  # type: ignore[attr-defined]
    }
    assert (state[0], held[state[0]]) == state


@pytest.mark.parametrize("uart", [False, True], ids=["usb", "uart"])
def test_a_servo_id_is_written_as_its_low_byte(uart: bool) -> None:
    # asipServos: `servoId > nbrElements-1` lets a negative id through, and write(byte
    # servoId, ...) keeps its low byte: -256 is servo 0, -255 servo 1 (not on this sketch)
    board = quiet_board(uart=uart)
    board.send(b"S,W,-255,30\n")
    board.run(0.05)
    assert board.sim.device.state.servos_deg == [90]  # type: ignore[attr-defined]
    board.send(b"S,W,-256,45\n")
    board.run(0.05)
    assert board.lines() == []
    assert board.sim.device.state.servos_deg == [45]  # type: ignore[attr-defined]


@pytest.mark.parametrize(
    ("uart", "sent", "tone_s"),
    [
        # asipTone keeps the duration in an int: past 32767 ms it is negative on a 328P,
        # and `duration > 0` fails: no tone; 65636 is 100
        (True, b"T,P,440,40000\n", None),
        (True, b"T,P,440,65636\n", 0.1),
        (False, b"T,P,440,40000\n", 40.0),
        (False, b"T,P,440,65636\n", 65.636),
    ],
    ids=["uart-40-s-plays-nothing", "uart-65.636-s-is-0.1", "usb-40-s", "usb-65.636-s"],
)
def test_a_tones_duration_is_the_boards_int(uart: bool, sent: bytes, tone_s: float | None) -> None:
    board = quiet_board(uart=uart)
    board.send(sent)
    board.run(0.05)
    tones = [duration_s for _, _, duration_s in board.sim.log.tones]
    assert tones == ([] if tone_s is None else [pytest.approx(tone_s)])


def test_the_32_bit_tick_of_a_usb_board_does_not_wrap_at_65536_ms() -> None:
    board = quiet_board(uart=False)
    board.send(b"B,A,50\n")
    board.run(65.45 - board.now)
    board.lines()
    # a 328P bursts here (its 16-bit due tick wraps); a Teensy's 32-bit one goes on
    assert _bump_events(board, 0.15) == 3
    assert _bump_events(board, 1.0) == 20


def test_a_negative_interval_reports_on_every_turn_of_the_loop_at_the_lines_pace() -> None:
    board = quiet_board(uart=True)
    board.send(b"B,A,-5\n")  # 65531: the next due tick is 5 ms before the tick now
    events = _bump_events(board, 1.0)
    event_bytes = len(b"@B,e,2,{1,1}\n")
    # what the line carries in that second: the 328P's USART asked for 57600 baud sends at
    # 58824 (UBRR 16 at 16 MHz), 5882 bytes a second
    line_bytes = 5882
    assert abs(events * event_bytes - line_bytes) <= 64 + event_bytes  # (its buffer, a partial)


def test_an_interval_under_the_physics_step_reports_at_its_own_pace() -> None:
    board = quiet_board(uart=True)
    board.send(b"B,A,3\n")
    # each turn that finds the due tick reached sets the next 3 ms on; millis() is counted
    # in Timer0's 1.024 ms overflows and skips a value every 42 of them, and a due tick
    # skipped over is found a tick late: 328 a second where 1000 / 3 would be 333 (the
    # emulated firmware: 327 by 0.999 s, 328 by 1.0 s)
    assert _bump_events(board, 0.999) == 328


def test_the_16_bit_tick_wraps_once_a_minute_into_a_burst_of_events() -> None:
    board = quiet_board(uart=True)
    board.run(65.49 - board.now)
    board.lines()
    # set in the last 50 ms before millis() passes 65536, the due tick wraps below the tick
    # now: the board reports on every turn of its loop, as fast as the line takes them,
    # until millis() wraps too (about 46 ms of 14-byte events at 170 us a byte)
    board.send(b"B,A,50\n")
    assert _bump_events(board, 0.045) >= 15
    board.run(0.01)
    board.lines()
    assert _bump_events(board, 1.0) == 20  # and then every 50 ms again


@pytest.mark.parametrize(
    ("uart", "answer", "row"),
    [
        # readBytesUntil(..., 21): the AVR core reads 21 characters, the Teensy 3 core 20;
        # strlcpy shows 20 either way, and the rest is read as new requests
        (True, "~v,?,1{INVALID_SERVICE}", "abcdefghijklmnopqrst"),
        (False, "~u,?,1{INVALID_SERVICE}", "abcdefghijklmnopqrst"),
    ],
    ids=["uart-avr-core-reads-21", "usb-teensy-core-reads-20"],
)
def test_a_long_lcd_row_is_read_as_the_boards_core_reads_it(
    uart: bool, answer: str, row: str
) -> None:
    board = quiet_board(uart=uart)
    board.send(b"L,W,2,abcdefghijklmnopqrstuvwxyz\n")
    board.run(0.05)
    assert board.lines() == [answer]
    assert board.sim.device.state.lcd_rows[2] == row  # type: ignore[attr-defined]


def test_an_encoder_pin_reads_its_pulled_up_lines_and_follows_the_wheel() -> None:
    # the Encoder library pulls its lines up: pin 7 (wheel 0's B line) reads high at rest;
    # I,P joins it to port 4's report mask even though the motor service owns it
    board = quiet_board(uart=True)
    board.send(b"I,P,7,1\n")
    board.run(0.05)
    assert board.lines() == ["@I,d,4,80", "~I,P,4{MODE_UNAVAILABLE}"]
    board.send(b"M,m,0,40\n")
    board.run(0.3)
    board.send(b"M,S,0\n")
    board.run(0.5)
    reports = [line for line in board.lines() if line.startswith("@I,d,4,")]
    ticks = board.sim.body.ticks[0]
    assert ticks > 8 and len(reports) >= 2  # the B line went low and high as the wheel turned
    # forward, (A, B) go (1, 1), (1, 0), (0, 0), (0, 1): B is high at ticks 0 and 3 (mod 4)
    assert reports[-1] == ("@I,d,4,80" if ticks % 4 in (0, 3) else "@I,d,4,0")


def test_a_uart_boards_reply_reaches_the_host_as_its_usart_sends_it() -> None:
    # the 104-byte #,N reply leaves the 328P's USART a byte every 170 us (58824 baud): about
    # half of it has gone after 10 ms, the rest waits in the board's transmit buffer
    board = quiet_board(uart=True)
    board.send(b"#,N\n")
    board.run(0.01)
    first = board.sim.read(board.sim.in_waiting)
    assert 45 <= len(first) <= 60
    board.run(0.02)
    reply = first + board.sim.read(board.sim.in_waiting)
    assert reply.startswith(b"@#,N,9,{I:ASIP core IO,") and reply.endswith(b"P:Pixels}\n")
