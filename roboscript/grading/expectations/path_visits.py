"""``path_visits``: waypoints, placed relative to the robot's start, that its path comes near."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import TYPE_CHECKING

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import at, by, cm
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlList, YamlMap
from roboscript.sim.geometry import Segment, closest_point, heading_vector

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["DEFAULT_WAYPOINT_TOLERANCE_MM", "PathVisits", "Waypoint", "waypoint_position"]

DEFAULT_WAYPOINT_TOLERANCE_MM = 80.0


@dataclass(frozen=True)
class Waypoint:
    """A point relative to the robot's start pose: ``forward_mm`` ahead, ``right_mm`` to the
    right of where it started, in the start heading's frame (negative: back, left)."""

    forward_mm: float
    right_mm: float

    @property
    def label(self) -> str:
        """How reports name it: ``50 cm forward, 50 cm right``, or ``the start``."""
        parts = [
            f"{abs(value) / 10.0:g} cm {ahead if value > 0 else behind}"
            for value, ahead, behind in (
                (self.forward_mm, "forward", "back"),
                (self.right_mm, "right", "left"),
            )
            if value
        ]
        return ", ".join(parts) or "the start"


@dataclass(frozen=True)
class PathVisits(Rule):
    """``path_visits``: waypoints relative to the start the path must come within
    ``tolerance_mm`` of, in order unless ``in_order`` is false."""

    kind = "path_visits"

    waypoints: tuple[Waypoint, ...]
    tolerance_mm: float = DEFAULT_WAYPOINT_TOLERANCE_MM
    in_order: bool = True

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        if isinstance(value, YamlMap):
            data = value
            reader.allowed(
                data, ("waypoints", "tolerance", "in_order"), "path_visits", required=("waypoints",)
            )
            written, where = data["waypoints"], data.value_mark("waypoints")
        else:
            data, written, where = YamlMap.at(mark), value, mark
        items = _waypoint_items(reader, written, where)
        return cls(
            waypoints=tuple(_waypoint(reader, item, item_mark) for item, item_mark in items),
            tolerance_mm=(
                reader.positive(data, "tolerance", "distance", "mm")
                if "tolerance" in data
                else DEFAULT_WAYPOINT_TOLERANCE_MM
            ),
            in_order=_true_or_false(reader, data, "in_order", default=True),
        )

    def judge(self, record: RunRecord) -> Verdict:
        tol = self.tolerance_mm
        if not record.path:
            return Verdict("path_visits", False, "", None, "the run has no path")
        points = [waypoint_position(w, record.start_pose) for w in self.waypoints]
        near = [_approaches(record.path, px, py) for px, py in points]
        # Per waypoint: (closest distance, when) on its visit, or anywhere it was looked for if
        # missed; and when it was first within reach.
        closest: list[tuple[float, float]] = []
        reached: dict[int, float] = {}
        begin = 0  # in order, each waypoint is looked for from where the last came within reach
        for k, stretches in enumerate(near):
            entry = next((j for j in range(begin, len(stretches)) if stretches[j][0] <= tol), None)
            if entry is None:
                closest.append(min(stretches[begin:]))
                if self.in_order:
                    break
                continue
            reached[k] = _entry_time(record.path, entry, *points[k], tol)
            if self.in_order:
                stay = entry
                while stay + 1 < len(stretches) and stretches[stay + 1][0] <= tol:
                    stay += 1
                closest.append(min(stretches[entry : stay + 1]))
                begin = entry
            else:
                closest.append(min(stretches))
        missed = [k for k in range(len(closest)) if k not in reached]

        def name(k: int) -> str:
            return f"waypoint {k + 1} ({self.waypoints[k].label})"

        if missed:
            k = missed[0]
            distance, when = closest[k]
            margin = min(tol - d for d, _ in closest)  # in order: only the missed one is judged
            detail = (
                f"missed {name(k)}: the closest the robot came was {cm(distance)}, at {at(when)}"
                f" (allowed {cm(tol)})"
            )
            if self.in_order and k > 0:
                visits = ", ".join(f"{i + 1} at {at(reached[i])}" for i in range(k))
                detail += f", after reaching waypoint{'s' if k > 1 else ''} {visits}"
            elif len(missed) > 1:
                detail += f"; {len(missed)} of {len(closest)} waypoints missed"
            return Verdict(
                "path_visits",
                False,
                by(margin, cm(margin)),
                None,
                detail,
                margin,
                "mm",
                margin / tol,
            )
        worst = max(range(len(closest)), key=lambda i: closest[i][0])
        margin = tol - closest[worst][0]
        if len(closest) == 1:
            detail = (
                f"came within {cm(closest[0][0])} of {name(0)} at {at(closest[0][1])}"
                f" (allowed {cm(tol)})"
            )
        else:
            order = " in order" if self.in_order else ""
            times = ", ".join(at(reached[i]) for i in range(len(closest)))
            detail = (
                f"reached all {len(closest)} waypoints{order} ({times}); the farthest off was"
                f" {name(worst)}, {cm(closest[worst][0])} away (allowed {cm(tol)})"
            )
        return Verdict(
            "path_visits", True, by(margin, cm(margin)), None, detail, margin, "mm", margin / tol
        )


_WAYPOINT_KEYS = ("forward", "back", "right", "left")


def _waypoint_items(reader: FieldReader, value: object, mark: Mark) -> list[tuple[object, Mark]]:
    example = "such as [{forward: 50 cm}, {forward: 50 cm, right: 50 cm}]"
    if not isinstance(value, YamlList):
        raise reader.fail(f"path_visits lists waypoints, {example}", mark)
    items = reader.items(value, "path_visits", mark)
    if not items:
        raise reader.fail(f"path_visits lists at least one waypoint, {example}", mark)
    return items


def _waypoint(reader: FieldReader, value: object, mark: Mark) -> Waypoint:
    """``{forward: 50 cm, right: 20 cm}`` (``back``/``left`` for the other way), or ``start``."""
    if value == "start":
        return Waypoint(0.0, 0.0)
    if not isinstance(value, YamlMap):
        raise reader.fail(
            f"a waypoint is written {{forward: 50 cm, right: 20 cm}} (or back, left), or 'start'"
            f" (got {value!r})",
            mark,
            did_you_mean(value, ("start",)) if isinstance(value, str) else None,
        )
    reader.allowed(value, _WAYPOINT_KEYS, "a waypoint")
    if not value:
        raise reader.fail("a waypoint needs forward, back, right or left (or write 'start')", mark)
    for one, other in (("forward", "back"), ("right", "left")):
        if one in value and other in value:
            raise reader.fail(
                f"give either {one} or {other}, not both (a negative {one} is {other})",
                value.key_mark(other),
            )
    along = {key: reader.quantity(value, key, "distance", "mm") for key in value}
    return Waypoint(
        forward_mm=along.get("forward", 0.0) - along.get("back", 0.0),
        right_mm=along.get("right", 0.0) - along.get("left", 0.0),
    )


def _true_or_false(reader: FieldReader, data: YamlMap, key: str, *, default: bool) -> bool:
    if key not in data:
        return default
    value = data[key]
    if not isinstance(value, bool):
        raise reader.fail(f"'{key}' must be true or false (got {value!r})", data.value_mark(key))
    return value


def waypoint_position(waypoint: Waypoint, start: tuple[float, float, float]) -> tuple[float, float]:
    """Where ``waypoint`` is in the world for a robot that started at ``start`` (x, y, heading)."""
    sx, sy, heading = start
    fx, fy = heading_vector(heading)  # forward; the right-hand side is (fy, -fx)
    return (
        sx + waypoint.forward_mm * fx + waypoint.right_mm * fy,
        sy + waypoint.forward_mm * fy - waypoint.right_mm * fx,
    )


def _approaches(
    path: Sequence[tuple[float, float, float, float]], px: float, py: float
) -> list[tuple[float, float]]:
    """For each stretch of path between two samples, ``(distance, time)`` of its point nearest
    to ``(px, py)``: exact between the samples, so a fast robot cannot pass a waypoint unseen."""
    if len(path) < 2:
        return [(math.hypot(px - x, py - y), t) for t, x, y, _ in path]
    found = []
    for (t0, x0, y0, _), (t1, x1, y1, _) in pairwise(path):
        qx, qy = closest_point(px, py, Segment(x0, y0, x1, y1))
        length = math.hypot(x1 - x0, y1 - y0)
        share = math.hypot(qx - x0, qy - y0) / length if length > 0 else 0.0
        found.append((math.hypot(px - qx, py - qy), t0 + (t1 - t0) * share))
    return found


def _entry_time(
    path: Sequence[tuple[float, float, float, float]], j: int, px: float, py: float, reach: float
) -> float:
    """When stretch ``j`` of the path (from sample ``j`` to the next) first comes within
    ``reach`` of ``(px, py)``; it must come that close."""
    if j + 1 >= len(path):
        return path[j][0]
    (t0, x0, y0, _), (t1, x1, y1, _) = path[j], path[j + 1]
    dx, dy, fx, fy = x1 - x0, y1 - y0, x0 - px, y0 - py
    a = dx * dx + dy * dy
    c = fx * fx + fy * fy - reach * reach
    if c <= 0 or a == 0:
        return t0
    b = 2.0 * (fx * dx + fy * dy)
    share = (-b - math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
    return t0 + (t1 - t0) * min(max(share, 0.0), 1.0)
