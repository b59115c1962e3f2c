"""Where a path runs with respect to named regions and walls: entries, closest approaches, gaps.

A path is judged by the robot's centre. Path samples are 0.1 s apart, during which a robot may
move a few centimetres, so :func:`dense_path` fills in points at most ``step_mm`` apart: a
fast robot cannot slip through the corner of a region between two samples.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

from roboscript.sim.geometry import Segment, closest_point, segment_distance
from roboscript.sim.world import Region

__all__ = ["dense_path", "nearest_wall_gap_mm", "signed_distance_mm"]

PathSample = tuple[float, float, float, float]


def dense_path(
    path: Sequence[PathSample], step_mm: float = 10.0
) -> Iterator[tuple[float, float, float]]:
    """``(t_s, x_mm, y_mm)`` along the path, with points filled in at most ``step_mm`` apart."""
    for i, (t, x, y, _h) in enumerate(path):
        if i == 0:
            yield t, x, y
            continue
        t0, x0, y0, _ = path[i - 1]
        steps = max(1, math.ceil(math.hypot(x - x0, y - y0) / step_mm))
        for k in range(1, steps + 1):
            f = k / steps
            yield t0 + (t - t0) * f, x0 + (x - x0) * f, y0 + (y - y0) * f


def signed_distance_mm(region: Region, x_mm: float, y_mm: float) -> float:
    """Distance from the point to the region's edge: positive outside, negative inside."""
    if region.radius_mm is not None:
        cx, cy = region.center
        return math.hypot(x_mm - cx, y_mm - cy) - region.radius_mm
    points = region.points
    edge = min(
        segment_distance(x_mm, y_mm, Segment(*points[i], *points[(i + 1) % len(points)]))
        for i in range(len(points))
    )
    return -edge if region.contains(x_mm, y_mm) else edge


def nearest_wall_gap_mm(
    walls: Sequence[Segment],
    x_mm: float,
    y_mm: float,
    heading_deg: float,
    side: str,
    offset_mm: float,
) -> float:
    """The gap from a side sensor to the nearest wall on that side of the robot, millimetres.

    The sensor sits ``offset_mm`` from the centre towards ``side`` (``left`` or ``right``);
    only wall points beyond it on that side count (a wall ahead or behind the robot's side line
    does not). ``math.inf`` if no wall is on that side.
    """
    rad = math.radians(heading_deg)
    # Heading is clockwise from north: forward (sin, cos), right-hand side (cos, -sin).
    sx, sy = math.cos(rad), -math.sin(rad)
    if side == "left":
        sx, sy = -sx, -sy
    px, py = x_mm + sx * offset_mm, y_mm + sy * offset_mm
    best = math.inf
    for wall in walls:
        clipped = _clip_to_side(wall, px, py, sx, sy)
        if clipped is None:
            continue
        qx, qy = closest_point(px, py, clipped)
        best = min(best, math.hypot(qx - px, qy - py))
    return best


def _clip_to_side(seg: Segment, px: float, py: float, sx: float, sy: float) -> Segment | None:
    """The part of ``seg`` where ``(q - p) . s >= 0``, or ``None``."""
    d0 = (seg.x0 - px) * sx + (seg.y0 - py) * sy
    d1 = (seg.x1 - px) * sx + (seg.y1 - py) * sy
    if d0 < 0 and d1 < 0:
        return None
    if d0 >= 0 and d1 >= 0:
        return seg
    f = d0 / (d0 - d1)
    mx, my = seg.x0 + (seg.x1 - seg.x0) * f, seg.y0 + (seg.y1 - seg.y0) * f
    if d0 >= 0:
        return Segment(seg.x0, seg.y0, mx, my)
    return Segment(mx, my, seg.x1, seg.y1)
