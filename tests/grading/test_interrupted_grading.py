"""``roboscript grade`` stopped mid-class by the teacher's Ctrl-C, a closed terminal or a
SIGTERM: one plain sentence, the finished runs kept, no traceback, no jail, process or jail
folder left behind; and a graded mission process stopped by a signal stops its robot and says
so instead of reading as a crash."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from helpers import HANG_BOUND_S, OUT_TURN_BEEP, ROOT, run_cli

SPEC = """\
test: long
runs:
  - {seed: 1}
  - {seed: 2}
max_time: 120 s
expect:
  - outcome: success
"""
# A minute of simulated driving each: the class is still being graded when the signal comes.
LONG_DRIVE = OUT_TURN_BEEP.replace("distance: 20 cm, speed: 15 cm/s", "distance: 900 cm")
STUDENTS = ("ada", "bea", "cyd", "dan", "eve", "fay")


def _alive(pid: int) -> bool:
    """Whether ``pid`` is a process that has not exited (a zombie waits only to be reaped)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def _session_processes(sid: int) -> list[str]:
    """The live processes in session ``sid``, as ``pid command``."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            if int(fields[3]) == sid and _alive(int(entry.name)):
                found.append(f"{entry.name} {(entry / 'cmdline').read_text()!r}")
        except (OSError, ValueError, IndexError):
            continue
    return found


def _left_behind(sid: int, below: set[int]) -> list[str]:
    """What of the grader is still running, once its helpers that exit on their own (the
    multiprocessing fork server, which ends when the grader's pipe to it closes) have had
    the time they need: a bound for a hang, never a measure of speed."""
    deadline = time.monotonic() + HANG_BOUND_S
    while True:
        left = _session_processes(sid) + [str(pid) for pid in below if _alive(pid)]
        if not left or time.monotonic() > deadline:
            return left
        time.sleep(0.2)


def _descendants(pid: int) -> set[int]:
    """Every process below ``pid``, whatever session it is in (a jail makes its own)."""
    children: dict[int, set[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                parent = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            children.setdefault(parent, set()).add(int(entry.name))
    found: set[int] = set()
    stack = [pid]
    while stack:
        for child in children.get(stack.pop(), ()):
            if child not in found:
                found.add(child)
                stack.append(child)
    return found


@pytest.mark.skipif(sys.platform != "linux", reason="reads processes from /proc")
@pytest.mark.parametrize(
    ("signum", "to_group", "said"),
    [
        (signal.SIGINT, True, "interrupted by Ctrl-C"),
        (signal.SIGHUP, True, "stopped by SIGHUP (the terminal was closed)"),
        (signal.SIGTERM, False, "stopped by SIGTERM (something asked roboscript to end)"),
    ],
    ids=["ctrl-c", "terminal closed", "sigterm to the grader"],
)
def test_a_class_stopped_by_a_signal_says_so_keeps_what_finished_and_leaves_nothing(
    tmp_path: Path, signum: int, to_group: bool, said: str
) -> None:
    (tmp_path / "spec.yaml").write_text(SPEC, encoding="utf-8")
    (tmp_path / "class").mkdir()
    for name in STUDENTS:
        (tmp_path / "class" / f"{name}.yaml").write_text(LONG_DRIVE, encoding="utf-8")
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch))
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    grader = subprocess.Popen(
        [sys.executable, "-m", "roboscript", "grade", "spec.yaml", "--mission", "class",
         "--results", "part.jsonl", "--csv", "grades.csv", "--jobs", "2", "--hang-after", "60"],
        cwd=tmp_path, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        start_new_session=True,  # its own process group, as a terminal gives a command
    )  # fmt: skip
    assert grader.stderr is not None
    # Signalled once the first run has ended: mid-class, runs going in jails.
    lines = []
    for line in grader.stderr:
        lines.append(line)
        if line.startswith("[1/"):
            break
    below = _descendants(grader.pid)
    if to_group:  # Ctrl-C and a closed terminal reach the terminal's whole process group
        os.killpg(grader.pid, signum)
    else:
        os.kill(grader.pid, signum)
    rest = grader.stderr.read()  # to its end: the grader has exited (stdout is empty)
    grader.wait(timeout=HANG_BOUND_S)
    stderr = "".join(lines) + rest
    assert grader.returncode == 128 + signum, stderr
    assert "Traceback" not in stderr, stderr
    last = stderr.splitlines()[-1]
    assert last.startswith(f"error: {said} after "), last
    assert "runs: no report written" in last
    assert not (tmp_path / "grades.csv").exists()
    # What finished is kept, whole, and nothing the signal cut short is anyone's result.
    header, *runs = (tmp_path / "part.jsonl").read_text(encoding="utf-8").splitlines()
    assert json.loads(header)["roboscript_results"]
    assert runs and {json.loads(run)["status"] for run in runs} == {"passed"}
    assert f"(the {len(runs)} finished" in last
    # Nothing is left: no process of the grader (jails included), no jail folder.
    assert _left_behind(grader.pid, below) == []
    assert sorted(p.name for p in scratch.iterdir()) == []


SIGNALS_ITSELF = """\
import os
import signal

from roboscript import Drive, Mission, state


class SignalsItself(Mission):
    go = state(Drive(distance_mm=2000), initial=True, on_done="end", when=[("far", "end")])
    end = state(final="success")

    def far(self) -> bool:
        if self.driven.total_mm > 300:
            os.kill(os.getpid(), signal.@SIGNAL@)
        return False
"""


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP"])
def test_a_graded_mission_that_signals_itself_stops_its_robot_and_crashes_at_its_line(
    tmp_path: Path, name: str
) -> None:
    # SIGTERM and SIGHUP end a graded mission as Ctrl-C does, its robot stopped; sent by its
    # own code they are its own crash at its line, not "something asked roboscript to end"
    # (a SIGTERM from outside keeps that sentence: tests/grading/test_mission_host.py).
    (tmp_path / "spec.yaml").write_text(
        "test: t\nruns: [{seed: 1}]\nexpect: [{outcome: success}]\n", encoding="utf-8"
    )
    (tmp_path / "ada.py").write_text(SIGNALS_ITSELF.replace("@SIGNAL@", name), encoding="utf-8")
    result = run_cli("grade", "spec.yaml", "--mission", "ada.py", "--json", cwd=tmp_path)
    assert result.returncode == 1, result.stderr
    (run,) = json.loads(result.stdout)["runs"]
    assert (run["status"], run["message"]) == (
        "crashed",
        (
            f"the run crashed: your code sent its own process {name} in state 'go': a mission ends"
            " by going to a final state, not by sending itself a signal (ada.py:13)"
        ),
    )
    assert run["record"]["duration_s"] > 1.0  # it drove 30 cm first
