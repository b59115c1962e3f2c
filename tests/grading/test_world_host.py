"""The world side of a graded run: it records the run itself and trusts the mission with nothing.

A graded run puts the student's mission in a sandboxed process that reaches the simulated
robot only through the lockstep wire. These tests prove that this costs nothing in fidelity
(a graded run records exactly what the same run records in-process, for every protocol) and
that whatever the mission process sends, it cannot make the world record what did not happen.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
from helpers import HANG_BOUND_S, MISSIONS, SLEEPER, every_core_busy, run_cli

from roboscript.grading.run import grade_run, record_from_session
from roboscript.grading.sandbox import Limits
from roboscript.grading.spec import TestSpec, load_test_spec
from roboscript.mission import mission_for_robot
from roboscript.session import run_session

SPEC = """\
test: fidelity
world: {world}
robot: {robot}
runs:
  - {{seed: 1}}
  - {{seed: 7, start: {{x: 370 mm, y: 170 mm, heading: 25 deg}}}}
max_time: {max_time}
expect:
  - outcome: success
"""


def _spec(tmp_path: Path, robot: str, world: str = "empty", max_time: str = "60 s") -> TestSpec:
    path = tmp_path / "test.yaml"
    path.write_text(SPEC.format(robot=robot, world=world, max_time=max_time), encoding="utf-8")
    return load_test_spec(path)


@pytest.mark.parametrize(
    ("robot", "mission", "world"),
    [
        ("mirto", "square.yaml", "empty"),
        ("asip-basic", "square.py", "empty"),
        ("mirto", "bump_and_turn.py", "square-room"),
        ("spike-prime", "square.yaml", "empty"),
        ("stackmod-rover", "stackmod_patrol.yaml", "maze"),
        ("plen2", "plen_walk.yaml", "empty"),
    ],
)
def test_a_graded_run_records_exactly_the_in_process_run(
    tmp_path: Path, robot: str, mission: str, world: str
) -> None:
    spec = _spec(tmp_path, robot, world, max_time="30 s")
    path = str(MISSIONS / mission)
    for variant in spec.variants:
        graded = grade_run(spec, path, variant)
        assert graded.record is not None, graded.message
        loaded, profile, _ = mission_for_robot(path, robot)
        session = run_session(
            loaded,
            profile,
            world=variant.world,
            seed=variant.seed,
            start=variant.start,
            max_time_s=spec.max_time_s,
        )
        assert graded.record.to_dict() == record_from_session(session).to_dict()
        assert graded.record.path, "the world recorded the path"


# The square, saying at each corner how many sides it has driven: its replay holds its prints.
TALKING_SQUARE = (
    (MISSIONS / "square.py")
    .read_text(encoding="utf-8")
    .replace(
        '        return self.visits("side") >= 4',
        '        print("sides:", self.visits("side"))\n        return self.visits("side") >= 4',
    )
)


def _graded_runs(tmp_path: Path, name: str) -> list[dict[str, Any]]:
    """Each run of a graded class as ``--results`` writes it (the replay too), less the two
    fields that measure the machine rather than the run."""
    results = tmp_path / name
    square = MISSIONS / "teacher" / "square"
    mission = _mission(tmp_path, "square.py", TALKING_SQUARE)
    done = run_cli(
        "grade", str(square / "test.yaml"), "--mission", mission, "--results", str(results),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    runs = [json.loads(line) for line in results.read_text(encoding="utf-8").splitlines()[1:]]
    for run in runs:
        del run["wall_time_s"], run["during_load"]
    # --results writes each run as it finishes, in an order the machine's timing decides
    return sorted(runs, key=lambda run: (run["test"], run["variant"]))


def test_a_seed_grades_to_the_same_results_on_an_idle_and_a_saturated_machine(
    tmp_path: Path,
) -> None:
    # The wire's frames are written in batches whose size follows the machine's timing; what
    # the world does with them, and so every byte of the results, must not.
    idle = _graded_runs(tmp_path, "idle.jsonl")
    with every_core_busy():
        busy = _graded_runs(tmp_path, "busy.jsonl")
    assert [run["status"] for run in idle] == ["passed"] * 3
    assert idle[0]["replay"]["frames"], "the replay is compared too"
    printed = [line for f in idle[0]["replay"]["frames"] for line in f.get("print", [])]
    assert printed == ["sides: 1", "sides: 2", "sides: 3", "sides: 4"], "and what it printed"
    assert busy == idle


def _mission(tmp_path: Path, name: str, code: str) -> str:
    path = tmp_path / name
    path.write_text(code, encoding="utf-8")
    return str(path)


# A Python mission can reach the wire's socket: its descriptor is on the process's command
# line. Each of these writes frames of its own when the module is imported.
FORGER = """\
import json, os, struct, sys, time
from roboscript import Mission, Wait, state

FD = int(sys.argv[1])


def frame(kind, payload=b""):
    os.write(FD, kind + struct.pack(">I", len(payload)) + payload)


{body}


class Idle(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end")
    end = state(final="success")
"""


def _forged(tmp_path: Path, body: str) -> str:
    return _mission(tmp_path, "forger.py", FORGER.format(body=body))


SQUARE = load_test_spec(MISSIONS / "teacher" / "square" / "test.yaml")


def test_a_forged_success_before_the_mission_started_scores_nothing(tmp_path: Path) -> None:
    mission = _forged(
        tmp_path,
        'frame(b"F", json.dumps({"outcome": "success", "final_state": "end", "student": "bob",'
        ' "score": 1, "status": "passed"}).encode())\ntime.sleep(60)',
    )
    result = grade_run(SQUARE, mission, SQUARE.variants[0], "alice")
    assert result.status == "crashed"
    assert result.score == 0.0
    assert result.student == "alice"
    assert "before its mission had started" in result.message


def test_a_clock_that_runs_backwards_ends_the_run(tmp_path: Path) -> None:
    mission = _forged(
        tmp_path,
        'frame(b"C")\nframe(b"T", struct.pack(">d", 5.0))\nframe(b"T", struct.pack(">d", 1.0))\n'
        "time.sleep(60)",
    )
    result = grade_run(SQUARE, mission, SQUARE.variants[0])
    assert (result.status, result.score) == ("crashed", 0.0)
    assert "clock went backwards" in result.message


def test_garbage_on_the_wire_ends_the_run(tmp_path: Path) -> None:
    mission = _forged(tmp_path, 'os.write(FD, b"Zgarbage")\ntime.sleep(60)')
    result = grade_run(SQUARE, mission, SQUARE.variants[0])
    assert result.status == "crashed"
    assert "broke the grading wire" in result.message


def test_asking_for_more_time_than_the_test_allows_runs_out_of_time(tmp_path: Path) -> None:
    mission = _forged(
        tmp_path,
        'frame(b"C")\nframe(b"T", struct.pack(">d", 1e9))\ntime.sleep(60)',
    )
    result = grade_run(SQUARE, mission, SQUARE.variants[0])
    assert result.status == "failed"
    assert result.score == 0.0
    assert result.record is not None
    assert "did not finish within" in (result.record.reason or "")


def test_a_flood_of_bytes_to_the_robot_ends_the_run(tmp_path: Path) -> None:
    mission = _forged(
        tmp_path,
        'frame(b"C")\nfor _ in range(400):\n    frame(b"W", b"x" * 200_000)\ntime.sleep(60)',
    )
    result = grade_run(SQUARE, mission, SQUARE.variants[0])
    assert result.status == "crashed"
    assert "more bytes" in result.message


# Writes lines "printed" straight onto the wire: one before its mission starts, and on its
# third tick one of 200,000 characters full of terminal escapes.
PRINT_FORGER = """\
import os, struct, sys
from roboscript import Mission, Wait, state

FD = int(sys.argv[1])
CALLS = []


def frame(kind, payload=b""):
    os.write(FD, kind + struct.pack(">I", len(payload)) + payload)


frame(b"P", b"before the start")


class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end", when=[("forge", "end")])
    end = state(final="success")

    def forge(self):
        CALLS.append(True)
        if len(CALLS) == 3:
            frame(b"P", ("\\x1b[2J\\x07" + "A" * 199_995).encode())
        return False
"""


def test_lines_sent_as_printed_are_made_printable_cut_and_counted_by_the_world(
    tmp_path: Path,
) -> None:
    from roboscript.replay.recording import fill_frames

    spec = tmp_path / "test.yaml"
    spec.write_text(ONE_RUN, encoding="utf-8")
    mission = _mission(tmp_path, "forger.py", PRINT_FORGER)
    result = grade_run(load_test_spec(spec), mission, load_test_spec(spec).variants[0])
    assert result.status == "passed"  # display only: it changes nothing of the run
    assert result.replay is not None
    frames = fill_frames(result.replay["frames"])
    printed = [(frame["t"], line) for frame in frames for line in frame.get("print", [])]
    assert printed == [(0.04, " [2J " + "A" * 495 + "…")]  # its third tick, at 20 ms a tick
    # the one sent as it loaded is the mission's before the start, as run --record keeps it
    assert result.replay["header"]["printed_before_start"] == ["before the start"]
    assert "prints_not_recorded" not in result.replay["result"]


def test_a_student_who_is_a_file_sees_only_the_files_it_names(tmp_path: Path) -> None:
    from roboscript.grading.batch import find_submissions, visible_files

    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "alice.yaml").write_text(
        (MISSIONS / "zigzag.yaml").read_text(encoding="utf-8").replace("zigzag.py", "alice_b.py"),
        encoding="utf-8",
    )
    (folder / "behaviours").mkdir()
    (folder / "behaviours" / "alice_b.py").write_text("import alice_util\n", encoding="utf-8")
    (folder / "alice_util.py").write_text("X = 1\n", encoding="utf-8")
    (folder / "carol").mkdir()  # a classmate who is a folder
    (folder / "carol" / "mission.yaml").write_text("mission: carol\n", encoding="utf-8")
    (folder / "carol" / "alice_util.py").write_text("SECRET = 1\n", encoding="utf-8")
    (folder / "bob.yaml").write_text("mission: bob  # copies alice.yaml\n", encoding="utf-8")
    (folder / "notes.txt").write_text("not named by anyone\n", encoding="utf-8")
    spec = folder / "test.yaml"
    spec.write_text("test: t\nexpect:\n  - outcome: success\n", encoding="utf-8")
    students = {s.student: s for s in find_submissions([str(folder)]).submissions}
    assert sorted(students) == ["alice", "bob", "carol"]
    private = frozenset(
        (folder / name).resolve() for name in ("alice.yaml", "bob.yaml", "test.yaml", "carol")
    )
    alice = students["alice"]
    seen = visible_files(alice, alice.missions[0], private - {(folder / "alice.yaml").resolve()})
    assert sorted(p.relative_to(folder.resolve()).as_posix() for p in seen) == [
        "alice.yaml",
        "alice_util.py",
        "behaviours/alice_b.py",
    ]
    bob = students["bob"]
    seen = visible_files(bob, bob.missions[0], private - {(folder / "bob.yaml").resolve()})
    assert [p.name for p in seen] == ["bob.yaml"]  # naming alice.yaml does not reveal it


# ----------------------------------------------------------------- through `roboscript grade`

ONE_RUN = """\
test: one-run
world: empty
robot: mirto
runs:
  - {seed: 1}
max_time: 60 s
wall_time_limit: 300 s   # far past every rule below: none of them may need it
expect:
  - outcome: success
"""


def _graded(tmp_path: Path, name: str, code: str) -> dict[str, Any]:
    """Grade one student's ``name`` through the command line; the one run's JSON."""
    spec = tmp_path / "test.yaml"
    spec.write_text(ONE_RUN, encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / name).write_text(code, encoding="utf-8")
    done = run_cli("grade", str(spec), "--mission", str(folder), "--json")
    assert "Traceback" not in done.stderr, done.stderr
    runs = json.loads(done.stdout)["runs"]
    assert len(runs) == 1
    run: dict[str, Any] = runs[0]
    return run


FLOODER = FORGER.format(
    body='frame(b"C")\nfor _ in range(40):\n    os.write(FD, b"Y\\0\\0\\0\\0" * 100_000)'
    "\ntime.sleep(600)"
)


def test_a_mission_that_floods_the_wire_and_never_reads_is_ended_as_its_own_fault(
    tmp_path: Path,
) -> None:
    run = _graded(tmp_path, "flood.py", FLOODER)
    assert run["status"] == "crashed"
    # The mission floods while it loads: one sentence, however busy the machine (the world
    # ends it at the first read holding many questions, before its load limit could cut it)
    assert run["message"] == "the run was stopped: it stopped reading the robot's answers"


NON_READER = FORGER.format(
    body='frame(b"C")\nfor _ in range(20):\n    frame(b"W", b"I,v\\n" * 5000)\ntime.sleep(600)'
)


def test_a_mission_that_lets_the_robots_answers_pile_up_is_ended_as_its_own_fault(
    tmp_path: Path,
) -> None:
    run = _graded(tmp_path, "deaf.py", NON_READER)
    assert run["status"] == "crashed"
    assert run["message"] == (
        "the run was stopped: it sent the robot commands far faster than it read the answers"
    )


def test_a_mission_that_sleeps_each_tick_is_ended_early_as_too_slow_at_its_line(
    tmp_path: Path,
) -> None:
    run = _graded(tmp_path, "sleepy.py", SLEEPER)
    assert run["status"] == "too slow"
    assert run["message"].startswith("the mission was too slow: its code at sleepy.py:22 in tired")
    assert "never time.sleep" in run["message"]
    # ended early: about a second of slow ticks, not the 13 s of robot time the drive takes
    assert run["record"]["duration_s"] < 5


def test_run_warns_about_the_same_code_once_and_ends_it_as_grade_does(tmp_path: Path) -> None:
    mission = tmp_path / "sleepy.py"
    mission.write_text(SLEEPER, encoding="utf-8")
    done = run_cli("run", str(mission), "--quiet")
    assert done.returncode == 1
    warnings = [line for line in done.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1
    assert re.match(
        r"warning: the mission's code at \S*sleepy\.py:22 in tired took 0\.\d\d s", warnings[0]
    )
    last = done.stderr.strip().splitlines()[-1]
    assert re.match(r"error: the mission was too slow: its code at \S*sleepy\.py:22 in tired", last)


def test_honest_missions_graded_on_a_saturated_machine_never_hang_or_crash(
    tmp_path: Path,
) -> None:
    # Bounded, not timed: twice as many spinners as cores, the default --hang-after, and
    # exactly the verdicts an idle machine gives, both ways: no honest run hung, too slow or
    # crashed, and the one that sleeps in a condition still too slow at its line.
    folder = tmp_path / "class"
    folder.mkdir()
    square = MISSIONS / "teacher" / "square"
    shutil.copy(square / "good.yaml", folder / "amy.yaml")
    shutil.copy(square / "good.yaml", folder / "ben.yaml")
    shutil.copy(square / "bad.yaml", folder / "cy.yaml")  # honest, but off by one
    shutil.copy(MISSIONS / "square.py", folder / "dee.py")  # Python: more to import
    (folder / "eve.py").write_text(SLEEPER, encoding="utf-8")  # time.sleep in a condition
    with every_core_busy(extra=os.cpu_count() or 1):
        done = run_cli("grade", str(square / "test.yaml"), "--mission", str(folder), "--json")
    assert done.returncode == 1, done.stderr  # cy and eve do not pass
    runs = json.loads(done.stdout)["runs"]
    verdicts = sorted((run["student"], run["variant"], run["status"]) for run in runs)
    expected = {"amy": "passed", "ben": "passed", "cy": "failed", "dee": "passed"}
    expected["eve"] = "too slow"
    assert verdicts == [(s, v, status) for s, status in expected.items() for v in range(3)], [
        (run["student"], run["status"], run["message"]) for run in runs
    ]
    assert all(
        r["message"].startswith("the mission was too slow: its code at eve.py:22 in tired")
        for r in runs
        if r["student"] == "eve"
    )


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
def test_a_mission_process_that_ends_while_loading_is_never_judged_hung() -> None:
    # A mission that crashes while loading ends its process before the world reads the closed
    # socket; on a busy machine the world can check for a stall in between. The tree is gone
    # then, and uses no more CPU: its stall must stay what it was, never wall time less the
    # CPU time read before (a run "hung for 35796.1 s" where it had crashed).
    from roboscript.grading.world_host import _Stall

    process = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    try:
        stall = _Stall(process.pid)
        assert stall.check(time.monotonic(), 1.0, 0.0) is None  # loading: no progress
        assert stall.check(time.monotonic(), 1.0, 0.0) is None  # the CPU time, read
    finally:
        process.kill()
        process.wait(HANG_BOUND_S)
    assert stall.check(time.monotonic(), 1.0, 0.0) is None  # the process is gone
    assert stall.measured == "CPU time"


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
def test_a_stall_is_cpu_time_used_while_simulated_time_stands_still() -> None:
    # The world compares simulated time at each check, not on each tick: a run that advanced
    # since the last check is never charged, one that stood still is charged its CPU time.
    from roboscript.grading.world_host import _Stall

    process = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        stall = _Stall(process.pid)
        assert stall.check(time.monotonic(), 0.05, 0.0) is None  # the first look
        stall.mission_loaded(0.0)
        assert stall.check(time.monotonic(), 0.05, 0.0) is None  # loading is progress
        deadline = time.monotonic() + HANG_BOUND_S
        stalled = None
        while stalled is None and time.monotonic() < deadline:
            time.sleep(0.01)
            stalled = stall.check(time.monotonic(), 0.05, 0.0)
        assert stalled is not None and stalled >= 0.05
        assert stall.measured == "CPU time"
        assert stall.check(time.monotonic(), 0.05, 0.02) is None  # time advanced: no stall
        assert stall.check(time.monotonic(), 0.05, 0.02) is None  # counted afresh from here
    finally:
        process.kill()
        process.wait(HANG_BOUND_S)


# Through ctypes: the mission process's os.kill of its own SIGSTOP ends the run at its line
# (test_hostile_class.py); one sent around it is seen only by the world.
PAUSES_ITSELF = """\
import ctypes, os, signal
from roboscript import Drive, Mission, state


class Paused(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", when=[("rest", "end")])
    end = state(final="success")

    def rest(self):
        ctypes.CDLL(None).kill(os.getpid(), signal.SIGSTOP)
        return False
"""


def test_a_mission_that_stops_its_own_process_is_hung_at_once_not_waited_out(
    tmp_path: Path,
) -> None:
    # A stopped process uses no CPU and waits for none: only being seen stopped ends it
    # (before, the run took the spec's whole wall limit, stretched by the machine's load).
    run = _graded(tmp_path, "paused.py", PAUSES_ITSELF)
    assert run["status"] == "hung"
    assert re.fullmatch(
        r"the mission stopped advancing at \d+\.\d\d s of simulated time: its process was"
        r" paused by a stop signal \(SIGSTOP\) and would never go on by itself",
        run["message"],
    ), run["message"]


# Starts four processes that each keep 48 MiB (well under a process's own limit), and waits
# (with subprocess: a graded mission's os.fork() is refused).
HOARDS_IN_FOUR_PROCESSES = """\
import subprocess
import sys
from roboscript import Mission, Wait, state

HOARD = (
    "import time\\n"
    "kept = bytearray(48 * 1024 * 1024)\\n"
    "for i in range(0, len(kept), 4096):\\n"
    "    kept[i] = 1  # touched, so the pages are held, not only promised\\n"
    "time.sleep(60)\\n"
)
_hoarders = []


class Hoard(Mission):
    # long enough that the world's reading (four times a second) sees the hoarders, however
    # slowly a busy machine starts them: the run ends on the memory rule, not on this wait
    go = state(Wait(duration_s=3000), initial=True, on_done="end", when=[("start_hoarding", "end")])
    end = state(final="success")

    def start_hoarding(self) -> bool:
        if not _hoarders:
            _hoarders.extend(subprocess.Popen([sys.executable, "-c", HOARD]) for _ in range(4))
        return False
"""


def test_a_run_whose_processes_together_hold_too_much_memory_is_ended(tmp_path: Path) -> None:
    spec = _spec(tmp_path, "mirto", max_time="3600 s")
    mission = tmp_path / "hoard.py"
    mission.write_text(HOARDS_IN_FOUR_PROCESSES, encoding="utf-8")
    limits = Limits(total_memory_bytes=128 * 1024**2)  # four times 48 MiB is over it
    result = grade_run(spec, str(mission), spec.variants[0], limits=limits)
    assert result.status == "crashed", result.message
    assert "processes together used" in result.message
    assert "over the 0.125 GiB a run may use" in result.message
    assert "roboscript problem" not in result.message
