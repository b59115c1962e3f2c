"""Simulator speed: real-time factor (simulated seconds per wall second) of 60 s missions.

Run by hand, not by pytest::

    python tests/bench/bench_sim.py [--quick]

Each variant simulates 60 s with the physics at a fixed 5 ms step; the table gives the median
of several runs, and the ratio held to its goal (performance.md, G8 and G8b):

* ``mission: patrol`` and ``mission: follow walls``: the whole stack in one process, as
  ``roboscript run`` does it: a YAML mission on the scheduler (20 ms ticks), the ASIP driver
  and codec, the simulated MIRTO board speaking bytes, the body with every sensor at its rate.
  Goal: RTF >= 200 (a 60 s mission graded in under 0.3 s).
* ``patrol mission, uart board``: the patrol with the board as a UART board (``transport:
  uart``), whose firmware reads each byte when the line delivers it and counts its own writing
  time; the row gives what that costs against the USB board, in CPU time (which the machine's
  other jobs change less than wall time, though on a busy machine still by tens of percent).
* ``body + sensors``: the body alone, bouncing round the room, its sensors read as often as the
  board reads them (distance 10 Hz, IR and bumpers 20 Hz, encoders 30 Hz).
* ``bare physics``: the body's step alone (motors, slip, encoders, collisions). Goal for the
  sensor model: costs at most 2x the bare physics (G8b).
"""

from __future__ import annotations

import argparse
import dataclasses
import random
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent))

from benchlib import Row, at_least, at_most, format_table, info, machine_header  # noqa: E402

from roboscript.mission import mission_for_robot  # noqa: E402
from roboscript.mission.runner import MissionRunner  # noqa: E402
from roboscript.profiles import get_profile  # noqa: E402
from roboscript.robot import Robot  # noqa: E402
from roboscript.sim.body import Body  # noqa: E402
from roboscript.sim.simulation import PHYSICS_DT_S, body_spec_for  # noqa: E402
from roboscript.sim.world import load_world  # noqa: E402

__all__ = ["RTF_GOAL", "measure"]

KEY = "sim"
MISSION_S = 60.0
RTF_GOAL = 200.0
"""performance.md G8: a 60 s mission simulated at least 200 times faster than real time."""
REALISM_COST_GOAL = 2.0
"""performance.md G8b: the sensor model costs at most twice the bare physics."""


def run_mission(file_name: str, transport: str | None = None) -> float:
    """Run a benchmark mission in-process (on a board with that ASIP ``transport``, or the
    profile's); return the simulated seconds."""
    spec, profile, _ = mission_for_robot(HERE / file_name)
    if transport is not None:
        # a name of its own: the simulator finds its board by the profile's name, and a
        # built-in's name would give it the built-in's (USB) board
        options = {**profile.options, "transport": transport}
        profile = dataclasses.replace(profile, name=f"{profile.name}-{transport}", options=options)
    robot = Robot.connect(profile, None, world=spec.world or "empty", seed=1)
    runner = MissionRunner(spec, robot.capabilities, robot_name=profile.name, gains=profile.gains)
    robot.scheduler.add(runner, "think")
    with robot:
        robot.scheduler.run(until=lambda: runner.finished, max_duration_s=MISSION_S + 30.0)
    if runner.result.outcome != "success":
        raise SystemExit(f"{file_name}: {runner.result.outcome}: {runner.result.reason}")
    return float(robot.simulation.time_s)


def run_body(read_sensors: bool) -> float:
    """Drive a bare body round the square room for 60 s; return the simulated seconds."""
    body = Body(load_world("square-room"), body_spec_for(get_profile("mirto")), random.Random(1))
    steps = round(MISSION_S / PHYSICS_DT_S)
    body.set_power(0.6, 0.55)
    turning_until = 0.0
    for step in range(1, steps + 1):
        body.step(PHYSICS_DT_S)
        if body.in_contact and body.time_s > turning_until:
            body.set_power(-0.5, 0.3)  # back off turning, then carry on
            turning_until = body.time_s + 0.8
        elif turning_until and body.time_s >= turning_until:
            body.set_power(0.6, 0.55)
            turning_until = 0.0
        if read_sensors:
            if step % 20 == 0:  # 100 ms: both distance sensors
                body.range_mm()
                body.side_range_mm()
            if step % 10 == 0:  # 50 ms: IR and bumpers
                body.line_readings()
                body.bumpers_pressed()
            if step % 7 == 0:  # ~33 ms: encoders (the board reads the tick counts)
                _ = body.ticks
    return body.time_s


def _median_run(work: Callable[[], float], runs: int) -> tuple[float, float, float]:
    """Median wall seconds of ``runs`` runs (after one warm-up), the simulated seconds, and
    the median CPU seconds of this thread (which leaves out the time other jobs ran)."""
    work()
    walls: list[float] = []
    cpus: list[float] = []
    simulated = 0.0
    for _ in range(runs):
        started, started_cpu = time.perf_counter(), time.thread_time()
        simulated = work()
        walls.append(time.perf_counter() - started)
        cpus.append(time.thread_time() - started_cpu)
    return statistics.median(walls), simulated, statistics.median(cpus)


def measure(quick: bool = False) -> list[Row]:
    """Time every variant and return the rows: RTF against its goal, and the sensors' cost."""
    runs = 3 if quick else 7
    variants: list[tuple[str, Callable[[], float]]] = [
        ("patrol mission", lambda: run_mission("patrol_60s.yaml")),
        ("wall-following mission", lambda: run_mission("follow_walls_60s.yaml")),
        ("patrol mission, uart board", lambda: run_mission("patrol_60s.yaml", "uart")),
        ("body + sensors", lambda: run_body(read_sensors=True)),
        ("bare physics", lambda: run_body(read_sensors=False)),
    ]
    rtf: dict[str, float] = {}
    cpu: dict[str, float] = {}
    detail: dict[str, str] = {}
    for name, work in variants:
        wall_s, sim_s, cpu[name] = _median_run(work, runs)
        rtf[name] = sim_s / wall_s
        steps_s = sim_s / PHYSICS_DT_S / wall_s
        detail[name] = f"{sim_s:.0f} s simulated in {wall_s * 1000:.0f} ms ({steps_s:,.0f} steps/s)"
    rows = [
        at_least(
            KEY,
            f"RTF, {name}, full stack (square-room)",
            rtf[name],
            RTF_GOAL,
            f"{detail[name]}, median of {runs}",
        )
        for name in ("patrol mission", "wall-following mission")
    ]
    rows.append(
        info(
            KEY,
            "RTF, body + sensors at their rates",
            rtf["body + sensors"],
            detail["body + sensors"],
        )
    )
    rows.append(
        info(KEY, "RTF, bare physics (body.step)", rtf["bare physics"], detail["bare physics"])
    )
    rows.append(
        at_most(
            KEY,
            "sensor model cost: bare physics RTF ÷ body + sensors RTF",
            rtf["bare physics"] / rtf["body + sensors"],
            REALISM_COST_GOAL,
            "G8b: realism may at most halve the speed",
        )
    )
    uart, usb = cpu["patrol mission, uart board"], cpu["patrol mission"]
    rows.append(
        info(
            KEY,
            "uart board cost: patrol CPU time (uart board) ÷ patrol CPU time (usb board)",
            uart / usb,
            f"its line and writing time; {uart * 1000:.0f} ms vs {usb * 1000:.0f} ms CPU for"
            f" 60 s simulated, medians of {runs}",
        )
    )
    slowest = min(rtf["patrol mission"], rtf["wall-following mission"])
    rows.append(
        info(
            KEY,
            "full stack cost: bare physics RTF ÷ slowest mission RTF",
            rtf["bare physics"] / slowest,
            "scheduler, mission, driver, codec and simulated board on top of the body",
        )
    )
    return rows


def main() -> None:
    """Print this benchmark's rows."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 timed runs per variant, not 7")
    args = parser.parse_args()
    print("\n".join(machine_header("not pinned (one process)")))
    print(f"physics step {PHYSICS_DT_S * 1000:g} ms; every variant simulates {MISSION_S:g} s\n")
    print(format_table(measure(args.quick)))


if __name__ == "__main__":
    main()
