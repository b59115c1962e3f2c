"""One StackMod GET in flight at a time, with a reply timeout and bounded retries.

StackMod modules share one line and answer only when asked, so the host asks one question at a
time: a reply then always belongs to the one request in flight, and two modules never talk at
once. A request that gets no answer within ``timeout_s`` (on the scheduler's clock: the poller
never sleeps and never reads a clock) is sent again, up to ``retries`` times; after that the
module is declared silent with a :class:`~roboscript.errors.LinkTimeoutError` naming it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from roboscript.drivers.stackmod.messages import Get, GetReply
from roboscript.errors import LinkTimeoutError

__all__ = ["GetPoller"]


@dataclass
class _InFlight:
    request: Get
    sent_s: float
    tries: int


class GetPoller:
    """Tracks the GET in flight (sans-IO: the caller sends and passes the time in).

    Args:
        timeout_s: How long to wait for each answer, seconds.
        retries: How many times a request is sent again before giving up.
        describe: Names the module at an address, for the error message
            (``the motor module at 'M' (0x4D)``).

    Attributes:
        retried: Requests sent again because an answer was late or lost.
        late_replies: Replies that matched no request in flight (an answer to a try that had
            already timed out, arriving after the request was answered or abandoned).
    """

    def __init__(self, *, timeout_s: float, retries: int, describe: Callable[[int], str]) -> None:
        if timeout_s <= 0:
            raise ValueError("a GET timeout must be positive")
        if retries < 0:
            raise ValueError("GET retries cannot be negative")
        self.timeout_s = timeout_s
        self.retries = retries
        self._describe = describe
        self._in_flight: _InFlight | None = None
        self.retried = 0
        self.late_replies = 0

    @property
    def in_flight(self) -> Get | None:
        """The request waiting for its answer, or ``None``."""
        return None if self._in_flight is None else self._in_flight.request

    def sent(self, request: Get, now_s: float) -> None:
        """Record that ``request`` was just sent for the first time.

        Raises:
            RuntimeError: Another request is still in flight.
        """
        if self._in_flight is not None:
            raise RuntimeError("a StackMod GET is already in flight")
        self._in_flight = _InFlight(request, now_s, 1)

    def answered(self, reply: GetReply) -> bool:
        """Return whether ``reply`` answers the request in flight (which is then done)."""
        pending = self._in_flight
        if pending is not None and _answers(reply, pending.request):
            self._in_flight = None
            return True
        self.late_replies += 1
        return False

    def resend_due(self, now_s: float) -> Get | None:
        """Return the request to send again now, if its answer is overdue.

        Args:
            now_s: Scheduler time, seconds.

        Returns:
            The request to send again (the caller sends it), or ``None``.

        Raises:
            LinkTimeoutError: The request has gone unanswered ``1 + retries`` times; the
                message names the module and the request.
        """
        pending = self._in_flight
        if pending is None or now_s - pending.sent_s < self.timeout_s - 1e-9:
            return None
        if pending.tries > self.retries:
            self._in_flight = None
            request = pending.request
            raise LinkTimeoutError(
                f"{self._describe(request.address)} did not answer "
                f"GET {request.command.value}{request.selector} "
                f"({pending.tries} tries, {self.timeout_s:g} s each): "
                "is it powered, wired to the line, and set to that address?"
            )
        pending.tries += 1
        pending.sent_s = now_s
        self.retried += 1
        return pending.request


def _answers(reply: GetReply, request: Get) -> bool:
    return (reply.address, reply.command, reply.selector) == (
        request.address,
        request.command,
        request.selector,
    )
