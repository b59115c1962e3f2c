"""``final_pose_within``: where the robot must end, and optionally facing which way."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from roboscript.angles import wrap_deg
from roboscript.grading.expectations.base import Canvas, Rule, SpecContext
from roboscript.grading.expectations.words import by, cm, deg
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["DEFAULT_HEADING_TOLERANCE_DEG", "FinalPose", "final_pose_target"]

DEFAULT_HEADING_TOLERANCE_DEG = 15.0


@dataclass(frozen=True)
class FinalPose(Rule):
    """``final_pose_within``: a circle to end in (``x_mm``, ``y_mm``, ``radius_mm``) and
    optionally a heading (degrees clockwise from north) within ``heading_tolerance_deg``;
    ``relative_to: start`` reads the target in the start pose's frame (x right, y ahead)."""

    kind = "final_pose_within"

    x_mm: float
    y_mm: float
    radius_mm: float
    heading_deg: float | None = None
    heading_tolerance_deg: float = DEFAULT_HEADING_TOLERANCE_DEG
    relative_to: str = "world"

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        data = reader.mapping(value, "final_pose_within", mark)
        reader.allowed(
            data,
            ("x", "y", "radius", "heading", "heading_tolerance", "relative_to"),
            "final_pose_within",
            required=("x", "y", "radius"),
        )
        heading = None
        tolerance = DEFAULT_HEADING_TOLERANCE_DEG
        if "heading" in data:
            heading = reader.quantity(data, "heading", "angle", "deg")
        if "heading_tolerance" in data:
            if heading is None:
                raise reader.fail(
                    "heading_tolerance needs a heading to compare with",
                    data.key_mark("heading_tolerance"),
                )
            tolerance = reader.positive(data, "heading_tolerance", "angle", "deg")
            if tolerance >= 180.0:
                raise reader.fail(
                    f"a heading_tolerance of {tolerance:g}° lets the robot end facing any way:"
                    " give one under 180°, or leave heading out",
                    data.value_mark("heading_tolerance"),
                )
        return cls(
            x_mm=reader.quantity(data, "x", "distance", "mm"),
            y_mm=reader.quantity(data, "y", "distance", "mm"),
            radius_mm=reader.positive(data, "radius", "distance", "mm"),
            heading_deg=heading,
            heading_tolerance_deg=tolerance,
            relative_to=(
                reader.choice(data, "relative_to", ("world", "start"))
                if "relative_to" in data
                else "world"
            ),
        )

    def in_world(self, record: RunRecord) -> FinalPose:
        """The target in world coordinates (a ``relative_to: start`` target moved to the
        start of ``record``)."""
        return self.at_start(record.start_pose)

    def at_start(self, start: tuple[float, float, float]) -> FinalPose:
        """The target in world coordinates for a run that starts at ``start`` (``x_mm``,
        ``y_mm``, ``heading_deg``): a ``relative_to: start`` target moved there."""
        if self.relative_to != "start":
            return self
        # The target is in the robot's start frame: x to its right, y ahead, heading from its own.
        sx, sy, sh = start
        rad = math.radians(sh)
        return replace(
            self,
            x_mm=sx + self.x_mm * math.cos(rad) + self.y_mm * math.sin(rad),
            y_mm=sy - self.x_mm * math.sin(rad) + self.y_mm * math.cos(rad),
            heading_deg=None if self.heading_deg is None else self.heading_deg + sh,
            relative_to="world",
        )

    def judge(self, record: RunRecord) -> Verdict:
        x, y, heading = record.final_pose
        target = self.in_world(record)
        off_mm = math.hypot(x - target.x_mm, y - target.y_mm)
        margin_mm = target.radius_mm - off_mm
        detail = (
            f"ended at ({x:.0f}, {y:.0f}) mm, {cm(off_mm)} from the target"
            f" ({target.x_mm:.0f}, {target.y_mm:.0f}) mm (allowed {cm(target.radius_mm)})"
        )
        relative = margin_mm / target.radius_mm
        text, value, unit = by(margin_mm, cm(margin_mm)), margin_mm, "mm"
        passed = margin_mm >= 0
        if target.heading_deg is not None:
            error = wrap_deg(heading - target.heading_deg)
            margin_deg = target.heading_tolerance_deg - abs(error)
            detail += (
                f"; heading {heading:.0f}°, {deg(error)} off"
                f" (allowed {deg(target.heading_tolerance_deg)})"
            )
            passed = passed and margin_deg >= 0
            if margin_deg / target.heading_tolerance_deg < relative:
                relative = margin_deg / target.heading_tolerance_deg
                text, value, unit = by(margin_deg, deg(margin_deg)), margin_deg, "deg"
        return Verdict(
            "final_pose_within",
            passed,
            text,
            None if passed else record.duration_s,
            detail,
            value,
            unit,
            relative,
        )

    def draw(self, record: RunRecord, canvas: Canvas) -> list[str]:
        target = self.in_world(record)
        title = "target: the robot must end inside this circle"
        return [canvas.target_circle(target.x_mm, target.y_mm, target.radius_mm, title)]


def final_pose_target(target: FinalPose, record: RunRecord) -> FinalPose:
    """The target in world coordinates (see :meth:`FinalPose.in_world`)."""
    return target.in_world(record)
