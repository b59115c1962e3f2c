"""What the guard names ``color.*`` and ``buttons.*`` read (see :mod:`roboscript.mission.guards`).

Kept apart from the runner, which only routes the two roots here.
"""

from __future__ import annotations

import math
from typing import cast

from roboscript import capabilities as cap
from roboscript.actions.base import ActionContext
from roboscript.mission.guards import RGB_NAMES

__all__ = ["color_or_buttons"]


def color_or_buttons(ctx: ActionContext, root: str, attr: str | None) -> float | bool:
    """The value of ``color.ATTR`` or ``buttons.ATTR`` now.

    ``color.reflection`` is a percentage, not-a-number before the first reading (so every
    comparison with it is false); ``color.NAME`` is True while the sensor names that colour;
    ``color.rgb_red`` (``_green``, ``_blue``) is the raw channel, 0 before a reading.
    ``buttons.left`` / ``right`` / ``any`` are True while held.

    Raises:
        KeyError: Another root.
    """
    if root == "buttons":
        pressed = cast(cap.HubButtons, ctx.get(cap.BUTTONS)).pressed()
        return bool(pressed) if attr == "any" else attr in pressed
    if root != "color":
        raise KeyError(root)
    sensor = cast(cap.ColorSensor, ctx.get(cap.COLOR))
    if attr == "reflection":
        reflection = sensor.reflection_percent()
        return math.nan if reflection is None else float(reflection)
    if attr in RGB_NAMES:
        rgb = sensor.rgb()
        return 0.0 if rgb is None else float(rgb[RGB_NAMES.index(attr)])
    return sensor.color_name() == attr
