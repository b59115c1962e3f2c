"""Expectations: what a teacher's test spec says must happen, and how each is judged.

Each kind of expectation (``outcome``, ``final_pose_within``, ``wall_distance``...) has a
parameter dataclass read from the spec (:func:`parse_expectation`) and a judge: a pure function
of a :class:`~roboscript.grading.record.RunRecord` returning a
:class:`~roboscript.grading.record.Verdict` with a signed margin ("passed by 2.1 cm", "failed
by 0.4 s") and, where failing has a moment, the mission time of the first violation.

A teacher's own ``check: file.py:function`` is imported and called in the grading worker, never
in the process that reads the spec. A run of the spec may give expectations targets of its own
(``runs: [{seed: 2, expect: {KIND: {key: value}}}]``, :func:`apply_run_targets`); the run is
told from its record when judged (:class:`RunTargets`).
"""

from __future__ import annotations

import ast
import importlib.util
import math
import sys
import traceback
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from itertools import pairwise
from pathlib import Path
from typing import Any

from roboscript.angles import wrap_deg
from roboscript.errors import did_you_mean
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.regions import dense_path, nearest_wall_gap_mm, signed_distance_mm
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Location, Mark, YamlList, YamlMap
from roboscript.sim.geometry import Segment, closest_point, heading_vector, ray_cast
from roboscript.sim.world import World

__all__ = [
    "EXPECTATION_KINDS",
    "CheckFunction",
    "Expectation",
    "FinalPose",
    "PathVisits",
    "RunOverride",
    "RunTargets",
    "Tones",
    "Turn",
    "Turns",
    "WallAhead",
    "WallDistance",
    "Waypoint",
    "apply_run_targets",
    "evaluate",
    "final_pose_target",
    "find_turns",
    "parse_expectation",
    "waypoint_position",
]

DEFAULT_TONE_TOLERANCE_HZ = 5.0
DEFAULT_HEADING_TOLERANCE_DEG = 15.0
DEFAULT_SETTLE_S = 1.0
DEFAULT_WAYPOINT_TOLERANCE_MM = 80.0
DEFAULT_TURN_TOLERANCE_DEG = 20.0
DEFAULT_WALL_AHEAD_TOLERANCE_MM = 30.0
TURN_RATE_DEG_S = 3.0
"""A robot turning faster than this is turning (driving straight, it drifts under 1°/s)."""
TURN_PAUSE_S = 0.2
"""Turning slower than :data:`TURN_RATE_DEG_S` for this long ends a turn, so the wobble that
settles a ``rotate`` belongs to its turn, while a beep between two turns separates them."""
MIN_TURN_DEG = 10.0
"""A turn smaller than this is a wobble (a steering correction), not a turn."""


# ------------------------------------------------------------------------------ parameters


@dataclass(frozen=True)
class FinalPose:
    """``final_pose_within``: where the robot must end, and optionally facing which way."""

    x_mm: float
    y_mm: float
    radius_mm: float
    heading_deg: float | None = None
    heading_tolerance_deg: float = DEFAULT_HEADING_TOLERANCE_DEG
    relative_to: str = "world"


@dataclass(frozen=True)
class Tones:
    """``tones``: how many, and which frequencies (in order, or all the same)."""

    count: int | None = None
    min_count: int | None = None
    max_count: int | None = None
    frequencies_hz: tuple[float, ...] | None = None
    frequency_hz: float | None = None
    tolerance_hz: float = DEFAULT_TONE_TOLERANCE_HZ


@dataclass(frozen=True)
class WallDistance:
    """``wall_distance``: the gap to keep to a wall while in a state."""

    state: str
    side: str = "right"
    min_mm: float | None = None
    max_mm: float | None = None
    settle_s: float = DEFAULT_SETTLE_S


@dataclass(frozen=True)
class CheckFunction:
    """``check``: a teacher's Python function, by file and name."""

    path: str
    function: str
    written: str


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
class PathVisits:
    """``path_visits``: waypoints relative to the start the path must come near, in order."""

    waypoints: tuple[Waypoint, ...]
    tolerance_mm: float = DEFAULT_WAYPOINT_TOLERANCE_MM
    in_order: bool = True


@dataclass(frozen=True)
class Turns:
    """``turns``: which way the robot turns, how many times, how far each, how far in all.

    Angles are sizes (above 0); ``direction`` says which way. See :func:`find_turns` for
    what counts as one turn.
    """

    direction: str | None = None
    count: int | None = None
    angle_deg: float | None = None
    total_deg: float | None = None
    tolerance_deg: float = DEFAULT_TURN_TOLERANCE_DEG


@dataclass(frozen=True)
class WallAhead:
    """``wall_ahead_at_end``: the gap from the body's front edge to the wall straight ahead."""

    distance_mm: float
    tolerance_mm: float = DEFAULT_WALL_AHEAD_TOLERANCE_MM


RunKey = tuple[str, int, tuple[float, float, float]]
"""How a run is recognised from its record: world name, seed, start pose ``(x, y, heading)``."""


@dataclass(frozen=True)
class RunTargets:
    """The parameters of an expectation that some runs give targets of their own.

    A record does not name its run, so the run is recognised by what the record holds: its
    world's name and seed, then the start pose nearest to the record's (two runs alike in all
    three but their targets are refused when the spec is read, :func:`apply_run_targets`).

    Attributes:
        default: The parameters written in the spec's ``expect``.
        runs: Every run's key and its parameters (the default, or its own).
    """

    default: Any
    runs: tuple[tuple[RunKey, Any], ...]

    def for_record(self, record: RunRecord) -> Any:
        """The parameters for the run this record is of (the default for an unknown run)."""
        same = [
            (key, params)
            for key, params in self.runs
            if key[0] == record.world_name and key[1] == record.seed
        ]
        if not same:
            return self.default
        x, y, heading = record.start_pose
        return min(same, key=lambda run: _start_mismatch(run[0][2], x, y, heading))[1]


def _start_mismatch(start: tuple[float, float, float], x: float, y: float, h: float) -> float:
    """How unlike two start poses are: millimetres, with 10 mm per degree of heading."""
    turn = abs(wrap_deg(start[2] - h))
    return math.hypot(start[0] - x, start[1] - y) + 10.0 * turn


@dataclass(frozen=True)
class Expectation:
    """One line of a spec's ``expect`` list.

    Attributes:
        kind: Which expectation (a key of :data:`EXPECTATION_KINDS`).
        params: The kind's parameters (a value or a dataclass of this module).
        weight: Its share of a run's score.
        location: Where it was written.
    """

    kind: str
    params: Any
    weight: float = 1.0
    location: Location | None = None

    @property
    def name(self) -> str:
        """How reports name it: the kind, or ``check: function`` for a teacher's check."""
        if isinstance(self.params, CheckFunction):
            return f"check: {self.params.function}"
        return self.kind

    def for_record(self, record: RunRecord) -> Expectation:
        """This expectation with the targets of the run ``record`` is of (see
        :class:`RunTargets`); itself when no run has targets of its own."""
        if isinstance(self.params, RunTargets):
            return replace(self, params=self.params.for_record(record))
        return self


# ---------------------------------------------------------------------------------- words


def _cm(value_mm: float) -> str:
    return f"{abs(value_mm) / 10.0:.1f} cm"


def _s(value_s: float) -> str:
    return f"{abs(value_s):.2f} s" if abs(value_s) < 1.0 else f"{abs(value_s):.1f} s"


def _deg(value: float) -> str:
    return f"{abs(value):.1f}°"


def _by(margin: float, words: str) -> str:
    return f"{'passed' if margin >= 0 else 'failed'} by {words}"


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _at(t_s: float) -> str:
    return f"{t_s:.1f} s"


# ---------------------------------------------------------------------------------- parse


@dataclass(frozen=True)
class SpecContext:
    """What expectations are checked against while a spec is read.

    Attributes:
        folder: The spec's folder (a ``check`` file is found relative to it).
        worlds: Every world the spec's runs use (region names must exist in each).
    """

    folder: Path
    worlds: tuple[World, ...]


Parser = Callable[[FieldReader, Any, Mark, SpecContext], Any]


def _parse_outcome(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> str:
    if value not in ("success", "failure"):
        hint = did_you_mean(str(value), ("success", "failure"))
        raise reader.fail(f"outcome must be success or failure (got {value!r})", mark, hint)
    return str(value)


def _parse_final_state(
    reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    holder = YamlMap.at(mark, {"final_state": value})
    return tuple(name for name, _ in reader.names(holder, "final_state"))


def _parse_final_pose(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> FinalPose:
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
    return FinalPose(
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


def _region_names(
    reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext, key: str
) -> tuple[str, ...]:
    holder = YamlMap.at(mark, {key: value})
    names = reader.names(holder, key)
    for name, where in names:
        for world in ctx.worlds:
            if name not in world.regions:
                known = ", ".join(sorted(world.regions)) or "none"
                raise reader.fail(
                    f"the world '{world.name}' has no region '{name}' (its regions: {known})",
                    where,
                    did_you_mean(name, world.regions),
                )
    return tuple(name for name, _ in names)


def _parse_regions_in_order(
    reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    return _region_names(reader, value, mark, ctx, "regions_in_order")


def _parse_never_enter(
    reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    return _region_names(reader, value, mark, ctx, "never_enter")


def _parse_no_collisions(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> bool:
    if value is not True:
        raise reader.fail(
            f"write 'no_collisions: true' (got {value!r}); leave it out to allow collisions",
            mark,
        )
    return True


def _parse_tones(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> Tones:
    data = reader.mapping(value, "tones", mark)
    keys = ("count", "min_count", "max_count", "frequencies", "frequency", "tolerance")
    reader.allowed(data, keys, "tones")
    if not data:
        raise reader.fail("tones needs at least one of: count, min_count, max_count, ...", mark)
    if "count" in data and ("min_count" in data or "max_count" in data):
        raise reader.fail(
            "give either count or min_count/max_count, not both", data.key_mark("count")
        )
    if "frequencies" in data and "frequency" in data:
        raise reader.fail(
            "give either frequencies (a list, in order) or frequency (every tone)",
            data.key_mark("frequency"),
        )
    counts = {k: reader.integer(data, k) for k in ("count", "min_count", "max_count") if k in data}
    if counts.get("min_count", 0) > counts.get("max_count", math.inf):
        raise reader.fail("min_count is more than max_count", data.key_mark("min_count"))
    frequencies = None
    if "frequencies" in data:
        items = reader.items(data["frequencies"], "frequencies", data.value_mark("frequencies"))
        if not items:
            raise reader.fail("frequencies lists at least one", data.value_mark("frequencies"))
        frequencies = tuple(_frequency(reader, v, m) for v, m in items)
        if "count" in counts and counts["count"] != len(frequencies):
            raise reader.fail(
                f"count is {counts['count']} but frequencies lists {len(frequencies)}",
                data.key_mark("count"),
            )
    return Tones(
        count=counts.get("count"),
        min_count=counts.get("min_count"),
        max_count=counts.get("max_count"),
        frequencies_hz=frequencies,
        frequency_hz=(
            reader.positive(data, "frequency", "frequency", "Hz") if "frequency" in data else None
        ),
        tolerance_hz=(
            reader.positive(data, "tolerance", "frequency", "Hz")
            if "tolerance" in data
            else DEFAULT_TONE_TOLERANCE_HZ
        ),
    )


def _frequency(reader: FieldReader, value: Any, mark: Mark) -> float:
    holder = YamlMap.at(mark, {"frequency": value})
    return reader.positive(holder, "frequency", "frequency", "Hz")


def _parse_max_duration(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> float:
    holder = YamlMap.at(mark, {"max_duration": value})
    return reader.positive(holder, "max_duration", "time", "s")


def _parse_wall_distance(
    reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext
) -> WallDistance:
    data = reader.mapping(value, "wall_distance", mark)
    reader.allowed(
        data, ("state", "min", "max", "side", "settle"), "wall_distance", required=("state",)
    )
    if "min" not in data and "max" not in data:
        raise reader.fail("wall_distance needs min, max or both", data.mark)
    low = reader.quantity(data, "min", "distance", "mm") if "min" in data else None
    high = reader.positive(data, "max", "distance", "mm") if "max" in data else None
    if low is not None and high is not None and low >= high:
        raise reader.fail("min must be less than max", data.value_mark("min"))
    settle = DEFAULT_SETTLE_S
    if "settle" in data:
        settle = reader.quantity(data, "settle", "time", "s")
        if settle < 0:
            raise reader.fail("settle cannot be negative", data.value_mark("settle"))
    return WallDistance(
        state=reader.text(data, "state"),
        side=reader.choice(data, "side", ("left", "right")) if "side" in data else "right",
        min_mm=low,
        max_mm=high,
        settle_s=settle,
    )


def _parse_check(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> CheckFunction:
    if not isinstance(value, str) or ":" not in value:
        raise reader.fail(
            "check is written 'file.py:function' (a Python file beside the spec)", mark
        )
    file_part, _, function = value.rpartition(":")
    if not function.isidentifier():
        raise reader.fail(f"'{function}' is not a Python function name", mark)
    path = (ctx.folder / file_part).resolve()
    if path.suffix != ".py" or not path.is_file():
        raise reader.fail(f"no Python file '{file_part}' next to the spec", mark)
    try:
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    except (SyntaxError, UnicodeDecodeError) as exc:
        raise reader.fail(f"cannot read {file_part}: {exc}", mark) from None
    defined = [n.name for n in tree.body if isinstance(n, ast.FunctionDef)]
    if function not in defined:
        raise reader.fail(
            f"{file_part} has no function '{function}'", mark, did_you_mean(function, defined)
        )
    return CheckFunction(str(path), function, value)


_WAYPOINT_KEYS = ("forward", "back", "right", "left")


def _parse_path_visits(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> PathVisits:
    if isinstance(value, YamlMap):
        data = value
        reader.allowed(
            data, ("waypoints", "tolerance", "in_order"), "path_visits", required=("waypoints",)
        )
        written, where = data["waypoints"], data.value_mark("waypoints")
    else:
        data, written, where = YamlMap.at(mark), value, mark
    items = _waypoint_items(reader, written, where)
    return PathVisits(
        waypoints=tuple(_waypoint(reader, item, item_mark) for item, item_mark in items),
        tolerance_mm=(
            reader.positive(data, "tolerance", "distance", "mm")
            if "tolerance" in data
            else DEFAULT_WAYPOINT_TOLERANCE_MM
        ),
        in_order=_true_or_false(reader, data, "in_order", default=True),
    )


def _waypoint_items(reader: FieldReader, value: Any, mark: Mark) -> list[tuple[Any, Mark]]:
    example = "such as [{forward: 50 cm}, {forward: 50 cm, right: 50 cm}]"
    if not isinstance(value, YamlList):
        raise reader.fail(f"path_visits lists waypoints, {example}", mark)
    items = reader.items(value, "path_visits", mark)
    if not items:
        raise reader.fail(f"path_visits lists at least one waypoint, {example}", mark)
    return items


def _waypoint(reader: FieldReader, value: Any, mark: Mark) -> Waypoint:
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


def _parse_turns(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> Turns:
    data = reader.mapping(value, "turns", mark)
    keys = ("direction", "count", "angle", "total", "tolerance")
    reader.allowed(data, keys, "turns")
    if not any(key in data for key in keys[:4]):
        raise reader.fail(
            "turns needs at least one of: direction, count, angle, total,"
            " such as {direction: right, count: 4, angle: 90 deg}",
            mark,
        )
    angles = {}
    for key in ("angle", "total"):
        if key in data:
            angles[key] = reader.quantity(data, key, "angle", "deg")
            if angles[key] <= 0:
                raise reader.fail(
                    f"'{key}' is a size, more than 0; say which way with direction: left or right",
                    data.value_mark(key),
                )
    return Turns(
        direction=(
            reader.choice(data, "direction", ("right", "left")) if "direction" in data else None
        ),
        count=reader.integer(data, "count") if "count" in data else None,
        angle_deg=angles.get("angle"),
        total_deg=angles.get("total"),
        tolerance_deg=(
            reader.positive(data, "tolerance", "angle", "deg")
            if "tolerance" in data
            else DEFAULT_TURN_TOLERANCE_DEG
        ),
    )


def _parse_wall_ahead(reader: FieldReader, value: Any, mark: Mark, ctx: SpecContext) -> WallAhead:
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
    return WallAhead(
        distance_mm=distance,
        tolerance_mm=(
            reader.positive(data, "tolerance", "distance", "mm")
            if "tolerance" in data
            else DEFAULT_WALL_AHEAD_TOLERANCE_MM
        ),
    )


EXPECTATION_KINDS: dict[str, Parser] = {
    "outcome": _parse_outcome,
    "final_state": _parse_final_state,
    "final_pose_within": _parse_final_pose,
    "regions_in_order": _parse_regions_in_order,
    "never_enter": _parse_never_enter,
    "no_collisions": _parse_no_collisions,
    "tones": _parse_tones,
    "max_duration": _parse_max_duration,
    "wall_distance": _parse_wall_distance,
    "path_visits": _parse_path_visits,
    "turns": _parse_turns,
    "wall_ahead_at_end": _parse_wall_ahead,
    "check": _parse_check,
}
"""Every expectation a spec may use, with its reader."""


def parse_expectation(reader: FieldReader, item: Any, mark: Mark, ctx: SpecContext) -> Expectation:
    """Read one item of ``expect`` (``{KIND: VALUE}``, optionally with ``weight``).

    Raises:
        SpecError: At the mistake, with a "did you mean" for a misspelt kind.
    """
    data = reader.mapping(item, "an expectation", mark)
    kinds = [key for key in data if key != "weight"]
    if len(kinds) != 1:
        listed = ", ".join(EXPECTATION_KINDS)
        raise reader.fail(f"an expectation has exactly one of: {listed}", data.mark)
    kind = kinds[0]
    if kind not in EXPECTATION_KINDS:
        raise reader.fail(
            f"unknown expectation '{kind}'",
            data.key_mark(kind),
            did_you_mean(kind, EXPECTATION_KINDS)
            or f"expected one of: {', '.join(EXPECTATION_KINDS)}",
        )
    weight = 1.0
    if "weight" in data:
        value = data["weight"]
        if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
            raise reader.fail("weight must be a number above 0", data.value_mark("weight"))
        weight = float(value)
    params = EXPECTATION_KINDS[kind](reader, data[kind], data.value_mark(kind), ctx)
    line, col = data.key_mark(kind)
    return Expectation(kind, params, weight, Location(reader.path, line, col))


@dataclass(frozen=True)
class RunOverride:
    """One run of a spec, for :func:`apply_run_targets`.

    Attributes:
        key: How its record is recognised (world name, seed, start pose).
        world: Its world (region names are checked in it).
        expect: Its own ``expect:`` as written (``{KIND: targets}``), or ``None``.
        mark: Where that ``expect:`` was written.
    """

    key: RunKey
    world: World
    expect: Any = None
    mark: Mark = (1, 1)


def apply_run_targets(
    reader: FieldReader,
    expectations: tuple[Expectation, ...],
    written: Sequence[tuple[Any, Mark]],
    runs: Sequence[RunOverride],
    folder: Path,
) -> tuple[Expectation, ...]:
    """The spec's expectations with each run's own targets (a run's ``expect:``).

    A run's ``expect: {KIND: {key: value}}`` changes those keys of the spec's one ``KIND``
    expectation for that run (the rest as the spec writes them); a value that is not a mapping
    (``max_duration: 50 s``) replaces the spec's. The expectations it changes get
    :class:`RunTargets` parameters, chosen per run when judged.

    Args:
        reader: The spec's reader.
        expectations: As read from the spec's ``expect``.
        written: The ``expect`` items as written, with their marks, in the same order.
        runs: Every run, in order.
        folder: The spec's folder.

    Raises:
        SpecError: At a run's target that names no expectation of the spec, names one the
            spec has twice, changes a weight or a check, or is not a valid target.
    """
    kinds = [e.kind for e in expectations]
    own: dict[int, dict[int, Any]] = {}  # expectation index -> run index -> its parameters
    for r, run in enumerate(runs):
        if run.expect is None:
            continue
        example = "such as expect: {final_pose_within: {x: 30 cm}}"
        if not isinstance(run.expect, YamlMap) or not run.expect:
            raise reader.fail(
                f"a run's expect changes the targets of the spec's expectations, {example}",
                run.mark,
            )
        for kind in run.expect:
            at = run.expect.key_mark(kind)
            if kind == "weight":
                raise reader.fail("a run cannot change weights, only targets", at)
            if kind == "check":
                raise reader.fail(
                    "a run cannot change a check; your function gets the run's record"
                    " (its seed, start and world) to judge by",
                    at,
                )
            found = [i for i, k in enumerate(kinds) if k == kind]
            if not found:
                known = EXPECTATION_KINDS if kind not in EXPECTATION_KINDS else kinds
                listed = ", ".join(dict.fromkeys(kinds))
                raise reader.fail(
                    f"the spec expects no '{kind}' for this run to change (a run changes the"
                    f" targets of the spec's own expectations: {listed})",
                    at,
                    did_you_mean(kind, known),
                )
            if len(found) > 1:
                raise reader.fail(
                    f"the spec expects '{kind}' {len(found)} times, so a run cannot say which"
                    " to change",
                    at,
                )
            i = found[0]
            item = written[i][0]
            base = item[kind]
            if kind == "path_visits" and isinstance(base, YamlList):  # the short form
                base = YamlMap.at(item.value_mark(kind), {"waypoints": base})
            merged = _merged(base, run.expect[kind], at)
            ctx = SpecContext(folder, (run.world,))
            value_at = run.expect.value_mark(kind)
            own.setdefault(i, {})[r] = EXPECTATION_KINDS[kind](reader, merged, value_at, ctx)
    if not own:
        return expectations
    changed = list(expectations)
    for i, by_run in own.items():
        base = expectations[i].params
        targets = tuple((run.key, by_run.get(r, base)) for r, run in enumerate(runs))
        _refuse_lookalike_runs(reader, targets, runs, expectations[i].kind)
        changed[i] = replace(expectations[i], params=RunTargets(base, targets))
    return tuple(changed)


def _merged(base: Any, change: Any, change_mark: Mark) -> Any:
    """``base`` with the keys of ``change`` (when both are mappings), else ``change``."""
    if not (isinstance(base, YamlMap) and isinstance(change, YamlMap)):
        return change
    merged = YamlMap.at(change_mark, {**base, **change})
    merged.key_marks = {**base.key_marks, **change.key_marks}
    merged.value_marks = {**base.value_marks, **change.value_marks}
    merged.quoted = (base.quoted - set(change)) | change.quoted
    return merged


def _refuse_lookalike_runs(
    reader: FieldReader,
    targets: tuple[tuple[RunKey, Any], ...],
    runs: Sequence[RunOverride],
    kind: str,
) -> None:
    """Two runs told apart only by their targets would be judged by the same ones."""
    for b, (key_b, params_b) in enumerate(targets):
        for a, (key_a, params_a) in enumerate(targets[:b]):
            same_run = key_a[:2] == key_b[:2] and _start_mismatch(key_a[2], *key_b[2]) < 50.0
            if same_run and params_a != params_b:
                raise reader.fail(
                    f"runs {a + 1} and {b + 1} have the same world, seed and start, but"
                    f" different '{kind}' targets; give them different seeds",
                    runs[b].mark if runs[b].expect is not None else runs[a].mark,
                )


# ------------------------------------------------------------------------------- evaluate


def evaluate(expectation: Expectation, record: RunRecord) -> Verdict:
    """Judge one expectation on a run's record (the teacher's ``check`` is imported here)."""
    judge = _JUDGES[expectation.kind]
    verdict = judge(expectation.for_record(record).params, record)
    return replace(verdict, name=expectation.name, weight=expectation.weight)


def _outcome(wanted: str, record: RunRecord) -> Verdict:
    passed = record.outcome == wanted
    detail = f"the mission ended in {record.outcome}"
    if record.reason:
        detail += f": {record.reason}"  # the reason names the state
    elif record.final_state:
        detail += f" in state '{record.final_state}'"
    return Verdict(
        "outcome", passed, first_violation_s=None if passed else record.duration_s, detail=detail
    )


def _final_state(wanted: tuple[str, ...], record: RunRecord) -> Verdict:
    passed = record.final_state in wanted
    expected = " or ".join(f"'{name}'" for name in wanted)
    detail = f"ended in '{record.final_state}' (expected {expected})"
    return Verdict(
        "final_state",
        passed,
        first_violation_s=None if passed else record.duration_s,
        detail=detail,
    )


def final_pose_target(target: FinalPose, record: RunRecord) -> FinalPose:
    """The target in world coordinates (a ``relative_to: start`` target moved to the start)."""
    if target.relative_to != "start":
        return target
    # The target is in the robot's start frame: x to its right, y ahead, heading from its own.
    sx, sy, sh = record.start_pose
    rad = math.radians(sh)
    return replace(
        target,
        x_mm=sx + target.x_mm * math.cos(rad) + target.y_mm * math.sin(rad),
        y_mm=sy - target.x_mm * math.sin(rad) + target.y_mm * math.cos(rad),
        heading_deg=None if target.heading_deg is None else target.heading_deg + sh,
        relative_to="world",
    )


def _final_pose(target: FinalPose, record: RunRecord) -> Verdict:
    x, y, heading = record.final_pose
    target = final_pose_target(target, record)
    off_mm = math.hypot(x - target.x_mm, y - target.y_mm)
    margin_mm = target.radius_mm - off_mm
    detail = (
        f"ended at ({x:.0f}, {y:.0f}) mm, {_cm(off_mm)} from the target"
        f" ({target.x_mm:.0f}, {target.y_mm:.0f}) mm (allowed {_cm(target.radius_mm)})"
    )
    relative = margin_mm / target.radius_mm
    text, value, unit = _by(margin_mm, _cm(margin_mm)), margin_mm, "mm"
    passed = margin_mm >= 0
    if target.heading_deg is not None:
        error = wrap_deg(heading - target.heading_deg)
        margin_deg = target.heading_tolerance_deg - abs(error)
        detail += (
            f"; heading {heading:.0f}°, {_deg(error)} off"
            f" (allowed {_deg(target.heading_tolerance_deg)})"
        )
        passed = passed and margin_deg >= 0
        if margin_deg / target.heading_tolerance_deg < relative:
            relative = margin_deg / target.heading_tolerance_deg
            text, value, unit = _by(margin_deg, _deg(margin_deg)), margin_deg, "deg"
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


def _regions(record: RunRecord) -> dict[str, Any]:
    if record.world is None:
        raise ValueError("this record has no world to find its regions in")
    return dict(record.world.regions)


def _regions_in_order(names: tuple[str, ...], record: RunRecord) -> Verdict:
    regions = _regions(record)
    reached: list[tuple[str, float]] = []
    closest_mm = math.inf
    for t, x, y in dense_path(record.path):
        if len(reached) == len(names):
            break
        region = regions[names[len(reached)]]
        if region.contains(x, y):
            reached.append((region.name, t))
            closest_mm = math.inf
        else:
            closest_mm = min(closest_mm, signed_distance_mm(region, x, y))
    visits = ", ".join(f"'{name}' at {_at(t)}" for name, t in reached)
    if len(reached) == len(names):
        return Verdict("regions_in_order", True, "", None, f"reached {visits}")
    missed = names[len(reached)]
    after = f" after {visits}" if reached else ""
    detail = f"never reached '{missed}'{after}"
    if math.isinf(closest_mm):
        return Verdict("regions_in_order", False, "", None, detail)
    return Verdict(
        "regions_in_order",
        False,
        f"failed by {_cm(closest_mm)}",
        None,
        f"{detail}; the closest it came was {_cm(closest_mm)} from its edge",
        -closest_mm,
        "mm",
    )


def _never_enter(names: tuple[str, ...], record: RunRecord) -> Verdict:
    regions = [_regions(record)[name] for name in names]
    first: tuple[float, str] | None = None
    closest = (math.inf, "")
    for t, x, y in dense_path(record.path):
        for region in regions:
            distance = signed_distance_mm(region, x, y)
            if distance < closest[0]:
                closest = (distance, region.name)
            if distance < 0 and first is None:
                first = (t, region.name)
    distance, name = closest
    if first is not None:
        return Verdict(
            "never_enter",
            False,
            f"failed by {_cm(distance)}",
            first[0],
            f"entered '{first[1]}' at {_at(first[0])}; the deepest was {_cm(distance)} inside"
            f" '{name}'",
            distance,
            "mm",
        )
    if math.isinf(distance):
        return Verdict("never_enter", True, "", None, "the robot never moved")
    return Verdict(
        "never_enter",
        True,
        f"passed by {_cm(distance)}",
        None,
        f"closest approach: {_cm(distance)} from '{name}'",
        distance,
        "mm",
    )


def _no_collisions(_: bool, record: RunRecord) -> Verdict:
    if record.collisions:
        count = len(record.collisions)
        hit = record.collisions[0]
        return Verdict(
            "no_collisions",
            False,
            f"failed by {_plural(count, 'collision')}",
            hit.t_s,
            f"{_plural(count, 'collision')}; the first at {_at(hit.t_s)} on the {hit.side}"
            f" bumper, at ({hit.x_mm:.0f}, {hit.y_mm:.0f}) mm",
            -float(count),
            "collisions",
        )
    walls = record.world.walls if record.world is not None else ()
    if not walls or not record.path:
        return Verdict("no_collisions", True, "", None, "no collisions")
    from roboscript.sim.geometry import segment_distance

    clearance = min(
        min(segment_distance(x, y, wall) for wall in walls) - record.body_radius_mm
        for _, x, y, _ in record.path
    )
    return Verdict(
        "no_collisions",
        True,
        f"passed by {_cm(clearance)}",
        None,
        f"no collisions; the closest the body came to a wall was {_cm(clearance)}",
        clearance,
        "mm",
    )


def _tones(rule: Tones, record: RunRecord) -> Verdict:
    played = record.tones
    n = len(played)
    heard = ", ".join(f"{t.frequency_hz:g} Hz" for t in played[:8]) + (" ..." if n > 8 else "")
    detail = f"{_plural(n, 'tone')} played" + (f" ({heard})" if played else "")
    low = rule.count if rule.count is not None else rule.min_count
    high = rule.count if rule.count is not None else rule.max_count
    if rule.frequencies_hz is not None and rule.count is None and low is None and high is None:
        low = high = len(rule.frequencies_hz)
    # Problems, each with the moment it happened (None: only knowable at the end).
    problems: list[tuple[float | None, str, float]] = []
    if high is not None and n > high:
        problems.append((played[high].t_s, f"{_plural(n - high, 'tone')} too many", n - high))
    if low is not None and n < low:
        problems.append((None, f"{_plural(low - n, 'tone')} too few", low - n))
    for i, tone in enumerate(played):
        wanted = rule.frequency_hz
        if rule.frequencies_hz is not None:
            wanted = rule.frequencies_hz[i] if i < len(rule.frequencies_hz) else None
        if wanted is not None and abs(tone.frequency_hz - wanted) > rule.tolerance_hz:
            problems.append(
                (
                    tone.t_s,
                    f"tone {i + 1} was {tone.frequency_hz:g} Hz, expected {wanted:g} Hz",
                    abs(tone.frequency_hz - wanted),
                )
            )
            break
    if not problems:
        return Verdict("tones", True, "", None, detail)
    problems.sort(key=lambda p: math.inf if p[0] is None else p[0])
    when, what, by = problems[0]
    unit = "Hz" if "expected" in what else "tones"
    margin = f"failed by {by:g} Hz" if unit == "Hz" else f"failed by {_plural(int(by), 'tone')}"
    return Verdict("tones", False, margin, when, f"{what}: {detail}", -by, unit)


def _max_duration(limit_s: float, record: RunRecord) -> Verdict:
    margin = limit_s - record.duration_s
    passed = margin >= 0
    return Verdict(
        "max_duration",
        passed,
        _by(margin, _s(margin)),
        None if passed else limit_s,
        f"the mission took {record.duration_s:.1f} s (allowed {limit_s:g} s)",
        margin,
        "s",
        margin / limit_s,
    )


def _wall_distance(rule: WallDistance, record: RunRecord) -> Verdict:
    spans = [(a, b) for a, b, name in record.state_intervals() if name == rule.state]
    band = _band_text(rule)
    if not spans:
        return Verdict(
            "wall_distance", False, "", None, f"the mission never entered state '{rule.state}'"
        )
    walls = record.world.walls if record.world is not None else ()
    worst = (math.inf, 0.0, 0.0)  # (margin, time, gap)
    first: float | None = None
    samples = 0
    for t, x, y, heading in record.path:
        if not any(a + rule.settle_s <= t < b for a, b in spans):
            continue
        samples += 1
        gap = nearest_wall_gap_mm(walls, x, y, heading, rule.side, record.side_sensor_offset_mm)
        margin = min(
            gap - rule.min_mm if rule.min_mm is not None else math.inf,
            rule.max_mm - gap if rule.max_mm is not None else math.inf,
        )
        if margin < worst[0]:
            worst = (margin, t, gap)
        if margin < 0 and first is None:
            first = t
    if samples == 0:
        return Verdict(
            "wall_distance",
            False,
            "",
            None,
            f"the robot never stayed in '{rule.state}' longer than the {rule.settle_s:g} s"
            " it is given to settle",
        )
    margin, when, gap = worst
    if math.isinf(margin) and margin > 0:
        return Verdict(
            "wall_distance", True, "", None, f"no {rule.side} wall was ever closer than allowed"
        )
    seen = "no wall in sight" if math.isinf(gap) else f"{_cm(gap)}"
    detail = (
        f"in '{rule.state}' the {rule.side} gap must stay {band};"
        f" the worst was {seen} at {_at(when)}"
    )
    if math.isinf(margin):
        return Verdict("wall_distance", False, "", first, detail)
    scale = _band_scale(rule)
    return Verdict(
        "wall_distance",
        margin >= 0,
        _by(margin, _cm(margin)),
        first,
        detail,
        margin,
        "mm",
        margin / scale if scale > 0 else None,
    )


def _band_text(rule: WallDistance) -> str:
    if rule.min_mm is not None and rule.max_mm is not None:
        return f"between {_cm(rule.min_mm)} and {_cm(rule.max_mm)}"
    if rule.min_mm is not None:
        return f"at least {_cm(rule.min_mm)}"
    return f"at most {_cm(rule.max_mm or 0.0)}"


def _band_scale(rule: WallDistance) -> float:
    if rule.min_mm is not None and rule.max_mm is not None:
        return (rule.max_mm - rule.min_mm) / 2.0
    return rule.min_mm if rule.min_mm is not None else rule.max_mm or 0.0


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


def _path_visits(rule: PathVisits, record: RunRecord) -> Verdict:
    tol = rule.tolerance_mm
    if not record.path:
        return Verdict("path_visits", False, "", None, "the run has no path")
    points = [waypoint_position(w, record.start_pose) for w in rule.waypoints]
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
            if rule.in_order:
                break
            continue
        reached[k] = _entry_time(record.path, entry, *points[k], tol)
        if rule.in_order:
            stay = entry
            while stay + 1 < len(stretches) and stretches[stay + 1][0] <= tol:
                stay += 1
            closest.append(min(stretches[entry : stay + 1]))
            begin = entry
        else:
            closest.append(min(stretches))
    missed = [k for k in range(len(closest)) if k not in reached]

    def name(k: int) -> str:
        return f"waypoint {k + 1} ({rule.waypoints[k].label})"

    if missed:
        k = missed[0]
        distance, when = closest[k]
        margin = min(tol - d for d, _ in closest)  # in order: only the missed one is judged
        detail = (
            f"missed {name(k)}: the closest the robot came was {_cm(distance)}, at {_at(when)}"
            f" (allowed {_cm(tol)})"
        )
        if rule.in_order and k > 0:
            visits = ", ".join(f"{i + 1} at {_at(reached[i])}" for i in range(k))
            detail += f", after reaching waypoint{'s' if k > 1 else ''} {visits}"
        elif len(missed) > 1:
            detail += f"; {len(missed)} of {len(closest)} waypoints missed"
        return Verdict(
            "path_visits", False, _by(margin, _cm(margin)), None, detail, margin, "mm", margin / tol
        )
    worst = max(range(len(closest)), key=lambda i: closest[i][0])
    margin = tol - closest[worst][0]
    if len(closest) == 1:
        detail = (
            f"came within {_cm(closest[0][0])} of {name(0)} at {_at(closest[0][1])}"
            f" (allowed {_cm(tol)})"
        )
    else:
        order = " in order" if rule.in_order else ""
        times = ", ".join(_at(reached[i]) for i in range(len(closest)))
        detail = (
            f"reached all {len(closest)} waypoints{order} ({times}); the farthest off was"
            f" {name(worst)}, {_cm(closest[worst][0])} away (allowed {_cm(tol)})"
        )
    return Verdict(
        "path_visits", True, _by(margin, _cm(margin)), None, detail, margin, "mm", margin / tol
    )


@dataclass(frozen=True)
class Turn:
    """One turn of a run: when it started and ended, and its angle (clockwise, right, > 0)."""

    start_s: float
    end_s: float
    angle_deg: float

    @property
    def direction(self) -> str:
        """``right`` (clockwise) or ``left``."""
        return "right" if self.angle_deg > 0 else "left"

    @property
    def text(self) -> str:
        """``91° right at 3.8 s``."""
        return f"{abs(self.angle_deg):.0f}° {self.direction} at {_at(self.start_s)}"


def _unwrapped_headings(path: Sequence[tuple[float, float, float, float]]) -> list[float]:
    """The path's headings, followed through north: 350° then 10° is 350° then 370°."""
    headings: list[float] = []
    for _, _, _, h in path:
        headings.append(h if not headings else headings[-1] + wrap_deg(h - headings[-1]))
    return headings


def find_turns(path: Sequence[tuple[float, float, float, float]]) -> list[Turn]:
    """The turns of a path: the stretches where its heading keeps changing.

    A turn starts when the robot turns faster than :data:`TURN_RATE_DEG_S` and ends once it has
    turned slower than that for :data:`TURN_PAUSE_S`; its angle is how far the heading changed
    from its start to its end, clockwise (to the right) positive. Turns smaller than
    :data:`MIN_TURN_DEG` are wobbles and left out.
    """
    headings = _unwrapped_headings(path)
    turns: list[Turn] = []
    first: int | None = None  # the sample a turn starts at
    last = 0  # its latest sample that ended a stretch of turning

    def close(a: int, b: int) -> None:
        angle = headings[b] - headings[a]
        if abs(angle) >= MIN_TURN_DEG:
            turns.append(Turn(path[a][0], path[b][0], round(angle, 1)))

    for i in range(1, len(path)):
        dt = path[i][0] - path[i - 1][0]
        if dt > 0 and abs(headings[i] - headings[i - 1]) / dt >= TURN_RATE_DEG_S:
            first = i - 1 if first is None else first
            last = i
        elif first is not None and path[i][0] - path[last][0] >= TURN_PAUSE_S - 1e-9:
            close(first, last)
            first = None
    if first is not None:
        close(first, last)
    return turns


@dataclass(frozen=True)
class _Part:
    """One condition of a compound expectation, judged."""

    passed: bool
    why: str = ""
    value: float | None = None
    unit: str = ""
    relative: float | None = None
    when: float | None = None


def _turns(rule: Turns, record: RunRecord) -> Verdict:
    turns = find_turns(record.path)
    headings = _unwrapped_headings(record.path)
    net = headings[-1] - headings[0] if headings else 0.0
    tol = rule.tolerance_deg
    parts: list[_Part] = []
    never = _Part(False, "the robot never turned")
    if rule.direction is not None:
        wrong = [t for t in turns if t.direction != rule.direction]
        if not turns:
            parts.append(never)
        elif wrong:
            worst = max(abs(t.angle_deg) for t in wrong)
            parts.append(
                _Part(
                    False,
                    f"turned {wrong[0].text}; this test wants {rule.direction} turns only",
                    -worst,
                    "deg",
                    None,
                    wrong[0].start_s,
                )
            )
        else:
            parts.append(_Part(True))
    if rule.count is not None:
        n, wanted = len(turns), rule.count
        why = f"{_plural(n, 'turn')}, expected {wanted}"
        when = turns[wanted].start_s if n > wanted else None  # too few has no moment
        short = float(wanted - n) if n > wanted else float(n - wanted) if n < wanted else None
        parts.append(_Part(n == wanted, why, short, "turns", None, when))
    if rule.angle_deg is not None:
        if not turns:
            parts.append(never)
        else:
            errors = [abs(t.angle_deg) - rule.angle_deg for t in turns]
            worst = max(range(len(turns)), key=lambda i: abs(errors[i]))
            margin = tol - abs(errors[worst])
            bad = next((i for i, e in enumerate(errors) if abs(e) > tol), worst)
            parts.append(
                _Part(
                    margin >= 0,
                    f"turn {bad + 1} was {turns[bad].text}, expected {rule.angle_deg:g}°"
                    f" ± {tol:g}°",
                    margin,
                    "deg",
                    margin / tol,
                    turns[bad].end_s if margin < 0 else None,
                )
            )
    if rule.total_deg is not None:
        sign = {"right": 1.0, "left": -1.0}.get(rule.direction or "")
        error = net - sign * rule.total_deg if sign else abs(net) - rule.total_deg
        margin = tol - abs(error)
        way = "right" if net >= 0 else "left"
        wanted_way = f" {rule.direction}" if rule.direction else ""
        parts.append(
            _Part(
                margin >= 0,
                f"turned {abs(net):.0f}° {way} in all, expected {rule.total_deg:g}°{wanted_way}"
                f" ± {tol:g}°",
                margin,
                "deg",
                margin / tol,
                record.duration_s if margin < 0 else None,
            )
        )
    shown = ", ".join(t.text for t in turns[:6]) + (" ..." if len(turns) > 6 else "")
    seen = f"{_plural(len(turns), 'turn')}" + (f" ({shown})" if turns else "")
    seen += f", {abs(net):.0f}° {'right' if net >= 0 else 'left'} in all"
    failed = [p for p in parts if not p.passed]
    if failed:
        part = failed[0]
        return Verdict(
            "turns",
            False,
            _turns_margin(part),
            part.when,
            f"{part.why}; {seen}" if turns else part.why,
            part.value,
            part.unit,
            part.relative,
        )
    measured = [p for p in parts if p.relative is not None]
    if not measured:
        return Verdict("turns", True, "", None, seen)
    part = min(measured, key=lambda p: p.relative if p.relative is not None else math.inf)
    return Verdict(
        "turns", True, _turns_margin(part), None, seen, part.value, part.unit, part.relative
    )


def _turns_margin(part: _Part) -> str:
    if part.value is None:
        return ""
    if part.unit == "turns":
        return _by(part.value, _plural(int(abs(part.value)), "turn"))
    return _by(part.value, _deg(part.value))


def _wall_ahead(rule: WallAhead, record: RunRecord) -> Verdict:
    x, y, heading = record.final_pose
    walls = list(record.world.walls) if record.world is not None else []
    dx, dy = heading_vector(heading)
    hit = ray_cast(x, y, dx, dy, walls, math.inf)
    wanted = f"wanted {_cm(rule.distance_mm)} ± {_cm(rule.tolerance_mm)}"
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
    error = gap - rule.distance_mm
    margin = rule.tolerance_mm - abs(error)
    how = "" if margin >= 0 else (" (too close)" if error < 0 else " (too far)")
    return Verdict(
        "wall_ahead_at_end",
        margin >= 0,
        _by(margin, _cm(margin)),
        None if margin >= 0 else record.duration_s,
        f"stopped {gap / 10.0:.1f} cm from the wall ahead{how}, measured from the front of the"
        f" robot straight ahead; {wanted}",
        margin,
        "mm",
        margin / rule.tolerance_mm,
    )


def _check(ref: CheckFunction, record: RunRecord) -> Verdict:
    name = f"check: {ref.function}"
    try:
        function = _load_check(ref)
        answer = function(record)
    except Exception as exc:  # noqa: BLE001 - any fault of the teacher's code fails this check only
        where = traceback.extract_tb(exc.__traceback__)[-1]
        return Verdict(
            name,
            False,
            "",
            None,
            f"the teacher's check raised {type(exc).__name__}: {exc}"
            f" ({Path(where.filename).name}:{where.lineno})",
        )
    if isinstance(answer, Verdict):
        return answer
    if isinstance(answer, bool):
        return Verdict(name, answer)
    if (
        isinstance(answer, tuple)
        and len(answer) == 2
        and isinstance(answer[0], bool)
        and isinstance(answer[1], str)
    ):
        return Verdict(name, answer[0], "", None, answer[1])
    return Verdict(
        name,
        False,
        "",
        None,
        f"the teacher's check returned {type(answer).__name__}; it must return True/False,"
        " (True/False, message) or a Verdict",
    )


def _load_check(ref: CheckFunction) -> Callable[[RunRecord], object]:
    module_name = f"roboscript_teacher_check_{zlib.crc32(ref.path.encode()):08x}"
    module = sys.modules.get(module_name)
    if module is None:
        spec = importlib.util.spec_from_file_location(module_name, ref.path)
        if spec is None or spec.loader is None:
            raise ImportError(f"cannot import {ref.path}")
        module = importlib.util.module_from_spec(spec)
        sys.modules[module_name] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[module_name]
            raise
    function = getattr(module, ref.function)
    if not callable(function):
        raise TypeError(f"{ref.function} is not a function")
    return function  # type: ignore[no-any-return]


_JUDGES: dict[str, Callable[[Any, RunRecord], Verdict]] = {
    "outcome": _outcome,
    "final_state": _final_state,
    "final_pose_within": _final_pose,
    "regions_in_order": _regions_in_order,
    "never_enter": _never_enter,
    "no_collisions": _no_collisions,
    "tones": _tones,
    "max_duration": _max_duration,
    "wall_distance": _wall_distance,
    "path_visits": _path_visits,
    "turns": _turns,
    "wall_ahead_at_end": _wall_ahead,
    "check": _check,
}
