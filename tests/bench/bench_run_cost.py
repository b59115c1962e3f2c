"""The cost of one graded run, in CPU seconds: the figure that sizes a sharded grading.

Run by hand, not by pytest::

    python tests/bench/bench_run_cost.py [--students N] [--jobs N]

It grades a class of N copies of ``missions/teacher/square/good.yaml`` (default 6) against
``missions/teacher/square/test.yaml`` (3 runs of about 30 s of simulated time each) with
``roboscript grade``, and adds up the CPU time of the grader and every process under it (the
workers, the sandboxes, the students' missions), read from ``/proc`` every 20 ms: the
processes run in a fork server and a sandbox's own PID namespace, whose CPU time the shell's
``time`` never sees. CPU time does not depend on what else the machine runs, so the figure
holds on a loaded machine; wall time does, and is printed beside it. A process that lives
less than 20 ms is missed: the figure is a little low, never high.

Linux only (``/proc``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "missions" / "teacher" / "square"
TICKS_PER_S = os.sysconf("SC_CLK_TCK")


def _processes() -> dict[int, tuple[int, str, float]]:
    """Every process now: pid -> (parent pid, start time, CPU seconds used)."""
    found = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            text = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue  # ended meanwhile
        fields = text[text.rindex(")") + 2 :].split()
        # after the name: state ppid ... utime(12) stime(13) ... starttime(20), 0-based here
        cpu = (int(fields[11]) + int(fields[12])) / TICKS_PER_S
        found[int(entry)] = (int(fields[1]), fields[19], cpu)
    return found


def measure(command: list[str]) -> tuple[float, float, int]:
    """Run ``command``; its wall seconds, CPU seconds of it and every descendant, exit status."""
    started = time.monotonic()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    seen: dict[tuple[int, str], float] = {}
    tree = {child.pid}
    while child.poll() is None:
        now = _processes()
        for pid, (parent, _, _) in sorted(now.items()):
            if parent in tree:
                tree.add(pid)
        for pid in tree:
            if pid in now:
                key = (pid, now[pid][1])
                seen[key] = max(seen.get(key, 0.0), now[pid][2])
        time.sleep(0.02)
    return time.monotonic() - started, sum(seen.values()), child.returncode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--students", type=int, default=6)
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        for i in range(args.students):
            shutil.copy(SQUARE / "good.yaml", Path(folder) / f"student{i:03}.yaml")
        command = [
            sys.executable, "-m", "roboscript", "grade", str(SQUARE / "test.yaml"),
            "--mission", folder, "--jobs", str(args.jobs), "--quiet", "--hang-after", "30",
        ]  # fmt: skip
        wall, cpu, status = measure(command)
    runs = args.students * 3
    print(f"{runs} runs (exit {status}): {wall:.1f} s wall, {cpu:.1f} s CPU")
    print(f"per run: {cpu / runs:.2f} s CPU, {wall / runs:.2f} s wall at --jobs {args.jobs}")
    per_1000 = cpu / runs * 3000 / 3600
    print(f"a class of 1000 students x 3 runs: about {per_1000:.1f} CPU hours")


if __name__ == "__main__":
    main()
