"""The grading worker: one graded run's world, in a process of its own.

It runs in a process the grader starts (see :mod:`roboscript.grading.pool`) and never loads a
student's file: it builds the simulated world, starts the student's mission in a sandboxed
process (:func:`roboscript.grading.run.grade_run`) and judges the run. Importing this module
imports everything the world side needs, so the fork server that preloads it hands each
worker a warm interpreter.
"""

from __future__ import annotations

import importlib
import logging
from multiprocessing.connection import Connection

from roboscript.grading.run import grade_run
from roboscript.grading.sandbox import detect_isolation
from roboscript.grading.task import RunTask, crash_result
from roboscript.grading.text import cap_result

__all__ = ["work"]

# Imported here, once, in the fork server: every worker forked from it starts warm.
_WARM_MODULES = (
    "roboscript.drivers.asip.device",
    "roboscript.drivers.spike.device",
    "roboscript.drivers.stackmod.device",
    "roboscript.drivers.plen.device",
    "roboscript.sim.simulation",
    "roboscript.grading.world_host",
)
for _name in _WARM_MODULES:
    importlib.import_module(_name)
# Probed once here, not once per run (it starts bwrap).
detect_isolation()


def work(connection: Connection, task: RunTask) -> None:
    """Grade one run and send its result dictionary to the parent."""
    logging.disable(logging.WARNING)
    try:
        graded = grade_run(
            task.spec,
            task.mission,
            task.variant,
            task.student,
            visible=task.visible,
            hang_after_s=task.hang_after_s,
        )
        # Capped here, so a student's flood never crosses the pipe or reaches --results.
        result = cap_result(graded).to_dict(replay=True)
    except Exception as exc:  # noqa: BLE001 - a bug of ours: report it for this run only
        result = crash_result(task, exc)
    try:
        connection.send(result)
    finally:
        connection.close()
