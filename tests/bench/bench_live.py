"""The live view's cost to the tick loop: the 100 Hz scheduler's p99 lateness with and without.

Run by hand, not by pytest::

    python tests/bench/bench_live.py [--quick]

Each tick does what ``run --record`` does after the mission's think phase: it hands the
recorder a full snapshot (pose, state, action, five sensors, motors) and the recorder keeps
what changed. With the live view, the recorder also hands every frame to
:class:`~roboscript.replay.live.LiveView`, whose server streams it to a browser: a separate
process reading ``/events`` as fast as it can, as a browser tab does. Lateness is measured
as in ``bench_scheduler.py`` (a tick's start minus its deadline, ``MonotonicClock``,
``record_lateness=True``).

Runs alternate (without, with, without, ...) so a noisy neighbour hits both kinds alike; each
figure is the median over the runs of its kind. Rows (issue 15):

* the p99 lateness the live view adds, as a share of the period. Goal: at most 5 %.
* for information, p99 with the live view ÷ p99 without, and the frames the browser got.
"""

from __future__ import annotations

import math
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
for _path in (str(HERE), str(HERE.parent), str(HERE.parent.parent)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

from benchlib import Row, at_most, info, percentile, run_alone  # noqa: E402

from roboscript.clock import MonotonicClock  # noqa: E402
from roboscript.replay.live import LiveView  # noqa: E402
from roboscript.replay.recording import Recorder  # noqa: E402
from roboscript.scheduler import Scheduler  # noqa: E402

__all__ = ["measure"]

KEY = "9"
PERIOD_S = 0.01  # 100 Hz
RUN_S = 3.0
REPETITIONS = 5
ADDED_GOAL_PERCENT = 5.0  # of the period
HEADER = {"mission": {"name": "bench", "initial": "drive", "states": []}, "tick_s": PERIOD_S}

# A browser tab: read the stream as fast as it comes, count the frames, say how many.
_BROWSER = """
import sys, urllib.request
frames = 0
with urllib.request.urlopen(sys.argv[1] + "events") as stream:
    for line in stream:
        if line.startswith(b"event: frame"):
            frames += 1
        elif line.startswith(b"event: end"):
            break
print(frames)
"""


def _snapshot(tick: int) -> dict[str, Any]:
    """One tick's full snapshot, changing as a driving robot's does."""
    t = tick * PERIOD_S
    return {
        "t": round(t, 3),
        "pose": [round(200 * math.sin(t / 3), 1), round(150 * t, 1), round(10 * t % 360, 1)],
        "state": "drive" if tick % 500 < 400 else "turn",
        "action": "drive",
        "outcome": None,
        "sensors": {
            "range_mm": round(800 - 100 * math.sin(t), 1),
            "line": [round(500 + 400 * math.sin(t + k)) for k in range(3)],
            "bumper": [],
            "heading_deg": round(10 * t % 360, 1),
        },
        "motors": {"left_mm_s": 150.0, "right_mm_s": 150.0 + (tick % 7)},
    }


def _run(live: bool, duration_s: float) -> tuple[list[float], list[float], int, int]:
    """One scheduler run: each tick's lateness s, each tick's recording work s, frames
    published, frames a browser got."""
    recorder = Recorder(HEADER)
    view = browser = None
    if live:
        view = LiveView("bench")
        url = view.start()
        recorder.subscribe(view.publish, with_header=True)
        browser = subprocess.Popen(
            [sys.executable, "-c", _BROWSER, url], stdout=subprocess.PIPE, text=True
        )
        while not view.clients():  # the browser is connected before the clock starts
            time.sleep(0.01)
    scheduler = Scheduler(MonotonicClock(), PERIOD_S, record_lateness=True)
    ticks = [0]
    work_s: list[float] = []

    def record(now_s: float, dt_s: float) -> None:
        started = time.perf_counter()
        recorder.add(_snapshot(ticks[0]))
        work_s.append(time.perf_counter() - started)
        ticks[0] += 1

    scheduler.add(record, "after")
    scheduler.run(until=lambda: False, max_duration_s=duration_s)
    recorder.finish({"outcome": "success"})
    received = 0
    if view is not None and browser is not None:
        out, _ = browser.communicate(timeout=30)
        received = int(out.strip() or 0)
        view.close()
    return scheduler.stats.lateness_s, work_s, ticks[0], received


def measure(quick: bool = False) -> list[Row]:
    """The rows: added p99 lateness ÷ period, p99 ratio, frames delivered."""
    duration_s, repetitions = (1.0, 2) if quick else (RUN_S, REPETITIONS)
    without: list[float] = []
    with_live: list[float] = []
    work: dict[bool, list[float]] = {False: [], True: []}
    delivered: list[tuple[int, int]] = []
    for _ in range(repetitions):
        lateness, spent, _, _ = _run(False, duration_s)
        without.append(percentile(lateness, 0.99))
        work[False] += spent
        lateness, spent, published, received = _run(True, duration_s)
        with_live.append(percentile(lateness, 0.99))
        work[True] += spent
        delivered.append((received, published))
    work_s = {live: statistics.median(spent) for live, spent in work.items()}
    base_s = statistics.median(without)
    live_s = statistics.median(with_live)
    added_percent = max(0.0, live_s - base_s) / PERIOD_S * 100
    runs = f"median of {repetitions} alternating runs of {duration_s:g} s each"
    got = sum(r for r, _ in delivered)
    sent = sum(p for _, p in delivered)
    return [
        at_most(
            KEY,
            "live view: added p99 lateness, % of the period (100 Hz)",
            added_percent,
            ADDED_GOAL_PERCENT,
            f"p99 {base_s * 1e6:.0f} µs without, {live_s * 1e6:.0f} µs with a browser"
            f" streaming; {runs} (without: {', '.join(f'{v * 1e6:.0f}' for v in without)};"
            f" with: {', '.join(f'{v * 1e6:.0f}' for v in with_live)})",
            unit="%",
        ),
        info(
            KEY,
            "live view: p99 lateness with ÷ without",
            live_s / base_s,
            f"{runs}; the browser got {got} of {sent} frames",
        ),
        info(
            KEY,
            "live view: a tick's recording work with ÷ without",
            work_s[True] / work_s[False],
            f"median {work_s[False] * 1e6:.1f} µs without, {work_s[True] * 1e6:.1f} µs with"
            " (handing the frame to the live view: a lock and an append)",
        ),
    ]


if __name__ == "__main__":
    run_alone(__doc__, measure, "2 runs of 1 s of each kind, not 5 of 3 s")
