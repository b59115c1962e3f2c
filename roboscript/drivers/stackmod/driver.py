"""The StackMod host driver: a rover built from StackMod modules on one serial line.

The modules (see :mod:`roboscript.drivers.stackmod.options` for addresses and wiring) are
reached as one serial byte stream, 9600 baud, through a USB-serial bridge. They speak only when
asked, so the driver is the line's master:

* **Handshake** (never a fixed sleep): ``{a$ARM01}`` arms every module, then ``{a?ARM0}`` asks
  each one in turn whether it is armed. The robot is ready when every module has answered 1.
* **GETs**, one in flight at a time (:func:`get_poller`): each is sent again if its answer
  has not come within ``get_timeout_s`` on the scheduler clock, up to ``get_retries`` times,
  then :class:`~roboscript.errors.LinkTimeoutError` names the silent module.
* **Sensors are polled while they are read.** At 9600 baud one GET and its answer take about
  22 ms of line time, so polling every sensor all the time would give each only a few readings
  a second. A reading of a range, line or bump sensor asks for that sensor to be polled for
  the next second; the first call returns ``None`` (nothing pressed, for bumpers) until the
  answer arrives, one or two ticks later. Readings older than a second count as missing.
* **Motors** get ``{M$MTRn±ppp}`` whenever the power changes. A SET is never acknowledged, so
  a heartbeat GET of one motor every 0.25 s both proves the line is alive and catches a SET
  that was lost (its power is then sent again).
* **No encoders.** Wheel distances are the commanded wheel speeds integrated over time with the
  profile's calibration (``wheel_speed_mm_s_per_pct``), so ``drive`` and ``rotate`` run on time
  and cannot notice a stall; the driver says so once.
* **Stopping** sends MTR +000 to both motors (and silences the buzzer); it never raises.

With ``firmware: reference`` (the ``stackmod-reference`` profile) the driver speaks the
StackMod author's firmware instead: it only ever sends
:class:`~roboscript.drivers.stackmod.messages.MotorPwm` packets (``{Ep$MTR1+139}``, ±255),
one per write, led by the I2C register byte when the framing is I2C. That firmware answers
nothing, so there is no handshake, no heartbeat and no sensor: the robot is ready at once, the
only capability is the drive base, every move is timed open-loop from the calibration, and
nothing can tell the driver that the module is missing or that a packet was lost.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterable

from roboscript import capabilities as cap
from roboscript.clock import Clock
from roboscript.drivers.base import Driver, PendingRequest, WheelDriveBase
from roboscript.drivers.stackmod.messages import (
    HOST_SOURCE,
    PWM_MAX,
    ULT_NO_ECHO,
    Command,
    Get,
    GetReply,
    MotorPwm,
    Set,
)
from roboscript.drivers.stackmod.options import StackModOptions
from roboscript.errors import DeviceError, LinkTimeoutError, ProfileError
from roboscript.robot_profile import RobotProfile
from roboscript.transport.link import Link

__all__ = ["StackModDriver", "get_poller"]

logger = logging.getLogger(__name__)

_HEARTBEAT_S = 0.25
"""A motor setpoint is read back at least this often (liveness and lost-SET check)."""
_WANT_HOLD_S = 1.0
"""A sensor is polled for this long after it was last read."""
_STALE_S = 1.0
"""Readings older than this count as missing."""

_Key = tuple[int, Command, int]
"""(address, command, selector): one thing a GET reads."""


def _options(profile: RobotProfile) -> StackModOptions:
    return StackModOptions.from_mapping(profile.options, profile=profile.name)


def _answers(request: Get, reply: object) -> bool:
    return isinstance(reply, GetReply) and (reply.address, reply.command, reply.selector) == (
        request.address,
        request.command,
        request.selector,
    )


def get_poller(
    *, timeout_s: float, retries: int, describe: Callable[[int], str]
) -> PendingRequest[Get]:
    """One StackMod GET in flight at a time, with a reply timeout and bounded retries.

    StackMod modules share one line and answer only when asked, so the host asks one question
    at a time: a reply then always belongs to the one request in flight, and two modules never
    talk at once. A request that gets no answer within ``timeout_s`` (on the scheduler's
    clock) is sent again, up to ``retries`` times; after that the module is declared silent
    with a :class:`~roboscript.errors.LinkTimeoutError` naming it.

    Args:
        timeout_s: How long to wait for each answer, seconds.
        retries: How many times a request is sent again before giving up.
        describe: Names the module at an address, for the error message
            (``the motor module at 'M' (0x4D)``).

    Raises:
        ValueError: A timeout that is not positive, or negative retries.
    """

    def silent(request: Get, tries: int) -> LinkTimeoutError:
        return LinkTimeoutError(
            f"{describe(request.address)} did not answer "
            f"GET {request.command.value}{request.selector} "
            f"({tries} tries, {timeout_s:g} s each): "
            "is it powered, wired to the line, and set to that address?"
        )

    return PendingRequest(timeout_s=timeout_s, retries=retries, matches=_answers, give_up=silent)


class StackModDriver(Driver):
    """Host side of a StackMod rover (see the module docstring).

    Raises:
        ProfileError: The profile's options are invalid.
    """

    protocol = "stackmod"

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        super().__init__(link, profile, clock)
        self.options = opts = _options(profile)
        self.reference = opts.firmware == "reference"
        """True when speaking the author's firmware (motor SETs only, nothing answered)."""
        if self.reference:
            unreadable = sorted(profile.capabilities - {cap.DRIVE_BASE})
            if unreadable:
                raise ProfileError(
                    f"{profile.name}: the reference StackMod firmware drives motors only and "
                    f"answers nothing, so it cannot offer {', '.join(unreadable)} "
                    "(extend stackmod-reference instead)"
                )
        self.full_power = PWM_MAX if self.reference else 100
        """The motor value of full power on the wire: PWM 255 (reference) or 100 %."""
        self.poller = get_poller(
            timeout_s=opts.get_timeout_s, retries=opts.get_retries, describe=opts.describe_module
        )
        self.lost_sets = 0
        """Motor SETs found not applied by the heartbeat (and sent again)."""
        self._unconfirmed = list(opts.module_roles)
        self._arm_refusals: dict[int, int] = {}
        self._readings: dict[_Key, tuple[int, float]] = {}
        self._wanted_until: dict[_Key, float] = {}
        self._sensor_keys: list[_Key] = []
        self._next_sensor = 0
        # Motors: power per wheel in wire units (forward positive, before inversion).
        self._motors = (opts.left_motor, opts.right_motor)
        self._signs = (-1 if opts.invert_left else 1, -1 if opts.invert_right else 1)
        self._target_power = [0, 0]
        self._sent_power: list[int | None] = [None, None]
        self._heartbeat_wheel = 0
        self._heartbeat_s = -math.inf
        self._heartbeat_expect: tuple[int, int] | None = None
        # Odometry estimated from the power sent and the time it was applied.
        self.wheel_distances_mm = [0.0, 0.0]
        self._integrated_to_s: float | None = None
        # Servos and buzzer.
        self._servo_targets: dict[int, int] = {}
        self._servo_sent: dict[int, int] = {}
        self._buzzer_on = False
        self._buzzer_for_s: float | None = None
        self._buzzer_off_at_s: float | None = None

    # ----------------------------------------------------------------------------- handshake

    def start(self) -> None:
        """Arm every module; the GETs that confirm it go out in the act phase.

        The reference firmware has no ARM and answers nothing: the robot is ready at once.
        """
        if self.reference:
            self._unconfirmed = []
            self._become_ready()
            self.notice(
                f"{self.profile.name}: the reference StackMod firmware answers nothing, so "
                "roboscript cannot tell whether the module is there or took a packet: "
                "watch the wheels"
            )
            return
        for address in self._unconfirmed:
            self.link.send(Set(address, Command.ARM, 0, 1))

    def _confirm(self, reply: GetReply) -> None:
        if reply.value != 1:
            refusals = self._arm_refusals.get(reply.address, 0) + 1
            self._arm_refusals[reply.address] = refusals
            if refusals > self.options.get_retries:
                raise DeviceError(
                    f"{self.options.describe_module(reply.address)} stays disarmed "
                    f"after {refusals} ARM requests"
                )
            # The ARM SET was lost on the line: arm again, then ask again.
            self.link.send(Set(reply.address, Command.ARM, 0, 1))
            return
        if reply.address in self._unconfirmed:
            self._unconfirmed.remove(reply.address)
        if not self._unconfirmed:
            self._become_ready()

    def _become_ready(self) -> None:
        opts = self.options
        self.stop_all()
        makers: dict[str, Callable[[], object]] = {
            cap.DRIVE_BASE: lambda: WheelDriveBase(
                self,
                lambda: (self.wheel_distances_mm[0], self.wheel_distances_mm[1]),
                odometry_is_estimated=True,
            ),
            cap.RANGE: lambda: _RangeSensor(self, 0),
            cap.SIDE_RANGE: lambda: _SideRangeSensor(self, 1),
            cap.LINE: lambda: _LineSensors(self),
            cap.BUMPER: lambda: _Bumpers(self),
            cap.SPEAKER: lambda: _Buzzer(self),
            cap.SERVOS: lambda: _Servos(self),
        }
        if self.reference:
            makers = {cap.DRIVE_BASE: makers[cap.DRIVE_BASE]}
        capabilities = self.wanted(makers)
        if not self.reference:
            self._sensor_keys = [
                *((opts.ultrasonic_address, Command.ULT, i) for i in (0, 1)),
                *((opts.ir_address, Command.IRS, i) for i in range(3)),
                *((opts.io_address, Command.DGT, pin) for pin in opts.bumper_pins),
            ]
        self.offer(capabilities)
        self.notice(
            f"{self.profile.name} has no wheel encoders: distances and angles are estimated "
            f"from time ({opts.wheel_speed_mm_s_per_pct:g} mm/s per % of motor power), so "
            "drive and rotate run on time and cannot tell when the robot is stuck"
        )

    def describe(self) -> str:
        """The modules and their addresses."""
        if self.reference:
            return (
                f"StackMod author's firmware (motor module {chr(self.options.motor_address)}, "
                f"{self.options.framing} framing, PWM ±{PWM_MAX}, answers nothing)"
            )
        roles = self.options.module_roles
        modules = ", ".join(f"{'/'.join(r)} {chr(a)}" for a, r in roles.items())
        return f"StackMod modules ({modules}; {self.options.checksum} checksum)"

    # ------------------------------------------------------------------------- sense / act

    def tick(self, now_s: float, dt_s: float) -> None:
        """Read replies, integrate odometry, resend an overdue GET.

        Raises:
            LinkTimeoutError: A module left a GET unanswered after every retry.
            LinkClosedError: The line was lost.
            DeviceError: A module stayed disarmed after every ARM (handshake).
        """
        self._integrate(now_s)
        for message in self.link.poll():
            if isinstance(message, GetReply):
                self._handle(message, now_s)
        again = self.poller.resend_due(now_s)
        if again is not None:
            logger.debug("no answer to %s yet: sending it again", again)
            self.link.send(again)

    def _handle(self, reply: GetReply, now_s: float) -> None:
        self.poller.answered(reply)
        key = (reply.address, reply.command, reply.selector)
        self._readings[key] = (reply.value, now_s)
        if reply.command is Command.ARM and not self.ready:
            self._confirm(reply)
        elif reply.command is Command.MTR and self._heartbeat_expect is not None:
            motor, expected = self._heartbeat_expect
            if reply.address == self.options.motor_address and reply.selector == motor:
                self._heartbeat_expect = None
                wheel = self._motors.index(motor)
                # A newer SET may be on its way; only a power nobody changed since is lost.
                if reply.value != expected and self._sent_wire(wheel) == expected:
                    self.lost_sets += 1
                    self._sent_power[wheel] = None

    def flush(self, now_s: float, dt_s: float) -> None:
        """Send changed setpoints, then the next GET if none is in flight."""
        if self.ready:
            self._flush_motors()
            self._flush_servos()
            self._flush_buzzer(now_s)
        if self.reference:
            return  # the firmware answers no GET: asking would only waste the bus
        if self.poller.in_flight is None:
            request = self._next_request(now_s)
            if request is not None:
                self.link.send(request)
                self.poller.sent(request, now_s)

    def _sent_wire(self, wheel: int) -> int | None:
        """The MTR value last sent for ``wheel`` (sign as on the wire), or ``None``."""
        sent = self._sent_power[wheel]
        return None if sent is None else sent * self._signs[wheel]

    def _flush_motors(self) -> None:
        for wheel in (0, 1):
            if self._target_power[wheel] != self._sent_power[wheel]:
                value = self._target_power[wheel] * self._signs[wheel]
                self._send_motor(self._motors[wheel], value)
                self._sent_power[wheel] = self._target_power[wheel]

    def _send_motor(self, motor: int, value: int) -> None:
        """Send one motor's power, in wire units, in the firmware's own packet."""
        address = self.options.motor_address
        if self.reference:
            self.link.send(MotorPwm(address, motor, value, HOST_SOURCE))
        else:
            self.link.send(Set(address, Command.MTR, motor, value))

    def _flush_servos(self) -> None:
        for number, angle in self._servo_targets.items():
            if self._servo_sent.get(number) != angle:
                self.link.send(Set(self.options.servo_address, Command.SRV, number, angle))
                self._servo_sent[number] = angle

    def _flush_buzzer(self, now_s: float) -> None:
        if self._buzzer_for_s is not None:
            # Timed from the moment the pin is set, so the beep lasts as long as asked.
            self._buzzer_off_at_s = now_s + self._buzzer_for_s
            self._buzzer_for_s = None
        off_at = self._buzzer_off_at_s
        sound = off_at is not None and now_s < off_at - 1e-9
        if sound != self._buzzer_on:
            opts = self.options
            self.link.send(Set(opts.io_address, Command.DGT, opts.buzzer_pin, int(sound)))
            self._buzzer_on = sound
        if not sound:
            self._buzzer_off_at_s = None

    def _next_request(self, now_s: float) -> Get | None:
        if not self.ready:
            if not self._unconfirmed:
                return None
            return Get(self._unconfirmed[0], Command.ARM, 0)
        if now_s - self._heartbeat_s >= _HEARTBEAT_S - 1e-9:
            return self._heartbeat(now_s)
        keys = self._sensor_keys
        for offset in range(len(keys)):
            index = (self._next_sensor + offset) % len(keys)
            if self._wanted_until.get(keys[index], -math.inf) >= now_s:
                self._next_sensor = index + 1
                address, command, selector = keys[index]
                return Get(address, command, selector)
        return None

    def _heartbeat(self, now_s: float) -> Get:
        wheel = self._heartbeat_wheel
        self._heartbeat_wheel = 1 - wheel
        self._heartbeat_s = now_s
        motor = self._motors[wheel]
        sent = self._sent_wire(wheel)
        self._heartbeat_expect = None if sent is None else (motor, sent)
        return Get(self.options.motor_address, Command.MTR, motor)

    def _integrate(self, now_s: float) -> None:
        """Advance the estimated wheel distances to ``now_s`` at the power last sent."""
        last = self._integrated_to_s
        self._integrated_to_s = now_s
        if last is None or now_s <= last:
            return
        per_unit = self.options.wheel_speed_mm_s_per_pct * 100.0 / self.full_power
        for wheel in (0, 1):
            self.wheel_distances_mm[wheel] += (
                (self._sent_power[wheel] or 0) * per_unit * (now_s - last)
            )

    def send_stop(self) -> None:
        """Send MTR +000 to both motors and silence the buzzer."""
        self._integrate(self.clock.now())
        self._target_power = [0, 0]
        opts = self.options
        for wheel in (0, 1):
            self._sent_power[wheel] = 0
            self._send_motor(self._motors[wheel], 0)
        self._buzzer_for_s = self._buzzer_off_at_s = None
        if self._buzzer_on:
            self._buzzer_on = False
            self.link.send(Set(opts.io_address, Command.DGT, opts.buzzer_pin, 0))

    # ------------------------------------------------------------------ capability plumbing

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Store wheel speed targets as motor power (sent in the act phase)."""
        self._target_power = [self._power(left_mm_s), self._power(right_mm_s)]

    def _power(self, speed_mm_s: float) -> int:
        """The motor value, in wire units, that turns a wheel at ``speed_mm_s`` (estimated)."""
        opts = self.options
        full = self.full_power
        power = round(speed_mm_s / opts.wheel_speed_mm_s_per_pct * full / 100.0)
        power = max(-full, min(full, power))
        least = math.ceil(opts.min_power_pct * full / 100.0)
        if 0 < abs(power) < least:
            power = least if power > 0 else -least
        return power

    def reading(self, keys: Iterable[_Key]) -> list[int] | None:
        """The fresh readings of ``keys``, or ``None`` if any is missing or stale.

        Reading a sensor also asks for it to be polled for the next second.
        """
        now_s = self.clock.now()
        keys = list(keys)
        for key in keys:
            self._wanted_until[key] = now_s + _WANT_HOLD_S
        values = []
        for key in keys:
            found = self._readings.get(key)
            if found is None or now_s - found[1] > _STALE_S:
                return None
            values.append(found[0])
        return values

    def set_servo(self, number: int, angle_deg: int) -> None:
        """Store a servo position (sent in the act phase)."""
        self._servo_targets[number] = angle_deg

    def beep(self, duration_s: float) -> None:
        """Sound the buzzer for ``duration_s`` seconds from the next act phase (scheduler clock)."""
        self._buzzer_for_s = duration_s


class _RangeSensor:
    max_range_mm = 4000.0

    def __init__(self, driver: StackModDriver, sensor: int) -> None:
        self._driver = driver
        self._key = (driver.options.ultrasonic_address, Command.ULT, sensor)

    def distance_mm(self) -> float | None:
        values = self._driver.reading([self._key])
        if values is None or values[0] == ULT_NO_ECHO:
            return None
        return values[0] * 10.0


class _SideRangeSensor(_RangeSensor):
    side = "right"


class _LineSensors:
    names = ("left", "center", "right")
    dark_threshold = 500.0

    def __init__(self, driver: StackModDriver) -> None:
        self._driver = driver
        self._keys = [(driver.options.ir_address, Command.IRS, i) for i in range(3)]

    def values(self) -> tuple[float, ...] | None:
        values = self._driver.reading(self._keys)
        return None if values is None else tuple(float(v) for v in values)


class _Bumpers:
    names = ("left", "right")

    def __init__(self, driver: StackModDriver) -> None:
        self._driver = driver
        opts = driver.options
        self._keys = [(opts.io_address, Command.DGT, pin) for pin in opts.bumper_pins]

    def pressed(self) -> frozenset[str]:
        # Each switch is read on its own, so one late answer does not hide the other.
        return frozenset(
            name
            for name, key in zip(self.names, self._keys, strict=True)
            if self._driver.reading([key]) == [1]
        )


class _Buzzer:
    """An active buzzer on a digital pin: one pitch, any length."""

    def __init__(self, driver: StackModDriver) -> None:
        self._driver = driver
        self.fixed_frequency_hz = driver.options.buzzer_frequency_hz
        """The only pitch this speaker plays, hertz."""

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        if abs(frequency_hz - self.fixed_frequency_hz) > 1.0:
            text = (
                f"the buzzer has one pitch ({self.fixed_frequency_hz:g} Hz): "
                "play_tone frequencies are ignored"
            )
            self._driver.notice(text)
        self._driver.beep(max(0.0, duration_s))


class _Servos:
    def __init__(self, driver: StackModDriver) -> None:
        self._driver = driver
        self.count = driver.options.servo_count

    def set_angle(self, index: int, angle_deg: float) -> None:
        if not 0 <= index < self.count:
            raise ValueError(f"servo index must be 0..{self.count - 1}, got {index}")
        if not 0.0 <= angle_deg <= 180.0:
            raise ValueError(f"a servo angle must be 0-180 degrees, got {angle_deg:g}")
        # Servos are numbered from 1 on the wire, as in the StackMod document's example.
        self._driver.set_servo(index + 1, round(angle_deg))
