"""CPU time a process tree has used: what a student's code consumed, whatever the machine's load.

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

__all__ = ["process_tree_cpu_s", "process_tree_stopped", "process_tree_waited_s"]

_TICKS_PER_S = float(os.sysconf("SC_CLK_TCK")) if hasattr(os, "sysconf") else 100.0
_CHILDREN_LISTED = os.path.exists(f"/proc/{os.getpid()}/task/{os.getpid()}/children")
"""Whether Linux lists each thread's children (``CONFIG_PROC_CHILDREN``, on in the common
distributions' kernels)."""


def _stat(pid: str) -> tuple[int, float] | None:
    """A process's parent and its CPU seconds (its own and its reaped children's), or None."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as handle:
            text = handle.read()
    except OSError:
        return None  # it ended meanwhile
    # The name (field 2) may hold spaces and parentheses: fields follow the last ")".
    fields = text[text.rfind(b")") + 2 :].split()
    try:
        parent = int(fields[1])
        ticks = int(fields[11]) + int(fields[12]) + int(fields[13]) + int(fields[14])
    except (IndexError, ValueError):
        return None
    return parent, ticks / _TICKS_PER_S


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
    if _CHILDREN_LISTED:
        return _walk(root_pid)
    return _scan_all(root_pid)


def _walk(root_pid: int) -> dict[int, float] | None:
    """The tree, from each of its threads' list of children: a handful of files for a jail's
    few processes, where reading every process's ``stat`` takes milliseconds on a desktop."""
    return _gather(root_pid, _listed_children, _own_cpu_s)


def _own_cpu_s(pid: int) -> float | None:
    found = _stat(str(pid))
    return None if found is None else found[1]


def _listed_children(pid: int) -> list[int]:
    children: list[int] = []
    try:
        threads = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return children
    for thread in threads:  # a child's parent is the thread that started it
        try:
            with open(f"/proc/{pid}/task/{thread}/children", "rb") as handle:
                children.extend(int(child) for child in handle.read().split())
        except (OSError, ValueError):
            continue
    return children


def _scan_all(root_pid: int) -> dict[int, float] | None:
    """The tree, from every process's parent (where the system lists no children)."""
    children: dict[int, list[int]] = {}
    cpu: dict[int, float] = {}
    try:
        names = os.listdir("/proc")
    except OSError:
        return None
    for name in names:
        if not name.isdigit():
            continue
        found = _stat(name)
        if found is None:
            continue
        pid = int(name)
        cpu[pid] = found[1]
        children.setdefault(found[0], []).append(pid)
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


def process_tree_waited_s(root_pid: int) -> float | None:
    """Seconds the main threads of ``root_pid``'s tree spent waiting for a CPU (runnable, but
    another program had it), from Linux's scheduler statistics; None where unknown."""
    pids = _tree(root_pid)
    if not pids:
        return None
    total = 0.0
    for pid in pids:
        try:
            with open(f"/proc/{pid}/schedstat", "rb") as handle:
                total += int(handle.read().split()[1]) / 1e9
        except (OSError, ValueError, IndexError):
            continue  # it ended meanwhile
    return total


def process_tree_stopped(root_pid: int) -> bool:
    """True when a process of ``root_pid``'s tree is stopped (``SIGSTOP``, ``SIGTSTP``; state
    ``T`` or ``t`` in ``/proc/PID/stat``): it uses no CPU and waits for none, so neither rule on
    CPU time ever ends it. False where the system does not tell."""
    for pid in _tree(root_pid):
        try:
            with open(f"/proc/{pid}/stat", "rb") as handle:
                text = handle.read()
        except OSError:
            continue  # it ended meanwhile
        if text[text.rfind(b")") + 2 : text.rfind(b")") + 3] in (b"T", b"t"):
            return True
    return False
