"""The ASIP host driver: MIRTO and other ASIP 1.1 boards.

Handshake (never a fixed sleep): send ``#,?`` every 250 ms until the board answers with its
version or its startup line, ask for the services with ``#,N``, then turn on the events the
robot's capabilities need (``M,A,1`` encoders, ``B,A,50`` bumpers, ``R,A,50`` IR, ``D,A,100``
distance) and turn off the 50 ms analog stream nobody reads (``I,A,0``).

Wheel speeds: with firmware PID the driver sends ``M,R,rpm0,rpm1,ms``. The firmware restarts
its PID on every ``M,R`` (its output drops to the first frame's step), so the driver sends one
only when the integer rpm changes, and refreshes it every 2 s with a 3 s duration: a host that
dies leaves the wheels running for at most 3 s. ``M,c`` and ``M,a`` are not used for moves,
because they round speeds down to whole cm/s (about 2 degrees short on a 90 degree turn);
distances and angles are measured by the actions from the encoders instead.

Because every ``M,R`` restarts the firmware PID from zero output, setpoints that change every
tick (steering: following a wall or a line) are held by the host instead: the driver stops the
firmware PID (``M,S,0``; power requests do not stop it) and runs
:class:`~roboscript.control.WheelSpeedLoop` on the encoder events, sending ``M,M`` power; once
the setpoints have been steady for half a second it hands them back to the firmware.

Without firmware PID (``asip-basic``, or a board that answers ``M,R`` with
``~M,R,2{UNKNOWN_REQUEST}``), the host holds wheel speeds that way all the time.

Stopping sends ``M,S,0`` and ``M,M,0,0`` (``M,S`` needs the dummy argument, see the codec).

A board that restarts (an Uno-style board's reset line, pulled when some program opens its
port, or its supply dipping under the motors' load) forgets every request: its events stop
and its motors with them, and once its sketch has started again it sends its start-up lines.
Start-up lines after the events were turned on mean that: during the handshake the events
are asked for again; once ready the run stops with one sentence
(:data:`BOARD_RESTARTED`), before any setpoint could start the motors of a board that knows
nothing of the mission. (The ``mirtle2017`` sketch is silent for 3.2 s while it starts: the
driver's one-second silence limit usually ends such a run first.)

What ASIP cannot report comes from the profile's options
(:class:`~roboscript.drivers.asip.options.AsipOptions`): the servo count and the LCD's width.
A display row is cut to that width before it is sent, because the board reads the characters
past its 20th as new requests.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import Literal

from roboscript import capabilities as cap
from roboscript.clock import Clock
from roboscript.control import WheelSpeedLoop
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.options import AsipOptions
from roboscript.drivers.base import Driver, PendingRequest, WheelDriveBase
from roboscript.errors import LinkClosedError, LinkTimeoutError
from roboscript.robot_profile import RobotProfile
from roboscript.transport.link import Link

__all__ = ["BOARD_RESTARTED", "AsipDriver"]

logger = logging.getLogger(__name__)

_Phase = Literal["probe", "discover", "pixels", "ready"]
"""The handshake: version probe, service discovery, pixel strip length, done."""

_PROBE_INTERVAL_S = 0.25
_ENCODER_FRAME_S = 0.033
_PID_REFRESH_S = 2.0
_PID_DURATION_MS = 3000
_SILENCE_LIMIT_S = 1.0
_PIXEL_INFO_WAIT_S = 0.5
_POWER_REFRESH_S = 0.5
_ERROR_MEANINGS: dict[int, str] = {
    m.ErrorCode.INVALID_SERVICE: "the sketch has no such service",
    m.ErrorCode.UNKNOWN_REQUEST: "the service does not know that request",
    m.ErrorCode.INVALID_PIN: "that pin cannot do it",
    m.ErrorCode.MODE_UNAVAILABLE: "that pin is reserved",
    m.ErrorCode.INVALID_MODE: "that pin mode is not supported",
    m.ErrorCode.WRONG_MODE: "the pin is in the wrong mode for that",
    m.ErrorCode.INVALID_DEVICE_NUMBER: "there is no device with that number",
    m.ErrorCode.DEVICE_NOT_AVAILABLE: "that device is not fitted",
    m.ErrorCode.I2C_NOT_ENABLED: "I2C is not enabled",
}
"""What ASIP error numbers mean, in words a student can act on."""

BOARD_RESTARTED = (
    "the board restarted {after} (it sent its start-up lines again: its reset line was "
    "pulled or its power dipped), so it forgot the mission's requests and the run stopped"
)
"""The sentence for a board that restarts once ready; ``{after}`` is "12.3 s after
connecting"."""
_START_UP = (m.StartupLine, m.PinModesReply, m.PortMapReply)
"""What only a sketch's ``setup()`` sends unasked (the driver never asks for the last two)."""

_STEERING_GAP_S = 0.3  # two setpoint changes closer than this mean "steering"
_STEADY_S = 0.5  # steady this long and the firmware PID takes the wheels back


def _answers(request: object, message: object) -> bool:
    """True if ``message`` answers the handshake request ``request``."""
    if isinstance(request, m.VersionRequest):
        return isinstance(message, m.VersionReply | m.StartupLine)
    if isinstance(request, m.ServiceNamesRequest):
        return isinstance(message, m.ServiceNamesReply)
    if isinstance(request, m.PixelsInfoRequest):
        return isinstance(message, m.PixelsInfoReply) and message.strip == request.strip
    return False


class AsipDriver(Driver):
    """Host side of ASIP (see the module docstring)."""

    protocol = "asip"

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        super().__init__(link, profile, clock)
        self.firmware_pid = profile.firmware_pid
        self.options = AsipOptions.from_mapping(profile.options, profile=profile.name)
        self.version: m.VersionReply | None = None
        self.startup: m.StartupLine | None = None
        self.services: dict[str, str] = {}
        self._phase: _Phase = "probe"
        # Probes go out every 250 ms until answered; the strip length is waited for briefly.
        self._probe_reply: PendingRequest[object] = PendingRequest(
            timeout_s=_PROBE_INTERVAL_S, retries=None, matches=_answers
        )
        self._pixels_reply: PendingRequest[object] = PendingRequest(
            timeout_s=_PIXEL_INFO_WAIT_S, retries=0, matches=_answers
        )
        # Sensor cache.
        self.encoder_totals = [0, 0]
        self.wheel_speeds_mm_s = [0.0, 0.0]
        self.bump_pressed: tuple[bool, ...] = (False, False)
        self.ir_values: tuple[int, ...] | None = None
        self.distance_cm: int | None = None
        self.side_distance_cm: int | None = None
        self.pixel_count = 0
        # Setpoints.
        self._target_mm_s = (0.0, 0.0)
        self._sent_rpm: tuple[int, int] | None = None
        self._sent_at_s = -math.inf
        self._sent_power: tuple[int, int] | None = None
        self._target_changed_s = -math.inf
        self._host_until_s = -math.inf
        self._host_mode = False
        self._host_loop = WheelSpeedLoop(
            profile.gains.get("wheel_speed", (0.0015, 0.004, 0.0)), profile.max_speed_mm_s * 1.3
        )
        self._mm_per_tick = math.pi * profile.wheel_diameter_mm / profile.ticks_per_rev
        self._tones: list[tuple[int, int]] = []
        self._padding_noticed = False
        self._configured = False  # the events have been asked for

    # ----------------------------------------------------------------------------- handshake

    def start(self) -> None:
        """Send the first version probe."""
        self._probe(self.clock.now())

    def _probe(self, now_s: float) -> None:
        request = m.VersionRequest() if self._phase == "probe" else m.ServiceNamesRequest()
        self._probe_reply.cancel()
        self.link.send(request)
        self._probe_reply.sent(request, now_s)

    def _configure(self) -> None:
        self._configured = True
        caps = self.profile.capabilities
        self.link.send(m.SetAutoEventInterval("I", 0))
        if "M" in self.services:
            self.link.send(m.EnableEncoderEvents(True))
        if cap.BUMPER in caps and "B" in self.services:
            self.link.send(m.SetAutoEventInterval("B", 50))
        if cap.LINE in caps and "R" in self.services:
            self.link.send(m.SetAutoEventInterval("R", 50))
        if (cap.RANGE in caps or cap.SIDE_RANGE in caps) and "D" in self.services:
            self.link.send(m.SetAutoEventInterval("D", 100))
        self.stop_all()
        if cap.LEDS in caps and "P" in self.services and self.options.whole_lines:
            # The strip's length decides the leds capability: wait for it (briefly).
            request = m.PixelsInfoRequest(0)
            self.link.send(request)
            self._phase = "pixels"
            self._pixels_reply.sent(request, self.clock.now())
        else:
            self._finish_handshake()

    def _finish_handshake(self) -> None:
        self._probe_reply.cancel()
        self._pixels_reply.cancel()
        self._phase = "ready"
        self.offer(self._build_capabilities())

    def _build_capabilities(self) -> dict[str, object]:
        wanted = self.profile.capabilities
        have = {
            cap.DRIVE_BASE: "M",
            cap.BUMPER: "B",
            cap.LINE: "R",
            cap.RANGE: "D",
            cap.SIDE_RANGE: "D",
            cap.SPEAKER: "T",
            cap.DISPLAY: "L",
            cap.SERVOS: "S",
            cap.LEDS: "P",
        }
        makers: dict[str, Callable[[], object]] = {
            cap.DRIVE_BASE: lambda: WheelDriveBase(self, self.wheel_distances_mm),
            cap.BUMPER: lambda: _Bumpers(self),
            cap.LINE: lambda: _LineSensors(self),
            cap.RANGE: lambda: _RangeSensor(self),
            cap.SIDE_RANGE: lambda: _SideRangeSensor(self),
            cap.SPEAKER: lambda: _Speaker(self),
            cap.DISPLAY: lambda: _Display(self),
            cap.SERVOS: lambda: _Servos(self),
            cap.LEDS: lambda: _Leds(self),
        }
        result: dict[str, object] = {}
        for name, service in have.items():
            if name not in wanted:
                continue
            if name == cap.LEDS and service in self.services and not self.options.whole_lines:
                self.notice(
                    "the board reads its line a byte at a time (transport: uart), and its "
                    "firmware drops pixel requests read that way: no leds"
                )
            elif name == cap.LEDS and service in self.services and not self.pixel_count:
                self.notice("the board's pixel strip did not say how long it is: no leds")
            elif service in self.services:
                result[name] = makers[name]()
            else:
                self.notice(f"the board has no {self.services_name(service)} service: no {name}")
        return result

    @staticmethod
    def services_name(service: str) -> str:
        """A service id's name, for messages."""
        return {
            "M": "motor",
            "B": "bump",
            "R": "IR",
            "D": "distance",
            "T": "tone",
            "L": "LCD",
            "S": "servo",
            "P": "pixels",
        }.get(service, service)

    def describe(self) -> str:
        """Sketch, chip and ASIP version, as the board reported them."""
        if self.version is not None:
            v = self.version
            return f"{v.sketch} on {v.chip} (ASIP {v.major}.{v.minor})"
        if self.startup is not None:
            return f"{self.startup.sketch} on {self.startup.chip} (ASIP)"
        return self.profile.name

    # ------------------------------------------------------------------------- sense / act

    def tick(self, now_s: float, dt_s: float) -> None:
        """Read events, advance the handshake, watch for silence."""
        for message in self.link.poll():
            if self._configured and isinstance(message, _START_UP):
                self._restarted(now_s)
            if self._phase != "ready":
                self._probe_reply.answered(message)
                self._pixels_reply.answered(message)
            self._handle(message)
        if self._phase == "probe" and (self.version or self.startup):
            self._phase = "discover"
            self._probe(now_s)
        elif self._phase == "discover" and self.services:
            self._configure()
        elif self._phase == "pixels":
            pixels = self._pixels_reply
            if self.pixel_count or pixels.in_flight is None or pixels.overdue(now_s):
                self._finish_handshake()
        elif self._phase != "ready":
            again = self._probe_reply.resend_due(now_s)
            if again is not None:
                self.link.send(again)
        if self.ready and "M" in self.services:
            last = self.link.last_receive_s
            if last is not None and now_s - last > _SILENCE_LIMIT_S:
                raise LinkTimeoutError(
                    f"the robot stopped responding (nothing for {now_s - last:.1f} s)"
                )

    def _restarted(self, now_s: float) -> None:
        """The board greeted again after its events were asked for: it restarted.

        Raises:
            LinkClosedError: Once ready: the run ends (its stop still goes out, and reaches
                the board that is running again).
        """
        if not self.ready:
            self._configured = False
            self._pixels_reply.cancel()
            self._phase = "discover"  # the services are known: ask for the events again
            return
        after = f"{now_s - self.connected_s:.1f} s after connecting"
        self.failure = LinkClosedError(BOARD_RESTARTED.format(after=after))
        raise self.failure

    def flush(self, now_s: float, dt_s: float) -> None:
        """Send wheel setpoints and tones."""
        if not self.ready:
            return
        for frequency, duration in self._tones:
            self.link.send(m.PlayTone(frequency, duration))
        self._tones.clear()
        steering = now_s < self._host_until_s and self._target_mm_s != (0.0, 0.0)
        if self.firmware_pid and not steering:
            if self._host_mode:
                self._host_mode = False
                # Clear the host's last power, then hand the wheels back to the firmware PID.
                self.link.send(m.SetMotorsPower(0, 0))
                self._sent_rpm = None
            self._flush_rpm(now_s)
        else:
            if not self._host_mode:
                self._host_mode = True
                self._sent_power = None
                if self.firmware_pid:
                    self.link.send(m.StopMotors())  # power requests do not stop the PID
            self._flush_power(now_s, dt_s)

    def _flush_rpm(self, now_s: float) -> None:
        per_rev = math.pi * self.profile.wheel_diameter_mm
        rpm = (
            round(self._target_mm_s[0] * 60.0 / per_rev),
            round(self._target_mm_s[1] * 60.0 / per_rev),
        )
        if rpm == (0, 0):
            if self._sent_rpm != (0, 0):
                self.link.send(m.StopMotors())
                self._sent_rpm = (0, 0)
            return
        stale = now_s - self._sent_at_s >= _PID_REFRESH_S
        if rpm == self._sent_rpm and not stale:
            return
        if 0 in rpm:  # V1.1 ignores rpm 0: stop that wheel instead
            for motor, value in enumerate(rpm):
                if value == 0:
                    self.link.send(m.StopMotor(motor))
                else:
                    self.link.send(m.SetMotorRpm(motor, value, _PID_DURATION_MS))
        else:
            self.link.send(m.SetMotorsRpm(rpm[0], rpm[1], _PID_DURATION_MS))
        self._sent_rpm = rpm
        self._sent_at_s = now_s

    def _flush_power(self, now_s: float, dt_s: float) -> None:
        self._host_loop.set_targets(*self._target_mm_s)
        left, right = self._host_loop.update(
            (self.wheel_speeds_mm_s[0], self.wheel_speeds_mm_s[1]), dt_s
        )
        power = (round(left * 100), round(right * 100))
        if power != self._sent_power or now_s - self._sent_at_s >= _POWER_REFRESH_S:
            self.link.send(m.SetMotorsPower(*power))
            self._sent_power = power
            self._sent_at_s = now_s

    def _handle(self, message: object) -> None:
        if isinstance(message, m.EncoderEvent):
            for index, (delta, total) in enumerate(message.counts[:2]):
                self.encoder_totals[index] = total
                self.wheel_speeds_mm_s[index] = delta * self._mm_per_tick / _ENCODER_FRAME_S
        elif isinstance(message, m.BumpEvent):
            self.bump_pressed = message.pressed
        elif isinstance(message, m.IrEvent):
            self.ir_values = message.values
        elif isinstance(message, m.DistanceEvent):
            values = message.distances_cm
            self.distance_cm = values[0] if values else None
            self.side_distance_cm = values[1] if len(values) > 1 else None
        elif isinstance(message, m.VersionReply):
            self.version = message
        elif isinstance(message, m.StartupLine):
            self.startup = message
        elif isinstance(message, m.ServiceNamesReply):
            self.services = dict(message.services)
        elif isinstance(message, m.ErrorReply):
            self._handle_error(message)
        elif isinstance(message, m.PixelsInfoReply) and message.strip == 0:
            self.pixel_count = message.count
        elif isinstance(message, m.InfoLine | m.DebugLine):
            logger.debug("board says: %s", message.text)

    def _handle_error(self, error: m.ErrorReply) -> None:
        if (
            error.service == "M"
            and error.tag in "rRca"
            and error.errno == m.ErrorCode.UNKNOWN_REQUEST
        ):
            if self.firmware_pid:
                self.firmware_pid = False
                self._sent_rpm = None
                self.notice(
                    "this board's firmware has no motor PID: roboscript holds the wheel "
                    "speeds itself"
                )
            return
        if error.errno == m.ErrorCode.INVALID_SERVICE and error.service == ",":
            # "~,,?,1" after "M,S,0": a board that reads M,S with no value (as documented)
            # found the ",0" padded for V1.1's parser. It did stop; nothing failed.
            if not self._padding_noticed:
                self._padding_noticed = True
                self.notice(
                    "the board reads 'M,S' without a value: the ',0' sent for ASIP V1.1 "
                    "boards came back as '~,,?,1{INVALID_SERVICE}' (harmless)"
                )
            return
        if error.errno == m.ErrorCode.INVALID_SERVICE and not error.service.isalpha():
            # "~0,?,1" and the like: the board read what was left of a request as a new one.
            self.device_errors.append(
                "the board read the end of a request as a new one: a request carried more "
                "values than the board takes"
            )
            logger.warning("the board found no service %r", error.service)
            return
        text = _ERROR_MEANINGS.get(error.errno, error.text or f"error {error.errno}")
        self.device_errors.append(f"the board refused '{error.service},{error.tag}': {text}")
        logger.warning("the board refused %s,%s: %s", error.service, error.tag, error.text)

    def send_stop(self) -> None:
        """Stop both motors: ``M,S,0`` and ``M,M,0,0``."""
        self._target_mm_s = (0.0, 0.0)
        self._sent_rpm = (0, 0)
        self._sent_power = (0, 0)
        self.link.send(m.StopMotors())
        self.link.send(m.SetMotorsPower(0, 0))

    # ------------------------------------------------------------------ capability plumbing

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Store wheel speed targets (sent in the act phase)."""
        target = (left_mm_s, right_mm_s)
        if target != self._target_mm_s:
            now = self.clock.now()
            if now - self._target_changed_s < _STEERING_GAP_S:
                self._host_until_s = now + _STEADY_S
            self._target_changed_s = now
        self._target_mm_s = target

    def wheel_distances_mm(self) -> tuple[float, float]:
        """Wheel travel (left, right) from the encoder totals, mm."""
        return (
            self.encoder_totals[0] * self._mm_per_tick,
            self.encoder_totals[1] * self._mm_per_tick,
        )

    def queue_tone(self, frequency_hz: float, duration_s: float) -> None:
        """Queue a tone (sent in the act phase)."""
        frequency = max(1, min(65535, round(frequency_hz)))
        duration = max(1, round(duration_s * 1000))
        self._tones.append((frequency, duration))


def _cm_to_mm(cm: int | None) -> float | None:
    """A distance reading in mm: 0 cm is no echo; the board truncates to whole centimetres,
    so the middle of the centimetre is the unbiased estimate."""
    return None if cm is None or cm <= 0 else cm * 10.0 + 5.0


class _RangeSensor:
    max_range_mm = 1000.0

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def distance_mm(self) -> float | None:
        return _cm_to_mm(self._driver.distance_cm)


class _SideRangeSensor:
    """Distance sensor 1 of the distance service, facing right (the MIRTO wall follower)."""

    side = "right"
    max_range_mm = 1000.0

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def distance_mm(self) -> float | None:
        return _cm_to_mm(self._driver.side_distance_cm)


class _Servos:
    """Servos of the servo service, by the order the sketch declares them (0, 1, ...).

    ASIP cannot say how many there are: the profile's ``servo_count`` does. A board answers
    an id it does not have with ``~S,W,7{INVALID_DEVICE_NUMBER}`` (and then reads the angle
    as a request of its own), which fails the running action.
    """

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver
        self.count = driver.options.servo_count

    def set_angle(self, index: int, angle_deg: float) -> None:
        self._driver.link.send(m.ServoWrite(index, round(max(0.0, min(180.0, angle_deg)))))


class _Leds:
    """The first strip of the pixels service (its length asked with ``P,I,0``)."""

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    @property
    def count(self) -> int:
        return self._driver.pixel_count

    def set_color(self, index: int, rgb: tuple[int, int, int]) -> None:
        self._driver.link.send(m.PixelsSetRgb(0, ((index, rgb),)))


class _Bumpers:
    names = ("left", "right")

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def pressed(self) -> frozenset[str]:
        return frozenset(
            name for name, down in zip(self.names, self._driver.bump_pressed, strict=False) if down
        )


class _LineSensors:
    names = ("left", "center", "right")
    dark_threshold = 500.0

    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def values(self) -> tuple[float, ...] | None:
        values = self._driver.ir_values
        return None if values is None else tuple(float(v) for v in values)


class _Speaker:
    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        self._driver.queue_tone(frequency_hz, duration_s)


class _Display:
    def __init__(self, driver: AsipDriver) -> None:
        self._driver = driver

    def show_text(self, text: str) -> None:
        link = self._driver.link
        link.send(m.LcdClear())
        clean = "".join(ch if ch.isascii() and ch.isprintable() else "?" for ch in text)
        width = self._driver.options.lcd_columns
        rows = [clean[i : i + width] for i in range(0, len(clean), width)]
        for line, row in enumerate(rows[: m.LCD_LINES]):
            link.send(m.LcdWrite(line, row))

    def clear(self) -> None:
        self._driver.link.send(m.LcdClear())
