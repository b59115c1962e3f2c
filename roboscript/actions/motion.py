"""Driving actions: ``drive``, ``rotate`` and ``stop``.

Both moves measure their progress from the wheel encoders and slow to a crawl for the last
stretch, so they stop within a millimetre or two whatever the cruise speed: the motors coast
for a few hundredths of a second after the stop, and at crawl speed that is short.
"""

from __future__ import annotations

import math

from roboscript import capabilities as cap
from roboscript.actions.base import Action, ActionContext, Param, Result

__all__ = ["Drive", "Rotate", "Stop"]

_STALL_TIME_S = 1.0
_STALL_PROGRESS_MM = 2.0


def _angle_deg(distances: tuple[float, float], track_mm: float) -> float:
    """Rotation from wheel travel, degrees clockwise."""
    return math.degrees((distances[0] - distances[1]) / track_mm)


class _Stall:
    """Fails a move whose wheels are powered but do not turn."""

    def __init__(self) -> None:
        self._mark_s = 0.0
        self._mark_mm = 0.0

    def reset(self, now_s: float, travelled_mm: float) -> None:
        self._mark_s = now_s
        self._mark_mm = travelled_mm

    def stalled(self, now_s: float, travelled_mm: float) -> bool:
        if abs(travelled_mm - self._mark_mm) >= _STALL_PROGRESS_MM:
            self.reset(now_s, travelled_mm)
            return False
        return now_s - self._mark_s >= _STALL_TIME_S


class Drive(Action):
    """Drive straight for a distance, or for a time.

    Args:
        distance_mm: How far; negative drives backward. Omit to drive for ``duration_s``.
        speed_mm_s: Cruise speed (magnitude), mm/s.
        duration_s: Drive for this long instead of a distance.

    Outcomes: ``done`` when the distance is covered (or the time is up); ``failed``
    ("stalled") when the wheels stop turning for a second, for example against a wall.
    """

    name = "drive"
    summary = "Drive straight for a distance or a time."
    params = (
        Param("distance", "distance_mm", "distance", "how far (negative = backward)", None),
        Param("speed", "speed_mm_s", "speed", "cruise speed", 150.0),
        Param("duration", "duration_s", "time", "drive for this long instead", None),
    )
    requires = frozenset({cap.DRIVE_BASE})

    CRAWL_MM_S = 40.0

    def __init__(
        self,
        distance_mm: float | None = None,
        speed_mm_s: float = 150.0,
        duration_s: float | None = None,
    ) -> None:
        if distance_mm is None and duration_s is None:
            raise ValueError("drive needs a distance or a duration")
        if speed_mm_s <= 0:
            raise ValueError("drive speed must be positive (use a negative distance to reverse)")
        self.distance_mm = distance_mm
        self.speed_mm_s = speed_mm_s
        self.duration_s = duration_s
        self._start_s = 0.0
        self._origin = (0.0, 0.0)
        self._stall = _Stall()

    def _travelled(self, base: cap.DriveBase) -> float:
        left, right = base.wheel_distances_mm()
        return ((left - self._origin[0]) + (right - self._origin[1])) / 2.0

    def start(self, ctx: ActionContext) -> None:
        base = ctx.drive_base
        self._origin = base.wheel_distances_mm()
        self._start_s = ctx.now_s
        self._stall.reset(ctx.now_s, 0.0)
        direction = -1.0 if (self.distance_mm or 0.0) < 0 else 1.0
        speed = min(self.speed_mm_s, base.max_speed_mm_s) * direction
        base.set_wheel_speeds(speed, speed)

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        travelled = self._travelled(base)
        if self.distance_mm is None:
            assert self.duration_s is not None
            self.feedback = f"driving {ctx.now_s - self._start_s:.1f}/{self.duration_s:.1f} s"
            if ctx.now_s - self._start_s >= self.duration_s:
                base.stop()
                return Result.done()
        else:
            direction = -1.0 if self.distance_mm < 0 else 1.0
            remaining = abs(self.distance_mm) - travelled * direction
            self.feedback = f"driving {abs(travelled):.0f}/{abs(self.distance_mm):.0f} mm"
            cruise = min(self.speed_mm_s, base.max_speed_mm_s)
            crawl = min(cruise, self.CRAWL_MM_S)
            if remaining <= crawl * 0.05:
                base.stop()
                return Result.done()
            slow_zone = max(15.0, cruise * 0.12)
            speed = crawl if remaining < slow_zone else cruise
            base.set_wheel_speeds(speed * direction, speed * direction)
        if not base.odometry_is_estimated and self._stall.stalled(ctx.now_s, travelled):
            base.stop()
            return Result.failed("stalled")
        return None

    def stop(self, ctx: ActionContext) -> None:
        ctx.drive_base.stop()


class Rotate(Action):
    """Turn in place by an angle.

    Args:
        angle_deg: How far to turn; positive turns right (clockwise seen from above).
        turn_rate_deg_s: Turning speed (magnitude), degrees per second.

    Outcomes: ``done`` when the angle is reached; ``failed`` ("stalled") when the wheels
    stop turning for a second.
    """

    name = "rotate"
    summary = "Turn in place by an angle (positive = right)."
    params = (
        Param("angle", "angle_deg", "angle", "how far to turn (positive = right)"),
        Param("turn_rate", "turn_rate_deg_s", "turn_rate", "turning speed", 90.0),
    )
    requires = frozenset({cap.DRIVE_BASE})

    CRAWL_DEG_S = 20.0

    def __init__(self, angle_deg: float, turn_rate_deg_s: float = 90.0) -> None:
        if turn_rate_deg_s <= 0:
            raise ValueError("turn rate must be positive (use a negative angle to turn left)")
        self.angle_deg = angle_deg
        self.turn_rate_deg_s = turn_rate_deg_s
        self._origin = (0.0, 0.0)
        self._stall = _Stall()

    def _turned(self, base: cap.DriveBase) -> float:
        left, right = base.wheel_distances_mm()
        return _angle_deg((left - self._origin[0], right - self._origin[1]), base.track_mm)

    def _set_rate(self, base: cap.DriveBase, rate_deg_s: float) -> None:
        wheel = math.radians(rate_deg_s) * base.track_mm / 2.0
        base.set_wheel_speeds(wheel, -wheel)

    def start(self, ctx: ActionContext) -> None:
        base = ctx.drive_base
        self._origin = base.wheel_distances_mm()
        self._stall.reset(ctx.now_s, 0.0)

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        turned = self._turned(base)
        direction = -1.0 if self.angle_deg < 0 else 1.0
        remaining = abs(self.angle_deg) - turned * direction
        self.feedback = f"turning {abs(turned):.0f}/{abs(self.angle_deg):.0f} deg"
        max_rate = math.degrees(2.0 * base.max_speed_mm_s / base.track_mm)
        cruise = min(self.turn_rate_deg_s, max_rate)
        crawl = min(cruise, self.CRAWL_DEG_S)
        if remaining <= crawl * 0.03:
            base.stop()
            return Result.done()
        slow_zone = max(6.0, cruise * 0.12)
        self._set_rate(base, (crawl if remaining < slow_zone else cruise) * direction)
        arc_mm = math.radians(turned) * base.track_mm / 2.0
        if not base.odometry_is_estimated and self._stall.stalled(ctx.now_s, arc_mm):
            base.stop()
            return Result.failed("stalled")
        return None

    def stop(self, ctx: ActionContext) -> None:
        ctx.drive_base.stop()


class Stop(Action):
    """Stop the wheels. Ends ``done`` at once."""

    name = "stop"
    summary = "Stop the wheels."
    requires = frozenset({cap.DRIVE_BASE})

    def update(self, ctx: ActionContext) -> Result | None:
        ctx.drive_base.stop()
        return Result.done()
