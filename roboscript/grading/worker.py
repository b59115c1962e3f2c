"""The grading worker: the only place a student's mission is loaded and run.

It runs in a process of its own (see :mod:`roboscript.grading.pool`). Importing this module
imports everything a run needs, so the fork server that preloads it hands each worker a warm
interpreter.
"""

from __future__ import annotations

import importlib
import logging
import os
import sys
from multiprocessing.connection import Connection
from typing import TYPE_CHECKING

from roboscript.grading.run import grade_run

if TYPE_CHECKING:
    from roboscript.grading.pool import RunTask

__all__ = ["work"]

# Imported here, once, in the fork server: every worker forked from it starts warm.
_WARM_MODULES = (
    "roboscript.drivers.asip.driver",
    "roboscript.drivers.asip.device",
    "roboscript.mission.yaml_loader",
    "roboscript.mission.python_loader",
    "roboscript.sim.simulation",
)
for _name in _WARM_MODULES:
    importlib.import_module(_name)


def work(connection: Connection, task: RunTask) -> None:
    """Grade one run and send its result dictionary to the parent."""
    from roboscript.grading.pool import MEMORY_LIMIT_BYTES, crash_result

    _quiet()
    _limit_memory(MEMORY_LIMIT_BYTES)
    try:
        result = grade_run(task.spec, task.mission, task.variant, task.student).to_dict()
    except BaseException as exc:  # noqa: BLE001 - whatever the student's code does is a failed run
        result = crash_result(task, exc)
    try:
        connection.send(result)
    finally:
        connection.close()


def _quiet() -> None:
    """Send the student's prints (and anything else written) nowhere: reports stay clean."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    for fd in (1, 2):
        os.dup2(devnull, fd)
    os.close(devnull)
    sys.stdout = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115 - lives as long as the worker
    sys.stderr = sys.stdout
    logging.disable(logging.WARNING)


def _limit_memory(limit_bytes: int) -> None:
    try:
        import resource
    except ImportError:  # not on Windows
        return
    try:
        _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        if hard == resource.RLIM_INFINITY or hard > limit_bytes:
            resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, hard))
    except (OSError, ValueError):
        pass
