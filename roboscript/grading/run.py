"""One graded run: a student's mission on one variant of a test, judged by its expectations.

:func:`grade_run` runs the mission in a sandboxed process of its own and the simulated world in
the calling process (:mod:`roboscript.grading.world_host`), joined by the robot's protocol
bytes; the verdicts are computed here, from the world's record, where the student's code
cannot reach. The same spec, mission file and variant always give the same
:class:`~roboscript.grading.record.RunResult` (but for ``wall_time_s``): the simulator is
deterministic and runs on its own clock, and the wire is lockstep.

Scores (written in the teachers' guide): a run that passed scores 1; a run that failed after
ending normally (its mission reached a final state by itself, within the test's simulated
time, without its own code raising) scores the weighted share of expectations that held, or 0
if it failed one the spec marks ``required``; every other run (out of simulated time, crashed,
hung, timed out, invalid, missing) scores 0.
"""

from __future__ import annotations

import time
from pathlib import Path

from roboscript.grading.expectations import evaluate
from roboscript.grading.record import RunRecord, RunResult, Verdict
from roboscript.grading.sandbox import Limits, WarmJail
from roboscript.grading.spec import TestSpec, Variant
from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S, run_world, simulation_record
from roboscript.session import Session

__all__ = ["grade_run", "record_from_session", "run_message", "run_score"]


def grade_run(
    spec: TestSpec,
    mission_path: str,
    variant: Variant,
    student: str = "",
    *,
    visible: tuple[Path, ...] | None = None,
    hang_after_s: float = DEFAULT_HANG_AFTER_S,
    limits: Limits | None = None,
    server: WarmJail | None = None,
) -> RunResult:
    """Run ``mission_path`` on ``variant`` of ``spec`` in the simulator and judge it.

    The spec's robot and world are used whatever the mission names; the run ends when the
    mission does, after the spec's ``max_time`` of simulated time, when its code does not
    return for ``hang_after_s`` of its own time or is too slow per tick too often
    (:mod:`roboscript.grading.world_host`), or at the spec's wall-clock limit.

    Args:
        spec: The test.
        mission_path: The student's mission file (``.yaml`` or ``.py``).
        variant: Which of the spec's runs.
        student: The student's name, for the result (never seen by the mission).
        visible: Files and folders the mission may read (default: the mission file and the
            files beside it that it names).
        hang_after_s: Seconds of its own time one tick's code may run before the run is
            ``hung`` (never wall time: a busy machine changes no verdict).
        limits: The sandbox's resource limits (default :class:`~roboscript.grading.sandbox.Limits`).
        server: A warm jail of this student's to fork the mission's process in (see
            :class:`~roboscript.grading.sandbox.WarmJail`); by default a jail of its own.

    Returns:
        The result: ``passed`` or ``failed`` (judged), or ``invalid``, ``crashed``, ``hung``
        or ``timeout`` with one sentence for the student.
    """
    started = time.perf_counter()
    base = spec.result(variant, student=student, mission=mission_path, status="crashed")
    world = run_world(
        spec,
        mission_path,
        variant,
        visible=visible,
        hang_after_s=hang_after_s,
        limits=limits,
        server=server,
    )
    if world.record is None:
        return _finish(
            base,
            started,
            status=world.status,
            message=world.message,
            debug=world.debug,
            during_load=not world.loaded,
        )
    record = world.record
    verdicts = tuple(evaluate(expectation, record) for expectation in spec.expectations)
    passed = all(v.passed for v in verdicts) and not world.status
    status = world.status or ("passed" if passed else "failed")
    message = world.message or run_message(verdicts)
    if not message and not passed:
        message = record.reason or "the mission did not end normally"
    return _finish(
        base,
        started,
        status=status,
        message=message,
        score=run_score(verdicts) if status == "passed" or world.ended_normally else 0.0,
        verdicts=verdicts,
        record=record,
        debug=world.debug,
        replay=world.replay,
    )


def _finish(base: RunResult, started: float, **changes: object) -> RunResult:
    from dataclasses import replace

    wall = round(time.perf_counter() - started, 3)
    return replace(base, wall_time_s=wall, **changes)  # type: ignore[arg-type]


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


def record_from_session(session: Session) -> RunRecord:
    """What a finished in-process simulated run did, on the mission clock.

    The grader never uses this (it records from its own world, :func:`grade_run`); it is the
    reference a graded run is compared with: the same mission, robot, world and seed give the
    same record either way.
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
