"""Nested states: a state whose action is a whole state machine.

The inner machine runs on its own :class:`~roboscript.mission.runner.MissionRunner`, ticked by
the outer state's action; it ends ``done`` when the inner machine reaches a success state and
``failed`` (with the inner reason) when it reaches a failure state. Inner states appear in the
outer mission's timeline as ``outer.inner``.
"""

from __future__ import annotations

from typing import Any

from roboscript.actions.base import Action, ActionContext, Result
from roboscript.mission.cause import TransitionCause
from roboscript.mission.spec import MissionSpec

__all__ = ["SubMission"]


class SubMission(Action):
    """Run an inner state machine as one action.

    Args:
        spec: The inner machine (an inline ``states:`` block or another mission file).
        label: The outer state's name, the prefix of inner states in the timeline.
    """

    name = "states"
    summary = "Run an inner state machine."

    def __init__(self, spec: MissionSpec, label: str) -> None:
        self.spec = spec
        self.label = label
        self._runner: Any = None

    def start(self, ctx: ActionContext) -> None:
        # transitions loads when a mission runs, never when one is only checked
        from roboscript.mission.runner import MissionRunner

        outer = ctx.env

        def record(time_s: float, state: str, cause: TransitionCause) -> None:
            if outer is not None:
                outer.record_inner_state(f"{self.label}.{state}", cause)

        self._runner = MissionRunner(
            self.spec,
            ctx.capabilities,
            robot_name=ctx.robot_name,
            gains=ctx.gains,
            on_state=record,
            outer=outer,  # pose, distance and regions are the whole mission's
        )

    def update(self, ctx: ActionContext) -> Result | None:
        runner = self._runner
        runner.tick(ctx.now_s, ctx.dt_s)
        self.feedback = f"{self.label}.{runner.state}"
        if not runner.finished:
            return None
        if runner.result.outcome == "success":
            return Result.done()
        return Result.failed(runner.result.reason or f"{self.label} failed")

    def stop(self, ctx: ActionContext) -> None:
        runner = self._runner
        if runner is not None and not runner.finished:
            runner.finish("failure", "interrupted")
        self._runner = None
