"""roboscript: behaviour scripting for educational robots.

Missions (state machines in YAML or Python) run on a single-threaded scheduler and talk to
robots through capabilities; protocol drivers speak ASIP, the LEGO SPIKE Prime hub protocol,
StackMod and PLEN2; a byte-exact simulator stands in for every robot.

Importing the package is cheap: heavy parts load when first used.
"""

from __future__ import annotations

import importlib
import logging
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from roboscript.actions import (
        REQUIRED,
        Action,
        ActionContext,
        Display,
        Drive,
        FollowLine,
        FollowWall,
        Motor,
        Outcome,
        Parallel,
        Param,
        PlayTone,
        Repeat,
        Result,
        Rotate,
        Servo,
        SetLed,
        Stop,
        Turn,
        Wait,
        WaitUntil,
        Walk,
    )
    from roboscript.api import RunResult, run
    from roboscript.mission.channels import log
    from roboscript.mission.python_api import Mission, state

__version__ = "0.1.0"
__all__ = [
    "REQUIRED",
    "Action",
    "ActionContext",
    "Display",
    "Drive",
    "FollowLine",
    "FollowWall",
    "Mission",
    "Motor",
    "Outcome",
    "Parallel",
    "Param",
    "PlayTone",
    "Repeat",
    "Result",
    "Rotate",
    "RunResult",
    "Servo",
    "SetLed",
    "Stop",
    "Turn",
    "Wait",
    "WaitUntil",
    "Walk",
    "__version__",
    "log",
    "run",
    "state",
]

logging.getLogger(__name__).addHandler(logging.NullHandler())

# The names a Python mission or behaviour imports (`from roboscript import Mission, Drive`),
# loaded on first use so that `import roboscript` stays cheap.
# `roboscript.run(...)` and its result load the whole run machinery, also only when used.
_LAZY = {
    "Mission": "roboscript.mission.python_api",
    "state": "roboscript.mission.python_api",
    "run": "roboscript.api",
    "log": "roboscript.mission.channels",
    "RunResult": "roboscript.api",
}


def __getattr__(name: str) -> Any:
    module = _LAZY.get(name)
    if module is not None:
        return getattr(importlib.import_module(module), name)
    if name[:1].isupper() or name == "REQUIRED":
        actions = importlib.import_module("roboscript.actions")
        if hasattr(actions, name):
            return getattr(actions, name)
        for cls in actions.ACTIONS.values():  # actions added since __all__ was written
            if cls.__name__ == name:
                return cls
    raise AttributeError(f"module 'roboscript' has no attribute '{name}'")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
