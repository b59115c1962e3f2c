"""Driving actions: ``drive``, ``rotate`` and ``stop``.

Both moves measure their progress from the wheel encoders and slow to a crawl for the last
stretch, so they stop within a millimetre or two whatever the cruise speed: the motors coast
for a few hundredths of a second after the stop, and at crawl speed that is short.

A robot with an IMU turns by the IMU and holds its heading with it while driving (wheel slip
is invisible to the encoders but not to a gyro). Without one, the wheel-speed loops (firmware
or host) already keep both wheels rolling alike, which is all odometry could check.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from roboscript import capabilities as cap
from roboscript.actions.base import (
    FROM_INIT,
    Action,
    ActionContext,
    Param,
    Result,
    UnderSpecifiedError,
)
from roboscript.actions.sensing import imu_heading_deg
from roboscript.actions.wheels import WheelAction
from roboscript.angles import turned_deg
from roboscript.control import HeadingHold, Settle, angle_error_deg, wheel_speeds

__all__ = ["Drive", "Rotate", "Stop"]


class Drive(WheelAction):
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
        Param("distance", "distance_mm", "distance", "how far (negative = backward)", FROM_INIT),
        Param("speed", "speed_mm_s", "speed", "cruise speed", FROM_INIT),
        Param("duration", "duration_s", "time", "drive for this long instead", FROM_INIT),
    )
    requires = frozenset({cap.DRIVE_BASE})
    failure = "stalled"
    drive_speeds = ("speed",)
    guessed_params = dict.fromkeys(
        ("direction", "backward", "backwards", "reverse"),
        "a drive has no direction: a negative distance drives backward",
    ) | dict.fromkeys(("power", "percent"), "a drive is given its speed, not a power")

    CRAWL_MM_S = 40.0

    @classmethod
    def conflicts(cls, values: Mapping[str, Any]) -> list[tuple[str, str, str | None]]:
        if values.get("distance_mm") is None or values.get("duration_s") is None:
            return []
        return [
            (
                "duration",
                (
                    f"{cls.name} takes a distance or a duration, not both: it would drive the "
                    "distance and ignore the duration"
                ),
                "remove 'duration' to drive the distance, or 'distance' to drive for the time",
            )
        ]

    def __init__(
        self,
        distance_mm: float | None = None,
        speed_mm_s: float = 150.0,
        duration_s: float | None = None,
    ) -> None:
        if distance_mm is None and duration_s is None:
            by_distance, by_time = type(self).example("distance"), type(self).example("duration")
            raise UnderSpecifiedError(
                "drive needs a distance or a duration",
                yaml=f"{by_distance[0]} or {by_time[0]}",
                python=f"{by_distance[1]} or {by_time[1]}",
            )
        if speed_mm_s <= 0:
            raise ValueError("drive speed must be positive (use a negative distance to reverse)")
        super().__init__()
        self.distance_mm = distance_mm
        self.speed_mm_s = speed_mm_s
        self.duration_s = duration_s
        self._start_s = 0.0
        self._origin = (0.0, 0.0)
        self._hold: HeadingHold | None = None
        self._hold_deg: float | None = None

    def _travelled(self, base: cap.DriveBase) -> float:
        left, right = base.wheel_distances_mm()
        return ((left - self._origin[0]) + (right - self._origin[1])) / 2.0

    def start(self, ctx: ActionContext) -> None:
        base = ctx.drive_base
        self._origin = base.wheel_distances_mm()
        self._start_s = ctx.now_s
        self.watch_stall(ctx, 0.0)
        self._hold_deg = imu_heading_deg(ctx)
        if self._hold_deg is not None:
            self._hold = HeadingHold(ctx.gain("heading", (2.0, 0.0, 0.05)), 30.0)
        direction = -1.0 if (self.distance_mm or 0.0) < 0 else 1.0
        speed = min(self.speed_mm_s, base.max_speed_mm_s) * direction
        base.set_wheel_speeds(speed, speed)

    def _steer(self, ctx: ActionContext, speed: float) -> None:
        base = ctx.drive_base
        turn = 0.0
        heading = imu_heading_deg(ctx)
        if self._hold is not None and self._hold_deg is not None and heading is not None:
            turn = self._hold.update(self._hold_deg, heading, ctx.dt_s)
        base.set_wheel_speeds(*wheel_speeds(speed, turn, base.track_mm))

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        travelled = self._travelled(base)
        if self.distance_mm is None:
            assert self.duration_s is not None
            self.feedback = f"driving {ctx.now_s - self._start_s:.1f}/{self.duration_s:.1f} s"
            if ctx.has_passed(self._start_s, self.duration_s):
                base.stop()
                return Result.done()
            self._steer(ctx, min(self.speed_mm_s, base.max_speed_mm_s))
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
            self._steer(ctx, speed * direction)
        return self.stalled(ctx, travelled)


class Rotate(WheelAction):
    """Turn in place by an angle.

    Turns at the cruise rate, slows to a crawl near the end, stops, and then settles: the
    action is done when the remaining error has stayed within :attr:`TOLERANCE_DEG` for
    :attr:`DWELL_S` (an overshoot is turned back at crawl speed). The angle is measured with
    the IMU when the robot has one, else with the wheel encoders.

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
        Param("turn_rate", "turn_rate_deg_s", "turn_rate", "turning speed", FROM_INIT),
    )
    requires = frozenset({cap.DRIVE_BASE})
    failure = "stalled"
    turn_rates = ("turn_rate",)
    guessed_params = (
        dict.fromkeys(
            ("direction", "left", "right", "clockwise"),
            "a rotate has no direction: a positive angle turns right, a negative one left",
        )
        | dict.fromkeys(("speed", "rate"), "a rotate's speed is its turn_rate")
        | dict.fromkeys(
            ("degrees", "degree", "deg", "amount", "turn"),
            "how far a rotate turns is its angle, with its unit: angle: 90 deg, or angle_deg=90"
            " in Python",
        )
    )

    CRAWL_DEG_S = 20.0
    TOLERANCE_DEG = 1.0
    DWELL_S = 0.15

    def __init__(self, angle_deg: float, turn_rate_deg_s: float = 90.0) -> None:
        if turn_rate_deg_s <= 0:
            raise ValueError("turn rate must be positive (use a negative angle to turn left)")
        super().__init__()
        self.angle_deg = angle_deg
        self.turn_rate_deg_s = turn_rate_deg_s
        self._origin = (0.0, 0.0)
        self._imu_last: float | None = None
        self._imu_turned = 0.0
        self._settle = Settle(self.TOLERANCE_DEG, self.DWELL_S)
        self._settling = False

    def _turned(self, ctx: ActionContext) -> float:
        """Degrees turned since the start, clockwise positive (not wrapped)."""
        heading = imu_heading_deg(ctx)
        if self._imu_last is not None and heading is not None:
            # Accumulate small steps, so turns beyond 180 degrees are counted whole.
            self._imu_turned -= angle_error_deg(self._imu_last, heading)
            self._imu_last = heading
            return self._imu_turned
        base = ctx.drive_base
        left, right = base.wheel_distances_mm()
        return turned_deg(left - self._origin[0], right - self._origin[1], base.track_mm)

    def _set_rate(self, base: cap.DriveBase, rate_deg_s: float) -> None:
        base.set_wheel_speeds(*wheel_speeds(0.0, rate_deg_s, base.track_mm))

    def start(self, ctx: ActionContext) -> None:
        base = ctx.drive_base
        self._origin = base.wheel_distances_mm()
        self._imu_last = imu_heading_deg(ctx)
        self._imu_turned = 0.0
        self._settling = False
        self.watch_stall(ctx, 0.0)

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        turned = self._turned(ctx)
        direction = -1.0 if self.angle_deg < 0 else 1.0
        remaining = abs(self.angle_deg) - turned * direction
        self.feedback = f"turning {abs(turned):.0f}/{abs(self.angle_deg):.0f} deg"
        max_rate = math.degrees(2.0 * base.max_speed_mm_s / base.track_mm)
        cruise = min(self.turn_rate_deg_s, max_rate)
        crawl = min(cruise, self.CRAWL_DEG_S)
        if not self._settling and remaining <= crawl * 0.03:
            self._settling = True  # stop and let the wheels coast, then check the result
            base.stop()
        if self._settling:
            if self._settle.update(remaining, ctx.dt_s):
                base.stop()
                return Result.done()
            if abs(remaining) > self.TOLERANCE_DEG:
                # Off after coasting: creep towards the target, slower the closer it is.
                creep = min(crawl, max(5.0, 4.0 * abs(remaining)))
                self._set_rate(base, math.copysign(creep, remaining) * direction)
            else:
                base.stop()
            return None
        slow_zone = max(6.0, cruise * 0.12)
        self._set_rate(base, (crawl if remaining < slow_zone else cruise) * direction)
        arc_mm = math.radians(turned) * base.track_mm / 2.0
        return self.stalled(ctx, arc_mm)


class Stop(Action):
    """Stop the wheels. Ends ``done`` at once."""

    name = "stop"
    summary = "Stop the wheels."
    requires = frozenset({cap.DRIVE_BASE})

    def update(self, ctx: ActionContext) -> Result | None:
        ctx.drive_base.stop()
        return Result.done()
