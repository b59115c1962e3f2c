"""Host-side control loops on simple-pid, for robots whose firmware cannot close them.

Every loop takes ``dt`` from the scheduler (simple-pid is built with ``sample_time=None``, so
each call computes; ``dt`` is never 0) and never reads a clock itself.
"""

from __future__ import annotations

from roboscript.control.pid import make_pid
from roboscript.control.wheel_speed import WheelSpeedLoop

__all__ = ["WheelSpeedLoop", "make_pid"]
