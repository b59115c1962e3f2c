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
was idle the most since the last choice (read from ``/proc/stat``), so two graders started
side by side on a larger machine spread over its idle cores instead of piling onto the first
ones. Nothing here changes a verdict: every rule of the grader counts the CPU time the
student's code used, never wall time.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterable

__all__ = ["CoreShare", "idle_ticks_by_core", "keep_on_core", "usable_cores"]


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
    """

    def __init__(
        self,
        cores: Iterable[int] | None = None,
        read_stat: Callable[[], str] = _read_proc_stat,
    ) -> None:
        chosen = usable_cores() if cores is None else sorted(set(cores))
        self._workers = dict.fromkeys(chosen, 0)
        self._read_stat = read_stat
        self._idle_before = idle_ticks_by_core(read_stat()) if len(chosen) > 1 else {}

    def take(self) -> int | None:
        """A core for a new worker: one that the fewest of this grader's workers use, and of
        those the one idle the most since the last call; ``None`` with fewer than two cores."""
        if len(self._workers) < 2:
            return None
        idle_now = idle_ticks_by_core(self._read_stat())
        idle_since = {
            core: idle_now.get(core, 0) - self._idle_before.get(core, 0) for core in self._workers
        }
        self._idle_before = idle_now or self._idle_before
        core = min(self._workers, key=lambda c: (self._workers[c], -idle_since[c], c))
        self._workers[core] += 1
        return core

    def give(self, core: int | None) -> None:
        """A worker that had ``core`` has ended."""
        if core is not None and self._workers.get(core, 0) > 0:
            self._workers[core] -= 1

    def workers_on(self, core: int) -> int:
        """How many of this grader's workers use ``core`` now."""
        return self._workers.get(core, 0)
