"""Steering loops: heading hold, wall following and line following, on simple-pid.

Each loop returns a *turn rate correction* in degrees per second, clockwise (right) positive,
to add to a base turn rate; :func:`wheel_speeds` turns (speed, turn rate) into wheel speeds.
"""

from __future__ import annotations

import math

from roboscript.angles import wrap_deg
from roboscript.control.pid import make_pid

__all__ = ["HeadingHold", "LineFollower", "WallFollower", "angle_error_deg", "wheel_speeds"]


def angle_error_deg(target_deg: float, measured_deg: float) -> float:
    """``target - measured`` wrapped to [-180, 180): the short way round."""
    return wrap_deg(target_deg - measured_deg)


def wheel_speeds(speed_mm_s: float, turn_rate_deg_s: float, track_mm: float) -> tuple[float, float]:
    """Wheel speeds (left, right) in mm/s for a forward speed and a clockwise turn rate."""
    delta = math.radians(turn_rate_deg_s) * track_mm / 2.0
    return speed_mm_s + delta, speed_mm_s - delta


class HeadingHold:
    """Keeps a heading: turn rate from the heading error, wrapped the short way round.

    Args:
        gains: ``(kp, ki, kd)`` in deg/s per degree of error.
        max_rate_deg_s: Limit of the correction, deg/s.
    """

    def __init__(self, gains: tuple[float, float, float], max_rate_deg_s: float) -> None:
        self.pid = make_pid(gains, output_limits=(-max_rate_deg_s, max_rate_deg_s))
        # simple-pid computes setpoint - input; feeding the wrapped error with setpoint 0
        # makes it turn the short way round across +-180 degrees.
        self.pid.setpoint = 0.0

    def update(self, target_deg: float, measured_deg: float, dt_s: float) -> float:
        """Turn rate correction (deg/s, clockwise positive)."""
        return float(self.pid(-angle_error_deg(target_deg, measured_deg), dt=dt_s) or 0.0)


class WallFollower:
    """Keeps a side sensor at a target gap from a wall: a cascade of two loops.

    The outer loop turns the gap error into an *approach angle* towards or away from the
    wall, limited to ``max_approach_deg``; the inner loop holds the heading ``wall direction +
    approach angle``. Limiting the angle keeps the side sensor looking at the wall: a reading
    taken at an angle is longer than the true gap (it is corrected by the cosine of the
    angle), and an unlimited loop would turn until the sensor saw along the wall.

    The wall's direction is the robot's heading when following starts (walls are followed
    from alongside them) and stays fixed for the whole follow: the loop is made for straight
    walls.

    Args:
        gains: ``(kp, ki, kd)`` of the outer loop, degrees of approach per mm of gap error.
        target_mm: Wanted gap between the side sensor and the wall.
        side: ``"left"`` or ``"right"``: where the wall is.
        heading_gains: ``(kp, ki, kd)`` of the inner loop, deg/s per degree.
        max_approach_deg: Steepest angle towards or away from the wall.
        max_rate_deg_s: Limit of the turn rate, deg/s.
    """

    def __init__(
        self,
        gains: tuple[float, float, float],
        target_mm: float,
        side: str,
        *,
        heading_gains: tuple[float, float, float] = (4.0, 0.0, 0.1),
        max_approach_deg: float = 25.0,
        max_rate_deg_s: float = 60.0,
    ) -> None:
        self.wall_heading_deg: float | None = None
        self._sign = 1.0 if side == "right" else -1.0
        self._outer = make_pid(
            gains, setpoint=target_mm, output_limits=(-max_approach_deg, max_approach_deg)
        )
        self._inner = HeadingHold(heading_gains, max_rate_deg_s)

    def update(self, gap_mm: float | None, heading_deg: float, dt_s: float) -> float:
        """Turn rate (deg/s, clockwise positive) from the side gap and the current heading.

        Args:
            gap_mm: The side sensor's reading, or ``None`` when there is no new echo.
            heading_deg: The robot's heading (odometry or IMU), clockwise positive.
            dt_s: Seconds since the last call.
        """
        if self.wall_heading_deg is None:
            self.wall_heading_deg = heading_deg
        relative = angle_error_deg(heading_deg, self.wall_heading_deg) * self._sign
        if gap_mm is None:
            approach = 0.0
        else:
            gap = gap_mm * math.cos(math.radians(relative))
            # PID output is positive when the wall is too close; approach is towards it.
            approach = -float(self._outer(gap, dt=dt_s) or 0.0)
        target = self.wall_heading_deg + approach * self._sign
        return self._inner.update(target, heading_deg, dt_s)


class LineFollower:
    """Steers so the line stays under the middle sensor (or under one edge).

    Args:
        gains: ``(kp, ki, kd)`` in deg/s per unit of line position (-1 .. 1).
        max_rate_deg_s: Limit of the correction, deg/s.
    """

    def __init__(self, gains: tuple[float, float, float], max_rate_deg_s: float = 120.0) -> None:
        self.pid = make_pid(gains, output_limits=(-max_rate_deg_s, max_rate_deg_s))

    @staticmethod
    def position(readings: tuple[float, ...], threshold: float) -> float | None:
        """Where the line is under the sensors, -1 (far left) to 1 (far right), or ``None``.

        Readings are left to right, higher = darker; the position is the darkness-weighted
        mean of the sensor positions, ignoring sensors below ``threshold / 4`` (bare floor).
        """
        count = len(readings)
        if count == 0 or max(readings) < threshold:
            return None
        floor = threshold / 4.0
        weights = [max(0.0, value - floor) for value in readings]
        total = sum(weights)
        if total <= 0:
            return None
        span = count - 1 if count > 1 else 1
        return sum(w * (2.0 * i / span - 1.0) for i, w in enumerate(weights)) / total

    def update(self, position: float, target: float, dt_s: float) -> float:
        """Turn rate correction (deg/s, clockwise positive): towards the line."""
        self.pid.setpoint = target
        # PID output is positive when position < target (line to the left): turn left.
        return -float(self.pid(position, dt=dt_s) or 0.0)
