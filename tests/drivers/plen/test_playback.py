"""The host's model of how long the firmware plays a motion, and how long after $SM."""

from __future__ import annotations

import pytest

from roboscript.drivers.plen.playback import Schedule

# Three frames of 2, 3 and 2 updates (64, 96 and 64 ms; 100 ms is 3 updates, like 96).
TIMES_MS = [64, 100, 64]


def test_a_motion_without_a_loop_plays_its_frames_once() -> None:
    assert Schedule.of(TIMES_MS).duration_s() == pytest.approx(7 * 0.032)


def test_passes_of_a_loop_section_in_the_middle() -> None:
    schedule = Schedule.of(TIMES_MS, loop=(1, 1), passes=3)
    assert schedule.duration_s() == pytest.approx((2 + 3 * 3 + 2) * 0.032)
    assert Schedule.of(TIMES_MS, loop=(0, 2), passes=None).duration_s() is None


def test_stop_finishes_the_frame_in_progress_and_the_rest_of_the_motion() -> None:
    schedule = Schedule.of(TIMES_MS, loop=(0, 2), passes=None)
    # At 1.0 s: pass 5 (0.896..1.120 s), frame 1 (0.960..1.056 s) -> frames 1 and 2 finish.
    assert schedule.stopped_at_s(1.0) == pytest.approx(1.12)
    assert schedule.stopped_at_s(0.0) == pytest.approx(7 * 0.032)
    finite = Schedule.of(TIMES_MS, loop=(0, 2), passes=2)
    assert finite.stopped_at_s(10.0) == pytest.approx(14 * 0.032)


def test_the_update_period_can_be_stretched() -> None:
    assert Schedule.of(TIMES_MS).duration_s(period_s=0.033) == pytest.approx(7 * 0.033)


def test_short_transitions_count_one_update() -> None:
    assert Schedule.of([10]).duration_s() == pytest.approx(0.032)


@pytest.mark.parametrize(
    ("times", "loop", "passes"), [([], None, 1), ([64], (0, 1), 1), ([64, 64], (0, 1), 0)]
)
def test_bad_schedules(times: list[int], loop: tuple[int, int] | None, passes: int) -> None:
    with pytest.raises(ValueError):
        Schedule.of(times, loop, passes)
