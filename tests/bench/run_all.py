"""Run every benchmark and print one table of ratios measured in this run.

    python tests/bench/run_all.py            # the full suite, about 80 s
    python tests/bench/run_all.py --quick    # a smoke run, about 15 s
    python tests/bench/run_all.py --markdown table.md  # also as Markdown, for the README

Every row is a ratio against a limit (the 115200-baud wire) or a baseline measured in this
same run (a raw socket, a plain ``time.sleep`` loop), so the machine's speed cancels out;
each row names its goal (performance.md, part C) and says PASS or MISS. The benchmarks with
a device process (rows 1-3) pin it and themselves to one CPU; the exit status is 1 if any
goal was missed.

The rows, numbered as in the README's "Performance" section:

1. ingest rate of each codec through a real transport ÷ the wire-limited rate at 115200;
2. host CPU per message ÷ the message's wire time at 115200;
3. a driver round trip through roboscript ÷ a raw socket round trip;
4. idle CPU with a connected, silent device;
5. the scheduler at 100 and 500 Hz against its targets and a plain ``sleep`` loop;
6. the simulator's real-time factor (from ``bench_sim.py``);
7. grading throughput: a class of 30 missions x 3 seeds of one minute, graded in parallel;
8. recorded runs: what ``run --record`` costs the simulator, a 60 s recording's size, the
   replay page's open time in headless Chromium, and a graded run's printed line on the wire
   (``bench_replay.py``);
9. the live view (``run --view``): the p99 lateness it adds to the 100 Hz scheduler while a
   browser streams the run (``bench_live.py``);
10. the robots' real firmware on the emulated AVR: simulated seconds per CPU second in
    lockstep, and the firmware tier's CI cost, cold and warm (``bench_firmware.py``).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from collections.abc import Callable
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
for _path in (str(HERE), str(ROOT)):  # run as a script from anywhere, without installing
    if _path not in sys.path:
        sys.path.insert(0, _path)

import bench_idle  # noqa: E402
import bench_ingest  # noqa: E402
import bench_rtt  # noqa: E402
import bench_scheduler  # noqa: E402
from benchlib import (  # noqa: E402
    PINNING_NOTE,
    Row,
    format_markdown,
    format_table,
    machine_header,
)

__all__ = ["main", "run"]


def _sim_rows(quick: bool) -> list[Row]:
    """Row 6, from the simulator benchmark (its rows carry their own key)."""
    import bench_sim

    return [dataclasses.replace(row, key="6") for row in bench_sim.measure(quick)]


def _replay_rows(quick: bool) -> list[Row]:
    """Row 8, from the recorded-run benchmark."""
    import bench_replay

    return bench_replay.measure(quick)


def _live_rows(quick: bool) -> list[Row]:
    """Row 9, from the live-view benchmark."""
    import bench_live

    return bench_live.measure(quick)


def _firmware_rows(quick: bool) -> list[Row]:
    """Row 10, from the firmware benchmark (empty without the AVR toolchain)."""
    import bench_firmware

    return bench_firmware.measure(quick)


def _grading_rows(quick: bool) -> list[Row]:
    """Row 7, from the grading benchmark: a class of 30 missions x 3 one-minute seeds."""
    import bench_grading

    return bench_grading.measure(quick)


BENCHMARKS: tuple[tuple[str, Callable[[bool], list[Row]]], ...] = (
    ("ingest and CPU per message", bench_ingest.measure),
    ("round trip", bench_rtt.measure),
    ("idle CPU", bench_idle.measure),
    ("scheduler", bench_scheduler.measure),
    ("simulator", _sim_rows),
    ("grading", _grading_rows),
    ("recorded runs", _replay_rows),
    ("live view", _live_rows),
    ("real firmware", _firmware_rows),
)


def run(quick: bool, progress: Callable[[str], None]) -> list[Row]:
    """Run every benchmark in order; return all rows, sorted by row number (stable)."""
    rows: list[Row] = []
    for name, measure in BENCHMARKS:
        started = time.perf_counter()
        rows += measure(quick)
        progress(f"  {name}: {time.perf_counter() - started:.1f} s")
    return sorted(rows, key=lambda row: row.key)


def main(argv: list[str] | None = None) -> int:
    """Run everything, print the header and the table; 1 if a goal was missed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a fast smoke run (seconds)")
    parser.add_argument(
        "--markdown", metavar="FILE", help="also write the header and a Markdown table to FILE"
    )
    args = parser.parse_args(argv)

    header = machine_header(PINNING_NOTE)
    if args.quick:
        header.append("mode:    --quick (smoke run: fewer samples; drift ratios read low)")
    print("\n".join(header), flush=True)
    started = time.perf_counter()
    rows = run(args.quick, lambda text: print(text, file=sys.stderr, flush=True))
    total_s = time.perf_counter() - started
    passed = sum(row.verdict == "PASS" for row in rows)
    missed = sum(row.verdict == "MISS" for row in rows)
    summary = f"{len(rows)} rows in {total_s:.0f} s; {passed} PASS, {missed} MISS"
    print(f"\n{format_table(rows)}\n\n{summary}")
    if args.markdown:
        lines = [f"    {line}" for line in header]  # an indented block keeps the alignment
        text = "\n".join([*lines, "", format_markdown(rows), "", summary, ""])
        Path(args.markdown).write_text(text, encoding="utf-8")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
