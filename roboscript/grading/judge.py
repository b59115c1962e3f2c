"""How a run is judged: the record of its simulation, its verdicts, status, message and score.

One set of rules for every graded run, wherever its mission ran: in a jail of its own
(:func:`roboscript.grading.run.grade_run`, the teacher's grade) or in the same process as its
world (:mod:`roboscript.grading.practice`, the browser page's practice grade). This module
loads nothing of the jail, so a browser tab can import it.

Scores (written in the teachers' guide): a run that passed scores 1; a run that failed after
ending normally (its mission reached a final state by itself, within the test's simulated
time, without its own code raising) scores the weighted share of expectations that held, or 0
if it failed one the spec marks ``required``; every other run (out of simulated time, crashed,
hung, timed out, invalid, missing) scores 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from roboscript.grading.expectations import evaluate
from roboscript.grading.record import Collision, RunRecord, RunStatus, Tone, Verdict
from roboscript.grading.spec import TestSpec
from roboscript.session import Session
from roboscript.sim.simulation import Simulation

__all__ = [
    "Judgement",
    "ended_in_time",
    "failure_marks",
    "judge",
    "record_from_session",
    "run_message",
    "run_score",
    "simulation_record",
]

OUT_OF_TIME_MARGIN_S = 0.05
"""A mission stopped by its own time limit ends on the tick at ``max_time`` (its limit is
counted from its first tick): a run that long did not end by itself."""


@dataclass(frozen=True)
class Judgement:
    """What a run's record earned.

    Attributes:
        status: ``passed`` or ``failed``, or the status the run had already stopped with.
        message: One sentence for the student (empty when it passed).
        score: 0 to 1 (see the module docstring).
        verdicts: One per expectation, in the spec's order.
    """

    status: RunStatus
    message: str
    score: float
    verdicts: tuple[Verdict, ...]


def judge(
    spec: TestSpec,
    record: RunRecord,
    *,
    ended_normally: bool,
    status: RunStatus | Literal[""] = "",
    message: str = "",
) -> Judgement:
    """Judge every expectation of ``spec`` on ``record``.

    Args:
        spec: The test.
        record: What the run did.
        ended_normally: The mission reached a final state by itself, within the test's
            simulated time, and its own code did not raise (see :func:`ended_in_time`).
        status: How the run had already stopped (``hung``, ``timeout``, ``crashed``), or
            ``""`` for a run that ended and is judged on its record alone.
        message: The sentence that goes with ``status``.
    """
    verdicts = tuple(evaluate(expectation, record) for expectation in spec.expectations)
    passed = all(v.passed for v in verdicts) and not status
    final: RunStatus = status or ("passed" if passed else "failed")
    text = message or run_message(verdicts)
    if not text and not passed:
        text = record.reason or "the mission did not end normally"
    score = run_score(verdicts) if final == "passed" or ended_normally else 0.0
    return Judgement(final, text, score, verdicts)


def ended_in_time(record: RunRecord, spec: TestSpec) -> bool:
    """False when the run lasted the test's whole simulated time (its limit stopped it)."""
    return record.duration_s < spec.max_time_s - OUT_OF_TIME_MARGIN_S


def failure_marks(verdicts: tuple[Verdict, ...]) -> list[dict[str, Any]]:
    """Where a replay marks the run: ``{"t": s, "label": name}`` at each failed verdict's
    first violation (mission clock), in the spec's order; a replay opens at the earliest."""
    return [
        {"t": v.first_violation_s, "label": v.name}
        for v in verdicts
        if not v.passed and v.first_violation_s is not None
    ]


def run_score(verdicts: tuple[Verdict, ...]) -> float:
    """The weighted share of verdicts that passed, 0 to 1 (0 with no verdicts, and 0 when a
    required one failed)."""
    if any(v.required and not v.passed for v in verdicts):
        return 0.0
    total = sum(v.weight for v in verdicts)
    if total <= 0:
        return 0.0
    return round(sum(v.weight for v in verdicts if v.passed) / total, 4)


def run_message(verdicts: tuple[Verdict, ...]) -> str:
    """One sentence for the student: the first expectation that failed (empty if none did)."""
    failed = [v for v in verdicts if not v.passed]
    if not failed:
        return ""
    first = next((v for v in failed if v.required), failed[0])
    text = first.text
    if first.required:
        text += " (required: without it the run scores 0)"
    if len(failed) > 1:
        text += f" (and {len(failed) - 1} more check{'s' if len(failed) > 2 else ''} failed)"
    return text


def simulation_record(
    sim: Simulation,
    start_s: float,
    end_s: float,
    *,
    mission: str,
    outcome: str,
    final_state: str | None,
    reason: str | None,
    states: tuple[tuple[float, str], ...],
) -> RunRecord:
    """The record of a simulated run whose mission started at ``start_s`` and ended at ``end_s``.

    Everything physical comes from ``sim``; ``mission``, ``outcome``, ``final_state``,
    ``reason`` and the state names are the mission's own account.
    """
    return RunRecord.simulated(
        mission=mission,
        robot=sim.profile.name,
        world_name=sim.world.name,
        seed=sim.seed,
        outcome=outcome,
        final_state=final_state,
        reason=reason,
        duration_s=round(end_s - start_s, 3),
        states=states,
        path=tuple(sim.path_since(start_s)),
        tones=tuple(Tone(t, float(f), d) for t, f, d in sim.tones_since(start_s)),
        collisions=tuple(
            Collision(round(c.start_s - start_s, 3), round(c.x_mm, 1), round(c.y_mm, 1), c.side)
            for c in sim.log.contacts
        ),
        final_pose=sim.final_pose(),
        distance_travelled_mm=round(sim.log.distance_travelled_mm, 1),
        collision_count=sim.log.contacts.total,
        tones_not_listed=sim.log.tones.more,
        body_radius_mm=sim.body.spec.body_radius_mm,
        side_sensor_offset_mm=sim.body.spec.side_range_offset_mm,
        world=sim.world,
    )


def record_from_session(session: Session) -> RunRecord:
    """What a finished in-process simulated run did, on the mission clock.

    A jailed run records from the grader's own world instead
    (:mod:`roboscript.grading.world_host`): the same mission, robot, world and seed give the
    same record either way (a test compares them).
    """
    sim = session.simulation
    if sim is None:
        raise ValueError("only simulated runs can be recorded")
    result = session.result
    start_s = session.start_time_s
    return simulation_record(
        sim,
        start_s,
        start_s + result.duration_s,
        mission=result.mission,
        outcome=result.outcome,
        final_state=result.final_state,
        reason=result.reason,
        states=tuple((round(t, 3), name) for t, name in result.states),
    )
