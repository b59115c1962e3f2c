"""Settle and Stall: when a closed-loop move counts as finished, and when as stuck."""

from __future__ import annotations

from roboscript.control import Settle, Stall


def _settled_after(settle: Settle, errors: list[float], dt_s: float) -> list[bool]:
    return [settle.update(error, dt_s) for error in errors]


def test_settles_once_within_tolerance_for_the_dwell() -> None:
    settle = Settle(tolerance=1.0, dwell_s=0.15)
    # 0.05 s ticks: three ticks inside make 0.15 s (float sums fall just short: allowed)
    assert _settled_after(settle, [3.0, 0.5, -0.9, 1.0], 0.05) == [False, False, False, True]


def test_leaving_the_tolerance_restarts_the_dwell() -> None:
    settle = Settle(tolerance=1.0, dwell_s=0.1)
    assert _settled_after(settle, [0.0, 1.5, 0.0, 0.0], 0.05) == [False, False, False, True]


def test_the_tolerance_is_inclusive_and_symmetric() -> None:
    assert Settle(tolerance=2.0, dwell_s=0.0).update(-2.0, 0.02)
    assert not Settle(tolerance=2.0, dwell_s=0.01).update(2.0001, 0.02)


def test_a_zero_dwell_settles_at_the_first_error_inside() -> None:
    settle = Settle(tolerance=0.5, dwell_s=0.0)
    assert settle.update(0.1, 0.02)


def test_stall_after_the_window_without_progress() -> None:
    stall = Stall(min_progress=2.0, window_s=1.0)
    stall.reset(0.0, 100.0)
    assert not stall.update(0.5, 101.9)  # under 2 mm is no progress
    assert not stall.update(0.99, 101.0)
    assert stall.update(1.0, 101.5)


def test_progress_restarts_the_window_in_either_direction() -> None:
    stall = Stall(min_progress=2.0, window_s=1.0)
    stall.reset(0.0, 0.0)
    assert not stall.update(0.5, -2.0)  # backwards counts too
    assert not stall.update(1.25, -2.5)
    assert stall.update(1.5, -2.5)


def test_reset_starts_watching_from_the_new_mark() -> None:
    stall = Stall()
    stall.reset(0.0, 0.0)
    assert stall.update(1.0, 0.0)
    stall.reset(5.0, 40.0)
    assert not stall.update(5.9, 41.0)
    assert stall.update(6.0, 41.0)


def test_defaults_are_two_millimetres_in_one_second() -> None:
    stall = Stall()
    assert (stall.min_progress, stall.window_s) == (2.0, 1.0)


def test_an_error_outside_the_tolerance_is_never_settled_even_without_a_dwell() -> None:
    # a rotate with no dwell must still not end while it is 5 degrees off
    settle = Settle(tolerance=1.0, dwell_s=0.0)
    assert not settle.update(5.0, 0.02)
    assert settle.update(0.5, 0.02)
    assert not settle.update(-5.0, 0.02)


def test_a_stall_watch_never_reset_starts_from_nought_at_time_nought() -> None:
    stall = Stall(min_progress=2.0, window_s=1.0)
    assert not stall.update(0.5, -1.5)
    assert stall.update(1.0, -1.5)
