"""Which CPU core each grading worker keeps its runs on: a run's two processes share one.

A graded run is two processes taking turns twice a simulated tick: the world, in the worker,
and the student's mission, in its jail (:mod:`roboscript.transport.lockstep`). Left alone,
Linux often puts the two on different cores, and every hand-over then wakes the other core
from idle: on the 2-core reference machine (a virtual machine) a round trip between two
processes took 48 µs across cores against 13 µs on one core, and one worker graded 12
one-minute runs in 11.1 s left alone against 8.0 s kept on one core. So each worker takes a
core of its own (of those the grader may use) before it starts its jail: the jail, and every
run's mission forked in it, inherit it. With more workers than cores, cores are shared evenly.

A core is chosen among the least shared by this grader's workers, and among those the one that
was idle the most lately (read from ``/proc/stat``; the first choice looks at the cores for
:data:`SAMPLE_S` first), so a grader beside another busy program, or a second grader on a larger
machine, takes the idle cores instead of piling onto the first ones. With every core busy,
keeping a run on one core costs nothing measurable (the same class took 22-26 s either way
beside other work at load 16). Nothing here changes a verdict: every rule of the grader counts
the CPU time the student's code used, never wall time.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Callable, Iterable
from typing import Final

__all__ = ["SAMPLE_S", "CoreShare", "idle_ticks_by_core", "keep_on_core", "usable_cores"]

SAMPLE_S: Final = 0.03
"""Seconds over which the cores' idle time is compared (``/proc/stat`` counts it in ticks of
10 ms): a reading sooner than this after the last one keeps the last comparison."""


def usable_cores() -> list[int]:
    """The CPU cores this process may run on (its affinity: ``taskset`` and containers count),
    in order; empty where the platform does not tell."""
    if not hasattr(os, "sched_getaffinity"):
        return []
    with contextlib.suppress(OSError):
        return sorted(os.sched_getaffinity(0))
    return []


def keep_on_core(core: int | None) -> bool:
    """Keep this process, and every process it starts from now on, on ``core``.

    Returns:
        True if the system took it (False for ``None``, or where it cannot be done).
    """
    if core is None or not hasattr(os, "sched_setaffinity"):
        return False
    try:
        os.sched_setaffinity(0, {core})
    except (OSError, ValueError):  # a core outside this container's set, or gone offline
        return False
    return True


def idle_ticks_by_core(stat_text: str) -> dict[int, int]:
    """Each core's idle time so far, in clock ticks, from the text of ``/proc/stat`` (its
    ``cpuN`` lines: idle plus waiting for I/O)."""
    idle: dict[int, int] = {}
    for line in stat_text.splitlines():
        name, _, rest = line.partition(" ")
        if not name.startswith("cpu") or not name[3:].isdigit():
            continue
        fields = rest.split()
        with contextlib.suppress(IndexError, ValueError):
            idle[int(name[3:])] = int(fields[3]) + int(fields[4])
    return idle


def _read_proc_stat() -> str:
    try:
        with open("/proc/stat", encoding="ascii") as stat:
            return stat.read()
    except (OSError, UnicodeDecodeError):
        return ""


class CoreShare:
    """The cores of a grader's workers: one taken per worker, given back when it ends.

    Args:
        cores: The cores workers may use (default: :func:`usable_cores`). With fewer than
            two there is nothing to choose, and :meth:`take` gives ``None``.
        read_stat: Gives the text of ``/proc/stat`` (tests give their own).
        clock: Monotonic seconds (tests give their own).
        sleep: Waits seconds (tests give their own).
    """

    def __init__(
        self,
        cores: Iterable[int] | None = None,
        read_stat: Callable[[], str] = _read_proc_stat,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        chosen = usable_cores() if cores is None else sorted(set(cores))
        self._workers = dict.fromkeys(chosen, 0)
        self._read_stat = read_stat
        self._clock = clock
        self._sleep = sleep
        self._idle_before = idle_ticks_by_core(read_stat()) if len(chosen) > 1 else {}
        self._read_at = clock()
        self._compared = False
        self._idle_lately = dict.fromkeys(chosen, 0)

    def take(self) -> int | None:
        """A core for a new worker: one that the fewest of this grader's workers use, and of
        those the one idle the most lately; ``None`` with fewer than two cores.

        The first call may wait up to :data:`SAMPLE_S` to compare the cores.
        """
        if len(self._workers) < 2:
            return None
        if not self._compared:
            self._sleep(max(0.0, SAMPLE_S - (self._clock() - self._read_at)))
        self._compare()
        core = min(self._workers, key=lambda c: (self._workers[c], -self._idle_lately[c], c))
        self._workers[core] += 1
        return core

    def _compare(self) -> None:
        """Each core's idle ticks since the last reading, if that was :data:`SAMPLE_S` ago."""
        now = self._clock()
        if self._compared and now - self._read_at < SAMPLE_S:
            return
        idle_now = idle_ticks_by_core(self._read_stat())
        if idle_now:
            before = self._idle_before
            self._idle_lately = {c: idle_now.get(c, 0) - before.get(c, 0) for c in self._workers}
            self._idle_before = idle_now
        self._read_at = now
        self._compared = True

    def give(self, core: int | None) -> None:
        """A worker that had ``core`` has ended."""
        if core is not None and self._workers.get(core, 0) > 0:
            self._workers[core] -= 1

    def workers_on(self, core: int) -> int:
        """How many of this grader's workers use ``core`` now."""
        return self._workers.get(core, 0)
