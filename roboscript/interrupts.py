"""Signals that end the program: Ctrl-C, SIGTERM, SIGHUP, all through one path.

A closed terminal sends SIGHUP, a process manager or a teacher's "kill all" sends SIGTERM, a
student presses Ctrl-C (SIGINT). Each one raises :class:`Interrupted` (a
:class:`KeyboardInterrupt`) in the main thread, wherever the program is, so the robot is
stopped on the way out exactly as for Ctrl-C (:func:`roboscript.session.run_session`,
:meth:`roboscript.robot.Robot.__exit__`), and the program exits with ``128 + signal number``
(130, 143, 129) after one plain sentence. A second signal while stopping raises again, so a
stuck stop can still be ended.
"""

from __future__ import annotations

import signal
from types import FrameType

__all__ = ["HANDLED_SIGNALS", "Interrupted", "exit_status_for", "install", "reason_for"]

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
    """

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__(signum)
        self.signum = signum

    @property
    def reason(self) -> str:
        """One plain sentence: what ended the run."""
        return reason_for(self)

    @property
    def exit_status(self) -> int:
        """The shell's status for a program ended by this signal: 128 + its number."""
        return 128 + int(self.signum)


def reason_for(exc: KeyboardInterrupt) -> str:
    """What ended the run, for any :class:`KeyboardInterrupt` (a bare one is Ctrl-C)."""
    signum = getattr(exc, "signum", signal.SIGINT)
    return _WHY.get(signal.Signals(signum).name, f"stopped by signal {int(signum)}")


def exit_status_for(exc: KeyboardInterrupt) -> int:
    """128 + the signal's number (130 for a bare :class:`KeyboardInterrupt`)."""
    return 128 + int(getattr(exc, "signum", signal.SIGINT))


def _raise(signum: int, frame: FrameType | None) -> None:
    del frame
    raise Interrupted(signum)


def install() -> None:
    """Make every signal in :data:`HANDLED_SIGNALS` raise :class:`Interrupted`."""
    for signum in HANDLED_SIGNALS:
        signal.signal(signum, _raise)
