"""Stand-in for ``hub.motion_sensor``."""

from __future__ import annotations

from standin_log import record


def reset_yaw(angle: int) -> None:
    record("motion_sensor.reset_yaw", angle)


def tilt_angles() -> tuple[int, int, int]:
    return (0, 0, 0)
