"""Clocks: the only source of time in roboscript.

Everything that needs the time (the scheduler, state timeouts, PID ``dt``, the simulator) asks
an injected :class:`Clock`, never ``time.time()``: a simulated run then jumps from tick to
tick and gives the same trace for the same seed, and a real run is paced by the wall clock.
"""

from __future__ import annotations

import ctypes
import sys
import threading
import time
from typing import Protocol, runtime_checkable

__all__ = ["DEFAULT_SPIN_S", "Clock", "MonotonicClock", "SimClock", "tighten_timer_slack"]


@runtime_checkable
class Clock(Protocol):
    """A source of time in seconds that can wait until a deadline."""

    def now(self) -> float:
        """Seconds since an arbitrary, fixed origin; never decreases."""
        ...

    def sleep_until(self, deadline_s: float) -> None:
        """Return once :meth:`now` has reached ``deadline_s`` (at once if it already has)."""
        ...


DEFAULT_SPIN_S = 50e-6
"""How long :class:`MonotonicClock` spins before a deadline by default, in seconds."""

_PR_SET_TIMERSLACK = 29  # <linux/prctl.h>
_TIMER_SLACK_NS = 1000


def tighten_timer_slack() -> bool:
    """Ask Linux to wake the calling thread within 1 µs of its timers, not 50 µs.

    Linux lets a timer fire up to the thread's *timer slack* late (50 µs by default) so that
    wake-ups can be batched. A control loop pays that on every tick: at 500 Hz it was half of
    the scheduler's median lateness (tests/bench/bench_scheduler.py). The setting is per
    thread and costs nothing while the thread runs.

    Returns:
        True if the slack was set (Linux only; elsewhere nothing happens).
    """
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return int(libc.prctl(_PR_SET_TIMERSLACK, _TIMER_SLACK_NS, 0, 0, 0)) == 0
    except (OSError, AttributeError):
        return False


class MonotonicClock:
    """Real time from ``time.monotonic``; :meth:`sleep_until` really sleeps.

    The first :meth:`sleep_until` on each thread tightens that thread's timer slack (see
    :func:`tighten_timer_slack`), so sleeps end closer to their deadlines.

    Args:
        spin_s: The last part of each wait, in seconds, is spent polling the clock instead of
            sleeping. Waking a sleeping thread takes tens of microseconds (more on a virtual
            machine); a short spin absorbs that for the cost of a little CPU. 0 never spins.
    """

    def __init__(self, *, spin_s: float = DEFAULT_SPIN_S) -> None:
        if spin_s < 0:
            raise ValueError("spin_s cannot be negative")
        self._origin = time.monotonic()
        self._tightened_thread: int | None = None
        self.spin_s = spin_s

    def now(self) -> float:
        """Seconds since this clock was made."""
        return time.monotonic() - self._origin

    def sleep_until(self, deadline_s: float) -> None:
        """Sleep until ``deadline_s``; absolute deadlines keep a loop from drifting."""
        thread = threading.get_ident()
        if thread != self._tightened_thread:
            tighten_timer_slack()
            self._tightened_thread = thread
        target = deadline_s + self._origin  # in time.monotonic()'s terms
        remaining = target - time.monotonic() - self.spin_s
        if remaining > 0:
            time.sleep(remaining)
        while time.monotonic() < target:
            pass


class SimClock:
    """Virtual time that jumps: :meth:`sleep_until` moves the clock, it never waits.

    Args:
        start_s: The time the clock starts at, in seconds.
    """

    def __init__(self, start_s: float = 0.0) -> None:
        self._now = start_s

    def now(self) -> float:
        """The current virtual time in seconds."""
        return self._now

    def sleep_until(self, deadline_s: float) -> None:
        """Jump to ``deadline_s`` (never backwards)."""
        self._now = max(self._now, deadline_s)

    def advance(self, duration_s: float) -> None:
        """Move the clock forward by ``duration_s`` seconds (must not be negative)."""
        if duration_s < 0:
            raise ValueError("a clock cannot go backwards")
        self._now += duration_s
