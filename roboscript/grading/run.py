"""One graded run: a student's mission on one variant of a test, judged by its expectations.

:func:`grade_run` is a pure function of its arguments: the same spec, mission file and variant
always give the same :class:`~roboscript.grading.record.RunResult` (but for ``wall_time_s``),
because the simulator is deterministic and runs on its own clock. It runs the mission in the
calling process; the grader calls it in a worker process of its own
(:mod:`roboscript.grading.pool`), since a Python mission is code that may loop or crash.
"""

from __future__ import annotations

import time

from roboscript.errors import CapabilityError, InputError
from roboscript.grading.expectations import evaluate
from roboscript.grading.record import Collision, RunRecord, RunResult, Tone, Verdict
from roboscript.grading.spec import TestSpec, Variant
from roboscript.session import Session, run_session

__all__ = ["grade_run", "record_from_session", "run_message", "run_score"]


def grade_run(spec: TestSpec, mission_path: str, variant: Variant, student: str = "") -> RunResult:
    """Run ``mission_path`` on ``variant`` of ``spec`` in the simulator and judge it.

    The spec's robot and world are used whatever the mission names; the run ends when the
    mission does or after the spec's ``max_time`` of simulated time.

    Args:
        spec: The test.
        mission_path: The student's mission file (``.yaml`` or ``.py``).
        variant: Which of the spec's runs.
        student: The student's name, for the result.

    Returns:
        The result: ``passed``, ``failed``, or ``invalid`` when the mission does not load or
        does not fit the robot (the message then quotes the first problem).
    """
    from roboscript.mission import mission_for_robot

    started = time.perf_counter()
    base = spec.result(variant, student=student, mission=mission_path, status="invalid")
    try:
        mission, profile, _warnings = mission_for_robot(mission_path, spec.robot)
    except InputError as exc:
        problems = [p.format() for p in getattr(exc, "problems", None) or [exc]]
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        return _finish(
            base,
            started,
            message=f"the mission has an error: {problems[0]}{more}",
            debug="\n".join(problems),
        )
    try:
        session = run_session(
            mission,
            profile,
            world=variant.world,
            seed=variant.seed,
            start=variant.start,
            max_time_s=spec.max_time_s,
        )
    except CapabilityError as exc:
        return _finish(base, started, message=f"the mission does not fit the robot: {exc}")
    record = record_from_session(session)
    verdicts = tuple(evaluate(expectation, record) for expectation in spec.expectations)
    passed = all(v.passed for v in verdicts)
    return _finish(
        base,
        started,
        status="passed" if passed else "failed",
        message=run_message(verdicts),
        score=run_score(verdicts),
        verdicts=verdicts,
        record=record,
    )


def _finish(base: RunResult, started: float, **changes: object) -> RunResult:
    from dataclasses import replace

    wall = round(time.perf_counter() - started, 3)
    return replace(base, wall_time_s=wall, **changes)  # type: ignore[arg-type]


def run_score(verdicts: tuple[Verdict, ...]) -> float:
    """The weighted share of verdicts that passed, 0 to 1 (0 with no verdicts)."""
    total = sum(v.weight for v in verdicts)
    if total <= 0:
        return 0.0
    return round(sum(v.weight for v in verdicts if v.passed) / total, 4)


def run_message(verdicts: tuple[Verdict, ...]) -> str:
    """One sentence for the student: the first expectation that failed (empty if none did)."""
    failed = [v for v in verdicts if not v.passed]
    if not failed:
        return ""
    first = failed[0]
    text = first.text
    if len(failed) > 1:
        text += f" (and {len(failed) - 1} more check{'s' if len(failed) > 2 else ''} failed)"
    return text


def record_from_session(session: Session) -> RunRecord:
    """What a finished simulated run did, on the mission clock."""
    sim = session.simulation
    if sim is None:
        raise ValueError("only simulated runs can be graded")
    result = session.result
    body = sim.body
    return RunRecord(
        mission=result.mission,
        robot=session.profile.name,
        world_name=sim.world.name,
        seed=sim.seed,
        outcome=result.outcome,
        final_state=result.final_state,
        reason=result.reason,
        duration_s=round(result.duration_s, 3),
        states=tuple((round(t, 3), name) for t, name in result.states),
        path=tuple(session.mission_path()),
        tones=tuple(Tone(t, float(f), d) for t, f, d in session.mission_tones()),
        collisions=tuple(
            Collision(session.mission_time_s(c.start_s), round(c.x_mm, 1), round(c.y_mm, 1), c.side)
            for c in sim.log.contacts
        ),
        final_pose=session.final_pose(),
        distance_travelled_mm=round(sim.log.distance_travelled_mm, 1),
        body_radius_mm=body.spec.body_radius_mm,
        side_sensor_offset_mm=body.spec.side_range_offset_mm,
        world=sim.world,
    )
