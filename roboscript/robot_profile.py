"""A robot profile: what a robot is, which protocol it speaks and what it can do.

The built-in profiles live with their protocol (``drivers/<protocol>/profiles.py``, named by
its :class:`~roboscript.drivers.unit.ProtocolUnit`); :mod:`roboscript.profiles` finds them,
and reads profile files that extend one. This module is the type alone, below them all.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from roboscript import capabilities as cap

__all__ = ["RobotProfile"]


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
