"""Built-in actions and their registry.

:data:`ACTIONS` maps the word a mission uses (``drive``) to its :class:`Action` class.
"""

from __future__ import annotations

from roboscript.actions.base import REQUIRED, Action, ActionContext, Outcome, Param, Result
from roboscript.actions.composite import Parallel, Repeat
from roboscript.actions.following import FollowLine, FollowWall
from roboscript.actions.gait import Turn, Walk
from roboscript.actions.motion import Drive, Rotate, Stop
from roboscript.actions.motors import Motor
from roboscript.actions.output import Display, Servo, SetLed
from roboscript.actions.timing import PlayTone, Wait, WaitUntil

__all__ = [
    "ACTIONS",
    "REQUIRED",
    "Action",
    "ActionContext",
    "Display",
    "Drive",
    "FollowLine",
    "FollowWall",
    "Motor",
    "Outcome",
    "Parallel",
    "Param",
    "PlayTone",
    "Repeat",
    "Result",
    "Rotate",
    "Servo",
    "SetLed",
    "Stop",
    "Turn",
    "Wait",
    "WaitUntil",
    "Walk",
]

ACTIONS: dict[str, type[Action]] = {
    cls.name: cls
    for cls in (
        Drive,
        Rotate,
        Stop,
        FollowWall,
        FollowLine,
        PlayTone,
        Wait,
        WaitUntil,
        Display,
        SetLed,
        Servo,
        Walk,
        Turn,
        Motor,
    )
}
"""Built-in actions by name."""
