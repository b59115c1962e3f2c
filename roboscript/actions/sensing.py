"""Reading the robot's heading for actions: the IMU when there is one, else odometry."""

from __future__ import annotations

from roboscript import capabilities as cap
from roboscript.actions.base import ActionContext
from roboscript.angles import turned_deg

__all__ = ["heading_deg", "imu_heading_deg", "odometry_heading_deg"]


def odometry_heading_deg(base: cap.DriveBase) -> float:
    """Turn since connection from wheel travel, degrees clockwise (not wrapped)."""
    left, right = base.wheel_distances_mm()
    return turned_deg(left, right, base.track_mm)


def imu_heading_deg(ctx: ActionContext) -> float | None:
    """The IMU heading, degrees clockwise, or ``None`` without an IMU or a reading."""
    if not ctx.has(cap.HEADING):
        return None
    sensor: cap.HeadingSensor = ctx.get(cap.HEADING)
    reading = sensor.heading_deg()
    return None if reading is None else float(reading)


def heading_deg(ctx: ActionContext) -> float:
    """The robot's heading, degrees clockwise: the IMU's if it has one, else odometry's."""
    reading = imu_heading_deg(ctx)
    return reading if reading is not None else odometry_heading_deg(ctx.drive_base)
