"""A graded run's processes ask for short scheduler slices; the processes they start keep them."""

from __future__ import annotations

import platform
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S

from roboscript.grading.latency import SLICE_NS

SCHED = Path("/proc/self/sched")


def _kernel_at_least(major: int, minor: int) -> bool:
    numbers = platform.release().split("-")[0].split(".")
    try:
        return (int(numbers[0]), int(numbers[1])) >= (major, minor)
    except (IndexError, ValueError):
        return False


@pytest.mark.skipif(
    sys.platform != "linux" or not SCHED.exists() or not _kernel_at_least(6, 12),
    reason="short slices are a request of Linux 6.12 and later",
)
def test_a_short_slice_is_granted_and_inherited_by_the_processes_started_after() -> None:
    # In a process of its own, so that this test process keeps its slice.
    code = (
        "import subprocess, sys\n"
        "from roboscript.grading.latency import ask_short_slice\n"
        "assert ask_short_slice()\n"
        "child = [sys.executable, '-c', 'print(open(\"/proc/self/sched\").read())']\n"
        "print(subprocess.run(child, capture_output=True, text=True, check=True).stdout)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code],
        check=False,
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
    )
    assert done.returncode == 0, done.stderr
    slices = [line.split(":")[1].strip() for line in done.stdout.splitlines() if "slice" in line]
    assert slices == [str(SLICE_NS)]
