"""Where a path runs with respect to named regions and walls: entries, closest approaches, gaps.

A path is judged by the robot's centre. Path samples are 0.1 s apart, during which a robot may
move a few centimetres, so :func:`dense_path` fills in points at most ``step_mm`` apart: a
fast robot cannot slip through the corner of a region between two samples.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from functools import lru_cache

from roboscript.sim.geometry import Segment, closest_point, segment_distance
from roboscript.sim.world import Region

__all__ = ["dense_path", "enclosing_walls", "nearest_wall_gap_mm", "signed_distance_mm"]

_CELL_MM = 50.0
"""The grid :func:`enclosing_walls` floods: a gap a robot fits through (every robot is more
than twice this wide) always leaves a row of free cells, so no open world is taken as closed."""
_MOST_CELLS = 400
"""Cells along a side of that grid: a world wider than 20 m is not looked at."""

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


def enclosing_walls(
    walls: Sequence[Segment], x_mm: float, y_mm: float
) -> tuple[float, float, float, float] | None:
    """The box ``(x_min, y_min, x_max, y_max)`` around ``walls`` when they shut the point
    ``(x_mm, y_mm)`` in (nothing outside that box can be reached from it without going through
    a wall), else ``None``: not shut in, no walls, or a world too large to look at.

    The plane around the walls is cut into cells of ``_CELL_MM``; cells a wall crosses are
    closed; the point is shut in when the cells reached from its own, side to side, never
    reach the edge of the grid.
    """
    return _enclosing(tuple(walls), x_mm, y_mm) if walls else None


@lru_cache(maxsize=256)  # a spec asks once per run and expectation; runs share starts
def _enclosing(
    walls: tuple[Segment, ...], x_mm: float, y_mm: float
) -> tuple[float, float, float, float] | None:
    x_min = min(min(w.x0, w.x1) for w in walls)
    y_min = min(min(w.y0, w.y1) for w in walls)
    x_max = max(max(w.x0, w.x1) for w in walls)
    y_max = max(max(w.y0, w.y1) for w in walls)
    if not (x_min < x_mm < x_max and y_min < y_mm < y_max):
        return None
    left, bottom = x_min - 2 * _CELL_MM, y_min - 2 * _CELL_MM
    columns = math.ceil((x_max - left) / _CELL_MM) + 2
    rows = math.ceil((y_max - bottom) / _CELL_MM) + 2
    if columns > _MOST_CELLS or rows > _MOST_CELLS:
        return None

    def cell(x: float, y: float) -> tuple[int, int]:
        return int((x - left) // _CELL_MM), int((y - bottom) // _CELL_MM)

    closed: set[tuple[int, int]] = set()
    for wall in walls:
        steps = max(1, math.ceil(math.hypot(wall.x1 - wall.x0, wall.y1 - wall.y0) / 10.0))
        for k in range(steps + 1):
            f = k / steps
            closed.add(cell(wall.x0 + (wall.x1 - wall.x0) * f, wall.y0 + (wall.y1 - wall.y0) * f))
    first = cell(x_mm, y_mm)
    if first in closed:
        return None  # on a wall: not for this to say
    seen = {first}
    todo = [first]
    while todo:
        i, j = todo.pop()
        if i in (0, columns - 1) or j in (0, rows - 1):
            return None  # out to the edge: the walls leave a way out
        for near in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if near not in seen and near not in closed:
                seen.add(near)
                todo.append(near)
    return x_min, y_min, x_max, y_max
