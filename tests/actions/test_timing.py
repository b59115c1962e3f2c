"""Timed actions: every one ends on the tick a student expects."""

from __future__ import annotations

import pytest

from roboscript.actions import Action, ActionContext, Drive, PlayTone, Wait
from roboscript.robot import Robot


def _ticks_until_done(action: Action, period_s: float) -> int:
    """Ticks after the action's start until it reports a result, on a clock that adds up
    periods from 0 as the scheduler's does."""
    with Robot.connect("mirto", period_s=period_s) as bot:
        ctx = ActionContext(bot.capabilities, gains=bot.profile.gains)
        ctx.now_s, ctx.dt_s = 0.0, period_s
        action.start(ctx)
        for ticks in range(1, 100):
            bot.run_for(period_s)  # the wheels turn as they would between ticks
            ctx.now_s += period_s
            result = action.update(ctx)
            if result is not None:
                action.stop(ctx)
                assert result.outcome == "done", result
                return ticks
    raise AssertionError("the action never ended")


@pytest.mark.parametrize(
    "action",
    [
        Wait(duration_s=1.1),
        Drive(duration_s=1.1, speed_mm_s=100),
        PlayTone(frequency_hz=440, duration_s=1.1),
    ],
    ids=["wait", "drive", "play_tone"],
)
def test_a_1_1_s_action_at_10_hz_ends_after_11_ticks(action: Action) -> None:
    # 11 sums of 0.1 read 1.0999999999999999 s: a strict comparison would need a 12th tick.
    assert _ticks_until_done(action, 0.1) == 11
