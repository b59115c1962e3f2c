"""Hostile submissions against the real grader: every cheat fails or is contained.

Each student below is one way a class tried to pass itself, harm a classmate or break the
grader. The whole class is graded once, through ``roboscript grade`` in a subprocess, exactly
as a teacher runs it, with every report written; then each test checks one promise. The
honest student's result must come out right whatever the others did.

The class is graded in each isolation that keeps students apart: bubblewrap's full jail,
and (where the grader is root, as in LMS containers where bubblewrap cannot run) each run as
a user of its own. A mode this computer cannot give is skipped (see the teachers' guide for
what each platform guarantees).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import html
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import uuid
from pathlib import Path
from typing import Any

import pytest
from helpers import FORWARD_50CM, FORWARD_50CM_EXPECT, HANG_BOUND_S

from roboscript.grading.sandbox import (
    BUBBLEWRAP,
    ISOLATION_VARIABLE,
    SEPARATE_USER,
)

MODES = {"bubblewrap": BUBBLEWRAP, "user": SEPARATE_USER}

SPEC = """\
test: forward
description: Drive 50 cm straight ahead, then stop.
world: empty
robot: mirto
runs:
  - {seed: 1}
  - {seed: 2, start: {x: 300 mm, y: 100 mm, heading: 0 deg}}
"""
SPEC += FORWARD_50CM_EXPECT

HONEST = FORWARD_50CM

SPIN = """\
mission: spin
behaviours: patch.py
initial: turn
states:
  turn:
    do: {rotate: {angle: 360 deg}}
    on: {done: finished}
  finished:
    final: success
"""

# Replaces the grader's record and judge with a perfect run, as far as its own process goes.
PATCH = """\
import roboscript.grading.expectations as expectations
import roboscript.grading.run as run
import roboscript.grading.world_host as world_host
from roboscript import Action
from roboscript.grading.record import Verdict


class Nothing(Action):
    name = "nothing"
    params = ()

    def update(self, ctx):
        return None


def perfect(*args, **kwargs):
    return Verdict("anything", True, "passed by a mile")


expectations.evaluate = perfect
run.evaluate = perfect
run.run_score = lambda *a, **k: 1.0
world_host.simulation_record = None
run.record_from_session = None
"""

IDLE_MISSION = """\
from roboscript import Mission, Wait, state

{body}


class Idle(Mission):
    go = state(Wait(duration_s=0.5), initial=True, on_done="end")
    end = state(final="success")
"""

FORGER = """\
import os, pickle, struct
forged = [
    {"student": "ada", "test": "forward", "status": "failed", "score": 0.0},
    {"student": "forger", "test": "forward", "status": "passed", "score": 1.0, "passed": True},
]
for fd in range(3, 256):
    for item in forged:
        try:
            data = pickle.dumps(item)
            os.write(fd, struct.pack("!i", len(data)) + data)
        except OSError:
            pass
"""

SNOOP = """\
import glob, os
seen = []
for path in [{spec!r}, {classmate!r}] + glob.glob("/proc/*/cmdline"):
    try:
        with open(path, "rb") as handle:
            text = handle.read(4000)
    except OSError:
        continue
    # the spec's name, or the grader's command line ("roboscript grade ...")
    if b"forward" in text or b"\\x00grade\\x00" in text:
        seen.append(path)
print("SNOOPED", seen)
folder = os.path.dirname({classmate!r})
try:
    print("SIBLINGS", sorted(os.listdir(folder)))
except OSError:
    print("SIBLINGS none")
"""

PLANTER = """\
import pathlib
for path in {targets!r}:
    try:
        pathlib.Path(path).parent.mkdir(parents=True, exist_ok=True)
        pathlib.Path(path).write_text("PLANTED")
        print("planted", path)
    except OSError as exc:
        print("refused", path, type(exc).__name__)
"""

EDITOR = """\
import roboscript.grading.gradebook as gradebook
try:
    with open(gradebook.__file__, "a") as handle:
        handle.write("\\nPLANTED = True\\n")
    print("edited")
except OSError as exc:
    print("refused", type(exc).__name__)
"""

# Leaves a process behind that outlives the run, named by a marker in its command line, and
# keeps trying to plant in the reports for as long as it lives. The mission says "DAEMON UP"
# only once that process has started and spoken, so the test knows it existed.
DAEMON = """\
import os, subprocess, sys
LOOP = '''
import os, pathlib, sys, time
os.write(int(sys.argv[2]), b"up")
os.close(int(sys.argv[2]))
while True:
    for path in {targets!r}:
        try:
            pathlib.Path(path).write_text("PLANTED BY A DAEMON")
        except OSError:
            pass
    time.sleep(0.05)
'''
ready, tell = os.pipe()
# in a session of its own, as a double fork would leave it (a graded run refuses os.fork())
subprocess.Popen(
    [sys.executable, "-I", "-c", LOOP, {marker!r}, str(tell)],
    pass_fds=(tell,), start_new_session=True,
)
os.close(tell)
print("DAEMON UP" if os.read(ready, 2) == b"up" else "DAEMON NEVER STARTED", flush=True)
"""

KILLER = """\
import os, signal
for target in (os.getppid(), -1, 0, 1):
    for sig in (signal.SIGKILL, signal.SIGTERM, signal.SIGSTOP):
        try:
            os.kill(target, sig)
        except BaseException:  # its own signals end its run where they land: go on all the same
            pass
for pid in os.listdir("/proc"):
    if pid.isdigit() and int(pid) != os.getpid():
        try:
            os.kill(int(pid), signal.SIGKILL)
        except OSError:
            pass
"""

# Sends its own process SIGTERM through a program it starts, while its file loads: the
# signal is the student's own doing, whatever the isolation, not "something asked roboscript
# to end".
SIGNALLER = """\
import os, subprocess
subprocess.run(["kill", "-TERM", str(os.getpid())], check=False)
"""

FAKE_LINES = """\
import os
for pid in os.listdir("/proc"):
    for fd in ("1", "2"):
        try:
            with open(f"/proc/{pid}/fd/{fd}", "w") as handle:
                handle.write("FAKE-LINE ada forward: crashed\\n")
        except OSError:
            pass
"""

FORK_BOMB = """\
import os
children = 0
try:
    while children < 100000:
        if os.fork() == 0:
            import uuid
            time.sleep(30)
            os._exit(0)
        children += 1
except OSError:
    pass
"""

FLOOD = """\
import sys
sys.stdout.write("x" * 20_000_000)
raise RuntimeError("y" * 20_000_000)
"""

MEMORY = """\
hog = bytearray(8 * 1024**3)
"""

DISK = """\
with open("/tmp/fill", "wb") as handle:
    for _ in range(2000):
        handle.write(b"z" * 1024 * 1024)
"""


@pytest.fixture(scope="module", params=sorted(MODES))
def graded(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> dict[str, Any]:
    """The class, graded once per isolation mode by the real command line."""
    mode = request.param
    environment = {**os.environ, ISOLATION_VARIABLE: mode}
    if _isolation_for(mode)["name"] != MODES[mode]:
        # bubblewrap missing; or not root, or an interpreter other users cannot run
        pytest.skip(f"this computer cannot give the '{mode}' isolation")
    root = tmp_path_factory.mktemp("cheats")
    if mode == "user":  # without bubblewrap a run must pass through the folders above its own
        root = Path(tempfile.mkdtemp(prefix="roboscript-cheats-"))
        root.chmod(0o711)
        request.addfinalizer(lambda: shutil.rmtree(root, ignore_errors=True))
    teacher = root / "teacher"
    teacher.mkdir()
    spec = teacher / "forward.yaml"
    spec.write_text(SPEC, encoding="utf-8")
    subs = root / "class"
    report_dir = root / "report"
    csv_file = root / "grades.csv"
    targets = [str(report_dir / "index.html"), str(csv_file), str(spec)]

    def student(name: str, files: dict[str, str]) -> None:
        folder = subs / name
        folder.mkdir(parents=True)
        for file, text in files.items():
            (folder / file).write_text(text, encoding="utf-8")

    def idle(name: str, body: str) -> None:
        student(name, {"mission.py": IDLE_MISSION.format(body=body)})

    student("ada", {"forward.yaml": HONEST})
    student("patcher", {"spin.yaml": SPIN, "patch.py": PATCH})
    idle("forger", FORGER)
    idle("snoop", SNOOP.format(spec=str(spec), classmate=str(subs / "ada" / "forward.yaml")))
    idle("planter", PLANTER.format(targets=targets))
    idle("editor", EDITOR)
    marker = f"roboscript-cheats-daemon-{uuid.uuid4().hex}"
    idle("daemon", DAEMON.format(targets=targets, marker=marker))
    idle("killer", KILLER)
    idle("signaller", SIGNALLER)
    idle("liar", FAKE_LINES)
    idle("forker", FORK_BOMB)
    idle("flooder", FLOOD)
    idle("hog", MEMORY)
    idle("filler", DISK)
    from roboscript.grading import gradebook

    package_file = Path(gradebook.__file__)
    before = hashlib.sha256(package_file.read_bytes()).hexdigest()
    results = root / "results.jsonl"
    command = [
        sys.executable,
        "-m",
        "roboscript",
        "grade",
        str(spec),
        "--mission",
        str(subs),
        "--json",
        "--jobs",
        "2",
        "--csv",
        str(csv_file),
        "--html",
        str(report_dir),
        "--results",
        str(results),
    ]
    try:
        done = subprocess.run(
            command,
            capture_output=True,
            text=True,
            timeout=HANG_BOUND_S,
            check=False,
            env=environment,
        )
    except subprocess.TimeoutExpired as stuck:  # say where it was, not only that it was
        pytest.fail(f"the grader did not return: {_tail(stuck.stderr)}")
    survivors = _processes_with(marker)  # the run has ended: its daemon must be gone now
    for pid in survivors:  # one that escaped is not left running after the test
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    return {
        "exit": done.returncode,
        "stdout": done.stdout,
        "stderr": done.stderr,
        "report": json.loads(done.stdout) if done.stdout.startswith("{") else None,
        "csv": csv_file.read_text(encoding="utf-8-sig") if csv_file.exists() else "",
        "html": report_dir,
        "spec": spec,
        "package_hash": (before, hashlib.sha256(package_file.read_bytes()).hexdigest()),
        "results": results,
        "mode": mode,
        "class": subs,
        "daemon_survivors": survivors,
    }


def _processes_with(marker: str) -> list[int]:
    """The processes of this computer whose command line holds ``marker``."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            command_line = (entry / "cmdline").read_bytes()
        except OSError:  # ended meanwhile, or not ours to read
            continue
        if marker.encode() in command_line.split(b"\0"):
            found.append(int(entry.name))
    return found


def _runs(graded: dict[str, Any], student: str) -> list[dict[str, Any]]:
    report = graded["report"]
    assert report is not None, graded["stderr"][-3000:]
    return [r for r in report["runs"] if r["student"] == student]


def _tail(text: str | bytes | None, chars: int = 3000) -> str:
    """The end of a process's output, for a failure to show."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    return (text or "")[-chars:]


def _shown(runs: list[dict[str, Any]]) -> list[tuple[str, str, str]]:
    """Each run's status and message, and the end of what its mission printed: what a failed
    check shows, so a verdict that came out wrong on a busy machine says why."""
    return [(r["status"], r["message"][:500], _tail(r["debug"], 1500)) for r in runs]


def test_the_grader_survives_the_class_and_reports_everyone(graded: dict[str, Any]) -> None:
    assert graded["exit"] == 1, graded["stderr"][-3000:]  # some students failed: exit 1
    students = {r["student"] for r in graded["report"]["results"]}
    assert len(students) == 14


def test_the_honest_student_passes_whatever_the_class_did(graded: dict[str, Any]) -> None:
    runs = _runs(graded, "ada")
    assert [r["status"] for r in runs] == ["passed", "passed"], _shown(runs)
    assert "ada," in graded["csv"] and "PLANTED" not in graded["csv"]


def test_patching_the_grader_from_the_mission_changes_nothing(graded: dict[str, Any]) -> None:
    runs = _runs(graded, "patcher")
    # refused where it puts its own in the place of the grader's (and the patch would only
    # reach the mission's own process: the world judges in another)
    assert [r["status"] for r in runs] == ["invalid", "invalid"], _shown(runs)
    assert all(r["score"] == 0 for r in runs)
    assert all("patch.py:" in r["message"] and "evaluate" in r["message"] for r in runs)


def test_a_forged_result_on_any_descriptor_changes_nothing(graded: dict[str, Any]) -> None:
    for run in _runs(graded, "forger"):
        assert run["status"] == "crashed", _shown([run])  # its bytes broke the wire
        assert run["score"] == 0
        assert "broke the grading wire" in run["message"]


def test_the_spec_and_classmates_files_are_out_of_reach(graded: dict[str, Any]) -> None:
    output = _runs(graded, "snoop")[0]["debug"]
    snooped = output.split("SNOOPED ", 1)[1].splitlines()[0]
    if graded["mode"] == "bubblewrap":
        assert snooped == "[]"  # not even the grader's command line is in sight
    else:  # a user of its own sees other processes, but reads neither file
        assert "forward.yaml" not in snooped and "ada" not in snooped
    assert "ada" not in output.split("SIBLINGS", 1)[1].splitlines()[0]


def test_every_report_says_how_the_runs_were_isolated(graded: dict[str, Any]) -> None:
    statement = graded["report"]["isolation"]
    assert statement == _isolation_for(graded["mode"])["statement"]
    index = (Path(graded["html"]) / "index.html").read_text(encoding="utf-8")
    assert html.escape(statement) in index


def test_nothing_is_planted_in_the_reports_or_the_spec(graded: dict[str, Any]) -> None:
    assert "refused" in _runs(graded, "planter")[0]["debug"]
    for page in Path(graded["html"]).rglob("*.html"):
        assert "PLANTED" not in page.read_text(encoding="utf-8")
    assert "PLANTED" not in graded["spec"].read_text(encoding="utf-8")


def test_the_installed_package_cannot_be_edited(graded: dict[str, Any]) -> None:
    before, after = graded["package_hash"]
    assert before == after
    assert "refused" in _runs(graded, "editor")[0]["debug"]


def test_a_daemon_dies_with_its_run(graded: dict[str, Any]) -> None:
    assert "DAEMON UP" in _runs(graded, "daemon")[0]["debug"]  # it did start, outside its run
    assert graded["daemon_survivors"] == []  # and was gone by the time the grader returned
    assert "PLANTED BY A DAEMON" not in graded["csv"]
    assert "PLANTED" not in graded["spec"].read_text(encoding="utf-8")


def test_signals_from_a_student_reach_no_one(graded: dict[str, Any]) -> None:
    assert graded["report"] is not None
    runs = _runs(graded, "killer")
    assert {r["status"] for r in runs} <= {"passed", "failed", "crashed"}, _shown(runs)


def test_a_signal_a_program_of_the_run_sends_it_is_the_students_own(
    graded: dict[str, Any],
) -> None:
    # Told from a teacher's kill by who sent it: a process of the run, under a user (or in a
    # PID namespace) that is the run's alone.
    runs = _runs(graded, "signaller")
    assert [r["status"] for r in runs] == ["invalid", "invalid"], _shown(runs)
    for run in runs:
        assert run["message"] == (
            "the mission has an error: mission.py:4: error: sent its own process SIGTERM"
            " (through a program it started): a mission ends by going to a final state, not by"
            " sending itself a signal"
        ), _shown([run])


def test_no_fake_line_reaches_the_graders_output(graded: dict[str, Any]) -> None:
    # What the student printed is kept, inside its own run's JSON string; never as a line.
    for stream in (graded["stdout"], graded["stderr"]):
        assert not any(line.startswith("FAKE-LINE") for line in stream.splitlines())


def test_a_fork_bomb_memory_hog_and_disk_filler_fail_only_themselves(
    graded: dict[str, Any],
) -> None:
    for name in ("forker", "hog", "filler"):
        for run in _runs(graded, name):
            assert run["score"] < 1, name
    # Both fail while the mission loads: the student is told what the file did.
    runs = _runs(graded, "hog") + _runs(graded, "filler")
    assert [r["status"] for r in runs] == ["invalid"] * 4, _shown(runs)
    assert "MemoryError" in _runs(graded, "hog")[0]["message"]
    assert "File too large" in _runs(graded, "filler")[0]["message"]


def test_a_flood_of_output_is_cut_everywhere(graded: dict[str, Any]) -> None:
    runs = _runs(graded, "flooder")
    # It raises while loading: the student is told what the file did (cut), as for the hog.
    assert [r["status"] for r in runs] == ["invalid", "invalid"], _shown(runs)
    assert "RuntimeError: yyy" in runs[0]["message"]
    assert len(graded["stdout"]) < 2_000_000
    for run in runs:
        assert len(run["debug"]) < 200_000, _tail(run["debug"])
        assert len(run["message"]) < 5_000, run["message"][:3000]
    for page in Path(graded["html"]).rglob("*.html"):
        assert page.stat().st_size < 2_000_000


def test_every_finished_run_is_in_the_results_file(graded: dict[str, Any]) -> None:
    lines = graded["results"].read_text(encoding="utf-8").splitlines()[1:]  # after the header
    assert len(lines) == len(graded["report"]["runs"])
    assert max(len(line) for line in lines) < 200_000  # the flood is cut there too
    assert {json.loads(line)["student"] for line in lines} == {
        r["student"] for r in graded["report"]["runs"]
    }


def test_no_student_process_outlives_the_grader(graded: dict[str, Any]) -> None:
    markers = (b"roboscript.grading.mission_host", b"roboscript.grading.jail_server")
    alive = []
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            cmdline = Path(f"/proc/{pid}/cmdline").read_bytes()
            folder = os.readlink(f"/proc/{pid}/cwd")
        except OSError:
            continue
        if any(m in cmdline for m in markers) and folder.startswith(str(graded["class"])):
            alive.append(pid)
    assert alive == []


@functools.cache
def _isolation_for(mode: str) -> dict[str, str]:
    """The isolation (name, statement) a grader started with ``ROBOSCRIPT_ISOLATION=mode``
    has on this computer, asked of a fresh interpreter as ``roboscript grade`` would be."""
    code = "from roboscript.grading.sandbox import detect_isolation as d; import json;"
    code += " print(json.dumps({'name': d().name, 'statement': d().statement}))"
    done = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, ISOLATION_VARIABLE: mode},
    )
    return dict(json.loads(done.stdout))
