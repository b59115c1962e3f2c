"""The ASIP host driver on a scripted link: handshake, wheel setpoints, refusals, silence.

The link is a stand-in that records the messages the driver sends and hands it the board's
messages a test queues, so every test reads as the conversation a MIRTO board would have.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import pytest

from roboscript import capabilities as cap
from roboscript.clock import SimClock
from roboscript.codec import Role, readable
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.asip.driver import BOARD_RESTARTED, AsipDriver
from roboscript.errors import LinkClosedError, LinkError, LinkTimeoutError
from roboscript.profiles import RobotProfile, get_profile

ALL_SERVICES = (
    ("I", "IO"),
    ("M", "Motor"),
    ("B", "Bump"),
    ("R", "IR"),
    ("D", "Distance"),
    ("T", "Tone"),
    ("L", "LCD"),
    ("S", "Servo"),
    ("P", "Pixels"),
)
VERSION = m.VersionReply(1, 1, "ATmega328P", 20, "mirto")
DT = 0.02


class ScriptedLink:
    """What the driver needs of a Link: send, poll and the time of the last receipt."""

    def __init__(self, clock: SimClock) -> None:
        self.clock = clock
        self.sent: list[tuple[float, object]] = []
        self.inbox: list[object] = []
        self.last_receive_s: float | None = None
        self.broken = False

    def send(self, message: object) -> None:
        if self.broken:
            raise LinkError("the link is gone")
        self.sent.append((self.clock.now(), message))

    def poll(self) -> list[object]:
        if self.inbox:
            self.last_receive_s = self.clock.now()
        found, self.inbox = self.inbox, []
        return found

    def take(self) -> list[object]:
        """The messages sent since the last take."""
        found = [message for _, message in self.sent]
        self.sent.clear()
        return found


class Board:
    """A driver, its link and a clock, stepped tick by tick as the scheduler would."""

    def __init__(self, robot: str = "mirto", profile: RobotProfile | None = None) -> None:
        self.clock = SimClock()
        self.link = ScriptedLink(self.clock)
        self.profile = profile or get_profile(robot)
        self.driver = AsipDriver(self.link, self.profile, self.clock)  # type: ignore[arg-type]

    def tick(self, *incoming: object, dt: float = DT) -> list[object]:
        """Advance the clock, deliver ``incoming``, run sense and act; what went out."""
        self.clock.advance(dt)
        self.link.inbox.extend(incoming)
        self.driver.tick(self.clock.now(), dt)
        self.driver.flush(self.clock.now(), dt)
        return self.link.take()

    def connect(self, services: tuple[tuple[str, str], ...] = ALL_SERVICES) -> None:
        self.driver.start()
        self.tick(VERSION)
        self.tick(m.ServiceNamesReply(services))
        if any(service == "P" for service, _ in services):
            self.tick(m.PixelsInfoReply(0, 8))
        assert self.driver.ready
        self.link.take()

    def keep_talking(self, seconds: float, *, ticks: tuple[int, int] = (0, 0)) -> list[object]:
        """Tick for ``seconds`` with an encoder event each tick; everything sent."""
        sent: list[object] = []
        for _ in range(round(seconds / DT)):
            sent += self.tick(m.EncoderEvent(((ticks[0], 0), (ticks[1], 0))))
        return sent


def rpm(mm_s: float) -> int:
    return round(mm_s * 60.0 / (math.pi * get_profile("mirto").wheel_diameter_mm))


def test_the_version_probe_repeats_every_quarter_second_until_the_board_answers() -> None:
    board = Board()
    board.driver.start()
    probes = [board.link.take()]
    for _ in range(round(0.6 / DT)):
        probes.append(board.tick())
    times = [i * DT for i, sent in enumerate(probes) if m.VersionRequest() in sent]
    assert times == pytest.approx([0.0, 0.26, 0.52])  # the first tick at or after each 250 ms
    assert not board.driver.ready


def test_the_handshake_asks_for_services_then_turns_on_the_events_the_robot_needs() -> None:
    board = Board()
    board.driver.start()
    assert board.link.take() == [m.VersionRequest()]
    assert board.tick(VERSION) == [m.ServiceNamesRequest()]
    configured = board.tick(m.ServiceNamesReply(ALL_SERVICES))
    assert configured[:5] == [
        m.SetAutoEventInterval("I", 0),  # nobody reads the analog stream
        m.EnableEncoderEvents(True),
        m.SetAutoEventInterval("B", 50),
        m.SetAutoEventInterval("R", 50),
        m.SetAutoEventInterval("D", 100),
    ]
    assert m.StopMotors() in configured  # the wheels start stopped
    assert configured[-1] == m.PixelsInfoRequest(0)
    assert not board.driver.ready  # waits for the pixel strip's length
    board.tick(m.PixelsInfoReply(0, 8))
    assert board.driver.ready
    assert set(board.driver.capabilities()) == set(board.profile.capabilities)
    assert board.driver.describe() == "mirto on ATmega328P (ASIP 1.1)"


def test_a_startup_line_also_answers_the_probe() -> None:
    board = Board()
    board.driver.start()
    board.link.take()
    assert board.tick(m.StartupLine("mirto", "ATmega328P")) == [m.ServiceNamesRequest()]
    assert board.driver.describe() == "mirto on ATmega328P (ASIP)"


def test_a_missing_service_drops_its_capability_with_a_notice() -> None:
    board = Board()
    board.connect(tuple(s for s in ALL_SERVICES if s[0] not in "TP"))
    capabilities = board.driver.capabilities()
    assert cap.SPEAKER not in capabilities and cap.LEDS not in capabilities
    assert cap.DRIVE_BASE in capabilities
    assert "the board has no tone service: no speaker" in board.driver.notices
    assert "the board has no pixels service: no leds" in board.driver.notices


def test_a_pixel_strip_that_never_says_its_length_gives_no_leds_after_half_a_second() -> None:
    board = Board()
    board.driver.start()
    board.tick(VERSION)
    board.tick(m.ServiceNamesReply(ALL_SERVICES))
    board.keep_talking(0.48)
    assert not board.driver.ready
    board.keep_talking(0.04)
    assert board.driver.ready
    assert cap.LEDS not in board.driver.capabilities()
    assert "the board's pixel strip did not say how long it is: no leds" in board.driver.notices


def test_firmware_pid_gets_one_rpm_request_refreshed_every_two_seconds() -> None:
    board = Board()
    board.connect()
    board.driver.set_wheel_speeds(150.0, 150.0)
    first = board.tick()
    assert first == [m.SetMotorsRpm(rpm(150.0), rpm(150.0), 3000)]
    again = board.keep_talking(1.9)
    assert again == []  # the firmware restarts its PID on every M,R: send it only on change
    refreshed = board.keep_talking(0.2)
    assert refreshed == [m.SetMotorsRpm(rpm(150.0), rpm(150.0), 3000)]


def test_a_wheel_at_rpm_zero_is_stopped_by_itself() -> None:
    board = Board()
    board.connect()
    board.driver.set_wheel_speeds(0.0, 100.0)
    assert board.tick() == [m.StopMotor(0), m.SetMotorRpm(1, rpm(100.0), 3000)]


def test_stopping_the_wheels_sends_one_stop() -> None:
    board = Board()
    board.connect()
    board.driver.set_wheel_speeds(100.0, 100.0)
    board.tick()
    board.keep_talking(1.0)
    board.driver.set_wheel_speeds(0.0, 0.0)
    assert board.tick() == [m.StopMotors()]
    assert board.keep_talking(3.0) == []


def test_setpoints_that_change_every_tick_are_held_by_the_host_then_handed_back() -> None:
    board = Board()
    board.connect()
    sent: list[object] = []
    for i in range(10):  # steering: a new setpoint every tick
        board.driver.set_wheel_speeds(100.0 + i, 100.0 - i)
        sent += board.tick(m.EncoderEvent(((10, 0), (10, 0))))
    assert m.StopMotors() in sent  # power requests alone would not stop the firmware PID
    assert any(isinstance(x, m.SetMotorsPower) for x in sent)
    assert not any(isinstance(x, m.SetMotorsRpm) for x in sent[sent.index(m.StopMotors()) :])
    steady = board.keep_talking(0.6, ticks=(10, 10))
    handback = steady.index(m.SetMotorsPower(0, 0))
    assert steady[handback + 1] == m.SetMotorsRpm(rpm(109.0), rpm(91.0), 3000)


def test_a_board_without_motor_pid_switches_to_host_control_with_a_notice() -> None:
    board = Board()
    board.connect()
    board.driver.set_wheel_speeds(150.0, 150.0)
    board.tick()
    sent = board.tick(m.ErrorReply("M", "R", m.ErrorCode.UNKNOWN_REQUEST))
    assert board.driver.firmware_pid is False
    assert board.driver.device_errors == []  # not the student's action's failure
    assert any("no motor PID" in notice for notice in board.driver.notices)
    power = [x for x in sent if isinstance(x, m.SetMotorsPower)]
    assert power and power[-1].power0_pct > 0


def test_asip_basic_holds_speeds_with_power_from_the_start() -> None:
    board = Board("asip-basic")
    board.connect()
    board.driver.set_wheel_speeds(150.0, -150.0)
    sent = board.tick()
    assert [type(x) for x in sent] == [m.SetMotorsPower]
    power = sent[0]
    assert isinstance(power, m.SetMotorsPower)
    assert power.power0_pct > 0 > power.power1_pct


def test_a_refused_request_is_a_device_error_in_words() -> None:
    board = Board()
    board.connect()
    board.tick(m.ErrorReply("T", "P", m.ErrorCode.UNKNOWN_REQUEST))
    assert board.driver.take_device_error() == (
        "the board refused 'T,P': the service does not know that request"
    )
    assert board.driver.take_device_error() is None


def test_silence_for_over_a_second_is_a_link_timeout() -> None:
    board = Board()
    board.connect()
    board.keep_talking(0.5)
    for _ in range(round(0.98 / DT)):
        board.tick()  # quiet, but not yet for a second
    with pytest.raises(LinkTimeoutError, match="the robot stopped responding"):
        for _ in range(3):
            board.tick()


def test_a_board_that_greets_again_mid_run_ends_the_run_before_any_setpoint_goes_out() -> None:
    board = Board()
    board.connect()
    board.driver.set_wheel_speeds(100.0, 100.0)
    board.keep_talking(2.5)  # an rpm refresh is due now
    with pytest.raises(LinkClosedError) as raised:
        board.tick(m.StartupLine("Mirtle2017", "ATmega328P", ("I", "M")))
    assert str(raised.value) == BOARD_RESTARTED.format(after="2.6 s after connecting")
    assert board.driver.failure is raised.value  # the user's sentence, as it stands
    assert not any(isinstance(sent, m.SetMotorsRpm) for sent in board.link.take())
    board.driver.stop_all()  # on the way out: reaches the board that runs again
    assert board.link.take() == [m.StopMotors(), m.SetMotorsPower(0, 0)]


@pytest.mark.parametrize("line", [m.PinModesReply((6, 6)), m.PortMapReply(((4, 1),))])
def test_the_sketchs_other_start_up_lines_also_mean_it_restarted(line: object) -> None:
    board = Board()
    board.connect()
    with pytest.raises(LinkClosedError, match="the board restarted"):
        board.tick(line)


def test_a_board_that_restarts_during_the_handshake_is_asked_for_its_events_again() -> None:
    board = Board()
    board.driver.start()
    board.tick(VERSION)
    configured = board.tick(m.ServiceNamesReply(ALL_SERVICES))
    assert m.EnableEncoderEvents(True) in configured  # then it waits for the strip length
    again = board.tick(m.StartupLine("Mirtle2017", "ATmega328P"))
    assert m.EnableEncoderEvents(True) in again
    board.tick(m.PixelsInfoReply(0, 8))
    assert board.driver.ready


def test_the_greeting_before_the_events_were_asked_for_is_no_restart() -> None:
    board = Board()
    board.driver.start()
    board.tick(m.StartupLine("Mirtle2017", "ATmega328P"), m.PinModesReply((6,)))
    board.tick(m.PortMapReply(((4, 1),)), VERSION)
    board.tick(m.ServiceNamesReply(ALL_SERVICES))
    board.tick(m.PixelsInfoReply(0, 8))
    assert board.driver.ready


def test_encoder_totals_are_wheel_travel_in_millimetres() -> None:
    board = Board()
    board.connect()
    per_tick = math.pi * board.profile.wheel_diameter_mm / board.profile.ticks_per_rev
    board.tick(m.EncoderEvent(((16, board.profile.ticks_per_rev), (-8, -100))))
    left, right = board.driver.wheel_distances_mm()
    assert left == pytest.approx(math.pi * board.profile.wheel_diameter_mm)
    assert right == pytest.approx(-100 * per_tick)
    base: Any = board.driver.capabilities()[cap.DRIVE_BASE]
    assert base.wheel_distances_mm() == (left, right)


def test_a_400_digit_encoder_count_never_reaches_the_wheel_distances() -> None:
    # It used to: the count times mm per tick raised OverflowError out of the sense phase.
    board = Board()
    board.connect()
    host = AsipCodec(Role.HOST)
    huge = "9" * 400
    host.receive_data(f"@M,e,2,{{1:{huge},1:5}}\n@M,e,2,{{2:100,2:-100}}\n".encode())
    board.tick(*readable(host))
    left, right = board.driver.wheel_distances_mm()
    per_tick = math.pi * board.profile.wheel_diameter_mm / board.profile.ticks_per_rev
    assert (left, right) == pytest.approx((100 * per_tick, -100 * per_tick))
    assert host.stats.faults == {"out_of_range": 1}


def test_sensor_events_reach_the_capabilities() -> None:
    board = Board()
    board.connect()
    board.tick(m.DistanceEvent((42, 0)), m.IrEvent((10, 900, 20)))
    caps: dict[str, Any] = board.driver.capabilities()
    # the board truncates to whole centimetres: the middle of the centimetre is reported
    assert caps[cap.RANGE].distance_mm() == 425.0
    assert caps[cap.SIDE_RANGE].distance_mm() is None  # 0 cm is no echo
    assert caps[cap.LINE].values() == (10.0, 900.0, 20.0)


def test_tones_are_sent_in_the_act_phase_clamped_to_what_asip_carries() -> None:
    board = Board()
    board.connect()
    board.driver.queue_tone(440.4, 0.25)
    board.driver.queue_tone(100_000.0, 0.0001)
    assert board.tick() == [m.PlayTone(440, 250), m.PlayTone(65535, 1)]


def test_stop_all_sends_both_stops_and_never_raises() -> None:
    board = Board()
    board.connect()
    board.driver.stop_all()
    assert board.link.take() == [m.StopMotors(), m.SetMotorsPower(0, 0)]
    board.link.broken = True
    board.driver.stop_all()  # a lost link must not hide the real error


def test_a_leftover_of_the_padded_stop_is_a_notice_not_a_failed_action() -> None:
    # "~,,?,1{INVALID_SERVICE}": a board that reads M,S with no value found the ",0"
    # roboscript pads for V1.1's parser; the motors did stop.
    board = Board()
    board.connect()
    board.tick(m.ErrorReply(",", "?", m.ErrorCode.INVALID_SERVICE, "INVALID_SERVICE"))
    assert board.driver.take_device_error() is None
    assert any("'M,S' without a value" in text for text in board.driver.notices)


def test_an_error_with_a_digit_for_a_service_says_a_request_was_read_in_two() -> None:
    board = Board()
    board.connect()
    board.tick(m.ErrorReply("0", "?", m.ErrorCode.INVALID_SERVICE, "INVALID_SERVICE"))
    assert board.driver.take_device_error() == (
        "the board read the end of a request as a new one: a request carried more values "
        "than the board takes"
    )
    board.tick(m.ErrorReply("X", "?", m.ErrorCode.INVALID_SERVICE, "INVALID_SERVICE"))
    assert board.driver.take_device_error() == (
        "the board refused 'X,?': the sketch has no such service"
    )


def test_the_mirto_profile_has_the_sketchs_one_servo() -> None:
    board = Board()
    board.connect()
    assert board.driver.capabilities()[cap.SERVOS].count == 1  # type: ignore[attr-defined]


def test_display_rows_are_cut_to_the_profiles_width_never_sent_long() -> None:
    board = Board()
    board.connect()
    board.driver.capabilities()[cap.DISPLAY].show_text("x" * 45)  # type: ignore[attr-defined]
    rows = [msg for msg in board.link.take() if isinstance(msg, m.LcdWrite)]
    assert rows == [m.LcdWrite(0, "x" * 20), m.LcdWrite(1, "x" * 20), m.LcdWrite(2, "x" * 5)]


def test_servo_count_and_lcd_width_come_from_the_profile_options() -> None:
    import dataclasses

    mirto = get_profile("mirto")
    narrow = dataclasses.replace(mirto, options={"servo_count": 3, "lcd_columns": 16})
    board = Board()
    board.driver = AsipDriver(board.link, narrow, board.clock)  # type: ignore[arg-type]
    board.connect()
    assert board.driver.capabilities()[cap.SERVOS].count == 3  # type: ignore[attr-defined]
    board.driver.capabilities()[cap.DISPLAY].show_text("y" * 20)  # type: ignore[attr-defined]
    rows = [msg for msg in board.link.take() if isinstance(msg, m.LcdWrite)]
    assert rows == [m.LcdWrite(0, "y" * 16), m.LcdWrite(1, "y" * 4)]


def test_a_uart_board_offers_no_leds_and_says_why() -> None:
    mirto = get_profile("mirto")
    uart = dataclasses.replace(mirto, options={**mirto.options, "transport": "uart"})
    board = Board(profile=uart)
    board.connect()
    assert cap.LEDS not in board.driver.capabilities()
    assert any("a byte at a time" in text for text in board.driver.notices)
