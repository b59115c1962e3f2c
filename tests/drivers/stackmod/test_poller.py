"""One GET in flight: answers, timeouts on the caller's clock, bounded retries.

The StackMod poller is the drivers' shared :class:`~roboscript.drivers.base.PendingRequest`
set up for GETs (tests/drivers/test_base.py tests the helper itself).
"""

from __future__ import annotations

import pytest

from roboscript.drivers.base import PendingRequest
from roboscript.drivers.stackmod.driver import get_poller
from roboscript.drivers.stackmod.messages import Command, Get, GetReply
from roboscript.errors import LinkTimeoutError

U = ord("U")
ASK = Get(U, Command.ULT, 0)


def poller(retries: int = 2) -> PendingRequest[Get]:
    return get_poller(timeout_s=0.2, retries=retries, describe=lambda a: f"module {chr(a)}")


def test_an_answer_ends_the_request() -> None:
    p = poller()
    p.sent(ASK, 0.0)
    assert p.in_flight == ASK
    assert p.answered(GetReply(U, Command.ULT, 0, 42))
    assert p.in_flight is None
    assert p.resend_due(10.0) is None


def test_an_answer_to_something_else_is_late_not_ours() -> None:
    p = poller()
    p.sent(ASK, 0.0)
    assert not p.answered(GetReply(U, Command.ULT, 1, 42))
    assert not p.answered(GetReply(ord("M"), Command.ULT, 0, 42))
    assert p.late_replies == 2
    assert p.in_flight == ASK


def test_resent_after_each_timeout_then_the_module_is_named() -> None:
    p = poller(retries=2)
    p.sent(ASK, 1.0)
    assert p.resend_due(1.19) is None
    assert p.resend_due(1.2) == ASK
    assert p.resend_due(1.39) is None
    assert p.resend_due(1.4) == ASK
    with pytest.raises(LinkTimeoutError, match=r"module U did not answer GET ULT0 \(3 tries"):
        p.resend_due(1.6)
    assert p.in_flight is None
    assert p.retried == 2


def test_no_retries_means_one_try() -> None:
    p = poller(retries=0)
    p.sent(ASK, 0.0)
    with pytest.raises(LinkTimeoutError, match=r"\(1 tries"):
        p.resend_due(0.2)


def test_one_request_at_a_time() -> None:
    p = poller()
    p.sent(ASK, 0.0)
    with pytest.raises(RuntimeError):
        p.sent(ASK, 0.0)


def test_bad_settings_are_refused() -> None:
    with pytest.raises(ValueError):
        get_poller(timeout_s=0.0, retries=1, describe=chr)
    with pytest.raises(ValueError):
        get_poller(timeout_s=0.1, retries=-1, describe=chr)
