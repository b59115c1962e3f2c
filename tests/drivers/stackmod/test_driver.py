"""The StackMod host driver against scripted modules at the far end of a real TCP socket."""

from __future__ import annotations

import select
import socket
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import replace
from types import SimpleNamespace
from typing import Any

import pytest
from serial.urlhandler import protocol_socket

from roboscript import capabilities as cap
from roboscript.clock import SimClock
from roboscript.codec import Role, drain
from roboscript.drivers.stackmod.codec import StackModCodec, seed_checksum
from roboscript.drivers.stackmod.driver import StackModDriver
from roboscript.drivers.stackmod.messages import Command, Get, Set
from roboscript.errors import DeviceError, LinkTimeoutError
from roboscript.profiles import get_profile
from roboscript.robot import Robot
from roboscript.scheduler import Scheduler
from roboscript.transport import Link, open_port

_WAIT_S = 5.0  # only a guard against a hung test: every wait ends as soon as bytes arrive


def pk(frame: bytes) -> bytes:
    """``frame`` (from ``{`` to ``}``) with its seed-rule checksum appended."""
    return frame + bytes([seed_checksum(frame)])


def text(message: Get | Set) -> str:
    """``M?ARM0`` or ``M$MTR1+025``: a request as a test names it."""
    action = "$" if isinstance(message, Set) else "?"
    head = f"{chr(message.address)}{action}{message.command.value}{message.selector}"
    if isinstance(message, Set) and message.command is Command.MTR:
        return f"{head}{message.value:+04d}"
    return head if isinstance(message, Get) else f"{head}{message.value}"


class FakeModules:
    """Scripted StackMod modules on the far end of a socket, ticked in the host's thread.

    They answer like healthy modules (ARM, MTR, SRV and DGT echo what was set; the ranger sees
    ``range_cm``; IR sensors read 500 + the sensor number) except what a test spoils. Each tick
    they wait for exactly the bytes the host has written so far and, after answering, until the
    answer is readable at the host, so a run is the same every time.

    Attributes:
        requests: (time, request text) of every packet received, in order.
        drop: Request text -> how many more times to ignore it (a packet lost on the line).
        silent: Addresses nobody answers.
        refuse_arm: Addresses whose ARM SETs are ignored.
        before_next_answer: Bytes sent ahead of the next answer (noise, bad packets).
    """

    def __init__(self, conn: socket.socket, host_port: Any, link: Link) -> None:
        self.conn = conn
        self.host_port = host_port
        self.link = link
        self.codec = StackModCodec(Role.DEVICE)
        self.received = 0
        self.raw = bytearray()
        self.requests: list[tuple[float, str]] = []
        self.drop: Counter[str] = Counter()
        self.silent: set[int] = set()
        self.refuse_arm: set[int] = set()
        self.before_next_answer = b""
        self.range_cm = 123
        self.values: dict[tuple[int, Command, int], int] = {}

    def sent(self, prefix: str) -> list[str]:
        """The requests received that start with ``prefix``."""
        return [request for _, request in self.requests if request.startswith(prefix)]

    def tick(self, now_s: float, dt_s: float) -> None:
        while self.received < self.link.bytes_sent:
            select.select([self.conn], [], [], _WAIT_S)
            data = self.conn.recv(65536)
            if not data:
                break
            self.received += len(data)
            self.raw += data
            self.codec.receive_data(data)
        out = bytearray()
        for message in drain(self.codec):
            if isinstance(message, Get | Set):
                out += self._handle(message, now_s)
        if out:
            self.conn.sendall(self.before_next_answer + out)
            self.before_next_answer = b""
            select.select([self.host_port.fileno()], [], [], _WAIT_S)

    def _handle(self, message: Get | Set, now_s: float) -> bytes:
        name = text(message)
        self.requests.append((now_s, name))
        key = next((k for k in self.drop if name.startswith(k) and self.drop[k] > 0), None)
        if key is not None:
            self.drop[key] -= 1
            return b""
        if message.address in self.silent:
            return b""
        where = (message.address, message.command, message.selector)
        if isinstance(message, Set):
            if message.command is not Command.ARM or message.address not in self.refuse_arm:
                self.values[where] = message.value
            return b""
        if message.command is Command.ULT:
            value = self.range_cm
        elif message.command is Command.IRS:
            value = 500 + message.selector
        else:
            value = self.values.get(where, 0)
        return self.codec.send(message.reply(value))


class Rig:
    """A driver, its scheduler on a simulated clock, and fake modules on a TCP socket."""

    def __init__(self, host_port: Any, conn: socket.socket, options: dict[str, Any]) -> None:
        self.profile = replace(get_profile("stackmod-rover"), options=options)
        self.clock = SimClock()
        self.scheduler = Scheduler(self.clock, 0.02)
        self.link = Link(host_port, StackModDriver.make_codec(self.profile), clock=self.clock)
        self.driver = StackModDriver(self.link, self.profile, self.clock)
        self.modules = FakeModules(conn, host_port, self.link)
        self.scheduler.add(self.modules, "sense")
        self.scheduler.add(self.driver.tick, "sense")
        self.scheduler.add(self.driver.flush, "act")

    def connect(self) -> None:
        self.driver.start()
        assert self.scheduler.run(until=lambda: self.driver.ready, max_duration_s=2.0)

    def run(self, seconds: float) -> None:
        self.scheduler.run(until=lambda: False, max_duration_s=seconds)

    def cap(self, name: str) -> Any:
        return self.driver.capabilities()[name]


@pytest.fixture
def make_rig(monkeypatch: pytest.MonkeyPatch) -> Iterator[Callable[..., Rig]]:
    # pyserial sleeps 0.3 s after closing a socket port, for quick reconnects; none happen here.
    monkeypatch.setattr(protocol_socket, "time", SimpleNamespace(sleep=lambda _s: None))
    server = socket.create_server(("127.0.0.1", 0))
    opened: list[tuple[Any, socket.socket]] = []

    def make(**options: Any) -> Rig:
        host_port = open_port(f"socket://127.0.0.1:{server.getsockname()[1]}")
        conn, _ = server.accept()
        conn.settimeout(_WAIT_S)
        opened.append((host_port, conn))
        return Rig(host_port, conn, options)

    yield make
    for host_port, conn in opened:
        host_port.close()
        conn.close()
    server.close()


# -- handshake ---------------------------------------------------------------------------------


def test_handshake_arms_every_module_then_asks_each_once(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    arms = [request for _, request in rig.modules.requests if "ARM" in request]
    assert arms == [
        *("M$ARM01", "S$ARM01", "U$ARM01", "I$ARM01"),
        *("M?ARM0", "S?ARM0", "U?ARM0", "I?ARM0"),
    ]
    assert set(rig.driver.capabilities()) == set(rig.profile.capabilities)
    assert rig.driver.describe() == (
        "StackMod modules (motor M, servo S, ultrasonic U, IR/IO I; seed checksum)"
    )


def test_handshake_stops_both_motors_once_ready(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.run(0.02)
    assert rig.modules.sent("M$MTR") == ["M$MTR1+000", "M$MTR2+000"]


def test_estimated_odometry_is_announced_once(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.run(1.0)
    assert len(rig.driver.notices) == 1
    assert "estimated" in rig.driver.notices[0]


def test_an_arm_lost_on_the_line_is_sent_again(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.modules.drop["S$ARM01"] = 1
    rig.connect()
    assert rig.modules.sent("S") == ["S$ARM01", "S?ARM0", "S$ARM01", "S?ARM0"]


def test_a_module_that_never_arms_is_named(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.modules.refuse_arm.add(ord("S"))
    with pytest.raises(DeviceError, match=r"servo module at 'S' \(0x53\) stays disarmed"):
        rig.connect()


# -- GET timeout and retries -------------------------------------------------------------------


def test_a_silent_module_is_retried_then_named(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.modules.silent.add(ord("U"))
    with pytest.raises(LinkTimeoutError) as raised:
        rig.connect()
    message = str(raised.value)
    assert "the ultrasonic module at 'U' (0x55) did not answer GET ARM0" in message
    assert "3 tries, 0.2 s each" in message
    assert rig.modules.sent("U?") == ["U?ARM0"] * 3
    # Timed on the scheduler clock: U is asked at 0.04 s, after M and S have answered.
    assert rig.clock.now() == pytest.approx(0.04 + 3 * 0.2)


def test_retries_and_timeout_are_profile_options(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig(get_timeout_s=0.1, get_retries=4)
    rig.modules.silent.add(ord("M"))
    with pytest.raises(LinkTimeoutError, match=r"5 tries, 0\.1 s each"):
        rig.connect()
    assert rig.modules.sent("M?") == ["M?ARM0"] * 5


def test_a_lost_answer_is_asked_again_and_the_run_goes_on(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.modules.drop["M?ARM0"] = 2
    rig.connect()
    assert rig.modules.sent("M?ARM0") == ["M?ARM0"] * 3
    assert rig.driver.poller.retried == 2


def test_a_robot_going_silent_mid_run_raises(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.run(0.5)
    rig.modules.silent.add(ord("M"))
    with pytest.raises(LinkTimeoutError, match="motor module at 'M'"):
        rig.run(2.0)


def test_garbage_and_bad_checksums_are_counted_and_skipped(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.modules.before_next_answer = b"\x00\xffnoise" + b"{M?ARM01}!"
    rig.connect()
    assert rig.link.faults == {"garbage": 1, "bad_checksum": 1}
    assert rig.driver.poller.retried == 0


# -- motors and odometry -----------------------------------------------------------------------


def test_wheel_speeds_become_motor_power_and_estimated_distance(
    make_rig: Callable[..., Rig],
) -> None:
    rig = make_rig()
    rig.connect()
    base = rig.cap(cap.DRIVE_BASE)
    assert base.odometry_is_estimated
    start = base.wheel_distances_mm()
    base.set_wheel_speeds(100.0, -50.0)
    rig.run(1.0)
    assert rig.modules.sent("M$MTR")[-2:] == ["M$MTR1+025", "M$MTR2-013"]
    left, right = base.wheel_distances_mm()
    # 25 % and -13 % at the profile's 3.968 mm/s per %, for 1 s give or take a tick.
    assert left - start[0] == pytest.approx(25 * 3.968, abs=2.1)
    assert right - start[1] == pytest.approx(-13 * 3.968, abs=1.1)


def test_small_speeds_are_raised_to_the_least_power_that_moves(
    make_rig: Callable[..., Rig],
) -> None:
    rig = make_rig(min_power_pct=8)
    rig.connect()
    rig.cap(cap.DRIVE_BASE).set_wheel_speeds(4.0, -12.0)
    rig.run(0.1)
    assert rig.modules.sent("M$MTR")[-2:] == ["M$MTR1+008", "M$MTR2-008"]


def test_an_inverted_motor_gets_the_opposite_sign(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig(invert_right=True, wheel_speed_mm_s_per_pct=2.0)
    rig.connect()
    base = rig.cap(cap.DRIVE_BASE)
    base.set_wheel_speeds(100.0, 100.0)
    rig.run(1.0)
    assert rig.modules.sent("M$MTR")[-2:] == ["M$MTR1+050", "M$MTR2-050"]
    left, right = base.wheel_distances_mm()
    assert left == pytest.approx(right) and left > 95.0


def test_a_lost_motor_set_is_caught_by_the_heartbeat(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.modules.drop["M$MTR1+025"] = 1
    rig.cap(cap.DRIVE_BASE).set_wheel_speeds(100.0, 100.0)
    rig.run(1.0)
    assert rig.modules.sent("M$MTR1+025") == ["M$MTR1+025"] * 2
    assert rig.modules.values[(ord("M"), Command.MTR, 1)] == 25
    assert rig.driver.lost_sets == 1


def test_exit_by_exception_stops_both_motors(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    robot = Robot(rig.profile, rig.driver, rig.scheduler, url="socket://test")
    with pytest.raises(RuntimeError), robot:
        robot.drive_base.set_wheel_speeds(150.0, 150.0)
        robot.run_for(0.3)
        raise RuntimeError("student code crashed")
    assert rig.link.closed
    rig.modules.tick(rig.clock.now(), 0.02)
    assert rig.modules.sent("M$MTR")[-2:] == ["M$MTR1+000", "M$MTR2+000"]


def test_stop_all_never_raises_even_on_a_closed_link(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.driver.stop_all()  # before the handshake
    rig.connect()
    rig.link.close()
    rig.driver.stop_all()


# -- sensors -----------------------------------------------------------------------------------


def test_a_sensor_is_polled_only_while_it_is_read(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.run(0.5)
    assert not rig.modules.sent("U?ULT")
    sensor = rig.cap(cap.RANGE)
    assert sensor.distance_mm() is None  # asked for now, answered by the next tick
    rig.run(0.1)
    assert sensor.distance_mm() == 1230.0
    polled = len(rig.modules.sent("U?ULT"))
    rig.run(1.5)
    stopped = len(rig.modules.sent("U?ULT"))
    assert stopped > polled
    rig.run(1.0)
    assert len(rig.modules.sent("U?ULT")) == stopped
    assert sensor.distance_mm() is None  # the last reading is too old to trust


def test_the_side_ranger_is_ultrasonic_sensor_1_facing_right(
    make_rig: Callable[..., Rig],
) -> None:
    rig = make_rig()
    rig.connect()
    side = rig.cap(cap.SIDE_RANGE)
    assert side.side == "right"
    side.distance_mm()
    rig.run(0.1)
    assert side.distance_mm() == 1230.0
    assert rig.modules.sent("U?ULT") == ["U?ULT1"] * len(rig.modules.sent("U?ULT"))


def test_no_echo_reads_as_none(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.modules.range_cm = 999
    sensor = rig.cap(cap.RANGE)
    sensor.distance_mm()
    rig.run(0.1)
    assert sensor.distance_mm() is None
    assert rig.modules.sent("U?ULT0")


def test_line_and_bump_sensors_read_their_modules(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig(bumper_pins=[4, 5])
    rig.connect()
    rig.modules.values[(ord("I"), Command.DGT, 5)] = 1
    line, bumper = rig.cap(cap.LINE), rig.cap(cap.BUMPER)
    line.values()
    bumper.pressed()
    rig.run(0.3)
    assert line.values() == (500.0, 501.0, 502.0)
    assert bumper.pressed() == frozenset({"right"})


# -- servos and buzzer -------------------------------------------------------------------------


def test_servo_angles_go_to_servos_numbered_from_1(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig(servo_count=2)
    rig.connect()
    servos = rig.cap(cap.SERVOS)
    servos.set_angle(0, 45.4)
    servos.set_angle(1, 180)
    rig.run(0.1)
    assert rig.modules.sent("S$SRV") == ["S$SRV145", "S$SRV2180"]
    with pytest.raises(ValueError, match="servo index"):
        servos.set_angle(2, 90)
    with pytest.raises(ValueError, match="0-180"):
        servos.set_angle(0, 181)


def test_the_buzzer_sounds_for_the_duration_at_its_one_pitch(
    make_rig: Callable[..., Rig], caplog: pytest.LogCaptureFixture
) -> None:
    rig = make_rig()
    rig.connect()
    speaker = rig.cap(cap.SPEAKER)
    assert speaker.fixed_frequency_hz == 2300.0
    speaker.beep(880.0, 0.2)
    rig.run(0.5)
    buzzer = [(t, r) for t, r in rig.modules.requests if r.startswith("I$DGT8")]
    assert [r for _, r in buzzer] == ["I$DGT81", "I$DGT80"]
    assert buzzer[1][0] - buzzer[0][0] == pytest.approx(0.2)
    speaker.beep(440.0, 0.1)
    assert sum("one pitch" in notice for notice in rig.driver.notices) == 1
    assert sum("one pitch" in record.message for record in caplog.records) == 1  # said once


def test_stop_all_silences_the_buzzer(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.cap(cap.SPEAKER).beep(2300.0, 5.0)
    rig.run(0.1)
    rig.driver.stop_all()
    rig.run(0.1)
    assert rig.modules.sent("I$DGT8") == ["I$DGT81", "I$DGT80"]


def test_the_packets_are_the_documented_bytes(make_rig: Callable[..., Rig]) -> None:
    rig = make_rig()
    rig.connect()
    rig.cap(cap.DRIVE_BASE).set_wheel_speeds(100.0, -100.0)
    rig.run(0.02)
    rig.modules.tick(rig.clock.now(), 0.02)  # read what the last act phase wrote
    frames = [
        *(b"{M$ARM01}", b"{S$ARM01}", b"{U$ARM01}", b"{I$ARM01}"),
        *(b"{M?ARM0}", b"{S?ARM0}", b"{U?ARM0}", b"{I?ARM0}"),
        *(b"{M$MTR1+000}", b"{M$MTR2+000}", b"{M?MTR1}"),
        *(b"{M$MTR1+025}", b"{M$MTR2-025}"),
    ]
    assert bytes(rig.modules.raw) == b"".join(pk(frame) for frame in frames)


def test_readings_no_module_can_report_are_counted_and_skipped(
    make_rig: Callable[..., Rig],
) -> None:
    rig = make_rig()
    rig.connect()
    sensor = rig.cap(cap.RANGE)
    sensor.distance_mm()
    rig.run(0.1)
    assert sensor.distance_mm() == 1230.0
    # 777 cm is past any ultrasonic module's reach; 5000 is past a 10-bit IR reading.
    rig.modules.before_next_answer = pk(b"{U?ULT0777}") + pk(b"{I?IRS05000}")
    rig.run(0.1)
    assert rig.link.faults == {"out_of_range": 2}
    assert sensor.distance_mm() == 1230.0  # the last good reading stands
    assert rig.driver.poller.retried == 0
