"""Code that never returns: a watchdog that ends it at the line where it is stuck.

A behaviour or a Python mission's condition with a loop that never ends would keep the
scheduler from ever ticking again: the mission's time limit never comes, the robot keeps doing
what it was last told, and Ctrl-C is the only way out. The scheduler pets the
:class:`Watchdog` after every tick; if one tick's code runs longer than the limit (wall
seconds: honest ticks take milliseconds), the watchdog raises :class:`RunawayCode` inside the
stuck code, naming the file, line and function it was in, and the session stops the robot.

:class:`RunawayCode` is a :class:`BaseException`, like :class:`KeyboardInterrupt`, so a
student's ``except Exception:`` cannot swallow it; it is raised again every
:data:`REPEAT_S` until it gets out, so one bare ``except:`` cannot either (code that
catches everything in an endless loop of its own can still only be ended with Ctrl-C).
Uses ``SIGALRM`` (POSIX, main thread); elsewhere the watchdog does nothing and says so in the
debug log.
"""

from __future__ import annotations

import logging
import signal
import threading
from collections.abc import Callable
from types import FrameType, TracebackType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: not a dependency

__all__ = ["DEFAULT_LIMIT_S", "REPEAT_S", "RunawayCode", "Watchdog"]

logger = logging.getLogger(__name__)

DEFAULT_LIMIT_S = 5.0
"""How long one tick's code may run before it counts as stuck, seconds of wall time."""

REPEAT_S = 0.25
"""After the first alarm, how often it is raised again until the stuck code lets it out."""


class RunawayCode(BaseException):
    """The mission's code ran longer than the watchdog's limit without returning.

    Args:
        limit_s: The limit it ran over, seconds.
        where: Where it was stuck (``spin.py:14 in update``), or ``""`` if not in a file of
            the student's.
    """

    def __init__(self, limit_s: float, where: str) -> None:
        super().__init__(limit_s, where)
        self.limit_s = limit_s
        self.where = where

    @property
    def reason(self) -> str:
        """One sentence for the student: what happened, where, and what to look for."""
        at = f" at {self.where}" if self.where else ""
        return (
            f"the mission's code did not return for {self.limit_s:g} s and was stopped{at}:"
            " is there a loop that never ends? (a behaviour's update() and a condition must"
            " return at once; wait with a state's action or timeout instead)"
        )


class Watchdog:
    """Raises :class:`RunawayCode` in code that runs ``limit_s`` without a :meth:`pet`.

    Use as a context manager around the loop, and call :meth:`pet` once per tick.

    Args:
        limit_s: Wall seconds one tick's code may take.
        locate: Where a frame is stuck, in the student's terms (``""`` if unknown).
    """

    def __init__(self, limit_s: float, locate: Callable[[FrameType | None], str]) -> None:
        if not limit_s > 0:
            raise ValueError(f"a watchdog limit must be more than 0 s (got {limit_s})")
        self.limit_s = limit_s
        self._locate = locate
        self._armed = False
        self._previous: Any = None

    @property
    def supported(self) -> bool:
        """True where the watchdog can interrupt code (POSIX, in the main thread)."""
        return (
            hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
        )

    def pet(self) -> None:
        """The loop is alive: start the limit again."""
        if self._armed:
            signal.setitimer(signal.ITIMER_REAL, self.limit_s, REPEAT_S)

    def _alarm(self, signum: int, frame: FrameType | None) -> None:
        del signum
        if self._armed:  # an alarm already on its way when the block ended is ignored
            raise RunawayCode(self.limit_s, self._locate(frame))

    def __enter__(self) -> Self:
        if not self.supported:
            logger.debug("no watchdog for runaway code here (needs SIGALRM in the main thread)")
            return self
        self._previous = signal.signal(signal.SIGALRM, self._alarm)
        self._armed = True
        self.pet()
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
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, self._previous)
