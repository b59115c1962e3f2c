"""A jail's CPU time counts every process in it, the student's own children too."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from helpers import HANG_BOUND_S

from roboscript.grading.cpu_time import process_tree_cpu_s, process_tree_waited_s

BURN = """
import time
while time.process_time() < 0.5:
    pass
print("burnt", flush=True)
time.sleep(600)
"""

pytestmark = pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")


def test_the_cpu_time_of_a_grandchild_counts_for_the_tree() -> None:
    # a shell (the jail's first process) whose child does the work
    tree = subprocess.Popen(
        ["sh", "-c", f"\"{sys.executable}\" -c '{BURN}'"],
        stdout=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        assert tree.stdout is not None
        assert tree.stdout.readline() == "burnt\n"
        used = process_tree_cpu_s(tree.pid)
        assert used is not None and used >= 0.4  # counted in clock ticks: a little behind
        waited = process_tree_waited_s(tree.pid)
        assert waited is not None and waited >= 0.0
    finally:
        os.killpg(tree.pid, 9)
        tree.wait(HANG_BOUND_S)


def test_a_process_that_is_gone_has_no_cpu_time() -> None:
    gone = max(int(name) for name in os.listdir("/proc") if name.isdigit()) + 100_000
    assert process_tree_cpu_s(gone) is None
    assert process_tree_waited_s(gone) is None
