"""Expectations: what a teacher's test spec says must happen, and how each is judged.

Each kind of expectation (``outcome``, ``final_pose_within``, ``wall_distance``...) has a
parameter dataclass read from the spec (:func:`parse_expectation`) and a judge: a pure function
of a :class:`~roboscript.grading.record.RunRecord` returning a
:class:`~roboscript.grading.record.Verdict` with a signed margin ("passed by 2.1 cm", "failed
by 0.4 s") and, where failing has a moment, the mission time of the first violation.

A teacher's own ``check: file.py:function`` is imported and called in the grading worker, never
in the process that reads the spec.
"""

from __future__ import annotations

import ast
import importlib.util
import math
import sys
import traceback
import zlib
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from roboscript.errors import did_you_mean
from roboscript.grading.reader import SpecReader
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.regions import dense_path, nearest_wall_gap_mm, signed_distance_mm
from roboscript.mission.source import Mark, YamlMap
from roboscript.mission.spec import Location
from roboscript.sim.world import World

__all__ = [
    "EXPECTATION_KINDS",
    "CheckFunction",
    "Expectation",
    "FinalPose",
    "Tones",
    "WallDistance",
    "evaluate",
    "final_pose_target",
    "parse_expectation",
]

DEFAULT_TONE_TOLERANCE_HZ = 5.0
DEFAULT_HEADING_TOLERANCE_DEG = 15.0
DEFAULT_SETTLE_S = 1.0


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


Parser = Callable[[SpecReader, Any, Mark, SpecContext], Any]


def _parse_outcome(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> str:
    if value not in ("success", "failure"):
        hint = did_you_mean(str(value), ("success", "failure"))
        raise reader.fail(f"outcome must be success or failure (got {value!r})", mark, hint)
    return str(value)


def _parse_final_state(
    reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    holder = YamlMap.at(mark, {"final_state": value})
    return tuple(name for name, _ in reader.names(holder, "final_state"))


def _parse_final_pose(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> FinalPose:
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
    reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext, key: str
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
    reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    return _region_names(reader, value, mark, ctx, "regions_in_order")


def _parse_never_enter(
    reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext
) -> tuple[str, ...]:
    return _region_names(reader, value, mark, ctx, "never_enter")


def _parse_no_collisions(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> bool:
    if value is not True:
        raise reader.fail(
            f"write 'no_collisions: true' (got {value!r}); leave it out to allow collisions",
            mark,
        )
    return True


def _parse_tones(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> Tones:
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


def _frequency(reader: SpecReader, value: Any, mark: Mark) -> float:
    holder = YamlMap.at(mark, {"frequency": value})
    return reader.positive(holder, "frequency", "frequency", "Hz")


def _parse_max_duration(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> float:
    holder = YamlMap.at(mark, {"max_duration": value})
    return reader.positive(holder, "max_duration", "time", "s")


def _parse_wall_distance(
    reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext
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


def _parse_check(reader: SpecReader, value: Any, mark: Mark, ctx: SpecContext) -> CheckFunction:
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
    "check": _parse_check,
}
"""Every expectation a spec may use, with its reader."""


def parse_expectation(reader: SpecReader, item: Any, mark: Mark, ctx: SpecContext) -> Expectation:
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


# ------------------------------------------------------------------------------- evaluate


def evaluate(expectation: Expectation, record: RunRecord) -> Verdict:
    """Judge one expectation on a run's record (the teacher's ``check`` is imported here)."""
    judge = _JUDGES[expectation.kind]
    verdict = judge(expectation.params, record)
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
        error = (heading - target.heading_deg + 180.0) % 360.0 - 180.0
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
    "check": _check,
}
