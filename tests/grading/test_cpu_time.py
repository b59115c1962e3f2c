"""A jail's CPU time counts every process in it, the student's own children too."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager

import pytest
from helpers import HANG_BOUND_S

from roboscript.grading import cpu_time, processes
from roboscript.grading.cpu_time import (
    process_tree_cpu_s,
    process_tree_stopped,
    process_tree_waited_s,
)

BURN = """
import time
while time.process_time() < 0.5:
    pass
print("burnt", flush=True)
time.sleep(600)
"""

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")


@contextmanager
def _burnt(argv: list[str]) -> Iterator[int]:
    """The first process of a tree started by ``argv``, once one of its processes has burnt
    half a CPU second (it says so); the whole tree is killed afterwards."""
    tree = subprocess.Popen(argv, stdout=subprocess.PIPE, text=True, start_new_session=True)
    try:
        assert tree.stdout is not None
        assert tree.stdout.readline() == "burnt\n"
        yield tree.pid
    finally:
        os.killpg(tree.pid, 9)
        tree.wait(HANG_BOUND_S)


def test_the_cpu_time_of_a_grandchild_counts_for_the_tree() -> None:
    # a shell (the jail's first process) whose child does the work
    with _burnt(["sh", "-c", f"\"{sys.executable}\" -c '{BURN}'"]) as pid:
        used = process_tree_cpu_s(pid)
        assert used is not None and used >= 0.4  # counted in clock ticks: a little behind
        waited = process_tree_waited_s(pid)
        assert waited is not None and waited >= 0.0


def test_a_process_that_is_gone_has_no_cpu_time() -> None:
    gone = max(int(name) for name in os.listdir("/proc") if name.isdigit()) + 100_000
    assert process_tree_cpu_s(gone) is None
    assert process_tree_waited_s(gone) is None


THREAD_BURN = f"""
import subprocess, sys, threading, time
def start():
    subprocess.Popen([sys.executable, "-c", {BURN!r}])
    time.sleep(600)  # alive: its children stay its own, not its process's main thread's
worker = threading.Thread(target=start)
worker.start()
worker.join()
"""


def test_a_child_started_by_a_thread_counts_for_the_tree() -> None:
    # Linux lists a child under the thread that started it, not under its process
    with _burnt([sys.executable, "-c", THREAD_BURN]) as pid:
        used = process_tree_cpu_s(pid)
        assert used is not None and used >= 0.4


def test_the_tree_is_the_same_whether_read_from_children_or_from_parents() -> None:
    # where Linux lists no children, every process's parent gives the same tree
    tree = subprocess.Popen(
        ["sh", "-c", "sleep 600 & sleep 600 & (sleep 600 & wait) & wait"],
        start_new_session=True,
    )
    try:
        expected = 5  # the shell, two sleeps, a subshell and its sleep
        for _ in range(int(HANG_BOUND_S / 0.01)):
            found = cpu_time._scan_all(tree.pid)
            if found is not None and len(found) == expected:
                break
            time.sleep(0.01)
        assert found is not None and len(found) == expected
        if processes.CHILDREN_LISTED:
            walked = cpu_time._walk(tree.pid)
            assert walked is not None and set(walked) == set(found)
    finally:
        os.killpg(tree.pid, 9)
        tree.wait(HANG_BOUND_S)


def test_a_tree_with_a_stopped_grandchild_is_stopped_and_one_running_is_not() -> None:
    stops = "import os, signal; print('burnt', flush=True); os.kill(os.getpid(), signal.SIGSTOP)"
    parent = f"import subprocess, sys, time; subprocess.Popen([sys.executable, '-c', {stops!r}]);"
    with _burnt([sys.executable, "-c", parent + " time.sleep(600)"]) as root:
        deadline = time.monotonic() + HANG_BOUND_S  # a bound for a broken test only
        while not process_tree_stopped(root):
            assert time.monotonic() < deadline, "never seen stopped"
            time.sleep(0.01)
    with _burnt([sys.executable, "-c", BURN]) as root:
        assert not process_tree_stopped(root)


def _child_stopped(parent: int) -> bool:
    """True once a child of ``parent`` is stopped, as its ``status`` file tells."""
    mine = str(parent).encode()
    return any(
        fields.get(b"PPid") == mine and fields.get(b"State", b"").startswith(b"T")
        for _pid, fields in processes.statuses()
    )


RENAMED_AND_STOPPED = """
import ctypes, os, signal
# a name that reads as running, parent 1, to a reader splitting stat at the first ")"
ctypes.CDLL(None).prctl(15, b"a) (R 1\\nb", 0, 0, 0)  # PR_SET_NAME
print("burnt", flush=True)
os.kill(os.getpid(), signal.SIGSTOP)
"""


def test_a_child_named_with_parentheses_and_a_newline_counts_and_is_seen_stopped() -> None:
    parent = (
        "import subprocess, sys, time;"
        f" subprocess.Popen([sys.executable, '-c', {RENAMED_AND_STOPPED!r}]); time.sleep(600)"
    )
    with _burnt([sys.executable, "-c", parent]) as root:
        deadline = time.monotonic() + HANG_BOUND_S  # a bound for a broken test only
        while not _child_stopped(root):  # told by status, which escapes the name
            assert time.monotonic() < deadline, "never stopped"
            time.sleep(0.01)
        assert process_tree_stopped(root)
        scanned = cpu_time._scan_all(root)
        assert scanned is not None and len(scanned) == 2  # the parent and its renamed child
        if processes.CHILDREN_LISTED:
            walked = cpu_time._walk(root)
            assert walked is not None and set(walked) == set(scanned)
