"""What every kind of expectation is: a class that reads, judges, names and draws itself.

Each kind (``outcome``, ``wall_distance``, ...) is one frozen dataclass extending :class:`Rule`:
its fields are the kind's parameters as the spec gives them, and its methods are everything
the grader does with it. Defining the class registers the kind under its ``kind`` name in
:data:`KINDS`, once; nothing else lists the kinds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar, Protocol

from roboscript.angles import wrap_deg
from roboscript.grading.record import RunRecord, Verdict
from roboscript.inputs.fields import FieldReader
from roboscript.inputs.source import Location, Mark
from roboscript.sim.world import World

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: Python 3.10 has no typing.Self

__all__ = [
    "KINDS",
    "Canvas",
    "Expectation",
    "Rule",
    "RunKey",
    "RunTargets",
    "SpecContext",
    "evaluate",
    "start_mismatch",
]


@dataclass(frozen=True)
class SpecContext:
    """What expectations are checked against while a spec is read.

    Attributes:
        folder: The spec's folder (a ``check`` file is found relative to it).
        worlds: Every world the spec's runs use (region names must exist in each).
    """

    folder: Path
    worlds: tuple[World, ...]


class Canvas(Protocol):
    """Where a kind draws on the picture of a run (world millimetres; the picture styles it)."""

    def target_circle(self, x_mm: float, y_mm: float, radius_mm: float, title: str) -> str:
        """A dashed circle the robot had to end inside, as SVG."""
        ...


KINDS: dict[str, type[Rule]] = {}
"""Every expectation a spec may use, by the name a spec writes, in the order they are listed
to teachers (the order their classes are defined in)."""


class Rule:
    """One kind of expectation with its parameters: what a spec demands of a run.

    A subclass sets ``kind`` (the name a spec writes) and is a frozen dataclass of the kind's
    parameters. It reads itself from a spec (:meth:`parse`), judges a run's record
    (:meth:`judge`), says how reports name it (:meth:`describe`) and may draw its target on
    the picture of a run (:meth:`draw`).
    """

    kind: ClassVar[str]

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in vars(cls):
            if cls.kind in KINDS:
                raise TypeError(f"two expectation kinds are called '{cls.kind}'")
            KINDS[cls.kind] = cls

    @classmethod
    def parse(cls, reader: FieldReader, value: object, mark: Mark, ctx: SpecContext) -> Self:
        """Read the kind's value as written in a spec (``value`` written at ``mark``).

        Raises:
            SpecError: At the mistake, through ``reader``.
        """
        raise NotImplementedError

    def judge(self, record: RunRecord) -> Verdict:
        """Whether a run held to this expectation, by how much, and from when it did not."""
        raise NotImplementedError

    def describe(self) -> str:
        """How reports name this expectation (its kind, unless a kind says more)."""
        return self.kind

    def draw(self, record: RunRecord, canvas: Canvas) -> list[str]:
        """SVG elements that show this expectation's target on ``record``'s picture (none)."""
        return []


RunKey = tuple[str, int, tuple[float, float, float]]
"""How a run is recognised from its record: world name, seed, start pose ``(x, y, heading)``."""


def start_mismatch(start: tuple[float, float, float], x: float, y: float, h: float) -> float:
    """How unlike two start poses are: millimetres, with 10 mm per degree of heading."""
    turn = abs(wrap_deg(start[2] - h))
    return math.hypot(start[0] - x, start[1] - y) + 10.0 * turn


@dataclass(frozen=True)
class RunTargets:
    """The parameters of an expectation that some runs give targets of their own.

    A record does not name its run, so the run is recognised by what the record holds: its
    world's name and seed, then the start pose nearest to the record's (two runs alike in all
    three but their targets are refused when the spec is read, see
    :func:`~roboscript.grading.expectations.reading.apply_run_targets`).

    Attributes:
        default: The parameters written in the spec's ``expect``.
        runs: Every run's key and its parameters (the default, or its own).
    """

    default: Rule
    runs: tuple[tuple[RunKey, Rule], ...]

    def for_record(self, record: RunRecord) -> Rule:
        """The parameters for the run this record is of (the default for an unknown run)."""
        same = [
            (key, rule)
            for key, rule in self.runs
            if key[0] == record.world_name and key[1] == record.seed
        ]
        if not same:
            return self.default
        x, y, heading = record.start_pose
        return min(same, key=lambda run: start_mismatch(run[0][2], x, y, heading))[1]


@dataclass(frozen=True)
class Expectation:
    """One line of a spec's ``expect`` list.

    Attributes:
        rule: What it demands (an instance of one of the :data:`KINDS`).
        weight: Its share of a run's score.
        location: Where it was written.
        required: A run that fails it scores 0, whatever else held.
        targets: The rules of runs that give targets of their own, or ``None``.
    """

    rule: Rule
    weight: float = 1.0
    location: Location | None = None
    required: bool = False
    targets: RunTargets | None = None

    @property
    def kind(self) -> str:
        """Which expectation (a key of :data:`KINDS`)."""
        return self.rule.kind

    @property
    def name(self) -> str:
        """How reports name it: the kind, or ``check: function`` for a teacher's check."""
        return self.rule.describe()

    def for_record(self, record: RunRecord) -> Rule:
        """The rule for the run ``record`` is of (see :class:`RunTargets`)."""
        return self.rule if self.targets is None else self.targets.for_record(record)


def evaluate(expectation: Expectation, record: RunRecord) -> Verdict:
    """Judge one expectation on a run's record (the teacher's ``check`` is imported here)."""
    verdict = expectation.for_record(record).judge(record)
    return replace(
        verdict,
        name=expectation.name,
        weight=expectation.weight,
        required=expectation.required,
    )
