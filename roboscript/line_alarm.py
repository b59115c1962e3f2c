"""An alarm that rings between two lines of Python: the watchdog's timer where there are no
timer signals (Windows, a browser tab).

:class:`roboscript.watchdog.Watchdog` interrupts stuck code with ``SIGALRM`` where it can. Where
it cannot, there is no other thread to interrupt from either (a browser tab runs Python on the
page's one thread), so the code itself must be asked, between two of its lines, whether its
time is up: Python calls a hook at each new line and each jump back of a loop in the code it
is told to watch (:mod:`sys.monitoring` from Python 3.12, :func:`sys.settrace` before). A loop
in watched code is then stopped at its line, as the signal would stop it; a single call that
blocks (``time.sleep(60)``) is stopped when it returns. Before Python 3.12 the hook is gone
once it has raised (CPython unsets a trace function that raises) until the alarm is set again,
so code that catches the first stop in a loop of its own can only be ended with Ctrl-C there.

Only code the caller names as watched (the student's own files) is checked line by line: the
rest of the program is told apart once per place and then runs at full speed with
:mod:`sys.monitoring`; with :func:`sys.settrace` it pays one call of the hook per function
call.
"""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from collections.abc import Callable
from types import CodeType, FrameType
from typing import Any

__all__ = ["LineAlarm"]

_TOOL_ID = 4
"""The :mod:`sys.monitoring` tool id taken while an alarm is started (0-2 and 5 are named for
debuggers, coverage tools, profilers and optimizers; 3 and 4 are free)."""
_TOOL_NAME = "roboscript watchdog"

_MONITORING: Any = getattr(sys, "monitoring", None)
"""Python 3.12's :mod:`sys.monitoring`, or None before it."""


class LineAlarm:
    """A timer, like ``signal.setitimer``, that rings in watched code between two lines.

    Args:
        ring: Called with the running watched frame when the time set has passed; what it
            raises is raised in that frame, at that line.
        watched: Whether code from a file (a code object's ``co_filename``) is watched.
    """

    def __init__(self, ring: Callable[[FrameType], None], watched: Callable[[str], bool]) -> None:
        self._ring = ring
        self._watched = watched
        self._known: dict[str, bool] = {}
        self._deadline_s: float | None = None
        self._repeat_s = 0.0
        self._hook = ""  # "monitoring", "trace" or "" (not started)
        self._thread = 0  # the thread it watches (sys.monitoring reports every thread)

    @staticmethod
    def available() -> bool:
        """True where Python offers a hook to watch code with (it always does in CPython and
        Pyodide; an alarm still cannot start when a debugger holds every hook)."""
        return _MONITORING is not None or hasattr(sys, "settrace")

    @property
    def started(self) -> bool:
        """True between a successful :meth:`start` and :meth:`stop`."""
        return bool(self._hook)

    def start(self) -> bool:
        """Watch code run from now on in this thread.

        Returns:
            False (and nothing watched) when a debugger or coverage tool already holds the
            hook: it is never taken from them.
        """
        self._thread = threading.get_ident()
        monitoring = _MONITORING
        if monitoring is not None:
            try:
                monitoring.use_tool_id(_TOOL_ID, _TOOL_NAME)
            except ValueError:  # the id is taken: leave it to its owner
                return False
            events = monitoring.events.LINE | monitoring.events.JUMP
            monitoring.register_callback(_TOOL_ID, monitoring.events.LINE, self._on_line)
            monitoring.register_callback(_TOOL_ID, monitoring.events.JUMP, self._on_jump)
            monitoring.set_events(_TOOL_ID, events)
            self._hook = "monitoring"
            return True
        if sys.gettrace() is not None:  # a debugger or coverage tool traces this thread
            return False
        sys.settrace(self._on_call)
        self._hook = "trace"
        return True

    def set(self, after_s: float, repeat_s: float = 0.0) -> None:
        """Ring once ``after_s`` seconds have passed, then every ``repeat_s`` (if > 0).

        Setting it again replaces what was set; ``after_s`` of 0 or less disarms it.
        """
        self._deadline_s = time.perf_counter() + after_s if after_s > 0 else None
        self._repeat_s = repeat_s
        if self._hook == "trace" and sys.gettrace() is None:
            # CPython unsets a trace function that raises: watch again from here on.
            sys.settrace(self._on_call)

    def stop(self) -> None:
        """Stop watching (the alarm is disarmed)."""
        self._deadline_s = None
        hook, self._hook = self._hook, ""
        if hook == "monitoring":
            monitoring = _MONITORING
            monitoring.set_events(_TOOL_ID, 0)
            monitoring.register_callback(_TOOL_ID, monitoring.events.LINE, None)
            monitoring.register_callback(_TOOL_ID, monitoring.events.JUMP, None)
            with contextlib.suppress(ValueError):
                monitoring.free_tool_id(_TOOL_ID)
        elif hook == "trace":
            sys.settrace(None)

    # -------------------------------------------------------------------------- the hooks

    def _is_watched(self, filename: str) -> bool:
        known = self._known.get(filename)
        if known is None:
            known = self._known[filename] = bool(self._watched(filename))
        return known

    def _due(self) -> bool:
        """The time set has passed, in the thread this alarm watches."""
        deadline = self._deadline_s
        return (
            deadline is not None
            and time.perf_counter() >= deadline
            and threading.get_ident() == self._thread  # another thread's code is not ours
        )

    def _check(self, frame: FrameType) -> None:
        if not self._due():
            return
        deadline = self._deadline_s or 0.0
        self._deadline_s = deadline + self._repeat_s if self._repeat_s > 0 else None
        self._ring(frame)

    def _on_line(self, code: CodeType, _line: int) -> object:
        if not self._is_watched(code.co_filename):
            return _MONITORING.DISABLE  # this place is never reported again
        if self._due():  # the frame is looked up only when it rings: this runs every line
            self._check(sys._getframe(1))
        return None

    def _on_jump(self, code: CodeType, _from: int, _to: int) -> object:
        # not delegated to _on_line: the watched frame must stay one call up
        if not self._is_watched(code.co_filename):
            return _MONITORING.DISABLE
        if self._due():
            self._check(sys._getframe(1))
        return None

    def _on_call(self, frame: FrameType, event: str, _arg: object) -> Any:
        # sys.settrace: a function starts; only watched ones are followed line by line
        if event == "call" and self._is_watched(frame.f_code.co_filename):
            return self._on_trace_line
        return None

    def _on_trace_line(self, frame: FrameType, event: str, _arg: object) -> Any:
        if event == "line":
            self._check(frame)
        return self._on_trace_line
