"""Completion and failure detectors for closed-loop moves."""

from __future__ import annotations

__all__ = ["Settle", "Stall"]


class Settle:
    """True once an error has stayed within a tolerance for a dwell time.

    Args:
        tolerance: Largest acceptable absolute error (in the error's unit).
        dwell_s: How long it must stay within tolerance, seconds.
    """

    def __init__(self, tolerance: float, dwell_s: float) -> None:
        self.tolerance = tolerance
        self.dwell_s = dwell_s
        self._inside_s = 0.0

    def update(self, error: float, dt_s: float) -> bool:
        """Feed the current error; return True when settled."""
        if abs(error) > self.tolerance:
            # Outside is never settled, even with no dwell at all.
            self._inside_s = 0.0
            return False
        self._inside_s += dt_s
        return self._inside_s >= self.dwell_s - 1e-9


class Stall:
    """True when a powered mechanism has not moved for a while.

    Args:
        min_progress: Movement that counts as progress (e.g. 2 mm of wheel travel).
        window_s: How long without progress means stalled, seconds.
    """

    def __init__(self, min_progress: float = 2.0, window_s: float = 1.0) -> None:
        self.min_progress = min_progress
        self.window_s = window_s
        self._mark_s = 0.0
        self._mark = 0.0

    def reset(self, now_s: float, position: float) -> None:
        """Start watching from ``position`` at ``now_s``."""
        self._mark_s = now_s
        self._mark = position

    def update(self, now_s: float, position: float) -> bool:
        """Feed the current position; return True if it has not moved for the window."""
        if abs(position - self._mark) >= self.min_progress:
            self.reset(now_s, position)
            return False
        return now_s - self._mark_s >= self.window_s
