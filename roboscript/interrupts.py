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
library logs and drops anything raised in the last step of a transition; pyserial's socket port
ignores every exception while it closes); :func:`kept` raises such a signal again as soon as that
code returns (the scheduler wraps each tick in it, the robot its handshake and its close), so it
still ends the run. A signal that lands while Python runs a finalizer (a ``__del__``, a weak
reference's callback: they run wherever memory is freed) can only be dropped there; it is kept
as well (:func:`install` hooks :data:`sys.unraisablehook`, silently) and raised at the end of
the next :func:`kept` block, or by :func:`raise_dropped` (the scheduler calls it before each
tick).
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = [
    "HANDLED_SIGNALS",
    "OUTSIDE_SIGNALS",
    "RUN_USER_ALONE",
    "Interrupted",
    "deferred",
    "exit_status_for",
    "handled",
    "install",
    "kept",
    "raise_dropped",
    "reason_for",
    "signal_name",
]

HANDLED_SIGNALS: tuple[signal.Signals, ...] = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)
"""The signals that end a run with the robot stopped (SIGHUP does not exist on Windows)."""

OUTSIDE_SIGNALS: frozenset[int] = frozenset(int(s) for s in HANDLED_SIGNALS if s != signal.SIGINT)
"""The signals something outside may send a graded run to end it (SIGTERM, SIGHUP): a
teacher's ``kill``, a process manager stopping the grader; never a keyboard in a graded run."""

RUN_USER_ALONE = "ROBOSCRIPT_RUN_USER_ALONE"
"""The variable the grader's jail sets to ``1`` when every process a graded run can see under
its own user is the run's (bubblewrap's namespaces, or a user of its own per jail): a signal
that user sends from another process than the run's is then from a program the run started,
never from outside. Without it (resource limits only, where the run shares the teacher's
user), only a sender in the run's own session counts as the run's."""


def signal_name(signum: int) -> str:
    """``SIGTERM`` for 15; ``signal 99`` for a number this system has no name for."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


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

    def __str__(self) -> str:
        return self.reason  # what a traceback, a notebook or ``str(exc)`` shows: the sentence

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
_dropped: int | None = None
"""A signal raised inside a finalizer, where Python could only drop it, not raised again yet."""


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


def raise_dropped() -> None:
    """Raise, as :class:`Interrupted`, a signal a finalizer dropped since the last check.

    Raises:
        Interrupted: A signal landed in a finalizer (where it could not be raised).
    """
    global _dropped
    if _dropped is not None:
        signum, _dropped = _dropped, None
        raise Interrupted(signum)


@contextmanager
def kept() -> Iterator[None]:
    """Raise again, when the block returns, a signal that code inside it caught and dropped.

    For calls into libraries that catch every exception somewhere (``transitions`` logs and
    drops whatever is raised while it finalises an event, a :class:`KeyboardInterrupt`
    included): a signal landing there would otherwise be lost and the run go on. A signal the
    block lets out is raised as usual; nothing is delayed. A signal a finalizer dropped, inside
    the block or before it, is raised at its end too: the block itself is never cut short (it
    may be the one that stops the robot).
    """
    before = _raised
    yield
    raise_dropped()  # one a finalizer dropped is the reason, when there is one (raised once)
    if _raised != before:
        raise Interrupted(_last_signum)


def _unraisable(unraisable: sys.UnraisableHookArgs) -> None:
    """Keep a signal raised inside a finalizer; show every other unraisable error as usual."""
    global _dropped
    if isinstance(unraisable.exc_value, Interrupted) and unraisable.exc_value.signum in _SIGNUMS:
        if _dropped is None:  # the first signal stays the reason
            _dropped = unraisable.exc_value.signum
        return  # no traceback: the run ends with the signal's own sentence
    _previous_hook(unraisable)


_SIGNUMS = frozenset(int(signum) for signum in HANDLED_SIGNALS)
_previous_hook = sys.unraisablehook


def install() -> None:
    """Make every signal in :data:`HANDLED_SIGNALS` raise :class:`Interrupted`.

    A signal landing in a finalizer is kept for :func:`kept` and :func:`raise_dropped`.
    """
    global _previous_hook
    for signum in HANDLED_SIGNALS:
        signal.signal(signum, _raise)
    if sys.unraisablehook is not _unraisable:
        _previous_hook = sys.unraisablehook
        sys.unraisablehook = _unraisable


@contextmanager
def handled() -> Iterator[None]:
    """:func:`install` for the block only: for a run inside someone else's program.

    ``roboscript.run()`` in a script or a notebook stops the robot on Ctrl-C, SIGTERM and
    SIGHUP exactly as ``roboscript run`` does, then gives the program back its own handlers
    (and :data:`sys.unraisablehook`). Python lets only the main thread set handlers: in any
    other thread the block runs with the program's handlers as they are. A signal a finalizer
    dropped in the block is raised at its end (never left for a later run).

    Raises:
        Interrupted: A signal a finalizer dropped in the block, raised at its end.
    """
    global _dropped
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = {signum: signal.getsignal(signum) for signum in HANDLED_SIGNALS}
    hook = sys.unraisablehook
    install()
    try:
        yield
        raise_dropped()
    finally:
        _dropped = None  # the block's signals end with it: the program's handlers are back
        for signum, previous in saved.items():
            # None: a handler set outside Python, which Python cannot set again
            signal.signal(signum, signal.SIG_DFL if previous is None else previous)
        sys.unraisablehook = hook
