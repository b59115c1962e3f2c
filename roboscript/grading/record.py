"""What a graded run leaves behind: the record of what happened, verdicts, and the run's result.

Everything here is plain frozen data that turns into JSON-ready dictionaries and back
(:meth:`RunResult.to_dict`, :meth:`RunResult.from_dict`); the record of a run is ``run
--json``'s (:class:`~roboscript.run_record.RunRecord`) with what grading adds
(:class:`GradedRecord`). So a run can be computed in another
process (or, later, on another machine) and reported anywhere. Times are on the mission clock:
0 is the moment the mission started.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields
from typing import TYPE_CHECKING, Any, Literal, get_args

from roboscript import run_record
from roboscript.run_record import NOT_SERIALISED, Pose, SimulatedRun, Tone
from roboscript.sim.world import World

if TYPE_CHECKING:
    from typing_extensions import Self  # annotations only: not a dependency

__all__ = [
    "MAX_GRADED_STATES",
    "MISSION_REPORTED",
    "RUN_STATUSES",
    "Collision",
    "GradedRecord",
    "RunRecord",
    "RunResult",
    "RunStatus",
    "Tone",
    "Verdict",
]

RunStatus = Literal[
    "passed", "failed", "too slow", "timeout", "hung", "crashed", "invalid", "missing"
]
"""How a run can end for the grader (the values of :data:`RUN_STATUSES`)."""

MAX_GRADED_STATES = 20_000
"""Most states a graded run's record lists: the world keeps the first this many the mission
reports entering and counts the rest in ``states_dropped`` (a mission looping between states
for its whole run would otherwise grow its record without bound)."""

RUN_STATUSES: tuple[RunStatus, ...] = get_args(RunStatus)
"""How a run can end for the grader: ``passed`` (every expectation held), ``failed`` (one did
not), ``too slow`` (its code took longer than a tick too often, as ``roboscript run`` warns,
or its process used far more CPU time than the robot's time it advanced), ``timeout`` (a last
resort: the test's wall-clock limit ended it, counting only time the machine was not busy),
``hung`` (the mission's code did not return), ``crashed``
(the mission's process died, its own code raised, or it broke the grading wire),
``invalid`` (the student's mission did not load), ``missing`` (no mission for this test)."""

MISSION_REPORTED = ("outcome", "final_state", "reason", "state names", "mission name")
"""What in a :class:`GradedRecord` is the mission process's own account (checked, never trusted
with a name, a score or a verdict); everything else, times included, is the world's."""


@dataclass(frozen=True)
class Collision:
    """A collision with a wall: when it began, where the body centre was, which side hit."""

    t_s: float
    x_mm: float
    y_mm: float
    side: str


@dataclass(frozen=True)
class GradedRecord(run_record.RunRecord):
    """What happened in one graded (always simulated) run, read-only (a teacher's ``check``
    gets this).

    The run's :class:`~roboscript.run_record.RunRecord` (the fields and JSON of ``run
    --json``), plus what the expectations measure against. In a graded run the grader's own
    simulation records it; only the fields named in :data:`MISSION_REPORTED` come from the
    mission's process.

    Attributes:
        collisions: Every collision with a wall, where and when (the first 1000; ``sim``'s
            ``collisions`` counts them all).
        body_radius_mm: Radius of the robot's round body.
        side_sensor_offset_mm: How far the side distance sensor sits from the body centre.
        world: The world the run happened in (walls, tape, regions); not serialised (the
            record names it: :attr:`world_name`).
    """

    collisions: tuple[Collision, ...] = ()
    body_radius_mm: float = 100.0
    side_sensor_offset_mm: float = 80.0
    world: World | None = field(default=None, compare=False, repr=False, metadata=NOT_SERIALISED)

    @classmethod
    def simulated(
        cls,
        *,
        mission: str,
        robot: str,
        world_name: str,
        seed: int,
        outcome: str,
        final_state: str | None,
        reason: str | None,
        duration_s: float,
        states: tuple[tuple[float, str], ...],
        path: tuple[tuple[float, float, float, float], ...],
        tones: tuple[tuple[float, float, float], ...] = (),
        collisions: tuple[Collision, ...] = (),
        final_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
        distance_travelled_mm: float = 0.0,
        collision_count: int | None = None,
        tones_not_listed: int = 0,
        body_radius_mm: float = 100.0,
        side_sensor_offset_mm: float = 80.0,
        world: World | None = None,
    ) -> Self:
        """The record of a simulated run, told field by field (``collision_count``: all the
        collisions, by default as many as are listed)."""
        return cls(
            mission=mission,
            robot=robot,
            outcome=outcome,
            final_state=final_state,
            reason=reason,
            duration_s=duration_s,
            states=states,
            sim=SimulatedRun(
                seed=seed,
                world=world_name,
                final_pose=Pose(*final_pose),
                distance_travelled_mm=distance_travelled_mm,
                collisions=len(collisions) if collision_count is None else collision_count,
                tones=tuple(Tone(*tone) for tone in tones),
                path=path,
                tones_not_listed=tones_not_listed,
            ),
            collisions=collisions,
            body_radius_mm=body_radius_mm,
            side_sensor_offset_mm=side_sensor_offset_mm,
            world=world,
        )

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], **kept: Any) -> Self:
        """The record :meth:`to_dict` made (``kept``: ``world``); also reads a record in the
        layout of results files of format 1 (``world_name``, ``seed`` and the simulator's
        values beside the outcome), so a gradebook still merges them."""
        if "world_name" not in data:
            return super().from_dict(data, **kept)
        return cls.simulated(
            **{key: data[key] for key in _FORMAT_1_AS_IS},
            states=tuple((t, name) for t, name in data["states"]),
            path=tuple((t, x, y, h) for t, x, y, h in data["path"]),
            tones=tuple(Tone(**tone) for tone in data["tones"]),
            collisions=tuple(Collision(**c) for c in data["collisions"]),
            final_pose=Pose(*data["final_pose"]),
            **kept,
        )

    @property
    def simulation(self) -> SimulatedRun:
        """What the simulator saw (a graded run is always simulated)."""
        if self.sim is None:
            raise ValueError(f"the record of {self.mission} has no simulated run")
        return self.sim

    @property
    def world_name(self) -> str:
        """The world's name."""
        return self.simulation.world

    @property
    def seed(self) -> int:
        """The simulator seed."""
        return self.simulation.seed

    @property
    def path(self) -> tuple[tuple[float, float, float, float], ...]:
        """Samples ``(time_s, x_mm, y_mm, heading_deg)`` every 0.1 s; heading clockwise from
        north."""
        return self.simulation.path

    @property
    def tones(self) -> tuple[Tone, ...]:
        """Every tone started (``t_s``, ``frequency_hz``, ``duration_s``)."""
        return self.simulation.tones

    @property
    def final_pose(self) -> Pose:
        """``(x_mm, y_mm, heading_deg)`` when the mission ended."""
        return self.simulation.final_pose

    @property
    def distance_travelled_mm(self) -> float:
        """Path length of the body centre."""
        return self.simulation.distance_travelled_mm

    @property
    def start_pose(self) -> tuple[float, float, float]:
        """``(x_mm, y_mm, heading_deg)`` when the mission started (the first path sample)."""
        if not self.path:
            return self.final_pose
        _, x, y, h = self.path[0]
        return x, y, h

    def state_intervals(self) -> list[tuple[float, float, str]]:
        """``(start_s, end_s, state)`` for each stay in a state, the last ending with the run."""
        spans = []
        for i, (start, name) in enumerate(self.states):
            end = self.states[i + 1][0] if i + 1 < len(self.states) else self.duration_s
            spans.append((start, max(start, end), name))
        return spans

    def state_at(self, t_s: float) -> str | None:
        """The state the mission was in at ``t_s``."""
        times = [t for t, _ in self.states]
        i = bisect.bisect_right(times, t_s) - 1
        return self.states[i][1] if i >= 0 else None

    def pose_at(self, t_s: float) -> tuple[float, float, float]:
        """The pose ``(x_mm, y_mm, heading_deg)`` at ``t_s``, from the nearest earlier sample."""
        if not self.path:
            return self.final_pose
        times = [p[0] for p in self.path]
        i = max(0, bisect.bisect_right(times, t_s) - 1)
        _, x, y, h = self.path[i]
        return x, y, h


RunRecord = GradedRecord
"""The name a teacher's ``check`` function imports the record by."""

_FORMAT_1_AS_IS = (
    "mission",
    "robot",
    "world_name",
    "seed",
    "outcome",
    "final_state",
    "reason",
    "duration_s",
    "distance_travelled_mm",
    "body_radius_mm",
    "side_sensor_offset_mm",
)
"""A format-1 record's values that :meth:`GradedRecord.simulated` takes as they are."""


@dataclass(frozen=True)
class Verdict:
    """Whether one expectation held, and by how much.

    Attributes:
        name: The expectation (``final_pose_within``, ``check: lap_time``...).
        passed: Whether it held.
        margin: How close it came, signed, in words: ``"passed by 2.1 cm"``,
            ``"failed by 0.4 s"``; empty when there is no measure (an outcome).
        first_violation_s: Mission time it first failed, or ``None`` (it held, or failing has
            no moment, such as a region never reached).
        detail: One sentence of what was seen.
        margin_value: The margin as a number in ``margin_unit``: positive passed with room,
            negative failed by that much; ``None`` without a measure.
        margin_unit: ``mm``, ``s``, ``deg``, ``Hz`` or ``tones``.
        relative_margin: The margin as a share of its tolerance (radius, band, limit), to find
            the tightest pass across expectations; ``None`` when there is no tolerance.
        weight: Share of the run's score this expectation carries.
        required: The expectation is required: a run that fails it scores 0.
        teachers_fault: The teacher's own check failed to judge (it raised, returned no
            answer or never returned): the run fails it, and the grade is not to be trusted
            until the check is fixed; the grader says so to the teacher.
    """

    name: str
    passed: bool
    margin: str = ""
    first_violation_s: float | None = None
    detail: str = ""
    margin_value: float | None = None
    margin_unit: str = ""
    relative_margin: float | None = None
    weight: float = 1.0
    required: bool = False
    teachers_fault: bool = False

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready dictionary (``required`` and ``teachers_fault`` only when true)."""
        data = asdict(self)
        for flag in ("required", "teachers_fault"):
            if not data[flag]:
                del data[flag]
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Verdict:
        """The verdict :meth:`to_dict` made."""
        return cls(**data)

    @property
    def text(self) -> str:
        """One line: ``name: margin (detail)``, for reports."""
        head = f"{self.name} {self.margin}" if self.margin else self.name
        if not self.margin:
            head += " passed" if self.passed else " failed"
        return f"{head}: {self.detail}" if self.detail else head


@dataclass(frozen=True)
class RunResult:
    """One student's mission, run on one variant of one test and judged.

    Attributes:
        student: The student's name.
        test: The test spec's ``test`` name.
        variant: Index of the run variant in the spec's ``runs`` (0-based).
        label: The variant as people read it (``seed 2, start (100, 0) mm 10°``).
        seed: The simulator seed.
        mission: The mission file, as given on the command line.
        status: One of :data:`RUN_STATUSES`.
        message: One sentence for the student: why it failed (empty when it passed).
        score: Weighted share of expectations that held, 0 to 1.
        verdicts: One per expectation, in the spec's order (empty if the run never ended).
        record: What happened, or ``None`` if the run never ended.
        wall_time_s: Wall-clock seconds the run took (the only field that varies between
            identical runs).
        debug: A traceback or other detail for the teacher; never shown to students.
        during_load: True when the run ended before the mission had loaded (so every run of
            this mission on this robot ends the same way, and the grader runs it once).
        replay: The run recorded for the HTML report's viewer (``{"header", "frames",
            "result"}``, :mod:`roboscript.replay.world_tap`), or ``None``; crosses from the
            worker as ``to_dict(replay=True)`` and is left out of the JSON reports.
    """

    student: str
    test: str
    variant: int
    label: str
    seed: int
    mission: str
    status: RunStatus
    message: str = ""
    score: float = 0.0
    verdicts: tuple[Verdict, ...] = ()
    record: GradedRecord | None = None
    wall_time_s: float = 0.0
    debug: str = ""
    during_load: bool = False
    replay: dict[str, Any] | None = field(default=None, compare=False, repr=False)

    @property
    def passed(self) -> bool:
        """True if every expectation held."""
        return self.status == "passed"

    def to_dict(self, *, replay: bool = False) -> dict[str, Any]:
        """A JSON-ready dictionary (with the replay only when ``replay`` is true)."""
        data = {
            "student": self.student,
            "test": self.test,
            "variant": self.variant,
            "label": self.label,
            "seed": self.seed,
            "mission": self.mission,
            "status": self.status,
            "passed": self.passed,
            "message": self.message,
            "score": self.score,
            "verdicts": [v.to_dict() for v in self.verdicts],
            "record": self.record.to_dict() if self.record is not None else None,
            "wall_time_s": self.wall_time_s,
            "debug": self.debug,
            "during_load": self.during_load,
        }
        if replay:
            data["replay"] = self.replay
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any], world: World | None = None) -> RunResult:
        """The result :meth:`to_dict` made (``world`` is attached to the record).

        Raises:
            ValueError, TypeError, KeyError: ``data`` is not what :meth:`to_dict` makes (a
                damaged results file): a field is missing or of the wrong kind.
        """
        _check_fields(data)
        record = data.get("record")
        return cls(
            student=data["student"],
            test=data["test"],
            variant=data["variant"],
            label=data["label"],
            seed=data["seed"],
            mission=data["mission"],
            status=data["status"],
            message=data["message"],
            score=data["score"],
            verdicts=tuple(Verdict.from_dict(v) for v in data["verdicts"]),
            record=GradedRecord.from_dict(record, world=world) if record is not None else None,
            wall_time_s=data["wall_time_s"],
            debug=data["debug"],
            during_load=bool(data.get("during_load", False)),
            replay=data.get("replay"),
        )

    def worst_verdict(self) -> Verdict | None:
        """The first failed required verdict, else the first failed one, else the passed one
        with the least relative margin."""
        failed = [verdict for verdict in self.verdicts if not verdict.passed]
        if failed:
            return next((verdict for verdict in failed if verdict.required), failed[0])
        measured = [v for v in self.verdicts if v.relative_margin is not None]
        return min(measured, key=lambda v: v.relative_margin or math.inf, default=None)


_TEXT_FIELDS = ("student", "test", "label", "mission", "message", "debug")
_WHOLE_FIELDS = ("variant", "seed")
_NUMBER_FIELDS = ("score", "wall_time_s")


def _check_fields(data: Mapping[str, Any]) -> None:
    """Refuse a run whose fields are of the wrong kind, before a report trips over one."""

    def wrong(key: str) -> TypeError:
        return TypeError(f"the run's {key!r} is {data[key]!r}"[:200])

    for key in _TEXT_FIELDS:
        if not isinstance(data[key], str):
            raise wrong(key)
    for key in _WHOLE_FIELDS:
        if not isinstance(data[key], int) or isinstance(data[key], bool):
            raise wrong(key)
    for key in _NUMBER_FIELDS:
        value = data[key]
        if not isinstance(value, int | float) or isinstance(value, bool) or math.isnan(value):
            raise wrong(key)
    if data["status"] not in RUN_STATUSES:
        raise wrong("status")
    if not isinstance(data["verdicts"], list):
        raise wrong("verdicts")
    known = {item.name for item in fields(Verdict)}
    for verdict in data["verdicts"]:
        if not isinstance(verdict, dict) or not known.issuperset(verdict):
            raise TypeError(f"a verdict of the run is {verdict!r}"[:200])
    if not isinstance(data.get("replay"), dict | None):
        raise wrong("replay")
