"""What every wheel action shares: the stall check and stopping the wheels when left."""

from __future__ import annotations

from roboscript.actions.base import Action, ActionContext, Result
from roboscript.control import Stall

__all__ = ["WheelAction"]


class WheelAction(Action):
    """Base of the actions that power the wheels (``drive``, ``rotate``, ``follow_wall``,
    ``follow_line``).

    Their common rules live here once: leaving the state stops the wheels, and wheels that
    make no progress for a second (:class:`~roboscript.control.Stall`) end the action
    ``failed`` ("stalled") with the wheels stopped. Robots whose odometry is estimated
    (no encoders) cannot see a stall, so they never fail this way.
    """

    def __init__(self) -> None:
        self._stall = Stall()

    def watch_stall(self, ctx: ActionContext, progress_mm: float) -> None:
        """Start the stall watch from ``progress_mm`` of wheel travel, now."""
        self._stall.reset(ctx.now_s, progress_mm)

    def stalled(self, ctx: ActionContext, progress_mm: float) -> Result | None:
        """Feed this tick's wheel travel; the ``failed("stalled")`` result if the wheels are
        stuck (they have just been stopped), else ``None``."""
        base = ctx.drive_base
        if not base.odometry_is_estimated and self._stall.update(ctx.now_s, progress_mm):
            base.stop()
            return Result.failed("stalled")
        return None

    def stop(self, ctx: ActionContext) -> None:
        """Stop the wheels, however the state is left."""
        ctx.drive_base.stop()
