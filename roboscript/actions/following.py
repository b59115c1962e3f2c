"""Closed-loop following: ``follow_wall`` and ``follow_line``.

Both steer on the host with simple-pid (see :mod:`roboscript.control`), with gains from the
robot profile (``wall``, ``line``) and defaults that work on the simulator. Both run until
their ``until`` condition holds or their ``duration`` is up; they fail when they lose what
they follow.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

from roboscript import capabilities as cap
from roboscript.actions.base import FROM_INIT, ActionContext, Param, Result
from roboscript.actions.sensing import heading_deg
from roboscript.actions.wheels import WheelAction
from roboscript.control import LineFollower, WallFollower, wheel_speeds

__all__ = ["FollowLine", "FollowWall"]

_LOST_WALL_S = 1.0
_LOST_LINE_S = 0.5


def _finished(ctx: ActionContext, until: Any, start_s: float, duration_s: float | None) -> bool:
    """True once the ``until`` condition holds or ``duration_s`` has passed since ``start_s``."""
    if ctx.holds(until):
        return True
    return duration_s is not None and ctx.has_passed(start_s, duration_s)


def _travelled(base: cap.DriveBase) -> float:
    left, right = base.wheel_distances_mm()
    return (left + right) / 2.0


class FollowWall(WheelAction):
    """Drive along a wall, keeping a side distance to it.

    Args:
        side: ``"left"`` or ``"right"``: where the wall is.
        distance_mm: Gap to keep between the side sensor and the wall, mm.
        speed_mm_s: Forward speed, mm/s.
        until: A condition that ends the action ``done`` when it holds.
        duration_s: End ``done`` after this long instead.

    Outcomes: ``done`` (until / duration); ``failed`` ("lost wall") after a second without
    a wall reading, ``failed`` ("not supported") if the side sensor faces the other way,
    ``failed`` ("stalled").
    """

    name = "follow_wall"
    summary = "Drive along a wall at a set distance."
    params = (
        Param("side", "side", "choice", "where the wall is", FROM_INIT, ("left", "right")),
        Param(
            "distance", "distance_mm", "distance", "gap to keep to the wall", FROM_INIT, (), "20 cm"
        ),
        Param("speed", "speed_mm_s", "speed", "forward speed", FROM_INIT, (), "12 cm/s"),
        Param("until", "until", "guard", "stop when this condition holds", FROM_INIT),
        Param("duration", "duration_s", "time", "stop after this long", FROM_INIT, (), "10 s"),
    )
    requires = frozenset({cap.DRIVE_BASE, cap.SIDE_RANGE})
    bounded_by = ("until", "duration")
    failure = "lost wall or stalled"
    drive_speeds = ("speed",)

    def __init__(
        self,
        side: str = "right",
        distance_mm: float = 200.0,
        speed_mm_s: float = 120.0,
        until: Any = None,
        duration_s: float | None = None,
    ) -> None:
        if side not in ("left", "right"):
            raise ValueError("side must be 'left' or 'right'")
        if distance_mm <= 0:
            raise type(self).needs("follow_wall needs a positive distance to keep", "distance")
        if speed_mm_s <= 0:
            raise type(self).needs("follow_wall needs a positive speed", "speed")
        super().__init__()
        self.side = side
        self.distance_mm = distance_mm
        self.speed_mm_s = speed_mm_s
        self.until = until
        self.duration_s = duration_s
        self._start_s = 0.0
        self._last_seen_s = 0.0
        self._loop: WallFollower | None = None

    def start(self, ctx: ActionContext) -> None:
        self._start_s = self._last_seen_s = ctx.now_s
        self._loop = WallFollower(
            ctx.gain("wall", (0.15, 0.0, 0.02)), self.distance_mm, self.side, max_rate_deg_s=60.0
        )
        self.watch_stall(ctx, _travelled(ctx.drive_base))

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        sensor: cap.SideRangeSensor = ctx.get(cap.SIDE_RANGE)
        if sensor.side != self.side:
            base.stop()
            return Result.failed(f"not supported: this robot's side sensor faces {sensor.side}")
        if _finished(ctx, self.until, self._start_s, self.duration_s):
            base.stop()
            return Result.done()
        gap = sensor.distance_mm()
        if gap is None:
            if ctx.now_s - self._last_seen_s >= _LOST_WALL_S:
                base.stop()
                return Result.failed("lost wall")
        else:
            self._last_seen_s = ctx.now_s
            self.feedback = f"wall at {gap / 10:.0f} cm"
        assert self._loop is not None
        turn = self._loop.update(gap, heading_deg(ctx), ctx.dt_s)
        base.set_wheel_speeds(*wheel_speeds(self.speed_mm_s, turn, base.track_mm))
        return self.stalled(ctx, _travelled(base))


class FollowLine(WheelAction):
    """Drive along a dark line on the floor.

    Args:
        speed_mm_s: Forward speed on a straight line, mm/s (slower in bends).
        edge: ``"center"`` keeps the line under the middle sensor; ``"left"`` or ``"right"``
            follows that edge of the line.
        until: A condition that ends the action ``done`` when it holds.
        duration_s: End ``done`` after this long instead.

    With one sensor (a SPIKE colour sensor looking down) there is no middle to keep: the
    robot follows an edge of the line by reflection, steering so the sensor sees half line,
    half floor (``edge: right`` follows the right edge; ``center`` and ``left`` the left one).

    Outcomes: ``done`` (until / duration); ``failed`` ("lost line") after half a second with
    no sensor over the line (one sensor: seeing bare floor only); ``failed`` ("stalled").
    """

    name = "follow_line"
    summary = "Drive along a dark line on the floor."
    params = (
        Param(
            "speed", "speed_mm_s", "speed", "forward speed on straights", FROM_INIT, (), "10 cm/s"
        ),
        Param(
            "edge",
            "edge",
            "choice",
            "which part of the line to follow",
            FROM_INIT,
            ("center", "left", "right"),
        ),
        Param("until", "until", "guard", "stop when this condition holds", FROM_INIT),
        Param("duration", "duration_s", "time", "stop after this long", FROM_INIT, (), "10 s"),
    )
    requires = frozenset({cap.DRIVE_BASE, cap.LINE})
    bounded_by = ("until", "duration")
    failure = "lost line or stalled"
    drive_speeds = ("speed",)

    _EDGE_TARGET: ClassVar[dict[str, float]] = {"center": 0.0, "left": 0.35, "right": -0.35}

    def __init__(
        self,
        speed_mm_s: float = 100.0,
        edge: str = "center",
        until: Any = None,
        duration_s: float | None = None,
    ) -> None:
        if edge not in self._EDGE_TARGET:
            raise ValueError("edge must be 'center', 'left' or 'right'")
        if speed_mm_s <= 0:
            raise type(self).needs("follow_line needs a positive speed", "speed")
        super().__init__()
        self.speed_mm_s = speed_mm_s
        self.edge = edge
        self.until = until
        self.duration_s = duration_s
        self._start_s = 0.0
        self._last_seen_s = 0.0
        self._last_position = 0.0
        self._loop: LineFollower | None = None

    def start(self, ctx: ActionContext) -> None:
        self._start_s = self._last_seen_s = ctx.now_s
        self._loop = LineFollower(ctx.gain("line", (150.0, 0.0, 8.0)), max_rate_deg_s=150.0)
        self.watch_stall(ctx, _travelled(ctx.drive_base))

    def update(self, ctx: ActionContext) -> Result | None:
        base = ctx.drive_base
        sensors: cap.LineSensors = ctx.get(cap.LINE)
        if _finished(ctx, self.until, self._start_s, self.duration_s):
            base.stop()
            return Result.done()
        readings = sensors.values()
        target = self._EDGE_TARGET[self.edge]
        if readings is not None and len(readings) == 1:
            position = _edge_position(readings[0], sensors.dark_threshold, self.edge)
            target = 0.0
        else:
            position = (
                None
                if readings is None
                else LineFollower.position(readings, sensors.dark_threshold)
            )
        assert self._loop is not None
        if position is None:
            if ctx.now_s - self._last_seen_s >= _LOST_LINE_S:
                base.stop()
                return Result.failed("lost line")
            # Keep turning towards where the line was last seen.
            turn = math.copysign(60.0, self._last_position) if self._last_position else 0.0
            speed = self.speed_mm_s * 0.3
        else:
            self._last_seen_s = ctx.now_s
            self._last_position = position
            turn = self._loop.update(position, target, ctx.dt_s)
            speed = self.speed_mm_s * (1.0 - 0.6 * min(1.0, abs(position)))
            self.feedback = f"line at {position:+.2f}"
        base.set_wheel_speeds(*wheel_speeds(speed, turn, base.track_mm))
        return self.stalled(ctx, _travelled(base))


def _edge_position(reading: float, threshold: float, edge: str) -> float | None:
    """Where one sensor is across a line's edge, -1 to 1 (0: on the edge), or ``None`` when it
    sees bare floor only.

    The sign is the one :meth:`LineFollower.position` gives the line: following the left edge,
    a darker reading means the sensor has moved onto the line, so the line lies to the left of
    where it should be (negative) and the robot turns left.
    """
    if threshold <= 0 or reading < threshold / 4.0:
        return None
    offset = max(-1.0, min(1.0, (threshold - reading) / threshold))
    return -offset if edge == "right" else offset
