"""``no_collisions``: the robot's body never touches a wall."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import at, cm, plural
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark
from roboscript.sim.geometry import segment_distance

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["NoCollisions"]


@dataclass(frozen=True)
class NoCollisions(Rule):
    """``no_collisions: true``: no collision with a wall after the start."""

    kind = "no_collisions"

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        if value is not True:
            raise reader.fail(
                f"write 'no_collisions: true' (got {value!r}); leave it out to allow collisions",
                mark,
            )
        return cls()

    def judge(self, record: RunRecord) -> Verdict:
        if record.collisions:
            count = len(record.collisions)
            hit = record.collisions[0]
            return Verdict(
                "no_collisions",
                False,
                f"failed by {plural(count, 'collision')}",
                hit.t_s,
                f"{plural(count, 'collision')}; the first at {at(hit.t_s)} on the {hit.side}"
                f" bumper, at ({hit.x_mm:.0f}, {hit.y_mm:.0f}) mm",
                -float(count),
                "collisions",
            )
        walls = record.world.walls if record.world is not None else ()
        if not walls or not record.path:
            return Verdict("no_collisions", True, "", None, "no collisions")
        clearance = min(
            min(segment_distance(x, y, wall) for wall in walls) - record.body_radius_mm
            for _, x, y, _ in record.path
        )
        return Verdict(
            "no_collisions",
            True,
            f"passed by {cm(clearance)}",
            None,
            f"no collisions; the closest the body came to a wall was {cm(clearance)}",
            clearance,
            "mm",
        )
