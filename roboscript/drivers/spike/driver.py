"""The SPIKE Prime host driver: the App 3 hub protocol plus roboscript's agent on the hub.

The hub protocol has no motor commands, so the driver runs a small program of its own on the
hub (the *agent*, ``roboscript/drivers/spike/agent/hub_agent.py``) and sends it commands over
TunnelMessage (:mod:`roboscript.drivers.spike.tunnel`). Sensor readings come from the
firmware's own DeviceNotification messages.

Handshake, advanced in :meth:`SpikeDriver.tick` on the scheduler clock (never a fixed sleep;
one request at a time, each answered within ``_REPLY_TIMEOUT_S``):

1. ``InfoRequest`` every 0.5 s until ``InfoResponse``: the max packet size goes to a BLE port
   (it writes in pieces of that size), the max chunk size sets the upload chunks. The hub's
   name is asked for ``describe()``.
2. ``ProgramFlowRequest(start, agent slot)``. A NACK (empty slot) means: upload.
3. ``VersionQuery`` over the tunnel every 0.25 s, and only once the hub has said the program
   started *and* the agent has printed its ready line (its tunnel callback is registered):
   a TunnelMessage while no program is ready for it crashes the hub (spike-prime-docs
   issue 8).
   The same ``AGENT_VERSION`` as the agent source in this package -> 5. Another version, no
   answer within 3 s (some other program is in the slot), or the program ending -> 4.
4. Upload: ``ProgramFlowRequest(stop)``, ``ClearSlotRequest`` (a NACK is fine),
   ``StartFileUploadRequest`` (the name as LEGO's example sends it: UTF-8, one NUL, slot, CRC)
   with the file CRC, then ``TransferChunkRequest`` one at a time with the running CRC (each
   chunk a multiple of 4 bytes but the last, so that the running CRC ends at the file CRC),
   then 2 again. A refused chunk ends connecting with a sentence naming it; if the fresh agent
   never prints its ready line or does not answer, connecting fails with a sentence saying
   which (and what the hub printed).
5. ``Configure`` (the drive motor ports), ``Watch`` (the colour sensor's port: the agent
   reports its reflection and the hub buttons every ``telemetry_ms``) and
   ``DeviceNotificationRequest(telemetry_ms)``; ready at the first DeviceNotification that
   holds both drive motors.

Wheel speeds are held by the hub (``motor_pair.move_tank``): the driver sends ``Tank`` in
motor degrees per second when the rounded speeds change, and again every 0.5 s with a 1.5 s
watchdog, so a host that dies leaves the wheels running for at most 1.5 s. Zero speeds send
``Stop`` (brake). Wheel distances come from the motors' positions (the left motor is mounted
mirrored, so its position is negated); the heading from the IMU yaw, which the hub counts
counter-clockwise (negated: roboscript's turns are clockwise positive). A device value outside
its documented range (a distance over 2000 mm, a force over 100 %, a motor that moved faster
than any SPIKE motor turns) is counted with the garbage (``out_of_range``) and skipped: the
last good reading stands.

:meth:`SpikeDriver.stop_all` sends ``Stop`` over the tunnel (if the agent runs) and
``ProgramFlowRequest(stop)``; a later motion command starts the agent again.
"""

from __future__ import annotations

import importlib.resources
import logging
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

from roboscript import capabilities as cap
from roboscript.angles import wrap_deg
from roboscript.clock import Clock
from roboscript.codec import Role
from roboscript.drivers.base import Driver, PendingRequest, WheelDriveBase
from roboscript.drivers.spike import messages as m
from roboscript.drivers.spike import tunnel as t
from roboscript.drivers.spike.crc import crc32
from roboscript.drivers.spike.options import SpikeOptions, port_name
from roboscript.errors import DeviceError, LinkClosedError, LinkTimeoutError
from roboscript.robot_profile import RobotProfile
from roboscript.transport.link import Link

__all__ = ["AGENT_FILE_NAME", "SpikeDriver", "agent_source"]

logger = logging.getLogger(__name__)

_Phase = Literal["info", "start", "version", "upload", "configure", "ready", "stopped"]
"""Where the hub's handshake is (see the module docstring); ``stopped`` after a stop."""

AGENT_FILE_NAME = "roboscript_agent.py"
"""The name the agent is stored under on the hub."""

_INFO_RETRY_S = 0.5
_REPLY_TIMEOUT_S = 2.0
_VERSION_RETRY_S = 0.25
_VERSION_TIMEOUT_S = 3.0
_READY_LINE = " ready, tunnel from "
"""What the agent prints once its tunnel callback is registered (``hub_agent.main``)."""
_TANK_REFRESH_S = 0.5
_MOVE_RESULTS = {
    t.MoveStatus.DONE: "done",
    t.MoveStatus.STALLED: "stalled",
    t.MoveStatus.CANCELLED: "cancelled",
    t.MoveStatus.FAILED: "failed",
}
_DARK_PERCENT = 50.0
"""Reflection below which the colour sensor, read as a line sensor, is over a dark line."""
_WATCHDOG_MS = 1500
_ACCELERATION_DEG_S2 = 4000
_BEEP_VOLUME_PERCENT = 100
_CONSOLE_LINES = 5
_MAX_MOTOR_DEG_S = 2000.0
"""Faster than any SPIKE motor turns (the large motor's top speed is about 1050 deg/s): a
position that moved faster between two readings is not a real reading."""
_MOTOR_JUMP_SLACK_DEG = 90.0
"""Position change allowed on top of ``_MAX_MOTOR_DEG_S`` (a late first reading)."""


def _impossible(device: m.DeviceMessage) -> str | None:
    """Why ``device`` holds a value no SPIKE hub reports (documented ranges), or ``None``."""
    checks: list[tuple[str, int, int, int]] = []
    if isinstance(device, m.DeviceMotor):
        checks = [
            ("absolute position", device.absolute_position_deg, -180, 179),
            ("speed", device.speed_percent, -100, 100),
        ]
    elif isinstance(device, m.DeviceImu):
        checks = [
            ("yaw", device.yaw, -180, 180),
            ("pitch", device.pitch, -180, 180),
            ("roll", device.roll, -180, 180),
        ]
    elif isinstance(device, m.DeviceDistance):
        checks = [("distance", device.distance_mm, -1, 2000)]
    elif isinstance(device, m.DeviceForce):
        checks = [("force", device.force_percent, 0, 100)]
    elif isinstance(device, m.DeviceColor):
        checks = [
            (name, value, 0, 1023)
            for name, value in zip(
                ("red", "green", "blue"), (device.red, device.green, device.blue), strict=True
            )
        ]
    for name, value, low, high in checks:
        if not low <= value <= high:
            return f"{type(device).__name__} {name} {value} is outside {low}..{high}"
    return None


def agent_source() -> bytes:
    """The agent program, as uploaded to the hub (package data)."""
    package = importlib.resources.files("roboscript.drivers.spike")
    return package.joinpath("agent", "hub_agent.py").read_bytes()


@dataclass
class _Request:
    message: m.Message
    reply_type: type[m.Message]
    on_reply: Callable[[Any], None]


def _answers(request: _Request, message: object) -> bool:
    return isinstance(message, request.reply_type)


def _no_answer(request: _Request, tries: int) -> LinkTimeoutError:
    del tries  # one try: the hub answers every request, or is gone
    return LinkTimeoutError(
        f"the SPIKE hub did not answer {type(request.message).__name__} "
        f"within {_REPLY_TIMEOUT_S:g} s"
    )


class SpikeDriver(Driver):
    """Host side of the SPIKE Prime hub and its agent (see the module docstring)."""

    protocol = "spike"

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        super().__init__(link, profile, clock)
        self.options = SpikeOptions.from_mapping(profile.options, profile=profile.name)
        # The hub streams DeviceNotifications every telemetry_ms once ready: ten missed in a
        # row (at least a second) is a hub that is gone (the drivers' common rule, base.py).
        self.silence_limit_s = max(1.0, 10 * self.options.telemetry_ms / 1000.0)
        self.agent = agent_source()
        version = t.agent_version_of(self.agent)
        assert version is not None, "the packaged agent has no AGENT_VERSION"
        self.agent_version = version
        self.info: m.InfoResponse | None = None
        self.hub_name: str | None = None
        self.hub_agent_version: str | None = None
        self.uploaded = False
        self.console: deque[str] = deque(maxlen=_CONSOLE_LINES)
        self.move_results: dict[int, t.MoveStatus] = {}
        self._phase: _Phase = "info"
        self._agent_said_ready = False
        self._console_tail = ""  # the end of the last console text, for a ready line cut in two
        self._now_s = 0.0
        self._pending: PendingRequest[_Request] = PendingRequest(
            timeout_s=_REPLY_TIMEOUT_S, retries=0, matches=_answers, give_up=_no_answer
        )
        self._next_probe_s = 0.0
        self._version_deadline_s = 0.0
        self._chunks: list[bytes] = []
        self._running_crc = 0
        self._agent_running = False
        self._stopping = False
        # Sensor cache (raw hub values; None until the first reading).
        self._positions: dict[int, int] = {}
        self._position_at_s: dict[int, float] = {}
        self._origins: tuple[int, int] | None = None
        self._yaw: int | None = None
        self._yaw_origin = 0
        self.distance_mm: int | None = None
        self.force_percent: int | None = None
        self.force_pressed = False
        self.color: m.DeviceColor | None = None
        self.reflection_percent: int | None = None
        self.buttons_pressed: frozenset[str] = frozenset()
        self.motor_ports_found: set[int] = set()
        # Extra motor port -> speed held (deg/s; 0 for a move or a stop): every port used.
        self._motor_runs: dict[int, int] = {}
        self._motor_sent_at_s = -math.inf
        self._chunk_count = 0
        # Set points.
        self._target_mm_s = (0.0, 0.0)
        self._sent_deg_s: tuple[int, int] | None = None
        self._sent_at_s = -math.inf
        self._power: tuple[int, int] | None = None
        self._queue: list[t.Record] = []
        self._move_seq = 0
        self._mm_per_deg = math.pi * profile.wheel_diameter_mm / profile.ticks_per_rev

    # ----------------------------------------------------------------------------- handshake

    def start(self) -> None:
        """Send the first InfoRequest."""
        self._now_s = self.clock.now()
        self._probe_info()

    def _probe_info(self) -> None:
        self.link.send(m.InfoRequest())
        self._next_probe_s = self._now_s + _INFO_RETRY_S

    def _request(
        self, message: m.Message, reply_type: type[m.Message], on_reply: Callable[[Any], None]
    ) -> None:
        self._pending.cancel()  # one request at a time: a new one replaces any other
        self._pending.sent(_Request(message, reply_type, on_reply), self._now_s)
        self.link.send(message)

    def _on_info(self, info: m.InfoResponse) -> None:
        self.info = info
        set_packet_size = getattr(self.link.port, "set_max_packet_size", None)
        if callable(set_packet_size):
            set_packet_size(info.max_packet_size)
        self.link.send(m.GetHubNameRequest())
        self._start_agent()

    def _start_agent(self) -> None:
        self._phase = "start"
        self._agent_running = False
        slot = self.options.agent_slot
        self._request(
            m.ProgramFlowRequest(m.ProgramAction.START, slot),
            m.ProgramFlowResponse,
            self._on_started,
        )

    def _on_started(self, reply: m.ProgramFlowResponse) -> None:
        if reply.status is not m.ResponseStatus.ACKNOWLEDGED:
            self._upload_or_fail(f"slot {self.options.agent_slot} is empty", replaces=False)
            return
        self._agent_running = True
        self._phase = "version"
        self._version_deadline_s = self._now_s + _VERSION_TIMEOUT_S
        self._agent_said_ready = False  # the first query waits for the ready line
        self._console_tail = ""

    def _why_silent(self) -> str:
        """Why the program in the slot is given up on: it never printed the agent's ready line
        (a program that is not the agent, or an agent that could not bind the tunnel), or it
        did and then did not answer the VersionQuery."""
        if self._agent_said_ready:
            return "the program in the slot does not answer"
        return f"the program in the slot never said it was ready within {_VERSION_TIMEOUT_S:g} s"

    def _query_version(self) -> None:
        self._tunnel(t.VersionQuery())
        self._next_probe_s = self._now_s + _VERSION_RETRY_S

    def _on_version(self, version: str) -> None:
        self.hub_agent_version = version
        if version == self.agent_version:
            self._configure()
        else:
            why = f"the hub has {version!r}, not {self.agent_version!r}"
            self._upload_or_fail(why, replaces=False)  # an update of roboscript's own agent

    def _firmware(self) -> str:
        info = self.info
        if info is None:
            return "unknown"
        return f"{info.firmware_major}.{info.firmware_minor}.{info.firmware_build}"

    def _upload_or_fail(self, why: str, *, replaces: bool = True) -> None:
        if self.uploaded:
            last = f" (the hub printed: {self.console[-1]})" if self.console else ""
            raise DeviceError(
                f"roboscript's agent did not start on the hub after the upload: {why}{last};"
                f" is the hub (firmware {self._firmware()}) running SPIKE App 3 firmware?"
            )
        slot = self.options.agent_slot
        logger.info("uploading roboscript's agent to slot %d: %s", slot, why)
        if replaces:
            self.notice(f"roboscript's agent replaced the program in slot {slot} of the hub")
        self._phase = "upload"
        self._request(
            m.ProgramFlowRequest(m.ProgramAction.STOP, self.options.agent_slot),
            m.ProgramFlowResponse,
            lambda _: self._clear_slot(),
        )

    def _clear_slot(self) -> None:
        self._agent_running = False
        self._request(  # a NACK only means the slot was empty already
            m.ClearSlotRequest(self.options.agent_slot), m.ClearSlotResponse, self._open_upload
        )

    def _open_upload(self, _: m.ClearSlotResponse) -> None:
        assert self.info is not None
        data = self.agent
        # A running CRC equals the file CRC only if every chunk but the last is a multiple of
        # 4 bytes (the CRC pads each piece to 4 bytes).
        size = max(4, min(self.info.max_chunk_size, self.info.max_message_size - 16) // 4 * 4)
        self._chunks = [data[i : i + size] for i in range(0, len(data), size)]
        self._chunk_count = len(self._chunks)
        self._running_crc = 0
        self._request(
            m.StartFileUploadRequest(AGENT_FILE_NAME, self.options.agent_slot, crc32(data)),
            m.StartFileUploadResponse,
            self._on_upload_opened,
        )

    def _on_upload_opened(self, reply: m.StartFileUploadResponse) -> None:
        if reply.status is not m.ResponseStatus.ACKNOWLEDGED:
            raise DeviceError(
                f"the hub refused to store roboscript's agent in slot {self.options.agent_slot}"
            )
        self._send_chunk()

    def _send_chunk(self) -> None:
        if not self._chunks:
            self.uploaded = True
            self._start_agent()
            return
        chunk = self._chunks.pop(0)
        self._running_crc = crc32(chunk, self._running_crc)
        self._request(
            m.TransferChunkRequest(self._running_crc, chunk),
            m.TransferChunkResponse,
            self._on_chunk,
        )

    def _on_chunk(self, reply: m.TransferChunkResponse) -> None:
        if reply.status is not m.ResponseStatus.ACKNOWLEDGED:
            number = self._chunk_count - len(self._chunks)
            raise DeviceError(
                f"the SPIKE hub refused piece {number} of {self._chunk_count} of roboscript's"
                f" agent (running CRC 0x{self._running_crc:08x}), so the agent was not stored"
            )
        self._send_chunk()

    def _configure(self) -> None:
        self._phase = "configure"
        self._tunnel(t.Configure(self.options.left_motor, self.options.right_motor))
        self._tunnel(t.Watch(self.options.color, self.options.telemetry_ms))
        self._sent_deg_s = None
        self._motor_sent_at_s = -math.inf
        self._power = None
        if self.ready:  # a restart after stop_all: telemetry is on already
            self._phase = "ready"
            return
        self._request(
            m.DeviceNotificationRequest(self.options.telemetry_ms),
            m.DeviceNotificationResponse,
            lambda _: None,
        )

    def _become_ready(self) -> None:
        self._phase = "ready"
        self._origins = (
            self._positions[self.options.left_motor],
            self._positions[self.options.right_motor],
        )
        self._yaw_origin = self._yaw or 0
        self.offer(self._build_capabilities())

    def _build_capabilities(self) -> dict[str, object]:
        makers: dict[str, Callable[[], object]] = {
            cap.DRIVE_BASE: lambda: WheelDriveBase(self, self.wheel_distances_mm),
            cap.RANGE: lambda: _RangeSensor(self),
            cap.BUMPER: lambda: _Bumper(self),
            cap.SPEAKER: lambda: _Speaker(self),
            cap.DISPLAY: lambda: _Display(self),
            cap.HEADING: lambda: _Heading(self),
            cap.FORCE: lambda: _ForceSensor(self),
            cap.COLOR: lambda: _ColorSensor(self),
            cap.LINE: lambda: _ColorLine(self),
            cap.BUTTONS: lambda: _Buttons(self),
            cap.MOTORS: lambda: _Motors(self),
        }
        return self.wanted(makers)

    def describe(self) -> str:
        """The hub's name, firmware and agent version."""
        if self.info is None:
            return self.profile.name
        info = self.info
        name = f" '{self.hub_name}'" if self.hub_name else ""
        firmware = f"{info.firmware_major}.{info.firmware_minor}.{info.firmware_build}"
        return f"SPIKE Prime hub{name} (firmware {firmware}, {self.agent_version})"

    # ------------------------------------------------------------------------- sense / act

    def tick(self, now_s: float, dt_s: float) -> None:
        """Read messages, advance the handshake, watch for silence."""
        self._now_s = now_s
        for message in self.link.poll():
            self._handle(message)
        self._pending.resend_due(now_s)  # one try: raises once the reply is overdue
        if self._phase == "info" and now_s >= self._next_probe_s:
            self._probe_info()
        elif self._phase == "version" and self._pending.in_flight is None:
            if now_s >= self._version_deadline_s:
                self._upload_or_fail(self._why_silent())
            elif self._agent_said_ready and now_s >= self._next_probe_s:
                self._query_version()

    def flush(self, now_s: float, dt_s: float) -> None:
        """Send wheel set points, tones and text to the agent."""
        self._now_s = now_s
        if not self.ready:
            return
        restart = self._wants_motion() or self._queue
        if self._phase == "stopped" and restart and self._pending.in_flight is None:
            self._stopping = False
            self._start_agent()
        if self._phase != "ready":
            return
        self._flush_motion(now_s)
        self._flush_motors(now_s)
        for record in self._queue:
            self._tunnel(record)
        self._queue.clear()

    def _wants_motion(self) -> bool:
        wheels = self._target_mm_s != (0.0, 0.0) or bool(self._power and any(self._power))
        return wheels or any(self._motor_runs.values())

    def _flush_motors(self, now_s: float) -> None:
        """Refresh the extra motors' speeds within their watchdog."""
        running = {port: speed for port, speed in self._motor_runs.items() if speed}
        if not running or now_s - self._motor_sent_at_s < _TANK_REFRESH_S:
            return
        for port, speed in running.items():
            self._tunnel(t.MotorRun(port, speed, _WATCHDOG_MS))
        self._motor_sent_at_s = now_s

    def _flush_motion(self, now_s: float) -> None:
        if self._power is not None:
            if now_s - self._sent_at_s >= _TANK_REFRESH_S:
                self._tunnel(t.Power(*self._power, _WATCHDOG_MS))
                self._sent_at_s = now_s
            return
        left, right = (round(speed / self._mm_per_deg) for speed in self._target_mm_s)
        speeds = (left, right)
        if speeds == (0, 0):
            if self._sent_deg_s != (0, 0):
                self._tunnel(t.Stop())
                self._sent_deg_s = (0, 0)
            return
        if speeds == self._sent_deg_s and now_s - self._sent_at_s < _TANK_REFRESH_S:
            return
        self._tunnel(t.Tank(left, right, _ACCELERATION_DEG_S2, _WATCHDOG_MS))
        self._sent_deg_s = speeds
        self._sent_at_s = now_s

    def _tunnel(self, record: t.Record) -> None:
        self.link.send(m.TunnelMessage(record.encode()))

    def _handle(self, message: object) -> None:
        request = self._pending.answered(message)
        if request is not None:
            request.on_reply(message)
        elif isinstance(message, m.DeviceNotification):
            self._read_devices(message)
        elif isinstance(message, m.TunnelMessage):
            for record in t.decode_records(message.data, Role.HOST):
                self._handle_record(record)
        elif isinstance(message, m.ConsoleNotification):
            # The hub may cut what a program prints into several notifications: the ready line
            # is looked for across the cut.
            text = self._console_tail + message.text
            self._console_tail = text[-len(_READY_LINE) :]
            if _READY_LINE in text and self._phase == "version":
                self._agent_said_ready = True  # the next tick asks for its version
            for line in message.text.splitlines():
                self.console.append(line)
                logger.info("hub says: %s", line)
        elif isinstance(message, m.ProgramFlowNotification):
            if message.action is m.ProgramAction.STOP:
                self._program_stopped()
        elif isinstance(message, m.InfoResponse) and self._phase == "info":
            self._on_info(message)
        elif isinstance(message, m.GetHubNameResponse):
            self.hub_name = message.name

    def _handle_record(self, record: t.Record | Exception) -> None:
        if isinstance(record, Exception):
            logger.debug("unreadable tunnel reply: %s", record)
        elif isinstance(record, t.Version):
            if self._phase == "version":
                self._on_version(record.text)
        elif isinstance(record, t.MoveDone):
            self.move_results[record.seq] = record.status
        elif isinstance(record, t.Report):
            reflection = record.reflection_percent
            self.reflection_percent = None if reflection == t.NO_REFLECTION else reflection
            self.buttons_pressed = record.pressed()
        elif isinstance(record, t.Refused):
            name = t.COMMAND_TYPES.get(record.refused_op)
            what = name.__name__ if name else f"op 0x{record.refused_op:02x}"
            why = record.reason.name.lower().replace("_", " ")
            # The runner fails the running action with this sentence, as for an ASIP board.
            self.device_errors.append(f"the agent on the hub refused {what}: {why}")
            logger.warning("the agent on the hub refused %s: %s", what, why)

    def _program_stopped(self) -> None:
        was_running = self._agent_running
        self._agent_running = False
        if self._stopping or self._phase in ("upload", "start", "stopped"):
            return
        if self._phase == "version":
            self._upload_or_fail("the program in the slot ended")
        elif self._phase == "configure" and not self.ready:
            last = f": {self.console[-1]}" if self.console else ""
            raise DeviceError("roboscript's agent stopped while starting on the SPIKE hub" + last)
        elif was_running and self.ready:
            last = f": {self.console[-1]}" if self.console else ""
            raise LinkClosedError(
                "the program on the SPIKE hub stopped (was the centre button pressed?)" + last
            )

    def _read_devices(self, notification: m.DeviceNotification) -> None:
        options = self.options
        for device in notification.devices:
            impossible = _impossible(device) or self._jumped(device)
            if impossible is not None:
                self.skip_reading(impossible)
                continue
            if isinstance(device, m.DeviceMotor):
                self.motor_ports_found.add(device.port)
                self._positions[device.port] = device.position_deg
                self._position_at_s[device.port] = self._now_s
            elif isinstance(device, m.DeviceImu):
                self._yaw = device.yaw
            elif isinstance(device, m.DeviceDistance) and device.port == options.distance:
                self.distance_mm = device.distance_mm
            elif isinstance(device, m.DeviceForce) and device.port == options.force:
                self.force_percent = device.force_percent
                self.force_pressed = device.pressed
            elif isinstance(device, m.DeviceColor) and device.port == options.color:
                self.color = device
        if self._phase == "configure" and not self.ready:
            missing = [
                port_name(port)
                for port in (options.left_motor, options.right_motor)
                if port not in self._positions
            ]
            if missing:
                found = ", ".join(port_name(p) for p in sorted(self._positions)) or "none"
                raise DeviceError(
                    f"no drive motor on port {' and '.join(missing)} of the SPIKE hub (motors"
                    f" found on: {found}); set left_motor and right_motor in the profile options"
                )
            self._become_ready()

    def _jumped(self, device: m.DeviceMessage) -> str | None:
        """Why a motor's position moved further than a motor can turn since its last reading."""
        if not isinstance(device, m.DeviceMotor) or device.port not in self._positions:
            return None
        moved = abs(device.position_deg - self._positions[device.port])
        elapsed = self._now_s - self._position_at_s[device.port]
        if moved <= _MAX_MOTOR_DEG_S * elapsed + _MOTOR_JUMP_SLACK_DEG:
            return None
        return f"the motor on port {port_name(device.port)} moved {moved} deg in {elapsed:.2f} s"

    def send_stop(self) -> None:
        """Brake the wheels and every other motor used (``Stop``, ``MotorStop`` over the
        tunnel) and stop the agent's program."""
        self._target_mm_s = (0.0, 0.0)
        self._power = None
        self._sent_deg_s = (0, 0)
        self._queue.clear()
        self._pending.cancel()
        if self._agent_running:
            self._tunnel(t.Stop())
            for port in sorted(self._motor_runs):
                self._tunnel(t.MotorStop(port))
        self._motor_runs.clear()
        if self.info is not None:
            # Waited for like a request, so that a restart cannot take this answer for
            # its own and send tunnel messages while no program runs.
            self._request(
                m.ProgramFlowRequest(m.ProgramAction.STOP, self.options.agent_slot),
                m.ProgramFlowResponse,
                lambda _: None,
            )

    def after_stop(self) -> None:
        """The agent counts as stopped; a later motion command starts it again."""
        self._agent_running = False
        self._stopping = True
        if self.ready:
            self._phase = "stopped"

    # ------------------------------------------------------------------ capability plumbing

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Store wheel speed targets, mm/s forward (sent in the act phase)."""
        if self._power is not None:
            self._power = None
            self._sent_deg_s = None
        self._target_mm_s = (left_mm_s, right_mm_s)

    def set_power(self, left_duty: int, right_duty: int) -> None:
        """Drive the wheels at a duty (-10000..10000, forward positive) without speed control.

        Raises:
            LocalProtocolError: A duty out of range.
        """
        t.Power(left_duty, right_duty, _WATCHDOG_MS)  # checks the ranges now, not in flush
        self._power = (left_duty, right_duty)
        self._target_mm_s = (0.0, 0.0)
        self._sent_at_s = -math.inf

    def move_for_degrees(self, degrees: int, left_deg_s: int, right_deg_s: int) -> int:
        """Turn the wheels by ``degrees`` (on the faster wheel) with the hub's own control.

        Returns:
            The move's sequence number; :attr:`move_results` holds its
            :class:`~roboscript.drivers.spike.tunnel.MoveStatus` once the hub reports it.
        """
        self._move_seq = (self._move_seq + 1) % 256
        self._queue.append(t.TankForDegrees(self._move_seq, degrees, left_deg_s, right_deg_s))
        self._sent_deg_s = None
        return self._move_seq

    def queue_record(self, record: t.Record) -> None:
        """Queue a tunnel command (sent in the act phase)."""
        self._queue.append(record)

    def motor_port(self, letter: str) -> int:
        """The port number of an extra motor, by its letter.

        Raises:
            DeviceError: No extra motor on that port (a sentence naming the profile's ports
                and the ports where the hub found motors).
        """
        port = m.HubPort.__members__.get(letter.upper())
        if port is None or int(port) not in self.options.motors:
            listed = ", ".join(port_name(p) for p in self.options.motors) or "none"
            raise DeviceError(
                f"there is no motor on port {letter} in profile {self.profile.name}"
                f" (its 'motors' option lists: {listed})"
            )
        if self.ready and int(port) not in self.motor_ports_found:
            found = ", ".join(port_name(p) for p in sorted(self.motor_ports_found)) or "none"
            raise DeviceError(
                f"the SPIKE hub has no motor plugged into port {letter.upper()}"
                f" (motors found on: {found})"
            )
        return int(port)

    def run_motor(self, port: int, speed_deg_s: int) -> None:
        """Hold an extra motor at ``speed_deg_s`` (0: brake it)."""
        self._motor_runs[port] = speed_deg_s
        self._queue.append(
            t.MotorRun(port, speed_deg_s, _WATCHDOG_MS) if speed_deg_s else t.MotorStop(port)
        )

    def motor_for_degrees(self, port: int, degrees: int, speed_deg_s: int) -> int:
        """Turn an extra motor by ``degrees``; returns the move's sequence number."""
        self._motor_runs[port] = 0
        self._move_seq = (self._move_seq + 1) % 256
        self.move_results.pop(self._move_seq, None)
        self._queue.append(t.MotorForDegrees(self._move_seq, port, degrees, speed_deg_s))
        return self._move_seq

    def wheel_distances_mm(self) -> tuple[float, float]:
        """Distance each wheel has rolled since connection, mm; forward positive."""
        if self._origins is None:
            return (0.0, 0.0)
        left = self._positions[self.options.left_motor] - self._origins[0]
        right = self._positions[self.options.right_motor] - self._origins[1]
        return (-left * self._mm_per_deg, right * self._mm_per_deg)

    def heading_deg(self) -> float | None:
        """Yaw since connection, degrees clockwise, -180..180; ``None`` before any reading."""
        if self._yaw is None:
            return None
        return wrap_deg(-(self._yaw - self._yaw_origin))


class _RangeSensor:
    max_range_mm = 2000.0

    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def distance_mm(self) -> float | None:
        reading = self._driver.distance_mm
        return None if reading is None or reading < 0 else float(reading)


class _Bumper:
    """The force sensor at the front, read as one bump switch."""

    names = ("front",)

    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def pressed(self) -> frozenset[str]:
        return frozenset(self.names) if self._driver.force_pressed else frozenset()


class _ForceSensor:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def force_n(self) -> float | None:
        percent = self._driver.force_percent
        return None if percent is None else percent / 10.0  # full scale is 10 N

    def pressed(self) -> bool:
        return self._driver.force_pressed


class _ColorSensor:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def reflection_percent(self) -> float | None:
        reading = self._driver.reflection_percent
        return None if reading is None else float(reading)

    def color_name(self) -> str | None:
        reading = self._driver.color
        if reading is None or reading.color == m.Color.NONE:
            return None
        if isinstance(reading.color, m.Color):
            return reading.color.name.lower()
        return None

    def rgb(self) -> tuple[int, int, int] | None:
        reading = self._driver.color
        return None if reading is None else (reading.red, reading.green, reading.blue)


class _ColorLine:
    """The colour sensor read as one line sensor (``follow_line``, ``line.center``).

    The reading is darkness 0-1023 (0 white, 1023 black) from the reflection, like the IR
    line sensors of other robots: ``1023 * (100 - reflection) / 100``.
    """

    names = ("center",)
    dark_threshold = 1023.0 * (100.0 - _DARK_PERCENT) / 100.0

    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def values(self) -> tuple[float, ...] | None:
        reflection = self._driver.reflection_percent
        return None if reflection is None else (1023.0 * (100 - reflection) / 100.0,)


class _Buttons:
    names = tuple(t.BUTTON_BITS)

    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def pressed(self) -> frozenset[str]:
        return self._driver.buttons_pressed


class _Motors:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver
        self.ports = tuple(port_name(port) for port in driver.options.motors)

    def run(self, port: str, speed_deg_s: float) -> None:
        self._driver.run_motor(self._driver.motor_port(port), _deg_s(speed_deg_s))

    def run_for_degrees(self, port: str, angle_deg: float, speed_deg_s: float) -> int:
        number = self._driver.motor_port(port)
        speed = max(1, abs(_deg_s(speed_deg_s)))
        return self._driver.motor_for_degrees(number, round(angle_deg), speed)

    def move_result(self, handle: int) -> str | None:
        status = self._driver.move_results.get(handle)
        return None if status is None else _MOVE_RESULTS[status]

    def stop(self, port: str) -> None:
        self._driver.run_motor(self._driver.motor_port(port), 0)


def _deg_s(speed_deg_s: float) -> int:
    return max(-0x7FFF, min(0x7FFF, round(speed_deg_s)))


class _Speaker:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        frequency = max(1, min(0xFFFF, round(frequency_hz)))
        duration = max(1, min(0xFFFF, round(duration_s * 1000)))
        self._driver.queue_record(t.Beep(frequency, duration, _BEEP_VOLUME_PERCENT))


class _Display:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def show_text(self, text: str) -> None:
        data = text.encode("utf-8")[: t.MAX_TEXT_BYTES]
        self._driver.queue_record(t.ShowText(data.decode("utf-8", "ignore")))

    def clear(self) -> None:
        self._driver.queue_record(t.ClearDisplay())


class _Heading:
    def __init__(self, driver: SpikeDriver) -> None:
        self._driver = driver

    def heading_deg(self) -> float | None:
        return self._driver.heading_deg()
