"""The shared driver base: the pending-request helper, the stop guard, capabilities, codec."""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

import pytest

from roboscript.clock import SimClock
from roboscript.codec import Role
from roboscript.drivers.asip.codec import AsipCodec
from roboscript.drivers.base import Driver, PendingRequest
from roboscript.errors import LinkClosedError, LinkTimeoutError
from roboscript.profiles import BUILTIN_PROFILES
from roboscript.transport.link import Link


@dataclass(frozen=True)
class Ask:
    key: str


@dataclass(frozen=True)
class Reply:
    key: str


def _answers(request: Ask, message: object) -> bool:
    return isinstance(message, Reply) and message.key == request.key


def pending(retries: int | None = 2, timeout_s: float = 0.5) -> PendingRequest[Ask]:
    return PendingRequest(timeout_s=timeout_s, retries=retries, matches=_answers)


ASK = Ask("a")


# ------------------------------------------------------------------------- PendingRequest


def test_the_matching_reply_ends_the_request_and_is_handed_back() -> None:
    p = pending()
    p.sent(ASK, 0.0)
    assert p.answered(Reply("b")) is None  # not ours: still waiting
    assert p.in_flight is ASK
    assert p.answered(Reply("a")) is ASK
    assert p.in_flight is None
    assert p.resend_due(100.0) is None  # nothing left to time out
    assert p.late_replies == 1


def test_no_resend_before_the_timeout_and_one_at_it() -> None:
    p = pending(timeout_s=0.2)
    p.sent(ASK, 1.0)
    assert p.resend_due(1.19) is None
    assert p.resend_due(1.2) is ASK  # 1.2 - 1.0 is a hair under 0.2 in floats: still due
    assert p.in_flight is ASK
    assert p.resend_due(1.39) is None  # timed from the resend
    assert p.resend_due(1.4) is ASK


def test_retries_are_counted_then_the_request_is_given_up() -> None:
    p = pending(retries=2)
    p.sent(ASK, 0.0)
    assert p.tries == 1
    assert p.resend_due(0.5) is ASK
    assert p.resend_due(1.0) is ASK
    assert p.tries == 3
    with pytest.raises(LinkTimeoutError, match=r"\(3 tries, 0.5 s each\)"):
        p.resend_due(1.5)
    assert p.in_flight is None
    assert p.retried == 2


def test_no_retries_means_one_try_and_a_custom_error() -> None:
    def gone(request: Ask, tries: int) -> Exception:
        return LinkTimeoutError(f"{request.key} unanswered after {tries}")

    p = PendingRequest(timeout_s=1.0, retries=0, matches=_answers, give_up=gone)
    p.sent(ASK, 0.0)
    assert p.resend_due(0.99) is None
    with pytest.raises(LinkTimeoutError, match="a unanswered after 1"):
        p.resend_due(1.0)


def test_unlimited_retries_resend_until_answered() -> None:
    p = pending(retries=None, timeout_s=0.25)
    p.sent(ASK, 0.0)
    resent = [t for t in (0.25 * i for i in range(1, 41)) if p.resend_due(t) is not None]
    assert len(resent) == 40
    assert p.answered(Reply("a")) is ASK


def test_a_late_reply_after_the_timeout_is_ignored() -> None:
    p = pending(retries=0)
    p.sent(ASK, 0.0)
    with pytest.raises(LinkTimeoutError):
        p.resend_due(0.5)
    assert p.answered(Reply("a")) is None  # the answer to the abandoned try
    assert p.late_replies == 1
    # The next request is not answered by the stale reply either.
    p.sent(Ask("b"), 1.0)
    assert p.answered(Reply("a")) is None
    assert p.in_flight == Ask("b")
    assert p.tries == 1


def test_bytes_arriving_restart_the_wait() -> None:
    p = pending(timeout_s=0.5)
    p.sent(ASK, 0.0)
    assert not p.overdue(0.6, heard_s=0.3)  # a long reply is still coming in
    assert p.overdue(0.8, heard_s=0.3)
    assert p.overdue(0.6)


def test_expired_leaves_the_caller_to_decide() -> None:
    p = pending(retries=1)
    p.sent(ASK, 0.0)
    assert p.expired(0.4) is None
    assert p.expired(0.5) is ASK
    assert p.in_flight is None
    assert p.may_retry
    p.sent(ASK, 0.7)  # the same request sent again later is a retry
    assert (p.tries, p.retried) == (2, 1)
    assert p.expired(1.2) is ASK
    assert not p.may_retry
    with pytest.raises(LinkTimeoutError, match=r"\(2 tries"):
        raise p.give_up_error()


def test_a_new_request_after_an_expired_one_starts_its_own_count() -> None:
    p = pending(retries=1)
    p.sent(ASK, 0.0)
    assert p.expired(0.5) is ASK
    p.sent(Ask("b"), 0.6)
    assert (p.tries, p.retried) == (1, 0)


def test_one_request_at_a_time_and_cancel() -> None:
    p = pending()
    p.sent(ASK, 0.0)
    with pytest.raises(RuntimeError):
        p.sent(Ask("b"), 0.0)
    p.cancel()
    assert p.in_flight is None
    assert p.resend_due(10.0) is None
    p.sent(Ask("b"), 0.0)


def test_bad_settings_are_refused() -> None:
    with pytest.raises(ValueError):
        pending(timeout_s=0.0)
    with pytest.raises(ValueError):
        pending(retries=-1)


# --------------------------------------------------------------------------------- Driver


class _DeadLink:
    """A link that has failed: every send raises."""

    codec = AsipCodec(Role.HOST)

    def send(self, message: object) -> None:
        raise LinkClosedError("the cable came out")


class _Probe(Driver):
    protocol = "asip"

    def __init__(self) -> None:
        super().__init__(cast(Link, _DeadLink()), BUILTIN_PROFILES["mirto"], SimClock())
        self.events: list[str] = []

    def start(self) -> None:
        pass

    def tick(self, now_s: float, dt_s: float) -> None:
        pass

    def flush(self, now_s: float, dt_s: float) -> None:
        pass

    def send_stop(self) -> None:
        self.events.append("forgot setpoints")
        self.link.send(object())
        self.events.append("sent")  # never reached: the link is dead

    def after_stop(self) -> None:
        self.events.append("after")


def test_stop_all_never_raises_and_always_finishes() -> None:
    driver = _Probe()
    driver.stop_all()  # the link raises LinkClosedError: logged, not raised
    assert driver.events == ["forgot setpoints", "after"]


def test_capabilities_are_offered_once_ready_and_handed_out_as_copies() -> None:
    driver = _Probe()
    assert driver.capabilities() == {}
    assert not driver.ready
    made = driver.wanted({"drive_base": lambda: "wheels", "walker": lambda: "legs"})
    assert made == {"drive_base": "wheels"}  # a mirto has no walker
    driver.offer(made)
    assert driver.ready
    copy = driver.capabilities()
    copy.clear()
    assert driver.capabilities() == {"drive_base": "wheels"}


def test_the_host_codec_comes_from_the_protocol_unit() -> None:
    codec = _Probe.make_codec(BUILTIN_PROFILES["mirto"])
    assert isinstance(codec, AsipCodec)
    assert codec.role is Role.HOST


# ------------------------------------------------------------------------------- liveness


class _QuietPort:
    """A port that has bytes to give only when told to, and can be lost."""

    def __init__(self) -> None:
        self.incoming = b""
        self.lost = False

    def read(self, size: int = 1) -> bytes:
        if self.lost:
            raise OSError("device disconnected")
        data, self.incoming = self.incoming, b""
        return data

    def write(self, data: bytes, /) -> int:
        return len(data)

    def close(self) -> None:
        pass


class _Listener(Driver):
    """Reads its link every tick; raises what a test puts in ``raise_next``."""

    protocol = "asip"

    def __init__(self, clock: SimClock, limit_s: float | None) -> None:
        self.port = _QuietPort()
        link = Link(self.port, AsipCodec(Role.HOST), clock=clock, name="socket://robot:1")
        super().__init__(link, BUILTIN_PROFILES["mirto"], clock)
        self.silence_limit_s = limit_s
        self.raise_next: Exception | None = None

    def start(self) -> None:
        pass

    def tick(self, now_s: float, dt_s: float) -> None:
        self.link.poll()
        if self.raise_next is not None:
            raise self.raise_next

    def flush(self, now_s: float, dt_s: float) -> None:
        pass

    def send_stop(self) -> None:
        pass


class _Subclassed(_Listener):
    """A driver built on another: the rule must not be applied twice."""

    def tick(self, now_s: float, dt_s: float) -> None:
        super().tick(now_s, dt_s)


def _ready_listener(limit_s: float | None = 1.0) -> tuple[_Listener, SimClock]:
    clock = SimClock()
    clock.advance(2.0)
    driver = _Listener(clock, limit_s)  # connected at 2.0 s
    clock.advance(0.5)
    driver.offer({})  # ready at 2.5 s
    return driver, clock


def test_silence_after_the_handshake_fails_with_one_sentence() -> None:
    driver, clock = _ready_listener(1.0)
    driver.port.incoming = b"@E,I,1\n"
    clock.advance(0.5)
    driver.tick(clock.now(), 0.02)  # heard at 3.0 s
    clock.advance(0.98)
    driver.tick(clock.now(), 0.02)  # quiet for 0.98 s: still alive
    clock.advance(0.02)
    with pytest.raises(LinkTimeoutError) as caught:
        driver.tick(clock.now(), 0.02)
    assert str(caught.value) == (
        "the robot stopped responding 2.0 s after connecting: nothing heard from it for 1.0 s"
    )
    assert driver.failure is caught.value


def test_without_a_limit_a_quiet_robot_is_fine() -> None:
    driver, clock = _ready_listener(None)
    clock.advance(60.0)
    driver.tick(clock.now(), 0.02)


def test_a_drivers_own_timeout_keeps_its_detail_once_ready() -> None:
    driver, clock = _ready_listener(None)
    driver.raise_next = LinkTimeoutError("the motor module did not answer")
    clock.advance(1.25)
    with pytest.raises(
        LinkTimeoutError,
        match=r"^the robot stopped responding 1\.8 s after "
        r"connecting: the motor module did not answer$",
    ):
        driver.tick(clock.now(), 0.02)


def test_a_timeout_during_the_handshake_keeps_the_handshake_sentence() -> None:
    clock = SimClock()
    driver = _Listener(clock, 1.0)
    driver.raise_next = LinkTimeoutError("no startup line")
    clock.advance(5.0)
    with pytest.raises(LinkTimeoutError, match=r"^no startup line$"):
        driver.tick(clock.now(), 0.02)


def test_a_lost_port_says_which_and_when() -> None:
    driver, clock = _ready_listener()
    driver.port.lost = True
    clock.advance(0.3)
    with pytest.raises(LinkClosedError) as caught:
        driver.tick(clock.now(), 0.02)
    assert str(caught.value) == "the connection to socket://robot:1 was lost 0.8 s after connecting"


def test_a_driver_built_on_another_says_it_once() -> None:
    clock = SimClock()
    driver = _Subclassed(clock, 1.0)
    driver.offer({})
    clock.advance(1.0)
    with pytest.raises(LinkTimeoutError) as caught:
        driver.tick(clock.now(), 0.02)
    assert str(caught.value).count("stopped responding") == 1


def test_skipped_readings_are_counted_with_the_garbage() -> None:
    driver, _ = _ready_listener()
    driver.skip_reading("distance 30000 mm")
    driver.skip_reading("distance 30000 mm")
    assert driver.link.faults == {"out_of_range": 2}
