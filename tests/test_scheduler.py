"""The tick loop: phases, dt, deadlines and overruns."""

from __future__ import annotations

import itertools

import pytest

from roboscript.clock import SimClock
from roboscript.scheduler import Scheduler


def test_phases_run_in_sense_think_act_after_order() -> None:
    sched = Scheduler(SimClock(), period_s=0.01)
    calls: list[str] = []
    sched.add(lambda now, dt: calls.append("after"), "after")
    sched.add(lambda now, dt: calls.append("act"), "act")
    sched.add(lambda now, dt: calls.append("think"), "think")
    sched.add(lambda now, dt: calls.append("sense"), "sense")
    sched.step()
    assert calls == ["sense", "think", "act", "after"]


def test_simulated_time_jumps_by_exact_periods() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.02)
    seen: list[tuple[float, float]] = []
    sched.add(lambda now, dt: seen.append((now, dt)))
    sched.run(until=lambda: len(seen) == 5)
    assert [round(t, 6) for t, _ in seen] == [0.0, 0.02, 0.04, 0.06, 0.08]
    assert all(dt == pytest.approx(0.02) for _, dt in seen)
    assert sched.stats.overruns == 0


def test_dt_is_never_zero_even_if_the_clock_does_not_move() -> None:
    class FrozenClock:
        def now(self) -> float:
            return 5.0

        def sleep_until(self, deadline_s: float) -> None:
            pass

    sched = Scheduler(FrozenClock(), period_s=0.01)
    dts: list[float] = []
    sched.add(lambda now, dt: dts.append(dt))
    for _ in range(3):
        sched.step()
    assert all(dt > 0 for dt in dts)


def test_max_duration_ends_the_run_on_the_scheduler_clock() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.05)
    assert sched.run(until=lambda: False, max_duration_s=1.0) is False
    assert clock.now() == pytest.approx(1.0, abs=0.05)


def test_a_late_tick_is_counted_and_gets_the_measured_dt() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.01)
    dts: list[float] = []

    def task(now: float, dt: float) -> None:
        dts.append(dt)
        if len(dts) == 3:
            clock.advance(0.05)  # this tick's work took 5 periods

    sched.add(task)
    sched.run(until=lambda: len(dts) == 6)
    assert sched.stats.overruns >= 1
    assert dts[3] == pytest.approx(0.05, abs=1e-9)


def test_after_a_stall_the_loop_catches_up_without_bursting() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.01)
    starts: list[float] = []
    dts: list[float] = []

    def task(now: float, dt: float) -> None:
        starts.append(now)
        dts.append(dt)
        if len(starts) == 3:
            clock.advance(0.05)  # a 5-period stall in the third tick

    sched.add(task)
    sched.run(until=lambda: False, max_duration_s=0.3)
    # Controllers never see a burst: at most two ticks per period while catching up.
    assert min(dts) == pytest.approx(0.005)
    # The grid is kept: one tick per period over the run, as if nothing had happened,
    # and the late ticks are back on the grid once caught up.
    assert len(starts) == 31
    assert starts[-5:] == pytest.approx([0.26, 0.27, 0.28, 0.29, 0.30])
    assert sched.stats.skipped_ticks == 0
    assert sched.stats.overruns > 0


def test_a_stall_longer_than_the_catch_up_bound_skips_ticks_and_restarts() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.01, max_catch_up_periods=10)
    starts: list[float] = []

    def task(now: float, dt: float) -> None:
        starts.append(now)
        if len(starts) == 2:
            clock.advance(0.25)  # 25 periods: too far behind to catch up

    sched.add(task)
    sched.run(until=lambda: len(starts) == 6)
    assert sched.stats.skipped_ticks == 24
    # The grid restarts from the late tick: one period apart again, no burst.
    assert [round(b - a, 6) for a, b in itertools.pairwise(starts[2:])] == [0.01] * 3


def test_time_between_two_runs_is_not_caught_up() -> None:
    clock = SimClock()
    sched = Scheduler(clock, period_s=0.01)
    starts: list[float] = []
    sched.add(lambda now, dt: starts.append(now))
    sched.run(until=lambda: len(starts) == 3)  # e.g. the handshake
    clock.advance(0.05)  # the mission is loaded: 5 periods in which nothing was due
    sched.run(until=lambda: len(starts) == 7)
    assert [round(b - a, 6) for a, b in itertools.pairwise(starts[3:])] == [0.01] * 3
    assert sched.stats.overruns == 0


def test_catch_up_bound_must_be_a_period_or_more() -> None:
    with pytest.raises(ValueError):
        Scheduler(SimClock(), period_s=0.01, max_catch_up_periods=0.5)


def test_period_must_be_positive() -> None:
    with pytest.raises(ValueError):
        Scheduler(SimClock(), period_s=0)
