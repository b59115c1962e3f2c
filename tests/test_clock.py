"""Clocks."""

from __future__ import annotations

import ctypes
import sys
import threading

import pytest

from roboscript.clock import Clock, MonotonicClock, SimClock


def test_sim_clock_jumps_and_never_goes_back() -> None:
    clock = SimClock(1.0)
    clock.sleep_until(3.5)
    assert clock.now() == 3.5
    clock.sleep_until(2.0)
    assert clock.now() == 3.5
    clock.advance(0.5)
    assert clock.now() == 4.0
    with pytest.raises(ValueError):
        clock.advance(-1.0)


def test_monotonic_clock_waits_until_the_deadline() -> None:
    clock = MonotonicClock()
    start = clock.now()
    clock.sleep_until(start + 0.02)
    assert clock.now() >= start + 0.02


def test_both_clocks_satisfy_the_protocol() -> None:
    assert isinstance(SimClock(), Clock)
    assert isinstance(MonotonicClock(), Clock)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="timer slack is Linux's")
def test_monotonic_clock_tightens_the_sleeping_threads_timer_slack() -> None:
    libc = ctypes.CDLL(None, use_errno=True)
    seen: list[int] = []

    def sleep_once() -> None:  # slack is per thread: the test runner's is left as it was
        before = libc.prctl(30, 0, 0, 0, 0)  # PR_GET_TIMERSLACK, in ns
        clock = MonotonicClock()
        clock.sleep_until(clock.now() + 0.001)
        seen.extend((before, libc.prctl(30, 0, 0, 0, 0)))

    worker = threading.Thread(target=sleep_once)
    worker.start()
    worker.join()
    before, after = seen
    assert after == 1000
    assert after <= before


def test_monotonic_clock_sleeps_short_of_the_deadline_and_spins_the_rest(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import time

    asked: list[float] = []
    real_sleep = time.sleep

    def recording_sleep(seconds: float) -> None:
        asked.append(seconds)
        real_sleep(seconds)

    monkeypatch.setattr(time, "sleep", recording_sleep)
    clock = MonotonicClock(spin_s=0.004)
    start = clock.now()
    clock.sleep_until(start + 0.01)
    assert clock.now() >= start + 0.01  # the spin finished the wait: never early
    assert len(asked) == 1 and asked[0] <= 0.006  # and the sleep left the spin its share


def test_monotonic_clock_spin_cannot_be_negative() -> None:
    with pytest.raises(ValueError):
        MonotonicClock(spin_s=-0.001)
