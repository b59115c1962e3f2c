"""A class folder built to break the grader, graded by the real ``roboscript grade``.

Honest students sit beside every hostile file a class has handed in: code the grader's own
process could choke on (a 20 000-term expression, a 1.7 GB sparse helper, a file that is not
UTF-8), links to a classmate's work, pipes and devices, a mission dropped beside a
classmate's with the same name, names made of escape sequences, newlines, formula text and
only non-Latin letters, invisible characters or a leading dash, a mission that tries to give a
hidden run's start away, ones that snoop on a classmate's helper and an earlier gradebook (one
of them named after it), and ones that exit with success just after the start, kill every
process they can reach or leave a thread spinning. The class is graded once, with every report
written; each test then checks one promise: every student gets exactly the verdict their own
work earns, and no report can be broken, forged or made to leak. It is graded once more beside
a spinner on every core, with the default hang limit: the verdicts must not change.

A second class (``ATTACKS``, below) is a table of attacks, one student each, in families: the
sentences the grader once got wrong (a student's own Ctrl-C, a wire the mission broke, copies
of its process, a flood), resource abuse, reading what is not its own, the wire, Python's own
machinery, report forgery, timing and names. Each row gives the verdict and the sentence the
student's own work earns; the class is graded once, and every report checked.
"""

from __future__ import annotations

import csv
import io
import json
import os
import re
import stat
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest
from helpers import FORWARD_50CM, FORWARD_50CM_EXPECT, HANG_BOUND_S, every_core_busy

from roboscript.grading.sandbox import detect_isolation
from roboscript.grading.text import clean_name, display_width

SPEC = """\
test: forward
world: empty
description: Drive 50 cm straight ahead from two starts; students do not see the first.
runs:
  - {seed: 2, start: {x: 313.7 mm, y: 123.4 mm, heading: 0 deg}, hidden: true}
  - {seed: 1}
"""
SPEC += FORWARD_50CM_EXPECT

HONEST = FORWARD_50CM

# Drives like HONEST, but where it starts 300 mm east of the world's start (only the hidden
# run) it prints and raises the start pose it read, hoping a report shows it to the student.
LEAKER = """\
import json, sys
from roboscript import Drive, Mission, state


def _start():
    with open(sys.argv[-1], encoding="utf-8") as handle:
        return json.load(handle)["start"]


class Forward(Mission):
    go = state(
        Drive(distance_mm=500, speed_mm_s=200),
        initial=True,
        on_done="finished",
        when=[("give_away", "finished")],
    )
    finished = state(final="success")

    def give_away(self):
        start = _start()
        if start[0] > 300:
            print(f"ValueError: LEAKED-PRINT {start}", file=sys.stderr)
            raise RuntimeError(f"LEAKED-START {start}")
        return False
"""

# Drives like HONEST unless it can read a classmate's helper or the earlier gradebook beside
# it, in which case it crashes with what it read.
SNOOP = """\
from roboscript import Drive, Mission, state

SEEN = []
for name in ("bea_helpers.py", "grades.csv"):
    try:
        with open(name, encoding="utf-8") as handle:
            SEEN.append(handle.read())
    except OSError:
        pass


class Forward(Mission):
    go = state(Drive(distance_mm=500, speed_mm_s=200), initial=True, on_done="finished",
               when=[("snooped", "finished")])
    finished = state(final="success")

    def snooped(self):
        if SEEN:
            raise RuntimeError("SNOOPED " + " ".join(SEEN))
        return False
"""
# A student named after the earlier reports beside them, who reads them by their own name.
GRADES_SNOOP = SNOOP.replace('"bea_helpers.py", "grades.csv"', '"grades.csv", "grades.jsonl"')

# Drives like HONEST, but does something else the first time its condition is asked.
ONCE = """\
import os, sys, threading
from roboscript import Drive, Mission, state


class Forward(Mission):
    go = state(Drive(distance_mm=500, speed_mm_s=200), initial=True, on_done="finished",
               when=[("first", "finished")])
    finished = state(final="success")

    def first(self):
        if not getattr(self, "asked", False):
            self.asked = True
            DO
        return False
"""
# sys.exit(0) just after the start, as if the mission had succeeded (called by another name:
# `roboscript check` refuses sys.exit() written in a condition)
EXITER = ONCE.replace("DO", 'getattr(sys, "exit")(0)')
# signals every process it can reach
KILLER = ONCE.replace("DO", "os.kill(-1, 9)")
# leaves a thread that never stops spinning, and drives on
SPINNER = ONCE.replace("DO", "threading.Thread(target=lambda: [0 for _ in iter(int, 1)]).start()")

# closes every descriptor it did not open (its wire to the world among them)
WIRE_CLOSER = ONCE.replace("DO", "os.closerange(3, 256)")
# writes a result of its own on every descriptor it did not open, hoping one is the wire
WIRE_FORGER = ONCE.replace("DO", "_forge()").replace(
    "class Forward",
    "def _forge():\n"
    "    for fd in range(3, 64):\n"
    "        try:\n"
    '            os.write(fd, b\'F{"outcome": "success", "final_state": "finished"}\')\n'
    "        except OSError:\n"
    "            pass\n\n\nclass Forward",
)
# raises a class of its own derived from BaseException (beyond `except Exception`)
GONE = ONCE.replace("DO", "raise Gone('bye')").replace(
    "class Forward", "class Gone(BaseException):\n    pass\n\n\nclass Forward"
)
# the same, while its file is loaded
GONE_AT_LOAD = "class Gone(BaseException):\n    pass\n\n\nraise Gone('at load')\n"
# sends itself SIGTERM while its file is loaded (line 3)
SIGTERM_AT_LOAD = "import os, signal\n\nos.kill(os.getpid(), signal.SIGTERM)\n"

IDLE = """\
from roboscript import Mission, Wait, state


class Idle(Mission):
    go = state(Wait(duration_s=0.5), initial=True, on_done="end")
    end = state(final="success")
"""

# Enters a new state with a 180-character name every few ticks, for the whole run.
MANY_STATES = """\
from roboscript import Mission, Wait, state

_PAD = "x" * 180
_states = {"end": state(final="success")}
for _i in range(5000):
    _next = f"s{_i + 1}_{_PAD}" if _i < 4999 else "end"
    _states[f"s{_i}_{_PAD}"] = state(Wait(duration_s=0.01), initial=_i == 0, on_done=_next)


class Many(Mission):
    locals().update(_states)
"""

DEEP = "X = " + "+".join(["1"] * 20_000) + "\n\n" + IDLE

ESCAPES = "\x1b]0;pwned\x07\x1b[2J\x01esc"
FORGER = "nl\nforged  forward  ✓ 2 of 2  100%"
FORMULA = "x;=2+5;"
NON_LATIN = ("Анна", "王芳")
# The honest students as every report names them: control characters show as "�".
DASHED = "--help"
HONEST_NAMES = ["ada", "bea", "c01_ana.yaml", "snoop", "grades", "leaker", FORMULA, *NON_LATIN]
HONEST_NAMES += [DASHED, "spinner"]
HONEST_NAMES += ["�]0;pwned��[2J�esc", "nl�forged  forward  ✓ 2 of 2  100%"]
AS_ROOT = os.geteuid() == 0
ISOLATED = detect_isolation().complete


def _write(path: Path, text: str | bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")


def _nest(top: Path, name: str, depth: int) -> None:
    """``depth`` folders called ``name``, each in the one before, under ``top`` (made through
    descriptors: their path is longer than the system opens)."""
    fd = os.open(top, os.O_RDONLY)
    try:
        for _ in range(depth):
            os.mkdir(name, dir_fd=fd)
            inner = os.open(name, os.O_RDONLY, dir_fd=fd)
            os.close(fd)
            fd = inner
    finally:
        os.close(fd)


def _hostile_class(subs: Path) -> None:
    """Build the class folder: honest students beside every hostile file."""
    _write(subs / "ada" / "forward.yaml", HONEST)
    _write(subs / "ada\u200b" / "forward.py", IDLE)  # looks like ada in a table, but fails
    _write(subs / "bea.yaml", HONEST)
    _write(subs / "bea_helpers.py", "CLASSMATE = 'BEA-SECRET'\n")
    _write(subs / "grades.csv", "student,score\nbea,SECRET-GRADES\n")
    _write(subs / "grades.jsonl", '{"student": "bea", "status": "SECRET-RESULTS"}\n')
    _write(subs / "grades.py", GRADES_SNOOP)
    _write(subs / "c01_ana.yaml", HONEST)
    _write(subs / "c01_ana.py", IDLE)  # dropped beside a classmate's mission
    _write(subs / "snoop.py", SNOOP)
    _write(subs / "exiter" / "forward.py", EXITER)
    _write(subs / "killer" / "forward.py", KILLER)
    _write(subs / "spinner" / "forward.py", SPINNER)
    _write(subs / "gone" / "forward.py", GONE)
    _write(subs / "wire_closer" / "forward.py", WIRE_CLOSER)
    _write(subs / "nested" / "forward.yaml", HONEST)
    _nest(subs / "nested", "folder-in-a-folder-", 300)  # 6000 characters: past PATH_MAX
    _write(subs / "wire_forger" / "forward.py", WIRE_FORGER)
    _write(subs / "gone_at_load" / "forward.py", GONE_AT_LOAD + IDLE)
    _write(subs / "sigterm" / "forward.py", SIGTERM_AT_LOAD + IDLE)
    _write(subs / "leaker" / "forward.py", LEAKER)
    _write(subs / "deep" / "mission.py", DEEP)
    _write(subs / "many" / "mission.py", MANY_STATES)
    _write(subs / "deep_helper.py", "X = " + "+".join(["1"] * 20_000) + "\n")
    _write(subs / "huge" / "forward.yaml", HONEST)
    with open(subs / "huge" / "helper.py", "wb") as handle:  # 1.7 GB, sparse
        handle.truncate(1_700_000_000)
    _write(subs / "latin" / "mission.py", IDLE.replace("Idle", "Idlé").encode("latin-1"))
    _write(subs / "typo.yaml", HONEST.replace("do: {drive:", "do: {drvie:"))
    (subs / "linker").mkdir()
    os.symlink(subs / "ada" / "forward.yaml", subs / "linker" / "forward.yaml")
    os.symlink(subs / "ada", subs / "dave")
    os.symlink("bea.yaml", subs / "carl.yaml")
    _write(subs / "piper" / "forward.yaml", HONEST)
    os.mkfifo(subs / "piper" / "pipe.py")
    os.mkfifo(subs / "eve.py")
    _write(subs / "fifi" / "forward.yaml", HONEST)
    os.mkfifo(subs / "fifi" / "\x1b[2Jline\nforged  forward  ✓ 2 of 2.py")  # a name of many lines
    if AS_ROOT:
        _write(subs / "devin" / "forward.yaml", HONEST)
        os.mknod(subs / "devin" / "null.py", stat.S_IFCHR | 0o666, os.makedev(1, 3))
    if AS_ROOT and ISOLATED:  # root reads it, a jail's user of its own could not
        _write(subs / "locked" / "forward.yaml", HONEST)
        _write(subs / "locked" / "helper.py", "X = 1\n")
        (subs / "locked" / "helper.py").chmod(0)
    undecodable = os.fsencode(subs) + b"/\xffbad"  # a folder name that is not UTF-8
    os.mkdir(undecodable)
    with open(undecodable + b"/forward.yaml", "w", encoding="utf-8") as handle:
        handle.write(HONEST)
    for name in (ESCAPES, FORGER, FORMULA, DASHED, *NON_LATIN):
        _write(subs / name / "forward.yaml", HONEST)


@pytest.fixture(scope="module")
def graded(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """The class, graded once by the real command line, with every report written."""
    root = tmp_path_factory.mktemp("hostile")
    spec = root / "teacher" / "forward.yaml"
    _write(spec, SPEC)
    subs = root / "class"
    _hostile_class(subs)
    out = root / "out"
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(subs),
        "--jobs", "2", "--hang-after", "30",
        "--junit", str(out / "junit.xml"), "--csv", str(out / "grades.csv"),
        "--html", str(out / "html"), "--results", str(out / "results.jsonl"),
    ]  # fmt: skip
    out.mkdir()
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
    )
    lines = (out / "results.jsonl").read_text().splitlines()
    runs = [json.loads(line) for line in lines[1:]]  # line 1 is the file's header
    return {
        "root": root,
        "exit": done.returncode,
        "stdout": done.stdout,
        "stderr": done.stderr,
        "runs": runs,
        "junit": (out / "junit.xml").read_text(encoding="utf-8"),
        "csv": (out / "grades.csv").read_text(encoding="utf-8-sig"),
        "html": out / "html",
    }


def _statuses(graded: dict[str, Any]) -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    for run in sorted(graded["runs"], key=lambda r: r["variant"]):
        found.setdefault(run["student"], []).append(run["status"])
    return found


def _messages(graded: dict[str, Any], student: str) -> list[str]:
    return [r["message"] for r in graded["runs"] if r["student"] == student]


def _student_facing(graded: dict[str, Any]) -> dict[str, str]:
    """Every text a student may read: the table, progress, JUnit, and the students' pages."""
    progress = [line for line in graded["stderr"].splitlines() if line.startswith("[")]
    texts = {"table": graded["stdout"], "progress": "\n".join(progress), "junit": graded["junit"]}
    for page in sorted((graded["html"] / "students").glob("*.html")):
        texts[page.name] = page.read_text(encoding="utf-8")
    return texts


def test_the_whole_class_is_graded_and_every_report_written(graded: dict[str, Any]) -> None:
    assert graded["exit"] == 1, graded["stderr"][-3000:]  # some failed: exit 1, no crash
    assert "Traceback" not in graded["stderr"]
    hostile = ["c01_ana.py", "deep", "many", "huge", "latin", "typo", "linker", "dave", "carl"]
    hostile += ["ada�", "exiter", "killer", "gone", "gone_at_load", "sigterm"]
    hostile += ["wire_closer", "wire_forger", "nested", "fifi"]
    hostile += ["piper", "eve", "�bad"] + (["devin"] if AS_ROOT else [])
    hostile += ["locked"] if AS_ROOT and ISOLATED else []
    assert sorted(_statuses(graded)) == sorted(HONEST_NAMES + hostile)
    assert all(len(statuses) == 2 for statuses in _statuses(graded).values())
    assert (graded["html"] / "index.html").is_file()


def test_honest_students_pass_beside_every_hostile_file(graded: dict[str, Any]) -> None:
    statuses = _statuses(graded)
    for name in HONEST_NAMES:
        expected = ["crashed", "passed"] if name == "leaker" else ["passed", "passed"]
        assert statuses[name] == expected, (name, _messages(graded, name))


def test_a_name_that_looks_like_a_classmates_is_told_apart_everywhere(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    assert statuses["ada"] == ["passed", "passed"]
    assert statuses["ada�"] == ["failed", "failed"]
    rows = [line.split()[0] for line in graded["stdout"].splitlines() if " forward " in line]
    assert rows.count("ada") == 1 and rows.count("ada�") == 1
    assert "\u200b" not in graded["stdout"] + graded["csv"] + graded["junit"]


def test_a_mission_beside_a_classmates_with_the_same_name_is_graded_as_what_it_is(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    assert statuses["c01_ana.yaml"] == ["passed", "passed"]  # never "missing"
    assert statuses["c01_ana.py"] == ["failed", "failed"]  # the idle mission, judged


def test_code_that_ends_or_kills_its_own_run_crashes_that_run_only(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    assert statuses["exiter"] == ["crashed", "crashed"]  # never taken for a success
    assert "called exit() in state 'go'" in _messages(graded, "exiter")[1]
    assert statuses["killer"] == ["crashed", "crashed"]
    assert statuses["spinner"] == ["passed", "passed"]  # its thread ends with its run


def test_code_that_closes_or_writes_on_the_wire_itself_crashes_its_own_run_saying_so(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    assert statuses["wire_closer"] == ["crashed", "crashed"]
    for message in _messages(graded, "wire_closer"):
        assert "broke its own connection to the simulated robot" in message, message
        assert "exit()" not in message
    assert statuses["wire_forger"] == ["crashed", "crashed"]  # never a success of its own
    assert "it broke the grading wire" in _messages(graded, "wire_forger")[1]


def test_a_students_own_base_exception_is_their_error_not_an_unexplained_exit(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    assert statuses["gone"] == ["crashed", "crashed"]
    assert "your condition 'first' raised Gone in state 'go'" in _messages(graded, "gone")[1]
    assert statuses["gone_at_load"] == ["invalid", "invalid"]
    assert "forward.py:5:1: error: Gone: at load" in _messages(graded, "gone_at_load")[1]


def test_a_signal_the_mission_sends_itself_while_it_loads_is_its_error_at_its_line(
    graded: dict[str, Any],
) -> None:
    # Its own SIGTERM, not "something asked roboscript to end": no one else sends a graded run
    # one, so it is the student's mistake, at the line that sent it.
    statuses = _statuses(graded)
    assert statuses["sigterm"] == ["invalid", "invalid"]
    sentence = (
        "forward.py:3: error: sent its own process SIGTERM: a mission ends by going to a final"
        " state, not by sending itself a signal"
    )
    for run in (r for r in graded["runs"] if r["student"] == "sigterm"):
        assert run["message"] == f"the mission has an error: {sentence}"
        assert "Traceback" not in run["debug"]  # the teacher's field: the sentence alone


def test_the_class_grades_the_same_on_a_saturated_machine(
    graded: dict[str, Any], tmp_path: Path
) -> None:
    # Bounded, not timed: the same class beside a spinner on every core and one more, with
    # the default --hang-after, gets exactly the verdicts it got above.
    subs = tmp_path / "class"
    _hostile_class(subs)
    results = tmp_path / "results.jsonl"
    spec = graded["root"] / "teacher" / "forward.yaml"
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(subs),
        "--jobs", "2", "--results", str(results), "--quiet",
    ]  # fmt: skip
    with every_core_busy(extra=1):
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
        )
    assert done.returncode == 1, done.stderr[-3000:]
    runs = [json.loads(line) for line in results.read_text().splitlines()[1:]]
    assert _statuses({"runs": runs}) == _statuses(graded), [
        (run["student"], run["status"], run["message"][:200]) for run in runs
    ]


def test_code_the_grader_could_choke_on_is_that_students_result(graded: dict[str, Any]) -> None:
    statuses = _statuses(graded)
    huge = _messages(graded, "huge")
    assert statuses["huge"] == ["invalid", "invalid"]
    assert huge[0].startswith("helper.py cannot be graded: the file is 1700000000 bytes")
    assert statuses["latin"] == ["invalid", "invalid"]
    assert _messages(graded, "latin")[0].startswith("mission.py:4 cannot be graded: byte 0xE9")
    # The 20 000-term expression is compiled in the student's own jail, never by the grader.
    assert statuses["deep"] == ["invalid", "invalid"]
    assert "mission.py: error: RecursionError" in _messages(graded, "deep")[0]
    assert "deep_helper" not in _statuses(graded)  # a helper is no student


def test_a_refused_files_name_is_shown_on_one_line_in_every_report(
    graded: dict[str, Any],
) -> None:
    assert _statuses(graded)["fifi"] == ["invalid", "invalid"]
    wanted = "�[2Jline�forged  forward  ✓ 2 of 2.py is a named pipe, not an ordinary file"
    for message in _messages(graded, "fifi"):  # the results file: what every report reads
        assert message.startswith(wanted), message
    for name, text in _student_facing(graded).items():
        assert "\x1b[2J" not in text and "\nforged  forward" not in text, name


def test_folders_nested_past_what_the_system_opens_are_refused_in_a_sentence_that_fits(
    graded: dict[str, Any],
) -> None:
    assert _statuses(graded)["nested"] == ["invalid", "invalid"]
    message = _messages(graded, "nested")[1]
    assert message.startswith("the folder nests folders more than 32 deep (folder-in-a-folder-/")
    assert message.endswith("): hand in the mission and its own files only")
    assert len(message) < 300  # the reason is read, not cut off after a path


def test_links_pipes_devices_and_undecodable_names_are_refused_with_the_reason(
    graded: dict[str, Any],
) -> None:
    statuses = _statuses(graded)
    expected = {
        "linker": "forward.yaml is a symbolic link",
        "dave": "dave is a symbolic link",
        "carl": "carl.yaml is a symbolic link",
        "piper": "pipe.py is a named pipe, not an ordinary file",
        "eve": "eve.py is a named pipe, not an ordinary file",
        "�bad": "�bad has a name that is not UTF-8 text: rename it",
    }
    if AS_ROOT:
        expected["devin"] = "null.py is a device, not an ordinary file"
    for student, reason in expected.items():
        assert statuses[student] == ["invalid", "invalid"], student
        assert _messages(graded, student)[0].startswith(reason), _messages(graded, student)


@pytest.mark.skipif(not (AS_ROOT and ISOLATED), reason="a jail's own user: root with bubblewrap")
def test_a_file_no_other_user_may_read_is_that_students_setup_problem_said_before_any_run(
    graded: dict[str, Any],
) -> None:
    assert _statuses(graded)["locked"] == ["invalid", "invalid"]
    for message in _messages(graded, "locked"):
        assert "helper.py is not readable by other users (mode 0)" in message
        assert "chmod -R o+rX" in message
        assert str(graded["root"]) not in message


def test_no_student_facing_text_holds_a_folder_of_the_teachers(graded: dict[str, Any]) -> None:
    assert _messages(graded, "typo")[0].startswith("the mission has an error: typo.yaml:5:")
    for where, text in _student_facing(graded).items():
        assert str(graded["root"]) not in text, where


def test_a_hidden_run_shows_nothing_the_mission_printed_or_raised(graded: dict[str, Any]) -> None:
    teacher = _messages(graded, "leaker")[0]
    assert "LEAKED-START [313.7, 123.4" in teacher  # the attempt was made, and kept for you
    for where, text in _student_facing(graded).items():
        assert "LEAKED" not in text and "313.7" not in text, where
    assert "LEAKED" not in graded["csv"]


@pytest.mark.skipif(not ISOLATED, reason="needs bubblewrap's full isolation")
def test_a_student_in_a_shared_folder_reads_no_classmates_file(graded: dict[str, Any]) -> None:
    assert _statuses(graded)["snoop"] == ["passed", "passed"], _messages(graded, "snoop")


@pytest.mark.skipif(not ISOLATED, reason="needs bubblewrap's full isolation")
def test_a_student_named_after_an_earlier_report_cannot_read_it(graded: dict[str, Any]) -> None:
    assert _statuses(graded)["grades"] == ["passed", "passed"], _messages(graded, "grades")


def test_no_name_moves_the_terminal_or_forges_a_table_row(graded: dict[str, Any]) -> None:
    for stream in (graded["stdout"], graded["stderr"]):
        assert not re.search("[\x00-\x08\x0b-\x1f\x7f-\x9f]", stream)
        assert not any(line.startswith("forged") for line in stream.splitlines())


def test_the_tables_columns_line_up_in_a_terminal_whatever_the_names(
    graded: dict[str, Any],
) -> None:
    # A Chinese name takes two columns a character, an accent none: each row's test column
    # starts at the same column of the terminal, the header's included.
    lines = graded["stdout"].splitlines()
    columns = {display_width(lines[0][: lines[0].index("  test  ")])}
    for line in lines[1:]:
        found = re.search("  forward  [✓✗] [0-9]+/[0-9]+", line)
        if found is not None:
            columns.add(display_width(line[: found.start()]))
    assert len(columns) == 1, columns


def test_junit_stays_well_formed_xml(graded: dict[str, Any]) -> None:
    cases = ET.fromstring(graded["junit"]).iter("testcase")
    names = {case.get("classname") for case in cases}
    assert "forward.�]0;pwned��[2J�esc" in names


def test_a_name_a_spreadsheet_would_split_into_a_formula_is_defused(
    graded: dict[str, Any],
) -> None:
    rows = list(csv.reader(io.StringIO(graded["csv"])))
    names = [row[0] for row in rows[1:]]
    assert "x;'=2+5;" in names
    for separator in ",;\t|":
        for row in rows:
            for cell in row:
                for part in [*cell.split(separator)[1:], cell]:
                    assert not part.lstrip(" \t").startswith(("=", "+", "@")), cell


def test_every_student_and_run_has_a_page_of_its_own(graded: dict[str, Any]) -> None:
    html = graded["html"]
    pages = sorted((html / "runs").glob("*.html"))
    assert len(pages) == len(graded["runs"])
    index = (html / "index.html").read_text(encoding="utf-8")
    for name in NON_LATIN:
        row = next(line for line in index.split("<tr>") if f">{name}</th>" in line)
        for link in re.findall(r'href="(runs/[^"]+)"', row):
            assert f"{name} — forward" in (html / link).read_text(encoding="utf-8")
    student_pages = sorted((html / "students").glob("*.html"))
    assert len(student_pages) == len(_statuses(graded))
    # no page a teacher zips or copies with a shell's * is read as an option
    assert not [page.name for page in [*pages, *student_pages] if page.name.startswith("-")]
    assert (html / "students" / "help.html").is_file()


def test_a_students_page_stays_small_whatever_the_mission_did(graded: dict[str, Any]) -> None:
    assert _statuses(graded)["many"] == ["failed", "failed"]
    many = (graded["html"] / "students" / "many.html").read_text(encoding="utf-8")
    assert "too many to draw them or replay the run here" in many
    for page in (graded["html"] / "students").glob("*.html"):
        assert page.stat().st_size < 1_500_000, page.name  # two runs each, 600 kB at most


def test_gradescope_results_hold_no_hidden_detail_and_no_teacher_folder(tmp_path: Path) -> None:
    spec = tmp_path / "tests" / "forward.yaml"
    _write(spec, SPEC)
    submission = tmp_path / "submission"
    _write(submission / "forward.py", LEAKER)
    results = tmp_path / "results" / "results.json"
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(submission),
        "--hang-after", "30", "--gradescope", str(results),
    ]  # fmt: skip
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
    )
    text = results.read_text(encoding="utf-8")
    tests = json.loads(text)["tests"]
    assert [t["status"] for t in tests] == ["failed", "passed"], done.stderr[-2000:]
    assert tests[0]["output"].splitlines()[1] == "the run crashed (a hidden run does not show why)"
    assert "LEAKED" not in text and "313.7" not in text
    assert str(tmp_path) not in text
    # A folder laid out wrongly: the student reads why, and no folder of the teacher's.
    empty = tmp_path / "empty"
    empty.mkdir()
    command[command.index(str(submission))] = str(empty)
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
    )
    assert done.returncode == 2
    text = results.read_text(encoding="utf-8")
    assert "no mission files in the folder empty" in text
    assert str(tmp_path) not in text


def test_a_glob_through_a_link_to_a_classmates_folder_is_refused(tmp_path: Path) -> None:
    spec = tmp_path / "forward.yaml"
    _write(spec, "test: forward\nworld: empty\n" + FORWARD_50CM_EXPECT)
    subs = tmp_path / "class"
    _write(subs / "ada" / "forward.yaml", HONEST)
    _write(subs / "ada\u200b" / "forward.py", IDLE)  # looks like ada in a table, but fails
    os.symlink(subs / "ada", subs / "dave")
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec),
        "--mission", str(subs / "*" / "forward.yaml"), "--hang-after", "30", "--json",
    ]  # fmt: skip
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
    )
    runs = {r["student"]: r for r in json.loads(done.stdout)["runs"]}
    assert runs["ada"]["status"] == "passed", done.stderr[-2000:]
    assert runs["dave"]["status"] == "invalid"
    assert runs["dave"]["message"].startswith("dave is a symbolic link")


def test_a_submission_changed_while_its_class_is_graded_is_not_counted_from_then_on(
    tmp_path: Path,
) -> None:
    # A late push or a sync rewrites a student's file between two of their runs: the runs
    # after it might have read another version, so each says so instead of counting.
    from roboscript.grading.batch import find_specs, grade_class
    from roboscript.grading.record import RunResult
    from roboscript.grading.submissions import find_submissions

    spec = tmp_path / "forward.yaml"
    _write(spec, SPEC)
    subs = tmp_path / "class"
    _write(subs / "ada" / "forward.yaml", HONEST)
    _write(subs / "bea" / "forward.yaml", HONEST)
    seen: list[RunResult] = []

    def rewrite_once(result: RunResult) -> None:
        seen.append(result)
        if result.student == "ada" and len([r for r in seen if r.student == "ada"]) == 1:
            _write(subs / "ada" / "forward.yaml", HONEST + "# pushed late\n")

    report = grade_class(
        find_specs([str(spec)]),
        find_submissions([str(subs)]).submissions,
        jobs=1,
        on_result=rewrite_once,
    )
    ada = [r for r in report.results if r.student == "ada"]
    assert sorted(r.status for r in ada) == ["invalid", "passed"]
    (late,) = [r for r in ada if r.status == "invalid"]
    assert late.message == (
        "forward.yaml changed while the class was being graded (added, removed or rewritten"
        " after grading began): this run may have read another version of the mission than"
        " the others, so it is not counted; grade the student again"
    )
    assert [r.status for r in report.results if r.student == "bea"] == ["passed", "passed"]


def test_a_hard_link_to_the_test_spec_in_a_submission_is_refused(tmp_path: Path) -> None:
    # The spec under another name in a student's folder: their run could read the hidden
    # runs' seeds and starts. Refused, naming both; the class is graded all the same.
    spec = tmp_path / "teacher" / "forward.yaml"
    _write(spec, SPEC)
    subs = tmp_path / "class"
    _write(subs / "ada" / "forward.yaml", HONEST)
    _write(subs / "eve" / "forward.yaml", HONEST)
    os.link(spec, subs / "eve" / "notes.yaml")
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(subs), "--json",
    ]  # fmt: skip
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False
    )
    runs = json.loads(done.stdout)["runs"]
    assert {(r["student"], r["status"]) for r in runs} == {("ada", "passed"), ("eve", "invalid")}
    for run in (r for r in runs if r["student"] == "eve"):
        assert run["message"].endswith(
            "notes.yaml is the same file as the test forward.yaml (a hard link, not a copy): a"
            " submission holds its own files, never the teacher's"
        ), run["message"]


# --------------------------------------------------------------------------- a second class
#
# Round two: a class of students who each try one attack, in families (the sentences the grader
# once got wrong, resource abuse, reading what is not theirs, the wire, Python's own machinery,
# report forgery, timing, names), beside honest classmates. It is graded once through
# `roboscript grade`, with every report written and a secret in the grader's environment.
# ATTACKS is the record: what each student did, the status each run must get (the hidden run
# first), and a part of the sentence it must say (None: no sentence, the run passed or the
# sentence does not matter).

_ROUND = """\
import os, signal, socket, stat, sys, threading, time
from roboscript import Drive, Mission, state


class Forward(Mission):
    go = state(Drive(distance_mm=MM, speed_mm_s=200), initial=True, on_done="finished",
               when=[("first", "finished")])
    finished = state(final="success")

    def first(self):
        if not getattr(self, "asked", False):
            self.asked = True
            DO  # the attack
        return False


PRE
"""
_ATTACK_LINE = _ROUND.splitlines().index("            DO  # the attack") + 1
_PRE_LINE = len(_ROUND.splitlines())  # the first line of PRE, the file's top-level code

_WIRES = '''
def wires():
    """The mission process's sockets: its wire to the world among them."""
    found = []
    for fd in range(3, 64):
        try:
            if stat.S_ISSOCK(os.fstat(fd).st_mode):
                found.append(fd)
        except OSError:
            pass
    return found


def flood():
    for fd in wires():
        for _ in range(40):
            os.write(fd, b"Y\\0\\0\\0\\0" * 100_000)
    time.sleep(600)


KEEP = []
'''

_LIFT = """
def lift():
    import resource
    for limit in (resource.RLIMIT_AS, resource.RLIMIT_NPROC, resource.RLIMIT_CPU):
        try:
            resource.setrlimit(limit, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
        except (ValueError, OSError):
            pass
"""

_NICE = """
def be_nice():
    os.nice(19)
    try:
        os.nice(-40)
    except OSError:
        pass
"""

_CHANNEL = """
def channel():
    from roboscript.transport.lockstep import _CHANNELS
    return next(iter(_CHANNELS.values()))
"""

_SECRET_ENV = "ROBOSCRIPT_TEST_TEACHER_SECRET"
_SECRET = "TEACHER-ONLY-7f3a"  # in the grader's environment; no student may read it

_PEEK = """
def peek():
    import glob
    paths = ["/proc/1/environ", f"/proc/{os.getppid()}/environ", "/proc/self/environ",
             "../bea.yaml", "../bea_helpers.py", "../../teacher/forward.yaml"]
    for pattern in ("/proc/*/cmdline", "/proc/*/environ", "/proc/self/fd/*", "/tmp/*"):
        paths += glob.glob(pattern)
    seen = [repr(dict(os.environ)).encode()]
    for path in paths:
        try:
            with open(path, "rb") as handle:
                seen.append(handle.read(1_000_000))
        except OSError:
            pass
    blob = b"".join(seen)
    # built from parts, so that reading this file is not a find
    for secret in ("TEACHER" + "-ONLY-7f3a", "BEA" + "-SECRET", "test: " + "forward"):
        if secret.encode() in blob:
            raise RuntimeError("SNOOPED " + secret)
"""

_LINKS = """
def links():
    for target in ("../bea.yaml", "/proc/1/cwd", "/proc/self/cwd/../bea_helpers.py"):
        for make in (os.symlink, os.link):
            try:
                make(target, f"/tmp/{make.__name__}-{len(target)}")
            except OSError:
                pass
    peek()
"""

_WORLD_OBJECTS = """
def world_objects():
    import gc
    gc.unfreeze()
    kinds = {"Simulation", "_WorldSession", "WorldRun", "TestSpec", "RunRecord", "Verdict"}
    found = sorted({type(o).__name__ for o in gc.get_objects()} & kinds)
    if found:
        raise RuntimeError(f"THE WORLD IS HERE {found}")
"""


def _attack(do: str = "pass", pre: str = "", mm: int = 500) -> str:
    code = _ROUND.replace("PRE", pre.strip("\n")).replace("DO", do).replace("MM", str(mm))
    return code


_NO_CTRL_C = "no one presses Ctrl-C in a graded run; a mission ends by going to a final state"
_NO_SIGNAL = "a mission ends by going to a final state, not by sending itself a signal"
_BROKE = (
    "the run crashed: the mission's process broke its own connection to the simulated robot:"
    " its code closed or changed a connection it did not open"
)
_HONEST_FILES = {"forward.yaml": HONEST}
_LIMITS = "a graded mission's recursion limit is between 250 and 10000"
_ALARM = (
    "the watchdog that stops code that never returns uses SIGALRM and the real-time timer"
    " (signal.alarm, signal.setitimer(signal.ITIMER_REAL)): a graded mission may not change,"
    " ignore or block them"
)
_SPIN = "def spin():\n    while True:\n        pass"
_STR_RAISED = "its __str__ raised ZeroDivisionError"
_ONE_PROCESS = "a graded mission runs in one process: os.fork() would copy it"
_AT = f"(forward.py:{_ATTACK_LINE})"
_STOPPED_IN_FIRST = (
    f"the mission's code did not return for 2 s and was stopped at forward.py:{_ATTACK_LINE}"
    " in first:"
)
_FAILED, _PASSED = ("failed", "failed"), ("passed", "passed")
_CRASHED, _INVALID, _HUNG = ("crashed", "crashed"), ("invalid", "invalid"), ("hung", "hung")

ATTACKS: list[tuple[str, str, str | dict[str, str], tuple[str, str], str | None]] = [
    # (family, student, the mission (or files), statuses: hidden run then visible, sentence)
    # -- sentences once wrong: the student's own Ctrl-C, a wire it broke, copies of itself
    ("sentence", "ctrl_c", _attack("raise KeyboardInterrupt"), _CRASHED,
     f"the run crashed: your code raised KeyboardInterrupt in state 'go': {_NO_CTRL_C} {_AT}"),
    ("sentence", "sigint", _attack("signal.raise_signal(signal.SIGINT)"), _CRASHED,
     f"your code sent its own process SIGINT (Ctrl-C's signal) in state 'go': {_NO_CTRL_C} {_AT}"),
    ("sentence", "interrupt_main", _attack("import _thread; _thread.interrupt_main()"), _CRASHED,
     "your code sent its own process SIGINT (Ctrl-C's signal) in state 'go'"),
    ("sentence", "ctrl_c_at_load", _attack(pre="raise KeyboardInterrupt"), _INVALID,
     f"forward.py:{_PRE_LINE}: error: raised KeyboardInterrupt: {_NO_CTRL_C}"),
    # its own SIGTERM, SIGHUP or any signal it sends itself: its crash at its line
    ("sentence", "sigterm_self", _attack("os.kill(os.getpid(), signal.SIGTERM)"), _CRASHED,
     f"the run crashed: your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sighup_group", _attack("os.killpg(0, signal.SIGHUP)"), _CRASHED,
     f"your code sent its own process SIGHUP in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sigterm_group", _attack("os.kill(0, signal.SIGTERM)"), _CRASHED,
     f"your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sigusr1", _attack("signal.raise_signal(signal.SIGUSR1)"), _CRASHED,
     f"your code sent its own process SIGUSR1 in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sigquit_thread", _attack(
        "signal.pthread_kill(threading.main_thread().ident, signal.SIGQUIT)"), _CRASHED,
     f"your code sent its own process SIGQUIT in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sigterm_posix", _attack("import posix; posix.kill(os.getpid(), 15)"), _CRASHED,
     f"your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sighup_at_load", _attack(pre="signal.raise_signal(signal.SIGHUP)"), _INVALID,
     f"forward.py:{_PRE_LINE}: error: sent its own process SIGHUP: {_NO_SIGNAL}"),
    # ... sent around os.kill (a program it started, ctypes): its own all the same, told from
    # a teacher's kill by who sent it
    ("sentence", "sigterm_program", _attack(
        "import subprocess; subprocess.run(['kill', '-TERM', str(os.getpid())])"), _CRASHED,
     ("the run crashed: your code sent its own process SIGTERM (through a program it"
      f" started) in state 'go': {_NO_SIGNAL} {_AT}")),
    ("sentence", "sighup_program", _attack(
        "import subprocess; subprocess.run(['sh', '-c', 'kill -HUP $PPID'])"), _CRASHED,
     "your code sent its own process SIGHUP (through a program it started) in state 'go'"),
    ("sentence", "sigterm_ctypes", _attack(
        "import ctypes; ctypes.CDLL(None).kill(os.getpid(), signal.SIGTERM)"), _CRASHED,
     f"your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL}"),
    ("sentence", "sigterm_interrupt_main", _attack(
        "import _thread; _thread.interrupt_main(signal.SIGTERM)"), _CRASHED,
     f"your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL} {_AT}"),
    ("sentence", "sigterm_unblocked", _attack(
        "signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGTERM}); import ctypes;"
        " ctypes.CDLL(None).kill(os.getpid(), signal.SIGTERM)"), _CRASHED,
     f"your code sent its own process SIGTERM in state 'go': {_NO_SIGNAL}"),
    ("sentence", "nonblocking", _attack(
        "[os.set_blocking(fd, False) for fd in wires()]", _WIRES), _CRASHED, _BROKE),
    ("sentence", "shutdown", _attack(
        "[socket.socket(fileno=os.dup(fd)).shutdown(socket.SHUT_RD) for fd in wires()]", _WIRES),
     _CRASHED, _BROKE),
    ("sentence", "timeout", _attack(
        "[KEEP.append(socket.socket(fileno=os.dup(fd))) or KEEP[-1].settimeout(1e-4)"
        " for fd in wires()]", _WIRES), _CRASHED, _BROKE),
    ("sentence", "dup2", _attack("[os.dup2(0, fd) for fd in wires()]", _WIRES), _CRASHED, _BROKE),
    ("sentence", "close_and_go_on", _attack(
        "os.closerange(3, 64); [time.sleep(0.01) for _ in iter(int, 1)]"), _CRASHED, _BROKE),
    ("sentence", "fork_bomb", _attack("[os.fork() for _ in iter(int, 1)]"), _CRASHED,
     f"your condition 'first' raised PermissionError in state 'go': [Errno 1] {_ONE_PROCESS}"),
    ("sentence", "fork_at_load", _attack(pre="for _ in range(6):\n    os.fork()"), _INVALID,
     f"forward.py:{_PRE_LINE + 1}:5: error: PermissionError: [Errno 1] {_ONE_PROCESS}"),
    # a copy made around os.fork is cut off before its first byte: the run is the mission's
    ("sentence", "fork_ctypes", _attack("import ctypes; ctypes.CDLL(None).fork()"), _PASSED, None),
    ("sentence", "flood_at_load", _attack(pre=_WIRES + "\nflood()"), _CRASHED,
     "the run was stopped: it stopped reading the robot's answers"),
    ("sentence", "flood", _attack("flood()", _WIRES), _CRASHED,
     "the run was stopped: it stopped reading the robot's answers"),
    # -- resource abuse
    ("resources", "memory", _attack("KEEP = bytearray(3 * 1024**3)"), _CRASHED,
     f"your condition 'first' raised MemoryError in state 'go' {_AT}"),
    ("resources", "lifts_limits", _attack("lift(); KEEP = bytearray(3 * 1024**3)", _LIFT),
     _CRASHED, "raised MemoryError"),
    ("resources", "threads", _attack(
        "exec('try:\\n    while True:\\n        threading.Thread(target=time.sleep, args=(600,),"
        " daemon=True).start()\\nexcept RuntimeError:\\n    pass')"), _PASSED, None),
    ("resources", "descriptors", _attack(
        "exec('try:\\n    while True:\\n        KEEP.append(open(\"/dev/null\"))\\n"
        "except OSError:\\n    pass')", _WIRES), _PASSED, None),
    ("resources", "tmp_filler", _attack(
        "exec('try:\\n    with open(\"/tmp/fill\", \"wb\") as f:\\n        while True:\\n"
        "            f.write(bytes(1 << 20))\\nexcept OSError:\\n    pass')"), _PASSED, None),
    ("resources", "huge_print", _attack("print('x' * 5_000_000)"), _PASSED, None),
    ("resources", "recursion", _attack("again()", "def again():\n    return again()"), _CRASHED,
     "'again' calls itself again and again"),
    # its own SIGKILL or SIGSTOP, which no handler catches, ends the run at its line as well
    ("resources", "kill_self", _attack("os.kill(os.getpid(), signal.SIGKILL)"), _CRASHED,
     f"your code sent its own process SIGKILL in state 'go': {_NO_SIGNAL} {_AT}"),
    ("resources", "kill_group", _attack("os.killpg(0, signal.SIGKILL)"), _CRASHED,
     f"your code sent its own process SIGKILL in state 'go': {_NO_SIGNAL} {_AT}"),
    ("resources", "kill_parent", _attack("os.kill(os.getppid(), signal.SIGKILL)"), _CRASHED,
     "its process was killed by SIGKILL (its own code may have sent it"),
    ("resources", "stop_self", _attack("os.kill(os.getpid(), signal.SIGSTOP)"), _CRASHED,
     f"your code sent its own process SIGSTOP in state 'go': {_NO_SIGNAL} {_AT}"),
    ("resources", "stop_self_raw", _attack(
        "import ctypes; ctypes.CDLL(None).kill(os.getpid(), signal.SIGSTOP)"), _HUNG,
     "its process was paused by a stop signal (SIGSTOP)"),
    ("resources", "segfault", _attack("import ctypes; ctypes.string_at(0)"), _CRASHED,
     "its process was killed by SIGSEGV (Python itself crashed"),
    ("resources", "abort", _attack("os.abort()"), _CRASHED, "its process was killed by SIGABRT"),
    ("resources", "nofile_limit", _attack(
        "import resource; resource.setrlimit(resource.RLIMIT_NOFILE, (3, 3))"), _PASSED, None),
    ("resources", "nice", _attack("be_nice()", _NICE), _PASSED, None),
    ("resources", "affinity", _attack("os.sched_setaffinity(0, {0})"), _PASSED, None),
    ("resources", "ptrace", _attack(
        "import ctypes; print(ctypes.CDLL(None).ptrace(16, os.getppid(), 0, 0))"), _PASSED, None),
    # -- reading what is not its own: /proc, the environment, relative paths, links
    ("reading", "proc_reader", _attack("peek()", _PEEK), _PASSED, None),
    ("reading", "link_maker", _attack("links()", _PEEK + _LINKS), _PASSED, None),
    # -- the wire: bytes the device must refuse, claims, a clock of its own
    ("wire", "device_garbage", _attack(
        "channel().send(b'W', bytes(range(256)) * 8)", _CHANNEL), _FAILED, "drive failed"),
    ("wire", "early_finish", _attack(
        "channel().send(b'Q', b'finished');"
        " channel().send_json(b'F', {'outcome': 'success', 'final_state': 'finished'})",
        _CHANNEL, mm=5000), _FAILED, "final_pose_within failed by 45.0 cm"),
    ("wire", "state_claims", _attack(
        "[channel().send(b'Q', ('passed 100%' + chr(27) + '[2J<b>x' + 'x' * 5000).encode())"
        " for _ in range(3)]", _CHANNEL), _PASSED, None),
    ("wire", "clock_back", _attack(
        "channel().request(b'T', __import__('struct').pack('>d', -1.0))", _CHANNEL), _CRASHED,
     "the run was stopped: its clock went backwards"),
    ("wire", "clock_jump", _attack(
        "channel().request(b'T', __import__('struct').pack('>d', 1e9))", _CHANNEL), _FAILED,
     "the mission did not finish within 20 s"),
    # -- Python's own machinery
    ("python", "builtins", _attack(
        "import builtins; builtins.open = builtins.print = builtins.__import__ = None"),
     _PASSED, None),
    ("python", "sys_modules", _attack(
        "[sys.modules.pop(n) for n in list(sys.modules) if n[:4] == 'json' or 'transport' in n]"),
     _PASSED, None),
    ("python", "json_forger", _attack(
        "import json; json.dumps = lambda *a, **k: '{\"outcome\": \"success\","
        " \"final_state\": \"finished\", \"code_error\": false}'", mm=50), _FAILED,
     "final_pose_within failed"),
    ("python", "world_objects", _attack("world_objects()", _WORLD_OBJECTS), _PASSED, None),
    ("python", "atexit", _attack(
        pre="import atexit\natexit.register(lambda: [os.write(fd, b'F\\0\\0\\0\\2{}')"
        " for fd in range(3, 20)])"), _PASSED, None),
    ("python", "del_forever", _attack(
        "globals()['KEEPER'] = type('K', (), {'__del__': lambda s: [0 for _ in iter(int, 1)]})()"),
     _PASSED, None),
    ("python", "os_exit", _attack("getattr(os, '_exit')(0)"), _CRASHED,
     "the run stopped unexpectedly (its process ended with exit code 0"),
    ("python", "os_exit_130", _attack(
        "print('interrupted by Ctrl-C', file=sys.stderr, flush=True); getattr(os, '_exit')(130)"),
     _CRASHED, "its process ended with exit code 130"),
    ("python", "str_raises", _attack(
        "raise type('Evil', (Exception,), {'__str__': lambda s: 1 / 0})()"), _CRASHED,
     f"raised Evil in state 'go': (its message cannot be shown: {_STR_RAISED}) {_AT}"),
    ("python", "exit_object", _attack(
        "raise SystemExit(type('X', (), {'__str__': lambda s: 1 / 0, '__repr__': lambda s: 1 / 0})"
        "())"), _CRASHED, "your condition 'first' called exit() in state 'go'"),
    ("python", "str_huge", _attack(
        "raise type('Big', (Exception,), {'__str__': lambda s: 'y' * 50_000_000})()"), _CRASHED,
     "raised Big in state 'go': yyy"),
    ("python", "name_huge", _attack("raise type('E' * 100_000, (Exception,), {})()"), _CRASHED,
     "raised EEE"),
    ("python", "str_forever", _attack(
        "raise type('Slow', (Exception,), {'__str__': lambda s: [0 for _ in iter(int, 1)]})()"),
     _HUNG, "the mission's code did not return for 2 s"),
    # -- report forgery: what it raises and prints
    ("forgery", "html_raiser", _attack(
        "raise RuntimeError('<script>alert(1)</script>]]><![CDATA[' + chr(0) + chr(27) + '[31m'"
        " + chr(0xD800) + chr(0xFFFE) + '\"},{\"score\": 100')"), _CRASHED,
     "raised RuntimeError in state 'go': <script>alert(1)</script>]]>"),
    # text that a terminal or a page would show backwards (Unicode's bidirectional controls)
    ("forgery", "bidi_raiser", _attack(
        "raise RuntimeError('deliaf ' + chr(0x202E) + 'passed' + chr(0x2067) + ' 100%')"),
     _CRASHED, "raised RuntimeError in state 'go': deliaf "),
    ("forgery", "row_raiser", _attack(
        "raise RuntimeError(chr(10) + 'ada  forward  ✓ 2/2  100%' + chr(10) + chr(27) + '[1A')"),
     _CRASHED, "raised RuntimeError"),
    ("forgery", "printer", _attack(
        "print('<script>alert(2)</script>' + chr(27) + '[2J]]>' + chr(0x202E), flush=True);"
        " sys.stdout.write(chr(0) * 100)"), _PASSED, None),
    # -- timing
    ("timing", "slow_import", _attack(pre="time.sleep(3)"), _PASSED, None),
    ("timing", "endless_import", _attack(pre="time.sleep(600)"), _HUNG,
     "the mission stopped while loading: the mission's code did not return for 10 s"),
    ("timing", "busy_condition", _attack("spin()", "def spin():\n    while True:\n        pass"),
     _HUNG, "the mission's code did not return for 2 s and was stopped at forward.py:"),
    # a loop written as a comprehension that builds as it spins: stopped at its line, in the
    # function it is written in (never Python's own "<listcomp>" or "<genexpr>")
    ("timing", "busy_listcomp", _attack("[[] for _ in iter(int, 1)]"), _HUNG,
     _STOPPED_IN_FIRST),
    ("timing", "busy_genexpr", _attack("any(False for _ in iter(int, 1))"), _HUNG,
     _STOPPED_IN_FIRST),
    ("timing", "busy_nested_comps", _attack(
        "any(False for _ in {k: [] for k in iter(int, 1)})"), _HUNG,
     _STOPPED_IN_FIRST),
    ("timing", "thread_after", _attack(
        "threading.Thread(target=lambda: [print('x') for _ in iter(int, 1)]).start()"),
     _PASSED, None),
    # -- round three: its own streams, recursion, threads, signals, odd exits and endings
    ("streams", "close_std", _attack("os.close(0); os.close(1); os.close(2)"), _PASSED, None),
    ("streams", "close_std_print", _attack(
        "os.close(1); os.close(2); print('x' * 100, flush=True)"), _PASSED, None),
    ("streams", "close_std_raise", _attack(
        "os.close(1); os.close(2); raise ValueError('after closing')"), _CRASHED,
     f"your condition 'first' raised ValueError in state 'go': after closing {_AT}"),
    ("streams", "std_none", _attack(
        "sys.stdout = sys.stderr = None; print('x'); raise ValueError('nowhere')"), _CRASHED,
     f"your condition 'first' raised ValueError in state 'go': nowhere {_AT}"),
    ("streams", "stdin_read", _attack("sys.stdin.read()"), _PASSED, None),
    ("streams", "dev_tty", _attack("open('/dev/tty', 'w').write('hello')"), _CRASHED,
     "your condition 'first' raised"),
    ("recursion", "recursion_huge_limit", _attack(
        "sys.setrecursionlimit(10**6); again()", "def again():\n    return again()"), _CRASHED,
     f"raised ValueError in state 'go': {_LIMITS} (it was asked for 1000000)"),
    ("recursion", "recursion_tiny_limit", _attack(pre="sys.setrecursionlimit(30)"), _INVALID,
     f"forward.py:{_PRE_LINE}:1: error: {_LIMITS} (it was asked for 30)"),
    ("recursion", "recursion_10k", _attack(
        "sys.setrecursionlimit(10_000); again()", "def again():\n    return again()"), _CRASHED,
     "'again' calls itself again and again"),
    ("threads", "thread_raises", _attack("threading.Thread(target=lambda: 1 / 0).start()"),
     _PASSED, None),
    ("threads", "thread_join_forever", _attack(
        "KEEP.append(threading.Thread(target=time.sleep, args=(600,), daemon=True));"
        " KEEP[-1].start(); KEEP[-1].join()", "KEEP = []"), _HUNG,
     f"did not return for 2 s and was stopped at forward.py:{_ATTACK_LINE}"),
    ("signals", "alarm_ignored", _attack(
        "signal.signal(signal.SIGALRM, signal.SIG_IGN); spin()", _SPIN), _CRASHED,
     f"raised PermissionError in state 'go': {_ALARM} {_AT}"),
    ("signals", "alarm_blocked", _attack(
        "signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGALRM}); spin()", _SPIN), _CRASHED,
     f"raised PermissionError in state 'go': {_ALARM} {_AT}"),
    ("signals", "timer_cancelled", _attack(
        "signal.setitimer(signal.ITIMER_REAL, 0); spin()", _SPIN), _CRASHED,
     f"raised PermissionError in state 'go': {_ALARM} {_AT}"),
    ("signals", "alarm_self", _attack("signal.alarm(1)"), _CRASHED,
     f"raised PermissionError in state 'go': {_ALARM} {_AT}"),
    ("signals", "alarm_raw", _attack(
        "import _signal; _signal.signal(signal.SIGALRM, signal.SIG_IGN); spin()", _SPIN),
     _CRASHED, f"{_ALARM} {_AT}"),
    ("signals", "clock_frozen", _attack(
        "time.perf_counter = time.monotonic = lambda: 0.0; spin()", _SPIN), _HUNG,
     "did not return for 2 s and was stopped at forward.py:"),
    ("signals", "handler_raises", _attack(
        "signal.signal(signal.SIGUSR1, lambda *a: 1 / 0); os.kill(os.getpid(), signal.SIGUSR1)"),
     _CRASHED, "your condition 'first' raised ZeroDivisionError in state 'go'"),
    ("signals", "sigterm_ignored", _attack(
        "signal.signal(signal.SIGTERM, signal.SIG_IGN); os.kill(os.getpid(), signal.SIGTERM)"),
     _PASSED, None),
    ("signals", "sigterm_in_del", _attack(
        "globals()['K'] = type('K', (), {'__del__': lambda s: signal.raise_signal(15)})();"
        " globals()['K'] = None"), _CRASHED, "your code sent its own process SIGTERM in state"),
    ("signals", "faulthandler", _attack(
        "import ctypes, faulthandler; faulthandler.enable(); ctypes.string_at(0)"), _CRASHED,
     "its process was killed by SIGSEGV (Python itself crashed"),
    ("exceptions", "msg_lines", _attack("raise ValueError(chr(10).join(['line'] * 1_000_000))"),
     _CRASHED, "raised ValueError in state 'go': line line"),
    ("exceptions", "msg_100mb", _attack("raise ValueError('z' * 100_000_000)"), _CRASHED,
     "raised ValueError in state 'go': zzz"),
    ("exceptions", "cause_cycle", _attack(
        "a = ValueError('a'); b = KeyError('b'); a.__cause__ = b; b.__cause__ = a; raise a"),
     _CRASHED, f"your condition 'first' raised ValueError in state 'go': a {_AT}"),
    ("exceptions", "context_cycle", _attack(
        "a = ValueError('a'); b = KeyError('b'); a.__context__ = b; b.__context__ = a; raise a"),
     _CRASHED, f"your condition 'first' raised ValueError in state 'go': a {_AT}"),
    ("exceptions", "args_cycle", _attack("e = ValueError(); e.args = (e,); raise e"), _CRASHED,
     "your condition 'first' raised ValueError in state 'go'"),
    ("exceptions", "group", _attack("raise ExceptionGroup('many', [ValueError(1), KeyError(2)])"),
     _CRASHED, f"raised ExceptionGroup in state 'go': many (2 sub-exceptions) {_AT}"),
    ("exceptions", "base_exception", _attack("raise BaseException('base')"), _CRASHED,
     f"your condition 'first' raised BaseException in state 'go': base {_AT}"),
    ("exceptions", "generator_exit", _attack("raise GeneratorExit"), _CRASHED,
     f"your condition 'first' raised GeneratorExit in state 'go' {_AT}"),
    ("exit", "exit_any_object", _attack("getattr(sys, 'ex' + 'it')(object())"), _CRASHED,
     "your condition 'first' called exit() in state 'go'"),
    ("exit", "exit_bignum", _attack("getattr(sys, 'ex' + 'it')(2 ** 100)"), _CRASHED,
     "your condition 'first' called exit() in state 'go'"),
    ("exit", "exit_negative", _attack("getattr(sys, 'ex' + 'it')(-1)"), _CRASHED,
     "your condition 'first' called exit() in state 'go'"),
    ("exit", "exit_true", _attack("getattr(sys, 'ex' + 'it')(True)"), _CRASHED,
     "your condition 'first' called exit() in state 'go'"),
    ("exit", "exit_written", _attack("sys.exit(None)"), _INVALID,
     "sys.exit() would end the whole program, not the mission"),
    ("exit", "exit_at_load", _attack(pre="sys.exit('bye')"), _INVALID,
     "the mission file called exit() while it was loaded"),
    ("endings", "del_exits", _attack(
        "globals()['K'] = type('K', (), {'__del__': lambda s: os._exit(0)})()"), _PASSED, None),
    ("endings", "del_raises_exit", _attack(
        "globals()['K'] = type('K', (), {'__del__': lambda s: sys.exit(3)})();"
        " globals()['K'] = None"), _PASSED, None),
    ("endings", "atexit_sleeps", _attack(pre="import atexit\natexit.register(time.sleep, 600)"),
     _PASSED, None),
    ("endings", "atexit_spins", _attack(
        pre="import atexit\natexit.register(lambda: [0 for _ in iter(int, 1)])"), _PASSED, None),
    ("endings", "atexit_exits", _attack(
        pre="import atexit\natexit.register(lambda: getattr(os, '_exit')(7))"), _PASSED, None),
    ("process", "setsid", _attack("os.setsid()"), _CRASHED,
     "your condition 'first' raised PermissionError in state 'go'"),
    # the programs it starts can be ended with SIGTERM, as anywhere (however it tells its own
    # SIGTERM from a teacher's)
    ("process", "ends_its_programs", _attack(
        "import subprocess; p = subprocess.Popen(['sleep', '30']); p.terminate();"
        " p.wait(timeout=5); pid = os.posix_spawn('/bin/sleep', ['sleep', '30'], {});"
        " os.kill(pid, signal.SIGTERM); os.waitpid(pid, 0); os.system('kill -TERM $$')"),
     _PASSED, None),
    ("process", "chdir_umask_environ", _attack(
        "os.chdir('/'); os.umask(0o777); os.environ.clear()"), _PASSED, None),
    ("process", "tracers", _attack(
        "sys.settrace(lambda *a: None); sys.setprofile(lambda *a: None); import gc;"
        " gc.disable()"), _PASSED, None),
    ("process", "writes_own_file", _attack("open(__file__, 'a').write('# changed')"), _CRASHED,
     "your condition 'first' raised"),
    ("load", "load_cause_cycle", _attack(
        pre="a = ValueError('a'); b = KeyError('b'); a.__cause__ = b; b.__cause__ = a\nraise a"),
     _INVALID, f"forward.py:{_PRE_LINE + 1}:1: error: ValueError: a"),
    ("load", "load_args_cycle", _attack(pre="e = ValueError(); e.args = (e,)\nraise e"), _INVALID,
     "ValueError: (its message cannot be shown: its __str__ raised RecursionError)"),
    ("load", "load_closes_std", _attack(pre="os.close(1); os.close(2)\nraise ValueError('shut')"),
     _INVALID, f"forward.py:{_PRE_LINE + 1}:1: error: ValueError: shut"),
    ("load", "load_sigusr2", _attack(pre="os.kill(os.getpid(), signal.SIGUSR2)"), _INVALID,
     f"forward.py:{_PRE_LINE}: error: sent its own process SIGUSR2: {_NO_SIGNAL}"),
    ("load", "load_generator_exit", _attack(pre="raise GeneratorExit"), _INVALID,
     f"forward.py:{_PRE_LINE}:1: error: GeneratorExit"),
    # -- names and files that try to break a report
    ("names", "ADA", _HONEST_FILES, _PASSED, None),  # ada's page, but for case: a page apart
    ("names", "nul", _HONEST_FILES, _PASSED, None),  # a Windows device: its page is nul_.html
    ("names", "<img src=x onerror=alert(4)>", _HONEST_FILES, _PASSED, None),
    ("names", "-1+2", _HONEST_FILES, _PASSED, None),
    ("names", "@SUM(A1)", _HONEST_FILES, _PASSED, None),
    ("names", "\tcell=1+1", _HONEST_FILES, _PASSED, None),
    ("names", "ada\u202eevil", _HONEST_FILES, _PASSED, None),
    ("names", "x" * 240, _HONEST_FILES, _PASSED, None),
    ("names", "fiona", _HONEST_FILES, _PASSED, None),
    ("names", "\ufb01ona", _HONEST_FILES, _PASSED, None),  # a ligature: drawn as "fiona"
    # characters drawn as nothing (a variation selector, a blank Braille cell, a tag) or as
    # a pile of accents that reaches over the lines around it
    ("names", "ada\ufe0f", _HONEST_FILES, _PASSED, None),
    ("names", "bea\u2800", _HONEST_FILES, _PASSED, None),
    ("names", "cy\U000e0041", _HONEST_FILES, _PASSED, None),
    ("names", "zalgo" + "\u0301" * 40, _HONEST_FILES, _PASSED, None),
    ("names", "socket_file", {"forward.yaml": HONEST, "s.py": "SOCKET"}, _INVALID,
     "s.py is a socket, not an ordinary file"),
    ("names", "odd_helper", {"forward.yaml": HONEST, "he\x1b[2Jlp\u202eer.py": "X = 1\n"},
     _PASSED, None),
    # -- files shared with a classmate: a hard link is one file, so both are refused
    ("files", "link_victim", _HONEST_FILES, _INVALID,
     "forward.yaml is the same file as link_thief's forward.yaml (a hard link, not a copy"),
    ("files", "link_thief", {"forward.yaml": "HARDLINK link_victim/forward.yaml"}, _INVALID,
     "forward.yaml is the same file as link_victim's forward.yaml (a hard link, not a copy"),
    ("files", "own_link", {"forward.yaml": HONEST, "backup.yaml": "HARDLINK own_link/forward.yaml"},
     _PASSED, None),
]  # fmt: skip
_SHOWN = {"\ufb01ona": "\ufb01ona-2"}  # numbered: it looks like "fiona"


def _shown_name(student: str) -> str:
    """A student's name as every report shows it."""
    return _SHOWN.get(student, clean_name(student))


def _round_two_class(subs: Path) -> None:
    import socket

    _write(subs / "ada" / "forward.yaml", HONEST)
    _write(subs / "bea.yaml", HONEST)
    _write(subs / "bea_helpers.py", "CLASSMATE = 'BEA" + "-SECRET'\n")
    os.mkfifo(subs / "a_fifo")  # a "student" that is a named pipe: never opened, never waited on
    for _family, student, mission, *_ in ATTACKS:
        files = mission if isinstance(mission, dict) else {"forward.py": mission}
        for name, text in files.items():
            if text == "SOCKET":
                with socket.socket(socket.AF_UNIX) as bound:
                    bound.bind(str(subs / student / name))
            elif text.startswith("HARDLINK "):
                (subs / student).mkdir(parents=True, exist_ok=True)
                os.link(subs / text.removeprefix("HARDLINK "), subs / student / name)
            else:
                _write(subs / student / name, text)


@pytest.fixture(scope="module")
def attacked(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Round two, graded once by the real command line with every report written."""
    root = tmp_path_factory.mktemp("round-two")
    spec = root / "teacher" / "forward.yaml"
    _write(spec, SPEC)
    subs = root / "class"
    _round_two_class(subs)
    out = root / "out"
    out.mkdir()
    command = [
        sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(subs),
        "--jobs", "2", "--hang-after", "2",
        "--junit", str(out / "junit.xml"), "--csv", str(out / "grades.csv"),
        "--html", str(out / "html"), "--results", str(out / "results.jsonl"),
    ]  # fmt: skip
    environment = {**os.environ, _SECRET_ENV: _SECRET}
    done = subprocess.run(
        command, capture_output=True, text=True, timeout=HANG_BOUND_S, check=False, env=environment
    )
    lines = (out / "results.jsonl").read_text().splitlines()
    return {
        "root": root,
        "exit": done.returncode,
        "stdout": done.stdout,
        "stderr": done.stderr,
        "runs": [json.loads(line) for line in lines[1:]],
        "junit": (out / "junit.xml").read_text(encoding="utf-8"),
        "csv": (out / "grades.csv").read_text(encoding="utf-8-sig"),
        "html": out / "html",
    }


@pytest.mark.parametrize(
    ("student", "statuses", "says"),
    [pytest.param(s, st, says, id=f"{family}-{s[:20]}") for family, s, _, st, says in ATTACKS],
)
def test_each_attack_gets_the_verdict_and_the_sentence_its_own_work_earns(
    attacked: dict[str, Any], student: str, statuses: tuple[str, str], says: str | None
) -> None:
    name = _shown_name(student)
    runs = sorted((r for r in attacked["runs"] if r["student"] == name), key=lambda r: r["variant"])
    shown = [(r["status"], r["message"][:600], r["debug"][-1500:]) for r in runs]
    assert tuple(r["status"] for r in runs) == statuses, shown
    for run in runs:
        assert "roboscript problem" not in run["message"], shown
        assert len(run["message"]) < 3000, shown
        if says is not None:
            assert says in run["message"], shown


def test_round_two_grades_everyone_and_writes_every_report(attacked: dict[str, Any]) -> None:
    assert attacked["exit"] == 1, attacked["stderr"][-3000:]
    assert "Traceback" not in attacked["stderr"]
    assert "the students 'fiona' and 'ﬁona-2' have names that look the same" in attacked["stderr"]
    (note,) = [line for line in attacked["stderr"].splitlines() if "no student's work" in line]
    assert "a_fifo" in note
    statuses = _statuses(attacked)
    assert statuses["ada"] == ["passed", "passed"] and statuses["bea"] == ["passed", "passed"]
    assert sorted(statuses) == sorted(["ada", "bea", *(_shown_name(a[1]) for a in ATTACKS)])
    cases = list(ET.fromstring(attacked["junit"]).iter("testcase"))
    assert len(cases) == len(attacked["runs"])
    assert len(list((attacked["html"] / "students").glob("*.html"))) == len(statuses)
    assert len(list((attacked["html"] / "runs").glob("*.html"))) == len(attacked["runs"])


def test_a_name_drawn_like_a_classmates_is_told_apart_in_every_report(
    attacked: dict[str, Any],
) -> None:
    # "ada" + a variation selector, "bea" + a blank Braille cell: drawn as "ada" and "bea".
    statuses = _statuses(attacked)
    for shown in ("ada�", "bea�", "cy�", "zalgó\u0301\u0301\u0301\u0301�"):
        assert statuses[shown] == ["passed", "passed"], sorted(statuses)
    pages = "".join(p.read_text(encoding="utf-8") for p in attacked["html"].rglob("*.html"))
    for text in (attacked["stdout"], attacked["stderr"], attacked["csv"], attacked["junit"], pages):
        assert not re.search("[\ufe0f\u2800\U000e0041]|\u0301{5}", text)


def test_no_attack_reads_the_teachers_secrets_or_a_classmates_file(
    attacked: dict[str, Any],
) -> None:
    everything = json.dumps(attacked["runs"]) + attacked["stdout"] + attacked["stderr"]
    assert "SNOOPED" not in everything and "THE WORLD IS HERE" not in everything
    assert _SECRET not in everything


def test_no_attack_forges_a_line_a_cell_or_markup_in_any_report(attacked: dict[str, Any]) -> None:
    for stream in (attacked["stdout"], attacked["stderr"]):
        assert not re.search("[\x00-\x08\x0b-\x1f\x7f-\x9f\u202e]", stream)
        assert not any(line.startswith("ada  forward") for line in stream.splitlines())
    for page in attacked["html"].rglob("*.html"):
        text = page.read_text(encoding="utf-8")
        assert "<script>alert(" not in text and "<img src=x" not in text, page.name
        assert not re.search("[\x00\x1b\u202e]", text), page.name
    rows = list(csv.reader(io.StringIO(attacked["csv"])))
    names = [row[0] for row in rows[1:]]
    assert "'-1+2" in names and "'@SUM(A1)" in names
    for row in rows:
        for cell in row:
            for part in [*re.split("[,;\t|]", cell)[1:], cell]:
                assert not part.lstrip(" ").startswith(("=", "+", "-", "@")), cell
    assert not re.search("[\ud800-\udfff\ufffe]", attacked["junit"])
    assert not re.search("[\u202a-\u202e\u2066-\u2069]", attacked["junit"] + attacked["csv"])
