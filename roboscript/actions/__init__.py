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
    "ACTION_WORDS",
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

ACTION_WORDS: dict[str, str] = {
    "move": "drive",
    "go": "drive",
    "forward": "drive",
    "forwards": "drive",
    "backward": "drive",
    "backwards": "drive",
    "reverse": "drive",
    "move_forward": "drive",
    "go_forward": "drive",
    "drive_forward": "drive",
    "move_backward": "drive",
    "go_backward": "drive",
    "turn_left": "rotate",
    "turn_right": "rotate",
    "left": "rotate",
    "right": "rotate",
    "rotate_left": "rotate",
    "rotate_right": "rotate",
    "beep": "play_tone",
    "tone": "play_tone",
    "sound": "play_tone",
    "play": "play_tone",
    "buzz": "play_tone",
    "sleep": "wait",
    "pause": "wait",
    "delay": "wait",
    "halt": "stop",
    "brake": "stop",
    "print": "display",
    "show": "display",
    "led": "set_led",
    "loop": "repeat",
}
"""Words a beginner writes for an action (in YAML, or called on ``self`` in a Python
condition), and the built-in action that does it."""
