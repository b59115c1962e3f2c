"""A simulated LEGO SPIKE Prime hub (App 3 firmware) on a simulated body.

This is a second, independent implementation of the hub's side (it never imports the host
driver). It answers every request of the hub protocol with the codec in the device role, and
behaves as the firmware does as far as roboscript relies on it:

* **InfoResponse** sizes: a 20-byte max packet (the ATT payload of BLE's default 23-byte
  MTU, the only write size every BLE stack accepts without negotiating), a 512-byte max
  chunk and a 1024-byte max message (a 512-byte TransferChunkRequest is 519 bytes).
* **Slots and uploads**: StartFileUploadRequest opens a transfer into a slot (the name is
  read up to its NUL, so LEGO's ``name + NUL`` form and a NUL-padded 32-byte field both
  work); every TransferChunkRequest must carry the running CRC computed as LEGO's example
  does (:func:`~roboscript.drivers.spike.crc.crc32`: the chunk zero-padded to 4 bytes,
  seeded with the previous value) or it is refused with a NACK at that chunk. A chunk that
  follows one whose size is not a multiple of 4 is refused too: the padding inside the file
  means the running CRC can never reach the file CRC, and a hub that took the rest would
  refuse to run the file later without a word. The file is stored when the running CRC
  reaches the file CRC announced at the start. :attr:`SpikeHub.refused_chunks` lists the
  refusals.
* **The tunnel**: the firmware offers the tunnel to programs in the forms of
  :attr:`HubConfig.tunnel_forms`; the agent is modelled as trying
  ``hub.config['module_tunnel']`` first and ``import tunnel`` second, as the real agent does
  (:attr:`SpikeHub.tunnel_tried` records what it tried). With neither, it prints the real
  agent's message naming the firmware version and never reads the tunnel.
* **Program flow**: ProgramFlowRequest answers with ProgramFlowResponse, then
  ProgramFlowNotification; starting an empty slot is refused. A program's end stops its
  motors. A program that defines ``AGENT_VERSION = "..."`` is taken to be roboscript's agent:
  after ``agent_boot_s`` it prints its ready line (ConsoleNotification) and then interprets
  the tunnel commands of :mod:`roboscript.drivers.spike.tunnel` as the real agent does, with
  the hub's speed control simulated by a feed-forward plus position loop per motor, and its
  brake as a shorted motor (a push against the wheel's speed). Other programs run silently
  and ignore the tunnel.
* **DeviceNotification** at the requested interval: battery, IMU, the 5x5 matrix, then each
  port's device in port order. The colour sensor reads the world's floor under it
  (:mod:`roboscript.sim.floor`): colour and RGB here, reflection in the agent's ``Report``
  with the hub buttons (pressed by :meth:`SpikeHub.press_button` or the world's
  ``button_presses``). Extra motors (profile option ``motors``) turn freely, off the body.
  Motor positions are the body's wheel rotation in degrees (the
  left motor mounted mirrored, so its position falls as the robot drives forward); IMU yaw is
  whole degrees, counter-clockwise positive; distance is millimetres or -1 without an echo.
* Bytes that do not decode are skipped silently, as the firmware does.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from roboscript.codec import Role, readable
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.codec import SpikeCodec
from roboscript.drivers.spike.crc import crc32
from roboscript.drivers.spike.options import SpikeOptions
from roboscript.errors import RemoteProtocolError

if TYPE_CHECKING:
    from roboscript.robot_profile import RobotProfile
    from roboscript.sim.body import Body
    from roboscript.sim.floor import FloorReading

__all__ = ["HubConfig", "SpikeHub", "simulated_device"]

_ACK = m.ResponseStatus.ACKNOWLEDGED
_NACK = m.ResponseStatus.NOT_ACKNOWLEDGED
# The hub's speed control: feed-forward from the target speed plus a position loop.
_KP_POWER_PER_DEG = 0.01
_MAX_LAG_DEG = 45.0
_STALL_S = 0.5
# A braked motor is shorted: it pushes back in proportion to its speed until it stops.
_BRAKE_GAIN = 3.0
_FORCE_PRESSED_PERCENT = 80
# The real agent's order (hub_agent.py TUNNEL_FORMS); a test checks the two agree.
AGENT_TUNNEL_ORDER = ("hub.config['module_tunnel']", "import tunnel")
# The colour sensor looks down this far ahead of the body centre (a LEGO driving base).
_COLOR_SENSOR_FORWARD_MM = 80.0
_EXTRA_MOTOR_MAX_DEG_S = 1100.0


@dataclass(frozen=True)
class HubConfig:
    """How the simulated hub is built and what it reports.

    Attributes:
        options: Which device is on which port (from the robot profile).
        name: Hub name (GetHubNameResponse).
        device_uuid: 16 bytes (DeviceUuidResponse).
        rpc_version: RPC major, minor, build (InfoResponse).
        firmware_version: Firmware major, minor, build (InfoResponse).
        max_packet_size: InfoResponse max packet size, bytes.
        max_message_size: InfoResponse max message size, bytes.
        max_chunk_size: InfoResponse max chunk size, bytes.
        agent_boot_s: Time from starting the agent to its first tunnel read, seconds (the
            hub compiles the program first; tunnel messages before then are lost).
        programs: Programs stored at power-on, by slot.
        tunnel_forms: How the firmware offers the tunnel to a program:
            ``"hub.config['module_tunnel']"``, ``"import tunnel"``, both, or neither.
    """

    options: SpikeOptions = field(default_factory=SpikeOptions)
    name: str = "Simulated SPIKE"
    device_uuid: bytes = bytes(range(0x10, 0x20))
    rpc_version: tuple[int, int, int] = (1, 0, 0)
    firmware_version: tuple[int, int, int] = (1, 0, 0)
    max_packet_size: int = 20
    max_message_size: int = 1024
    max_chunk_size: int = 512
    agent_boot_s: float = 0.2
    programs: dict[int, bytes] = field(default_factory=dict)
    tunnel_forms: tuple[str, ...] = (AGENT_TUNNEL_ORDER[0],)


@dataclass
class _Upload:
    slot: int
    file_crc: int
    running_crc: int = 0
    data: bytearray = field(default_factory=bytearray)
    chunks: int = 0
    unaligned: bool = False  # a chunk so far was not a multiple of 4 bytes


@dataclass
class _ExtraMotor:
    position_deg: float = 0.0
    speed_deg_s: float = 0.0
    target_deg: float | None = None  # a MotorForDegrees move's end
    seq: int | None = None


@dataclass
class _Wheel:
    mode: str = "brake"  # "brake", "speed" (speed control) or "power" (duty)
    target_deg_s: float = 0.0
    speed_deg_s: float = 0.0  # the ramped set point
    reference_deg: float = 0.0
    duty: float = 0.0


@dataclass
class _Move:
    seq: int
    lead: int  # the wheel whose rotation is counted
    start_deg: int
    degrees: int
    last_deg: int
    last_progress_s: float


@dataclass
class _Agent:
    version: str
    ready_s: float
    booted: bool = False
    decoder: t.TunnelDecoder = field(default_factory=lambda: t.TunnelDecoder(Role.DEVICE))
    pair: tuple[int, int] | None = None  # body wheel index of (left, right)
    acceleration_deg_s2: float = 1000.0
    watchdog_s: float | None = None
    move: _Move | None = None
    watch_port: int = t.NO_PORT
    watch_s: float = 0.0
    next_report_s: float | None = None


class SpikeHub:
    """The simulated hub on a body (see the module docstring).

    Args:
        body: The simulated body the hub drives and senses.
        config: How the hub is built.

    Attributes:
        slots: Stored programs by slot.
        running_slot: The slot of the running program, or ``None``.
        tunnel_without_program: TunnelMessages received while no program ran (they crash a
            real hub).
        tunnel_lost: TunnelMessages that reached a program not reading the tunnel yet.
        refused_chunks: Each refused TransferChunkRequest: (1-based chunk number, why).
        tunnel_tried: The tunnel forms the last started agent tried, in order.
        tunnel_form: The form it bound the tunnel with, or ``None``.
        buttons: The hub buttons held down now (``"left"``, ``"right"``).
        extra_motors: The motors on the profile's ``motors`` ports, by port.
    """

    def __init__(self, body: Body, config: HubConfig | None = None) -> None:
        self.body = body
        self.config = config or HubConfig()
        self.codec = SpikeCodec(Role.DEVICE)
        self.name = self.config.name
        self.slots: dict[int, bytes] = dict(self.config.programs)
        self.running_slot: int | None = None
        self.tunnel_without_program = 0
        self.tunnel_lost = 0
        self.refused_chunks: list[tuple[int, str]] = []
        self.tunnel_tried: list[str] = []
        self.tunnel_form: str | None = None
        self.buttons: set[str] = set()
        self._releases: dict[str, float] = {}
        self._presses = sorted(getattr(body.world, "button_presses", ()))
        self.extra_motors = {port: _ExtraMotor() for port in self.config.options.motors}
        self._out = bytearray()
        self._upload: _Upload | None = None
        self._agent: _Agent | None = None
        self._notify_s = 0.0
        self._next_notify_s = math.inf
        self._wheels = [_Wheel(), _Wheel()]
        self._last_step_s = 0.0
        self._pixels = (0,) * 25
        mm_per_deg = body.spec.mm_per_tick
        self._max_deg_s = body.spec.max_wheel_speed_mm_s / mm_per_deg
        options = self.config.options
        # Hub port -> body wheel index of each drive motor.
        self._motor_ports = {options.left_motor: 0, options.right_motor: 1}

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """A new host session: fresh framing state; notifications off until requested."""
        self.codec = SpikeCodec(Role.DEVICE)
        self._notify_s = 0.0
        self._next_notify_s = math.inf
        self._last_step_s = now_s

    def receive(self, data: bytes, now_s: float) -> None:
        """Decode requests and answer them."""
        self.codec.receive_data(data)
        for message in readable(self.codec):  # the firmware drops what it cannot read
            self._handle(message, now_s)

    def step(self, now_s: float) -> None:
        """Run the motor control, the agent's timers and the notifications up to ``now_s``."""
        dt_s = max(0.0, now_s - self._last_step_s)
        self._last_step_s = now_s
        self._scripted_buttons(now_s)
        agent = self._agent
        if agent is not None:
            self._agent_timers(agent, now_s)
        self._control_motors(dt_s)
        self._turn_extra_motors(dt_s)
        if now_s >= self._next_notify_s - 1e-9:  # sums of 0.005 s steps are not exact
            self._send(self._notification())
            self._next_notify_s += self._notify_s
            if self._next_notify_s < now_s:
                self._next_notify_s = now_s + self._notify_s

    def pending_input_bytes(self) -> int:
        """Request bytes received and not yet a whole message (a frame the host has not
        finished)."""
        return self.codec.buffered_bytes

    def read_output(self) -> bytes:
        """Take the bytes sent since the last call."""
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Power loss: the program ends and the motors stop."""
        self._end_program(notify=False)

    def press_centre_button(self) -> None:
        """What the hub's centre button does to a running program: end it, and say so."""
        self._end_program(notify=True)

    def press_button(self, name: str, duration_s: float | None = None) -> None:
        """Hold the hub's ``left`` or ``right`` button down (for ``duration_s``, or until
        :meth:`release_button`).

        Raises:
            ValueError: Another button name (the centre one ends the program:
                :meth:`press_centre_button`).
        """
        if name not in t.BUTTON_BITS:
            raise ValueError(f"the hub has no '{name}' button a program can read")
        self.buttons.add(name)
        self._releases.pop(name, None)
        if duration_s is not None:
            self._releases[name] = self._last_step_s + duration_s

    def release_button(self, name: str) -> None:
        """Let go of a button."""
        self.buttons.discard(name)
        self._releases.pop(name, None)

    def _scripted_buttons(self, now_s: float) -> None:
        while self._presses and self._presses[0][0] <= now_s + 1e-9:
            _, name, duration_s = self._presses.pop(0)
            self._last_step_s = now_s
            self.press_button(name, duration_s)
        for name, release_s in list(self._releases.items()):
            if now_s >= release_s - 1e-9:
                self.release_button(name)

    # ------------------------------------------------------------------------------ helpers

    def _send(self, message: m.Message) -> None:
        self._out += self.codec.send(message)

    def _handle(self, msg: m.Message, now_s: float) -> None:
        cfg = self.config
        if isinstance(msg, m.InfoRequest):
            self._send(
                m.InfoResponse(
                    *cfg.rpc_version[:2],
                    cfg.rpc_version[2],
                    *cfg.firmware_version[:2],
                    cfg.firmware_version[2],
                    cfg.max_packet_size,
                    cfg.max_message_size,
                    cfg.max_chunk_size,
                    m.ProductGroupDevice.SPIKE_PRIME,
                )
            )
        elif isinstance(msg, m.GetHubNameRequest):
            self._send(m.GetHubNameResponse(self.name))
        elif isinstance(msg, m.SetHubNameRequest):
            self.name = msg.name
            self._send(m.SetHubNameResponse(_ACK))
        elif isinstance(msg, m.DeviceUuidRequest):
            self._send(m.DeviceUuidResponse(cfg.device_uuid))
        elif isinstance(msg, m.DeviceNotificationRequest):
            self._notify_s = msg.interval_ms / 1000.0
            self._next_notify_s = now_s + self._notify_s if msg.interval_ms else math.inf
            self._send(m.DeviceNotificationResponse(_ACK))
        elif isinstance(msg, m.ProgramFlowRequest):
            self._program_flow(msg, now_s)
        elif isinstance(msg, m.ClearSlotRequest):
            found = msg.slot in self.slots
            if found:
                if self.running_slot == msg.slot:
                    self._end_program(notify=True)
                del self.slots[msg.slot]
            self._send(m.ClearSlotResponse(_ACK if found else _NACK))
        elif isinstance(msg, m.StartFileUploadRequest):
            if self.running_slot == msg.slot:
                self._end_program(notify=True)
            self._upload = _Upload(msg.slot, msg.crc32)
            self._send(m.StartFileUploadResponse(_ACK))
        elif isinstance(msg, m.TransferChunkRequest):
            refused = self._take_chunk(msg)
            if refused is not None:
                number = self._upload.chunks + 1 if self._upload else 1
                self.refused_chunks.append((number, refused))
            self._send(m.TransferChunkResponse(_NACK if refused else _ACK))
        elif isinstance(msg, m.StartFirmwareUploadRequest):
            self._send(m.StartFirmwareUploadResponse(_NACK, 0))  # the simulator has no flash
        elif isinstance(msg, m.BeginFirmwareUpdateRequest):
            self._send(m.BeginFirmwareUpdateResponse(_NACK))
        elif isinstance(msg, m.TunnelMessage):
            self._tunnel(msg.data, now_s)

    def _take_chunk(self, msg: m.TransferChunkRequest) -> str | None:
        """Store a chunk; why it is refused, or ``None`` if it is taken."""
        upload = self._upload
        if upload is None:
            return "no upload was started"
        if len(msg.data) > self.config.max_chunk_size:
            return f"{len(msg.data)} bytes is more than the {self.config.max_chunk_size}-byte max"
        if upload.unaligned:
            return "it follows a chunk whose size is not a multiple of 4 bytes"
        expected = crc32(msg.data, upload.running_crc)
        if msg.running_crc32 != expected:
            return f"running CRC 0x{msg.running_crc32:08x} is not 0x{expected:08x}"
        upload.chunks += 1
        upload.data += msg.data
        upload.running_crc = expected
        upload.unaligned = len(msg.data) % 4 != 0
        if expected == upload.file_crc and crc32(bytes(upload.data)) == upload.file_crc:
            self.slots[upload.slot] = bytes(upload.data)
            self._upload = None
        return None

    # ------------------------------------------------------------------------ program flow

    def _program_flow(self, msg: m.ProgramFlowRequest, now_s: float) -> None:
        if msg.action is m.ProgramAction.STOP:
            self._send(m.ProgramFlowResponse(_ACK))
            self._end_program(notify=True)
            return
        source = self.slots.get(msg.slot)
        if source is None:
            self._send(m.ProgramFlowResponse(_NACK))
            return
        self._end_program(notify=True)
        self._send(m.ProgramFlowResponse(_ACK))
        self._send(m.ProgramFlowNotification(m.ProgramAction.START))
        self.running_slot = msg.slot
        version = t.agent_version_of(source)
        if version is not None and self._bind_tunnel():
            self._agent = _Agent(version, now_s + self.config.agent_boot_s)

    def _bind_tunnel(self) -> bool:
        """The agent's tunnel binding, as the real agent tries it; False if none is found."""
        self.tunnel_tried = []
        self.tunnel_form = None
        for form in AGENT_TUNNEL_ORDER:
            self.tunnel_tried.append(form)
            if form in self.config.tunnel_forms:
                self.tunnel_form = form
                return True
        firmware = ".".join(str(part) for part in self.config.firmware_version)
        self._send(
            m.ConsoleNotification(
                f"roboscript agent: no tunnel on this hub (firmware {firmware}): tried "
                + " and ".join(self.tunnel_tried)
                + "; update the hub with the SPIKE App 3"
            )
        )
        return False

    def _end_program(self, *, notify: bool) -> None:
        self._brake()
        self._agent = None
        if self.running_slot is not None:
            self.running_slot = None
            if notify:
                self._send(m.ProgramFlowNotification(m.ProgramAction.STOP))

    def _agent_timers(self, agent: _Agent, now_s: float) -> None:
        if not agent.booted and now_s >= agent.ready_s:
            agent.booted = True
            self._send(
                m.ConsoleNotification(f"{agent.version} ready, tunnel from {self.tunnel_form}")
            )
        if agent.next_report_s is not None and now_s >= agent.next_report_s - 1e-9:
            agent.next_report_s += agent.watch_s
            if agent.next_report_s < now_s:
                agent.next_report_s = now_s + agent.watch_s
            self._reply(self._report(agent))
        if agent.watchdog_s is not None and now_s >= agent.watchdog_s:
            agent.watchdog_s = None
            self._brake()
        if agent.move is not None:
            self._check_move(agent, agent.move, now_s)

    # ------------------------------------------------------------------------------ tunnel

    def _tunnel(self, data: bytes, now_s: float) -> None:
        agent = self._agent
        if self.running_slot is None:
            self.tunnel_without_program += 1
            return
        if agent is None or not agent.booted:
            self.tunnel_lost += 1
            return
        decoder = agent.decoder
        decoder.feed(data)
        while True:
            try:
                record = decoder.next_record()
            except RemoteProtocolError as fault:
                reason = {
                    "tunnel_length": t.RefuseReason.BAD_LENGTH,
                    "tunnel_value": t.RefuseReason.BAD_VALUE,
                }.get(fault.kind, t.RefuseReason.UNKNOWN_COMMAND)
                self._reply(t.Refused(decoder.last_op or 0, reason))
                continue
            if record is None:
                return
            self._command(agent, record, now_s)

    def _reply(self, record: t.Record) -> None:
        self._send(m.TunnelMessage(record.encode()))

    def _command(self, agent: _Agent, record: t.Record, now_s: float) -> None:
        log = self.body.log
        motion = isinstance(record, t.Tank | t.TankForDegrees | t.Power)
        if motion and agent.pair is None:
            self._reply(t.Refused(record.op, t.RefuseReason.NOT_CONFIGURED))
            return
        if motion or isinstance(record, t.Stop):
            self._cancel_move(agent)
        if isinstance(record, t.MotorRun | t.MotorForDegrees | t.MotorStop | t.Stop | t.Watch):
            self._other_command(agent, record, now_s)
            return
        if isinstance(record, t.VersionQuery):
            self._reply(t.Version(agent.version))
        elif isinstance(record, t.Configure):
            left = self._motor_ports.get(record.left_port)
            right = self._motor_ports.get(record.right_port)
            if left is None or right is None:
                self._reply(t.Refused(record.op, t.RefuseReason.BAD_VALUE))  # no motor there
            else:
                agent.pair = (left, right)
        elif isinstance(record, t.Tank):
            agent.acceleration_deg_s2 = float(record.acceleration_deg_s2)
            self._run(agent, record.left_deg_s, record.right_deg_s)
            agent.watchdog_s = now_s + record.watchdog_ms / 1000.0 if record.watchdog_ms else None
        elif isinstance(record, t.TankForDegrees):
            self._start_move(agent, record, now_s)
        elif isinstance(record, t.Power):
            assert agent.pair is not None
            for index, duty in zip(agent.pair, (record.left_duty, record.right_duty), strict=True):
                wheel = self._wheels[index]
                wheel.mode = "power"
                wheel.duty = duty / t.MAX_DUTY
            agent.watchdog_s = now_s + record.watchdog_ms / 1000.0 if record.watchdog_ms else None
        elif isinstance(record, t.Beep):
            log.tones.append((now_s, float(record.frequency_hz), record.duration_ms / 1000.0))
        elif isinstance(record, t.ShowText):
            log.display = record.text
            self._pixels = (0,) * 12 + (100,) + (0,) * 12 if record.text else (0,) * 25
        elif isinstance(record, t.ClearDisplay):
            log.display = ""
            self._pixels = (0,) * 25

    def _other_command(self, agent: _Agent, record: t.Record, now_s: float) -> None:
        """Stop, Watch and the commands for one extra motor."""
        if isinstance(record, t.Watch):
            agent.watch_port = record.color_port
            agent.watch_s = record.interval_ms / 1000.0
            agent.next_report_s = now_s if record.interval_ms else None
            return
        if isinstance(record, t.Stop):
            agent.watchdog_s = None
            self._brake(others=False)
            return
        assert isinstance(record, t.MotorRun | t.MotorForDegrees | t.MotorStop)
        drive = set(self._motor_ports) if agent.pair is not None else set()
        if record.port in drive:
            self._reply(t.Refused(record.op, t.RefuseReason.BAD_VALUE))
            return
        motor = self.extra_motors.get(record.port)
        if motor is None:
            # The real motor module raises on an empty port; the agent refuses the command.
            self._reply(t.Refused(record.op, t.RefuseReason.BAD_VALUE))
            return
        self._end_extra_move(record.port, motor, t.MoveStatus.CANCELLED)
        if isinstance(record, t.MotorRun):
            motor.speed_deg_s = float(record.speed_deg_s)
            agent.watchdog_s = now_s + record.watchdog_ms / 1000.0 if record.watchdog_ms else None
        elif isinstance(record, t.MotorForDegrees):
            sign = 1.0 if record.degrees >= 0 else -1.0
            motor.speed_deg_s = sign * min(float(record.speed_deg_s), _EXTRA_MOTOR_MAX_DEG_S)
            motor.target_deg = motor.position_deg + record.degrees
            motor.seq = record.seq
        else:
            motor.speed_deg_s = 0.0

    def _end_extra_move(self, port: int, motor: _ExtraMotor, status: t.MoveStatus) -> None:
        if motor.seq is not None:
            seq, motor.seq, motor.target_deg = motor.seq, None, None
            motor.speed_deg_s = 0.0
            self._reply(t.MoveDone(seq, status))

    def _turn_extra_motors(self, dt_s: float) -> None:
        for port, motor in self.extra_motors.items():
            speed = max(-_EXTRA_MOTOR_MAX_DEG_S, min(_EXTRA_MOTOR_MAX_DEG_S, motor.speed_deg_s))
            motor.position_deg += speed * dt_s
            target = motor.target_deg
            if target is not None and (motor.position_deg - target) * speed >= 0:
                motor.position_deg = target
                self._end_extra_move(port, motor, t.MoveStatus.DONE)

    def _report(self, agent: _Agent) -> t.Report:
        reflection = t.NO_REFLECTION
        if agent.watch_port != t.NO_PORT and agent.watch_port == self.config.options.color:
            reflection = round(self._floor_reading().reflection_percent)
        bits = sum(t.BUTTON_BITS[name] for name in self.buttons)
        return t.Report(reflection, bits)

    def _run(self, agent: _Agent, left_deg_s: float, right_deg_s: float) -> None:
        assert agent.pair is not None
        for index, target in zip(agent.pair, (left_deg_s, right_deg_s), strict=True):
            wheel = self._wheels[index]
            if wheel.mode != "speed":
                wheel.mode = "speed"
                wheel.speed_deg_s = self.body.wheel_speed_mm_s[index] / self.body.spec.mm_per_tick
                wheel.reference_deg = float(self.body.ticks[index])
            wheel.target_deg_s = float(target)

    def _start_move(self, agent: _Agent, record: t.TankForDegrees, now_s: float) -> None:
        assert agent.pair is not None
        agent.watchdog_s = None
        agent.acceleration_deg_s2 = 1000.0  # motor_pair's default ramp
        self._run(agent, record.left_deg_s, record.right_deg_s)
        side = 0 if abs(record.left_deg_s) >= abs(record.right_deg_s) else 1
        lead = agent.pair[side]
        ticks = self.body.ticks[lead]
        agent.move = _Move(record.seq, lead, ticks, record.degrees, ticks, now_s)

    def _check_move(self, agent: _Agent, move: _Move, now_s: float) -> None:
        ticks = self.body.ticks[move.lead]
        if ticks != move.last_deg:
            move.last_deg = ticks
            move.last_progress_s = now_s
        if abs(ticks - move.start_deg) >= move.degrees:
            self._finish_move(agent, t.MoveStatus.DONE)
        elif now_s - move.last_progress_s >= _STALL_S:
            self._finish_move(agent, t.MoveStatus.STALLED)

    def _finish_move(self, agent: _Agent, status: t.MoveStatus) -> None:
        move = agent.move
        assert move is not None
        agent.move = None
        self._brake(others=False)
        self._reply(t.MoveDone(move.seq, status))

    def _cancel_move(self, agent: _Agent) -> None:
        move = agent.move
        if move is not None:
            agent.move = None
            self._reply(t.MoveDone(move.seq, t.MoveStatus.CANCELLED))

    # ----------------------------------------------------------------------- motor control

    def _brake(self, *, others: bool = True) -> None:
        """Brake the wheels, and with ``others`` the extra motors too (not for Stop)."""
        for wheel in self._wheels:
            wheel.mode = "brake"
            wheel.target_deg_s = wheel.speed_deg_s = wheel.duty = 0.0
        self.body.set_power(0.0, 0.0)
        if not others:
            return
        for port, motor in self.extra_motors.items():
            self._end_extra_move(port, motor, t.MoveStatus.CANCELLED)
            motor.speed_deg_s = 0.0

    def _control_motors(self, dt_s: float) -> None:
        agent = self._agent
        ramp = (agent.acceleration_deg_s2 if agent else 0.0) * dt_s
        power = [0.0, 0.0]
        for index, wheel in enumerate(self._wheels):
            if wheel.mode == "power":
                power[index] = wheel.duty
            elif wheel.mode == "speed":
                change = wheel.target_deg_s - wheel.speed_deg_s
                wheel.speed_deg_s += max(-ramp, min(ramp, change)) if ramp else change
                wheel.reference_deg += wheel.speed_deg_s * dt_s
                ticks = float(self.body.ticks[index])
                lag = max(-_MAX_LAG_DEG, min(_MAX_LAG_DEG, wheel.reference_deg - ticks))
                wheel.reference_deg = ticks + lag  # a stalled wheel does not wind up
                power[index] = wheel.speed_deg_s / self._max_deg_s + _KP_POWER_PER_DEG * lag
            else:
                power[index] = self._braking_power(index)
        self.body.set_power(power[0], power[1])

    def _braking_power(self, index: int) -> float:
        body = self.body
        power = -_BRAKE_GAIN * body.wheel_speed_mm_s[index] / body.spec.max_wheel_speed_mm_s
        return power if abs(power) >= body.spec.dead_band else 0.0

    # ------------------------------------------------------------------------ notification

    def _notification(self) -> m.DeviceNotification:
        body = self.body
        yaw = -round(body.imu_heading_deg())  # the hub counts yaw counter-clockwise
        yaw = (yaw + 180) % 360 - 180
        devices: list[m.DeviceMessage] = [
            m.DeviceBattery(100),
            m.DeviceImu(m.HubFace.TOP, m.HubFace.TOP, yaw, 0, 0, 0, 0, 1000, 0, 0, 0),
            m.DeviceMatrix5x5(self._pixels),
        ]
        options = self.config.options
        for port in range(t.PORT_COUNT):
            if port in self._motor_ports:
                devices.append(self._motor(port, self._motor_ports[port]))
            elif port in self.extra_motors:
                devices.append(self._extra_motor(port, self.extra_motors[port]))
            elif port == options.force:
                pressed = any(body.bumpers_pressed())
                devices.append(
                    m.DeviceForce(
                        m.HubPort(port), _FORCE_PRESSED_PERCENT if pressed else 0, pressed
                    )
                )
            elif port == options.distance:
                reading = body.range_mm()
                distance = -1 if reading is None else max(40, min(2000, round(reading)))
                devices.append(m.DeviceDistance(m.HubPort(port), distance))
            elif port == options.color:
                devices.append(self._color(port))
        return m.DeviceNotification(tuple(devices))

    def _motor(self, port: int, index: int) -> m.DeviceMotor:
        body = self.body
        mirror = -1 if index == 0 else 1  # the left motor is mounted mirrored
        position = mirror * body.ticks[index]
        speed_deg_s = mirror * body.wheel_speed_mm_s[index] / body.spec.mm_per_tick
        speed = max(-100, min(100, round(100 * speed_deg_s / self._max_deg_s)))
        power = max(-10000, min(10000, round(mirror * body.power[index] * 10000)))
        absolute = (position + 180) % 360 - 180
        return m.DeviceMotor(
            m.HubPort(port), m.MotorDeviceType.MEDIUM_MOTOR, absolute, power, speed, position
        )

    def _extra_motor(self, port: int, motor: _ExtraMotor) -> m.DeviceMotor:
        position = round(motor.position_deg)
        speed = max(-100, min(100, round(100 * motor.speed_deg_s / _EXTRA_MOTOR_MAX_DEG_S)))
        absolute = (position + 180) % 360 - 180
        return m.DeviceMotor(
            m.HubPort(port), m.MotorDeviceType.MEDIUM_MOTOR, absolute, speed * 100, speed, position
        )

    def _floor_reading(self) -> FloorReading:
        return self.body.floor_reading(_COLOR_SENSOR_FORWARD_MM)

    def _color(self, port: int) -> m.DeviceColor:
        reading = self._floor_reading()
        red, green, blue = reading.rgb
        return m.DeviceColor(m.HubPort(port), m.Color[reading.color.upper()], red, green, blue)


def simulated_device(profile: RobotProfile) -> Callable[[Body], SpikeHub]:
    """The SPIKE unit's simulated device factory: a hub wired as the profile's options say.

    Raises:
        ProfileError: The profile's options are invalid (checked here, before any body).
    """
    config = HubConfig(SpikeOptions.from_mapping(profile.options, profile=profile.name))
    return lambda body: SpikeHub(body, config)
