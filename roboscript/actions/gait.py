"""Actions of walking robots: ``walk`` and ``turn``, a number of gait steps at a time.

A humanoid cannot report where its feet are, so both actions end when the gait motion has
finished playing (the walker stops being busy), not at a measured distance or angle. Leaving
the state early asks the robot to stop, and it finishes the step it is in.
"""

from __future__ import annotations

from typing import cast

from roboscript import capabilities as cap
from roboscript.actions.base import Action, ActionContext, Param, Result

__all__ = ["Turn", "Walk"]


class _GaitAction(Action):
    """Start a gait on the walker, then wait until it has finished."""

    requires = frozenset({cap.WALKER})

    def __init__(self, steps: float) -> None:
        if isinstance(steps, bool) or not isinstance(steps, int | float):
            raise type(self).needs(f"{self.name} takes a number of steps, not {steps!r}", "steps")
        if steps != int(steps):
            raise ValueError(f"{self.name} takes whole steps, not {steps:g}")
        if steps == 0:
            raise type(self).needs(f"{self.name} needs at least one step (0 does nothing)", "steps")
        self.steps = int(steps)
        self._walker: cap.Walker | None = None

    def _start_gait(self, walker: cap.Walker) -> None:
        raise NotImplementedError

    def _progress(self) -> str:
        raise NotImplementedError

    def start(self, ctx: ActionContext) -> None:
        walker = ctx.capabilities.get(cap.WALKER)
        if walker is not None:
            self._walker = cast(cap.Walker, walker)
            self._start_gait(self._walker)

    def update(self, ctx: ActionContext) -> Result | None:
        if self._walker is None:
            return Result.failed("not supported")
        if self._walker.busy():
            self.feedback = self._progress()
            return None
        return Result.done()

    def stop(self, ctx: ActionContext) -> None:
        if self._walker is not None and self._walker.busy():
            self._walker.stop()


class Walk(_GaitAction):
    """Walk a number of steps.

    Args:
        steps: How many steps; negative walks backward.

    Outcomes: ``done`` when the robot has taken the steps and stands still; ``failed`` ("not
    supported") on a robot without legs.
    """

    name = "walk"
    summary = "Walk a number of steps (negative = backward) on a walking robot."
    params = (Param("steps", "steps", "count", "how many steps (negative = backward)"),)

    def _start_gait(self, walker: cap.Walker) -> None:
        walker.walk(self.steps)

    def _progress(self) -> str:
        return f"walking {abs(self.steps)} steps {'forward' if self.steps > 0 else 'backward'}"


class Turn(_GaitAction):
    """Turn on the spot by a number of turning steps.

    Args:
        steps: How many steps; positive turns right (clockwise seen from above).

    Outcomes: ``done`` when the robot has taken the steps and stands still; ``failed`` ("not
    supported") on a robot without legs.
    """

    name = "turn"
    summary = "Turn a number of steps (positive = right) on a walking robot."
    params = (Param("steps", "steps", "count", "how many turning steps (positive = right)"),)
    guessed_params = dict.fromkeys(
        ("angle", "angle_deg", "angle_rad", "degrees", "deg", "direction"),
        "turn is a walking robot's turn, by steps; a robot on wheels turns by an angle with rotate",
    )

    def _start_gait(self, walker: cap.Walker) -> None:
        walker.turn(self.steps)

    def _progress(self) -> str:
        return f"turning {abs(self.steps)} steps {'right' if self.steps > 0 else 'left'}"
