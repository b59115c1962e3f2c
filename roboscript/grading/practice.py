"""The practice grade: a test spec's runs done in this process, judged as the grader judges them.

The browser page (``roboscript web build --spec``) grades a student's mission against a spec
the teacher shipped with this module. Each run is the in-process run ``roboscript run`` does
(the spec's robot, the variant's world, seed and start, the spec's simulated time), recorded
and judged by :mod:`roboscript.grading.judge`, the rules ``roboscript grade`` judges with; a
test's points add up as in the class's reports (:class:`~roboscript.grading.cell.Cell`). A
mission that plays fair gets the same record, verdicts, status, score and points here as from
``roboscript grade`` (a test compares them).

There is no jail: the mission runs in the same process as its world and its judge, so its
code could change anything here, its own result included. A practice grade is for the
student; the teacher's grade comes from ``roboscript grade``, which runs each mission in a
jail of its own and reads the world from its own process.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from roboscript.errors import CapabilityError, InputError
from roboscript.grading.cell import Cell
from roboscript.grading.judge import ended_in_time, judge, record_from_session
from roboscript.grading.record import RunResult, RunStatus
from roboscript.grading.spec import TestSpec, Variant
from roboscript.mission import mission_for_robot
from roboscript.replay.recording import Recording
from roboscript.replay.session_tap import RunRecording
from roboscript.session import run_session

__all__ = ["PracticeRun", "practice_grade", "practice_run"]


@dataclass(frozen=True)
class PracticeRun:
    """One run of a practice grade.

    Attributes:
        result: The run's result, as ``roboscript grade`` reports one.
        recording: The run, tick by tick, for the replay viewer (``None`` when it never ran).
    """

    result: RunResult
    recording: Recording | None


def practice_run(
    spec: TestSpec,
    mission_path: str,
    variant: Variant,
    *,
    student: str = "",
    hang_after_s: float | None = None,
) -> PracticeRun:
    """Run ``mission_path`` on ``variant`` of ``spec`` in this process, and judge it.

    Args:
        spec: The test.
        mission_path: The student's mission file (``.yaml`` or ``.py``).
        variant: Which of the spec's runs.
        student: The student's name, for the result.
        hang_after_s: Seconds of its own time one tick's code may run before the run is
            ``hung``; ``None`` (a browser tab, which has no second thread to watch with):
            not watched.

    Returns:
        The run: ``passed`` or ``failed`` (judged), or ``invalid``, ``crashed``, ``hung`` or
        ``timeout`` with one sentence for the student, as the grader words them.
    """
    base = spec.result(variant, student=student, mission=mission_path, status="crashed")
    try:
        mission, profile, _warnings = mission_for_robot(mission_path, spec.robot)
    except InputError as exc:
        first = (getattr(exc, "problems", None) or [exc])[0]
        return _unjudged(base, "invalid", f"the mission has an error: {first.format()}")
    recording = RunRecording()
    try:
        session = run_session(
            mission,
            profile,
            world=variant.world,
            seed=variant.seed,
            start=variant.start,
            max_time_s=spec.max_time_s,
            runaway_after_s=hang_after_s,
            recording=recording,
        )
    except CapabilityError as exc:
        return _unjudged(
            base, "invalid", f"the mission has an error: it does not fit the robot: {exc}"
        )
    record = record_from_session(session)
    status: RunStatus | None = None
    message = ""
    if session.code_stopped:  # the mission's own code was stopped: it made its own run worse
        status = "hung" if session.code_stopped == "hung" else "timeout"
        message = record.reason or f"the mission's code was stopped ({session.code_stopped})"
    elif session.result.code_error:
        status = "crashed"
        message = f"the run crashed: {record.reason or 'the mission raised an exception'}"
    judged = judge(
        spec,
        record,
        ended_normally=status is None and ended_in_time(record, spec),
        status=status or "",
        message=message,
    )
    result = replace(
        base,
        status=judged.status,
        message=judged.message,
        score=judged.score,
        verdicts=judged.verdicts,
        record=record,
    )
    played = recording.recorder.recording() if recording.recorder is not None else None
    return PracticeRun(result, played)


def practice_grade(
    spec: TestSpec, mission_path: str, *, student: str = ""
) -> tuple[Cell, tuple[PracticeRun, ...]]:
    """Every run of ``spec`` on ``mission_path``, judged, and the points they earn.

    A mission that does not load is tried once; that result stands for every run, as in
    ``roboscript grade``.

    Returns:
        The student in this test (runs, score, points) and each run with its recording.
    """
    runs: list[PracticeRun] = []
    for variant in spec.variants:
        if runs and runs[0].result.status == "invalid":
            first = runs[0].result
            again = spec.result(variant, student=student, mission=mission_path, status="invalid")
            runs.append(PracticeRun(replace(again, message=first.message), None))
            continue
        runs.append(practice_run(spec, mission_path, variant, student=student))
    hidden = frozenset(v.index for v in spec.variants if v.hidden)
    cell = Cell(student, spec.name, tuple(r.result for r in runs), spec.max_points, hidden)
    return cell, tuple(runs)


def _unjudged(base: RunResult, status: RunStatus, message: str) -> PracticeRun:
    return PracticeRun(replace(base, status=status, message=message, during_load=True), None)
