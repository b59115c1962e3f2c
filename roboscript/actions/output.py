"""Actions that show or move something: ``display``, ``set_led`` and ``servo``."""

from __future__ import annotations

from collections.abc import Sequence

from roboscript import capabilities as cap
from roboscript.actions.base import FROM_INIT, Action, ActionContext, Param, Result

__all__ = ["COLORS", "Display", "Servo", "SetLed"]

COLORS: dict[str, tuple[int, int, int]] = {
    "off": (0, 0, 0),
    "black": (0, 0, 0),
    "white": (255, 255, 255),
    "red": (255, 0, 0),
    "green": (0, 255, 0),
    "blue": (0, 0, 255),
    "yellow": (255, 200, 0),
    "orange": (255, 100, 0),
    "purple": (150, 0, 200),
    "cyan": (0, 200, 255),
    "pink": (255, 80, 150),
}
"""Colour names ``set_led`` understands (also ``#RRGGBB`` and ``[r, g, b]``)."""


def parse_color(value: object) -> tuple[int, int, int]:
    """Read a colour name, ``#RRGGBB`` or ``[r, g, b]`` (0-255 each).

    Raises:
        ValueError: With the accepted forms.
    """
    if isinstance(value, str):
        text = value.strip().lower()
        if text in COLORS:
            return COLORS[text]
        if text.startswith("#") and len(text) == 7:
            try:
                return int(text[1:3], 16), int(text[3:5], 16), int(text[5:7], 16)
            except ValueError:
                pass
    elif (
        isinstance(value, list | tuple)
        and len(value) == 3
        and all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 255 for v in value)
    ):
        return int(value[0]), int(value[1]), int(value[2])
    names = ", ".join(COLORS)
    raise ValueError(f"expected a colour ({names}, '#RRGGBB' or [r, g, b]), got {value!r}")


class Display(Action):
    """Show text on the robot's display (LCD or light matrix).

    Args:
        text: What to show (cut or scrolled to fit).

    Outcome: ``done`` at once.
    """

    name = "display"
    summary = "Show text on the display."
    params = (Param("text", "text", "text", "what to show"),)
    requires = frozenset({cap.DISPLAY})

    def __init__(self, text: str) -> None:
        if text is None or isinstance(text, list | tuple | dict | set):
            # str() would show "None" or "['a']" on the robot's screen
            raise ValueError(f'display text: expected text such as "hello", got {text!r}')
        self.text = str(text)

    def update(self, ctx: ActionContext) -> Result | None:
        display: cap.Display = ctx.get(cap.DISPLAY)
        display.show_text(self.text)
        return Result.done()


class SetLed(Action):
    """Set one RGB LED's colour.

    Args:
        index: Which LED, from 0.
        color: A colour name, ``"#RRGGBB"`` or ``(r, g, b)``, each 0-255.

    Outcomes: ``done`` at once; ``failed`` ("not supported") if the robot has fewer LEDs.
    """

    name = "set_led"
    summary = "Set an LED's colour."
    params = (
        Param("index", "index", "count", "which LED, from 0", FROM_INIT),
        Param("color", "color", "color", "a colour name, '#RRGGBB' or [r, g, b]"),
    )
    requires = frozenset({cap.LEDS})

    def __init__(self, color: str | tuple[int, int, int] | list[int], index: int = 0) -> None:
        if index < 0:
            raise ValueError("LED index must not be negative")
        self.index = int(index)
        # a list, a tuple or any other sequence of three numbers; None or a number is refused
        # by parse_color with the forms a colour takes
        given = list(color) if isinstance(color, Sequence) and not isinstance(color, str) else color
        try:
            self.color = parse_color(given)
        except ValueError as exc:
            raise ValueError(f"set_led color: {exc}") from None

    def update(self, ctx: ActionContext) -> Result | None:
        leds: cap.Leds = ctx.get(cap.LEDS)
        if self.index >= leds.count:
            return Result.failed(f"not supported: the robot has {leds.count} LEDs")
        leds.set_color(self.index, self.color)
        return Result.done()


class Servo(Action):
    """Move a hobby servo and give it time to get there.

    Args:
        index: Which servo, from 0.
        angle_deg: Target angle, 0-180 degrees.
        duration_s: Time allowed for the move before ``done``, seconds.

    Outcomes: ``done`` after ``duration_s``; ``failed`` ("not supported") if the robot has
    fewer servos.
    """

    name = "servo"
    summary = "Move a servo to an angle."
    params = (
        Param("index", "index", "count", "which servo, from 0", FROM_INIT),
        Param("angle", "angle_deg", "angle", "target angle, 0-180 deg"),
        Param("duration", "duration_s", "time", "time allowed for the move", FROM_INIT),
    )
    requires = frozenset({cap.SERVOS})

    def __init__(self, angle_deg: float, index: int = 0, duration_s: float = 0.5) -> None:
        if not 0 <= angle_deg <= 180:
            raise ValueError("a servo angle is between 0 and 180 degrees")
        if index < 0 or duration_s < 0:
            raise ValueError("servo index and duration must not be negative")
        self.index = int(index)
        self.angle_deg = angle_deg
        self.duration_s = duration_s
        self._start_s = 0.0

    def start(self, ctx: ActionContext) -> None:
        self._start_s = ctx.now_s
        servos: cap.Servos = ctx.get(cap.SERVOS)
        if self.index < servos.count:
            servos.set_angle(self.index, self.angle_deg)

    def update(self, ctx: ActionContext) -> Result | None:
        servos: cap.Servos = ctx.get(cap.SERVOS)
        if self.index >= servos.count:
            return Result.failed(f"not supported: the robot has {servos.count} servos")
        return Result.done() if ctx.has_passed(self._start_s, self.duration_s) else None
