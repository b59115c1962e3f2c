"""One graded run to do, and the result of a run whose grading itself failed.

Shared by the parent (:mod:`roboscript.grading.pool`) and the worker process
(:mod:`roboscript.grading.worker`), which both import it; neither imports the other's module
for these, so the worker never loads the pool and the pool loads the worker only to start it.
"""

from __future__ import annotations

import os
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from roboscript.grading.spec import TestSpec, Variant
from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S

__all__ = ["RunTask", "crash_result"]


@dataclass(frozen=True)
class RunTask:
    """One run to do: a student's mission on one variant of a test.

    Attributes:
        spec: The test.
        mission: The mission file.
        variant: The run variant.
        student: The student (never passed to the mission).
        visible: What the mission may read (default: the file and the files it names).
        hang_after_s: Own seconds one tick's code may run before the run is ``hung``.
    """

    spec: TestSpec
    mission: str
    variant: Variant
    student: str
    visible: tuple[Path, ...] | None = None
    hang_after_s: float = DEFAULT_HANG_AFTER_S

    @property
    def load_key(self) -> tuple[str, str]:
        """Runs with the same key load the same mission on the same robot."""
        return self.mission, self.spec.robot


def crash_result(task: RunTask, exc: BaseException) -> dict[str, Any]:
    """The result dictionary of a run whose grading raised ``exc`` (in the worker)."""
    where = ""
    frames = traceback.extract_tb(exc.__traceback__)
    if frames:
        where = f" ({os.path.basename(frames[-1].filename)}:{frames[-1].lineno})"
    text = str(exc).splitlines()[0][:300] if str(exc) else ""
    return task.spec.result(
        task.variant,
        student=task.student,
        mission=task.mission,
        status="crashed",
        message=(
            f"the grader failed on this run: {type(exc).__name__}{': ' + text if text else ''}"
            f"{where}; this is a roboscript problem, not the student's: please report it"
        ),
        debug="".join(traceback.format_exception(exc)),
    ).to_dict()
