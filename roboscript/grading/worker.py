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
import signal
from collections.abc import Sequence
from multiprocessing.connection import Connection

from roboscript.drivers import units
from roboscript.grading.record import RunResult
from roboscript.grading.run import grade_run
from roboscript.grading.sandbox import WarmJail, detect_isolation, warm_jails_supported
from roboscript.grading.task import RunTask, crash_result
from roboscript.grading.text import cap_result
from roboscript.grading.world_host import warm_jail
from roboscript.interrupts import HANDLED_SIGNALS

__all__ = ["work"]

# Imported here, once, in the fork server: every worker forked from it starts warm.
_WARM_MODULES = (
    *(unit.device.partition(":")[0] for unit in units()),  # each protocol's simulated device
    "roboscript.sim.simulation",
    "roboscript.grading.world_host",
)
for _name in _WARM_MODULES:
    importlib.import_module(_name)
# Probed once here, not once per run (it starts bwrap).
detect_isolation()


def work(
    connection: Connection, tasks: Sequence[tuple[int, RunTask]], *, first: bool = False
) -> None:
    """Grade runs of one student's mission in turn; send ``(index, result, ended_with)`` for
    each run done (``ended_with``: the indices of the runs that result stands for too, undone).

    The runs share one warm jail (:class:`~roboscript.grading.sandbox.WarmJail`) where the
    platform allows: its interpreter imports roboscript once and forks each run. The parent
    gives one worker only runs that may share a jail (the same mission and files, all hidden
    or all visible).

    Args:
        connection: Where the results go (the parent).
        tasks: The runs, with their indices.
        first: The first of ``tasks`` is its mission's first run: when the mission ends while
            loading, that result stands for every other run (the mission would load no
            differently), so they are not done.
    """
    logging.disable(logging.WARNING)
    # Stopped by the parent (its runs are known already), or with it by the teacher's Ctrl-C
    # or a closed terminal (which reach the whole process group): clean up on the way out,
    # quietly, so no jail, jail's folder or world map outlives the worker.
    for signum in HANDLED_SIGNALS:
        signal.signal(signum, _exit_on_term)
    server: WarmJail | None = None
    try:
        for position, (index, task) in enumerate(tasks):
            if warm_jails_supported() and (server is None or not server.alive):
                if server is not None:
                    server.close()
                server = _warm_jail(task)
            try:
                try:
                    graded = _grade(task, server)
                except OSError:
                    if server is None or server.alive:
                        raise
                    # The previous run killed its jail's server as it ended: a new jail.
                    server.close()
                    server = _warm_jail(task)
                    graded = _grade(task, server)
                # Capped here, so a student's flood never crosses the pipe or reaches --results.
                result = cap_result(graded).to_dict(replay=True)
            except Exception as exc:  # noqa: BLE001 - a bug of ours: report it for this run only
                result = crash_result(task, exc)
            if first and position == 0 and result.get("during_load"):
                # It would load no differently in the others: they end as it did, unrun.
                connection.send((index, result, [n for n, _task in tasks[1:]]))
                return
            connection.send((index, result, []))
    finally:
        if server is not None:
            server.close()
        connection.close()


def _exit_on_term(signum: int, _frame: object) -> None:
    # Cleaning up from now on: the parent's SIGTERM that follows a Ctrl-C must not cut the
    # jail's removal short (the parent kills a worker that takes too long).
    # (A handler that does nothing, not SIG_IGN: a signal already pending would then be
    # reported as "ignored due to race condition", with a traceback.)
    for other in HANDLED_SIGNALS:
        signal.signal(other, _cleaning_up)
    raise SystemExit(128 + signum)


def _cleaning_up(_signum: int, _frame: object) -> None:
    """The handler while the worker cleans up after a signal: the first one said it all."""


def _grade(task: RunTask, server: WarmJail | None) -> RunResult:
    return grade_run(
        task.spec,
        task.mission,
        task.variant,
        task.student,
        visible=task.visible,
        hang_after_s=task.hang_after_s,
        server=server,
    )


def _warm_jail(task: RunTask) -> WarmJail | None:
    """The student's warm jail, or None (each run then gets a jail of its own, which reports
    the same problem as a run result)."""
    try:
        return warm_jail(task.spec, task.mission, visible=task.visible)
    except (OSError, ValueError):
        return None
