"""What one student's warm jail costs: the CPU of its start, and of a run forked from it.

Run by hand, not by pytest::

    python tests/bench/bench_jail_start.py [--quick]

A graded student gets one warm jail (:class:`roboscript.grading.sandbox.WarmJail`): a
sandboxed interpreter that imports everything a run imports, once, then forks each run. This
starts such jails for a one-minute benchmark mission, as the grader does, and reads the CPU
time of each jail's processes from ``/proc`` (the jail's server, and the runs it forked and
reaped), so the machine's load changes the figures little: waiting for a CPU is not CPU time.

* the jail's start: bubblewrap, the interpreter and its imports, until the server is ready;
* a short run forked from it (one simulated second: mostly loading the mission, connecting
  and the handshake, which a one-minute run pays once too), as a ratio to the start.

Linux only (warm jails are). Figures are medians of several jails.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
for _path in (str(HERE), str(HERE.parent.parent)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

from benchlib import Row, info, machine_header, run_alone  # noqa: E402

from roboscript.grading.run import grade_run  # noqa: E402
from roboscript.grading.sandbox import (  # noqa: E402
    byte_compile_package,
    detect_isolation,
    warm_jails_supported,
)
from roboscript.grading.spec import load_test_spec  # noqa: E402
from roboscript.grading.world_host import warm_jail  # noqa: E402

__all__ = ["measure"]

KEY = "7"
SPEC = """\
test: start
world: square-room
runs:
  - {seed: 1}
max_time: 1 s
expect:
  - outcome: success
"""


def tree_cpu_s(root: int) -> float:
    """CPU seconds used by ``root`` and every process below it, live or reaped."""
    children: dict[int, list[int]] = {}
    used: dict[int, int] = {}
    for name in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{name}/stat", encoding="ascii") as handle:
                fields = handle.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue  # it ended meanwhile
        children.setdefault(int(fields[1]), []).append(int(name))
        used[int(name)] = sum(int(x) for x in fields[11:15])  # utime stime cutime cstime
    total, todo = 0, [root]
    while todo:
        pid = todo.pop()
        total += used.get(pid, 0)
        todo += children.get(pid, [])
    return total / os.sysconf("SC_CLK_TCK")


def measure(quick: bool = False) -> list[Row]:
    """Start several warm jails; return the rows (CPU seconds of a start, a run's ratio)."""
    if not warm_jails_supported():
        raise SystemExit("warm jails are Linux only")
    byte_compile_package()  # as the grader does before any jail
    jails = 3 if quick else 9
    starts: list[float] = []
    runs: list[float] = []
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="bench-jail-") as tmp:
        spec_file = Path(tmp) / "spec.yaml"
        spec_file.write_text(SPEC, encoding="utf-8")
        spec = load_test_spec(spec_file)
        mission = str(HERE / "patrol_60s.yaml")
        for _ in range(jails):
            with warm_jail(spec, mission) as jail:
                jail._wait_ready()  # the server has imported everything
                root = jail._jail.pid  # bubblewrap, above the server and its runs
                started = tree_cpu_s(root)
                result = grade_run(spec, mission, spec.variants[0], "bench", server=jail)
                if result.record is None:
                    raise SystemExit(f"the run did not finish: {result.message}")
                starts.append(started)
                runs.append(tree_cpu_s(root) - started)
    start_s, run_s = statistics.median(starts), statistics.median(runs)
    load = f"load average {load_before:.1f} -> {os.getloadavg()[0]:.1f}"
    return [
        info(
            KEY,
            "grading: CPU of one student's warm jail start, s",
            start_s,
            f"median of {jails} jails ({detect_isolation().name}), min {min(starts):.3f} s; {load}",
            unit="s",
        ),
        info(
            KEY,
            "grading: CPU of a 1 s run forked from it / the jail's start",
            run_s / start_s,
            f"{run_s:.3f} s a run (median), {start_s:.3f} s a start",
        ),
    ]


def main() -> None:
    """Print this benchmark's rows."""
    print("\n".join(machine_header("not pinned (a jail's processes, read from /proc)")))
    run_alone(__doc__ or "", measure, "3 jails instead of 9")


if __name__ == "__main__":
    main()
