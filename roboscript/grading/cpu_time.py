"""CPU time (and memory) a process tree has used: what a student's code consumed, whatever the
machine's load.

The grader judges a mission process by the CPU time it used, never by wall time: on a busy
machine an honest process waits for a CPU, and that wait is not its own. Linux tells every
process's CPU time in ``/proc/PID/stat``; the tree is found from the jail's first process
down, through each thread's list of children (the interpreter under ``bwrap``, ``setpriv`` and
the student's own children all count), and the time of children already reaped is in their
parent's total. Reading the tree costs a few files, not one per process of the machine: the
world reads it while its run goes on.
"""

from __future__ import annotations

import os
from collections.abc import Callable

from roboscript.grading.processes import (
    CHILDREN_LISTED,
    listed_children,
    memory_bytes,
    read_stat,
    stats,
    waited_s,
)

__all__ = [
    "process_tree_cpu_s",
    "process_tree_memory_bytes",
    "process_tree_stopped",
    "process_tree_waited_s",
]


def process_tree_cpu_s(root_pid: int) -> float | None:
    """CPU seconds (user and system) used by ``root_pid`` and every process below it.

    Returns:
        The seconds, or None where the system does not tell (no ``/proc``: macOS, Windows) or
        the process is gone.
    """
    found = _scan(root_pid)
    return None if found is None else sum(found.values())


def _tree(root_pid: int) -> list[int]:
    found = _scan(root_pid)
    return [] if found is None else list(found)


def _scan(root_pid: int) -> dict[int, float] | None:
    """Each process of the tree and its CPU seconds, or None."""
    if not os.path.isdir("/proc/self"):
        return None
    if CHILDREN_LISTED:
        return _walk(root_pid)
    return _scan_all(root_pid)


def _walk(root_pid: int) -> dict[int, float] | None:
    """The tree, from each of its threads' list of children: a handful of files for a jail's
    few processes, where reading every process's ``stat`` takes milliseconds on a desktop."""
    return _gather(root_pid, listed_children, _cpu_s)


def _cpu_s(pid: int) -> float | None:
    """Process ``pid``'s CPU seconds, its own and its reaped children's; None if it ended."""
    found = read_stat(pid)
    return None if found is None else found.cpu_with_reaped_children_s


def _scan_all(root_pid: int) -> dict[int, float] | None:
    """The tree, from every process's parent (where the system lists no children)."""
    children: dict[int, list[int]] = {}
    cpu: dict[int, float] = {}
    for pid, found in stats():
        cpu[pid] = found.cpu_with_reaped_children_s
        children.setdefault(found.parent, []).append(pid)
    if root_pid not in cpu:
        return None
    return _gather(root_pid, lambda pid: children.get(pid, []), lambda pid: cpu.get(pid, 0.0))


def _gather(
    root_pid: int,
    children_of: Callable[[int], list[int]],
    cpu_s_of: Callable[[int], float | None],
) -> dict[int, float] | None:
    """Each process from ``root_pid`` down and its CPU seconds; None if the root is gone (a
    process gone below it is left out: its time is in its parent's once reaped)."""
    tree: dict[int, float] = {}
    queue = [root_pid]
    while queue:
        pid = queue.pop()
        if pid in tree:
            continue
        cpu_s = cpu_s_of(pid)
        if cpu_s is None:
            if pid == root_pid:
                return None
            continue
        tree[pid] = cpu_s
        queue.extend(children_of(pid))
    return tree


def process_tree_memory_bytes(root_pid: int) -> int | None:
    """Memory ``root_pid`` and every process below it hold together, in bytes (each page
    counted once, shared ones split among their processes); None where unknown."""
    pids = _tree(root_pid)
    if not pids:
        return None
    return sum(held or 0 for held in map(memory_bytes, pids))


def process_tree_waited_s(root_pid: int) -> float | None:
    """Seconds the main threads of ``root_pid``'s tree spent waiting for a CPU (runnable, but
    another program had it), from Linux's scheduler statistics; None where unknown."""
    pids = _tree(root_pid)
    if not pids:
        return None
    return sum(waited or 0.0 for waited in map(waited_s, pids))


def process_tree_stopped(root_pid: int) -> bool:
    """True when a process of ``root_pid``'s tree is stopped (``SIGSTOP``, ``SIGTSTP``; state
    ``T`` or ``t`` in ``/proc/PID/stat``): it uses no CPU and waits for none, so neither rule on
    CPU time ever ends it. False where the system does not tell."""
    for pid in _tree(root_pid):
        found = read_stat(pid)  # None: it ended meanwhile
        if found is not None and found.state in ("T", "t"):
            return True
    return False
