"""make_pid: a simple-pid controller that computes on every call with the scheduler's dt."""

from __future__ import annotations

import pytest

from roboscript.control import make_pid


def test_proportional_output_is_gain_times_error() -> None:
    pid = make_pid((2.0, 0.0, 0.0), setpoint=10.0)
    assert pid(4.0, dt=0.02) == pytest.approx(12.0)
    assert pid(13.0, dt=0.02) == pytest.approx(-6.0)


def test_the_integral_grows_with_the_dt_given_not_with_the_wall_clock() -> None:
    pid = make_pid((0.0, 1.0, 0.0), setpoint=1.0)
    # two calls a few microseconds apart still integrate half a second each
    assert pid(0.0, dt=0.5) == pytest.approx(0.5)
    assert pid(0.0, dt=0.5) == pytest.approx(1.0)


def test_every_call_computes_even_at_short_intervals() -> None:
    pid = make_pid((1.0, 0.0, 0.0), setpoint=0.0)
    assert pid(1.0, dt=1e-6) == pytest.approx(-1.0)
    assert pid(2.0, dt=1e-6) == pytest.approx(-2.0)


def test_output_limits_clamp_and_stop_integral_wind_up() -> None:
    pid = make_pid((1.0, 10.0, 0.0), setpoint=100.0, output_limits=(-5.0, 5.0))
    for _ in range(50):
        assert pid(0.0, dt=0.1) == pytest.approx(5.0)
    # the error turns round: without wind-up the output follows at once
    assert (pid(200.0, dt=0.1) or 0.0) < 0.0


def test_the_default_setpoint_is_zero_and_outputs_are_unlimited() -> None:
    pid = make_pid((1000.0, 0.0, 0.0))
    assert pid(3.0, dt=0.02) == pytest.approx(-3000.0)


def test_derivative_term_uses_the_measurement_change_over_dt() -> None:
    pid = make_pid((0.0, 0.0, 0.5), setpoint=0.0)
    pid(0.0, dt=0.1)
    # measurement rose by 1 in 0.1 s: d(input)/dt = 10, output = -kd * 10
    assert pid(1.0, dt=0.1) == pytest.approx(-5.0)


def test_a_zero_dt_is_refused() -> None:
    with pytest.raises(ValueError, match="dt"):
        make_pid((1.0, 0.0, 0.0))(1.0, dt=0.0)
