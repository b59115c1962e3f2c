"""Run graded runs in worker processes, in parallel.

Each run has a worker process of its own that hosts the simulated world and judges the run
(:mod:`roboscript.grading.worker`); the student's mission runs in a sandboxed process the
worker starts (:mod:`roboscript.grading.world_host`). Neither the parent nor a worker ever
loads a student's file. The parent

* starts at most ``jobs`` workers at a time (forked from a server process that has already
  imported roboscript, so a worker is ready in milliseconds; spawned where fork is not
  available);
* runs each mission's first run alone: when the mission does not load, crashes or hangs while
  loading, that one result stands for all of its runs on the same robot, so a broken
  submission costs one run, not one per variant;
* gives each result to ``on_result`` the moment it arrives (the command line writes it out at
  once, so a grader that is killed keeps every finished run);
* stops a worker that outlives its run's limits by a wide margin (it never should) and records
  the run as ``crashed``.

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
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from typing import Any

from roboscript.grading.record import RunResult, RunStatus
from roboscript.grading.sandbox import byte_compile_package
from roboscript.grading.task import RunTask, crash_result

__all__ = ["RunTask", "crash_result", "default_jobs", "run_tasks"]

_KILL_GRACE_S = 2.0
_BACKSTOP_S = 15.0
"""A worker enforces its run's limits itself; the parent ends one this far past them."""


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
    # Before any jail starts: a jail cannot compile, so every run would compile from source.
    byte_compile_package()
    context = _context()
    waiting = list(enumerate(tasks))
    results: dict[int, RunResult] = {}
    running: list[_Running] = []
    probing: set[tuple[str, str]] = set()  # keys whose first run is under way
    loaded: set[tuple[str, str]] = set()  # keys whose mission is known to load

    def deliver(index: int, result: RunResult) -> None:
        results[index] = result
        if on_result is not None:
            on_result(result)

    try:
        while waiting or running:
            for entry in list(waiting):
                if len(running) >= jobs:
                    break
                index, task = entry
                key = task.load_key
                if key in probing:
                    continue  # wait for the first run of this mission to say whether it loads
                if key not in loaded:
                    probing.add(key)
                waiting.remove(entry)
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
                deliver(run.index, result)
                key = run.task.load_key
                if key in probing:
                    probing.discard(key)
                    if result.during_load:
                        for entry in [e for e in waiting if e[1].load_key == key]:
                            waiting.remove(entry)
                            deliver(entry[0], _same_as(result, entry[1]))
                    else:
                        loaded.add(key)
            running = still
    finally:
        for run in running:  # interrupted (Ctrl-C): leave no worker behind
            _stop(run.process)
    return [results[i] for i in range(len(tasks))]


def _same_as(first: RunResult, task: RunTask) -> RunResult:
    """``task``'s result when its mission ended while loading in ``first``."""
    return task.spec.result(
        task.variant,
        student=task.student,
        mission=task.mission,
        status=first.status,
        message=first.message,
        debug=first.debug,
        during_load=True,
    )


def _start(context: Any, index: int, task: RunTask) -> _Running:
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(
        target=_worker_entry, args=(sender, task), name=f"roboscript-grade-{index}", daemon=True
    )
    started = time.monotonic()
    process.start()
    sender.close()  # the parent keeps only its reading end, so a dead worker reads as EOF
    deadline = started + task.spec.wall_time_limit_s + _BACKSTOP_S
    return _Running(task, index, process, receiver, started, deadline)


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
            "the grader could not finish this run (its world process ended with exit code"
            f" {code}); this is a roboscript problem, not the student's: please report it",
            f"world worker exit code {code}; {data or 'no result was sent'}",
            wall,
        )
    if time.monotonic() >= run.deadline:
        _stop(run.process)
        run.connection.close()
        return _failed(
            run,
            "crashed",
            "the grader could not finish this run in time; this is a roboscript problem, not"
            " the student's: please report it",
            f"world worker stopped by the parent after {wall:g} s",
            wall,
        )
    return None


def _failed(run: _Running, status: RunStatus, message: str, debug: str, wall: float) -> RunResult:
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
