"""Run graded runs in worker processes, in parallel.

A worker process hosts the simulated world of each run and judges it
(:mod:`roboscript.grading.worker`); the student's mission runs in a sandboxed process the
worker starts (:mod:`roboscript.grading.world_host`). Neither the parent nor a worker ever
loads a student's file. The parent

* gives one worker all the runs of a student's mission that may share a jail (the same files
  and robot, all hidden or all visible; split only when they are more than one worker's share
  of the class), so a student costs one worker and one warm jail per kind of run;
* starts at most ``jobs`` workers at a time (forked from a server process that has already
  imported roboscript, so a worker is ready in milliseconds; spawned where fork is not
  available);
* learns from each mission's first run whether it loads: when the mission does not load,
  crashes or hangs while loading, that one result stands for all of its runs on the same
  robot, so a broken submission costs one run, not one per variant. The worker doing that
  first run gives its result to the rest of its own runs itself, without running them; the
  parent holds the mission's other workers back (its hidden runs, or runs past one worker's
  share) until that first run has ended, and gives them the same result;
* keeps each worker, its jail and so its runs' two processes on one CPU core, cores shared
  evenly among workers (:mod:`roboscript.grading.cores`: hand-overs on one core are cheaper);
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

import math
import multiprocessing
import os
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from multiprocessing.connection import Connection, wait
from multiprocessing.process import BaseProcess
from pathlib import Path
from typing import Any

from roboscript.grading.cores import CoreShare, keep_on_core
from roboscript.grading.cpu_time import process_tree_waited_s
from roboscript.grading.record import RunResult, RunStatus
from roboscript.grading.sandbox import byte_compile_package
from roboscript.grading.task import RunTask, crash_result

__all__ = ["RunTask", "bounded_jobs", "crash_result", "default_jobs", "run_tasks"]

_KILL_GRACE_S = 2.0


def default_jobs() -> int:
    """How many runs to do at once by default, and at most: one per CPU core this process may
    use (its affinity, so a container or ``taskset`` limit counts, not the machine's cores).

    Each run keeps one core busy (its world and its mission take turns), so more runs at once
    would only wait for each other, each holding a sandbox, processes and memory meanwhile.
    """
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


def bounded_jobs(requested: int | None) -> tuple[int, str]:
    """The runs to do at once for ``--jobs requested``, and a warning (one sentence, or
    empty) when ``requested`` was more than :func:`default_jobs` allows.

    Raises:
        ValueError: ``requested`` is less than 1.
    """
    most = default_jobs()
    if requested is None:
        return most, ""
    if requested < 1:
        raise ValueError("--jobs must be 1 or more")
    if requested <= most:
        return requested, ""
    cores = f"{most} CPU core{'s' if most != 1 else ''}"
    return most, (
        f"--jobs {requested} is more than the {cores} this machine gives roboscript: grading"
        f" {most} run{'s' if most != 1 else ''} at once (more would only wait for each other)"
    )


_LONGEST_SOCKET_FOLDER = 64
"""Longest temporary folder (bytes) the fork server's socket fits in: its path (the folder, a
``pymp-`` folder and a ``listener-`` name, about 35 bytes more) must fit the 107 bytes of a
Unix socket's address."""


def _context() -> Any:
    long_folder = len(os.fsencode(tempfile.gettempdir())) > _LONGEST_SOCKET_FOLDER
    if "forkserver" in multiprocessing.get_all_start_methods() and not long_folder:
        context = multiprocessing.get_context("forkserver")
        # Workers fork from a server that has imported the simulator, drivers and runner once.
        # That server looks modules up in the working folder first: one that holds a
        # roboscript.py would give every worker that file as the package, so there each
        # worker imports the package for itself instead.
        hidden = _working_folder_hides_package()
        context.set_forkserver_preload([] if hidden else ["roboscript.grading.worker"])
        return context
    # Each worker then imports what it needs itself: slower to start, and the same grades.
    return multiprocessing.get_context("spawn")


def _working_folder_hides_package() -> bool:
    """Whether the working folder holds a ``roboscript.py``, or a ``roboscript`` folder that
    is not this package, which an import from that folder would take for the package."""
    here = Path.cwd()
    folder = here / "roboscript"
    ours = Path(__file__).resolve().parents[1]
    return (here / "roboscript.py").exists() or (folder.is_dir() and folder.resolve() != ours)


@dataclass
class _Running:
    batch: list[tuple[int, RunTask]]
    """The runs the worker has not reported yet, in the order it does them."""
    process: BaseProcess
    connection: Connection
    started: float
    deadline: float
    core: int | None
    """The core the worker keeps itself and its jail on (:mod:`roboscript.grading.cores`)."""


def _jail_key(task: RunTask) -> tuple[object, ...]:
    """Runs with the same key may share a jail: the same mission, files and robot, and all
    hidden or all visible (a run could keep what it saw for the next in its jail)."""
    return task.mission, task.visible, task.spec.robot, task.variant.hidden


def _batches(tasks: Sequence[RunTask], jobs: int) -> list[list[tuple[int, RunTask]]]:
    """The runs, in batches that share a jail; no batch so long that a worker idles."""
    groups: dict[tuple[object, ...], list[tuple[int, RunTask]]] = {}
    for index, task in enumerate(tasks):
        groups.setdefault(_jail_key(task), []).append((index, task))
    longest = max(1, math.ceil(len(tasks) / jobs))
    return [
        group[start : start + longest]
        for group in groups.values()
        for start in range(0, len(group), longest)
    ]


def run_tasks(
    tasks: Sequence[RunTask],
    jobs: int | None = None,
    on_result: Callable[[RunResult], None] | None = None,
    keep: Callable[[RunResult], RunResult] | None = None,
) -> list[RunResult]:
    """Do every task in a worker process, ``jobs`` workers at a time.

    A worker does the runs of one student's mission that may share a jail (see
    :func:`roboscript.grading.worker.work`), one after the other, in one warm jail. A mission
    that ends while loading in its first run gets that result for every run (see the module
    docstring).

    Args:
        tasks: The runs.
        jobs: Workers at once (default: one per CPU core).
        on_result: Called in the parent with each result as it comes (for progress).
        keep: What to hold of each result until the end, called with it as it comes (before
            ``on_result``): a summary, when the full result is written elsewhere, so a class's
            records and replays are not all held at once. By default, the whole result.

    Returns:
        One result per task (or what ``keep`` made of it), in the order of ``tasks``.
    """
    jobs = max(1, jobs or default_jobs())
    # Before any jail starts: a jail cannot compile, so every run would compile from source.
    byte_compile_package()
    context = _context()
    cores = CoreShare()
    waiting = _batches(tasks, jobs)
    results: dict[int, RunResult] = {}
    running: list[_Running] = []
    probing: set[tuple[str, str]] = set()  # keys whose first run is under way
    loaded: set[tuple[str, str]] = set()  # keys whose mission is known to load

    def deliver(index: int, result: RunResult) -> None:
        results[index] = result if keep is None else keep(result)
        if on_result is not None:
            on_result(result)

    def same_for_all(key: tuple[str, str], first: RunResult) -> None:
        """The mission ended while loading: every other run of it ends the same way."""
        for batch in [b for b in waiting if b[0][1].load_key == key]:
            waiting.remove(batch)
            for index, task in batch:
                deliver(index, _same_as(first, task))

    try:
        while waiting or running:
            for batch in list(waiting):
                if len(running) >= jobs:
                    break
                key = batch[0][1].load_key
                if key in probing:
                    continue  # wait for the first run of this mission to say whether it loads
                first = key not in loaded
                if first:
                    probing.add(key)
                waiting.remove(batch)
                running.append(_start(context, batch, first, cores.take()))
            if not running:
                continue  # a batch was put back: start it
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
                # Whether the worker lives is read before its pipe: one that sends its last
                # result and ends after ``wait`` returned is read now, not mistaken for a
                # worker that died with its batch undone (and its batch done again).
                alive = run.process.is_alive()
                for index, result, copies in _collect(
                    run, ready if alive else ready | {run.process.sentinel}
                ):
                    deliver(index, result)
                    for other_index, other in copies:  # the worker ended them with this one
                        deliver(other_index, _same_as(result, other))
                    key = tasks[index].load_key
                    if key not in probing:
                        continue
                    probing.discard(key)
                    if result.during_load:
                        same_for_all(key, result)
                    else:
                        loaded.add(key)
                if run.batch and alive:
                    still.append(run)
                    continue
                if run.batch:  # the worker ended before doing them all: do them again
                    probing.discard(run.batch[0][1].load_key)  # its first run included
                    waiting.insert(0, list(run.batch))
                else:  # done: it closes its jail and ends by itself
                    run.process.join(_KILL_GRACE_S)
                _stop(run.process)
                run.connection.close()
                cores.give(run.core)
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


def _start(
    context: Any, batch: list[tuple[int, RunTask]], first: bool, core: int | None
) -> _Running:
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(
        target=_worker_entry,
        args=(sender, batch, first, core),
        name=f"roboscript-grade-{batch[0][0]}",
        daemon=True,
    )
    started = time.monotonic()
    process.start()
    sender.close()  # the parent keeps only its reading end, so a dead worker reads as EOF
    deadline = _deadline(started, batch[0][1])
    return _Running(list(batch), process, receiver, started, deadline, core)


def _deadline(started: float, task: RunTask) -> float:
    return started + task.spec.longest_wall_time_s


def _worker_entry(
    connection: Connection, batch: list[tuple[int, RunTask]], first: bool, core: int | None
) -> None:
    # First of all, so the jail and every run's mission inherit it: a run's two processes
    # then hand over on one core instead of waking another (see roboscript.grading.cores).
    keep_on_core(core)
    # the worker warms every simulated device when imported: only its process needs them
    from roboscript.grading.worker import work

    work(connection, batch, first=first)


_Found = tuple[int, RunResult, list[tuple[int, RunTask]]]
"""A run's index and result, and the runs of the batch that the worker ended with it."""


def _collect(run: _Running, ready: set[Any]) -> list[_Found]:
    """The results the worker has now (sent, or its run failed as it died or timed out)."""
    found: list[_Found] = []
    now = time.monotonic()
    if run.connection in ready or run.process.sentinel in ready:
        while run.batch and run.connection.poll():
            try:
                data = run.connection.recv()
            except (EOFError, OSError):
                break
            except Exception as exc:  # noqa: BLE001 - a half-sent result from a dying worker
                found.append(_lost(run, f"unreadable result: {type(exc).__name__}: {exc}"))
                break
            index, result, ended_with = data
            position = next(i for i, (n, _task) in enumerate(run.batch) if n == index)
            wall = round(now - run.started, 3)
            del run.batch[position]
            copies = [(n, task) for n, task in run.batch if n in ended_with]
            run.batch = [(n, task) for n, task in run.batch if n not in ended_with]
            found.append((index, replace(RunResult.from_dict(result), wall_time_s=wall), copies))
            run.started = now
            if run.batch:
                run.deadline = _deadline(now, run.batch[0][1])
        if found or run.process.is_alive():
            return found
        code = run.process.exitcode
        if run.batch:
            found.append(_lost(run, f"world worker exit code {code}; no result was sent", code))
        return found
    if now >= run.deadline and run.batch and not _busy_machine_delayed(run):
        _stop(run.process)
        wall = round(now - run.started, 3)
        index, task = run.batch.pop(0)
        found.append(
            (
                index,
                _failed(
                    task,
                    "crashed",
                    "the grader could not finish this run in time; this is a roboscript"
                    " problem, not the student's: please report it",
                    f"world worker stopped by the parent after {wall:g} s",
                    wall,
                ),
                [],
            )
        )
    return found


def _busy_machine_delayed(run: _Running) -> bool:
    """True (and the deadline moved) when the worker's tree waited for a CPU long enough that
    its limits are not yet used up: a busy machine's time is not the run's."""
    waited_s = process_tree_waited_s(run.process.pid or 0) or 0.0
    left_s = run.deadline - (time.monotonic() - waited_s)
    if left_s <= 0:
        return False
    run.deadline = time.monotonic() + left_s
    return True


def _lost(run: _Running, debug: str, code: int | None = None) -> _Found:
    """The worker's current run, when the worker died without sending it."""
    index, task = run.batch.pop(0)
    wall = round(time.monotonic() - run.started, 3)
    result = _failed(
        task,
        "crashed",
        "the grader could not finish this run (its world process ended with exit code"
        f" {code}); this is a roboscript problem, not the student's: please report it",
        debug,
        wall,
    )
    return index, result, []


def _failed(task: RunTask, status: RunStatus, message: str, debug: str, wall: float) -> RunResult:
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
