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

Code may catch a signal's exception and drop it (a student's bare ``except:``; the state-machine
library logs and drops anything raised in the last step of a transition); :func:`kept` raises
such a signal again as soon as that code returns (the scheduler wraps each tick in it), so it
still ends the run.
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
    "kept",
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
_raised = 0
"""How many signals have been raised as :class:`Interrupted` (what :func:`kept` compares)."""
_last_signum: int = signal.SIGINT
"""The signal most recently raised."""


def _raise_now(signum: int) -> None:
    global _raised, _last_signum
    _raised += 1
    _last_signum = signum
    raise Interrupted(signum)


def _raise(signum: int, frame: FrameType | None) -> None:
    global _pending
    del frame
    if _deferring and _pending is None:
        _pending = signum
        return
    if _pending is not None:  # asked twice: end now, for the first reason given
        signum, _pending = _pending, None
    _raise_now(signum)


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
            _raise_now(signum)


@contextmanager
def kept() -> Iterator[None]:
    """Raise again, when the block returns, a signal that code inside it caught and dropped.

    For calls into libraries that catch every exception somewhere (``transitions`` logs and
    drops whatever is raised while it finalises an event, a :class:`KeyboardInterrupt`
    included): a signal landing there would otherwise be lost and the run go on. A signal the
    block lets out is raised as usual; nothing is delayed.
    """
    before = _raised
    yield
    if _raised != before:
        raise Interrupted(_last_signum)


def install() -> None:
    """Make every signal in :data:`HANDLED_SIGNALS` raise :class:`Interrupted`."""
    for signum in HANDLED_SIGNALS:
        signal.signal(signum, _raise)
