"""A simple-pid controller configured for the scheduler."""

from __future__ import annotations

from simple_pid import PID

__all__ = ["PID", "make_pid"]


def make_pid(
    gains: tuple[float, float, float],
    *,
    setpoint: float = 0.0,
    output_limits: tuple[float | None, float | None] = (None, None),
) -> PID:
    """Build a PID that computes on every call and takes ``dt`` from the caller.

    Args:
        gains: ``(kp, ki, kd)``.
        setpoint: Initial setpoint.
        output_limits: Clamp of the output (also stops integral wind-up).

    Returns:
        A :class:`simple_pid.PID`; call it as ``pid(measurement, dt=dt_s)`` with ``dt_s > 0``.
    """
    kp, ki, kd = gains
    return PID(kp, ki, kd, setpoint=setpoint, sample_time=None, output_limits=output_limits)
