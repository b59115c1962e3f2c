"""Simulator worlds: walls, floor lines, named regions and a start pose, from YAML.

A world file (millimetres unless a unit is given)::

    world: square-room
    description: A 2 m square room.
    start: {x: 0 mm, y: 0 mm, heading: 0 deg}
    walls:
      - box: {x: -1 m, y: -1 m, width: 2 m, height: 2 m}   # four walls, the room's outline
      - segment: [[0, 500], [300, 500]]
      - polyline: [[0, 0], [100 mm, 50 cm], [1 m, 1 m]]
    lines:                                            # dark tape on the floor
      - {polyline: [[0, 0], [0, 800]], width: 20 mm}
    regions:                                          # named areas for grading
      goal: {x: 0 mm, y: 800 mm, radius: 100 mm}
      home: {box: {x: -100, y: -100, width: 200, height: 200}}

Built-in worlds ship as package data in ``roboscript/sim/worlds/``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from roboscript.errors import WorldError
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlList, YamlMap, load_yaml, load_yaml_text
from roboscript.sim.geometry import Segment, point_in_polygon

__all__ = ["Pose", "Region", "TapeLine", "World", "builtin_worlds", "load_world"]


@dataclass(frozen=True, slots=True)
class Pose:
    """A position and heading: millimetres, degrees clockwise from north."""

    x_mm: float = 0.0
    y_mm: float = 0.0
    heading_deg: float = 0.0


@dataclass(frozen=True)
class TapeLine:
    """A strip of dark tape on the floor along a polyline."""

    segments: tuple[Segment, ...]
    width_mm: float = 20.0


@dataclass(frozen=True)
class Region:
    """A named area: a circle (``radius_mm``) or a polygon (``points``)."""

    name: str
    center: tuple[float, float] = (0.0, 0.0)
    radius_mm: float | None = None
    points: tuple[tuple[float, float], ...] = ()

    def contains(self, x_mm: float, y_mm: float) -> bool:
        """True if the point is inside the region."""
        if self.radius_mm is not None:
            return math.hypot(x_mm - self.center[0], y_mm - self.center[1]) <= self.radius_mm
        return point_in_polygon(x_mm, y_mm, list(self.points))


@dataclass(frozen=True)
class World:
    """Everything static in a simulated world."""

    name: str
    description: str = ""
    walls: tuple[Segment, ...] = ()
    lines: tuple[TapeLine, ...] = ()
    regions: dict[str, Region] = field(default_factory=dict)
    start: Pose = Pose()


def builtin_worlds() -> list[str]:
    """Names of the worlds that ship with roboscript."""
    folder = resources.files("roboscript.sim") / "worlds"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def load_world(name_or_path: str) -> World:
    """Load a built-in world by name, or a world file by path.

    Raises:
        WorldError: Unknown name, unreadable file, or invalid content (with ``file:line:col``).
    """
    if name_or_path in builtin_worlds():
        resource = resources.files("roboscript.sim") / "worlds" / f"{name_or_path}.yaml"
        data = load_yaml_text(resource.read_text(encoding="utf-8"), name_or_path, error=WorldError)
        return _WorldReader(name_or_path).read(data)
    path = Path(name_or_path)
    if not path.exists():
        known = ", ".join(builtin_worlds())
        raise WorldError(
            f"no world called '{name_or_path}' (built-in worlds: {known}; or give a file path)"
        )
    return _WorldReader(str(path)).read(load_yaml(path, error=WorldError))


class _WorldReader(FieldReader):
    def __init__(self, path: str) -> None:
        super().__init__(path, WorldError)

    def length(self, value: Any, mark: Mark) -> float:
        return self.value_quantity(value, "distance", mark)

    def point(self, value: Any, mark: Mark) -> tuple[float, float]:
        if not isinstance(value, list) or len(value) != 2:
            raise self.fail("a point is written [x, y]", mark)
        return self.length(value[0], mark), self.length(value[1], mark)

    def points(self, value: Any, mark: Mark, minimum: int) -> list[tuple[float, float]]:
        if not isinstance(value, YamlList) or len(value) < minimum:
            raise self.fail(f"expected a list of at least {minimum} points [x, y]", mark)
        return [self.point(item, m) for item, m in zip(value, value.item_marks, strict=True)]

    def box(self, value: Any, mark: Mark) -> list[tuple[float, float]]:
        box = self.mapping(value, "a box", mark)
        self.allowed(box, ("x", "y", "width", "height"), "a box")
        for key in ("x", "y", "width", "height"):
            if key not in box:
                raise self.fail(f"a box needs '{key}'", box.mark)
        x = self.length(box["x"], box.value_mark("x"))
        y = self.length(box["y"], box.value_mark("y"))
        w = self.length(box["width"], box.value_mark("width"))
        h = self.length(box["height"], box.value_mark("height"))
        if w <= 0 or h <= 0:
            raise self.fail("a box needs a positive width and height", box.mark)
        return [(x, y), (x + w, y), (x + w, y + h), (x, y + h), (x, y)]

    def shape(self, item: Any, mark: Mark, what: str, extra: set[str]) -> list[tuple[float, float]]:
        data = self.mapping(item, what, mark)
        kinds = [k for k in ("segment", "polyline", "box") if k in data]
        self.allowed(data, ("segment", "polyline", "box", *extra), what)
        if len(kinds) != 1:
            raise self.fail(f"{what} needs exactly one of segment, polyline or box", data.mark)
        kind = kinds[0]
        if kind == "box":
            return self.box(data["box"], data.value_mark("box"))
        pts = self.points(data[kind], data.value_mark(kind), 2)
        if kind == "segment" and len(pts) != 2:
            raise self.fail("a segment has exactly two points", data.value_mark(kind))
        return pts

    def read(self, data: Any) -> World:
        top = self.mapping(data, "a world file", (1, 1))
        self.allowed(top, ("world", "description", "start", "walls", "lines", "regions"), "world")
        walls: list[Segment] = []
        for item, mark in self.listed(top, "walls"):
            pts = self.shape(item, mark, "a wall", set())
            walls.extend(Segment(*a, *b) for a, b in itertools.pairwise(pts))
        lines: list[TapeLine] = []
        for item, mark in self.listed(top, "lines"):
            pts = self.shape(item, mark, "a line", {"width"})
            width = 20.0
            if isinstance(item, YamlMap) and "width" in item:
                width = self.length(item["width"], item.value_mark("width"))
            segs = tuple(Segment(*a, *b) for a, b in itertools.pairwise(pts))
            lines.append(TapeLine(segs, width))
        regions: dict[str, Region] = {}
        if "regions" in top:
            table = self.mapping(top["regions"], "regions", top.value_mark("regions"))
            for name, spec in table.items():
                regions[name] = self.region(name, spec, table.value_mark(name))
        start = Pose()
        if "start" in top:
            start = self.pose(top["start"], top.value_mark("start"))
        name = str(top.get("world", Path(self.path).stem))
        return World(
            name, str(top.get("description", "")), tuple(walls), tuple(lines), regions, start
        )

    def listed(self, top: YamlMap, key: str) -> list[tuple[Any, Mark]]:
        if key not in top:
            return []
        value = top[key]
        if not isinstance(value, YamlList):
            raise self.fail(f"'{key}' must be a list", top.value_mark(key))
        return list(zip(value, value.item_marks, strict=True))

    def region(self, name: str, spec: Any, mark: Mark) -> Region:
        data = self.mapping(spec, f"region '{name}'", mark)
        if "radius" in data:
            self.allowed(data, ("x", "y", "radius"), f"region '{name}'")
            x = self.length(data.get("x", 0), data.value_mark("x"))
            y = self.length(data.get("y", 0), data.value_mark("y"))
            radius = self.length(data["radius"], data.value_mark("radius"))
            return Region(name, (x, y), radius_mm=radius)
        if "box" in data or "polygon" in data:
            self.allowed(data, ("box", "polygon"), f"region '{name}'")
            if "box" in data:
                pts = self.box(data["box"], data.value_mark("box"))[:-1]
            else:
                pts = self.points(data["polygon"], data.value_mark("polygon"), 3)
            cx = sum(p[0] for p in pts) / len(pts)
            cy = sum(p[1] for p in pts) / len(pts)
            return Region(name, (cx, cy), points=tuple(pts))
        raise self.fail(f"region '{name}' needs a radius (with x, y), a box or a polygon", mark)

    def pose(self, value: Any, mark: Mark) -> Pose:
        data = self.mapping(value, "start", mark)
        self.allowed(data, ("x", "y", "heading"), "start")
        x = self.length(data.get("x", 0), data.value_mark("x"))
        y = self.length(data.get("y", 0), data.value_mark("y"))
        heading = self.value_quantity(data.get("heading", 0), "angle", data.value_mark("heading"))
        return Pose(x, y, heading)
