"""Expectations: what a teacher's test spec says must happen, and how each is judged.

Each kind of expectation (``outcome``, ``final_pose_within``, ``wall_distance``...) is one
class of this package (:class:`~roboscript.grading.expectations.base.Rule`): its fields are
the parameters read from the spec, and it judges a
:class:`~roboscript.grading.record.RunRecord`, returning a
:class:`~roboscript.grading.record.Verdict` with a signed margin ("passed by 2.1 cm", "failed
by 0.4 s") and, where failing has a moment, the mission time of the first violation.
Defining a kind's class registers it (:data:`KINDS`); the modules below are imported in the
order teachers see the kinds listed.

What a run is judged on is what the world recorded after the mission started. Where a kind
judges part of a run, it selects that part from the world's record (:class:`Selection`), not
from the mission's account of its states, unless the spec asks for a state by name.

A teacher's own ``check: file.py:function`` is imported and called in the grading worker,
never in the process that reads the spec. A run of the spec may give expectations targets of
its own (``runs: [{seed: 2, expect: {KIND: {key: value}}}]``, :func:`apply_run_targets`); the
run is told from its record when judged (:class:`RunTargets`).
"""

from __future__ import annotations

from roboscript.grading.expectations.base import (
    KINDS,
    Canvas,
    Expectation,
    Rule,
    RunKey,
    RunTargets,
    SpecContext,
    evaluate,
)

# isort: off
# Kinds register as their classes are defined: this order is the order teachers see them in.
from roboscript.grading.expectations.outcome import FinalState, Outcome
from roboscript.grading.expectations.final_pose import (
    DEFAULT_HEADING_TOLERANCE_DEG,
    FinalPose,
    final_pose_target,
)
from roboscript.grading.expectations.regions import NeverEnter, RegionsInOrder
from roboscript.grading.expectations.collisions import NoCollisions
from roboscript.grading.expectations.tones import DEFAULT_TONE_TOLERANCE_HZ, Tones
from roboscript.grading.expectations.duration import MaxDuration
from roboscript.grading.expectations.wall_distance import WallDistance
from roboscript.grading.expectations.path_visits import (
    DEFAULT_WAYPOINT_TOLERANCE_MM,
    PathVisits,
    Waypoint,
    waypoint_position,
)
from roboscript.grading.expectations.turns import (
    DEFAULT_TURN_TOLERANCE_DEG,
    Turn,
    Turns,
    find_turns,
)
from roboscript.grading.expectations.wall_ahead import DEFAULT_WALL_AHEAD_TOLERANCE_MM, WallAhead
from roboscript.grading.expectations.check import CheckFunction

# isort: on
from roboscript.grading.expectations.reading import (
    RunOverride,
    apply_run_targets,
    parse_expectation,
)
from roboscript.grading.expectations.selection import DEFAULT_SETTLE_S, Selection

__all__ = [
    "DEFAULT_HEADING_TOLERANCE_DEG",
    "DEFAULT_SETTLE_S",
    "DEFAULT_TONE_TOLERANCE_HZ",
    "DEFAULT_TURN_TOLERANCE_DEG",
    "DEFAULT_WALL_AHEAD_TOLERANCE_MM",
    "DEFAULT_WAYPOINT_TOLERANCE_MM",
    "KINDS",
    "Canvas",
    "CheckFunction",
    "Expectation",
    "FinalPose",
    "FinalState",
    "MaxDuration",
    "NeverEnter",
    "NoCollisions",
    "Outcome",
    "PathVisits",
    "RegionsInOrder",
    "Rule",
    "RunKey",
    "RunOverride",
    "RunTargets",
    "Selection",
    "SpecContext",
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
