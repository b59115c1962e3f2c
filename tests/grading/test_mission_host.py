"""The mission process of a graded run (``roboscript.grading.mission_host``), seen from outside."""

from __future__ import annotations

import contextlib
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, MISSIONS, one_run_spec

from roboscript.grading import mission_host, world_host
from roboscript.grading.batch import find_specs, find_submissions, grade_class
from roboscript.grading.run import grade_run
from roboscript.grading.sandbox import (
    ISOLATION_VARIABLE,
    LIMITS_ONLY,
    Jail,
    detect_isolation,
    warm_jails_supported,
)
from roboscript.interrupts import Interrupted

# Finishes at once; as its robot's link closes, the process is sent Ctrl-C's signal.
SIGNALLED_WHILE_CLOSING = """\
import os, signal

from roboscript import Mission, Wait, state
from roboscript.transport.link import Link

_close = Link.close


def close(self):
    os.kill(os.getpid(), signal.SIGINT)  # the mission has ended: the port is closing
    _close(self)


# by a name the loader cannot read before it runs: this stands for code that does anything
setattr(Link, "close".strip(), close)


class Short(Mission):
    go = state(Wait(duration_s=0.1), initial=True, on_done="end")
    end = state(final="success")
"""


def test_a_ctrl_c_while_the_mission_process_closes_ends_it_with_the_signals_status(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Ctrl-C (SIGINT) is the signal Python turns into an exception the run catches; SIGTERM
    # and SIGHUP end the process by themselves.
    statuses: list[int] = []

    class Watched(Jail):
        """The mission process's jail, keeping the status it ended with."""

        def poll(self) -> int | None:
            status = super().poll()
            if status is not None and not statuses:
                statuses.append(status)
            return status

    monkeypatch.setattr(world_host, "Jail", Watched)
    spec = one_run_spec(tmp_path)
    mission = tmp_path / "short.py"
    mission.write_text(SIGNALLED_WHILE_CLOSING, encoding="utf-8")
    result = grade_run(spec, str(mission), spec.variants[0])
    assert result.status == "passed", result.message  # it had finished: its result stands
    signum = signal.SIGINT
    # 128 + N as it exits; under bubblewrap that reads as -N, as an end by the signal does
    assert statuses in ([128 + signum], [-signum]), statuses


SAYS_WHAT_ITS_RUN_IMPORTED = """\
import sys
from roboscript import Mission, Wait, state

LOADED = set(sys.modules)


class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end", when=[("look", "end")])
    end = state(final="success")

    def look(self) -> bool:
        print("IMPORTED SINCE LOADING", sorted(set(sys.modules) - LOADED))
        return False
"""


@pytest.mark.skipif(not warm_jails_supported(), reason="warm jails are Linux only")
def test_a_run_forked_from_a_warm_jail_imports_nothing_once_its_mission_loaded(
    tmp_path: Path,
) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        "test: t\nrobot: mirto\nruns:\n  - {seed: 1}\nexpect:\n  - outcome: success\n",
        encoding="utf-8",
    )
    student = tmp_path / "class" / "ivy.py"
    student.parent.mkdir()
    student.write_text(SAYS_WHAT_ITS_RUN_IMPORTED, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(student.parent)]).submissions, jobs=1
    )
    assert report.passed
    # The run machinery, the port and the robot's codec: all imported by the jail's server.
    # (pyserial's own handler package, where it looks first for any URL, is transport's to
    # import, and it holds nothing but its name.)
    seen = re.findall(r"IMPORTED SINCE LOADING (\[.*\])", report.results[0].debug)
    assert seen and set(json.loads(seen[0].replace("'", '"'))) <= {"serial.urlhandler"}


LOADS_BOTH_KINDS = """\
import sys
from roboscript.grading.mission_host import warm_up

warm_up("mirto")
before = set(sys.modules)
from roboscript.mission import mission_for_robot

for path in sys.argv[1:]:
    mission_for_robot(path, "mirto")
print(sorted(name for name in set(sys.modules) - before if not name.startswith("_roboscript")))
"""


def test_the_warm_up_imports_what_loading_either_kind_of_mission_imports(tmp_path: Path) -> None:
    # A Python mission's own module is the one import its loading may add.
    done = subprocess.run(
        [
            sys.executable,
            "-I",
            "-c",
            LOADS_BOTH_KINDS,
            str(MISSIONS / "square.yaml"),
            str(MISSIONS / "square.py"),
        ],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=HANG_BOUND_S,
        check=True,
    )
    assert done.stdout.strip() == "[]", done.stdout + done.stderr


# Drives, and says so once it has driven 30 cm: the test then sends its process SIGTERM.
DRIVES_AND_SAYS_SO = """\
from roboscript import Drive, Mission, state


class Drives(Mission):
    go = state(Drive(distance_mm=2000), initial=True, on_done="end", when=[("far", "end")])
    end = state(final="success")

    def far(self) -> bool:
        if self.driven.total_mm > 300 and not getattr(self, "said", False):
            self.said = True
            print("DRIVEN 30 CM", flush=True)
        return False
"""


@pytest.fixture(params=["best", "limits"])
def isolation(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    """The best isolation this computer gives, and resource limits only (where the run shares
    the grader's user). (A user of its own per jail is held to the grader's warm jails: a run
    started alone cannot read its world's map there.)"""
    mode = str(request.param)
    if mode != "best":
        monkeypatch.setenv(ISOLATION_VARIABLE, mode)
    detect_isolation.cache_clear()
    request.addfinalizer(detect_isolation.cache_clear)
    if mode == "limits" and detect_isolation().name != LIMITS_ONLY:
        pytest.skip("this computer cannot give the 'limits' isolation")
    return mode


@pytest.mark.usefixtures("isolation")
def test_a_sigterm_from_outside_the_mission_keeps_its_own_sentence(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # A teacher's `kill`, a process manager: not the student's code. The run ends with its
    # robot stopped and the signal's sentence, as before, whichever isolation holds the run
    # (even one that shares the teacher's user); the mission's own SIGTERM, sent itself or
    # through a program it started, is its crash (tests/grading/test_cheats.py,
    # tests/grading/test_hostile_class.py).
    frame = world_host._WorldSession._frame
    sent: list[int] = []

    def signalled_once_driving(session: world_host._WorldSession, kind: bytes, data: bytes) -> None:
        frame(session, kind, data)
        if kind == b"P" and b"DRIVEN 30 CM" in data and not sent and session.jail.pid:
            sent.append(_mission_process(session.jail.pid))
            os.kill(sent[0], signal.SIGTERM)

    monkeypatch.setattr(world_host._WorldSession, "_frame", signalled_once_driving)
    spec = one_run_spec(tmp_path)
    mission = tmp_path / "drives.py"
    mission.write_text(DRIVES_AND_SAYS_SO, encoding="utf-8")
    result = grade_run(spec, str(mission), spec.variants[0])
    assert sent, result.debug
    assert (result.status, result.message) == (
        "failed",
        (
            "outcome failed: the mission ended in error: stopped by SIGTERM (something asked"
            " roboscript to end)"
        ),
    )
    assert result.record is not None and result.record.duration_s > 1.0  # it drove 30 cm


# Drives 30 cm, then has a program it starts send its own process SIGTERM.
SIGNALS_ITSELF_THROUGH_A_PROGRAM = """\
import os, subprocess

from roboscript import Drive, Mission, state


class Drives(Mission):
    go = state(Drive(distance_mm=2000), initial=True, on_done="end", when=[("far", "end")])
    end = state(final="success")

    def far(self) -> bool:
        if self.driven.total_mm > 300:
            subprocess.run(["kill", "-TERM", str(os.getpid())], check=False)
        return False
"""


@pytest.mark.usefixtures("isolation")
def test_a_sigterm_a_program_of_the_run_sends_it_is_the_students_own(tmp_path: Path) -> None:
    # Told from a teacher's kill (above) by its sender: a process in the run's own PID
    # namespace or under its own user, or, where it shares the teacher's user, in its session.
    spec = one_run_spec(tmp_path)
    mission = tmp_path / "signals.py"
    mission.write_text(SIGNALS_ITSELF_THROUGH_A_PROGRAM, encoding="utf-8")
    result = grade_run(spec, str(mission), spec.variants[0])
    assert (result.status, result.message) == (
        "crashed",
        (
            "the run crashed: your code sent its own process SIGTERM (through a program it"
            " started) in state 'go': a mission ends by going to a final state, not by sending"
            " itself a signal (signals.py:12)"
        ),
    ), result.debug


def test_a_signal_from_a_program_still_being_started_is_the_runs(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # The program runs, signals its starter and may be reaped before the starter has noted
    # its pid (fork_exec returns after the program's exec): the sender is looked for once
    # the programs under way are noted, not before.
    monkeypatch.setattr(mission_host, "_started_programs", set())
    monkeypatch.setattr(mission_host, "_spawns_under_way", 1)
    monkeypatch.setattr(mission_host, "_SPAWN_WAIT_S", 600.0)  # a bound, not a timing
    gone_pid = 2**22 + 1  # above Linux's largest pid: no process to be seen in /proc
    info = signal.struct_siginfo((signal.SIGTERM, 0, 0, gone_pid, os.getuid() + 1, 0, 0))

    def starter_returns() -> None:
        time.sleep(0.2)  # the signal is looked at first (an order, not a limit)
        with mission_host._spawning:
            mission_host._started_programs.add(gone_pid)
            mission_host._spawns_under_way -= 1
            mission_host._spawning.notify_all()

    thread = threading.Thread(target=starter_returns)
    thread.start()
    try:
        how = mission_host._sender_of(info, os.getpid(), user_alone=False)
    finally:
        thread.join()
    assert how == mission_host._THROUGH_A_PROGRAM


def test_a_signal_landing_on_the_starter_while_it_starts_a_program_is_the_runs(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # While it starts a program the starter has the signal unblocked (the program must get it
    # so): one the program sends at once lands on the starter, where no sender is told.
    monkeypatch.setattr(mission_host, "_sent_itself", {})
    monkeypatch.setattr(mission_host, "_spawns_under_way", 0)
    seen: list[int] = []
    previous = signal.signal(signal.SIGTERM, lambda number, _frame: seen.append(number))
    try:
        mission_host._note_if_spawned(signal.SIGTERM)
        signal.raise_signal(signal.SIGTERM)  # no program being started: nothing noted
        assert mission_host._sent_itself == {}
        monkeypatch.setattr(mission_host, "_spawns_under_way", 1)
        signal.raise_signal(signal.SIGTERM)
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert seen == [signal.SIGTERM, signal.SIGTERM]  # the run's own handler runs as before
    assert mission_host._sent_itself == {signal.SIGTERM: mission_host._THROUGH_A_PROGRAM}


def test_a_signal_a_program_sent_names_the_line_that_started_the_program(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Handed on from the thread that learned its sender, the signal lands wherever the
    # mission's code has got to by then (often past its own file): the line that started the
    # program that sent it is the one the stop names, every time.
    monkeypatch.setattr(
        mission_host, "_sent_itself", {signal.SIGTERM: mission_host._THROUGH_A_PROGRAM}
    )
    monkeypatch.setattr(mission_host, "_sent_from", {signal.SIGTERM: ("/jail/signals.py", 12)})
    own = mission_host._own_interrupt(Interrupted(signal.SIGTERM))
    assert own is not None
    assert own.where == "signals.py:12"
    assert own.did == "sent its own process SIGTERM (through a program it started)"


def _mission_process(jail_pid: int) -> int:
    """The mission process among the jail's process and its descendants (Linux's /proc)."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError):
                stat = (entry / "stat").read_text()
                parents[int(entry.name)] = int(stat.rsplit(")", 1)[1].split()[1])
    tree, grew = {jail_pid}, True
    while grew:
        below = {pid for pid, parent in parents.items() if parent in tree} - tree
        tree |= below
        grew = bool(below)
    for pid in sorted(tree):
        with contextlib.suppress(OSError):
            argv = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")
            if b"roboscript.grading.mission_host" in argv and b"bwrap" not in argv[0]:
                return pid
    return jail_pid  # the jail is the mission process itself (no bubblewrap)
