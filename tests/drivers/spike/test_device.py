"""The simulated SPIKE Prime hub, driven through raw hub-protocol bytes as the firmware would be."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from roboscript.codec import Role, drain
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.crc import crc32
from roboscript.drivers.spike.device import SpikeHub
from roboscript.errors import RemoteProtocolError
from roboscript.profiles import get_profile
from roboscript.sim.simulation import Simulation
from roboscript.sim.world import Pose, load_world

ACK = m.ResponseStatus.ACKNOWLEDGED
NACK = m.ResponseStatus.NOT_ACKNOWLEDGED
SLOT = 19
AGENT = b'"""A stand-in agent: the simulated hub only reads its version."""\n'
AGENT += b'AGENT_VERSION = "test-agent 3"\n' + b"# padding to several chunks\n" * 60


class Hub:
    """A simulated hub plus a host-role codec and a clock, speaking frames."""

    def __init__(self, world: str = "empty", start: Pose | None = None, **options: object) -> None:
        profile = get_profile("spike-prime")
        if options:
            profile = replace(profile, options=options)
        self.sim = Simulation(load_world(world), profile, seed=1, start=start)
        self.codec = SpikeCodec(Role.HOST)
        self.now = 0.0
        self.sim.connect()

    @property
    def device(self) -> SpikeHub:
        assert isinstance(self.sim.device, SpikeHub)
        return self.sim.device

    def send(self, *messages: m.Message) -> None:
        self.sim.write(b"".join(self.codec.send(message) for message in messages))

    def tunnel(self, *records: t.Record) -> None:
        self.send(m.TunnelMessage(t.encode(*records)))

    def run(self, seconds: float) -> None:
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.now = round(self.now + 0.01, 6)
            self.sim.tick(self.now, 0.01)

    def replies(self) -> list[m.Message]:
        self.codec.receive_data(self.sim.read(self.sim.in_waiting))
        out = list(drain(self.codec))
        assert not [x for x in out if isinstance(x, RemoteProtocolError)], out
        return [x for x in out if not isinstance(x, RemoteProtocolError)]

    def answers(self) -> list[m.Message]:
        """Replies other than the periodic DeviceNotification."""
        return [x for x in self.replies() if not isinstance(x, m.DeviceNotification)]

    def tunnel_replies(self) -> list[t.Record | RemoteProtocolError]:
        return [
            record
            for message in self.replies()
            if isinstance(message, m.TunnelMessage)
            for record in t.decode_records(message.data, Role.HOST)
        ]

    def upload(self, source: bytes, slot: int = SLOT, chunk: int = 512) -> list[m.Message]:
        self.send(m.StartFileUploadRequest("agent.py", slot, crc32(source)))
        running = 0
        for start in range(0, len(source), chunk):
            piece = source[start : start + chunk]
            running = crc32(piece, running)
            self.send(m.TransferChunkRequest(running, piece))
        return self.answers()

    def start_agent(self) -> None:
        self.upload(AGENT)
        self.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
        self.run(0.3)
        self.tunnel(t.Configure(0, 1))
        self.answers()

    def notifications(self) -> list[m.DeviceNotification]:
        return [x for x in self.replies() if isinstance(x, m.DeviceNotification)]

    def motors(self) -> dict[int, m.DeviceMotor]:
        """The motors in the last notification, by port."""
        last = self.notifications()[-1]
        return {d.port: d for d in last.devices if isinstance(d, m.DeviceMotor)}


# ------------------------------------------------------------------------ basic requests


def test_info_response_reports_ble_sized_limits() -> None:
    hub = Hub()
    hub.send(m.InfoRequest())
    (info,) = hub.answers()
    assert isinstance(info, m.InfoResponse)
    assert (info.max_packet_size, info.max_message_size, info.max_chunk_size) == (20, 1024, 512)
    assert info.product_group_device is m.ProductGroupDevice.SPIKE_PRIME


def test_name_can_be_read_and_changed_and_the_uuid_read() -> None:
    hub = Hub()
    hub.send(m.GetHubNameRequest(), m.SetHubNameRequest("Team 4"), m.GetHubNameRequest())
    hub.send(m.DeviceUuidRequest())
    first, renamed, second, uuid = hub.answers()
    assert first == m.GetHubNameResponse("Simulated SPIKE")
    assert renamed == m.SetHubNameResponse(ACK)
    assert second == m.GetHubNameResponse("Team 4")
    assert isinstance(uuid, m.DeviceUuidResponse) and len(uuid.device_uuid) == 16


def test_the_simulator_takes_no_firmware() -> None:
    hub = Hub()
    hub.send(m.StartFirmwareUploadRequest(bytes(20), 1), m.BeginFirmwareUpdateRequest(bytes(20), 1))
    assert hub.answers() == [
        m.StartFirmwareUploadResponse(NACK, 0),
        m.BeginFirmwareUpdateResponse(NACK),
    ]


def test_garbage_between_frames_is_skipped() -> None:
    hub = Hub()
    hub.sim.write(b"\x55\xaa\x00garbage\x02" + hub.codec.send(m.GetHubNameRequest()) + b"\x77")
    hub.sim.write(b"\x02" + hub.codec.send(m.InfoRequest()))
    answers = hub.answers()
    assert [type(a) for a in answers] == [m.GetHubNameResponse, m.InfoResponse]


# ------------------------------------------------------------------------- slots, uploads


def test_an_upload_with_the_running_crc_is_stored_in_its_slot() -> None:
    hub = Hub()
    answers = hub.upload(AGENT, slot=3, chunk=128)
    assert answers[0] == m.StartFileUploadResponse(ACK)
    assert set(answers[1:]) == {m.TransferChunkResponse(ACK)}
    assert len(answers) == 1 + -(-len(AGENT) // 128)
    assert hub.device.slots[3] == AGENT


def test_a_chunk_with_a_wrong_running_crc_is_refused_and_not_stored() -> None:
    hub = Hub()
    hub.send(m.StartFileUploadRequest("a.py", 2, crc32(AGENT)))
    first = AGENT[:512]
    hub.send(m.TransferChunkRequest(crc32(first) ^ 1, first))
    hub.send(m.TransferChunkRequest(crc32(first), first))  # the same chunk, right this time
    assert hub.answers() == [
        m.StartFileUploadResponse(ACK),
        m.TransferChunkResponse(NACK),
        m.TransferChunkResponse(ACK),
    ]
    assert 2 not in hub.device.slots  # not complete yet


def test_chunks_without_an_upload_or_over_the_chunk_size_are_refused() -> None:
    hub = Hub()
    hub.send(m.TransferChunkRequest(crc32(b"abcd"), b"abcd"))
    hub.send(m.StartFileUploadRequest("a.py", 2, 0))
    hub.send(m.TransferChunkRequest(crc32(bytes(600)), bytes(600)))
    assert hub.answers()[::2] == [m.TransferChunkResponse(NACK), m.TransferChunkResponse(NACK)]


def test_clearing_a_slot_acknowledges_only_a_full_one() -> None:
    hub = Hub()
    hub.upload(AGENT, slot=5)
    hub.send(m.ClearSlotRequest(5), m.ClearSlotRequest(5))
    assert hub.answers() == [m.ClearSlotResponse(ACK), m.ClearSlotResponse(NACK)]


# ---------------------------------------------------------------------------- program flow


def test_starting_an_empty_slot_is_refused() -> None:
    hub = Hub()
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, 7))
    assert hub.answers() == [m.ProgramFlowResponse(NACK)]
    assert hub.device.running_slot is None


def test_program_flow_answers_then_notifies_and_the_agent_prints_when_booted() -> None:
    hub = Hub()
    hub.upload(AGENT)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    assert hub.answers() == [
        m.ProgramFlowResponse(ACK),
        m.ProgramFlowNotification(m.ProgramAction.START),
    ]
    hub.run(0.3)
    assert hub.answers() == [
        m.ConsoleNotification("test-agent 3 ready, tunnel from hub.config['module_tunnel']")
    ]
    hub.send(m.ProgramFlowRequest(m.ProgramAction.STOP, SLOT))
    assert hub.answers() == [
        m.ProgramFlowResponse(ACK),
        m.ProgramFlowNotification(m.ProgramAction.STOP),
    ]


def test_tunnel_messages_need_a_running_agent_that_has_booted() -> None:
    hub = Hub()
    hub.tunnel(t.VersionQuery())
    assert hub.device.tunnel_without_program == 1
    hub.upload(AGENT)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    hub.tunnel(t.VersionQuery())  # the hub is still compiling the program
    assert hub.device.tunnel_lost == 1
    hub.run(0.3)
    hub.tunnel(t.VersionQuery())
    assert hub.tunnel_replies() == [t.Version("test-agent 3")]


def test_a_program_that_is_not_the_agent_ignores_the_tunnel() -> None:
    hub = Hub()
    hub.upload(b"print('hello')\n", slot=SLOT)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    hub.run(1.0)
    hub.tunnel(t.VersionQuery())
    hub.run(0.5)
    assert hub.tunnel_replies() == []


def test_stored_programs_survive_a_new_connection() -> None:
    hub = Hub()
    hub.upload(AGENT)
    hub.sim.connect()
    hub.codec = SpikeCodec(Role.HOST)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    assert hub.answers()[0] == m.ProgramFlowResponse(ACK)


# ------------------------------------------------------------------------------- the agent


def test_tank_holds_the_wheel_speeds_with_the_left_motor_mirrored() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.Tank(360, 360, 4000, 0))
    hub.run(1.0)
    before = hub.motors()
    hub.run(1.0)
    after = hub.motors()
    left = after[m.HubPort.A].position_deg - before[m.HubPort.A].position_deg
    right = after[m.HubPort.B].position_deg - before[m.HubPort.B].position_deg
    assert left == pytest.approx(-360, abs=15)
    assert right == pytest.approx(360, abs=15)
    assert after[m.HubPort.A].device_type is m.MotorDeviceType.MEDIUM_MOTOR


def test_the_watchdog_stops_the_wheels_when_the_host_goes_quiet() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.Tank(300, 300, 4000, 300))
    hub.run(0.25)
    assert hub.device.body.power[1] > 0.1
    hub.run(0.1)
    assert hub.device.body.power[1] <= 0.0  # braking
    hub.run(0.3)
    assert hub.device.body.wheel_speed_mm_s == pytest.approx([0.0, 0.0], abs=1.0)
    assert hub.device.body.power == [0.0, 0.0]


def test_a_move_turns_the_wheels_by_its_angle_and_reports_done() -> None:
    hub = Hub()
    hub.start_agent()
    ticks = list(hub.device.body.ticks)
    hub.tunnel(t.TankForDegrees(5, 360, 200, 200))
    hub.run(3.0)
    assert hub.tunnel_replies() == [t.MoveDone(5, t.MoveStatus.DONE)]
    turned = hub.device.body.ticks[1] - ticks[1]
    assert 360 <= turned < 380


def test_stop_cancels_a_move_and_brakes() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.TankForDegrees(6, 3600, 300, 300))
    hub.run(0.5)
    hub.tunnel(t.Stop())
    assert hub.tunnel_replies() == [t.MoveDone(6, t.MoveStatus.CANCELLED)]
    assert hub.device.body.power == [0.0, 0.0]


def test_a_move_into_a_wall_reports_stalled() -> None:
    hub = Hub("square-room", start=Pose(0.0, 850.0, 0.0))
    hub.start_agent()
    hub.tunnel(t.TankForDegrees(1, 3600, 300, 300))
    hub.run(2.0)
    assert hub.tunnel_replies() == [t.MoveDone(1, t.MoveStatus.STALLED)]


@pytest.mark.parametrize(
    ("records", "refusals"),
    [
        ([t.Tank(100, 100, 1000, 0)], [t.Refused(t.Tank.op, t.RefuseReason.NOT_CONFIGURED)]),
        ([t.Configure(2, 3)], [t.Refused(t.Configure.op, t.RefuseReason.BAD_VALUE)]),
    ],
)
def test_the_agent_refuses_what_it_cannot_do(
    records: list[t.Record], refusals: list[t.Refused]
) -> None:
    hub = Hub()
    hub.upload(AGENT)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    hub.run(0.3)
    hub.answers()
    hub.tunnel(*records)
    assert hub.tunnel_replies() == refusals
    assert hub.device.body.power == [0.0, 0.0]


def test_unknown_and_short_tunnel_records_are_refused_by_op() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.TunnelMessage(b"\x40\x00" + b"\x03\x01\x00"))
    assert hub.tunnel_replies() == [
        t.Refused(0x40, t.RefuseReason.UNKNOWN_COMMAND),
        t.Refused(0x03, t.RefuseReason.BAD_LENGTH),
    ]


def test_beeps_and_text_reach_the_simulation_log() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.Beep(523, 250, 100), t.ShowText("Hi"))
    log = hub.device.body.log
    assert [(f, d) for _, f, d in log.tones] == [(523.0, 0.25)]
    assert log.display == "Hi"
    hub.tunnel(t.ClearDisplay())
    assert log.display == ""


def test_a_program_ending_stops_its_motors() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.Tank(300, 300, 4000, 0))
    hub.run(0.3)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.STOP, SLOT))
    assert hub.device.body.power == [0.0, 0.0]
    hub.tunnel(t.Tank(300, 300, 4000, 0))
    assert hub.device.tunnel_without_program == 1


# --------------------------------------------------------------------------- notifications


def test_notifications_come_at_the_requested_interval_until_turned_off() -> None:
    hub = Hub()
    hub.send(m.DeviceNotificationRequest(100))
    assert hub.answers() == [m.DeviceNotificationResponse(ACK)]
    hub.run(1.0)
    assert len(hub.notifications()) == 10
    hub.send(m.DeviceNotificationRequest(0))
    hub.run(1.0)
    assert hub.notifications() == []


def test_a_notification_holds_the_hub_then_each_port_in_order() -> None:
    hub = Hub()
    hub.send(m.DeviceNotificationRequest(50))
    hub.run(0.05)
    (notification,) = hub.notifications()
    kinds = [(type(d).__name__, getattr(d, "port", None)) for d in notification.devices]
    assert kinds == [
        ("DeviceBattery", None),
        ("DeviceImu", None),
        ("DeviceMatrix5x5", None),
        ("DeviceMotor", m.HubPort.A),
        ("DeviceMotor", m.HubPort.B),
        ("DeviceForce", m.HubPort.C),
        ("DeviceDistance", m.HubPort.D),
        ("DeviceColor", m.HubPort.E),
        ("DeviceMotor", m.HubPort.F),  # the extra motor (option 'motors': the free port)
    ]
    assert notification.unparsed == b""


def test_devices_follow_the_profile_ports() -> None:
    hub = Hub(left_motor="E", right_motor="F", distance="A")
    hub.send(m.DeviceNotificationRequest(50))
    hub.run(0.05)
    (notification,) = hub.notifications()
    ports = {type(d).__name__: getattr(d, "port", None) for d in notification.devices}
    assert ports["DeviceDistance"] is m.HubPort.A
    motors = [d.port for d in notification.devices if isinstance(d, m.DeviceMotor)]
    # E and F drive; B and D, which no option names, get the extra motors.
    assert motors == [m.HubPort.B, m.HubPort.D, m.HubPort.E, m.HubPort.F]


def test_yaw_counts_counter_clockwise() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.Tank(200, -200, 4000, 0))  # turning right
    hub.run(0.5)
    hub.tunnel(t.Stop())
    hub.run(0.5)
    imu = next(d for d in hub.notifications()[-1].devices if isinstance(d, m.DeviceImu))
    heading = hub.device.body.heading_deg
    assert 10 < heading < 90
    assert imu.yaw == pytest.approx(-heading, abs=1.0)


def _distance(hub: Hub) -> int:
    hub.send(m.DeviceNotificationRequest(50))
    hub.run(0.2)
    last = hub.notifications()[-1]
    return next(d.distance_mm for d in last.devices if isinstance(d, m.DeviceDistance))


def test_distance_is_minus_one_without_an_echo_and_millimetres_with_one() -> None:
    assert _distance(Hub()) == -1
    # 2 m room: the north wall is 1000 mm from the centre, the sensor 90 mm ahead of it.
    near = _distance(Hub("square-room", start=Pose(0.0, 500.0, 0.0)))
    assert near == pytest.approx(410, abs=15)


def test_the_force_sensor_is_pressed_against_a_wall() -> None:
    hub = Hub("square-room", start=Pose(0.0, 850.0, 0.0))
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.Tank(300, 300, 4000, 0))
    hub.run(1.0)
    force = next(d for d in hub.notifications()[-1].devices if isinstance(d, m.DeviceForce))
    assert force.pressed and force.force_percent > 0


def test_power_off_ends_the_program_and_stops_the_motors() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.Power(5000, 5000, 0))
    hub.run(0.2)
    hub.sim.stop_all()
    assert hub.device.running_slot is None
    assert hub.device.body.power == [0.0, 0.0]


# -------------------------------------------------------- upload checks (LEGO's crc() rules)


def test_a_chunk_after_one_that_is_not_a_multiple_of_4_bytes_is_refused_at_once() -> None:
    hub = Hub()
    answers = hub.upload(AGENT, chunk=510)  # each chunk padded: LEGO's crc(), per chunk
    statuses = [a.status for a in answers if isinstance(a, m.TransferChunkResponse)]
    assert statuses == [ACK] + [NACK] * (len(statuses) - 1) and len(statuses) > 2
    assert hub.device.refused_chunks[0] == (
        2,
        "it follows a chunk whose size is not a multiple of 4 bytes",
    )
    assert SLOT not in hub.device.slots


def test_a_wrong_running_crc_is_refused_at_that_chunk_and_says_why() -> None:
    hub = Hub()
    hub.send(m.StartFileUploadRequest("agent.py", SLOT, crc32(AGENT)))
    first, second = AGENT[:512], AGENT[512:1024]
    running = crc32(first)
    hub.send(m.TransferChunkRequest(running, first), m.TransferChunkRequest(running, second))
    statuses = [a.status for a in hub.answers() if isinstance(a, m.TransferChunkResponse)]
    assert statuses == [ACK, NACK]
    (refusal,) = hub.device.refused_chunks
    assert refusal == (2, f"running CRC 0x{running:08x} is not 0x{crc32(second, running):08x}")


# ------------------------------------------------------------------------ tunnel binding


@pytest.mark.parametrize(
    ("offered", "tried", "bound"),
    [
        (
            ("hub.config['module_tunnel']", "import tunnel"),
            ["hub.config['module_tunnel']"],
            "hub.config['module_tunnel']",
        ),
        (("import tunnel",), ["hub.config['module_tunnel']", "import tunnel"], "import tunnel"),
    ],
    ids=["both-offered", "import-only"],
)
def test_the_agent_binds_the_first_form_the_firmware_offers(
    offered: tuple[str, ...], tried: list[str], bound: str
) -> None:
    hub = Hub()
    hub.device.config = replace(hub.device.config, tunnel_forms=offered)
    hub.start_agent()
    assert (hub.device.tunnel_tried, hub.device.tunnel_form) == (tried, bound)
    hub.tunnel(t.VersionQuery())
    assert hub.tunnel_replies() == [t.Version("test-agent 3")]


def test_without_a_tunnel_the_agent_names_the_firmware_and_never_answers() -> None:
    hub = Hub()
    hub.device.config = replace(hub.device.config, tunnel_forms=(), firmware_version=(3, 4, 0))
    hub.upload(AGENT)
    hub.send(m.ProgramFlowRequest(m.ProgramAction.START, SLOT))
    hub.run(0.5)
    consoles = [a for a in hub.answers() if isinstance(a, m.ConsoleNotification)]
    assert consoles == [
        m.ConsoleNotification(
            "roboscript agent: no tunnel on this hub (firmware 3.4.0): tried"
            " hub.config['module_tunnel'] and import tunnel; update the hub with the SPIKE App 3"
        )
    ]
    hub.tunnel(t.VersionQuery())
    assert hub.tunnel_replies() == []


def test_the_simulated_agent_tries_the_forms_in_the_real_agents_order() -> None:
    import ast

    from roboscript.drivers.spike.device import AGENT_TUNNEL_ORDER

    agent = Path(__file__).parents[3] / "roboscript" / "drivers" / "spike" / "agent"
    tree = ast.parse((agent / "hub_agent.py").read_text(encoding="utf-8"))
    (forms,) = [
        ast.literal_eval(node.value)
        for node in tree.body
        if isinstance(node, ast.Assign) and ast.unparse(node.targets[0]) == "TUNNEL_FORMS"
    ]
    assert forms == AGENT_TUNNEL_ORDER


# ------------------------------------------------------------ colour sensor and buttons


def colour_and_reports(hub: Hub) -> tuple[m.DeviceColor, list[t.Report]]:
    """The colour sensor in the last notification, and the agent's Reports since last read."""
    replies = hub.replies()
    notification = [x for x in replies if isinstance(x, m.DeviceNotification)][-1]
    (color,) = [d for d in notification.devices if isinstance(d, m.DeviceColor)]
    reports = [
        record
        for x in replies
        if isinstance(x, m.TunnelMessage)
        for record in t.decode_records(x.data, Role.HOST)
        if isinstance(record, t.Report)
    ]
    return color, reports


def test_the_colour_sensor_sees_the_tape_under_it_black_and_dark() -> None:
    hub = Hub("line-track")  # starts on the tape
    hub.start_agent()
    hub.tunnel(t.Watch(int(m.HubPort.E), 50))
    hub.send(m.DeviceNotificationRequest(50))
    hub.run(0.05)
    color, reports = colour_and_reports(hub)
    assert (color.color, color.red, color.green, color.blue) == (m.Color.BLACK, 60, 60, 70)
    assert reports and {r.reflection_percent for r in reports} == {10}


def test_a_coloured_floor_patch_is_named_and_reflects_its_own_share(tmp_path: Path) -> None:
    world = tmp_path / "patch.yaml"
    world.write_text(
        "world: patch\nfloor:\n  - {color: red, box: {x: -50, y: 0, width: 100, height: 200}}\n"
    )
    hub = Hub(str(world))  # the sensor is 80 mm ahead of the centre: over the patch
    hub.start_agent()
    hub.tunnel(t.Watch(int(m.HubPort.E), 50))
    hub.send(m.DeviceNotificationRequest(50))
    hub.run(0.05)
    color, reports = colour_and_reports(hub)
    assert color.color is m.Color.RED and color.red > color.green
    assert {r.reflection_percent for r in reports} == {55}


def test_a_watch_on_a_port_without_the_colour_sensor_reports_no_reflection() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.Watch(int(m.HubPort.D), 50))
    hub.run(0.02)
    assert hub.tunnel_replies() == [t.Report(t.NO_REFLECTION, 0)]


def test_buttons_pressed_by_a_test_or_the_world_script_are_reported(tmp_path: Path) -> None:
    world = tmp_path / "buttons.yaml"
    world.write_text("world: b\nbutton_presses:\n  - {at: 1 s, button: right, for: 200 ms}\n")
    hub = Hub(str(world))
    hub.start_agent()
    hub.device.press_button("left", 0.1)
    hub.tunnel(t.Watch(t.NO_PORT, 50))
    hub.run(0.7)  # to t = 1.0 s
    held = [r.pressed() for r in hub.tunnel_replies() if isinstance(r, t.Report)]
    assert held[0] == {"left"} and held[-1] == {"right"} and frozenset() in held
    hub.run(0.3)
    assert [r.pressed() for r in hub.tunnel_replies() if isinstance(r, t.Report)][-1] == set()
    with pytest.raises(ValueError, match=r"no 'center' button"):
        hub.device.press_button("center")


# ---------------------------------------------------------------------------- extra motors


def test_an_extra_motor_turns_by_its_angle_and_reports_done() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.MotorForDegrees(7, int(m.HubPort.F), -90, 180))
    hub.run(0.4)
    assert hub.tunnel_replies() == []
    hub.run(0.2)
    assert hub.tunnel_replies() == [t.MoveDone(7, t.MoveStatus.DONE)]
    hub.run(0.05)
    assert hub.motors()[m.HubPort.F].position_deg == -90


def test_an_extra_motor_runs_through_a_wheel_stop_until_its_own_stop() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.MotorRun(int(m.HubPort.F), 100, 0), t.Stop())  # Stop is for the wheels
    hub.run(1.0)
    assert hub.motors()[m.HubPort.F].position_deg == 100
    hub.tunnel(t.MotorForDegrees(8, int(m.HubPort.F), 720, 100), t.MotorStop(int(m.HubPort.F)))
    hub.run(0.5)
    assert hub.tunnel_replies() == [t.MoveDone(8, t.MoveStatus.CANCELLED)]
    hub.run(0.05)
    assert hub.motors()[m.HubPort.F].position_deg == 100


def test_the_watchdog_brakes_an_extra_motor_when_the_host_goes_quiet() -> None:
    hub = Hub()
    hub.start_agent()
    hub.send(m.DeviceNotificationRequest(50))
    hub.tunnel(t.MotorRun(int(m.HubPort.F), 100, 500))
    hub.run(1.0)
    stopped_at = hub.motors()[m.HubPort.F].position_deg
    assert stopped_at == pytest.approx(50, abs=2)  # 0.5 s at 100 deg/s
    hub.run(1.0)
    assert hub.motors()[m.HubPort.F].position_deg == stopped_at


def test_one_motor_commands_on_a_drive_port_or_an_empty_port_are_refused() -> None:
    hub = Hub()
    hub.start_agent()
    hub.tunnel(t.MotorRun(int(m.HubPort.A), 100, 0), t.MotorStop(int(m.HubPort.C)))
    assert hub.tunnel_replies() == [
        t.Refused(t.MotorRun.op, t.RefuseReason.BAD_VALUE),
        t.Refused(t.MotorStop.op, t.RefuseReason.BAD_VALUE),
    ]
