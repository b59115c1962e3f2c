"""The graded mission process's stuck-watch: it writes the stacks only when the mission is stuck.

Reading another thread's frames while that thread runs Python code is not safe: when the
watch fired on a timer in healthy runs, a busy machine saw some honest students' runs die of
a segmentation fault. Progress must restart the countdown; no progress must still end in a
dump, so the grader can name the line a hung mission is stuck on.
"""

from __future__ import annotations

import subprocess
import sys

SCRIPT = """
import time
from roboscript.grading.mission_host import _StuckWatch

watch = _StuckWatch(1.5)
watch.arm()
end = time.monotonic() + 3.0
while time.monotonic() < end:  # a healthy mission: progress on every tick
    watch.progress()
    time.sleep(0.001)
print("healthy part done", flush=True)
time.sleep(2.5)  # now stuck: no progress
"""


def test_progress_holds_the_dump_back_and_a_stall_lets_it_out() -> None:
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], check=False, capture_output=True, text=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "healthy part done\n"
    # one dump, 1.5 s into the stall; none in the 3 s of progress before it (a timer that
    # progress did not restart would have fired at 1.5 s and 3 s as well)
    assert done.stderr.count("Timeout (0:00:01.500000)!") == 1
    assert "in <module>" in done.stderr
