"""Signals that end the program: Ctrl-C, SIGTERM, SIGHUP, all through one path.

A closed terminal sends SIGHUP, a process manager or a teacher's "kill all" sends SIGTERM, a
student presses Ctrl-C (SIGINT). Each one raises :class:`Interrupted` (a
:class:`KeyboardInterrupt`) in the main thread, wherever the program is, so the robot is
stopped on the way out exactly as for Ctrl-C (:func:`roboscript.session.run_session`,
:meth:`roboscript.robot.Robot.__exit__`), and the program exits with ``128 + signal number``
(130, 143, 129) after one plain sentence.

While the stop command is being sent (:func:`deferred`), one signal waits until it has gone
out, so pressing Ctrl-C twice cannot cut the stop in half; a further signal in that time raises
at once, so a stop stuck on a dead port can still be ended.
"""

from __future__ import annotations

import signal
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = [
    "HANDLED_SIGNALS",
    "Interrupted",
    "deferred",
    "exit_status_for",
    "install",
    "reason_for",
]

HANDLED_SIGNALS: tuple[signal.Signals, ...] = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)
"""The signals that end a run with the robot stopped (SIGHUP does not exist on Windows)."""

_WHY = {
    "SIGINT": "interrupted by Ctrl-C",
    "SIGTERM": "stopped by SIGTERM (something asked roboscript to end)",
    "SIGHUP": "stopped by SIGHUP (the terminal was closed)",
}


class Interrupted(KeyboardInterrupt):
    """A signal asked the program to end.

    Args:
        signum: The signal's number.
        reason: What asked, when it was not a signal but acts as Ctrl-C does (the browser
            app's Stop button, its tab closing); by default the signal's own sentence.
    """

    def __init__(self, signum: int = signal.SIGINT, reason: str | None = None) -> None:
        super().__init__(signum)
        self.signum = signum
        self._reason = reason

    @property
    def reason(self) -> str:
        """One plain sentence: what ended the run."""
        if self._reason is not None:
            return self._reason
        return _WHY.get(signal.Signals(self.signum).name, f"stopped by signal {int(self.signum)}")

    @property
    def exit_status(self) -> int:
        """The shell's status for a program ended by this signal: 128 + its number."""
        return 128 + int(self.signum)


def reason_for(exc: KeyboardInterrupt) -> str:
    """What ended the run, for any :class:`KeyboardInterrupt` (a bare one is Ctrl-C)."""
    return exc.reason if isinstance(exc, Interrupted) else Interrupted().reason


def exit_status_for(exc: KeyboardInterrupt) -> int:
    """128 + the signal's number (130 for a bare :class:`KeyboardInterrupt`)."""
    return 128 + int(getattr(exc, "signum", signal.SIGINT))


_deferring = 0
"""How many :func:`deferred` blocks are open (they nest: a close inside a stop)."""
_pending: int | None = None
"""The signal that arrived inside a :func:`deferred` block and waits for its end."""


def _raise(signum: int, frame: FrameType | None) -> None:
    global _pending
    del frame
    if _deferring and _pending is None:
        _pending = signum
        return
    if _pending is not None:  # asked twice: end now, for the first reason given
        signum, _pending = _pending, None
    raise Interrupted(signum)


@contextmanager
def deferred() -> Iterator[None]:
    """Hold back the first signal until the block (sending the stop command) has finished.

    The held signal is raised as :class:`Interrupted` when the outermost block ends; a second
    signal inside the block raises it at once (the first signal stays the reason).
    """
    global _deferring, _pending
    _deferring += 1
    try:
        yield
    finally:
        _deferring -= 1
        if not _deferring and _pending is not None:
            signum, _pending = _pending, None
            raise Interrupted(signum)


def install() -> None:
    """Make every signal in :data:`HANDLED_SIGNALS` raise :class:`Interrupted`."""
    for signum in HANDLED_SIGNALS:
        signal.signal(signum, _raise)
