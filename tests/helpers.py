"""Helpers shared by the tests (importable as ``helpers``)."""

from __future__ import annotations

import contextlib
import os
import re
import subprocess
import sys
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path
from typing import Any

import pytest

from roboscript.errors import MissionError
from roboscript.grading.spec import TestSpec, load_test_spec
from roboscript.mission import load_mission
from roboscript.sim.simulation import make_simulation
from roboscript.transport.wirelog import read_wire_log

ROOT = Path(__file__).resolve().parent.parent
MISSIONS = ROOT / "missions"


HANG_BOUND_S = 900.0
"""How long a child process may take before the test calls it stuck: a bound for a hang, never
a measure of speed. A test must pass on a machine whose every core is busy, where a run that
takes a second on an idle machine can take a minute."""


def refusal(
    path: Path, profile: Any = None, *, shown: Mapping[str, str] | None = None
) -> list[str]:
    """Every problem a mission file is refused with, as ``roboscript check`` prints them.

    Args:
        path: The mission file; loading it must fail.
        profile: The robot it is checked against, if any.
        shown: Texts to write otherwise, in order (default: ``path`` is written ``M``).
    """
    with pytest.raises(MissionError) as info:
        load_mission(path, profile)
    found = getattr(info.value, "problems", [info.value])
    replacements = {str(path): "M"} if shown is None else shown
    printed = []
    for problem in found:
        text = problem.format()
        for old, new in replacements.items():
            text = text.replace(old, new)
        printed.append(text)
    return printed


def run_cli(
    *args: str,
    timeout: float = HANG_BOUND_S,
    cwd: Path | None = None,
    wrap: tuple[str, ...] = (),
) -> subprocess.CompletedProcess[str]:
    """Run ``roboscript ARGS`` in a child process, as a user would (``wrap``: a command that
    runs it, such as ``("taskset", "-c", "0")``)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run(
        [*wrap, sys.executable, "-m", "roboscript", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=cwd or ROOT,
        env=env,
        check=False,
    )


def checked_by_file(folder: Path, names: list[str]) -> tuple[dict[str, list[str]], str]:
    """Run one ``roboscript check`` of ``names`` in ``folder`` (in that order).

    Returns:
        What it printed about each file (each line after the file's name, in order), and its
        last line (the count of files checked).
    """
    result = run_cli("check", *names, cwd=folder)
    assert "Traceback" not in result.stderr, result.stderr
    printed: dict[str, list[str]] = {name: [] for name in names}
    for line in result.stderr.splitlines():
        name, _, rest = line.partition(":")
        if name in printed:
            printed[name].append(rest)
    return printed, result.stderr.splitlines()[-1]


@contextlib.contextmanager
def served_simulator(robot: str, *options: str) -> Iterator[int]:
    """Serve a simulated ``robot`` on loopback TCP (``roboscript sim``, a real process).

    Yields:
        The port it listens on (``socket://127.0.0.1:PORT``); the server is ended after.
    """
    with serving_simulator(robot, *options) as (port, _):
        yield port


@contextlib.contextmanager
def serving_simulator(robot: str, *options: str) -> Iterator[tuple[int, subprocess.Popen[str]]]:
    """:func:`served_simulator`, with the server's process (its pid, what it printed).

    Yields:
        The port it listens on and the process; the server is ended after, and what it printed
        after its first line stays readable from the process's ``stdout``.
    """
    with _simulator_process(robot, *options, "--tcp", "127.0.0.1:0") as (first, proc):
        match = re.search(r"tcp://127\.0\.0\.1:(\d+)", first)
        assert match, first + (proc.stderr.read() if proc.stderr and not first else "")
        yield int(match.group(1)), proc


@contextlib.contextmanager
def served_on_pty(robot: str, *options: str) -> Iterator[str]:
    """Serve a simulated ``robot`` on a pseudo-terminal (``roboscript sim --pty``, a real
    process), reached as a USB serial port is (pyserial's POSIX port).

    Yields:
        The pty's path, to open as a serial port; the server is ended after.
    """
    with _simulator_process(robot, *options, "--pty") as (first, proc):
        assert first.startswith("/"), first + (proc.stderr.read() if proc.stderr else "")
        yield first


@contextlib.contextmanager
def _simulator_process(robot: str, *options: str) -> Iterator[tuple[str, subprocess.Popen[str]]]:
    """``roboscript sim --robot ROBOT OPTIONS`` running: yields the first line it printed."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.Popen(
        [sys.executable, "-m", "roboscript", "sim", "--robot", robot, *options],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
        env=env,
    )
    try:
        assert proc.stdout is not None
        yield proc.stdout.readline().strip(), proc
    finally:
        proc.terminate()
        proc.wait(timeout=HANG_BOUND_S)


RUN_FROM_PYTHON = """\
import signal, sys

import roboscript
from roboscript.robot import Robot

mission, log, *port = sys.argv[1:]
connect = Robot.connect.__func__
Robot.connect = classmethod(lambda cls, *a, **k: connect(cls, *a, **{**k, "wire_log": log}))


def own(signum, frame):
    pass


signal.signal(signal.SIGHUP, own)
before = [signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)]
try:
    roboscript.run(mission, realtime=True, port=port[0] if port else None)
except KeyboardInterrupt as exc:
    after = [signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)]
    print(f"{type(exc).__name__}: {exc}", file=sys.stderr)
    print("handlers given back:", after == before, file=sys.stderr)
    sys.exit(exc.exit_status)
"""
"""A script (``python -c``) that runs ``MISSION`` with ``roboscript.run()``, in real time, on
the robot at ``[PORT]`` (default: the simulator), recording every byte it sends to ``LOG`` (a
test's judge). A signal that ends the run is told on standard error as the exception's type
and text, then whether the script's own handlers were given back (``True``); the script exits
with the exception's ``exit_status``."""


def signalled_once(
    command: list[str],
    signum: int,
    ready: Callable[[subprocess.Popen[str]], None],
    cwd: Path = ROOT,
) -> tuple[int, str]:
    """Start ``command``, send it ``signum`` once ``ready(process)`` returns, and wait for it.

    Args:
        command: The program and its arguments (run with this checkout on its path).
        signum: The signal to send.
        ready: Returns once the process has done what the signal must find done: an event the
            test sees (a line it printed, bytes it sent), never a time waited.
        cwd: The folder it runs in.

    Returns:
        Its exit status and what it wrote on standard error.
    """
    proc = subprocess.Popen(
        command,
        cwd=cwd,
        env=dict(os.environ, PYTHONPATH=str(ROOT)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        ready(proc)
        proc.send_signal(signum)
        _, stderr = proc.communicate(timeout=HANG_BOUND_S)
    finally:
        proc.kill()  # only if the test failed before the process ended
        proc.wait()
    return proc.returncode, stderr


def replayed_power(robot: str, log: Path) -> tuple[float, list[float]]:
    """Judge, outside the program, whether a run left its robot driving: every byte the host
    sent (its wire log) is replayed into a fresh simulated robot of the same kind.

    Returns:
        The most power any motor was driven at, and each motor's power after the last byte.
    """
    sim = make_simulation(robot)
    sim.connect()
    sent = [(t, data) for t, direction, data in read_wire_log(log) if direction == ">"]
    origin = sent[0][0]
    most = 0.0
    for t, data in sent:
        sim.tick(t - origin, 0.0)
        most = max(most, *(abs(p) for p in sim.body.power))
        sim.write(data)
    sim.tick(sim.time_s + 0.25, 0.0)  # time for the firmware to act on the last bytes
    return most, list(sim.body.power)


ONE_RUN_SPEC = """\
test: one-run
world: empty
robot: mirto
runs:
  - {seed: 1}
max_time: 10 s
expect:
  - outcome: success
"""
"""A test of one 10 s run in the empty world that a mission passes by ending in success."""


def one_run_spec(folder: Path) -> TestSpec:
    """:data:`ONE_RUN_SPEC`, written as ``test.yaml`` in ``folder`` and loaded."""
    path = folder / "test.yaml"
    path.write_text(ONE_RUN_SPEC, encoding="utf-8")
    return load_test_spec(path)


def run_action(bot: object, action: object, limit_s: float = 30.0) -> object:
    """Run one action on a connected robot until it ends; return its Result."""
    from roboscript.actions import ActionContext

    robot: Any = bot
    act: Any = action
    ctx = ActionContext(robot.capabilities, gains=robot.profile.gains)
    state: dict[str, Any] = {}

    def tick(now: float, dt: float) -> None:
        ctx.now_s, ctx.dt_s = now, dt
        if "started" not in state:
            act.start(ctx)
            state["started"] = True
            return
        if "result" not in state:
            result = act.update(ctx)
            if result is not None:
                state["result"] = result
                act.stop(ctx)

    robot.scheduler.add(tick)
    robot.scheduler.run(until=lambda: "result" in state, max_duration_s=limit_s)
    robot.scheduler.remove(tick)
    robot.run_for(0.5)  # let the wheels coast to a stop before anyone measures
    return state.get("result")


def write_track(path: Path) -> Path:
    """A rounded-rectangle tape track (1 m straights, 300 mm bends); start on the right straight."""
    import math

    points: list[tuple[float, float]] = [(300.0, -500.0), (300.0, 500.0)]
    for centre_y, start_deg in ((500.0, 0.0), (-500.0, 180.0)):
        for i in range(25):
            angle = math.radians(start_deg + 180.0 * i / 24)
            points.append((300.0 * math.cos(angle), centre_y + 300.0 * math.sin(angle)))
    polyline = ", ".join(f"[{x:.1f}, {y:.1f}]" for x, y in points)
    path.write_text(
        "world: test-track\n"
        "start: {x: 300 mm, y: -300 mm, heading: 0 deg}\n"
        f"lines:\n  - {{polyline: [{polyline}], width: 20 mm}}\n",
        encoding="utf-8",
    )
    return path


TWICE_PY = """\
from roboscript import Drive, Mission, Rotate, state


class OutAndBack(Mission):
    out = state(Drive(distance_mm=300), initial=True, on_done="turn", on_failed="oops")
    turn = state(Rotate(angle_deg=180), on_done="home", on_failed="oops")
    home = state(final="success")
    oops = state(final="failure")


class Twice(Mission):
    first = state(OutAndBack, initial=True, on_done="second", on_failed="sad")
    second = state(OutAndBack, on_done="happy", on_failed="sad")
    happy = state(final="success")
    sad = state(final="failure")
"""
"""A Python mission that nests another twice (``Twice`` runs ``OutAndBack`` two times)."""

OUT_TURN_BEEP = """\
mission: out-and-turn
initial: out
states:
  out:
    do: {drive: {distance: 20 cm, speed: 15 cm/s}}
    on: {done: turn, failed: stuck}
  turn:
    do: {rotate: {angle: 90 deg}}
    on: {done: beep, failed: stuck}
  beep:
    do: {play_tone: {frequency: 660 Hz, duration: 200 ms}}
    final: success
  stuck:
    final: failure
"""
"""A short YAML mission that drives, turns and beeps (a few seconds simulated)."""

FORWARD_50CM = """\
mission: forward
initial: go
states:
  go:
    do: {drive: {distance: 50 cm, speed: 20 cm/s}}
    on: {done: finished}
  finished:
    final: success
"""
"""An honest YAML mission: 50 cm straight ahead, then stop (2.5 s simulated)."""

FORWARD_50CM_EXPECT = """\
max_time: 20 s
expect:
  - outcome: success
  - final_pose_within: {x: 0 mm, y: 500 mm, radius: 5 cm, relative_to: start}
"""
"""The end of a test spec that :data:`FORWARD_50CM` passes from any start."""


# A Python mission that logs its own values and prints once, a second in (log(), prints).
LOGGING_MISSION = """\
from roboscript import Drive, Mission, log, state


class Logged(Mission):
    go = state(Drive(distance_mm=300), initial=True, when=[("near", "end")],
               on_done="end", on_failed="end")
    end = state(final="success")

    def near(self) -> bool:
        log(driven_cm=self.driven.total_cm, halfway=self.driven.total_cm > 15)
        if self.visits("go") == 1 and 1.0 < self.elapsed < 1.03:
            print("one second in")
        return False
"""


SLEEPER = '''\
"""Drive, checking a condition that naps every tick."""

import time

from roboscript import Drive, Mission, state


class Sleeper(Mission):
    """Drive two metres unless the condition fires."""

    go = state(
        Drive(distance_mm=2000, speed_mm_s=150),
        initial=True,
        on_done="done",
        on_failed="done",
        when=[("tired", "done")],
    )
    done = state(final="success")

    def tired(self) -> bool:
        """Wait a little, a beginner's way."""
        time.sleep(0.05)
        return False
'''
"""A Python mission whose condition sleeps 0.05 s every tick (line 22): too slow, at home
and in class."""


@contextlib.contextmanager
def every_core_busy(extra: int = 0) -> Iterator[None]:
    """A process spinning on every core (and ``extra`` more) for the block: a saturated machine.

    Each spinner also ends itself after ten minutes, whatever happens to the test.
    """
    spin = "import time\nend = time.monotonic() + 600\nwhile time.monotonic() < end:\n    pass"
    count = (os.cpu_count() or 1) + extra
    hogs = [subprocess.Popen([sys.executable, "-c", spin]) for _ in range(count)]
    try:
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()
