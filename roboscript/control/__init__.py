"""Host-side control loops on simple-pid, for robots whose firmware cannot close them.

Every loop takes ``dt`` from the scheduler (simple-pid is built with ``sample_time=None``, so
each call computes; ``dt`` is never 0) and never reads a clock itself. Angles wrap the short
way round; outputs are limited.
"""

from __future__ import annotations

from roboscript.control.pid import make_pid
from roboscript.control.settle import Settle, Stall
from roboscript.control.steering import (
    HeadingHold,
    LineFollower,
    WallFollower,
    angle_error_deg,
    wheel_speeds,
)
from roboscript.control.wheel_speed import WheelSpeedLoop

__all__ = [
    "HeadingHold",
    "LineFollower",
    "Settle",
    "Stall",
    "WallFollower",
    "WheelSpeedLoop",
    "angle_error_deg",
    "make_pid",
    "wheel_speeds",
]
