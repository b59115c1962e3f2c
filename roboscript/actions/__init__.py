"""Built-in actions and their registry.

:data:`ACTIONS` maps the word a mission uses (``drive``) to its :class:`Action` class.
"""

from __future__ import annotations

from roboscript.actions.base import REQUIRED, Action, ActionContext, Outcome, Param, Result
from roboscript.actions.motion import Drive, Rotate, Stop
from roboscript.actions.timing import PlayTone, Wait

__all__ = [
    "ACTIONS",
    "REQUIRED",
    "Action",
    "ActionContext",
    "Drive",
    "Outcome",
    "Param",
    "PlayTone",
    "Result",
    "Rotate",
    "Stop",
    "Wait",
]

ACTIONS: dict[str, type[Action]] = {cls.name: cls for cls in (Drive, Rotate, PlayTone, Wait, Stop)}
"""Built-in actions by name."""
