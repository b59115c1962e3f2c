"""Whatever signal ends roboscript, the robot is told to stop first, and the exit says which.

Each run is a real ``roboscript run`` process driving a robot in real time. The judge of
"stopped" is protocol-independent and outside the program: every byte the host sent (its
wire log) is replayed into a fresh simulated robot of the same kind, whose motors must have
been driving during the run and must be off after the last byte.
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from helpers import (
    HANG_BOUND_S,
    ROOT,
    RUN_FROM_PYTHON,
    replayed_power,
    served_on_pty,
    served_simulator,
    signalled_once,
)

from roboscript.clock import SimClock
from roboscript.interrupts import (
    Interrupted,
    deferred,
    exit_status_for,
    handled,
    kept,
    raise_dropped,
    reason_for,
)
from roboscript.mission.runner import MissionRunner
from roboscript.mission.yaml_loader import parse_yaml_mission
from roboscript.robot import Robot
from roboscript.scheduler import Scheduler
from roboscript.transport.wirelog import read_wire_log

WHEELED = ("mirto", "spike-prime", "stackmod-rover")
SIGNALS = ("SIGTERM", "SIGHUP", "SIGINT")


def test_each_signal_has_its_sentence_and_exit_status() -> None:
    assert (reason_for(KeyboardInterrupt()), exit_status_for(KeyboardInterrupt())) == (
        "interrupted by Ctrl-C",
        130,
    )
    term = Interrupted(signal.SIGTERM)
    assert (term.exit_status, term.reason) == (
        143,
        "stopped by SIGTERM (something asked roboscript to end)",
    )
    hup = Interrupted(signal.SIGHUP)
    assert (hup.exit_status, hup.reason) == (129, "stopped by SIGHUP (the terminal was closed)")
    assert isinstance(term, KeyboardInterrupt)  # every Ctrl-C path stops the robot for it too
    assert str(term) == term.reason  # what a traceback or a notebook shows


# A mission that drives at 15 cm/s (DRIVEN: how far or how long), then ends in success.
DRIVE = """\
mission: drive
initial: forward
states:
  forward:
    do: {drive: {DRIVEN, speed: 15 cm/s}}
    on: {done: finished, failed: finished}
  finished:
    final: success
"""

LONG_DRIVE = DRIVE.replace("DRIVEN", "duration: 10 min")
"""Whenever the signal comes, the wheels are turning."""


def _wait_until_driven(robot: str, log: Path, proc: subprocess.Popen[str]) -> None:
    """Return once the bytes the run has sent so far (its wire log, flushed at least once a
    second; a record cut short is not read) drive the wheels, judged as the run's end is."""
    deadline = time.monotonic() + HANG_BOUND_S  # a bound for a hang, never a measure of speed
    while time.monotonic() < deadline:
        assert proc.poll() is None, "the run ended before it drove"
        sent = log.exists() and any(d == ">" for _, d, _ in read_wire_log(log))
        if sent and replayed_power(robot, log)[0] > 0.1:
            return
        time.sleep(0.05)  # until the next flush: this only paces the reads
    raise AssertionError(f"the run sent nothing that drives within {HANG_BOUND_S} s")


@pytest.mark.parametrize("robot", WHEELED)
@pytest.mark.parametrize("name", SIGNALS)
def test_a_signal_mid_mission_stops_the_robot_then_exits_with_its_status(
    tmp_path: Path, robot: str, name: str
) -> None:
    signum = getattr(signal, name)
    mission = tmp_path / "long.yaml"
    mission.write_text(LONG_DRIVE, encoding="utf-8")
    log = tmp_path / "wire.log"
    status, stderr = signalled_once(
        [
            *(sys.executable, "-m", "roboscript", "run", str(mission)),
            *("--robot", robot, "--realtime", "--wire-log", str(log)),
        ],
        signum,
        lambda proc: _wait_until_driven(robot, log, proc),  # the wheels are turning
    )
    assert status == 128 + signum, stderr
    assert "Traceback" not in stderr
    assert stderr.strip().splitlines()[-1] == f"error: {Interrupted(signum).reason}"
    most, end = replayed_power(robot, log)
    assert most > 0.1, "the robot never drove: the test proves nothing"
    assert all(abs(p) < 1e-6 for p in end), f"{robot} left driving at {end} after {name}"


@pytest.fixture
def handlers() -> Iterator[None]:
    """roboscript's handlers for the test (as a run from Python has them), the test's after."""
    with handled():
        yield


@pytest.mark.usefixtures("handlers")
def test_a_signal_while_the_stop_goes_out_waits_for_it() -> None:
    sent: list[str] = []
    with pytest.raises(Interrupted) as raised, deferred():
        os.kill(os.getpid(), signal.SIGTERM)
        sent.append("stop")  # reached: the signal did not cut the stop short
    assert sent == ["stop"]
    assert raised.value.signum == signal.SIGTERM


@pytest.mark.usefixtures("handlers")
def test_a_second_signal_while_stopping_ends_at_once() -> None:
    sent: list[str] = []
    # nested: closing the robot stops it inside a stop path
    with pytest.raises(Interrupted) as raised, deferred(), deferred():
        os.kill(os.getpid(), signal.SIGINT)
        os.kill(os.getpid(), signal.SIGHUP)
        sent.append("never")
    assert sent == []
    assert raised.value.signum == signal.SIGINT  # the first signal is why the run ended
    with deferred():  # nothing is left pending for the next stop
        pass


@pytest.mark.usefixtures("handlers")
def test_outside_a_stop_a_signal_raises_where_the_program_is() -> None:
    with pytest.raises(Interrupted) as raised:
        os.kill(os.getpid(), signal.SIGINT)
    assert raised.value.exit_status == 130


@pytest.mark.usefixtures("handlers")
def test_a_signal_that_code_inside_drops_is_raised_again_when_it_returns() -> None:
    after: list[str] = []
    with pytest.raises(Interrupted) as raised, kept():
        # as a library that logs every error and goes on
        with contextlib.suppress(BaseException):
            os.kill(os.getpid(), signal.SIGTERM)
        after.append("the rest of the block")
    assert after == ["the rest of the block"]
    assert raised.value.signum == signal.SIGTERM
    with kept():  # nothing is left over for the next block
        pass


def _ticking(task: object) -> Scheduler:
    sched = Scheduler(SimClock(), 0.02)
    sched.add(task)  # type: ignore[arg-type]
    return sched


class _SignalsWhenCollected:
    """An object whose finalizer signals the program: the signal lands inside ``__del__``."""

    def __init__(self, signum: int) -> None:
        self.signum = signum

    def __del__(self) -> None:
        os.kill(os.getpid(), self.signum)


@pytest.mark.usefixtures("handlers")
def test_a_signal_landing_in_a_finalizer_between_ticks_ends_the_run_before_the_next(
    capfd: pytest.CaptureFixture[str],
) -> None:
    ticks: list[float] = []
    sched = _ticking(lambda now_s, dt_s: ticks.append(now_s))
    sched.step()
    _SignalsWhenCollected(signal.SIGHUP)  # collected at once; Python can only drop the error
    with pytest.raises(Interrupted) as raised:
        sched.run(until=lambda: False, max_duration_s=10)
    assert len(ticks) == 1  # not one tick more
    assert raised.value.signum == signal.SIGHUP
    assert "Exception ignored" not in capfd.readouterr().err  # the run's own sentence says why
    raise_dropped()  # raised once: nothing is left over


@pytest.mark.usefixtures("handlers")
def test_a_signal_a_finalizer_dropped_before_a_stop_lets_the_stop_go_out_first() -> None:
    sent: list[str] = []
    _SignalsWhenCollected(signal.SIGTERM)
    with pytest.raises(Interrupted) as raised, kept():
        sent.append("stop")
    assert sent == ["stop"]
    assert raised.value.signum == signal.SIGTERM


@pytest.mark.usefixtures("handlers")
def test_a_signal_a_finalizer_dropped_after_the_last_tick_still_lets_the_robot_stop() -> None:
    with pytest.raises(Interrupted) as raised, Robot.connect("mirto") as robot:
        robot.drive_base.set_wheel_speeds(200, 200)
        robot.run_for(0.5)
        assert robot.simulation.body.power != [0.0, 0.0]
        _SignalsWhenCollected(signal.SIGTERM)  # no tick runs after it: leaving the block stops
    assert raised.value.signum == signal.SIGTERM
    robot.simulation.tick(robot.simulation.time_s + 0.25, 0.0)  # the board acts on the stop
    assert robot.simulation.body.power == [0.0, 0.0]


@pytest.mark.usefixtures("handlers")
def test_a_signal_a_finalizer_drops_inside_a_block_is_raised_when_it_returns() -> None:
    with pytest.raises(Interrupted) as raised, kept():
        _SignalsWhenCollected(signal.SIGTERM)
    assert raised.value.signum == signal.SIGTERM
    with kept():  # raised once: nothing is left over for the next block
        pass


@pytest.mark.usefixtures("handlers")
def test_a_signal_a_finalizer_dropped_outside_any_block_is_raised_when_asked() -> None:
    _SignalsWhenCollected(signal.SIGINT)
    with pytest.raises(Interrupted) as raised:
        raise_dropped()
    assert raised.value.exit_status == 130


def test_other_errors_in_finalizers_are_still_reported_as_python_reports_them() -> None:
    class Faulty:
        def __del__(self) -> None:
            raise ValueError("a bug in a finalizer")

    reported: list[type[BaseException] | None] = []
    hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: reported.append(unraisable.exc_type)
    try:
        with handled():
            Faulty()
    finally:
        sys.unraisablehook = hook
    assert reported == [ValueError]


@pytest.mark.usefixtures("handlers")
def test_a_signal_a_students_bare_except_catches_still_ends_the_run_at_the_ticks_end() -> None:
    after: list[str] = []

    def student(now_s: float, dt_s: float) -> None:
        try:  # noqa: SIM105 - as a beginner writes it
            os.kill(os.getpid(), signal.SIGINT)
        except:  # noqa: E722, S110
            pass
        after.append("rest of the tick")

    sched = _ticking(student)
    with pytest.raises(Interrupted) as raised:
        sched.run(until=lambda: False, max_duration_s=10)
    assert after == ["rest of the tick"]  # not one tick more
    assert raised.value.exit_status == 130


@pytest.mark.usefixtures("handlers")
def test_a_signal_in_the_state_machines_last_step_still_ends_the_mission(
    caplog: pytest.LogCaptureFixture,
) -> None:
    spec, _ = parse_yaml_mission(
        "states:\n  a:\n    do: {wait: {duration: 0.1 s}}\n    on: {done: b}\n"
        "  b: {final: success}\n"
    )
    runner = MissionRunner(spec, {})
    # transitions logs and drops whatever is raised while it finalises an event
    runner._machine.finalize_event = [lambda event: os.kill(os.getpid(), signal.SIGINT)]
    with pytest.raises(Interrupted):
        _ticking(runner).run(until=lambda: runner.finished, max_duration_s=10)
    assert "Interrupted" not in caplog.text  # the run's own sentence says why, once


# A module that makes the program signal itself the moment it starts to import MODULE: the
# signal lands while the command line is still loading, however fast or slow the machine.
SIGNAL_ON_IMPORT = """\
import os, signal, sys

class SignalOnImport:
    def find_spec(self, name, path=None, target=None):
        if name == os.environ["SIGNAL_ON_IMPORT"]:
            sys.meta_path.remove(self)
            os.kill(os.getpid(), getattr(signal, os.environ["SIGNAL_NAME"]))
        return None

sys.meta_path.insert(0, SignalOnImport())
"""


def _run_signalling_itself(
    tmp_path: Path, signalling: str, command: list[str], **env: str
) -> subprocess.CompletedProcess[str]:
    """Run ``command`` with ``signalling`` as its ``sitecustomize`` and ``env`` added."""
    (tmp_path / "sitecustomize.py").write_text(signalling, encoding="utf-8")
    return subprocess.run(
        command,
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)]), **env},
        capture_output=True,
        text=True,
        timeout=HANG_BOUND_S,
        check=False,
    )


def _commands() -> list[list[str]]:
    commands = [[sys.executable, "-m", "roboscript"]]
    script = Path(sys.executable).with_name("roboscript")
    if script.exists():  # the installed command, whose entry point is the same function
        commands.append([str(script)])
    return commands


@pytest.mark.parametrize("name", SIGNALS)
@pytest.mark.parametrize("module", ["roboscript.errors", "roboscript.watchdog", "argparse"])
def test_a_signal_while_the_program_starts_ends_it_in_one_line(
    tmp_path: Path, name: str, module: str
) -> None:
    for command in _commands():
        done = _run_signalling_itself(
            tmp_path,
            SIGNAL_ON_IMPORT,
            [*command, "run", "missions/square.yaml"],
            SIGNAL_ON_IMPORT=module,
            SIGNAL_NAME=name,
        )
        signum = getattr(signal, name)
        assert done.stderr == f"error: {Interrupted(signum).reason}\n", (command, done.stderr)
        assert done.returncode == 128 + signum


# A module that makes the program signal itself at one chosen call into the standard library
# (SIGNAL_AT, the SIGNAL_NTH such call; with SIGNAL_WHEN, only calls sending bytes that hold
# it, or given an argument written so):
# the signal lands in one phase of the run, on every machine, at whatever speed. With
# SIGNAL_FROM=finalizer it lands while an object is being collected there, where Python can only
# print an exception and drop it, as it does for a signal landing in any ``__del__``.
SIGNAL_AT_CALL = """\
import os, signal, socket, time

_OWNERS = {"os": os, "socket": socket, "socket.socket": socket.socket, "time": time}
_owner_name, _, _attr = os.environ["SIGNAL_AT"].rpartition(".")
_owner = _OWNERS[_owner_name]
_original = getattr(_owner, _attr)
_nth = int(os.environ.get("SIGNAL_NTH", "1"))
_marker = os.environ.get("SIGNAL_WHEN", "")
_signum = getattr(signal, os.environ["SIGNAL_NAME"])
_seen = [0]


class _Finalised:
    def __del__(self):
        os.kill(os.getpid(), _signum)


def _matches(arg):
    if isinstance(arg, (bytes, bytearray, memoryview)):  # bytes sent: they hold the marker
        return _marker.encode("latin-1") in bytes(arg)
    return repr(arg) == _marker


def _has_marker(args):
    return any(_matches(arg) for arg in args)


def _signalling(*args, **kwargs):
    if not _marker or _has_marker(args):
        _seen[0] += 1
        if _seen[0] == _nth:
            if os.environ.get("SIGNAL_FROM") == "finalizer":
                _Finalised()  # collected at once: the signal lands inside its __del__
            else:
                os.kill(os.getpid(), _signum)
    return _original(*args, **kwargs)


setattr(_owner, _attr, _signalling)
"""

SHORT_DRIVE = DRIVE.replace("DRIVEN", "distance: 10 cm")


@contextlib.contextmanager
def _served(transport: str) -> Iterator[str]:
    """A MIRTO served by ``roboscript sim`` (a real process); yields the URL to reach it on.

    ``socket``: roboscript's own TCP port; ``pyserial socket``: the same URL with an option,
    which pyserial's port serves (its close swallows every exception); ``pty``: a
    pseudo-terminal, as a USB serial port is reached (pyserial's POSIX port).
    """
    if transport == "pty":
        with served_on_pty("mirto") as path:
            yield path
        return
    with served_simulator("mirto") as port:
        yield f"socket://127.0.0.1:{port}" + ("?logging=warning" if "pyserial" in transport else "")


def _run_signalled(
    tmp_path: Path, url: str, name: str, *, from_python: bool = False, **where: str
) -> tuple[subprocess.CompletedProcess[str], Path]:
    """``roboscript run`` a short drive on the MIRTO at ``url`` (``from_python``: a script's
    ``roboscript.run()``, see :data:`helpers.RUN_FROM_PYTHON`), signalled where ``where`` says.
    """
    mission = tmp_path / "short.yaml"
    mission.write_text(SHORT_DRIVE, encoding="utf-8")
    log = tmp_path / "wire.log"
    command = (
        [sys.executable, "-c", RUN_FROM_PYTHON, str(mission), str(log), url]
        if from_python
        else [
            *(sys.executable, "-m", "roboscript", "run", str(mission), "--robot", "mirto"),
            *("--port", url, "--wire-log", str(log)),
        ]
    )
    done = _run_signalling_itself(tmp_path, SIGNAL_AT_CALL, command, SIGNAL_NAME=name, **where)
    return done, log


def _ended_by(done: subprocess.CompletedProcess[str], name: str) -> None:
    signum = getattr(signal, name)
    assert done.returncode == 128 + signum, done.stderr
    assert "Traceback" not in done.stderr
    assert "Exception ignored" not in done.stderr
    assert done.stderr.strip().splitlines()[-1] == f"error: {Interrupted(signum).reason}"


def _left_stopped(log: Path) -> float:
    """The most power the run's bytes drove at; fails if they leave the robot driving."""
    if not log.exists() or not any(d == ">" for _, d, _ in read_wire_log(log)):
        return 0.0  # nothing was sent: nothing can be driving
    most, end = replayed_power("mirto", log)
    assert all(abs(p) < 1e-6 for p in end), f"left driving at {end}"
    return most


# Where each phase of a run is, seen from the calls it makes into the standard library, on
# each transport (see _served).
_SECOND_SPEED = {"SIGNAL_WHEN": "M,R,", "SIGNAL_NTH": "2"}  # the first set the wheels turning
_LAST_STOP = {"SIGNAL_WHEN": "M,M,0,0", "SIGNAL_NTH": "2"}  # the first is the handshake's setup
PHASES: dict[str, tuple[str, dict[str, str]]] = {
    "connecting": ("socket", {"SIGNAL_AT": "socket.create_connection"}),
    "sending the first handshake request": ("socket", {"SIGNAL_AT": "socket.socket.send"}),
    "waiting for the handshake's answer": ("socket", {"SIGNAL_AT": "socket.socket.recv"}),
    "driving": ("socket", {"SIGNAL_AT": "socket.socket.send", **_SECOND_SPEED}),
    "sending the stop": ("socket", {"SIGNAL_AT": "socket.socket.send", **_LAST_STOP}),
    "closing the port": ("socket", {"SIGNAL_AT": "socket.socket.close"}),
    "closing pyserial's port": ("pyserial socket", {"SIGNAL_AT": "socket.socket.shutdown"}),
    "waiting in pyserial's close": (
        "pyserial socket",
        {"SIGNAL_AT": "time.sleep", "SIGNAL_WHEN": "0.3"},
    ),
    "driving over a serial line": ("pty", {"SIGNAL_AT": "os.write", **_SECOND_SPEED}),
    "stopping over a serial line": ("pty", {"SIGNAL_AT": "os.write", **_LAST_STOP}),
}

CASES = [
    ("connecting", "SIGTERM", "call"),
    ("connecting", "SIGINT", "finalizer"),
    ("sending the first handshake request", "SIGHUP", "call"),
    ("sending the first handshake request", "SIGTERM", "finalizer"),
    ("waiting for the handshake's answer", "SIGINT", "finalizer"),
    ("driving", "SIGHUP", "call"),
    ("driving", "SIGTERM", "finalizer"),
    ("sending the stop", "SIGINT", "call"),
    ("sending the stop", "SIGTERM", "finalizer"),
    ("closing the port", "SIGHUP", "call"),
    ("closing the port", "SIGINT", "finalizer"),
    ("closing pyserial's port", "SIGTERM", "call"),
    ("waiting in pyserial's close", "SIGINT", "call"),
    ("driving over a serial line", "SIGTERM", "call"),
    ("stopping over a serial line", "SIGHUP", "finalizer"),
]


PYTHON_CASES = [
    ("connecting", "SIGTERM", "call"),
    ("driving", "SIGHUP", "finalizer"),
    ("sending the stop", "SIGINT", "call"),
    ("closing the port", "SIGTERM", "finalizer"),
    ("waiting in pyserial's close", "SIGHUP", "call"),
]
"""Phases of a run from Python (``roboscript.run()`` in a script) a signal is forced into."""


def _phases() -> list[Any]:
    """Every case as test parameters, named for its phase, signal, landing and who ran it."""
    cases = [(*case, False) for case in CASES] + [(*case, True) for case in PYTHON_CASES]
    return [
        pytest.param(
            *case,
            id="-".join([*case[:3], "python"] if case[3] else case[:3])
            .replace(" ", "_")
            .replace("'", ""),
        )
        for case in cases
    ]


def _raised_from_python(done: subprocess.CompletedProcess[str], name: str) -> None:
    """``roboscript.run()`` raised the signal's exception, with the command's sentence, and
    gave the script its own handlers back (:data:`helpers.RUN_FROM_PYTHON`)."""
    signum = getattr(signal, name)
    assert done.returncode == 128 + signum, done.stderr
    assert "Exception ignored" not in done.stderr
    assert done.stderr.splitlines()[-2:] == [
        f"Interrupted: {Interrupted(signum).reason}",  # the sentence roboscript run ends with
        "handlers given back: True",
    ]


@pytest.mark.parametrize(("phase", "name", "landing", "from_python"), _phases())
def test_a_signal_in_any_phase_of_a_run_stops_the_robot_and_ends_it_with_its_status(
    tmp_path: Path, phase: str, name: str, landing: str, from_python: bool
) -> None:
    transport, where = PHASES[phase]
    with _served(transport) as url:
        done, log = _run_signalled(
            tmp_path, url, name, from_python=from_python, SIGNAL_FROM=landing, **where
        )
    (_raised_from_python if from_python else _ended_by)(done, name)
    most = _left_stopped(log)
    if phase.startswith("driving"):
        assert most > 0.1, "the robot never drove: the test proves nothing"
