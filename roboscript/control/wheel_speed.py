"""Wheel speed held by the host: power from measured encoder speed, one PID per wheel."""

from __future__ import annotations

from roboscript.control.pid import make_pid

__all__ = ["WheelSpeedLoop"]


class WheelSpeedLoop:
    """Two PIDs that turn wheel speed targets into motor power.

    Output = feed-forward (target / max speed) + PID correction, limited to -1..1. The
    feed-forward gets the wheel moving at once; the PID removes what it gets wrong (load,
    battery, dead band).

    Args:
        gains: ``(kp, ki, kd)`` in power per mm/s of speed error.
        max_speed_mm_s: The wheel speed at full power (for the feed-forward).
    """

    def __init__(self, gains: tuple[float, float, float], max_speed_mm_s: float) -> None:
        self.max_speed_mm_s = max_speed_mm_s
        self._pids = [make_pid(gains, output_limits=(-1.0, 1.0)) for _ in range(2)]
        self.targets_mm_s = (0.0, 0.0)

    def set_targets(self, left_mm_s: float, right_mm_s: float) -> None:
        """New wheel speed targets, mm/s (forward positive)."""
        if (left_mm_s, right_mm_s) != self.targets_mm_s:
            for pid, target in zip(self._pids, (left_mm_s, right_mm_s), strict=True):
                if target == 0.0 or (target > 0) != (pid.setpoint > 0):
                    pid.reset()
                pid.setpoint = target
            self.targets_mm_s = (left_mm_s, right_mm_s)

    def update(self, measured_mm_s: tuple[float, float], dt_s: float) -> tuple[float, float]:
        """Return motor power (-1..1) for each wheel from the measured speeds."""
        powers = []
        for pid, target, measured in zip(self._pids, self.targets_mm_s, measured_mm_s, strict=True):
            if target == 0.0:
                powers.append(0.0)
                continue
            feed_forward = target / self.max_speed_mm_s
            correction = float(pid(measured, dt=dt_s) or 0.0)
            powers.append(max(-1.0, min(1.0, feed_forward + correction)))
        return powers[0], powers[1]
