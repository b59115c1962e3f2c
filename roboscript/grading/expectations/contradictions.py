"""Expectations no run can meet: refused when a spec is read, naming the lines that clash.

A spec written quickly may ask for two things no mission can do at once (``outcome: success``
and ``outcome: failure``; ``never_enter: pit`` and ``regions_in_order: [start, pit]``; a
``wall_distance`` judged from 20 s on with ``max_duration: 10 s``), or for one thing no run of
it can do (``never_enter`` a region a run starts in). Every student would fail it, whatever
they wrote, so the spec is refused at the later of the two lines, with one sentence naming
the other line and why both cannot hold.

Each run is checked with its own targets (``runs: [{expect: ...}]``), where it has any.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from roboscript.angles import wrap_deg
from roboscript.grading.expectations.base import Expectation, Rule
from roboscript.grading.expectations.duration import MaxDuration
from roboscript.grading.expectations.final_pose import FinalPose
from roboscript.grading.expectations.outcome import FinalState, Outcome
from roboscript.grading.expectations.path_visits import PathVisits, waypoint_position
from roboscript.grading.expectations.regions import NeverEnter, RegionsInOrder
from roboscript.grading.expectations.tones import Tones
from roboscript.grading.expectations.turns import TURN_PAUSE_S, Turns
from roboscript.grading.expectations.wall_ahead import WallAhead
from roboscript.grading.expectations.wall_distance import WallDistance
from roboscript.grading.regions import enclosing_walls, signed_distance_mm
from roboscript.sim.world import World

__all__ = ["RunSetup", "find_contradiction"]


@dataclass(frozen=True)
class RunSetup:
    """One run of a spec, as its expectations are checked against it.

    Attributes:
        number: The run's number as teachers count (1 for the first).
        world: Its world.
        start: Where it starts: ``(x_mm, y_mm, heading_deg)``.
    """

    number: int
    world: World
    start: tuple[float, float, float]


def find_contradiction(
    expectations: Sequence[Expectation], runs: Sequence[RunSetup], max_time_s: float
) -> tuple[Expectation, str] | None:
    """The first expectation no run can meet (alone, or with an earlier one), and one
    sentence saying why, naming the other line; ``None`` when every run could pass."""
    for index, run in enumerate(runs):
        rules = [_rule_for(e, index) for e in expectations]
        for b, later in enumerate(expectations):
            why = _impossible(rules[b], run, max_time_s)
            if why:
                return later, f"no run can pass this {later.kind}: {why}"
            for a, earlier in enumerate(expectations[:b]):
                why = _clash(rules[a], rules[b], run) or _clash(rules[b], rules[a], run)
                if why:
                    own = _is_own(earlier, rules[a]) or _is_own(later, rules[b])
                    whose = f" (run {run.number}'s targets)" if own else ""
                    return later, (
                        f"this {later.kind} contradicts the {earlier.kind} on line"
                        f" {_line(earlier)}{whose}: {why}"
                    )
    return None


def _rule_for(expectation: Expectation, run_index: int) -> Rule:
    """What ``expectation`` demands of the run at ``run_index``: its own targets, if it gives
    any, else what the spec's ``expect`` says."""
    targets = expectation.targets
    if targets is None or run_index >= len(targets.runs):
        return expectation.rule
    return targets.runs[run_index][1]


def _is_own(expectation: Expectation, rule: Rule) -> bool:
    """Whether ``rule`` is a run's own targets for ``expectation``, not the spec's."""
    return expectation.targets is not None and rule != expectation.targets.default


def _line(expectation: Expectation) -> str:
    """The spec's line ``expectation`` is written on, for a sentence."""
    return str(expectation.location.line) if expectation.location else "?"


def _impossible(rule: Rule, run: RunSetup, max_time_s: float) -> str | None:
    """Why no run could meet ``rule`` alone, or ``None``."""
    if isinstance(rule, NeverEnter):
        x, y, _ = run.start
        for name in rule.names:
            region = run.world.regions.get(name)
            if region is not None and signed_distance_mm(region, x, y) < 0:
                return (
                    f"run {run.number} starts inside '{name}' ({round(x)}, {round(y)}) mm, so"
                    " the robot is in it before it moves"
                )
    shut_in = _outside_the_walls(rule, run)
    if shut_in:
        return shut_in
    if isinstance(rule, Turns) and rule.count == 0:
        if rule.direction is not None:
            return f"count: 0 means no turn, and direction: {rule.direction} needs turns"
        if rule.angle_deg is not None:
            return "count: 0 means no turn, and angle needs each turn to be that size"
    if isinstance(rule, Turns):
        too_many = _turns_past(rule, max_time_s, "every run ends by the spec's max_time of")
        if too_many:
            return too_many
    if isinstance(rule, WallDistance):
        judged_from_s = _judged_from_s(rule)
        if judged_from_s is not None and judged_from_s >= max_time_s:
            return (
                f"it judges from {judged_from_s:g} s on (with its settle time), but every run"
                f" ends by the spec's max_time of {max_time_s:g} s"
            )
    return None


def _outside_the_walls(rule: Rule, run: RunSetup) -> str | None:
    """Why ``rule`` asks the robot to reach a place outside the walls that shut its start in
    (a target 5 m east of a 2 m room), or ``None``."""
    if not isinstance(rule, FinalPose | PathVisits | RegionsInOrder):
        return None
    box = enclosing_walls(run.world.walls, run.start[0], run.start[1])
    if box is None:
        return None
    x_min, y_min, x_max, y_max = box

    def beyond_mm(x: float, y: float) -> float:
        """How far the point is outside the walls' box (0 inside it)."""
        return math.hypot(max(x_min - x, 0.0, x - x_max), max(y_min - y, 0.0, y - y_max))

    places: list[tuple[str, float, float, float]] = []  # (what, x, y, how near counts)
    if isinstance(rule, FinalPose):
        target = rule.at_start(run.start)
        places.append(("the circle it must end in", target.x_mm, target.y_mm, target.radius_mm))
    elif isinstance(rule, PathVisits):
        for waypoint in rule.waypoints:
            x, y = waypoint_position(waypoint, run.start)
            places.append((f"the waypoint at ({round(x)}, {round(y)}) mm", x, y, rule.tolerance_mm))
    else:
        for name in rule.names:
            region = run.world.regions.get(name)
            if region is not None and region.radius_mm is not None:
                x, y = region.center
                places.append((f"'{name}'", x, y, region.radius_mm))
            elif region is not None and region.points:
                # the point of the region's own box nearest the walls' box: a region may cross
                # the room with every corner outside it, so its corners alone cannot say
                xs = [p[0] for p in region.points]
                ys = [p[1] for p in region.points]
                near_x = _nearest_in(min(xs), max(xs), x_min, x_max)
                near_y = _nearest_in(min(ys), max(ys), y_min, y_max)
                places.append((f"'{name}'", near_x, near_y, 0.0))
    for what, x, y, reach_mm in places:
        if beyond_mm(x, y) > reach_mm:
            return (
                f"{what} lies outside the walls of '{run.world.name}' that shut in run"
                f" {run.number}'s start, so the robot can never get there"
            )
    return None


def _nearest_in(low: float, high: float, wall_low: float, wall_high: float) -> float:
    """The value of ``[low, high]`` nearest ``[wall_low, wall_high]`` (one they share if any)."""
    if high < wall_low:
        return high
    if low > wall_high:
        return low
    return max(low, wall_low)


def _turns_past(rule: Turns, limit_s: float, limit: str) -> str | None:
    """Why ``rule``'s count of turns cannot fit in ``limit_s`` (``limit``, words ending before
    the time), or ``None``: a turn ends only
    once the robot has turned slowly for ``TURN_PAUSE_S``, so every turn but the last takes
    at least that long."""
    if rule.count is None or rule.count <= 1:
        return None
    least_s = round((rule.count - 1) * TURN_PAUSE_S, 6)
    if least_s < limit_s:
        return None
    return (
        f"{rule.count} turns take at least {least_s:g} s (each turn but the last ends only"
        f" after {TURN_PAUSE_S:g} s of turning slowly), but {limit} {limit_s:g} s"
    )


def _judged_from_s(rule: WallDistance) -> float | None:
    """The earliest moment a ``wall_distance`` judges: its ``during: {from: ...}`` (0 s
    without one) and its settle time, as every stretch it judges starts no earlier."""
    selection = rule.selection
    if selection.state is not None:
        return None
    return (selection.from_s or 0.0) + selection.settle_s


def _clash(a: Rule, b: Rule, run: RunSetup) -> str | None:
    """Why no run could meet both ``a`` and ``b`` (in this order), or ``None``."""
    check = _CLASHES.get((type(a), type(b)))
    return check(a, b, run) if check is not None else None


def _outcomes_clash(a: Outcome, b: Outcome, run: RunSetup) -> str | None:
    if a.wanted == b.wanted:
        return None
    return f"a mission ends in {a.wanted} or in {b.wanted}, not both"


def _final_states_clash(a: FinalState, b: FinalState, run: RunSetup) -> str | None:
    if set(a.names) & set(b.names):
        return None
    return (
        "a mission ends in one state, and they name different ones"
        f" ({_names(a.names)} and {_names(b.names)})"
    )


def _tones_clash(a: Tones, b: Tones, run: RunSetup) -> str | None:
    low_a, high_a = _tone_counts(a)
    low_b, high_b = _tone_counts(b)
    if low_a > high_b or low_b > high_a:
        return (
            f"one wants {_count_range(low_a, high_a)} tones and the other"
            f" {_count_range(low_b, high_b)}"
        )
    # Past the longer list of frequencies every tone is wanted alike, so one index more tells
    # them all: a count of a billion is not a billion comparisons.
    listed = max((len(r.frequencies_hz) for r in (a, b) if r.frequencies_hz is not None), default=0)
    for i in range(int(min(max(low_a, low_b), listed + 1))):  # tones both say must be played
        wanted_a, wanted_b = a.wanted_hz(i), b.wanted_hz(i)
        if wanted_a is None or wanted_b is None:
            continue
        if abs(wanted_a - wanted_b) > a.tolerance_hz + b.tolerance_hz:
            return (
                f"tone {i + 1} cannot be both {wanted_a:g} Hz (±{a.tolerance_hz:g}) and"
                f" {wanted_b:g} Hz (±{b.tolerance_hz:g})"
            )
    return None


def _turns_clash(a: Turns, b: Turns, run: RunSetup) -> str | None:
    if a.count is not None and b.count is not None and a.count != b.count:
        return f"one wants {a.count} turns and the other {b.count}"
    if a.direction is not None and b.direction is not None and a.direction != b.direction:
        return f"one wants {a.direction} turns only and the other {b.direction} turns only"
    return None


def _walls_ahead_clash(a: WallAhead, b: WallAhead, run: RunSetup) -> str | None:
    if abs(a.distance_mm - b.distance_mm) <= a.tolerance_mm + b.tolerance_mm:
        return None
    return (
        f"the wall ahead at the end cannot be both {_mm(a.distance_mm)}"
        f" ± {_mm(a.tolerance_mm)} and {_mm(b.distance_mm)} ± {_mm(b.tolerance_mm)} away"
    )


def _wall_distances_clash(a: WallDistance, b: WallDistance, run: RunSetup) -> str | None:
    if a.side != b.side or a.selection != b.selection:
        return None
    low = max(a.min_mm or 0.0, b.min_mm or 0.0)
    high = min(
        a.max_mm if a.max_mm is not None else math.inf,
        b.max_mm if b.max_mm is not None else math.inf,
    )
    if low <= high:
        return None
    return f"over the same stretch the {a.side} gap cannot stay both {a.band} and {b.band}"


def _duration_and_wall_distance_clash(a: MaxDuration, b: WallDistance, run: RunSetup) -> str | None:
    judged_from_s = _judged_from_s(b)
    if judged_from_s is None or judged_from_s < a.limit_s:
        return None
    return (
        f"the mission must end within {a.limit_s:g} s, but the wall_distance judges only"
        f" from {judged_from_s:g} s on (with its settle time)"
    )


def _duration_and_turns_clash(a: MaxDuration, b: Turns, run: RunSetup) -> str | None:
    return _turns_past(b, a.limit_s, "the mission must end within")


def _never_enter_clash(never: NeverEnter, other: Rule, run: RunSetup) -> str | None:
    """Why no run could keep out of ``never``'s regions and meet ``other``, or ``None``."""
    regions = run.world.regions
    forbidden = {name: regions[name] for name in never.names if name in regions}
    if isinstance(other, RegionsInOrder):
        both = [name for name in other.names if name in forbidden]
        if both:
            return f"the robot must enter '{both[0]}' for one and never enter it for the other"
    selected = other.selection.regions if isinstance(other, WallDistance) else ()
    if selected and all(name in forbidden for name in selected):
        return (
            f"the wall_distance judges only inside {_names(selected)}, which the robot must"
            " never enter"
        )
    if isinstance(other, FinalPose):
        target = other.at_start(run.start)
        for name, region in forbidden.items():
            if signed_distance_mm(region, target.x_mm, target.y_mm) + target.radius_mm <= 0:
                return (
                    f"the circle the robot must end in lies wholly inside '{name}', which it"
                    " must never enter"
                )
    if isinstance(other, PathVisits):
        for waypoint in other.waypoints:
            x, y = waypoint_position(waypoint, run.start)
            for name, region in forbidden.items():
                if signed_distance_mm(region, x, y) + other.tolerance_mm <= 0:
                    return (
                        f"the path must come within {_mm(other.tolerance_mm)} of a waypoint"
                        f" at ({round(x)}, {round(y)}) mm, which lies that deep inside"
                        f" '{name}', which the robot must never enter"
                    )
    return None


def _final_poses_clash(a: FinalPose, b: FinalPose, run: RunSetup) -> str | None:
    one, two = a.at_start(run.start), b.at_start(run.start)
    apart_mm = math.hypot(one.x_mm - two.x_mm, one.y_mm - two.y_mm)
    if apart_mm > one.radius_mm + two.radius_mm:
        return (
            f"the robot cannot end in both circles: their centres are {_mm(apart_mm)} apart,"
            f" more than their radii ({_mm(one.radius_mm)} and {_mm(two.radius_mm)}) together"
        )
    if one.heading_deg is not None and two.heading_deg is not None:
        apart_deg = abs(wrap_deg(one.heading_deg - two.heading_deg))
        if apart_deg > one.heading_tolerance_deg + two.heading_tolerance_deg:
            return (
                f"the robot cannot end facing both {one.heading_deg:g}° and"
                f" {two.heading_deg:g}° (±{one.heading_tolerance_deg:g}° and"
                f" ±{two.heading_tolerance_deg:g}°)"
            )
    return None


def _tone_counts(rule: Tones) -> tuple[float, float]:
    """The tone counts ``rule`` allows, as ``(fewest, most)``, unbounded ones made numbers."""
    low, high = rule.counts()
    return (low or 0.0, math.inf if high is None else high)


def _count_range(low: float, high: float) -> str:
    if low == high:
        return f"{low:g}"
    if math.isinf(high):
        return f"at least {low:g}"
    return f"{low:g} to {high:g}"


def _names(names: Sequence[str]) -> str:
    return " or ".join(f"'{name}'" for name in names)


def _mm(value_mm: float) -> str:
    """A length as teachers write it: ``25 cm`` from 10 cm up, else ``8 mm``."""
    return f"{value_mm / 10:g} cm" if abs(value_mm) >= 100 else f"{value_mm:g} mm"


_CLASHES: dict[tuple[type[Rule], type[Rule]], Callable[[Any, Any, RunSetup], str | None]] = {
    (Outcome, Outcome): _outcomes_clash,
    (FinalState, FinalState): _final_states_clash,
    (FinalPose, FinalPose): _final_poses_clash,
    (Tones, Tones): _tones_clash,
    (Turns, Turns): _turns_clash,
    (WallAhead, WallAhead): _walls_ahead_clash,
    (WallDistance, WallDistance): _wall_distances_clash,
    (MaxDuration, WallDistance): _duration_and_wall_distance_clash,
    (MaxDuration, Turns): _duration_and_turns_clash,
    **{
        (NeverEnter, other): _never_enter_clash
        for other in (RegionsInOrder, WallDistance, FinalPose, PathVisits)
    },
}
"""Which pairs of kinds can contradict each other, and how to tell (each pair in one order:
:func:`find_contradiction` tries both)."""
