"""The host-side driver contract: what every protocol driver provides, and what they share.

A driver owns a :class:`~roboscript.transport.Link` and turns it into capabilities. It is
ticked twice per scheduler tick: :meth:`Driver.tick` in the *sense* phase (read the link,
update cached sensor values, advance the handshake, watch for silence) and :meth:`Driver.flush`
in the *act* phase (send setpoints that changed). It never blocks and never sleeps.

Safety: :meth:`Driver.stop_all` must stop every actuator with the fewest bytes that work on
the real firmware, must be callable at any time (even before the handshake finished), and
must never raise: it is called on every exit path, including after the link has failed. The
base class keeps that promise once for every driver (the *stop guard*): a driver says what to
send in :meth:`Driver.send_stop`, and a link that fails on the way is logged, not raised.

Shared here, so that each driver has one copy of them:

* the capability table (:meth:`Driver.capabilities`, filled by :meth:`Driver.offer`);
* the stop guard (:meth:`Driver.stop_all`);
* the host codec, from the protocol's unit (:meth:`Driver.make_codec`);
* :class:`PendingRequest`: one request in flight, its reply matched, a timeout on the
  scheduler clock and bounded retries;
* :class:`WheelDriveBase`: the ``drive_base`` of a driver that takes wheel speeds;
* the *liveness rule*, the same for every protocol: once the robot is ready, a driver whose
  robot talks steadily sets :attr:`Driver.silence_limit_s`, and nothing heard for that long
  fails the run; any :class:`~roboscript.errors.LinkTimeoutError` out of :meth:`Driver.tick`
  or :meth:`Driver.flush` after the handshake reads "the robot stopped responding 12.3 s
  after connecting: ..."; a lost port reads "the connection to X was lost 12.3 s after
  connecting". Every subclass's ``tick`` and ``flush`` are wrapped once, when the class is
  defined, so a driver cannot forget the rule;
* :meth:`Driver.skip_reading`: a device value no real robot can report is counted with the
  link's garbage (``Link.faults``) and skipped.
"""

from __future__ import annotations

import abc
import functools
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, Protocol, TypeVar

from roboscript.clock import Clock
from roboscript.codec import Codec, Role
from roboscript.drivers import protocol_unit
from roboscript.errors import LinkClosedError, LinkError, LinkTimeoutError, LocalProtocolError
from roboscript.robot_profile import RobotProfile
from roboscript.transport.link import Link

__all__ = ["OUT_OF_RANGE", "STOPPED_RESPONDING", "Driver", "PendingRequest", "WheelDriveBase"]

logger = logging.getLogger("roboscript.drivers")

RequestT = TypeVar("RequestT")

_EPSILON_S = 1e-9
"""Slack in timeout comparisons, so float noise in clock sums never delays one by a tick."""

STOPPED_RESPONDING = "the robot stopped responding"
"""How every silence failure after the handshake begins, whatever the protocol."""

OUT_OF_RANGE = "out_of_range"
"""The garbage kind (``Link.faults``) of a device value no real robot can report."""

_Tick = Callable[[Any, float, float], None]


def _guarded(method: _Tick, *, watch: bool) -> _Tick:
    """Wrap a driver's ``tick`` or ``flush`` with the liveness rule (see the module docstring).

    ``watch`` adds the silence check after the method (``tick`` only: it has read the link).
    """

    @functools.wraps(method)
    def guarded(self: Driver, now_s: float, dt_s: float) -> None:
        try:
            method(self, now_s, dt_s)
            if watch:
                self.watch_silence(now_s)
        except LinkClosedError as exc:
            failure = self._failed(exc, now_s)
            if failure is exc:
                raise
            raise failure from exc
        except LinkTimeoutError as exc:
            if not self.ready:
                raise  # the handshake's own sentence says what did not answer
            failure = self._failed(exc, now_s)
            if failure is exc:
                raise
            raise failure from exc

    guarded.liveness_guarded = True  # type: ignore[attr-defined]
    return guarded


@dataclass
class _Try(Generic[RequestT]):
    request: RequestT
    sent_s: float
    tries: int


class PendingRequest(Generic[RequestT]):
    """One request in flight, waiting for its reply, with a timeout and bounded retries.

    Sans-IO: the driver sends the bytes and passes the scheduler's time in; this never sleeps
    and never reads a clock. The driver tells it when a request went out (:meth:`sent`),
    passes it each message it receives (:meth:`answered`), and asks every tick whether the
    request must go out again (:meth:`resend_due`), or, to decide for itself what a late
    reply means, takes the overdue request out of flight (:meth:`expired`).

    One request at a time: a reply then always belongs to the request in flight (the
    protocols concerned have no request ids). A reply that comes after its request was
    given up, or answers nothing in flight, is ignored (and counted).

    Args:
        timeout_s: How long each try waits for its reply, seconds (scheduler clock).
        retries: How many times a request is sent again before giving up; ``None`` sends it
            again until it is answered.
        matches: ``matches(request, message)`` is true when ``message`` answers ``request``.
        give_up: Builds the error raised when the last try went unanswered:
            ``give_up(request, tries)``. Default: a
            :class:`~roboscript.errors.LinkTimeoutError` naming the request.

    Attributes:
        retried: Requests sent again because an answer was late or lost.
        late_replies: Messages passed to :meth:`answered` that answered nothing in flight.

    Raises:
        ValueError: A timeout that is not positive, or negative retries.
    """

    def __init__(
        self,
        *,
        timeout_s: float,
        retries: int | None = 0,
        matches: Callable[[RequestT, object], bool],
        give_up: Callable[[RequestT, int], Exception] | None = None,
    ) -> None:
        if timeout_s <= 0:
            raise ValueError("a reply timeout must be positive")
        if retries is not None and retries < 0:
            raise ValueError("retries cannot be negative")
        self.timeout_s = timeout_s
        self.retries = retries
        self._matches = matches
        self._give_up = give_up or self._no_answer
        self._in_flight: _Try[RequestT] | None = None
        self._expired: _Try[RequestT] | None = None
        self.retried = 0
        self.late_replies = 0

    def _no_answer(self, request: RequestT, tries: int) -> Exception:
        return LinkTimeoutError(
            f"no answer to {request!r} ({tries} tries, {self.timeout_s:g} s each)"
        )

    @property
    def in_flight(self) -> RequestT | None:
        """The request waiting for its reply, or ``None``."""
        return None if self._in_flight is None else self._in_flight.request

    @property
    def tries(self) -> int:
        """How many times the request in flight (or the one that just expired) was sent."""
        current = self._in_flight or self._expired
        return 0 if current is None else current.tries

    @property
    def may_retry(self) -> bool:
        """True if the request that just expired may be sent again."""
        last = self._expired
        return last is not None and (self.retries is None or last.tries <= self.retries)

    def sent(self, request: RequestT, now_s: float) -> None:
        """Record that ``request`` went out at ``now_s``.

        Sending the request that just expired (:meth:`expired`) again counts as a retry.

        Raises:
            RuntimeError: Another request is still in flight.
        """
        if self._in_flight is not None:
            raise RuntimeError("a request is already in flight")
        last = self._expired
        self._expired = None
        if last is not None and last.request is request:
            self.retried += 1
            self._in_flight = _Try(request, now_s, last.tries + 1)
        else:
            self._in_flight = _Try(request, now_s, 1)

    def answered(self, message: object) -> RequestT | None:
        """If ``message`` answers the request in flight, end it and return that request.

        Returns:
            The answered request, or ``None`` (the message answered nothing in flight: a
            late reply, or not a reply at all; counted in :attr:`late_replies`).
        """
        pending = self._in_flight
        if pending is not None and self._matches(pending.request, message):
            self._in_flight = None
            return pending.request
        self.late_replies += 1
        return None

    def overdue(self, now_s: float, *, heard_s: float | None = None) -> bool:
        """True if the request in flight has waited ``timeout_s`` for its reply.

        Args:
            now_s: Scheduler time, seconds.
            heard_s: When bytes last arrived, if a slow reply restarts the wait (a long reply
                with no terminator); ``None`` times from the sending only.
        """
        pending = self._in_flight
        if pending is None:
            return False
        start = pending.sent_s if heard_s is None else max(pending.sent_s, heard_s)
        return now_s - start >= self.timeout_s - _EPSILON_S

    def expired(self, now_s: float, *, heard_s: float | None = None) -> RequestT | None:
        """Take the request in flight out of flight if its reply is overdue, and return it.

        The caller then sends it again (:meth:`sent` counts a retry; :attr:`may_retry` says
        whether retries are left) or gives up (:meth:`give_up_error`).

        Args:
            now_s: Scheduler time, seconds.
            heard_s: As for :meth:`overdue`.
        """
        if not self.overdue(now_s, heard_s=heard_s):
            return None
        assert self._in_flight is not None
        self._expired, self._in_flight = self._in_flight, None
        return self._expired.request

    def give_up_error(self) -> Exception:
        """The error for the request that just expired with no retries left."""
        last = self._expired
        if last is None:
            raise RuntimeError("no request has expired")
        self._expired = None
        return self._give_up(last.request, last.tries)

    def resend_due(self, now_s: float, *, heard_s: float | None = None) -> RequestT | None:
        """Return the request to send again now, if its reply is overdue.

        Args:
            now_s: Scheduler time, seconds.
            heard_s: As for :meth:`overdue`.

        Returns:
            The request to send again (the caller sends it; it is in flight again from
            ``now_s``), or ``None``.

        Raises:
            Exception: The request went unanswered ``1 + retries`` times: the ``give_up``
                error (by default :class:`~roboscript.errors.LinkTimeoutError`).
        """
        request = self.expired(now_s, heard_s=heard_s)
        if request is None:
            return None
        if not self.may_retry:
            raise self.give_up_error()
        self.sent(request, now_s)
        return request

    def cancel(self) -> None:
        """Forget the request in flight (its reply, if it comes, is ignored)."""
        self._in_flight = None
        self._expired = None


class Driver(abc.ABC):
    """Base class of protocol drivers.

    Args:
        link: The open link to the robot (its codec made by :meth:`make_codec`).
        profile: The robot model.
        clock: The scheduler's clock.
    """

    protocol: ClassVar[str]

    silence_limit_s: float | None = None
    """Once ready, nothing heard from the robot for this long fails the run, seconds; ``None``
    for a robot that only speaks when asked (its driver's unanswered requests say it)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name, watch in (("tick", True), ("flush", False)):
            method = cls.__dict__.get(name)
            if method is not None and not getattr(method, "liveness_guarded", False):
                setattr(cls, name, _guarded(method, watch=watch))

    def __init__(self, link: Link, profile: RobotProfile, clock: Clock) -> None:
        self.link = link
        self.profile = profile
        self.clock = clock
        self.ready = False
        self.connected_s = clock.now()
        """Scheduler time at which the port was opened, seconds."""
        self.ready_s: float | None = None
        """Scheduler time at which the handshake ended, seconds (``None`` before)."""
        self.failure: LinkError | None = None
        """The silence or loss that ended the run, as the user reads it, or ``None``."""
        self.notices: list[str] = []
        """One-line messages for the user (for example a switch to host-side control)."""
        self.device_errors: list[str] = []
        """Errors the robot reported (refused requests), oldest first, not yet taken."""
        self._capabilities: dict[str, object] = {}

    @classmethod
    def make_codec(cls, profile: RobotProfile) -> Codec[Any]:
        """The host-role codec for this protocol, from its unit's codec factory.

        Raises:
            ProfileError: The profile's options are invalid.
        """
        codec: Codec[Any] = protocol_unit(cls.protocol).make_codec(Role.HOST, profile)
        return codec

    @abc.abstractmethod
    def start(self) -> None:
        """Begin the handshake (send the first probe)."""

    @abc.abstractmethod
    def tick(self, now_s: float, dt_s: float) -> None:
        """Sense phase: read the link, update sensor values, advance the handshake.

        Raises:
            LinkError: The link was lost or the robot stopped responding.
        """

    @abc.abstractmethod
    def flush(self, now_s: float, dt_s: float) -> None:
        """Act phase: send setpoints that changed since the last tick."""

    def capabilities(self) -> dict[str, object]:
        """The capability objects, by capability name (empty until the handshake ends)."""
        return dict(self._capabilities)

    def offer(self, capabilities: Mapping[str, object]) -> None:
        """End the handshake: offer ``capabilities`` and become ready."""
        self._capabilities = dict(capabilities)
        self.ready = True
        self.ready_s = self.clock.now()

    # ------------------------------------------------------------------------------ liveness

    def silent_for_s(self, now_s: float) -> float:
        """How long nothing has been heard from the robot at ``now_s``, seconds.

        Timed from the last byte received, or from the end of the handshake if that is later
        (or from connecting, before it).
        """
        heard = [t for t in (self.link.last_receive_s, self.ready_s) if t is not None]
        return now_s - max(heard, default=self.connected_s)

    def watch_silence(self, now_s: float) -> None:
        """Apply :attr:`silence_limit_s` (called after every :meth:`tick`).

        Raises:
            LinkTimeoutError: The robot is ready and nothing was heard for the limit.
        """
        limit = self.silence_limit_s
        if limit is None or not self.ready:
            return
        if self.silent_for_s(now_s) >= limit - _EPSILON_S:
            raise LinkTimeoutError(STOPPED_RESPONDING)

    def _failed(self, exc: LinkError, now_s: float) -> LinkError:
        """The error the user reads for a silence or loss at ``now_s`` (kept in ``failure``)."""
        if exc is self.failure:
            return exc  # a subclass's tick already turned it into the user's sentence
        after = f"{now_s - self.connected_s:.1f} s after connecting"
        failure: LinkError
        if isinstance(exc, LinkClosedError):
            if self.link.closed:
                text = f"the connection to {self.link.name} was lost {after}"
            else:  # the robot closed something of its own (a program on the hub stopped)
                text = f"{exc} ({after})"
            failure = LinkClosedError(text)
        else:
            detail = str(exc)
            if STOPPED_RESPONDING in detail:  # a driver's own silence check: say it once
                detail = f"nothing heard from it for {self.silent_for_s(now_s):.1f} s"
            failure = LinkTimeoutError(f"{STOPPED_RESPONDING} {after}: {detail}")
        self.failure = failure
        return failure

    def skip_reading(self, what: str) -> None:
        """Count a device value no real robot can report with the link's garbage, and skip it.

        Counted under :data:`OUT_OF_RANGE` in ``link.faults``; logged once, like other
        garbage, so a broken sensor cannot flood the log.

        Args:
            what: The value and why it is impossible, for the log.
        """
        faults = self.link.faults
        if not faults[OUT_OF_RANGE]:
            logger.warning(
                "%s sent a value no real robot can report (%s); skipping such values",
                self.link.name,
                what,
            )
        faults[OUT_OF_RANGE] += 1

    def wanted(self, makers: Mapping[str, Callable[[], object]]) -> dict[str, object]:
        """Build the capabilities the profile lists, each with its maker, in ``makers`` order."""
        wanted = self.profile.capabilities
        return {name: make() for name, make in makers.items() if name in wanted}

    def stop_all(self) -> None:
        """Stop every actuator now. Never raises.

        Sends :meth:`send_stop`; a link that fails on the way (or a stop the codec refuses)
        is logged, not raised. Then :meth:`after_stop` runs, whether the stop went out or not.
        Drivers override those two, not this.
        """
        try:
            self.send_stop()
        except (LinkError, LocalProtocolError) as exc:
            logger.debug("stop not sent: %s", exc)
        self.after_stop()

    @abc.abstractmethod
    def send_stop(self) -> None:
        """Forget every setpoint and send what stops every actuator, with the fewest bytes
        that work on the real firmware.

        Raises:
            LinkError: The link failed (:meth:`stop_all` logs it).
        """

    def after_stop(self) -> None:
        """State to change once the stop was sent or failed (nothing by default)."""
        return

    def describe(self) -> str:
        """What is on the other end, in a few words (after the handshake)."""
        return self.profile.name

    def take_device_error(self) -> str | None:
        """The oldest error the robot reported and nobody has taken yet, or ``None``.

        The mission runner takes them every tick and fails the running action with them.
        """
        return self.device_errors.pop(0) if self.device_errors else None

    def notice(self, text: str) -> None:
        """Tell the user something once, in one line (logged at once as a warning)."""
        if text not in self.notices:
            self.notices.append(text)
            logger.warning("%s", text)


class _WheelSetpoints(Protocol):
    profile: RobotProfile

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None: ...


class WheelDriveBase:
    """The ``drive_base`` capability of a driver that takes wheel speed setpoints.

    It limits setpoints to the profile's top speed and reads wheel travel from the driver;
    the driver decides how speeds are held (firmware PID, host PID, or timing).

    Args:
        driver: Takes ``set_wheel_speeds(left_mm_s, right_mm_s)``; its ``profile`` gives the
            track and top speed.
        distances: Returns the wheel travel (left, right) since connection, mm.
        odometry_is_estimated: True when travel is computed from time, not encoders.
    """

    def __init__(
        self,
        driver: _WheelSetpoints,
        distances: Callable[[], tuple[float, float]],
        *,
        odometry_is_estimated: bool = False,
    ) -> None:
        self._driver = driver
        self._distances = distances
        self.track_mm = driver.profile.track_mm
        self.max_speed_mm_s = driver.profile.max_speed_mm_s
        self.odometry_is_estimated = odometry_is_estimated

    def set_wheel_speeds(self, left_mm_s: float, right_mm_s: float) -> None:
        """Hold each wheel at a speed, mm/s (forward positive), limited to the top speed."""
        limit = self.max_speed_mm_s
        self._driver.set_wheel_speeds(
            max(-limit, min(limit, left_mm_s)), max(-limit, min(limit, right_mm_s))
        )

    def stop(self) -> None:
        """Stop both wheels."""
        self._driver.set_wheel_speeds(0.0, 0.0)

    def wheel_distances_mm(self) -> tuple[float, float]:
        """Wheel travel (left, right) since connection, mm; forward positive."""
        return self._distances()
