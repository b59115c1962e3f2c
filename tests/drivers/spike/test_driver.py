"""The SPIKE Prime host driver against the simulated hub, over real hub-protocol bytes."""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import pytest

from roboscript import capabilities as cap
from roboscript.clock import SimClock
from roboscript.codec import Role, drain
from roboscript.drivers.spike import driver as spike_driver
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.device import SpikeHub
from roboscript.drivers.spike.driver import SpikeDriver, agent_source
from roboscript.errors import DeviceError, LinkClosedError, LinkTimeoutError
from roboscript.profiles import RobotProfile, get_profile
from roboscript.robot import Robot
from roboscript.scheduler import Scheduler
from roboscript.sim.simulation import Simulation
from roboscript.transport import Link, open_port

SLOT = 19
MM_PER_DEG = math.pi * 56.0 / 360


class SpyPort:
    """A port that keeps a copy of everything written (and may take a BLE packet size)."""

    def __init__(self, port: Any) -> None:
        self.port = port
        self.written = bytearray()
        self.packet_sizes: list[int] = []

    def read(self, size: int = 1) -> bytes:
        data: bytes = self.port.read(size)
        return data

    def write(self, data: bytes, /) -> int:
        self.written += data
        return int(self.port.write(data))

    def close(self) -> None:
        self.port.close()

    def set_max_packet_size(self, size: int) -> None:
        self.packet_sizes.append(size)


class Session:
    """A driver connected to a simulated hub, on a virtual clock."""

    def __init__(
        self,
        *,
        world: str = "empty",
        start: str = "",
        profile: RobotProfile | None = None,
        prepare: Callable[[SpikeHub], None] | None = None,
        expect_ready: bool = True,
    ) -> None:
        self.profile = profile or get_profile("spike-prime")
        self.port = SpyPort(open_port(f"sim://spike-prime?world={world}&seed=1{start}"))
        self.sim: Simulation = self.port.port.simulation
        if prepare is not None:
            prepare(self.hub)
        self.clock = SimClock()
        self.scheduler = Scheduler(self.clock, 0.02)
        self.link = Link(self.port, SpikeDriver.make_codec(self.profile), clock=self.clock)
        self.driver = SpikeDriver(self.link, self.profile, self.clock)
        self.scheduler.add(self.sim, "sense")
        self.scheduler.add(self.driver.tick, "sense")
        self.scheduler.add(self.driver.flush, "act")
        self.driver.start()
        ready = self.scheduler.run(
            until=lambda: self.driver.ready, max_duration_s=self.profile.handshake_timeout_s
        )
        assert ready == expect_ready
        self.ready_s = self.clock.now()

    @property
    def hub(self) -> SpikeHub:
        assert isinstance(self.sim.device, SpikeHub)
        return self.sim.device

    def run(self, seconds: float) -> None:
        self.scheduler.run(until=lambda: False, max_duration_s=seconds)

    def sent(self) -> list[m.Message]:
        codec = SpikeCodec(Role.DEVICE)
        codec.receive_data(bytes(self.port.written))
        messages = list(drain(codec))
        assert all(isinstance(x, m.Message) for x in messages), messages
        return messages  # type: ignore[return-value]

    def sent_records(self) -> list[t.Record]:
        return [
            record  # type: ignore[misc]
            for message in self.sent()
            if isinstance(message, m.TunnelMessage)
            for record in t.decode_records(message.data, Role.DEVICE)
        ]

    def capability(self, name: str) -> Any:
        return self.driver.capabilities()[name]


def _install(source: bytes) -> Callable[[SpikeHub], None]:
    def prepare(hub: SpikeHub) -> None:
        hub.slots[SLOT] = source

    return prepare


# ------------------------------------------------------------------------------ handshake


def test_a_first_connection_uploads_the_agent_then_starts_and_configures_it() -> None:
    session = Session()
    kinds = [type(x).__name__ for x in session.sent()]
    chunks = kinds.count("TransferChunkRequest")
    assert chunks == -(-len(agent_source()) // 512)
    assert kinds[:7] == [
        "InfoRequest",
        "GetHubNameRequest",
        "ProgramFlowRequest",  # start: the slot is empty
        "ProgramFlowRequest",  # stop before uploading
        "ClearSlotRequest",
        "StartFileUploadRequest",
        "TransferChunkRequest",
    ]
    assert kinds[6 + chunks] == "ProgramFlowRequest"
    assert session.hub.slots[SLOT] == agent_source()
    records = session.sent_records()
    assert records.index(t.VersionQuery()) < records.index(t.Configure(0, 1))
    assert m.DeviceNotificationRequest(50) in session.sent()
    assert session.driver.describe() == (
        "SPIKE Prime hub 'Simulated SPIKE' (firmware 1.0.0, roboscript-agent 2)"
    )


def test_an_agent_of_the_current_version_is_started_without_an_upload() -> None:
    session = Session(prepare=_install(agent_source()))
    kinds = {type(x).__name__ for x in session.sent()}
    assert "StartFileUploadRequest" not in kinds
    assert session.driver.hub_agent_version == session.driver.agent_version
    assert not session.driver.uploaded


def test_an_agent_of_another_version_is_replaced() -> None:
    old = agent_source().replace(b'AGENT_VERSION = "', b'AGENT_VERSION = "old ', 1)
    session = Session(prepare=_install(old))
    assert session.driver.uploaded
    assert session.hub.slots[SLOT] == agent_source()
    assert session.ready_s < 2.0  # it said its version: no waiting for a timeout
    assert session.driver.notices == []


def test_a_foreign_program_in_the_slot_is_replaced_once_it_fails_to_answer() -> None:
    session = Session(prepare=_install(b"print('my robot dance')\n"))
    assert session.driver.uploaded
    assert session.hub.slots[SLOT] == agent_source()
    assert session.ready_s > 3.0  # the version query's time limit
    assert session.driver.notices == [
        "roboscript's agent replaced the program in slot 19 of the hub"
    ]


def test_the_hub_gets_no_tunnel_message_while_no_program_runs() -> None:
    session = Session()
    session.capability(cap.DRIVE_BASE).set_wheel_speeds(100.0, 100.0)
    session.run(0.5)
    session.driver.stop_all()
    session.run(0.2)
    session.capability(cap.DRIVE_BASE).set_wheel_speeds(100.0, 100.0)  # restarts the agent
    session.run(1.0)
    session.driver.stop_all()
    assert session.hub.tunnel_without_program == 0


def test_the_hubs_packet_size_reaches_a_port_that_writes_in_packets() -> None:
    session = Session()
    assert session.port.packet_sizes == [20]


def test_a_hub_refusing_a_chunk_fails_the_connection_in_one_sentence(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(spike_driver, "crc32", lambda data, seed=0: 1234)
    with pytest.raises(DeviceError) as caught:
        Session()
    chunks = -(-len(agent_source()) // 512)
    assert str(caught.value) == (
        f"the SPIKE hub refused piece 1 of {chunks} of roboscript's agent"
        " (running CRC 0x000004d2), so the agent was not stored"
    )


def test_an_agent_that_never_says_ready_fails_the_connection_in_one_sentence() -> None:
    def never_boots(hub: SpikeHub) -> None:
        hub.config = replace(hub.config, agent_boot_s=1000.0)

    with pytest.raises(DeviceError) as caught:
        Session(prepare=never_boots)
    assert str(caught.value) == (
        "roboscript's agent did not start on the hub after the upload: the program in the slot"
        " never said it was ready within 3 s; is the hub (firmware 1.0.0) running SPIKE App 3"
        " firmware?"
    )


def test_an_agent_that_says_ready_but_never_answers_fails_saying_it_does_not_answer(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    def mute(hub: SpikeHub, data: bytes, now_s: float) -> None:
        hub.tunnel_lost += 1  # a program that printed the line but reads nothing

    monkeypatch.setattr(SpikeHub, "_tunnel", mute)
    with pytest.raises(DeviceError) as caught:
        Session()
    assert str(caught.value).startswith(
        "roboscript's agent did not start on the hub after the upload: the program in the slot"
        " does not answer (the hub printed: roboscript-agent 2 ready, tunnel from "
    )


def test_a_drive_motor_missing_from_its_port_is_named() -> None:
    profile = replace(get_profile("spike-prime"), options={"left_motor": "C"})
    with pytest.raises(DeviceError, match=r"no drive motor on port C .*found on: A, B, F\)"):
        Session(profile=profile)


def test_console_lines_become_log_lines(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.INFO, logger="roboscript.drivers.spike.driver"):
        session = Session()
    ready = "roboscript-agent 2 ready, tunnel from hub.config['module_tunnel']"
    assert f"hub says: {ready}" in caplog.messages
    assert list(session.driver.console) == [ready]


# -------------------------------------------------------------------------------- driving


def test_wheel_speeds_are_sent_in_motor_degrees_per_second_and_refreshed() -> None:
    session = Session()
    base = session.capability(cap.DRIVE_BASE)
    before = len(session.sent_records())
    base.set_wheel_speeds(100.0, 50.0)
    session.run(1.1)
    base.stop()
    session.run(0.2)
    records = session.sent_records()[before:]
    tank = t.Tank(round(100 / MM_PER_DEG), round(50 / MM_PER_DEG), 4000, 1500)
    assert records == [tank, tank, tank, t.Stop()]


def test_wheel_distances_and_heading_follow_the_body() -> None:
    session = Session()
    base = session.capability(cap.DRIVE_BASE)
    base.set_wheel_speeds(150.0, 150.0)
    session.run(2.0)
    base.stop()
    session.run(0.5)
    left, right = base.wheel_distances_mm()
    ticks = session.sim.body.ticks
    assert left == pytest.approx(ticks[0] * MM_PER_DEG, abs=1.0)
    assert right == pytest.approx(ticks[1] * MM_PER_DEG, abs=1.0)
    assert 250 < left < 330 and 250 < right < 330
    base.set_wheel_speeds(60.0, -60.0)  # turn right
    session.run(1.0)
    base.stop()
    session.run(0.5)
    heading = session.capability(cap.HEADING).heading_deg()
    assert heading is not None and heading > 20
    assert heading == pytest.approx(session.sim.body.heading_deg, abs=1.5)


def test_speeds_beyond_the_profile_limit_are_clamped() -> None:
    session = Session()
    session.capability(cap.DRIVE_BASE).set_wheel_speeds(5000.0, -5000.0)
    session.run(0.1)
    top = round(350.0 / MM_PER_DEG)
    assert session.sent_records()[-1] == t.Tank(top, -top, 4000, 1500)


def test_a_move_for_degrees_reports_done_from_the_hub() -> None:
    session = Session()
    seq = session.driver.move_for_degrees(360, 200, 200)
    session.run(3.0)
    assert session.driver.move_results[seq] is t.MoveStatus.DONE
    assert session.capability(cap.DRIVE_BASE).wheel_distances_mm()[1] == pytest.approx(
        360 * MM_PER_DEG, abs=10
    )


def test_power_drives_without_speed_control() -> None:
    session = Session()
    session.driver.set_power(3000, 3000)
    session.run(1.0)
    assert session.sim.body.power == pytest.approx([0.3, 0.3])
    assert t.Power(3000, 3000, 1500) in session.sent_records()


# ----------------------------------------------------------------------------- stopping


def test_stop_all_brakes_and_stops_the_program_then_motion_starts_it_again() -> None:
    session = Session()
    base = session.capability(cap.DRIVE_BASE)
    base.set_wheel_speeds(150.0, 150.0)
    session.run(0.5)
    session.driver.stop_all()
    records, sent = session.sent_records(), session.sent()
    assert records[-1] == t.Stop()
    assert sent[-1] == m.ProgramFlowRequest(m.ProgramAction.STOP, SLOT)
    assert session.sim.body.power == [0.0, 0.0]
    session.run(0.5)
    assert session.hub.running_slot is None
    base.set_wheel_speeds(150.0, 150.0)
    session.run(1.0)
    assert session.hub.running_slot == SLOT
    assert session.sim.body.wheel_speed_mm_s[1] > 100
    assert sum(isinstance(x, m.StartFileUploadRequest) for x in session.sent()) == 1


def test_stop_all_never_raises_even_on_a_closed_link() -> None:
    session = Session()
    session.link.close()
    session.driver.stop_all()


def test_the_program_stopped_on_the_hub_ends_the_session_with_a_clear_error() -> None:
    session = Session()
    session.hub.press_centre_button()
    with pytest.raises(LinkClosedError, match="program on the SPIKE hub stopped"):
        session.run(0.1)


def test_a_silent_hub_is_a_link_timeout() -> None:
    session = Session()
    session.scheduler.remove(session.sim)
    with pytest.raises(LinkTimeoutError, match="stopped responding"):
        session.run(2.0)


# ------------------------------------------------------------------------------- sensors


def test_range_force_bumper_and_colour_read_the_simulated_sensors() -> None:
    session = Session(world="square-room", start="&x=0&y=500&heading=0")
    distance = session.capability(cap.RANGE).distance_mm()
    assert distance == pytest.approx(410, abs=15)
    assert session.capability(cap.COLOR).color_name() == "white"
    assert session.capability(cap.BUMPER).pressed() == frozenset()
    session.capability(cap.DRIVE_BASE).set_wheel_speeds(200.0, 200.0)
    session.run(3.0)
    assert session.capability(cap.BUMPER).pressed() == frozenset({"front"})
    assert session.capability(cap.FORCE).pressed()
    assert session.capability(cap.FORCE).force_n() == pytest.approx(8.0)


def test_no_echo_reads_as_none() -> None:
    session = Session()
    assert session.capability(cap.RANGE).distance_mm() is None


def test_text_and_tones_reach_the_hub() -> None:
    with Robot.connect("spike-prime") as robot:
        robot.display.show_text("Hello")
        robot.speaker.beep(440.0, 0.1)
        robot.run_for(0.1)
        assert robot.simulation.log.display == "Hello"
        robot.display.clear()
        robot.run_for(0.1)
        assert robot.simulation.log.display == ""
        assert [(f, d) for _, f, d in robot.simulation.log.tones] == [(440.0, 0.1)]


def test_the_robot_has_every_capability_of_its_profile() -> None:
    with Robot.connect("spike-prime") as robot:
        assert set(robot.capabilities) == set(robot.profile.capabilities)
        for name, protocol in [
            (cap.DRIVE_BASE, cap.DriveBase),
            (cap.RANGE, cap.RangeSensor),
            (cap.BUMPER, cap.Bumpers),
            (cap.SPEAKER, cap.Speaker),
            (cap.DISPLAY, cap.Display),
            (cap.HEADING, cap.HeadingSensor),
            (cap.FORCE, cap.ForceSensor),
            (cap.COLOR, cap.ColorSensor),
            (cap.LINE, cap.LineSensors),
            (cap.BUTTONS, cap.HubButtons),
            (cap.MOTORS, cap.Motors),
        ]:
            assert isinstance(robot.capabilities[name], protocol), name


def test_a_command_the_agent_refuses_fails_the_running_action_with_its_reason() -> None:
    session = Session()
    agent = session.hub._agent
    assert agent is not None
    agent.pair = None  # as if the agent had lost its motor configuration
    session.driver.set_wheel_speeds(100.0, 100.0)
    session.run(0.1)
    assert session.driver.take_device_error() == (
        "the agent on the hub refused Tank: not configured"
    )


# ------------------------------------------------------------------- impossible readings


def _hub_says(session: Session, *devices: m.DeviceMessage) -> None:
    """Make the hub's next bytes a DeviceNotification of ``devices`` (real hub framing)."""
    data = SpikeCodec(Role.DEVICE).send(m.DeviceNotification(tuple(devices)))
    read = session.port.read

    def read_once(size: int = 1) -> bytes:
        session.port.read = read  # type: ignore[method-assign]
        return read(size) + data

    session.port.read = read_once  # type: ignore[method-assign]


def test_readings_no_hub_can_report_are_counted_and_skipped() -> None:
    session = Session(world="square-room", start="&x=0&y=500&heading=0")
    options = session.driver.options
    before = session.capability(cap.RANGE).distance_mm()
    _hub_says(
        session,
        m.DeviceDistance(m.HubPort(options.distance), 30000),
        m.DeviceForce(m.HubPort(options.force), 250, True),
        m.DeviceColor(m.HubPort(options.color), m.Color.RED, 60000, 0, 0),
    )
    session.run(0.02)
    assert session.link.faults["out_of_range"] == 3
    assert session.capability(cap.RANGE).distance_mm() == before
    assert session.capability(cap.BUMPER).pressed() == frozenset()
    assert session.capability(cap.COLOR).color_name() == "white"
    session.run(0.2)  # the real readings that follow are used as before
    assert session.link.faults["out_of_range"] == 3


def test_a_motor_position_jump_no_motor_can_turn_is_skipped() -> None:
    session = Session()
    base = session.capability(cap.DRIVE_BASE)
    before = base.wheel_distances_mm()
    right = m.HubPort(session.driver.options.right_motor)
    _hub_says(session, m.DeviceMotor(right, 48, 0, 0, 0, 2_000_000_000))
    session.run(0.02)
    assert session.link.faults["out_of_range"] == 1
    assert base.wheel_distances_mm() == pytest.approx(before, abs=1.0)


def test_a_plausible_reading_is_not_counted() -> None:
    session = Session(world="square-room", start="&x=0&y=500&heading=0")
    options = session.driver.options
    _hub_says(session, m.DeviceDistance(m.HubPort(options.distance), 1999))
    session.run(0.02)
    assert session.link.faults["out_of_range"] == 0
    assert session.capability(cap.RANGE).distance_mm() == 1999.0


# ------------------------------------------------------------- colour, buttons, motors


def test_the_colour_sensor_reads_reflection_colour_and_rgb_and_serves_as_a_line_sensor() -> None:
    session = Session(world="line-track")  # starts with the sensor on the tape
    session.run(0.2)
    color = session.capability(cap.COLOR)
    assert (color.reflection_percent(), color.color_name(), color.rgb()) == (
        10.0,
        "black",
        (60, 60, 70),
    )
    line = session.capability(cap.LINE)
    assert line.names == ("center",)
    (darkness,) = line.values()
    assert darkness == pytest.approx(1023 * 0.9) and darkness > line.dark_threshold
    assert t.Watch(int(m.HubPort.E), 50) in session.sent_records()


def test_the_hub_buttons_read_what_the_agent_reports() -> None:
    session = Session()
    buttons = session.capability(cap.BUTTONS)
    assert buttons.names == ("left", "right") and buttons.pressed() == frozenset()
    session.hub.press_button("left", 0.3)
    session.run(0.1)
    assert buttons.pressed() == frozenset({"left"})
    session.run(0.4)
    assert buttons.pressed() == frozenset()


def test_an_extra_motor_turns_by_an_angle_and_reports_the_result() -> None:
    session = Session()
    motors = session.capability(cap.MOTORS)
    assert motors.ports == ("F",)
    handle = motors.run_for_degrees("F", -45, 90.0)
    session.run(0.2)
    assert motors.move_result(handle) is None
    session.run(0.5)
    assert motors.move_result(handle) == "done"
    assert session.hub.extra_motors[int(m.HubPort.F)].position_deg == -45
    assert t.MotorForDegrees(handle, int(m.HubPort.F), -45, 90) in session.sent_records()


def test_an_extra_motor_runs_refreshed_within_its_watchdog_until_stopped() -> None:
    session = Session()
    motors = session.capability(cap.MOTORS)
    motors.run("F", 120.0)
    session.run(1.2)
    runs = [r for r in session.sent_records() if isinstance(r, t.MotorRun)]
    assert len(runs) >= 3 and runs[0] == t.MotorRun(int(m.HubPort.F), 120, 1500)
    motors.stop("F")
    session.run(0.1)
    position = session.hub.extra_motors[int(m.HubPort.F)].position_deg
    session.run(0.5)
    assert session.hub.extra_motors[int(m.HubPort.F)].position_deg == position
    assert position == pytest.approx(120 * 1.2, abs=15)


def test_a_motor_on_a_port_the_profile_does_not_list_is_refused_in_one_sentence() -> None:
    session = Session()
    with pytest.raises(DeviceError) as caught:
        session.capability(cap.MOTORS).run("C", 90.0)
    assert str(caught.value) == (
        "there is no motor on port C in profile spike-prime (its 'motors' option lists: F)"
    )


def test_a_hub_without_a_tunnel_fails_naming_the_firmware_and_the_forms_tried() -> None:
    def no_tunnel(hub: SpikeHub) -> None:
        hub.config = replace(hub.config, tunnel_forms=(), firmware_version=(3, 4, 0))

    with pytest.raises(DeviceError) as caught:
        Session(prepare=no_tunnel)
    assert str(caught.value) == (
        "roboscript's agent did not start on the hub after the upload: the program in the slot"
        " never said it was ready within 3 s (the hub printed: roboscript agent: no tunnel on"
        " this hub (firmware 3.4.0): tried hub.config['module_tunnel'] and import tunnel;"
        " update the hub with the SPIKE App 3); is the hub (firmware 3.4.0) running SPIKE App 3"
        " firmware?"
    )


def test_stop_all_brakes_every_extra_motor_used_and_a_wheel_stop_does_not() -> None:
    session = Session()
    base, motors = session.capability(cap.DRIVE_BASE), session.capability(cap.MOTORS)
    motors.run("F", 200.0)
    base.set_wheel_speeds(100.0, 100.0)
    session.run(0.3)
    base.stop()
    session.run(0.3)
    assert t.MotorStop(int(m.HubPort.F)) not in session.sent_records()
    assert session.hub.extra_motors[int(m.HubPort.F)].speed_deg_s == 200.0
    session.driver.stop_all()
    assert session.sent_records()[-2:] == [t.Stop(), t.MotorStop(int(m.HubPort.F))]
    assert session.hub.extra_motors[int(m.HubPort.F)].speed_deg_s == 0.0


def test_the_host_sends_nothing_on_the_tunnel_before_the_agents_ready_line() -> None:
    # LEGO's tracker reports hubs crashing on a TunnelMessage no program is ready for: the
    # first VersionQuery waits for the agent to print that its callback is registered.
    session = Session()
    assert session.hub.tunnel_lost == 0
    assert session.hub.tunnel_without_program == 0
    assert any(" ready, tunnel from " in line for line in session.driver.console)


def test_the_host_waits_for_a_slow_agent_to_say_ready_and_keeps_it() -> None:
    # A hub that takes 2.5 s to compile and start the agent: nothing on the tunnel is lost
    # while it starts, and the agent in the slot is used, not replaced.
    def slow_agent(hub: SpikeHub) -> None:
        _install(agent_source())(hub)
        hub.config = replace(hub.config, agent_boot_s=2.5)

    session = Session(prepare=slow_agent)
    assert session.hub.tunnel_lost == 0
    assert not session.driver.uploaded
    assert session.ready_s > 2.5


def test_a_ready_line_the_hub_prints_in_pieces_is_still_heard() -> None:
    def print_in_pieces(hub: SpikeHub) -> None:
        send = hub._send

        def cut(message: m.Message) -> None:
            if not isinstance(message, m.ConsoleNotification):
                send(message)
                return
            for start in range(0, len(message.text), 7):
                send(m.ConsoleNotification(message.text[start : start + 7]))

        hub._send = cut  # type: ignore[method-assign]

    session = Session(prepare=print_in_pieces)
    assert session.ready_s < 3.0  # no waiting for the time limit, no second upload
    assert session.hub.tunnel_lost == 0
