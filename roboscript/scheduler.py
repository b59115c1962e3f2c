"""The tick loop: one thread, sense -> think -> act, on an injected clock.

Each tick calls every task of the ``sense`` phase (simulation steps, link polls), then
``think`` (the mission runner and its actions), then ``act`` (drivers flush setpoints), then
``after`` (telemetry, status lines). Tasks receive ``now_s`` and ``dt_s``; ``dt_s`` is always
greater than zero, because controllers divide by it (simple-pid refuses ``dt == 0``).

Real-time runs sleep until absolute deadlines on a fixed grid (``next += period``), which
does not drift the way ``sleep(period)`` does. A tick that starts more than one period late is
an *overrun*: it is counted and the measured ``dt_s`` is passed on.

A signal that ends the program (:mod:`roboscript.interrupts`) and that something a tick calls
catches and drops is raised again when that tick's tasks have run; one that landed in a finalizer
between two ticks, before the next.

After a stall (a slow tick, or the machine pausing the process for a few milliseconds) the loop
catches up with its grid, so a run keeps its tick rate, but never faster than two ticks per
period: a controller's ``dt_s`` never drops below half the period, where a back-to-back burst
would hand it near-zero ``dt`` values that amplify derivative noise. A loop that falls more than
``max_catch_up_periods`` behind gives the missed ticks up (counted in
:attr:`SchedulerStats.skipped_ticks`) and restarts its grid from now.

On a :class:`~roboscript.clock.SimClock` the loop jumps from deadline to deadline, so every
``dt_s`` equals the period exactly.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal, Protocol

from roboscript.clock import Clock
from roboscript.interrupts import kept, raise_dropped

__all__ = ["Phase", "Scheduler", "SchedulerStats", "Tickable"]

logger = logging.getLogger(__name__)

Phase = Literal["sense", "think", "act", "after"]
_PHASES: tuple[Phase, ...] = ("sense", "think", "act", "after")
_MIN_SPACING = 0.5  # of a period, between tick starts while catching up


class Tickable(Protocol):
    """Anything the scheduler calls once per tick."""

    def tick(self, now_s: float, dt_s: float) -> None:
        """Do one tick's work without blocking.

        Args:
            now_s: Scheduler time in seconds.
            dt_s: Seconds since the previous tick; always > 0.
        """
        ...


@dataclass
class SchedulerStats:
    """What the loop measured.

    Attributes:
        ticks: Ticks run.
        overruns: Ticks that started more than one period after their deadline.
        skipped_ticks: Ticks given up because the loop fell too far behind to catch up.
        max_lateness_s: Largest delay between a deadline and the tick's start, seconds.
        lateness_s: Per-tick lateness samples (kept only when ``record_lateness`` is set).
    """

    ticks: int = 0
    overruns: int = 0
    skipped_ticks: int = 0
    max_lateness_s: float = 0.0
    lateness_s: list[float] = field(default_factory=list)


class Scheduler:
    """Runs tasks at a fixed period on a clock.

    Args:
        clock: Where time comes from (real or simulated).
        period_s: Tick period in seconds (0.02 = 50 Hz).
        record_lateness: Keep every tick's lateness in :attr:`stats` (for benchmarks).
        max_catch_up_periods: How far behind, in periods, the loop may fall and still catch
            up; beyond it the missed ticks are skipped and the grid restarts from now.

    Example:
        >>> from roboscript.clock import SimClock
        >>> sched = Scheduler(SimClock(), period_s=0.01)
        >>> seen = []
        >>> sched.add(lambda now, dt: seen.append(round(dt, 3)))
        >>> sched.run(until=lambda: len(seen) == 3)
        >>> seen
        [0.01, 0.01, 0.01]
    """

    def __init__(
        self,
        clock: Clock,
        period_s: float = 0.02,
        *,
        record_lateness: bool = False,
        max_catch_up_periods: float = 10.0,
    ):
        if period_s <= 0:
            raise ValueError("the tick period must be positive")
        if max_catch_up_periods < 1:
            raise ValueError("max_catch_up_periods must be at least 1")
        self.max_catch_up_periods = max_catch_up_periods
        self.clock = clock
        self.period_s = period_s
        self.stats = SchedulerStats()
        self._record = record_lateness
        self._tasks: dict[Phase, list[Callable[[float, float], None]]] = {p: [] for p in _PHASES}
        self._last_tick_s: float | None = None
        self._next_deadline_s: float | None = None

    def add(self, task: Tickable | Callable[[float, float], None], phase: Phase = "think") -> None:
        """Add a task, called every tick in ``phase`` in the order added."""
        call = task.tick if hasattr(task, "tick") else task
        self._tasks[phase].append(call)

    def remove(self, task: Tickable | Callable[[float, float], None]) -> None:
        """Remove a task added earlier (no error if it is not there)."""
        call = task.tick if hasattr(task, "tick") else task
        for calls in self._tasks.values():
            if call in calls:
                calls.remove(call)

    def step(self) -> None:
        """Run one tick now, without waiting for a deadline."""
        now = self.clock.now()
        # A clock with coarse resolution can repeat a reading; dt must still be > 0.
        last = self._last_tick_s
        dt = self.period_s if last is None else max(now - last, 1e-6)
        self._last_tick_s = now
        self.stats.ticks += 1
        # A signal that landed in a finalizer since the last tick (where Python drops it) ends
        # the run before this one.
        raise_dropped()
        # What a tick calls may catch a Ctrl-C and go on (a student's bare ``except:``, a
        # library that logs every error): the signal still ends the run, at this tick's end.
        with kept():
            for phase in _PHASES:
                for call in self._tasks[phase]:
                    call(now, dt)

    def run(
        self,
        until: Callable[[], bool],
        *,
        max_duration_s: float | None = None,
    ) -> bool:
        """Tick at the period until ``until()`` is true or ``max_duration_s`` has passed.

        Args:
            until: Checked after every tick; the loop ends when it returns true.
            max_duration_s: Upper bound on run time by the scheduler's clock, seconds.

        Returns:
            True if ``until()`` became true, False if the time bound ended the run.
        """
        start = self.clock.now()
        # Time between two runs (a handshake, then a mission) was never scheduled: there is
        # nothing to catch up, so a grid left behind restarts from now.
        if self._next_deadline_s is None or self._next_deadline_s < start:
            self._next_deadline_s = start
        period = self.period_s
        give_up_s = period * self.max_catch_up_periods
        stats = self.stats
        while True:
            deadline = self._next_deadline_s
            last = self._last_tick_s
            # Catching up runs at most two ticks per period, so dt never drops below T/2.
            wake = deadline if last is None else max(deadline, last + period * _MIN_SPACING)
            self.clock.sleep_until(wake)
            now = self.clock.now()
            lateness = now - deadline
            stats.max_lateness_s = max(stats.max_lateness_s, lateness)
            if self._record:
                stats.lateness_s.append(lateness)
            if lateness > period:
                stats.overruns += 1
                if lateness > give_up_s:
                    skipped = int(lateness / period + 1e-9)
                    stats.skipped_ticks += skipped
                    logger.debug(
                        "tick %d started %.1f ms late: %d ticks skipped",
                        stats.ticks,
                        lateness * 1e3,
                        skipped,
                    )
                    self._next_deadline_s = now
            self.step()
            self._next_deadline_s += period
            if until():
                return True
            if max_duration_s is not None and self.clock.now() - start >= max_duration_s - 1e-9:
                return False
