"""One graded run: a student's mission on one variant of a test, judged by its expectations.

:func:`grade_run` runs the mission in a sandboxed process of its own and the simulated world in
the calling process (:mod:`roboscript.grading.world_host`), joined by the robot's protocol
bytes; the verdicts are computed here, from the world's record, where the student's code
cannot reach. The same spec, mission file and variant always give the same
:class:`~roboscript.grading.record.RunResult` (but for ``wall_time_s``): the simulator is
deterministic and runs on its own clock, and the wire is lockstep.

The run is judged by :mod:`roboscript.grading.judge`, the rules the browser page's practice
grade uses too (its scores are written there and in the teachers' guide).
"""

from __future__ import annotations

import time
from pathlib import Path

from roboscript.grading.judge import judge, record_from_session, run_message, run_score
from roboscript.grading.record import RunResult
from roboscript.grading.sandbox import Limits, WarmJail
from roboscript.grading.spec import TestSpec, Variant
from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S, run_world

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
        The result: ``passed`` or ``failed`` (judged), or ``invalid``, ``crashed``, ``hung``,
        ``too slow`` or ``timeout`` with one sentence for the student.
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
    judged = judge(
        spec,
        record,
        ended_normally=world.ended_normally,
        status=world.status,
        message=world.message,
    )
    return _finish(
        base,
        started,
        status=judged.status,
        message=judged.message,
        score=judged.score,
        verdicts=judged.verdicts,
        record=record,
        debug=world.debug,
        replay=world.replay,
    )


def _finish(base: RunResult, started: float, **changes: object) -> RunResult:
    from dataclasses import replace

    wall = round(time.perf_counter() - started, 3)
    return replace(base, wall_time_s=wall, **changes)  # type: ignore[arg-type]
