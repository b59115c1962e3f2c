"""What a robot can do, as one small protocol per capability.

Actions and missions talk only to these protocols, never to a driver, so a mission that works
on one robot with a ``drive_base`` works on every robot with one, simulated or real.

Units and signs, stated once for the whole project:

* Distances in millimetres, times in seconds, angles in degrees, frequencies in hertz.
* Forward is positive: a positive wheel speed or distance moves the robot forward.
* **A positive turn is to the right** (clockwise seen from above), as in Pybricks and the ASIP
  firmware. Headings are degrees clockwise from the robot's start direction (world files:
  clockwise from north).
* Sensors return ``None`` when they have no reading (nothing received yet, or no echo).

Capability names (the keys of :attr:`Robot.capabilities <roboscript.robot.Robot.capabilities>`
and the roots of mission guards) are the constants below.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

__all__ = [
    "BUMPER",
    "BUTTONS",
    "CAPABILITY_NAMES",
    "COLOR",
    "DISPLAY",
    "DRIVE_BASE",
    "FORCE",
    "HEADING",
    "JOINTS",
    "LEDS",
    "LINE",
    "MOTORS",
    "RANGE",
    "SERVOS",
    "SIDE_RANGE",
    "SPEAKER",
    "WALKER",
    "Bumpers",
    "ColorSensor",
    "Display",
    "DriveBase",
    "ForceSensor",
    "HeadingSensor",
    "HubButtons",
    "Joints",
    "Leds",
    "LineSensors",
    "Motors",
    "RangeSensor",
    "Servos",
    "SideRangeSensor",
    "Speaker",
    "Walker",
]

DRIVE_BASE = "drive_base"
RANGE = "range"
SIDE_RANGE = "side_range"
BUMPER = "bumper"
LINE = "line"
SPEAKER = "speaker"
DISPLAY = "display"
HEADING = "heading"
LEDS = "leds"
SERVOS = "servos"
WALKER = "walker"
JOINTS = "joints"
FORCE = "force"
COLOR = "color"
BUTTONS = "buttons"
MOTORS = "motors"

CAPABILITY_NAMES: dict[str, str] = {
    DRIVE_BASE: "two driven wheels with encoders or timing",
    RANGE: "a distance sensor (ultrasonic or time of flight)",
    SIDE_RANGE: "a distance sensor facing sideways (for wall following)",
    BUMPER: "bump switches",
    LINE: "downward IR line sensors",
    SPEAKER: "a tone generator",
    DISPLAY: "a text display (LCD or light matrix)",
    HEADING: "an IMU or compass heading",
    LEDS: "RGB LEDs",
    SERVOS: "hobby servos",
    WALKER: "legs that walk by gait motions",
    JOINTS: "servo joints moved by name (humanoid limbs)",
    FORCE: "a force (push) sensor",
    COLOR: "a colour sensor (reflection, colour, RGB)",
    BUTTONS: "buttons on the robot (a hub's left and right buttons)",
    MOTORS: "motors on numbered or lettered ports, besides the wheels (an arm, a claw)",
}
"""Every capability name with a phrase for error messages."""


@runtime_checkable
class DriveBase(Protocol):
    """Two driven wheels.

    Wheel speeds are closed-loop: the firmware holds them when it can (ASIP ``M,R``), else the
    host does (see :mod:`roboscript.control`). Robots without encoders estimate distances from
    time and a calibration, and say so through :attr:`odometry_is_estimated`.
    """

    track_mm: float
    """Distance between the wheel contact points, millimetres."""
    max_speed_mm_s: float
    """Fastest wheel speed the base can hold, mm/s."""
    odometry_is_estimated: bool
    """True when wheel distances are computed from time instead of encoders."""

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Hold each wheel at a speed, mm/s; positive drives forward.

        Equal speeds drive straight; ``left > right`` turns right (clockwise).
        """
        ...

    def stop(self) -> None:
        """Stop both wheels now."""
        ...

    def wheel_distances_mm(self) -> tuple[float, float]:
        """Distance each wheel (left, right) has rolled since connection, mm; forward > 0."""
        ...


@runtime_checkable
class RangeSensor(Protocol):
    """A forward-facing distance sensor."""

    max_range_mm: float
    """Readings beyond this are reported as no echo."""

    def distance_mm(self) -> float | None:
        """Distance to the nearest obstacle in mm, or ``None`` for no echo / no reading."""
        ...


@runtime_checkable
class SideRangeSensor(Protocol):
    """A distance sensor facing to one side, for following walls."""

    side: str
    """``"left"`` or ``"right"``: which way it faces."""
    max_range_mm: float
    """Readings beyond this are reported as no echo."""

    def distance_mm(self) -> float | None:
        """Distance from the sensor to the wall in mm, or ``None`` for no echo / no reading."""
        ...


@runtime_checkable
class Bumpers(Protocol):
    """Bump switches at the front."""

    names: tuple[str, ...]
    """Switch names, e.g. ``("left", "right")``."""

    def pressed(self) -> frozenset[str]:
        """The names of the switches pressed now."""
        ...


@runtime_checkable
class LineSensors(Protocol):
    """Downward-facing reflectance sensors."""

    names: tuple[str, ...]
    """Sensor names from left to right, e.g. ``("left", "center", "right")``."""
    dark_threshold: float
    """Readings above this are over a dark line."""

    def values(self) -> tuple[float, ...] | None:
        """Readings 0-1023 in the order of :attr:`names` (higher = darker), or ``None``."""
        ...


@runtime_checkable
class Speaker(Protocol):
    """A tone generator."""

    def beep(self, frequency_hz: float, duration_s: float) -> None:
        """Start a tone; returns at once (the tone plays for ``duration_s``)."""
        ...


@runtime_checkable
class Display(Protocol):
    """A small text display."""

    def show_text(self, text: str) -> None:
        """Show ``text`` (cut or scrolled to fit)."""
        ...

    def clear(self) -> None:
        """Blank the display."""
        ...


@runtime_checkable
class HeadingSensor(Protocol):
    """An IMU yaw or compass."""

    def heading_deg(self) -> float | None:
        """Heading in degrees, clockwise positive, or ``None`` before the first reading."""
        ...


@runtime_checkable
class Leds(Protocol):
    """RGB LEDs."""

    count: int

    def set_color(self, index: int, rgb: tuple[int, int, int]) -> None:
        """Set LED ``index`` (0-based) to ``rgb``, each channel 0-255."""
        ...


@runtime_checkable
class Servos(Protocol):
    """Hobby servos."""

    count: int

    def set_angle(self, index: int, angle_deg: float) -> None:
        """Move servo ``index`` (0-based) to ``angle_deg`` (0-180)."""
        ...


@runtime_checkable
class Walker(Protocol):
    """Legs moved by gait motions (humanoids)."""

    stride_mm: float
    """Approximate distance of one walking step on a flat floor, mm."""
    turn_step_deg: float
    """Approximate rotation of one turning step, degrees."""

    def walk(self, steps: int) -> None:
        """Start walking ``steps`` steps; negative walks backward."""
        ...

    def turn(self, steps: int) -> None:
        """Start turning ``steps`` steps; positive turns right."""
        ...

    def play_motion(self, slot: int) -> None:
        """Start the motion stored in ``slot`` of the robot's motion memory."""
        ...

    def busy(self) -> bool:
        """True while a gait motion is playing."""
        ...

    def stop(self) -> None:
        """Stop as soon as the robot stands safely.

        A humanoid finishes the step it is in (both feet down) rather than freezing on one
        leg, so :meth:`busy` may stay true for up to one step after this call.
        """
        ...


@runtime_checkable
class Joints(Protocol):
    """Servo joints addressed by name (a humanoid's limbs).

    Angles are offsets from each joint's home angle, in degrees; which way is positive for
    each joint is the robot's own convention (see its page under ``docs/robots/``).
    """

    names: tuple[str, ...]
    """Joint names, e.g. ``("left_shoulder_pitch", ...)``."""

    def set_angle(self, name: str, angle_deg: float) -> None:
        """Move joint ``name`` to ``angle_deg`` away from its home angle."""
        ...

    def angle_deg(self, name: str) -> float | None:
        """The offset last commanded for ``name``, degrees, or ``None`` if none was."""
        ...

    def home(self) -> None:
        """Move every joint to its home angle."""
        ...


@runtime_checkable
class ForceSensor(Protocol):
    """A push sensor (the SPIKE force sensor)."""

    def force_n(self) -> float | None:
        """Force on the tip in newtons (0 to about 10), or ``None`` before the first reading."""
        ...

    def pressed(self) -> bool:
        """True while the tip is pushed in."""
        ...


@runtime_checkable
class ColorSensor(Protocol):
    """A colour sensor, usually looking down at the floor."""

    def reflection_percent(self) -> float | None:
        """Light reflected by the surface, 0 (black) to 100 (white), or ``None`` for none."""
        ...

    def color_name(self) -> str | None:
        """The colour seen (``"black"``, ``"red"``, ``"white"``, ...), or ``None`` for none."""
        ...

    def rgb(self) -> tuple[int, int, int] | None:
        """Raw red, green and blue, each 0-1023, or ``None`` before the first reading."""
        ...


@runtime_checkable
class HubButtons(Protocol):
    """Buttons on the robot a program can read (a SPIKE hub's left and right buttons)."""

    names: tuple[str, ...]
    """Button names, e.g. ``("left", "right")``."""

    def pressed(self) -> frozenset[str]:
        """The names of the buttons held down now."""
        ...


@runtime_checkable
class Motors(Protocol):
    """Motors on ports besides the wheels (an arm on port C), each with an encoder.

    Angles and speeds are the motor's own: positive turns it clockwise seen from its face.
    """

    ports: tuple[str, ...]
    """The ports that have such a motor, e.g. ``("C", "F")``."""

    def run(self, port: str, speed_deg_s: float) -> None:
        """Turn the motor at ``speed_deg_s`` until :meth:`stop` (0 stops it)."""
        ...

    def run_for_degrees(self, port: str, angle_deg: float, speed_deg_s: float) -> int:
        """Start turning the motor by ``angle_deg`` (negative: the other way) at
        ``speed_deg_s`` (positive); returns a handle for :meth:`move_result`."""
        ...

    def move_result(self, handle: int) -> str | None:
        """``None`` while the move runs, then ``"done"``, ``"stalled"``, ``"cancelled"`` or
        ``"failed"``."""
        ...

    def stop(self, port: str) -> None:
        """Brake the motor now (and end its move ``cancelled``)."""
        ...
