"""Robot profiles: what a robot is, which protocol it speaks and what it can do.

Built-in profiles are defined here; a profile file (YAML) starts from a built-in one and
changes what differs::

    extends: mirto
    name: mirto-classroom-3
    track_mm: 165
    gains:
      wheel_speed: [0.004, 0.02, 0.0]
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

from roboscript import capabilities as cap
from roboscript.errors import InputError, ProfileError, did_you_mean

__all__ = ["BUILTIN_PROFILES", "RobotProfile", "get_profile", "register_profile"]


@dataclass(frozen=True)
class RobotProfile:
    """A robot model.

    Attributes:
        name: Profile name (``mirto``, ``asip-basic``, ...).
        protocol: Protocol family: ``asip``, ``spike``, ``stackmod`` or ``plen``.
        description: One line for ``roboscript robots``.
        baudrate: Serial speed, bits per second.
        capabilities: Capability names the robot has (see :mod:`roboscript.capabilities`).
        firmware_pid: True if the firmware holds wheel speeds itself.
        wheel_diameter_mm: Wheel diameter.
        track_mm: Distance between the wheels.
        ticks_per_rev: Encoder ticks per wheel revolution.
        body_radius_mm: Radius of the body (simulated collisions).
        max_speed_mm_s: Fastest wheel speed the robot holds reliably.
        gains: Host PID gains ``(kp, ki, kd)`` by loop name (``wheel_speed``, ``heading``,
            ``wall``, ``line``).
        handshake_timeout_s: How long to wait for the robot to answer at connection.
        encoders: False for wheels without encoders (moves are timed from a calibration).
        options: Protocol-specific settings (StackMod: module addresses, wiring and
            calibration, see :mod:`roboscript.drivers.stackmod.options`); empty for others.
    """

    name: str
    protocol: str
    description: str
    baudrate: int
    capabilities: frozenset[str]
    firmware_pid: bool
    wheel_diameter_mm: float = 64.0
    track_mm: float = 162.0
    ticks_per_rev: int = 1632
    body_radius_mm: float = 100.0
    max_speed_mm_s: float = 300.0
    gains: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    handshake_timeout_s: float = 3.0
    options: dict[str, Any] = field(default_factory=dict)
    encoders: bool = True

    @property
    def control(self) -> str:
        """How the robot moves, in a few words, for ``roboscript robots``."""
        if cap.DRIVE_BASE not in self.capabilities:
            return "gait motions" if cap.WALKER in self.capabilities else "no wheels"
        if self.firmware_pid:
            return "firmware PID"
        return "host PID" if self.encoders else "timed moves"

    def lacks(self, capability: str) -> bool:
        """True if the robot does not have ``capability``."""
        return capability not in self.capabilities


_ASIP_CAPS = frozenset(
    {
        cap.DRIVE_BASE,
        cap.RANGE,
        cap.SIDE_RANGE,
        cap.BUMPER,
        cap.LINE,
        cap.SPEAKER,
        cap.DISPLAY,
        cap.SERVOS,
        cap.LEDS,
    }
)

BUILTIN_PROFILES: dict[str, RobotProfile] = {
    "mirto": RobotProfile(
        name="mirto",
        protocol="asip",
        description="MIRTO robot, ASIP 1.1 firmware with motor PID",
        baudrate=57600,
        capabilities=_ASIP_CAPS,
        firmware_pid=True,
        # The V1.1 mirtle2017 sketch: one servo, nine pixels; the LCD keeps 20 characters.
        options={"servo_count": 1, "pixel_count": 9, "lcd_columns": 20},
        # A board that resets when the port opens (an Uno-style 328 board) runs the sketch's
        # start-up for 3.2 s (pixelFun's three 1 s delays, then setup()) before it answers.
        handshake_timeout_s=5.0,
    ),
    "asip-basic": RobotProfile(
        name="asip-basic",
        protocol="asip",
        description="ASIP robot whose firmware has no PID: the host closes every loop",
        baudrate=57600,
        capabilities=_ASIP_CAPS,
        firmware_pid=False,
        gains={"wheel_speed": (0.0015, 0.004, 0.0)},
    ),
    "stackmod-rover": RobotProfile(
        name="stackmod-rover",
        protocol="stackmod",
        description="StackMod modules on a 9600 baud line: no encoders, timed moves",
        encoders=False,
        baudrate=9600,
        capabilities=frozenset(
            {
                cap.DRIVE_BASE,
                cap.RANGE,
                cap.SIDE_RANGE,
                cap.LINE,
                cap.BUMPER,
                cap.SPEAKER,
                cap.SERVOS,
            }
        ),
        firmware_pid=False,
        wheel_diameter_mm=65.0,
        track_mm=140.0,
        body_radius_mm=90.0,
        handshake_timeout_s=2.0,
    ),
    # The StackMod author's own firmware (74ls04/StackMod): motor SETs over I2C, nothing else.
    "stackmod-reference": RobotProfile(
        name="stackmod-reference",
        protocol="stackmod",
        description="StackMod author's motor firmware (I2C, PWM): drive only, timed moves",
        encoders=False,
        baudrate=100_000,  # I2C standard mode, Arduino Wire's default clock
        capabilities=frozenset({cap.DRIVE_BASE}),
        firmware_pid=False,
        wheel_diameter_mm=65.0,
        track_mm=140.0,
        body_radius_mm=90.0,
        handshake_timeout_s=2.0,
        options={
            "firmware": "reference",
            "checksum": "braces_excluded",
            "framing": "i2c",
            "motor_address": "E",
        },
    ),
    "spike-prime": RobotProfile(
        name="spike-prime",
        protocol="spike",
        description="LEGO SPIKE Prime hub (App 3 firmware) running roboscript's agent",
        baudrate=115200,
        capabilities=frozenset(
            {
                cap.DRIVE_BASE,
                cap.RANGE,
                cap.BUMPER,
                cap.SPEAKER,
                cap.DISPLAY,
                cap.HEADING,
                cap.FORCE,
                cap.COLOR,
                cap.LINE,  # the colour sensor, read as one line sensor
                cap.BUTTONS,
                cap.MOTORS,
            }
        ),
        firmware_pid=True,
        # Ports (options, roboscript/drivers/spike/options.py): drive motors A and B, force
        # sensor C, distance sensor D, colour sensor E (looking down), one more motor on F.
        # follow_line on the one colour sensor follows the tape's edge: the reading swings
        # from -1 to 1 across the edge's few millimetres, so it needs a softer steer than
        # three IR sensors (150): on the simulated line-track, kp 30-40 follows the whole run
        # and 50 loses the line at the start.
        gains={"line": (40.0, 0.0, 3.0)},
        # LEGO's driving base: 56 mm wheels, 112 mm apart; motor degrees are the encoder ticks.
        wheel_diameter_mm=56.0,
        track_mm=112.0,
        ticks_per_rev=360,
        body_radius_mm=90.0,
        max_speed_mm_s=350.0,
        # Room for a first upload of the agent over BLE (about 14 kB in 20-byte packets).
        handshake_timeout_s=20.0,
    ),
    "plen2": RobotProfile(
        name="plen2",
        protocol="plen",
        description="PLEN2 humanoid, firmware 1.4.2: walks and turns by gait motions",
        baudrate=2_000_000,
        capabilities=frozenset({cap.WALKER, cap.JOINTS}),
        firmware_pid=False,
        body_radius_mm=60.0,
        # Room for a first install of the four gait motions (32-byte writes 50 ms apart).
        handshake_timeout_s=20.0,
    ),
}


_REGISTERED: dict[str, RobotProfile] = {}


def register_profile(profile: RobotProfile) -> None:
    """Make a profile (from a file, say) findable by name in this process.

    ``sim://NAME`` URLs carry only a name; registering lets a profile file's robot be
    simulated in-process.
    """
    if profile.name not in BUILTIN_PROFILES:
        _REGISTERED[profile.name] = profile


def get_profile(name_or_path: str) -> RobotProfile:
    """Return a built-in or registered profile by name, or load a profile file.

    Raises:
        ProfileError: Unknown name, or an invalid profile file (with ``file:line:col``).
    """
    if name_or_path in BUILTIN_PROFILES:
        return BUILTIN_PROFILES[name_or_path]
    if name_or_path in _REGISTERED:
        return _REGISTERED[name_or_path]
    if name_or_path.endswith((".yaml", ".yml")) or Path(name_or_path).exists():
        return _load_profile_file(Path(name_or_path))
    raise ProfileError(
        f"no robot called '{name_or_path}' (built-in: {', '.join(BUILTIN_PROFILES)})",
        hint=did_you_mean(name_or_path, BUILTIN_PROFILES),
    )


_NUMBER_FIELDS = {
    f.name: f.type
    for f in fields(RobotProfile)
    if f.name in {"wheel_diameter_mm", "track_mm", "body_radius_mm", "max_speed_mm_s"}
}


def _load_profile_file(path: Path) -> RobotProfile:
    # YAML loads only for a profile file, so codecs and drivers import profiles without it
    from roboscript.inputs.fields import FieldReader
    from roboscript.inputs.source import YamlMap, load_yaml

    data = load_yaml(path, error=ProfileError)
    reader = FieldReader(str(path), ProfileError)

    def fail(message: str, key: str | None = None) -> InputError:
        mark = data.key_mark(key) if isinstance(data, YamlMap) and key else None
        return reader.fail(message, mark)

    if not isinstance(data, YamlMap):
        raise fail("a profile file must be a mapping with 'extends:' and the values to change")
    base_name = data.get("extends")
    if base_name not in BUILTIN_PROFILES:
        raise fail(
            f"'extends' must name a built-in robot ({', '.join(BUILTIN_PROFILES)})", "extends"
        )
    changes: dict[str, Any] = {"name": str(data.get("name", path.stem))}
    allowed = ("extends", "name", "description", "gains", "ticks_per_rev", *_NUMBER_FIELDS)
    reader.allowed(data, (*allowed, "options"), "a profile")
    for key, value in data.items():
        if key in _NUMBER_FIELDS or key == "ticks_per_rev":
            if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
                raise fail(f"'{key}' must be a positive number", key)
            changes[key] = int(value) if key == "ticks_per_rev" else float(value)
        elif key == "description":
            changes[key] = str(value)
        elif key == "gains":
            changes[key] = _read_gains(value, fail)
        elif key == "options":
            if not isinstance(value, dict):
                raise fail("'options' maps option names to values", key)
            # Values are checked by the protocol's driver, which knows what they mean.
            changes[key] = {**BUILTIN_PROFILES[base_name].options, **value}
    return replace(BUILTIN_PROFILES[base_name], **changes)


def _read_gains(value: Any, fail: Any) -> dict[str, tuple[float, float, float]]:
    if not isinstance(value, dict):
        raise fail("'gains' maps a loop name to [kp, ki, kd]", "gains")
    gains = {}
    for loop, triple in value.items():
        if (
            not isinstance(triple, list)
            or len(triple) != 3
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in triple)
        ):
            raise fail(f"gains for '{loop}' must be [kp, ki, kd]", "gains")
        gains[str(loop)] = (float(triple[0]), float(triple[1]), float(triple[2]))
    return gains
