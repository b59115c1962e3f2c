"""Recorded runs: what recording costs the simulator, a recording's size, the viewer's speed.

Run by hand, not by pytest::

    python tests/bench/bench_replay.py [--quick]

Rows (issue 15):

* recording cost: the simulator's real-time factor of the 60 s patrol mission run through
  ``run_session`` with ``--record``'s recorder, as a share lost against the same run without
  it. Runs alternate, each timed in CPU seconds of this process, and the fastest of each kind
  counts: on a shared machine it is the run least disturbed. Goal: at most 10 %.
* size: the 60 s run's recording file against 2 MB. Goal: at most 1.
* open time: headless Chromium, from the start of loading ``roboscript view``'s page to the
  viewer's first picture, against 1 s; for the 60 s run (goal: at most 1) and, for
  information, a 30-minute recording (90,000 frames).
* a printed line in a graded run: the CPU time the mission's process spends sending a line it
  printed over the grading wire (a ``P`` frame, read at the other end by a thread of this
  process), against the stamped terminal line it writes for it anyway. Goal: at most 1.
"""

from __future__ import annotations

import math
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
for _path in (str(HERE), str(HERE.parent), str(HERE.parent.parent)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

from benchlib import Row, at_most, info, run_alone  # noqa: E402

from roboscript.grading.mission_host import print_payload  # noqa: E402
from roboscript.mission import mission_for_robot  # noqa: E402
from roboscript.mission.channels import StampedPrints  # noqa: E402
from roboscript.replay.recording import Recorder  # noqa: E402
from roboscript.replay.session_tap import RunRecording  # noqa: E402
from roboscript.replay.viewer import write_viewer_page  # noqa: E402
from roboscript.session import run_session  # noqa: E402
from roboscript.transport.lockstep import Kind, WorldChannel  # noqa: E402

__all__ = ["measure"]

KEY = "8"
MISSION = HERE / "patrol_60s.yaml"
COST_GOAL = 0.10
SIZE_LIMIT_BYTES = 2_000_000
OPEN_LIMIT_S = 1.0


def _run(record: bool) -> tuple[float, float, RunRecording | None]:
    """One 60 s patrol; (CPU s, simulated s, the recording if any)."""
    spec, profile, _ = mission_for_robot(MISSION)
    recording = RunRecording() if record else None
    started = time.process_time()
    session = run_session(spec, profile, world=spec.world or "empty", recording=recording)
    wall = time.process_time() - started
    return wall, float(session.result.duration_s), recording


def _open_ms(page: Path, folder: Path) -> float:
    import pytest
    from browser import open_browser

    try:
        with open_browser(folder) as browser:
            browser.open(page.as_uri())
            ready = browser.wait_for(
                "document.querySelector('.rs-viewer').getAttribute('data-ready-ms')", 60.0
            )
            return float(ready)
    except pytest.skip.Exception:
        return float("nan")


def _long_recording(path: Path, frames: int) -> None:
    """A synthetic recording of ``frames`` ticks: a robot circling, a sensor that varies."""
    recorder = Recorder(
        {
            "mission": {"name": "long", "states": []},
            "world": None,
            "robot": {"name": "mirto", "body_radius_mm": 100.0, "sensors": []},
        }
    )
    for i in range(frames):
        t = i * 0.02
        angle = t * 0.3
        recorder.add(
            {
                "t": round(t, 3),
                "pose": [
                    round(500 * math.sin(angle), 1),
                    round(500 * math.cos(angle), 1),
                    round(math.degrees(angle) + 90, 1) % 360.0,
                ],
                "state": "circle" if (i // 3000) % 2 == 0 else "again",
                "sensors": {"range_mm": round(400 + 300 * math.sin(t), 1)},
                "motors": {"left_mm_s": 120.0, "right_mm_s": 100.0},
            }
        )
    recorder.finish({"outcome": "success"})
    recorder.write(path)


def _print_cost(lines: int) -> tuple[float, float]:
    """CPU seconds a line: (the stamped terminal line, the ``P`` frame over a socket pair)."""
    import io
    import socket
    import threading

    line = "t=1.23 s: the wall is 23.5 cm away"
    ours, theirs = socket.socketpair()

    def world() -> None:  # reads as the world does, so the sender never blocks for long
        while theirs.recv(1 << 20):
            pass

    reader = threading.Thread(target=world, daemon=True)
    reader.start()
    channel = WorldChannel(ours)
    stamped = StampedPrints(io.StringIO(), lambda: 1.23, None)
    started = time.process_time()
    for _ in range(lines):
        stamped.write(line + "\n")
    terminal_s = time.process_time() - started
    started = time.process_time()
    for number in range(lines):
        channel.send(Kind.PRINT, print_payload(line, number % 1000 + 1))
    channel.flush()
    wire_s = time.process_time() - started
    channel.close()
    reader.join()
    theirs.close()
    return terminal_s / lines, wire_s / lines


def measure(quick: bool = False) -> list[Row]:
    """Time runs with and without recording, the file's size, and the viewer's open time."""
    runs = 5 if quick else 15
    _run(False)
    _run(True)  # warm-up
    plain: list[float] = []
    recorded: list[float] = []
    recording = None
    for _ in range(runs):  # interleaved, so a slower moment of the machine hits both
        wall, sim_s, _ = _run(False)
        plain.append(sim_s / wall)
        wall, sim_s, recording = _run(True)
        recorded.append(sim_s / wall)
    rtf_plain, rtf_recorded = max(plain), max(recorded)
    cost = 1.0 - rtf_recorded / rtf_plain
    rows = [
        at_most(
            KEY,
            "recording cost: share of the simulator's RTF lost",
            cost * 100,
            COST_GOAL * 100,
            f"RTF {rtf_plain:.0f} without, {rtf_recorded:.0f} with (CPU time), best of {runs}",
            unit="%",
        )
    ]
    assert recording is not None and recording.recorder is not None
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        path = folder / "run.jsonl"
        started = time.process_time()
        recording.recorder.write(path)  # formats the frames the tick loop only stored
        write_s = time.process_time() - started
        size = path.stat().st_size
        frames = len(recording.recorder.frames)
        rows.append(
            at_most(
                KEY,
                "size of a 60 s run's recording ÷ 2 MB",
                size / SIZE_LIMIT_BYTES,
                1.0,
                f"{size / 1000:.0f} kB, {frames} frames, {size / frames:.0f} B a frame",
            )
        )
        rows.append(
            info(
                KEY,
                "writing it after the run ÷ the run's CPU time",
                write_s / (60.0 / rtf_recorded),
                f"{write_s * 1000:.0f} ms to format and write, once the robot is stopped",
            )
        )
        page = write_viewer_page(path, folder / "run.html")
        opened = _open_ms(page, folder)
        if not math.isnan(opened):  # Chromium was there
            rows.append(
                at_most(
                    KEY,
                    "viewer open time, 60 s run ÷ 1 s (headless Chromium)",
                    opened / 1000 / OPEN_LIMIT_S,
                    1.0,
                    f"{opened:.0f} ms from loading to the first picture",
                )
            )
            long_path = folder / "long.jsonl"
            _long_recording(long_path, 90_000)
            long_page = write_viewer_page(long_path, folder / "long.html")
            opened = _open_ms(long_page, folder)
            rows.append(
                info(
                    KEY,
                    "viewer open time, 30-minute run ÷ 1 s",
                    opened / 1000 / OPEN_LIMIT_S,
                    f"{opened:.0f} ms for 90,000 frames"
                    f" ({long_path.stat().st_size / 1e6:.1f} MB recording)",
                )
            )
        else:
            rows.append(
                Row(KEY, "viewer open time (Chromium not installed)", None, "×", "", None, "")
            )
    costs = [_print_cost(20_000 if quick else 100_000) for _ in range(3)]
    terminal_s = min(cost[0] for cost in costs)  # the least disturbed of three
    wire_s = min(cost[1] for cost in costs)
    rows.append(
        at_most(
            KEY,
            "a printed line sent over the grading wire ÷ its stamped terminal line",
            wire_s / terminal_s,
            1.0,
            f"{wire_s * 1e6:.2f} µs a line on the wire, {terminal_s * 1e6:.2f} µs on the"
            " terminal (CPU time), best of 3",
        )
    )
    return rows


if __name__ == "__main__":
    run_alone(__doc__, measure, "5 timed runs with and without recording, not 15")
