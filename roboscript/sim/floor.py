"""What a colour sensor looking down sees: the world's floor colours and its dark tape.

The floor is white unless a world's ``floor`` patch gives a part of it a colour; tape lines are
black and lie on top of every patch. A sensor sees a round spot of the floor (as the IR line
sensors do, :class:`~roboscript.sim.sensors.TapeReader`): across a tape edge its reflection and
RGB change in proportion to the part of the spot on tape, and it names the colour under most of
the spot. Readings carry no noise: they depend on the pose alone.

Reflection is in percent of the light sent out (LEGO's ``color_sensor.reflection``: black
tape about 10, a white floor about 90); RGB values are 0-1023 per channel, as the SPIKE
colour sensor reports them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from roboscript.sim.sensors import TapeReader
from roboscript.sim.world import World

__all__ = ["FLOOR_COLORS", "TAPE_COLOR", "FloorReader", "FloorReading"]

FLOOR_COLORS: Final[dict[str, tuple[float, tuple[int, int, int]]]] = {
    "white": (90.0, (920, 940, 960)),
    "black": (10.0, (60, 60, 70)),
    "red": (55.0, (900, 180, 160)),
    "green": (30.0, (170, 620, 240)),
    "blue": (25.0, (150, 260, 780)),
    "yellow": (80.0, (950, 860, 250)),
    "azure": (55.0, (300, 700, 900)),
    "magenta": (45.0, (800, 200, 650)),
    "orange": (60.0, (960, 480, 150)),
    "purple": (25.0, (400, 180, 600)),
    "turquoise": (45.0, (150, 700, 650)),
}
"""What each colour a floor patch may have (``world.FLOOR_COLOR_NAMES``) reflects:
(reflection %, RGB 0-1023)."""

TAPE_COLOR: Final = "black"
"""The colour of every tape line."""

_FLOOR_COLOR: Final = "white"


@dataclass(frozen=True, slots=True)
class FloorReading:
    """One colour sensor reading.

    Attributes:
        color: The colour under most of the spot (a :data:`FLOOR_COLORS` name).
        reflection_percent: Reflected light, 0 (black) to 100 (white).
        rgb: Red, green and blue, each 0-1023.
    """

    color: str
    reflection_percent: float
    rgb: tuple[int, int, int]


class FloorReader:
    """Reads the floor of ``world`` under a colour sensor's spot.

    Args:
        world: The world (its ``lines`` and ``floor`` patches).
        spot_mm: Diameter of the patch of floor the sensor sees.
    """

    def __init__(self, world: World, spot_mm: float) -> None:
        self._tape = TapeReader(world.lines, spot_mm)
        self._patches = world.floor

    def color_at(self, x_mm: float, y_mm: float) -> str:
        """The floor's colour at a point, tape aside (the last patch listed wins)."""
        for patch in reversed(self._patches):
            if patch.region.contains(x_mm, y_mm):
                return patch.color
        return _FLOOR_COLOR

    def read(self, x_mm: float, y_mm: float) -> FloorReading:
        """What a sensor whose spot is centred at ``(x_mm, y_mm)`` reads."""
        floor = self.color_at(x_mm, y_mm)
        on_tape = self._tape.coverage(x_mm, y_mm)
        floor_reflection, floor_rgb = FLOOR_COLORS[floor]
        tape_reflection, tape_rgb = FLOOR_COLORS[TAPE_COLOR]
        reflection = on_tape * tape_reflection + (1.0 - on_tape) * floor_reflection
        rgb = tuple(
            round(on_tape * tape + (1.0 - on_tape) * bare)
            for tape, bare in zip(tape_rgb, floor_rgb, strict=True)
        )
        color = TAPE_COLOR if on_tape >= 0.5 else floor
        return FloorReading(color, reflection, (rgb[0], rgb[1], rgb[2]))
