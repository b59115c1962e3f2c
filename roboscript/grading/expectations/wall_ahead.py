"""``wall_ahead_at_end``: the gap from the robot's front to the wall straight ahead at the end."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import by, cm
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark
from roboscript.sim.geometry import heading_vector, ray_cast

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["DEFAULT_WALL_AHEAD_TOLERANCE_MM", "WallAhead"]

DEFAULT_WALL_AHEAD_TOLERANCE_MM = 30.0


@dataclass(frozen=True)
class WallAhead(Rule):
    """``wall_ahead_at_end``: the gap from the body's front edge to the wall straight ahead,
    ``distance_mm`` within ``tolerance_mm``."""

    kind = "wall_ahead_at_end"

    distance_mm: float
    tolerance_mm: float = DEFAULT_WALL_AHEAD_TOLERANCE_MM

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        data = reader.mapping(value, "wall_ahead_at_end", mark)
        reader.allowed(data, ("distance", "tolerance"), "wall_ahead_at_end", required=("distance",))
        distance = reader.quantity(data, "distance", "distance", "mm")
        if distance < 0:
            raise reader.fail("'distance' cannot be negative", data.value_mark("distance"))
        for world in ctx.worlds:
            if not world.walls:
                raise reader.fail(
                    f"the world '{world.name}' has no walls, so there is never a wall ahead",
                    mark,
                )
        return cls(
            distance_mm=distance,
            tolerance_mm=(
                reader.positive(data, "tolerance", "distance", "mm")
                if "tolerance" in data
                else DEFAULT_WALL_AHEAD_TOLERANCE_MM
            ),
        )

    def judge(self, record: RunRecord) -> Verdict:
        x, y, heading = record.final_pose
        walls = list(record.world.walls) if record.world is not None else []
        dx, dy = heading_vector(heading)
        hit = ray_cast(x, y, dx, dy, walls, math.inf)
        wanted = f"wanted {cm(self.distance_mm)} ± {cm(self.tolerance_mm)}"
        if hit is None:
            return Verdict(
                "wall_ahead_at_end",
                False,
                "",
                record.duration_s,
                f"no wall straight ahead when the robot stopped (facing {heading:.0f}°); {wanted}",
            )
        # Measured as with a ruler: from the front edge of the round body, straight ahead.
        gap = hit - record.body_radius_mm
        error = gap - self.distance_mm
        margin = self.tolerance_mm - abs(error)
        how = "" if margin >= 0 else (" (too close)" if error < 0 else " (too far)")
        return Verdict(
            "wall_ahead_at_end",
            margin >= 0,
            by(margin, cm(margin)),
            None if margin >= 0 else record.duration_s,
            f"stopped {gap / 10.0:.1f} cm from the wall ahead{how}, measured from the front of the"
            f" robot straight ahead; {wanted}",
            margin,
            "mm",
            margin / self.tolerance_mm,
        )
