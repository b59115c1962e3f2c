"""The live status line ``roboscript run`` shows on a terminal.

One line, rewritten in place a few times a second (wall clock), with the mission time, the
state, the action's progress and the pose (simulator) or the distance ahead (real robot).
State changes are printed as lines of their own above it. Nothing of this is printed when
standard error is not a terminal, or with ``--json``/``--quiet``.
"""

from __future__ import annotations

import time
from typing import Any, TextIO

__all__ = ["StatusLine"]

_CLEAR = "\r\x1b[K"


class StatusLine:
    """Writes progress to a terminal stream.

    Args:
        stream: Where to write (standard error).
        live: Whether to draw the rewritten status line (only on a terminal).
        interval_s: Least wall time between two redraws.
    """

    def __init__(self, stream: TextIO, *, live: bool, interval_s: float = 0.2) -> None:
        self.stream = stream
        self.live = live
        self.interval_s = interval_s
        self._last_draw = -float("inf")
        self._shown = False

    def state(self, time_s: float, name: str, why: str | None = None) -> None:
        """Print a state change as its own line, with why it happened in brackets."""
        self._clear()
        because = f"  [{why}]" if why else ""
        self.stream.write(f"{time_s:8.2f} s  {name}{because}\n")
        self.stream.flush()

    def warn(self, text: str) -> None:
        """Print a warning as its own line (even with ``--quiet``: it is about the code)."""
        self._clear()
        self.stream.write(text + "\n")
        self.stream.flush()

    def update(self, time_s: float, state: str, feedback: str, extra: str) -> None:
        """Redraw the status line if it is due."""
        if not self.live:
            return
        now = time.monotonic()
        if now - self._last_draw < self.interval_s:
            return
        self._last_draw = now
        text = f"{time_s:8.2f} s  {state}"
        if feedback:
            text += f"  {feedback}"
        if extra:
            text += f"  {extra}"
        self.stream.write(_CLEAR + text[:119])
        self.stream.flush()
        self._shown = True

    def close(self) -> None:
        """Remove the status line before the final result is printed."""
        self._clear()

    def _clear(self) -> None:
        if self._shown:
            self.stream.write(_CLEAR)
            self.stream.flush()
            self._shown = False


def describe_robot(robot: Any) -> str:
    """Pose from the simulator, else the distance ahead, for the status line."""
    sim = getattr(robot, "simulation", None)
    if sim is not None:
        x_mm, y_mm, heading_deg = sim.final_pose()  # heading in [-180, 180), as in --json
        return f"x {x_mm:6.0f} y {y_mm:6.0f} mm  heading {heading_deg:6.1f}°"
    capabilities = getattr(robot, "capabilities", {})
    sensor = capabilities.get("range")
    if sensor is not None:
        distance = sensor.distance_mm()
        return "ahead: no echo" if distance is None else f"ahead {distance / 10:.0f} cm"
    return ""
