"""WheelSpeedLoop: motor power from wheel speed targets on boards without firmware PID."""

from __future__ import annotations

import math

import pytest

from roboscript.control import WheelSpeedLoop

NO_PID = (0.0, 0.0, 0.0)


def test_feed_forward_alone_gives_the_fraction_of_full_speed() -> None:
    loop = WheelSpeedLoop(NO_PID, max_speed_mm_s=300.0)
    loop.set_targets(150.0, -75.0)
    assert loop.update((0.0, 0.0), 0.02) == pytest.approx((0.5, -0.25))


def test_a_zero_target_is_zero_power_whatever_the_wheel_does() -> None:
    loop = WheelSpeedLoop((0.01, 0.5, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(0.0, 100.0)
    left, right = loop.update((80.0, 0.0), 0.02)
    assert left == 0.0
    assert right > 100.0 / 300.0  # the slow right wheel gets more than feed-forward


def test_a_slow_wheel_gets_more_power_a_fast_one_less() -> None:
    loop = WheelSpeedLoop((0.002, 0.0, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(150.0, 150.0)
    left, right = loop.update((100.0, 200.0), 0.02)
    assert left == pytest.approx(0.5 + 0.002 * 50.0)
    assert right == pytest.approx(0.5 - 0.002 * 50.0)


def test_power_is_limited_to_full() -> None:
    loop = WheelSpeedLoop((1.0, 0.0, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(300.0, -300.0)
    assert loop.update((0.0, 0.0), 0.02) == (1.0, -1.0)


def test_reversing_forgets_the_integral_of_the_old_direction() -> None:
    loop = WheelSpeedLoop((0.0, 0.01, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(150.0, 150.0)
    for _ in range(20):
        loop.update((50.0, 50.0), 0.1)  # a wheel held back winds up the integral
    loop.set_targets(-150.0, -150.0)
    assert loop.update((-150.0, -150.0), 0.1) == pytest.approx((-0.5, -0.5))


def test_a_new_target_in_the_same_direction_keeps_the_integral() -> None:
    loop = WheelSpeedLoop((0.0, 0.01, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(150.0, 150.0)
    loop.update((50.0, 50.0), 0.1)
    loop.set_targets(120.0, 120.0)
    left, _ = loop.update((120.0, 120.0), 0.1)
    assert left > 120.0 / 300.0


def test_setting_the_same_targets_again_changes_nothing() -> None:
    loop = WheelSpeedLoop((0.0, 0.01, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(150.0, 150.0)
    first = loop.update((50.0, 50.0), 0.1)
    loop.set_targets(150.0, 150.0)
    second = loop.update((50.0, 50.0), 0.1)
    assert second[0] > first[0]  # still integrating
    assert loop.targets_mm_s == (150.0, 150.0)


def test_stopping_and_starting_again_starts_from_zero_integral() -> None:
    loop = WheelSpeedLoop((0.0, 0.01, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(150.0, 150.0)
    for _ in range(10):
        loop.update((0.0, 0.0), 0.1)
    loop.set_targets(0.0, 0.0)
    assert loop.update((0.0, 0.0), 0.1) == (0.0, 0.0)
    loop.set_targets(150.0, 150.0)
    assert loop.update((150.0, 150.0), 0.1) == pytest.approx((0.5, 0.5))


def test_a_new_loop_gives_no_power_before_any_target() -> None:
    loop = WheelSpeedLoop((0.01, 0.0, 0.0), max_speed_mm_s=300.0)
    assert loop.targets_mm_s == (0.0, 0.0)
    assert loop.update((50.0, -50.0), 0.02) == (0.0, 0.0)


@pytest.mark.parametrize("target", [150.0, -150.0])
def test_the_correction_is_limited_to_one_full_power_step(target: float) -> None:
    # a wheel spinning far too fast in either direction: kp alone would say -2.5 (or +2.5),
    # limited to -1 (+1) it still leaves the feed-forward half of the power
    loop = WheelSpeedLoop((0.01, 0.0, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(target, target)
    power = target / 300.0 - math.copysign(1.0, target)
    assert loop.update((target + math.copysign(250.0, target),) * 2, 0.02) == pytest.approx(
        (power, power)
    )


def test_stopping_after_reversing_then_reversing_again_starts_from_zero_integral() -> None:
    loop = WheelSpeedLoop((0.0, 0.01, 0.0), max_speed_mm_s=300.0)
    loop.set_targets(-150.0, -150.0)
    for _ in range(10):
        loop.update((0.0, 0.0), 0.1)  # held back: the integral winds up
    loop.set_targets(0.0, 0.0)
    loop.set_targets(-150.0, -150.0)
    assert loop.update((-150.0, -150.0), 0.1) == pytest.approx((-0.5, -0.5))
