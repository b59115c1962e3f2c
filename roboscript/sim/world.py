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
    floor:                                            # coloured floor (default white)
      - {color: red, box: {x: 200, y: 600, width: 200, height: 200}}
      - {color: green, polygon: [[0, 0], [300, 0], [0, 300]]}
    button_presses:                                   # a hub button pressed during the run
      - {at: 2 s, button: left, for: 300 ms}          # (robots with hub buttons: SPIKE)

Built-in worlds ship as package data in ``roboscript/sim/worlds/``.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

from roboscript.errors import WorldError, did_you_mean, nearby_file
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.kinds import refuse_another_kind
from roboscript.inputs.source import Mark, YamlList, YamlMap, load_yaml, load_yaml_text
from roboscript.sim.geometry import Segment, point_in_polygon

__all__ = [
    "FLOOR_COLOR_NAMES",
    "WORLD_REACH_MM",
    "FloorPatch",
    "Pose",
    "Region",
    "TapeLine",
    "World",
    "builtin_worlds",
    "load_world",
]

FLOOR_COLOR_NAMES = (
    "white",
    "black",
    "red",
    "green",
    "blue",
    "yellow",
    "azure",
    "magenta",
    "orange",
    "purple",
    "turquoise",
)
"""The colours a floor patch may have (LEGO's colour sensor names; ``sim/floor.py`` has
what each reflects)."""


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
class FloorPatch:
    """A part of the floor with a colour (what a colour sensor sees; see ``sim/floor.py``)."""

    color: str
    region: Region


@dataclass(frozen=True)
class World:
    """Everything static in a simulated world."""

    name: str
    description: str = ""
    walls: tuple[Segment, ...] = ()
    lines: tuple[TapeLine, ...] = ()
    regions: dict[str, Region] = field(default_factory=dict)
    start: Pose = Pose()
    floor: tuple[FloorPatch, ...] = ()
    button_presses: tuple[tuple[float, str, float], ...] = ()
    """Scripted button presses: (time s, button name, how long s), in time order."""


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
            f"no world called '{name_or_path}' (built-in worlds: {known}; or give a file path)",
            hint=did_you_mean(name_or_path, builtin_worlds()) or nearby_file(path),
        )
    data = load_yaml(path, error=WorldError)
    if isinstance(data, YamlMap):  # --world square.yaml: said as what the file is
        refuse_another_kind(data, path, "world", WorldError)
    return _WorldReader(str(path)).read(data)


_TOP_KEYS = (
    "world",
    "description",
    "start",
    "walls",
    "lines",
    "regions",
    "floor",
    "button_presses",
)


WORLD_REACH_MM = 1_000_000.0
"""Farthest any coordinate or size of a world may be from its origin: 1 km, far past any room
(and still exact to a thousandth of a millimetre)."""


class _WorldReader(FieldReader):
    def __init__(self, path: str) -> None:
        super().__init__(path, WorldError)

    def length(self, value: Any, mark: Mark) -> float:
        found = self.value_quantity(value, "distance", mark)
        if abs(found) > WORLD_REACH_MM:
            # past it, a robot's steps of a millimetre vanish in the coordinates' rounding
            raise self.fail(
                f"{found / 1000:g} m is farther than a world reaches (at most 1 km from its"
                " origin)",
                mark,
            )
        return found

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
        self.allowed(
            top,
            _TOP_KEYS,
            "world",
        )
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
        floor = tuple(self.floor_patch(item, mark) for item, mark in self.listed(top, "floor"))
        presses = sorted(
            self.button_press(item, mark) for item, mark in self.listed(top, "button_presses")
        )
        return World(
            name,
            str(top.get("description", "")),
            tuple(walls),
            tuple(lines),
            regions,
            start,
            floor,
            tuple(presses),
        )

    def button_press(self, item: Any, mark: Mark) -> tuple[float, str, float]:
        data = self.mapping(item, "a button press", mark)
        self.allowed(data, ("at", "button", "for"), "a button press")
        if data.get("button") not in ("left", "right"):
            where = data.value_mark("button") if "button" in data else data.mark
            raise self.fail("a button press needs 'button: left' or 'button: right'", where)
        if "at" not in data:
            raise self.fail("a button press needs 'at' (when, e.g. 2 s)", data.mark)
        at_s = self.value_quantity(data["at"], "time", data.value_mark("at"))
        duration_s = 0.2
        if "for" in data:
            duration_s = self.value_quantity(data["for"], "time", data.value_mark("for"))
        if at_s < 0 or duration_s <= 0:
            raise self.fail("a button press needs 'at' >= 0 s and a positive 'for'", data.mark)
        return (at_s, str(data["button"]), duration_s)

    def floor_patch(self, item: Any, mark: Mark) -> FloorPatch:
        data = self.mapping(item, "a floor patch", mark)
        self.allowed(data, ("color", "box", "polygon"), "a floor patch")
        color = data.get("color")
        if color not in FLOOR_COLOR_NAMES:
            raise self.fail(
                f"a floor patch needs a color, one of {', '.join(FLOOR_COLOR_NAMES)}",
                data.value_mark("color") if "color" in data else data.mark,
            )
        if ("box" in data) == ("polygon" in data):
            raise self.fail("a floor patch needs exactly one of box or polygon", data.mark)
        if "box" in data:
            points = self.box(data["box"], data.value_mark("box"))[:-1]
        else:
            points = self.points(data["polygon"], data.value_mark("polygon"), 3)
        return FloorPatch(str(color), Region(str(color), points=tuple(points)))

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
