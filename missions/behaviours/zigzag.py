"""A behaviour written by a student: drive forward in a zig-zag by steering the wheels.

Use it by name from a YAML mission (see missions/zigzag.yaml):

    behaviours: [behaviours/zigzag.py]
    states:
      weave:
        do: {zigzag: {leg: 20 cm, legs: 4, speed: 15 cm/s}}

or import it in a Python mission: ``from behaviours.zigzag import ZigZag``.
"""

from __future__ import annotations

from roboscript import Action, ActionContext, Param, Result


class ZigZag(Action):
    """Drive forward in legs that curve right and left in turn.

    During a leg one wheel turns faster than the other, so the robot swings to one side;
    the next leg swings back. A leg ends after ``leg_mm`` of travel (the average of both
    wheels), measured with the wheel encoders.

    Outcomes: ``done`` after the last leg; ``failed`` ("stalled") if the wheels stop
    turning for a second, for example against a wall.
    """

    name = "zigzag"
    summary = "Drive forward in a zig-zag."
    params = (
        Param("leg", "leg_mm", "distance", "travel per leg", 200.0),
        Param("legs", "legs", "count", "how many legs", 4),
        Param("speed", "speed_mm_s", "speed", "average wheel speed", 150.0),
        Param("swerve", "swerve_pct", "percent", "how much faster the outer wheel turns", 30.0),
    )
    requires = frozenset({"drive_base"})

    STALL_S = 1.0  # this long without progress counts as stalled

    def __init__(
        self,
        leg_mm: float = 200.0,
        legs: int = 4,
        speed_mm_s: float = 150.0,
        swerve_pct: float = 30.0,
    ) -> None:
        # A ValueError here is reported when the mission is checked, before the robot moves.
        if leg_mm <= 0:
            raise ValueError("a zigzag leg must be longer than 0 mm")
        if legs < 1:
            raise ValueError("a zigzag needs at least 1 leg")
        if speed_mm_s <= 0:
            raise ValueError("zigzag speed must be positive")
        if not 0 <= swerve_pct < 200:
            raise ValueError("zigzag swerve must be from 0 % to under 200 %")
        self.leg_mm = leg_mm
        self.legs = legs
        self.speed_mm_s = speed_mm_s
        self.swerve_pct = swerve_pct
        self._leg = 0  # the leg being driven, from 0
        self._leg_start_mm = 0.0
        self._progress_mm = 0.0
        self._progress_s = 0.0

    def _travelled_mm(self, ctx: ActionContext) -> float:
        left_mm, right_mm = ctx.drive_base.wheel_distances_mm()
        return (left_mm + right_mm) / 2.0

    def _steer(self, ctx: ActionContext) -> None:
        """Set the wheel speeds for the current leg: even legs swing right, odd legs left."""
        fast = self.speed_mm_s * (1.0 + self.swerve_pct / 200.0)
        slow = self.speed_mm_s * (1.0 - self.swerve_pct / 200.0)
        if self._leg % 2 == 0:
            ctx.drive_base.set_wheel_speeds(fast, slow)  # left wheel faster: curve right
        else:
            ctx.drive_base.set_wheel_speeds(slow, fast)

    def start(self, ctx: ActionContext) -> None:
        self._leg = 0
        self._leg_start_mm = self._travelled_mm(ctx)
        self._progress_mm = self._leg_start_mm
        self._progress_s = ctx.now_s
        self._steer(ctx)

    def update(self, ctx: ActionContext) -> Result | None:
        travelled_mm = self._travelled_mm(ctx)
        leg_done_mm = travelled_mm - self._leg_start_mm
        self.feedback = f"leg {self._leg + 1}/{self.legs}: {leg_done_mm:.0f}/{self.leg_mm:.0f} mm"
        # Stalled: no progress for STALL_S. Robots without encoders compute their distances
        # from time, so they cannot tell; they skip this check.
        if abs(travelled_mm - self._progress_mm) >= 2.0:
            self._progress_mm, self._progress_s = travelled_mm, ctx.now_s
        elif (
            ctx.now_s - self._progress_s >= self.STALL_S
            and not ctx.drive_base.odometry_is_estimated
        ):
            ctx.drive_base.stop()
            return Result.failed("stalled")
        if leg_done_mm < self.leg_mm:
            return None  # still on this leg: update() never waits, it is called again
        self._leg += 1
        if self._leg >= self.legs:
            ctx.drive_base.stop()
            return Result.done()
        self._leg_start_mm += self.leg_mm
        self._steer(ctx)
        return None

    def stop(self, ctx: ActionContext) -> None:
        ctx.drive_base.stop()
