"""Student code that never returns, or takes too long per tick: the one rule, and its watchdog.

A behaviour or a Python mission's condition with a loop that never ends would keep the
scheduler from ever ticking again: the mission's time limit never comes, the robot keeps doing
what it was last told, and Ctrl-C is the only way out. The session times every tick's student
code with a :class:`Watchdog`; if one tick's code runs longer than the limit, the watchdog
raises :class:`RunawayCode` inside the stuck code, naming the file, line and function it was
in, and the session stops the robot.

Code that returns, but slowly (``time.sleep`` in a condition), makes a tick late: the robot
keeps doing what it was last told while the code sleeps. :class:`TickBudget` is the one rule for
how long student code may take per tick, shared by ``roboscript run`` (which warns about the
first slow tick, naming its line and the time it took) and the grader (whose mission process
runs the same session): once slow ticks add up to :attr:`TickBudget.too_slow_after_s`, the run
ends as *too slow* (:class:`TooSlow`), at home exactly as in class.

Every time here is the code's *own* time (:class:`CodeClock`): wall time minus the time the
thread waited for a CPU (a busy machine) and for the robot or the grader's world (the wire).
So a verdict never depends on the machine's load: on Linux the wait for a CPU comes from the
kernel's per-thread scheduler statistics; elsewhere it cannot be told apart and counts. Nor
does it depend on what else the process holds: while a watchdog watches, Python's full garbage
collections visit only the objects made since it started (:func:`collections_of_own_objects`),
so a collection that happens to start in a tick takes as long as the run's own objects make it,
not a notebook's or a test suite's millions.

:class:`RunawayCode` is a :class:`BaseException`, like :class:`KeyboardInterrupt`, so a
student's ``except Exception:`` cannot swallow it; it is raised again every
:data:`REPEAT_S` until it gets out, so one bare ``except:`` cannot either (code that
catches everything in an endless loop of its own can still only be ended with Ctrl-C). Code
that drops it and returns (a student's bare ``except:``, a library that logs and drops what
is raised in its callbacks, a finaliser, whose exceptions Python ignores) does not keep the
run going: the stop is raised again as that tick's code (or the watched block) returns.
Uses ``SIGALRM`` (POSIX, main thread). Elsewhere (Windows, a browser tab, another thread) it
checks between two lines of the student's own code instead (:class:`~roboscript.line_alarm.
LineAlarm`): a loop is stopped at its line just the same, and a single call that blocks
(``time.sleep(60)``) is stopped when it returns.
"""

from __future__ import annotations

import atexit
import contextlib
import gc
import logging
import operator
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from types import FrameType, TracebackType
from typing import TYPE_CHECKING, Any

from roboscript.code_owner import is_student_file
from roboscript.line_alarm import LineAlarm

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: not a dependency

__all__ = [
    "DEFAULT_LIMIT_S",
    "RECURSION_LIMITS",
    "REPEAT_S",
    "RETURN_AT_ONCE",
    "TICK_BUDGET",
    "CodeClock",
    "CodePlace",
    "RunawayCode",
    "TickBudget",
    "TooSlow",
    "Watchdog",
    "alarm_kept_sentence",
    "bound_recursion",
    "collections_of_own_objects",
    "cpu_wait_s",
    "keep_alarm",
    "keep_program",
    "wire_wait",
]

logger = logging.getLogger(__name__)

_perf_counter = time.perf_counter
"""The clock the code's own time is read from, bound when this module is imported: code that
replaces ``time.perf_counter`` (a mission that stops time for itself) cannot stop its own
watchdog."""

DEFAULT_LIMIT_S = 5.0
"""How long one tick's code may run before it counts as stuck, seconds of its own time."""

REPEAT_S = 0.25
"""After the first alarm, how often it is raised again until the stuck code lets it out."""


RETURN_AT_ONCE = (
    "a condition or update() must return at once; wait with a state's action or timeout,"
    " never time.sleep"
)
"""What code that runs every tick must do, as each warning about slow code says it."""


@dataclass(frozen=True)
class TickBudget:
    """How long student code may take per tick: the rule ``run`` and ``grade`` share.

    Attributes:
        slow_tick_s: Own time one tick's student code may take, seconds: one tick of the
            50 Hz loop. Slower code cannot keep up with the robot (it keeps doing what it
            was last told meanwhile). Honest code takes well under a millisecond.
        too_slow_after_s: Once the slow ticks' own time adds up to this many seconds, the
            run ends as too slow (a single slow tick, such as a first import, is forgiven).
        cpu_margin_s: The grader's outer bound, for a mission process that does not end
            itself: it may use this many CPU seconds more than the simulated time it advanced.
    """

    slow_tick_s: float = 0.02
    too_slow_after_s: float = 1.0
    cpu_margin_s: float = 5.0

    def cpu_allowance_s(self, simulated_s: float) -> float:
        """CPU seconds a mission process may use while advancing ``simulated_s`` seconds.

        A mission that keeps up with its robot uses less than one CPU second per simulated
        second (honest ones use a few hundredths); this bound sits past where the tick rule
        has already ended a slow one.
        """
        return max(0.0, simulated_s) + self.cpu_margin_s

    def slow_message(self, spent_s: float, where: CodePlace | None) -> str:
        """The warning for a slow tick: where (if known), how long, and what a graded run
        does about it."""
        at = f" at {where}" if where is not None else ""
        return (
            f"warning: the mission's code{at} took {spent_s:.2f} s in one tick (a tick is"
            f" {self.slow_tick_s:g} s; meanwhile the robot keeps doing what it was last told):"
            f" once slow ticks add up to {self.too_slow_after_s:g} s the run ends as too slow,"
            f" here and when graded ({RETURN_AT_ONCE})"
        )


TICK_BUDGET = TickBudget()
"""The rule in force (``run`` and the grader's mission process both use it)."""


@dataclass(frozen=True)
class CodePlace:
    """Where the student's code was when it was caught: ``spin.py:14 in update``.

    Attributes:
        file: The student's file, as they would type it (relative to the working directory
            when inside it).
        line: The line running there, 1-based.
        function: The function running there (``<module>`` while the file is imported).
        loop_line: The first line of the loop that line runs in (the innermost ``while``
            around it in its function, else the innermost ``for``), or None outside a loop.
    """

    file: str
    line: int
    function: str
    loop_line: int | None = None

    def __str__(self) -> str:
        return f"{self.file}:{self.line} in {self.function}"

    def in_loop(self) -> CodePlace:
        """This place named by its loop's first line, when it runs in a loop.

        A loop caught at an arbitrary moment is on any of its lines; its first line is the
        same whenever it is caught, and it is the loop a student has to look at."""
        if self.loop_line is None or self.loop_line == self.line:
            return self
        return CodePlace(self.file, self.loop_line, self.function)


# ------------------------------------------------------------------------------ own time


class _WireWait:
    """Seconds this process's threads spent blocked on the wire (the robot, the grader).

    A context manager: time spent inside it is a wait on the wire. A plain class rather than
    a generator, since the transport enters it every tick of every run.
    """

    def __init__(self) -> None:
        self.total_s = 0.0
        self.since: float | None = None  # a wait under way (an alarm may land inside it)

    def so_far_s(self) -> float:
        """Every wait so far, the one under way included."""
        since = self.since
        return self.total_s + (_perf_counter() - since if since is not None else 0.0)

    def __enter__(self) -> None:
        self.since = _perf_counter()

    def __exit__(self, *exc_info: object) -> None:
        since = self.since
        self.since = None
        if since is not None:
            self.total_s += _perf_counter() - since


_WIRE = _WireWait()


def wire_wait() -> contextlib.AbstractContextManager[None]:
    """Time spent in here is the robot's (or the grader's world's), never the code's own.

    The transport wraps every blocking wait for an answer in it (waits do not nest).
    """
    return _WIRE


_READERS = threading.local()
_PAIR_TRIES = 8
"""Reads of the wall clock to find one not split by a wait for the CPU (each try that fails
was preempted, so a few always suffice; the last is kept if none was whole)."""

_PAIR_SLACK_S = 50e-6
"""A reading of the CPU wait taken between two readings of the wall clock this close is paired
with the first of them: a wait for the CPU that fell between them is no longer than this, so
the pair is off by no more (a read takes a few microseconds; a wait for the CPU, a scheduler
slice of milliseconds)."""


def _schedstat_reader() -> Callable[[], float] | None:
    """Seconds this thread has waited for a CPU so far, from Linux's scheduler statistics.

    One open file per thread, kept for the thread's life (a clock per run must not leak one),
    and opened again in a forked child (whose thread it is not).
    """
    if getattr(_READERS, "pid", None) != os.getpid():
        _READERS.pid = os.getpid()
        _READERS.read = _open_schedstat()
    read: Callable[[], float] | None = _READERS.read
    return read


def _open_schedstat() -> Callable[[], float] | None:
    try:
        fd = os.open("/proc/thread-self/schedstat", os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
        os.pread(fd, 64, 0)
    except (OSError, AttributeError):
        return None

    def read() -> float:
        try:
            return int(os.pread(fd, 64, 0).split()[1]) / 1e9
        except (OSError, ValueError, IndexError):
            return 0.0

    return read


def cpu_wait_s() -> float:
    """Seconds this thread has waited for a CPU so far: another program had it (a busy
    machine). From an arbitrary origin; 0.0 where the system does not tell (not Linux)."""
    read = _schedstat_reader()
    return read() if read is not None else 0.0


_FROZEN = threading.Lock()
_FROZEN_DEPTH = [0]  # blocks under way, in any thread: the first freezes, the last thaws


@contextlib.contextmanager
def collections_of_own_objects() -> Iterator[None]:
    """Inside, Python's garbage collections leave alone every object made before the block.

    A full collection starts in whichever tick allocates past its threshold and visits every
    object it may free: in a notebook's or a test suite's process, millions, for up to a
    second, held against that one tick (honest missions were ended as too slow so). Objects
    older than the run are set aside (``gc.freeze``) and given back when the last such block
    ends; garbage among them is freed then, at the next collection, outside every tick.
    """
    with _FROZEN:
        _FROZEN_DEPTH[0] += 1
        if _FROZEN_DEPTH[0] == 1:
            gc.freeze()
    try:
        yield
    finally:
        with _FROZEN:
            _FROZEN_DEPTH[0] -= 1
            if _FROZEN_DEPTH[0] == 0:
                gc.unfreeze()


class CodeClock:
    """The own time of the code this thread runs: wall time, less the time spent waiting.

    Waiting for a CPU (another program had it: the machine is busy) and waiting on the wire
    (the robot or the grader's world answering) are not the code's own; sleeping, computing
    and blocking on anything else are. Create it on the thread it measures.

    A wait for a CPU that falls inside a sleep to a deadline (``time.sleep`` woken by the
    watchdog's alarm, or preempted on its way in) is left out too, although the sleep did not
    last longer for it: on a busy machine a sleeping tick can measure a little short, never
    long, so load still never makes code look slow.
    """

    def __init__(self) -> None:
        self._queued = _schedstat_reader()
        self.queued_s = 0.0
        """The CPU wait paired with the last :meth:`now`, seconds (its own time plus this is
        :meth:`ceiling` at that moment)."""

    @property
    def load_independent(self) -> bool:
        """True where waiting for a CPU is known and left out (Linux)."""
        return self._queued is not None

    def now(self) -> float:
        """Own seconds, from an arbitrary origin (one system call, where the system tells the
        CPU wait; two or more when the thread lost the CPU while reading it)."""
        read = self._queued
        if read is None:
            return _perf_counter() - _WIRE.so_far_s()
        # The wall clock and the CPU wait must be read as one pair: a thread that loses the
        # CPU between the two reads counts that wait in one and not the other, which made a
        # span longer (an honest tick slow) or shorter (a sleeping tick quick) by as long as
        # a busy machine kept it waiting. The CPU wait only grows when the thread gets the
        # CPU back, so the wait read between two close readings of the wall clock pairs with
        # them (off by no more than they are apart); failing that, the same wait read on both
        # sides of one reading of the wall clock is a true pair.
        wall_s = _perf_counter()
        queued = read()
        for _ in range(_PAIR_TRIES):
            after_s = _perf_counter()
            if after_s - wall_s <= _PAIR_SLACK_S:
                break
            again = read()
            if again == queued:
                wall_s = after_s
                break
            wall_s, queued = after_s, again
        self.queued_s = queued
        return wall_s - queued - _WIRE.so_far_s()

    def ceiling(self) -> float:
        """Own seconds plus every wait for a CPU so far, with no system call: of a span, never
        less than its own time (and equal to it while nothing else had the CPU)."""
        return _perf_counter() - _WIRE.so_far_s()


def _every_file(_filename: str) -> bool:
    return True


# ---------------------------------------------------------------------------- exceptions


class RunawayCode(BaseException):
    """The mission's code ran longer than the watchdog's limit without returning.

    Args:
        limit_s: The limit it ran over, seconds.
        where: Where it was stuck, or None if not in a file of the student's.
    """

    def __init__(self, limit_s: float, where: CodePlace | None) -> None:
        super().__init__(limit_s, where)
        self.limit_s = limit_s
        self.where = where

    @property
    def file(self) -> str | None:
        """The student's file it was stuck in (as :attr:`CodePlace.file`), or None."""
        return self.where.file if self.where is not None else None

    @property
    def line(self) -> int | None:
        """The line of :attr:`file` it was stuck at (1-based), or None."""
        return self.where.line if self.where is not None else None

    @property
    def reason(self) -> str:
        """One sentence for the student: what happened, where, and what to look for."""
        at = f" at {self.where}" if self.where is not None else ""
        return (
            f"the mission's code did not return for {self.limit_s:g} s and was stopped{at}:"
            " is there a loop that never ends? (a behaviour's update() and a condition must"
            " return at once; wait with a state's action or timeout instead)"
        )


class TooSlow(RunawayCode):
    """The mission's code took longer than a tick in so many ticks that the run was ended.

    Args:
        spent_s: Own time of the slow ticks, in all, seconds.
        where: Where the first slow tick was caught (``wait.py:12 in near_wall``), or None.
        slowest_s: Own time of the slowest tick, seconds.
        budget: The rule it broke.
    """

    def __init__(
        self, spent_s: float, where: CodePlace | None, slowest_s: float, budget: TickBudget
    ) -> None:
        super().__init__(spent_s, where)
        self.slowest_s = slowest_s
        self.budget = budget

    @property
    def reason(self) -> str:
        """One sentence for the student."""
        at = f" at {self.where}" if self.where is not None else ""
        return (
            f"the mission was too slow: its code{at} took up to {self.slowest_s:.2f} s per tick"
            f" (a tick is {self.budget.slow_tick_s:g} s) and was stopped once slow ticks added up"
            f" to {self.budget.too_slow_after_s:g} s ({RETURN_AT_ONCE})"
        )


class Watchdog:
    """Raises :class:`RunawayCode` in code that runs ``limit_s`` of its own time unchecked.

    Use as a context manager around the loop. Either call :meth:`pet` once per tick (the time
    between two pets is timed), or wrap the call that runs the student's code each tick with
    :meth:`timed`: its calls are timed, and slow ones are held against ``budget``. Times are
    the code's own (:class:`CodeClock`): a busy machine never makes code look slow.

    Args:
        limit_s: Own seconds one tick's code may take.
        locate: Where a frame is stuck, in the student's terms (None if in no file of theirs).
        budget: The per-tick rule for timed calls (None: slow ticks are not looked for).
        on_slow: Called once, for the first slow tick, with its own time in seconds and where
            it was caught (``wait.py:12 in near_wall``, or None).
        end_when_too_slow: Raise :class:`TooSlow` once slow ticks add up to the budget.
        watched: Where there is no ``SIGALRM``: whether code from a file is checked between
            its lines (the student's files; by default every file, which is slower).
    """

    def __init__(
        self,
        limit_s: float,
        locate: Callable[[FrameType | None], CodePlace | None],
        *,
        budget: TickBudget | None = None,
        on_slow: Callable[[float, CodePlace | None], None] | None = None,
        end_when_too_slow: bool = True,
        watched: Callable[[str], bool] | None = None,
    ) -> None:
        if not limit_s > 0:
            raise ValueError(f"a watchdog limit must be more than 0 s (got {limit_s})")
        self.limit_s = limit_s
        self.budget = budget
        self._locate = locate
        self._on_slow = on_slow
        self._end_when_too_slow = end_when_too_slow
        self._clock = CodeClock()
        self._armed = False
        self._previous: Any = None
        self._began_s = 0.0
        self._began_ceiling_s = 0.0  # CodeClock.ceiling() when the timed call began
        # a timed call whose wall time (less the wire's) is no longer is not slow
        self._quick_s = (budget or TICK_BUDGET).slow_tick_s
        self._timing = False
        self._where: CodePlace | None = None  # where the current timed call was caught slow
        self.slow_ticks = 0
        """Timed calls that took longer than the budget's tick."""
        self.slow_total_s = 0.0
        """Their own time, in all, seconds."""
        self.slowest_s = 0.0
        self._first_where: CodePlace | None = None
        self._unreported_s: float | None = None  # a slow tick not yet warned about
        self._warned = False
        self._line_alarm: LineAlarm | None = None  # where there is no SIGALRM
        self._watched = watched or _every_file
        self._stopped: RunawayCode | None = None  # raised, and not yet seen to get out
        self._older_objects = contextlib.ExitStack()  # set aside from collections while in

    @property
    def supported(self) -> bool:
        """True where the watchdog can stop code: with ``SIGALRM`` (POSIX, in the main
        thread), else between two lines of the watched code."""
        return self._signals or LineAlarm.available()

    @property
    def _signals(self) -> bool:
        return (
            hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
        )

    def pet(self) -> None:
        """The loop is alive: start the limit again (a stop raised before it has been dealt
        with by the loop)."""
        self._restart(self._clock.now())

    def _restart(self, now_s: float) -> None:
        # The timer is not set again here (two system calls a tick): the alarm already on
        # its way rings no later than the limit counted from now would, and sets itself
        # for what is left of the limit from the latest start (see _alarm).
        self._stopped = None
        self._began_s = now_s
        if self._line_alarm is not None:
            # No system call here; and Python drops a trace function that raised, which
            # setting the alarm puts back, so a later tick's loop is watched again.
            self._line_alarm.set(self.limit_s)

    def timed(self, call: Callable[[float, float], None]) -> Callable[[float, float], None]:
        """``call`` (a scheduler task running student code), timed against the budget.

        Raises (from the returned task):
            RunawayCode: The call ran past the limit; also when the code it called dropped
                that stop and returned (the stop it dropped, raised again).
            TooSlow: Slow ticks added up to the budget (when ``end_when_too_slow``).
        """

        def task(now_s: float, dt_s: float) -> None:
            self._begin()
            try:
                call(now_s, dt_s)
            except BaseException:
                self._timing = False
                self._stopped = None  # what got out ends the run
                raise
            if self._stopped is not None:
                self._timing = False
                self._raise_dropped()
            self._end()

        return task

    def _begin(self) -> None:
        self._timing = True
        self._where = None
        clock = self._clock
        self._began_s = clock.now()
        self._began_ceiling_s = self._began_s + clock.queued_s
        # Only once a tick has been slow is the next one interrupted to see where it is: an
        # alarm that wakes a sleeping tick lets the machine's load hide in its sleep.
        if self._armed and self._locating and self.budget is not None:
            self._arm(min(self.limit_s, self.budget.slow_tick_s))

    def _end(self) -> None:
        budget = self.budget
        clock = self._clock
        # Own time is at most the wall time less the wire's: a call that took no longer than
        # a tick by that measure was not slow, whatever it waited for a CPU, and needs no
        # system call to say so (honest code, every tick).
        spent_s = clock.ceiling() - self._began_ceiling_s
        if spent_s > self._quick_s:
            ended_s = clock.now()
            spent_s = ended_s - self._began_s
        else:  # the limit counts from a little later: by what the call waited for a CPU
            ended_s = self._began_s + spent_s
        self._timing = False
        if budget is not None and spent_s > budget.slow_tick_s:
            self.slow_ticks += 1
            self.slow_total_s += spent_s
            self.slowest_s = max(self.slowest_s, spent_s)
            self._first_where = self._first_where or self._where
            if self._where is not None or not self._armed:
                self._report_slow(max(spent_s, self._unreported_s or 0.0), self._where)
            else:  # the next tick, if slow too, says where
                self._unreported_s = max(spent_s, self._unreported_s or 0.0)
            if self._end_when_too_slow and self.slow_total_s >= budget.too_slow_after_s:
                raise TooSlow(self.slow_total_s, self._first_where, self.slowest_s, budget)
        elif self._unreported_s is not None:
            self._report_slow(self._unreported_s, None)  # one slow tick alone: no line to name
        self._restart(ended_s)  # code outside the timed calls (the loop's own): the plain limit

    def _raise_dropped(self) -> None:
        """Raise again the stop that code the watchdog timed caught and dropped."""
        stopped, self._stopped = self._stopped, None
        if stopped is not None:
            raise stopped

    def _report_slow(self, spent_s: float, where: CodePlace | None) -> None:
        """Warn about the first slow tick (once)."""
        self._unreported_s = None
        if not self._warned and self._on_slow is not None:
            self._warned = True
            self._on_slow(spent_s, where)

    def _arm(self, after_s: float, repeat_s: float = 0.0) -> None:
        if self._line_alarm is not None:
            self._line_alarm.set(max(after_s, 1e-3), repeat_s)
        else:
            signal.setitimer(signal.ITIMER_REAL, max(after_s, 1e-3), repeat_s)

    def _ring(self, frame: FrameType) -> None:
        self._alarm(0, frame)

    def _alarm(self, signum: int, frame: FrameType | None) -> None:
        del signum
        if not self._armed:  # an alarm already on its way when the block ended is ignored
            return
        own_s = self._clock.now() - self._began_s
        budget = self.budget
        watching_tick = self._timing and budget is not None and self._where is None
        if watching_tick and budget is not None and own_s >= budget.slow_tick_s:
            self._where = self._locate(frame)
            watching_tick = False
        if own_s >= self.limit_s:
            self._arm(REPEAT_S, REPEAT_S)  # again and again, until it gets out
            where = self._locate(frame)
            if where is not None:  # a stop names the loop, not the line it happened to be on
                where = where.in_loop()
            if where is None and self._stopped is not None:
                # raised again on its way out of the student's code: freeing what a loop
                # built ([[] for _ in iter(int, 1)]) takes seconds in no file of theirs, and
                # the stop still names where their loop was
                where = self._stopped.where
            self._stopped = RunawayCode(self.limit_s, where)
            raise self._stopped
        # Not yet: the machine was busy, or the code waited on the wire. Wait for what is left
        # (and, while the first slow tick's place is looked for, until this tick is slow).
        left_s = self.limit_s - own_s
        if watching_tick and budget is not None and self._locating:
            left_s = min(left_s, budget.slow_tick_s - own_s)
        self._arm(left_s)

    @property
    def _locating(self) -> bool:
        """A tick was slow, and no tick has yet been caught slow where it was."""
        return self.budget is not None and self.slow_ticks > 0 and self._first_where is None

    def __enter__(self) -> Self:
        self._older_objects.enter_context(collections_of_own_objects())
        if self._signals:
            self._previous = signal.signal(signal.SIGALRM, self._alarm)
        else:
            line_alarm = LineAlarm(self._ring, self._watched)
            if not line_alarm.start():
                logger.debug("no watchdog for runaway code: a debugger holds Python's hooks")
                return self
            self._line_alarm = line_alarm
        self._armed = True
        self.pet()
        self._arm(self.limit_s)
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if self._armed:
            # disarm before anything else: an alarm landing in here must not raise again
            self._armed = False
            if self._line_alarm is not None:
                self._line_alarm.stop()
                self._line_alarm = None
            else:
                signal.setitimer(signal.ITIMER_REAL, 0)
                signal.signal(signal.SIGALRM, self._previous)
        self._older_objects.close()
        if exc is None:  # the block returned, though it was stopped: the stop was dropped
            self._raise_dropped()
        self._stopped = None


# ------------------------------------------ the watchdog's means, kept from the code it stops


def alarm_kept_sentence(whose: str) -> str:
    """What code that changes the watchdog's alarm is told (``whose``: ``a graded mission``,
    ``a mission``): with the alarm gone, a loop that never ends could only be stopped by
    something that cannot say at which line (the grader's CPU bound; at home, Ctrl-C)."""
    return (
        "the watchdog that stops code that never returns uses SIGALRM and the real-time timer"
        f" (signal.alarm, signal.setitimer(signal.ITIMER_REAL)): {whose} may not change,"
        " ignore or block them"
    )


def keep_alarm(
    whose: str, refused: Callable[[str], bool], kept_blocked: frozenset[int] = frozenset()
) -> None:
    """Refuse, for the rest of the process, every change to the watchdog's SIGALRM and timer
    (``signal.signal(signal.SIGALRM, ...)``, ``signal.alarm``, ``signal.setitimer(signal.
    ITIMER_REAL, ...)``, ``signal.pthread_sigmask`` blocking SIGALRM, through :mod:`signal` or
    ``_signal``) made by code from a file ``refused`` names: a :class:`PermissionError` at its
    line, saying :func:`alarm_kept_sentence` of ``whose``.

    Args:
        whose: Whose code is refused, for the sentence (``a mission``, ``a graded mission``).
        refused: Whether code of a file (a code object's ``co_filename``) is refused.
        kept_blocked: Signals that stay blocked whatever ``pthread_sigmask`` is asked (those
            a thread of their own waits for).
    """
    alarm_signal, real_timer = int(signal.SIGALRM), int(signal.ITIMER_REAL)
    unblock, set_whole = int(signal.SIG_UNBLOCK), int(signal.SIG_SETMASK)
    blocking = {int(signal.SIG_BLOCK), int(signal.SIG_SETMASK)}
    python_wrapper = signal.__file__  # signal.signal() calls _signal.signal(): look past it
    sentence = alarm_kept_sentence(whose)

    def refuse_if_theirs() -> None:
        frame = sys._getframe(2)
        while frame.f_back is not None and frame.f_code.co_filename == python_wrapper:
            frame = frame.f_back
        if refused(frame.f_code.co_filename):
            raise PermissionError(sentence)

    def kept(module: Any) -> dict[str, Callable[..., Any]]:
        set_handler, set_timer = module.signal, module.setitimer
        set_mask, alarm = module.pthread_sigmask, module.alarm

        def kept_handler(signum: int, handler: Any, /) -> Any:
            if _as_int(signum) == alarm_signal:
                refuse_if_theirs()
            return set_handler(signum, handler)

        def kept_timer(which: int, seconds: float, interval: float = 0.0, /) -> Any:
            if _as_int(which) == real_timer:
                refuse_if_theirs()
            return set_timer(which, seconds, interval)

        def kept_alarm(seconds: int, /) -> Any:
            refuse_if_theirs()
            return alarm(seconds)

        def kept_mask(how: int, mask: Iterable[int], /) -> Any:
            chosen = list(mask)
            numbers = {_as_int(s) for s in chosen}
            if _as_int(how) in blocking and alarm_signal in numbers:
                refuse_if_theirs()
            if _as_int(how) == unblock:
                chosen = [s for s in chosen if _as_int(s) not in kept_blocked]
            elif _as_int(how) == set_whole:
                chosen += sorted(kept_blocked - numbers)
            return set_mask(how, chosen)

        return {
            "signal": kept_handler,
            "setitimer": kept_timer,
            "alarm": kept_alarm,
            "pthread_sigmask": kept_mask,
        }

    for module in (signal, sys.modules.get("_signal")):
        if module is not None and hasattr(module, "setitimer"):
            for name, wrapper in kept(module).items():
                setattr(module, name, wrapper)


def _as_int(value: object) -> int | None:
    """``value`` as a signal's or a timer's number, or ``None`` (the call itself then says
    what is wrong with it)."""
    try:
        return operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        return None


RECURSION_LIMITS = (250, 10_000)
"""The lowest and highest recursion limit a mission may set (``sys.setrecursionlimit``):
lower, roboscript's own calls that run the mission (at most a hundred deep) would fail in the
middle of its robot's commands; higher, a runaway recursion goes on past what the watchdog
can stop at its line (the traceback of a runaway recursion would take longer to read than the
run may take), and Python itself may crash."""


def bound_recursion(whose: str) -> None:
    """Keep ``sys.setrecursionlimit`` within :data:`RECURSION_LIMITS` for the rest of the
    process: outside, it raises ``ValueError`` at the caller's line, saying why (``whose``:
    ``a graded mission's``, ``a mission's``)."""
    set_limit = sys.setrecursionlimit
    low, high = RECURSION_LIMITS

    def bounded(limit: int, /) -> None:
        if isinstance(limit, int) and not low <= limit <= high:
            raise ValueError(
                f"{whose} recursion limit is between {low} and {high} (it was asked"
                f" for {limit}): roboscript's own calls need {low}, and deeper calls than"
                f" {high} are a runaway recursion"
            )
        set_limit(limit)

    sys.setrecursionlimit = bounded


def _shown_at(frame: FrameType) -> str:
    """``file:line:col`` of the call ``frame`` is making, the file as the student names it (from
    the folder they are in)."""
    code = frame.f_code
    positions = list(code.co_positions())
    at = positions[frame.f_lasti // 2] if 0 <= frame.f_lasti // 2 < len(positions) else None
    col = f":{at[2] + 1}" if at is not None and at[2] is not None else ""
    file = code.co_filename
    with contextlib.suppress(ValueError, OSError):
        inside = os.path.relpath(file)
        file = file if inside.startswith("..") else inside
    return f"{file}:{frame.f_lineno}{col}"


def _tell(line: str) -> None:
    """Write ``line`` on standard error (which a student's code may have closed)."""
    with contextlib.suppress(OSError, ValueError, AttributeError):
        sys.stderr.write(line + "\n")
        sys.stderr.flush()


def _keep_exit() -> None:
    """Turn ``os._exit(N)`` called by a student's code into ``SystemExit(N)`` at its line,
    which the mission's loader and runner tell in the student's terms: a program that ended
    at once, with nothing said, would leave the student with no line to look at. From a
    thread of theirs, which a ``SystemExit`` only ends, the line is said as it ends; so is
    the line of an exit in a function of theirs run as the program ends (``atexit``), which
    Python would tell with a traceback."""
    real_exit, register = os._exit, atexit.register

    def kept_exit(status: int, /) -> None:
        frame = sys._getframe(1)
        if not is_student_file(frame.f_code.co_filename):
            real_exit(status)
        if threading.current_thread() is not threading.main_thread():
            _tell(
                f"{_shown_at(frame)}: warning: os._exit({status!r}) in a thread would end the"
                " whole program, not the mission: the thread was ended instead (a mission"
                " ends by going to a final state)"
            )
        raise SystemExit(status)

    def kept_register(func: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Any:
        caller = sys._getframe(1)
        if not is_student_file(caller.f_code.co_filename):
            return register(func, *args, **kwargs)
        at = _shown_at(caller)

        def at_the_end() -> None:
            try:
                func(*args, **kwargs)
            except BaseException as exc:  # noqa: BLE001  # theirs, told at its line, not as a traceback
                _tell(
                    f"{at}: warning: the function given to atexit.register here raised"
                    f" {type(exc).__name__} as the program ended (a mission's work ends with"
                    " its final state: take atexit away)"
                )

        register(at_the_end)
        return func

    os._exit = kept_exit  # type: ignore[assignment]
    atexit.register = kept_register


_program_kept = False
"""Whether :func:`keep_program` has kept this process."""


def keep_program() -> None:
    """At home (``roboscript check`` and ``run``), for the rest of the process: a student's
    file may not take the watchdog's alarm (:func:`keep_alarm`), set a recursion limit it
    cannot stop (:func:`bound_recursion`) nor end the program with no word (``os._exit``),
    as a graded run may not; each is said at the student's line. Kept once however often
    it is asked."""
    global _program_kept
    if _program_kept:
        return
    _program_kept = True
    keep_alarm("a mission", is_student_file)
    bound_recursion("a mission's")
    _keep_exit()
