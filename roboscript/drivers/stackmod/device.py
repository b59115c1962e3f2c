"""Simulated StackMod modules: the robot's side of the line, on a simulated body.

A second, independent implementation of the protocol's device side (it never imports the host
driver), wired as :class:`~roboscript.drivers.stackmod.options.StackModOptions` says. Every
module listens to the one line and acts only on packets carrying its own address:

* **Motor module**: ``MTR`` SET sets a motor's power (-100..100 %) on the body; GET answers the
  power last set. Motors other than the left and right wheels' are ignored.
* **Servo module**: ``SRV`` SET moves servo 1..servo_count (0-180 degrees; 90 at power-on);
  GET answers the position last set.
* **Ultrasonic module**: ``ULT`` GET of sensor 0 (facing forward) or 1 (facing right) answers
  the body's range in whole cm, or 999 when there is no echo.
* **IR module**: ``IRS`` GET of sensor 0, 1, 2 (left, center, right) answers the body's line
  reading 0-1023.
* **Every module**: ``ARM`` SET arms (1) or disarms (0) it and GET answers which; ``DGT`` SET
  latches a digital output and GET reads a pin; ``ANL`` GET of channel 0 reads the battery
  through a 1:2 divider (757 = 7.4 V on a 5 V, 10-bit converter), other channels read 0.
  On the IO module the bump-switch pins read 1 while pressed and the buzzer pin sounds the
  buzzer (logged as a tone of its one pitch when it stops).

Modules power on **armed**: ``ARM`` has no data format in the seed, so a module built on the
seed alone cannot require it, and a plain seed ``{M$MTR1+050}`` moves the motor. ``ARM`` is
roboscript's own extension: a host that disarms a module (``{M$ARM00}``) stops its outputs
(motors at 0, buzzer silent), and the module then ignores SETs of them, saying so in one log
line, until it is armed again. No module answers a SET, a packet with a bad checksum, a command
it does not have, or a selector it does not have: the packet is dropped as a real module
would, and the host's GET times out.

A profile with ``firmware: reference`` gets the StackMod author's own module instead
(:mod:`roboscript.drivers.stackmod.reference_device`).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from roboscript.codec import Role, readable
from roboscript.drivers.stackmod.codec import StackModCodec
from roboscript.drivers.stackmod.messages import ULT_NO_ECHO, Command, Get, Set
from roboscript.drivers.stackmod.options import StackModOptions, address_name
from roboscript.drivers.stackmod.reference_device import ReferenceModule

if TYPE_CHECKING:
    from roboscript.robot_profile import RobotProfile
    from roboscript.sim.body import Body

__all__ = ["BATTERY_ADC", "SERVO_HOME_DEG", "StackModRover", "simulated_device"]

logger = logging.getLogger(__name__)

BATTERY_ADC = 757
"""ANL channel 0 of every module: a 7.4 V battery through a 1:2 divider, 5 V reference."""
SERVO_HOME_DEG = 90
"""Where the servos stand at power-on, degrees."""
_MAX_RANGE_CM = 400


@dataclass
class _Module:
    """The state one module board keeps."""

    armed: bool = True
    told_disarmed: bool = False
    """Whether the log has said since the last disarm that this module ignores SETs."""
    outputs: dict[int, int] = field(default_factory=dict)
    """Digital pin -> level last SET (0 or 1)."""


class StackModRover:
    """The modules of a StackMod rover on a simulated body (see the module docstring).

    Args:
        body: The simulated body the modules drive and sense.
        options: The robot's addresses and wiring (the profile's options).

    Attributes:
        codec: The device-role codec; its ``stats`` count the packets dropped.
        modules: Each module's state, by address.
        motor_values: Motor number -> power last set, percent, as on the wire.
        servo_deg: Servo number -> position, degrees.
    """

    def __init__(self, body: Body, options: StackModOptions | None = None) -> None:
        self.body = body
        self.options = opts = options or StackModOptions()
        self.codec = self._codec()
        self.modules = {address: _Module() for address in opts.module_roles}
        self.motor_values = dict.fromkeys((opts.left_motor, opts.right_motor), 0)
        self.servo_deg = dict.fromkeys(range(1, opts.servo_count + 1), SERVO_HOME_DEG)
        self._buzzer_since_s: float | None = None
        self._out = bytearray()
        self._now_s = 0.0

    # ------------------------------------------------------------------------- SimDevice API

    def connect(self, now_s: float) -> None:
        """A host opened the line: the modules keep their state but drop a half packet."""
        self._now_s = now_s
        self.codec = self._codec()

    def _codec(self) -> StackModCodec:
        opts = self.options
        return StackModCodec(Role.DEVICE, checksum=opts.checksum, framing=opts.framing)

    def receive(self, data: bytes, now_s: float) -> None:
        """Act on request bytes and queue the answers to GETs."""
        self._now_s = now_s
        self.codec.receive_data(data)
        for message in readable(self.codec):  # a real module drops what it cannot read
            if isinstance(message, Set):
                self._set(message)
            elif isinstance(message, Get):
                self._get(message)

    def step(self, now_s: float) -> None:
        """Nothing in the modules runs on a timer; the time is kept for the tone log."""
        self._now_s = now_s

    def pending_input_bytes(self) -> int:
        """Request bytes received and not yet a whole message (a frame the host has not
        finished)."""
        return self.codec.buffered

    def read_output(self) -> bytes:
        """Take the bytes written since the last call."""
        data = bytes(self._out)
        self._out.clear()
        return data

    def stop_all(self) -> None:
        """Power loss: every module comes back as at power-on, outputs off and armed."""
        for address, module in self.modules.items():
            self._disarm(address)
            module.armed = True

    # --------------------------------------------------------------------------------- SET

    def _set(self, message: Set) -> None:
        module = self.modules.get(message.address)
        if module is None:
            return
        opts = self.options
        command = message.command
        if command is Command.ARM:
            if message.selector != 0:
                return
            if message.value == 1:
                module.armed = True
            else:
                self._disarm(message.address)
        elif not module.armed:
            if not module.told_disarmed:
                module.told_disarmed = True
                logger.warning(
                    "simulated StackMod module %s ignores %s SETs: a host disarmed it "
                    "with ARM 0 (send ARM 1 to arm it again)",
                    address_name(message.address),
                    command.value,
                )
            return
        elif command is Command.MTR and message.address == opts.motor_address:
            if message.selector in self.motor_values:
                self.motor_values[message.selector] = message.value
                self._apply_motors()
        elif command is Command.SRV and message.address == opts.servo_address:
            if message.selector in self.servo_deg:
                self.servo_deg[message.selector] = message.value
        elif command is Command.DGT and not self._is_bumper(message.address, message.selector):
            module.outputs[message.selector] = message.value
            self._update_buzzer()

    def _disarm(self, address: int) -> None:
        self.modules[address].armed = False
        self.modules[address].told_disarmed = False
        self.modules[address].outputs.clear()
        if address == self.options.motor_address:
            for motor in self.motor_values:
                self.motor_values[motor] = 0
            self._apply_motors()
        self._update_buzzer()

    def _apply_motors(self) -> None:
        opts = self.options
        left = self.motor_values[opts.left_motor] * (-1 if opts.invert_left else 1)
        right = self.motor_values[opts.right_motor] * (-1 if opts.invert_right else 1)
        self.body.set_power(left / 100.0, right / 100.0)

    def _is_bumper(self, address: int, pin: int) -> bool:
        return address == self.options.io_address and pin in self.options.bumper_pins

    def _update_buzzer(self) -> None:
        """Start or end a tone when the buzzer pin changes; a tone is logged when it ends."""
        opts = self.options
        on = self.modules[opts.io_address].outputs.get(opts.buzzer_pin, 0) == 1
        since = self._buzzer_since_s
        if on and since is None:
            self._buzzer_since_s = self._now_s
        elif not on and since is not None:
            self._buzzer_since_s = None
            self.body.log.tones.append(
                (since, opts.buzzer_frequency_hz, round(self._now_s - since, 6))
            )

    # --------------------------------------------------------------------------------- GET

    def _get(self, request: Get) -> None:
        value = self._read(request)
        if value is not None:
            self._out += self.codec.send(request.reply(value))

    def _read(self, request: Get) -> int | None:
        """The value a GET answers, or ``None`` if no module at that address has it."""
        module = self.modules.get(request.address)
        if module is None:
            return None
        opts = self.options
        address, command, selector = request.address, request.command, request.selector
        if command is Command.ARM:
            return int(module.armed) if selector == 0 else None
        if command is Command.DGT:
            if self._is_bumper(address, selector):
                pressed = self.body.bumpers_pressed()
                return int(pressed[opts.bumper_pins.index(selector)])
            return module.outputs.get(selector, 0)
        if command is Command.ANL:
            return BATTERY_ADC if selector == 0 else 0
        if command is Command.MTR and address == opts.motor_address:
            return self.motor_values.get(selector)
        if command is Command.SRV and address == opts.servo_address:
            return self.servo_deg.get(selector)
        if command is Command.ULT and address == opts.ultrasonic_address and selector <= 1:
            return self._range_cm(self.body.side_range_mm() if selector else self.body.range_mm())
        if command is Command.IRS and address == opts.ir_address:
            readings = self.body.line_readings()
            return readings[selector] if selector < len(readings) else None
        return None

    @staticmethod
    def _range_cm(reading: float | None) -> int:
        if reading is None:
            return ULT_NO_ECHO
        cm = round(reading / 10.0)
        return cm if cm <= _MAX_RANGE_CM else ULT_NO_ECHO


def simulated_device(
    profile: RobotProfile,
) -> Callable[[Body], StackModRover | ReferenceModule]:
    """The StackMod unit's simulated device factory: the modules the profile's options list,
    or the author's own module for ``firmware: reference``.

    Raises:
        ProfileError: The profile's options are invalid (checked here, before any body).
    """
    options = StackModOptions.from_mapping(profile.options, profile=profile.name)
    if options.firmware == "reference":
        return lambda body: ReferenceModule(body, options)
    return lambda body: StackModRover(body, options)
