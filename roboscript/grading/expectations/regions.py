"""Where the robot went among the world's regions: ``regions_in_order`` and ``never_enter``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from roboscript.errors import did_you_mean
from roboscript.grading.expectations.base import Rule, SpecContext
from roboscript.grading.expectations.words import at, cm
from roboscript.grading.record import RunRecord, Verdict
from roboscript.grading.regions import dense_path, signed_distance_mm
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Mark, YamlMap
from roboscript.sim.world import Region

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = ["NeverEnter", "RegionsInOrder", "read_region_names", "world_regions"]


def read_region_names(
    reader: FieldReader, value: object, mark: Mark, ctx: SpecContext, key: str
) -> tuple[str, ...]:
    """A name or a list of names (written under ``key``) of regions every run's world has.

    Raises:
        SpecError: At a name some world lacks, with that world's regions and a "did you mean".
    """
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


def world_regions(record: RunRecord) -> dict[str, Region]:
    """The regions of the world ``record`` happened in."""
    if record.world is None:
        raise ValueError("this record has no world to find its regions in")
    return dict(record.world.regions)


@dataclass(frozen=True)
class _RegionRule(Rule):
    """A kind whose value is the names of world regions (one name or a list)."""

    names: tuple[str, ...]

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        return cls(read_region_names(reader, value, mark, ctx, cls.kind))


@dataclass(frozen=True)
class RegionsInOrder(_RegionRule):
    """``regions_in_order: [a, b]``: the robot's centre enters each region, in this order."""

    kind = "regions_in_order"

    def judge(self, record: RunRecord) -> Verdict:
        regions = world_regions(record)
        names = self.names
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
        visits = ", ".join(f"'{name}' at {at(t)}" for name, t in reached)
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
            f"failed by {cm(closest_mm)}",
            None,
            f"{detail}; the closest it came was {cm(closest_mm)} from its edge",
            -closest_mm,
            "mm",
        )


@dataclass(frozen=True)
class NeverEnter(_RegionRule):
    """``never_enter: [pit]``: the robot's centre never enters any of these regions."""

    kind = "never_enter"

    def judge(self, record: RunRecord) -> Verdict:
        regions = [world_regions(record)[name] for name in self.names]
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
                f"failed by {cm(distance)}",
                first[0],
                f"entered '{first[1]}' at {at(first[0])}; the deepest was {cm(distance)} inside"
                f" '{name}'",
                distance,
                "mm",
            )
        if math.isinf(distance):
            return Verdict("never_enter", True, "", None, "the robot never moved")
        return Verdict(
            "never_enter",
            True,
            f"passed by {cm(distance)}",
            None,
            f"closest approach: {cm(distance)} from '{name}'",
            distance,
            "mm",
        )
