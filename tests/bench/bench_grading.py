"""Grading throughput: a class of 30 missions x 3 seeds, each about 60 s of simulated time.

Run by hand, not by pytest::

    python tests/bench/bench_grading.py [--quick] [--jobs N]

It grades the way ``roboscript grade`` does: every run's world in a worker process of its own
(forked from a preloaded server), the student's mission in a sandboxed process beside it,
``--jobs`` at a time (default: one per core), each judged by five expectations (outcome,
collisions, regions, a wall-distance band, duration). It grades two classes:

* the honest class: 30 students who all finish;
* the troubled class: the same, but 3 students hang (one while loading, two mid-run) and 3
  crash (one while loading, two mid-run), as a real class does.

It prints each class's wall time against the goal (under 60 s on the 2-core reference
machine), the troubled class's time as a ratio to the honest class's (the cost of the broken
submissions), and the aggregate real-time factor.

The cost of isolation is the honest class graded sandboxed against the same runs done
in-process (no second process, no wire, no jail), both in this one run, in the order
sandboxed, in-process, in-process, sandboxed over the two halves of the class, so a load that
rises or falls while it runs weighs on both alike. The row gives the load average before and
after. The script exits with status 1 when that ratio is over 1.5.

The baseline does each run's record and judging only; a graded run also records its replay
and watches each tick's code. A row measures, the same way, the runs in-process as the
product's practice grade does them (:func:`roboscript.grading.practice.practice_run`: record,
replay, watchdog, judging) against the baseline, and gives the sandboxed ratio against that.

What one process hand-over per tick costs this machine is measured beside it, the same way:
the same in-process runs, but with each tick waiting for one round trip to an idle process (a
byte out, the byte back; no jail, no wire protocol, no world in the other process), the two
kept on one core as the grader keeps a run's world and mission (:mod:`roboscript.grading.cores`).
A sandboxed run hands over twice a tick (the mission asks, the world answers), so on a machine
where that row is far over 1 the sandboxed ratio cannot be much under it: the row says how
much of the isolation cost is the machine's context switches rather than the grader's work. It
reads so on an idle machine only: on a busy one a process that waits often is woken ahead of the
programs that keep the cores busy, so the round trips can even make the runs faster.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import multiprocessing
import os
import shutil
import socket
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
for _path in (str(HERE), str(HERE.parent.parent)):
    if _path not in sys.path:
        sys.path.insert(0, _path)

from benchlib import Row, at_most, format_table, info, machine_header  # noqa: E402

from roboscript.grading.batch import find_specs, find_submissions, grade_class  # noqa: E402
from roboscript.grading.cores import keep_on_core, usable_cores  # noqa: E402
from roboscript.grading.expectations import evaluate  # noqa: E402
from roboscript.grading.pool import default_jobs  # noqa: E402
from roboscript.grading.practice import practice_run  # noqa: E402
from roboscript.grading.run import record_from_session  # noqa: E402
from roboscript.grading.sandbox import detect_isolation  # noqa: E402
from roboscript.grading.spec import TestSpec, Variant  # noqa: E402
from roboscript.grading.world_host import DEFAULT_HANG_AFTER_S  # noqa: E402
from roboscript.mission import mission_for_robot  # noqa: E402
from roboscript.scheduler import Scheduler  # noqa: E402
from roboscript.session import run_session  # noqa: E402

__all__ = ["CLASS_WALL_GOAL_S", "ISOLATION_COST_GOAL", "ISOLATION_ROW", "measure"]

KEY = "7"
STUDENTS = 30
SEEDS = 3
CLASS_WALL_GOAL_S = 60.0
"""The issue's goal: 30 missions x 3 seeds of about 60 s each, graded in under a minute."""
ISOLATION_COST_GOAL = 1.5
"""Sandboxed grading may take at most this multiple of the same runs done in-process."""
ISOLATION_ROW = "grading: sandboxed class time / the same runs in-process"

SPEC = """\
test: patrol-minute
description: Benchmark load for the grader.
world: square-room
runs:
{runs}
max_time: 75 s
expect:
  - outcome: success
  - no_collisions: true
  - never_enter: [north-wall]
  - wall_distance: {{state: follow, side: right, min: 5 cm, max: 60 cm}}
  - max_duration: 70 s
"""


_TROUBLE = {
    "hangs_loading.py": "while True:\n    pass\n",
    "crashes_loading.py": "raise ImportError('no module named robotlib')\n",
    "hangs_mid_run.py": """\
from roboscript import Drive, Mission, state


class Hang(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="spin", when=[])
    spin = state(Drive(distance_mm=300), on_done="end", when=[("stuck", "end")])
    end = state(final="success")

    def stuck(self) -> bool:
        while True:
            pass
""",
    "crashes_mid_run.py": """\
from roboscript import Action, Drive, Mission, state


class Boom(Action):
    name = "boom"
    params = ()

    def update(self, ctx):
        raise ZeroDivisionError("division by zero")


class Crash(Mission):
    go = state(Drive(distance_mm=300), initial=True, on_done="boom")
    boom = state(Boom(), on_done="end")
    end = state(final="success")
""",
}
_TROUBLED = (
    "hangs_loading.py",
    "hangs_mid_run.py",
    "hangs_mid_run.py",
    "crashes_loading.py",
    "crashes_mid_run.py",
    "crashes_mid_run.py",
)


def _make_class(
    folder: Path, students: int, seeds: int, troubled: bool = False
) -> tuple[Path, Path]:
    """A spec and a class folder: half the students patrol, half follow the walls.

    With ``troubled``, six of them hang or crash instead (see the module docstring).
    """
    runs = "\n".join(f"  - {{seed: {seed}}}" for seed in range(1, seeds + 1))
    spec = folder / "spec.yaml"
    spec.write_text(SPEC.format(runs=runs), encoding="utf-8")
    submissions = folder / "class"
    submissions.mkdir()
    loads = ("patrol_60s.yaml", "follow_walls_60s.yaml")
    trouble = list(_TROUBLED) if troubled else []
    for i in range(students):
        name = f"student{i + 1:02d}"
        # Spread the trouble through the class, as names would.
        if trouble and i % (students // len(_TROUBLED)) == 0:
            text = _TROUBLE[trouble.pop()]
            (submissions / f"{name}.py").write_text(text, encoding="utf-8")
            continue
        shutil.copy(HERE / loads[i % 2], submissions / f"{name}.yaml")
    return spec, submissions


def _grade(
    students: int, troubled: bool, jobs: int | None, part: slice = slice(None)
) -> tuple[float, Any]:
    """Wall seconds to grade the class (its ``part`` of the students), and the report."""
    with tempfile.TemporaryDirectory(prefix="bench-grading-") as tmp:
        spec, submissions = _make_class(Path(tmp), students, SEEDS, troubled)
        specs = find_specs([str(spec)])
        found = find_submissions([str(submissions)]).submissions[part]
        started = time.perf_counter()
        report = grade_class(specs, found, jobs)
        return time.perf_counter() - started, report


def _in_process_run(spec: TestSpec, mission: str, variant: Variant) -> float:
    """One run as it went before the sandbox: mission and world in this process, judged.

    Returns:
        Simulated seconds the mission ran.
    """
    mission_spec, profile, _warnings = mission_for_robot(mission, spec.robot)
    session = run_session(
        mission_spec,
        profile,
        world=spec.worlds[variant.world].name,
        seed=variant.seed,
        start=variant.start,
        max_time_s=spec.max_time_s,
    )
    record = record_from_session(session)
    for expectation in spec.expectations:
        evaluate(expectation, record)
    return record.duration_s


def _practice_run(spec: TestSpec, mission: str, variant: Variant) -> float:
    """One run as the product grades in-process (the browser's practice grade): the same
    record, plus the replay's recording and the per-tick watchdog a graded run also has.

    Returns:
        Simulated seconds the mission ran.
    """
    run = practice_run(spec, mission, variant, hang_after_s=DEFAULT_HANG_AFTER_S)
    record = run.result.record
    return 0.0 if record is None else record.duration_s


def _grade_in_process(
    students: int,
    jobs: int | None,
    part: slice = slice(None),
    hand_over: bool = False,
    practice: bool = False,
) -> float:
    """Wall seconds to do the honest class's runs (its ``part`` of the students) in-process,
    ``jobs`` warm workers at a time.

    The baseline the sandbox is measured against: the same missions, variants and judging,
    with no second process, no wire and no jail (workers are reused, which only flatters it).
    With ``hand_over``, each tick first waits for one round trip to an idle process.
    """
    with tempfile.TemporaryDirectory(prefix="bench-grading-") as tmp:
        spec_file, submissions = _make_class(Path(tmp), students, SEEDS)
        spec = find_specs([str(spec_file)])[0]
        runs = [
            (spec, mission, variant)
            for submission in find_submissions([str(submissions)]).submissions[part]
            for mission in submission.missions
            for variant in spec.variants
        ]
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(["roboscript.grading.worker"])
        started = time.perf_counter()
        workers = jobs or default_jobs()
        initializer = _hand_over_per_tick if hand_over else None
        # Like the grader's workers: worker i on core i (shared evenly past the cores).
        cores = usable_cores()
        initargs = (context.Queue(),) if hand_over else ()
        if hand_over:
            for i in range(workers):
                initargs[0].put(cores[i % len(cores)] if len(cores) > 1 else None)
        with concurrent.futures.ProcessPoolExecutor(
            workers, context, initializer=initializer, initargs=initargs
        ) as pool:
            run_one = _practice_run if practice else _in_process_run
            list(pool.map(run_one, *zip(*runs, strict=True)))
        return time.perf_counter() - started


_PARTNER: list[socket.socket] = []
"""The worker's end of the socket to its idle partner process (see :func:`_hand_over_per_tick`)."""


def _hand_over_per_tick(cores: Any) -> None:
    """Pool initializer: every tick of every run in this worker first waits for one round
    trip to an idle process of its own (a byte out, the same byte back), both kept on one
    core taken from ``cores`` (a queue), as the grader keeps a run's two processes."""
    keep_on_core(cores.get())
    ours, theirs = socket.socketpair()
    if os.fork() == 0:  # the partner: answer each byte at once, until the worker goes
        ours.close()
        while data := theirs.recv(64):
            theirs.sendall(data)
        os._exit(0)
    theirs.close()
    _PARTNER.append(ours)
    step = Scheduler.step

    def step_after_a_round_trip(self: Scheduler) -> None:
        ours.sendall(b"t")
        ours.recv(64)
        step(self)

    Scheduler.step = step_after_a_round_trip  # type: ignore[method-assign]


def _isolation_cost(students: int, jobs: int | None) -> tuple[float, list[Any], float, str]:
    """The honest class sandboxed and in-process, interleaved (see the module docstring).

    Returns:
        Sandboxed wall seconds, the sandboxed results, in-process wall seconds, and the load
        average (one minute) before and after, as text.
    """
    load_before = os.getloadavg()[0]
    halves = (slice(None, students // 2), slice(students // 2, None))
    first_s, first = _grade(students, False, jobs, halves[0])
    in_process_s = _grade_in_process(students, jobs, halves[0])
    in_process_s += _grade_in_process(students, jobs, halves[1])
    second_s, second = _grade(students, False, jobs, halves[1])
    load = f"{load_before:.1f} -> {os.getloadavg()[0]:.1f}"
    return first_s + second_s, [*first.results, *second.results], in_process_s, load


def _hand_over_cost(students: int, jobs: int | None) -> tuple[float, float, str]:
    """The honest class in-process with and without one round trip per tick, interleaved.

    Returns:
        Wall seconds with the round trips, without, and the load average before and after.
    """
    load_before = os.getloadavg()[0]
    halves = (slice(None, students // 2), slice(students // 2, None))
    with_s = _grade_in_process(students, jobs, halves[0], hand_over=True)
    without_s = _grade_in_process(students, jobs, halves[0])
    without_s += _grade_in_process(students, jobs, halves[1])
    with_s += _grade_in_process(students, jobs, halves[1], hand_over=True)
    return with_s, without_s, f"{load_before:.1f} -> {os.getloadavg()[0]:.1f}"


def _practice_cost(students: int, jobs: int | None) -> tuple[float, float, str]:
    """The honest class in-process as the practice grade does it, and as the baseline does,
    interleaved.

    Returns:
        Wall seconds as the practice grade, as the baseline, and the load average before and
        after.
    """
    load_before = os.getloadavg()[0]
    halves = (slice(None, students // 2), slice(students // 2, None))
    practice_s = _grade_in_process(students, jobs, halves[0], practice=True)
    plain_s = _grade_in_process(students, jobs, halves[0])
    plain_s += _grade_in_process(students, jobs, halves[1])
    practice_s += _grade_in_process(students, jobs, halves[1], practice=True)
    return practice_s, plain_s, f"{load_before:.1f} -> {os.getloadavg()[0]:.1f}"


def measure(quick: bool = False, jobs: int | None = None) -> list[Row]:
    """Grade the benchmark class once; return the rows (wall time against the goal, RTF)."""
    students = 12 if quick else STUDENTS
    wall_s, results, in_process_s, load = _isolation_cost(students, jobs)
    troubled_s, troubled = _grade(students, True, jobs)
    hand_over_s, plain_s, hand_over_load = _hand_over_cost(students, jobs)
    practice_s, baseline_s, practice_load = _practice_cost(students, jobs)
    statuses = Counter(r.status for r in troubled.results)
    simulated_s = sum(r.record.duration_s for r in results if r.record is not None)
    unfinished = [r for r in results if r.record is None]
    if unfinished:
        raise SystemExit(f"{len(unfinished)} runs did not finish: {unfinished[0].message}")
    runs = len(results)
    workers = jobs or default_jobs()
    detail = (
        f"{runs} runs ({students} missions x {SEEDS} seeds), {simulated_s:.0f} s simulated,"
        f" {wall_s:.1f} s wall, {workers} workers"
    )
    # Scale a --quick class up to the full one, so the goal reads the same.
    projected_s = wall_s * STUDENTS / students
    trouble_detail = (
        f"{runs} runs, 3 hanging and 3 crashing students: "
        + ", ".join(f"{n} {status}" for status, n in sorted(statuses.items()))
        + f"; {troubled_s:.1f} s wall"
    )
    return [
        at_most(
            KEY,
            "grading: a class of 30 x 3 one-minute runs, wall s",
            projected_s,
            CLASS_WALL_GOAL_S,
            detail,
            unit="s",
        ),
        at_most(
            KEY,
            "grading: the class with 3 hanging and 3 crashing students, wall s",
            troubled_s * STUDENTS / students,
            CLASS_WALL_GOAL_S,
            trouble_detail,
            unit="s",
        ),
        at_most(
            KEY,
            ISOLATION_ROW,
            wall_s / in_process_s,
            ISOLATION_COST_GOAL,
            f"{wall_s:.1f} s sandboxed ({detect_isolation().name}), {in_process_s:.1f} s"
            f" in-process, {runs} runs, {workers} workers, load average {load}",
        ),
        info(
            KEY,
            "grading: in-process + one process round trip a tick / in-process",
            hand_over_s / plain_s,
            f"{hand_over_s:.1f} s with a round trip to an idle process before each tick,"
            f" {plain_s:.1f} s without, {runs} runs, {workers} workers, load average"
            f" {hand_over_load}: this machine's cost of handing the CPU over, twice a tick in"
            " a sandboxed run (on an idle machine; see the module docstring)",
        ),
        info(
            KEY,
            "grading: in-process with replay and watchdog (practice grade) / in-process",
            practice_s / baseline_s,
            f"{practice_s:.1f} s as the practice grade runs (the record, the replay's recording"
            f" and the per-tick watchdog, as a graded run has), {baseline_s:.1f} s as the"
            f" baseline above (record and judge only), {runs} runs, {workers} workers, load"
            f" average {practice_load}: the sandboxed ratio against that in-process grade is"
            f" {wall_s / in_process_s / (practice_s / baseline_s):.2f} ×",
        ),
        info(
            KEY,
            "grading: troubled class time / honest class time",
            troubled_s / wall_s,
            "what hanging and crashing students add to a class",
        ),
        info(KEY, "grading: aggregate real-time factor", simulated_s / wall_s, detail),
    ]


def main() -> None:
    """Print this benchmark's rows."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="12 missions instead of 30")
    parser.add_argument("--jobs", type=int, help="workers at once (default: one per core)")
    args = parser.parse_args()
    print("\n".join(machine_header("each grading worker keeps its runs on one core")))
    rows = measure(args.quick, args.jobs)
    print(format_table(rows))
    isolation = next(row for row in rows if row.name == ISOLATION_ROW)
    if not isolation.passed:
        print(
            f"the sandbox costs {isolation.ratio_text}, over {ISOLATION_COST_GOAL:g} ×",
            file=sys.stderr,
        )
        sys.exit(1)


if __name__ == "__main__":
    main()
