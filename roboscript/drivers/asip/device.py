"""A simulated MIRTO board: the ASIP 1.1 firmware's device side, on a simulated body.

This is a second, independent implementation of the protocol (it never imports the host
driver), written from the firmware's behaviour:

* On connection it sends the startup line ``!<sketch> running on <chip> with Services: ...``,
  then, as the ``mirtle2017`` sketch does, its pin modes and port map and one unprefixed
  ``<name> is service <id>`` line per service (CRLF-terminated).
* Requests are parsed with the firmware's ``parseInt`` semantics (see the codec), with the
  1000 ms stream timeout counted on the simulation clock.
* The motor service runs every 33 ms (30 Hz): it services the firmware PID of ``M,r``,
  ``M,R``, ``M,c`` and ``M,a`` (integer gains Kp 20, Ki 0, Kd 12, divisor Ko 20, acceleration
  limit per frame, stop when the duration has passed or after 2000 ms without an encoder
  pulse) and, when enabled with ``M,A,1``, sends ``@M,e,2,{delta:total,...}``.
* Without firmware PID (``asip-basic``) the PID tags answer ``~M,<tag>,2{UNKNOWN_REQUEST}``.
* The IO service streams free analog pins every 50 ms from power-on (``@I,a``); bump, IR and
  distance events follow their ``A`` intervals; errors carry the firmware's numbers and texts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from roboscript.codec import Role, readable
from roboscript.drivers.asip import messages as m
from roboscript.drivers.asip.codec import AsipCodec

if TYPE_CHECKING:
    from roboscript.profiles import RobotProfile
    from roboscript.sim.body import Body

__all__ = ["BoardConfig", "MirtoBoard", "simulated_device"]

_MOTOR_FRAME_S = 0.033  # 1000 / PID_FRAME_HZ in integer milliseconds
_AUTO_STOP_S = 2.0
_PARSE_TIMEOUT_S = 1.0

# Pin map of the simulated board (an Uno-sized, 20-pin layout).
_PIN_SERVICES = "@@MMRMMMMMMBBTRRRDII"
_PORT_MAP = tuple([(4, 1 << i) for i in range(8)] + [(2, 1 << i) for i in range(6)]) + tuple(
    (3, 1 << i) for i in range(6)
)
_ANALOG_PINS = {14 + i: i for i in range(6)}
_PWM_PINS = {3, 5, 6, 9, 10, 11}
_SERVICE_NAMES = {
    "I": "ASIP core IO",
    "M": "Motors",
    "B": "Bump Sensors",
    "R": "IR Sensors",
    "D": "Distance",
    "T": "Tone",
    "L": "LCD",
    "S": "Servos",
    "P": "Pixels",
}
# Like the LCD (on I2C), servos and the pixel strip sit on pins the 20-pin map does not show.
_SERVO_COUNT = 2
_PIXEL_COUNT = 8


def _cdiv(a: int, b: int) -> int:
    """C integer division (truncates toward zero)."""
    q = abs(a) // abs(b)
    return q if (a >= 0) == (b >= 0) else -q


@dataclass(frozen=True)
class BoardConfig:
    """How the simulated board is built.

    Attributes:
        firmware_pid: Whether the sketch was built with the motor PID (``ASIP_PID``).
        sketch: Sketch name in the startup line and version reply.
        chip: Chip name in the startup line and version reply.
        kp: Proportional gain (integer, firmware units).
        ki: Integral gain.
        kd: Derivative gain.
        ko: Output divisor.
        max_pwm: PWM limit.
        max_pwm_delta: Largest PWM change per PID frame.
        encoder_events_on: Whether ``@M,e`` events are on at power-on (V1.1: off).
    """

    firmware_pid: bool = True
    sketch: str = "mirto2017"
    chip: str = "ATmega328P"
    kp: int = 20
    ki: int = 0
    kd: int = 12
    ko: int = 20
    max_pwm: int = 255
    max_pwm_delta: int = 30
    encoder_events_on: bool = False


@dataclass
class _Wheel:
    pwm: int = 0
    pid_active: bool = False
    target_ticks_per_s: int = 0
    start_s: float = 0.0
    duration_s: float = 0.0
    prev_pulse_s: float = 0.0
    prev_input: int = 0
    prev_output: int = 0
    iterm: int = 0
    last_ticks: int = 0
    delta: int = 0
    total_offset: int = 0


@dataclass
class _AutoEvent:
    interval_s: float = 0.0
    next_s: float = 0.0


@dataclass
class _State:
    wheels: list[_Wheel] = field(default_factory=lambda: [_Wheel(), _Wheel()])
    encoder_events: bool = False
    motor_frames: bool = True
    next_motor_frame_s: float = 0.0
    auto: dict[str, _AutoEvent] = field(default_factory=dict)
    pin_modes: list[int] = field(default_factory=list)
    lcd: list[str] = field(default_factory=lambda: [""] * m.LCD_LINES)
    servos_deg: list[int] = field(default_factory=lambda: [90] * _SERVO_COUNT)
    pixels: list[tuple[int, int, int]] = field(default_factory=lambda: [(0, 0, 0)] * _PIXEL_COUNT)
    brightness: int = 64


class MirtoBoard:
    """The simulated MIRTO board on a body (see the module docstring).

    Args:
        body: The simulated body the board drives and senses.
        config: Firmware build options.
    """

    def __init__(self, body: Body, config: BoardConfig | None = None) -> None:
        self.body = body
        self.config = config or BoardConfig()
        self.codec = AsipCodec(Role.DEVICE, services="".join(_SERVICE_NAMES))
        self._out = bytearray()
        self._last_rx_s = 0.0
        self.state = self._power_on_state()

    def _power_on_state(self) -> _State:
        state = _State(encoder_events=self.config.encoder_events_on)
        for service in "IBRD":
            state.auto[service] = _AutoEvent()
        modes = []
        for pin, owner in enumerate(_PIN_SERVICES):
            if owner == "@":
                modes.append(int(m.PinMode.RESERVED))
            elif owner == "I":
                # Without STRICT_PINMODE every free analog pin starts in ANALOG mode.
                modes.append(
                    int(m.PinMode.ANALOG if pin in _ANALOG_PINS else m.PinMode.UNALLOCATED)
                )
            else:
                modes.append(int(m.PinMode.OTHER_SERVICE))
        state.pin_modes = modes
        state.auto["I"].interval_s = 0.050
        return state

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """Greet a new host the way the sketch's ``setup()`` does."""
        self.codec = AsipCodec(Role.DEVICE, services="".join(_SERVICE_NAMES))
        services = tuple(_SERVICE_NAMES)
        self._send(m.StartupLine(self.config.sketch, self.config.chip, services))
        self._send(m.PinModesReply(tuple(self.state.pin_modes)))
        self._send(m.PortMapReply(_PORT_MAP))
        for service, name in _SERVICE_NAMES.items():
            if service != "I":
                self._out += f"{name} is service {service}\r\n".encode("ascii")
        for event in self.state.auto.values():
            event.next_s = now_s + event.interval_s
        self.state.next_motor_frame_s = now_s + _MOTOR_FRAME_S

    def receive(self, data: bytes, now_s: float) -> None:
        """Parse and act on request bytes."""
        if data:
            self._last_rx_s = now_s
            self.codec.receive_data(data)
            self._process(now_s)

    def step(self, now_s: float) -> None:
        """Run timers: parse timeout, PID frames, auto-events."""
        if self.codec.pending_bytes() and now_s - self._last_rx_s >= _PARSE_TIMEOUT_S:
            self.codec.parse_timeout()
            self._process(now_s)
        state = self.state
        # The epsilon keeps float sums of intervals (20 x 0.05 s) from slipping a tick.
        if state.motor_frames and now_s >= state.next_motor_frame_s - 1e-9:
            self._motor_frame(now_s)
            state.next_motor_frame_s += _MOTOR_FRAME_S
            if state.next_motor_frame_s < now_s:
                state.next_motor_frame_s = now_s + _MOTOR_FRAME_S
        for service, event in state.auto.items():
            if event.interval_s > 0 and now_s >= event.next_s - 1e-9:
                self._report(service)
                event.next_s += event.interval_s
                if event.next_s < now_s:
                    event.next_s = now_s + event.interval_s

    def read_output(self) -> bytes:
        """Take the bytes written since the last call."""
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Stop both motors and their PID."""
        for index in (0, 1):
            self._stop_wheel(index)

    # ------------------------------------------------------------------------------ helpers

    def _send(self, message: object) -> None:
        self._out += self.codec.send(message)

    def _error(self, service: str, tag: str, code: m.ErrorCode) -> None:
        self._send(m.ErrorReply(service, tag, int(code)))

    def _process(self, now_s: float) -> None:
        # The firmware drops what it cannot parse, silently.
        for message in readable(self.codec):
            self._handle(message, now_s)

    def _set_pwm(self, index: int, pwm: int) -> None:
        wheel = self.state.wheels[index]
        limit = self.config.max_pwm
        wheel.pwm = max(-limit, min(limit, pwm))
        powers = [w.pwm / limit for w in self.state.wheels]
        self.body.set_power(powers[0], powers[1])

    def _stop_wheel(self, index: int) -> None:
        self.state.wheels[index].pid_active = False
        self._set_pwm(index, 0)

    def _start_pid(self, index: int, rpm: int, duration_ms: int, now_s: float) -> None:
        wheel = self.state.wheels[index]
        if rpm == 0:  # V1.1 ignores r with rpm 0
            return
        wheel.pid_active = True
        wheel.start_s = wheel.prev_pulse_s = now_s
        wheel.duration_s = duration_ms / 1000.0
        wheel.prev_input = wheel.prev_output = 0
        wheel.target_ticks_per_s = rpm * self.body.spec.ticks_per_rev // 60

    # -------------------------------------------------------------------------- motor frame

    def _motor_frame(self, now_s: float) -> None:
        ticks = self.body.ticks
        for index, wheel in enumerate(self.state.wheels):
            wheel.delta = ticks[index] - wheel.last_ticks
            wheel.last_ticks = ticks[index]
            if wheel.pid_active:
                self._service_pid(index, wheel, now_s)
        if self.state.encoder_events:
            counts = tuple((w.delta, w.last_ticks - w.total_offset) for w in self.state.wheels)
            self._send(m.EncoderEvent(counts))

    def _service_pid(self, index: int, wheel: _Wheel, now_s: float) -> None:
        cfg = self.config
        if now_s - wheel.start_s > wheel.duration_s:
            self._stop_wheel(index)
            return
        encoder = wheel.delta
        if encoder != 0:
            wheel.prev_pulse_s = now_s
        elif now_s - wheel.prev_pulse_s > _AUTO_STOP_S:
            self._stop_wheel(index)
            return
        frame_ms = round(_MOTOR_FRAME_S * 1000)
        target = wheel.target_ticks_per_s * frame_ms // 1000
        error = target - encoder
        pid = _cdiv(cfg.kp * error - cfg.kd * (encoder - wheel.prev_input) + wheel.iterm, cfg.ko)
        pid = max(-cfg.max_pwm_delta, min(cfg.max_pwm_delta, pid))
        output = pid + wheel.prev_output
        if output >= cfg.max_pwm:
            output = cfg.max_pwm
        elif output <= -cfg.max_pwm:
            output = -cfg.max_pwm
        else:
            wheel.iterm += cfg.ki * error
        wheel.prev_output = output
        wheel.prev_input = encoder
        self._set_pwm(index, output)

    # --------------------------------------------------------------------------- reporting

    def _report(self, service: str) -> None:
        body = self.body
        if service == "I":
            values = tuple(
                (chan, 512 + (pin * 37) % 200)
                for pin, chan in _ANALOG_PINS.items()
                if self.state.pin_modes[pin] == m.PinMode.ANALOG
            )
            if values:
                self._send(m.AnalogEvent(values))
        elif service == "B":
            self._send(
                m.BumpEvent(tuple(0 if pressed else 1 for pressed in body.bumpers_pressed()))
            )
        elif service == "R":
            self._send(m.IrEvent(body.line_readings()))
        elif service == "D":
            self._send(m.DistanceEvent(self._distances_cm()))

    def _distances_cm(self) -> tuple[int, ...]:
        # Two HC-SR04 sensors on the distance service: 0 faces forward, 1 faces right.
        readings = (self.body.range_mm(), self.body.side_range_mm())
        return tuple(0 if r is None else int(r // 10) for r in readings)

    # ------------------------------------------------------------------------------ requests

    def _handle(self, msg: object, now_s: float) -> None:
        state = self.state
        if isinstance(msg, m.InvalidServiceRequest):
            self._error(msg.service, "?", m.ErrorCode.INVALID_SERVICE)
        elif isinstance(msg, m.VersionRequest):
            self._send(
                m.VersionReply(1, 1, self.config.chip, len(_PIN_SERVICES), self.config.sketch)
            )
        elif isinstance(msg, m.ServiceNamesRequest):
            self._send(m.ServiceNamesReply(tuple(_SERVICE_NAMES.items())))
        elif isinstance(msg, m.PinServicesRequest):
            self._send(m.PinServicesReply(tuple(_PIN_SERVICES)))
        elif isinstance(msg, m.RestartRequest):
            self.stop_all()
            for event in state.auto.values():
                event.interval_s = 0.0
            state.motor_frames = False  # reset() zeroes every auto-report, the PID's too
        elif isinstance(msg, m.SetAutoEventInterval):
            if msg.service in state.auto:
                event = state.auto[msg.service]
                event.interval_s = msg.interval_ms / 1000.0
                event.next_s = now_s + event.interval_s
        elif isinstance(msg, m.MeasureRequest):
            if msg.service == "D":
                self._send(m.DistanceEvent(self._distances_cm()))
            else:
                self._error(msg.service, "M", m.ErrorCode.UNKNOWN_REQUEST)
        elif isinstance(msg, m.EnableEncoderEvents):
            state.encoder_events = msg.enabled
        elif isinstance(msg, m.SetMotorPower):
            # As on the board, power does not stop a running PID: its next frame overrides it.
            if msg.motor < 2:
                self._set_pwm(msg.motor, msg.power_pct * self.config.max_pwm // 100)
        elif isinstance(msg, m.SetMotorsPower):
            for index, power in enumerate((msg.power0_pct, msg.power1_pct)):
                self._set_pwm(index, power * self.config.max_pwm // 100)
        elif isinstance(msg, m.StopMotor):
            if msg.motor < 2:
                self._stop_wheel(msg.motor)
        elif isinstance(msg, m.StopMotors):
            self.stop_all()
        elif isinstance(msg, m.ResetEncoders):
            for wheel in state.wheels:
                wheel.total_offset = wheel.last_ticks
        elif isinstance(msg, m.SetMotorRpm | m.SetMotorsRpm | m.SetRobotSpeed | m.RotateRobot):
            self._pid_request(msg, now_s)
        elif isinstance(msg, m.PlayTone):
            self.body.log.tones.append((now_s, float(msg.frequency_hz), msg.duration_ms / 1000.0))
        elif isinstance(msg, m.LcdWrite | m.LcdWriteAt | m.LcdClear | m.LcdBarGraph):
            self._lcd(msg)
        elif isinstance(msg, m.ServoWrite):
            if msg.servo >= _SERVO_COUNT:
                self._error("S", "W", m.ErrorCode.INVALID_DEVICE_NUMBER)
            else:
                state.servos_deg[msg.servo] = msg.angle_deg
        elif isinstance(
            msg,
            m.PixelsSet
            | m.PixelsSetRgb
            | m.PixelsSequence
            | m.PixelsSequenceRgb
            | m.PixelsBrightness
            | m.PixelsInfoRequest
            | m.PixelsClear,
        ):
            self._pixels(msg)
        else:
            self._io_or_unknown(msg)

    def _pid_request(self, msg: object, now_s: float) -> None:
        tags = {m.SetMotorRpm: "r", m.SetMotorsRpm: "R", m.SetRobotSpeed: "c", m.RotateRobot: "a"}
        if not self.config.firmware_pid:
            self._error("M", tags[type(msg)], m.ErrorCode.UNKNOWN_REQUEST)
            return
        wheel_circ_mm = math.pi * self.body.spec.wheel_diameter_mm
        if isinstance(msg, m.SetMotorRpm):
            if msg.motor < 2:
                self._start_pid(msg.motor, msg.rpm, msg.duration_ms, now_s)
        elif isinstance(msg, m.SetMotorsRpm):
            self._start_pid(0, msg.rpm0, msg.duration_ms, now_s)
            self._start_pid(1, msg.rpm1, msg.duration_ms, now_s)
        elif isinstance(msg, m.SetRobotSpeed):
            rpm = int(60 * msg.speed_cm_s / (wheel_circ_mm / 10.0))
            self._start_pid(0, rpm, msg.duration_ms, now_s)
            self._start_pid(1, rpm, msg.duration_ms, now_s)
        elif isinstance(msg, m.RotateRobot):
            # rotateRobot(dps, angle), with the firmware's integer rounding.
            track_circ_mm = math.pi * self.body.spec.track_mm
            duration = abs(msg.angle_deg * 1000 // msg.turn_rate_deg_s) if msg.angle_deg else 0
            distance = int(track_circ_mm * msg.angle_deg / 360.0)
            if duration == 0 or distance == 0:
                return
            speed = _cdiv(distance * 100, duration)
            if speed == 0:
                return
            duration = abs(_cdiv(distance * 100, speed))
            rpm = int(60 * speed / (wheel_circ_mm / 10.0))
            self._start_pid(0, rpm, duration, now_s)
            self._start_pid(1, -rpm, duration, now_s)

    def _pixels(self, msg: object) -> None:
        state = self.state
        strip = getattr(msg, "strip", 0)
        tag = {
            m.PixelsSet: "P", m.PixelsSetRgb: "p", m.PixelsSequence: "S",
            m.PixelsSequenceRgb: "s", m.PixelsBrightness: "B", m.PixelsInfoRequest: "I",
            m.PixelsClear: "C",
        }[type(msg)]  # fmt: skip
        if strip != 0:
            self._error("P", tag, m.ErrorCode.INVALID_DEVICE_NUMBER)
            return

        def unpack(color: int) -> tuple[int, int, int]:
            return (color >> 16) & 0xFF, (color >> 8) & 0xFF, color & 0xFF

        updates: list[tuple[int, tuple[int, int, int]]] = []
        if isinstance(msg, m.PixelsSet):
            updates = [(pixel, unpack(color)) for pixel, color in msg.pixels]
        elif isinstance(msg, m.PixelsSetRgb):
            updates = list(msg.pixels)
        elif isinstance(msg, m.PixelsSequence):
            updates = [(msg.first + i, unpack(c)) for i, c in enumerate(msg.colors)]
        elif isinstance(msg, m.PixelsSequenceRgb):
            updates = [(msg.first + i, rgb) for i, rgb in enumerate(msg.colors)]
        elif isinstance(msg, m.PixelsBrightness):
            state.brightness = msg.level
        elif isinstance(msg, m.PixelsInfoRequest):
            self._send(m.PixelsInfoReply(0, _PIXEL_COUNT))
        else:
            state.pixels = [(0, 0, 0)] * _PIXEL_COUNT
        for pixel, rgb in updates:
            if 0 <= pixel < _PIXEL_COUNT:  # the library ignores pixels past the strip's end
                state.pixels[pixel] = rgb

    def _lcd(self, msg: object) -> None:
        lines = self.state.lcd
        if isinstance(msg, m.LcdWrite):
            lines[msg.line] = msg.text[: m.LCD_COLUMNS]
        elif isinstance(msg, m.LcdWriteAt):
            current = lines[msg.line].ljust(msg.column)
            text = current[: msg.column] + msg.text
            lines[msg.line] = text[: m.LCD_COLUMNS]
        elif isinstance(msg, m.LcdClear):
            lines[:] = [""] * m.LCD_LINES
        self.body.log.display = "\n".join(line for line in lines if line)

    def _io_or_unknown(self, msg: object) -> None:
        state = self.state
        if isinstance(msg, m.PortMapRequest):
            self._send(m.PortMapReply(_PORT_MAP))
        elif isinstance(msg, m.AnalogMapRequest):
            self._send(m.AnalogMapReply(tuple(_ANALOG_PINS.items())))
        elif isinstance(msg, m.PinModesRequest):
            self._send(m.PinModesReply(tuple(state.pin_modes)))
        elif isinstance(msg, m.CapabilitiesRequest):
            caps = tuple(
                1 | (2 if pin in _ANALOG_PINS else 0) | (4 if pin in _PWM_PINS else 0)
                for pin in range(len(_PIN_SERVICES))
            )
            self._send(m.CapabilitiesReply(caps))
        elif isinstance(msg, m.SetPinMode):
            self._set_pin_mode(msg)
        elif isinstance(msg, m.DigitalWrite):
            modes = (m.PinMode.OUTPUT, m.PinMode.INPUT, m.PinMode.INPUT_PULLUP)
            if msg.pin >= len(_PIN_SERVICES) or state.pin_modes[msg.pin] not in modes:
                self._error("I", "d", m.ErrorCode.WRONG_MODE)
        elif isinstance(msg, m.AnalogWrite):
            if msg.pin not in _PWM_PINS or _PIN_SERVICES[msg.pin] != "I":
                self._error("I", "a", m.ErrorCode.INVALID_PIN)
        elif isinstance(msg, m.UnknownRequest) and msg.service not in "TL":
            # (tone and LCD ignore unknown tags silently)
            self._error(msg.service, msg.tag, m.ErrorCode.UNKNOWN_REQUEST)

    def _set_pin_mode(self, msg: m.SetPinMode) -> None:
        state = self.state
        if msg.pin >= len(_PIN_SERVICES) or _PIN_SERVICES[msg.pin] != "I":
            self._error("I", "P", m.ErrorCode.MODE_UNAVAILABLE)
            return
        if msg.mode not in (
            m.PinMode.INPUT,
            m.PinMode.INPUT_PULLUP,
            m.PinMode.OUTPUT,
            m.PinMode.ANALOG,
            m.PinMode.PWM,
        ):
            self._error("I", "P", m.ErrorCode.INVALID_MODE)
            return
        if msg.mode is m.PinMode.ANALOG and msg.pin not in _ANALOG_PINS:
            self._error("I", "P", m.ErrorCode.INVALID_MODE)
            return
        if msg.mode is m.PinMode.PWM and msg.pin not in _PWM_PINS:
            self._error("I", "P", m.ErrorCode.INVALID_MODE)
            return
        state.pin_modes[msg.pin] = int(msg.mode)
        if msg.mode in (m.PinMode.INPUT, m.PinMode.INPUT_PULLUP):
            ports = sorted({port for port, _ in _PORT_MAP})
            for port in ports:
                mask = 0
                for pin, (pin_port, bit) in enumerate(_PORT_MAP):
                    if pin_port == port and state.pin_modes[pin] == m.PinMode.INPUT_PULLUP:
                        mask |= bit
                self._send(m.DigitalPortEvent(port, mask))


def simulated_device(profile: RobotProfile) -> Callable[[Body], MirtoBoard]:
    """The ASIP unit's simulated device factory: a MIRTO board, with firmware PID or without
    as the profile says."""
    config = BoardConfig(firmware_pid=profile.firmware_pid)
    return lambda body: MirtoBoard(body, config)
