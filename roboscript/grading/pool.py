"""Run graded runs in worker processes, in parallel, each with a wall-clock limit.

A student's Python mission is code: a condition may loop forever, a behaviour may raise, call
``exit()`` or eat all the memory. So every run happens in a fresh worker process, and only
there: the parent never imports a student's file. The parent

* starts at most ``jobs`` workers at a time (forked from a server process that has already
  imported roboscript, so a worker is ready in milliseconds; spawned where fork is not
  available);
* stops a worker that passes its run's wall-clock limit (terminate, then kill) and records the
  run as ``timeout``;
* records a worker that raised or died as ``crashed``, with one sentence for the student and
  the traceback (if any) in the result's ``debug`` field.

Each worker starts from the same state, whatever ran before it or beside it, so results do not
depend on ``jobs`` or on the order runs finish in; they are returned in the order given.

A script that calls :func:`run_tasks` must keep its top level under
``if __name__ == "__main__":``, as with any ``multiprocessing`` program: workers load the
script's module (not as ``__main__``) before they start.
"""

from __future__ import annotations

import multiprocessing
import os
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from typing import Any

from roboscript.grading.record import RunResult
from roboscript.grading.spec import TestSpec, Variant

__all__ = ["MEMORY_LIMIT_BYTES", "RunTask", "crash_result", "default_jobs", "run_tasks"]

MEMORY_LIMIT_BYTES = 4 * 1024**3
"""Address space a worker may use (where the OS lets us set it): a runaway student program
fails its own run instead of starving the teacher's computer."""

_KILL_GRACE_S = 2.0


@dataclass(frozen=True)
class RunTask:
    """One run to do: a student's mission on one variant of a test."""

    spec: TestSpec
    mission: str
    variant: Variant
    student: str


def default_jobs() -> int:
    """How many runs to do at once by default: one per CPU core."""
    return os.cpu_count() or 1


def _context() -> Any:
    if "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        # Workers fork from a server that has imported the simulator, drivers and runner once.
        context.set_forkserver_preload(["roboscript.grading.worker"])
        return context
    return multiprocessing.get_context("spawn")


@dataclass
class _Running:
    task: RunTask
    index: int
    process: BaseProcess
    connection: Connection
    started: float
    deadline: float


def run_tasks(
    tasks: Sequence[RunTask],
    jobs: int | None = None,
    on_result: Callable[[RunResult], None] | None = None,
) -> list[RunResult]:
    """Do every task in its own worker process, ``jobs`` at a time.

    Args:
        tasks: The runs.
        jobs: Workers at once (default: one per CPU core).
        on_result: Called in the parent with each result as it comes (for progress).

    Returns:
        One result per task, in the order of ``tasks``.
    """
    jobs = max(1, jobs or default_jobs())
    context = _context()
    pending = list(enumerate(tasks))
    pending.reverse()  # pop() from the end takes them in order
    results: dict[int, RunResult] = {}
    running: list[_Running] = []
    try:
        while pending or running:
            while pending and len(running) < jobs:
                index, task = pending.pop()
                running.append(_start(context, index, task))
            now = time.monotonic()
            timeout = max(0.0, min(r.deadline for r in running) - now)
            ready = set(
                wait(
                    [r.connection for r in running] + [r.process.sentinel for r in running],
                    timeout,
                )
            )
            still: list[_Running] = []
            for run in running:
                result = _collect(run, ready)
                if result is None:
                    still.append(run)
                    continue
                results[run.index] = result
                if on_result is not None:
                    on_result(result)
            running = still
    finally:
        for run in running:  # interrupted (Ctrl-C): leave no worker behind
            _stop(run.process)
    return [results[i] for i in range(len(tasks))]


def _start(context: Any, index: int, task: RunTask) -> _Running:
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(
        target=_worker_entry, args=(sender, task), name=f"roboscript-grade-{index}", daemon=True
    )
    started = time.monotonic()
    process.start()
    sender.close()  # the parent keeps only its reading end, so a dead worker reads as EOF
    return _Running(task, index, process, receiver, started, started + task.spec.wall_time_limit_s)


def _worker_entry(connection: Connection, task: RunTask) -> None:
    from roboscript.grading.worker import work

    work(connection, task)


def _collect(run: _Running, ready: set[Any]) -> RunResult | None:
    """The run's result if it has one now (sent, died or timed out), else ``None``."""
    wall = round(time.monotonic() - run.started, 3)
    if run.connection in ready or run.process.sentinel in ready:
        data = None
        if run.connection.poll():
            try:
                data = run.connection.recv()
            except (EOFError, OSError):
                data = None
            except Exception as exc:  # noqa: BLE001 - a half-sent result from a dying worker
                data = {"unreadable": f"{type(exc).__name__}: {exc}"}
        if isinstance(data, dict) and "student" in data:
            _stop(run.process)
            run.connection.close()
            return replace(RunResult.from_dict(data), wall_time_s=wall)
        if data is None and run.process.is_alive() and run.connection not in ready:
            return None
        _stop(run.process)
        run.connection.close()
        code = run.process.exitcode
        return _failed(
            run,
            "crashed",
            "the run stopped unexpectedly (its process ended with exit code"
            f" {code}): does the mission call exit(), or use a great deal of memory?",
            f"worker exit code {code}; {data or 'no result was sent'}",
            wall,
        )
    if time.monotonic() >= run.deadline:
        _stop(run.process)
        run.connection.close()
        limit = run.task.spec.wall_time_limit_s
        return _failed(
            run,
            "timeout",
            f"timed out after {limit:g} s of wall time (the mission may loop forever:"
            " look for a condition or behaviour that never returns)",
            f"stopped by the grader after {limit:g} s of wall time",
            wall,
        )
    return None


def _failed(run: _Running, status: str, message: str, debug: str, wall: float) -> RunResult:
    task = run.task
    return task.spec.result(
        task.variant,
        student=task.student,
        mission=task.mission,
        status=status,
        message=message,
        wall_time_s=wall,
        debug=debug,
    )


def _stop(process: BaseProcess) -> None:
    """End a worker: politely, then for sure."""
    if process.is_alive():
        process.terminate()
        process.join(_KILL_GRACE_S)
    if process.is_alive():
        process.kill()
    process.join(_KILL_GRACE_S)


def crash_result(task: RunTask, exc: BaseException) -> dict[str, Any]:
    """The result dictionary of a run whose grading raised ``exc`` (in the worker)."""
    where = ""
    frames = traceback.extract_tb(exc.__traceback__)
    if frames:
        where = f" ({os.path.basename(frames[-1].filename)}:{frames[-1].lineno})"
    text = str(exc).splitlines()[0] if str(exc) else ""
    return task.spec.result(
        task.variant,
        student=task.student,
        mission=task.mission,
        status="crashed",
        message=f"the run crashed: {type(exc).__name__}{': ' + text if text else ''}{where}",
        debug="".join(traceback.format_exception(exc)),
    ).to_dict()
