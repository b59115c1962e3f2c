"""A graded batch is trustworthy: runs are isolated, bounded in wall time, and deterministic."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from helpers import FORWARD_50CM, FORWARD_50CM_EXPECT, HANG_BOUND_S, MISSIONS

from roboscript.grading import pool
from roboscript.grading.batch import find_specs, find_submissions, grade_class
from roboscript.grading.run import grade_run
from roboscript.grading.sandbox import warm_jails_supported
from roboscript.grading.spec import load_test_spec
from roboscript.grading.task import RunTask

SPEC = """\
test: square
world: empty
runs:
  - {seed: 1}
  - {seed: 2, start: {x: 200 mm, y: 0 mm, heading: 20 deg}}
max_time: 40 s
wall_time_limit: 600 s  # a bound: hangs end on the mission's own time, never on this
expect:
  - outcome: success
  - final_pose_within: {x: 0 mm, y: 0 mm, radius: 8 cm, relative_to: start}
  - tones: {count: 4}
"""

HANGS = """\
from roboscript import Drive, Mission, state


class Hang(Mission):
    go = state(Drive(distance_mm=500), initial=True, on_done="end", when=[("stuck", "end")])
    end = state(final="success")

    def stuck(self) -> bool:
        while True:
            pass
"""

RAISES = """\
from roboscript import Action, Mission, Param, state


class Boom(Action):
    name = "boom"
    params = ()

    def update(self, ctx):
        raise RuntimeError("the wheel fell off")


class Crash(Mission):
    go = state(Boom(), initial=True, on_done="end")
    end = state(final="success")
"""

EXITS = """\
import os
from roboscript import Mission, Wait, state


class Quit(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end", when=[("bye", "end")])
    end = state(final="success")

    def bye(self) -> bool:
        print("this must not reach the report")
        getattr(os, "_exit")(3)  # by another name: check refuses os._exit() in a condition
"""

MARKS_ITS_PROCESS = """\
import os
from pathlib import Path
from roboscript import Mission, Wait, state

try:
    Path(__file__).with_suffix(".pid").write_text(str(os.getpid()))
    print("wrote beside the mission")
except OSError:
    print("the mission's folder is read-only")
print("pid", os.getpid())


class Idle(Mission):
    go = state(Wait(duration_s=0.5), initial=True, on_done="end")
    end = state(final="success")
"""


@pytest.fixture
def batch(tmp_path: Path) -> tuple[Path, Path]:
    """A spec and a class folder: two good students and four kinds of trouble."""
    spec = tmp_path / "square.yaml"
    spec.write_text(SPEC, encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    shutil.copy(MISSIONS / "square.yaml", folder / "ada.yaml")
    shutil.copy(MISSIONS / "square.py", folder / "ben.py")
    (folder / "cy.py").write_text(HANGS, encoding="utf-8")
    (folder / "di.py").write_text(RAISES, encoding="utf-8")
    (folder / "ed.py").write_text(EXITS, encoding="utf-8")
    (folder / "flo.yaml").write_text("mission: flo\nstates: {}\n", encoding="utf-8")
    return spec, folder


def _without_wall_time(report: Any) -> list[dict[str, Any]]:
    return [replace(r, wall_time_s=0.0).to_dict() for r in report.results]


def test_a_batch_survives_hanging_crashing_and_exiting_missions(batch: tuple[Path, Path]) -> None:
    spec, folder = batch
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=2
    )
    by_student = {s.student: report.cell(s.student, "square") for s in report.submissions}
    assert sorted(by_student) == ["ada", "ben", "cy", "di", "ed", "flo"]
    assert by_student["ada"].passed and by_student["ben"].passed
    statuses = {name: {r.status for r in cell.results} for name, cell in by_student.items()}
    assert statuses["cy"] == {"hung"}
    assert statuses["di"] == {"crashed"}
    assert statuses["ed"] == {"crashed"}
    assert statuses["flo"] == {"invalid"}
    for name in ("cy", "di", "ed", "flo"):
        for result in by_student[name].results:
            assert result.score == 0.0
            message = result.message
            assert message and "\n" not in message and "Traceback" not in message, message
    assert (
        by_student["cy"]
        .results[0]
        .message.startswith("the mission's code did not return for 2 s and was stopped at ")
    )
    assert re.search(
        r"cy\.py:(9|10) in stuck: is there a loop that never ends\?",
        by_student["cy"].results[0].message,
    )
    assert "raised RuntimeError in state 'go': the wheel fell off" in (
        by_student["di"].results[0].message
    )
    assert "exit code 3" in by_student["ed"].results[0].message
    assert by_student["flo"].results[0].message.startswith("the mission has an error: ")
    assert not report.passed


def test_results_do_not_depend_on_the_number_of_workers(batch: tuple[Path, Path]) -> None:
    spec, folder = batch
    for name in ("cy.py", "ed.py"):  # keep the comparison quick: no hang limits
        (folder / name).unlink()
    specs = find_specs([str(spec)])
    submissions = find_submissions([str(folder)]).submissions
    one = grade_class(specs, submissions, jobs=1)
    two = grade_class(specs, submissions, jobs=2)
    assert _without_wall_time(one) == _without_wall_time(two)
    assert [r.student for r in one.results] == [
        "ada",
        "ada",
        "ben",
        "ben",
        "di",
        "di",
        "flo",
        "flo",
    ]


def test_the_parent_ends_a_worker_at_its_runs_longest_wall_time(batch: tuple[Path, Path]) -> None:
    spec_path, folder = batch
    spec = load_test_spec(spec_path)
    task = RunTask(spec, str(folder / "ada.yaml"), spec.variants[0], "ada")
    assert pool._deadline(100.0, task) == 100.0 + spec.longest_wall_time_s


def test_a_run_in_process_equals_the_run_in_a_worker(batch: tuple[Path, Path]) -> None:
    spec_path, folder = batch
    spec = load_test_spec(spec_path)
    mission = str(folder / "ada.yaml")
    here = grade_run(spec, mission, spec.variants[1], "ada")
    (folder / "ben.py").unlink()
    for name in ("cy.py", "di.py", "ed.py", "flo.yaml"):
        (folder / name).unlink()
    report = grade_class([spec], find_submissions([str(folder)]).submissions, jobs=1)
    there = report.results[1]
    assert replace(here, wall_time_s=0.0).to_dict() == replace(there, wall_time_s=0.0).to_dict()
    assert here.passed


def test_student_code_runs_only_in_its_own_sandboxed_process(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: idle\nexpect:\n  - outcome: success\n", encoding="utf-8")
    student = tmp_path / "class" / "gus.py"
    student.parent.mkdir()
    student.write_text(MARKS_ITS_PROCESS, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(student.parent)]).submissions, jobs=1
    )
    assert report.passed
    output = report.results[0].debug
    assert "the mission's folder is read-only" in output
    assert not student.with_suffix(".pid").exists()
    pid = int(re.search(r"pid (\d+)", output)[1])  # type: ignore[index]
    assert pid != os.getpid()


HANGS_LOADING = """\
from roboscript import Mission, Wait, state

while True:
    pass


class Never(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end")
    end = state(final="success")
"""


def test_a_mission_that_hangs_while_loading_is_run_once_for_all_its_variants(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from roboscript.grading import pool

    spec = tmp_path / "spec.yaml"
    variants = "".join(f"  - {{seed: {n}}}\n" for n in range(1, 5))
    spec.write_text(f"test: t\nruns:\n{variants}expect:\n  - outcome: success\n", encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "zed.py").write_text(HANGS_LOADING, encoding="utf-8")
    (folder / "amy.py").write_text(RAISES, encoding="utf-8")
    started: list[str] = []
    real_start = pool._start

    def counting(context: Any, batch: list[tuple[int, pool.RunTask]], *args: Any) -> Any:
        started.extend(Path(task.mission).stem for _index, task in batch)
        return real_start(context, batch, *args)

    monkeypatch.setattr(pool, "_start", counting)
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=2
    )
    assert started.count("amy") == 4  # it loads: each variant runs (and crashes) on its own
    zed = report.cell("zed", "t").results
    assert [r.status for r in zed] == ["hung"] * 4
    assert all(r.during_load and "while loading" in r.message for r in zed)
    assert [r.variant for r in zed] == [0, 1, 2, 3]
    # Only the first was run: the others are its result, given without a run of their own.
    assert [r.wall_time_s > 0 for r in zed] == [True, False, False, False]
    amy = report.cell("amy", "t").results
    assert all(r.status == "crashed" and r.wall_time_s > 0 for r in amy)


IDLES = """\
from roboscript import Mission, Wait, state


class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end")
    end = state(final="success")
"""

CRASHES_LOADING = """\
from roboscript import Mission, Wait, state

import robotlib  # not installed: the mission crashes while loading


class Never(Mission):
    go = state(Wait(duration_s=1), initial=True, on_done="end")
    end = state(final="success")
"""


@pytest.fixture
def workers_log(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Workers forked from this process, each writing a line to the returned file per jail it
    starts (``jail STUDENT hidden|visible``) and per run it does (``run STUDENT VARIANT``)."""
    import multiprocessing

    from roboscript.grading import pool, worker

    log = tmp_path / "workers.log"
    real_jail, real_grade = worker._warm_jail, worker._grade

    def note(line: str) -> None:
        with log.open("a", encoding="utf-8") as handle:
            handle.write(line + "\n")

    def warm_jail(task: pool.RunTask) -> Any:
        note(f"jail {task.student} {'hidden' if task.variant.hidden else 'visible'}")
        return real_jail(task)

    def grade(task: pool.RunTask, server: Any) -> Any:
        note(f"run {task.student} {task.variant.index}")
        return real_grade(task, server)

    monkeypatch.setattr(worker, "_warm_jail", warm_jail)
    monkeypatch.setattr(worker, "_grade", grade)
    # Forked from here (not from the fork server), so each worker has the counting functions.
    monkeypatch.setattr(pool, "_context", lambda: multiprocessing.get_context("fork"))
    log.touch()
    return log


def _spec_with_runs(tmp_path: Path, visible: int, hidden: int) -> Path:
    spec = tmp_path / "spec.yaml"
    runs = [f"  - {{seed: {n + 1}}}\n" for n in range(visible)]
    runs += [f"  - {{seed: {n + 1}, hidden: true}}\n" for n in range(visible, visible + hidden)]
    spec.write_text(
        f"test: t\nruns:\n{''.join(runs)}expect:\n  - outcome: success\n", encoding="utf-8"
    )
    return spec


@pytest.mark.skipif(not warm_jails_supported(), reason="warm jails are Linux only")
def test_a_students_runs_cost_one_worker_and_one_jail_per_kind_of_run(
    tmp_path: Path, workers_log: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from roboscript.grading import pool

    spec = _spec_with_runs(tmp_path, visible=3, hidden=1)
    folder = tmp_path / "class"
    folder.mkdir()
    for name in ("ann", "bob"):
        (folder / f"{name}.py").write_text(IDLES, encoding="utf-8")
    started: list[tuple[str, int]] = []
    real_start = pool._start

    def counting(context: Any, batch: list[tuple[int, pool.RunTask]], *args: Any) -> Any:
        started.append((batch[0][1].student, len(batch)))
        return real_start(context, batch, *args)

    monkeypatch.setattr(pool, "_start", counting)
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=2
    )
    assert report.passed
    assert sorted(started) == [("ann", 1), ("ann", 3), ("bob", 1), ("bob", 3)]
    lines = workers_log.read_text(encoding="utf-8").splitlines()
    jails = sorted(line for line in lines if line.startswith("jail"))
    assert jails == ["jail ann hidden", "jail ann visible", "jail bob hidden", "jail bob visible"]
    assert sorted(line for line in lines if line.startswith("run")) == [
        f"run {name} {variant}" for name in ("ann", "bob") for variant in range(4)
    ]


@pytest.mark.parametrize("jobs", [1, 2, 4])
def test_a_mission_that_fails_to_load_costs_one_run_whatever_the_workers(
    tmp_path: Path, workers_log: Path, jobs: int
) -> None:
    # With 4 workers zed's visible runs are split in two batches (more than one worker's
    # share): one batch's worker does the first run, the parent answers the other.
    spec = _spec_with_runs(tmp_path, visible=3, hidden=1)
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "ann.py").write_text(IDLES, encoding="utf-8")
    (folder / "zed.py").write_text(CRASHES_LOADING, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=jobs
    )
    lines = workers_log.read_text(encoding="utf-8").splitlines()
    assert [line for line in lines if "zed" in line] == ["jail zed visible", "run zed 0"]
    assert sorted(line for line in lines if line.startswith("run ann")) == [
        f"run ann {variant}" for variant in range(4)
    ]
    zed = report.cell("zed", "t").results
    assert [r.variant for r in zed] == [0, 1, 2, 3]
    assert all(r.status == "invalid" and r.during_load for r in zed)
    assert "No module named 'robotlib'" in zed[0].message
    assert len({(r.message, r.debug) for r in zed}) == 1  # the first run's result, for all
    assert [r.wall_time_s > 0 for r in zed] == [True, False, False, False]
    assert report.cell("ann", "t").passed


def test_a_worker_that_ends_just_after_the_parent_looked_is_read_not_run_again(
    tmp_path: Path, workers_log: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The worker sends its result and ends after the parent's wait() returned for another
    # reason: its result is still in the pipe, and its batch must not be started again.
    from multiprocessing.connection import wait as real_wait

    from roboscript.grading import pool

    late = [True]

    def wait_that_looks_too_early(objects: list[Any], timeout: float | None = None) -> list[Any]:
        ready = real_wait(objects, timeout)
        if ready and late[0]:
            late[0] = False
            sentinels = [o for o in objects if isinstance(o, int)]
            assert real_wait(sentinels, 60)  # every worker here ends after its one result
            return []
        return ready

    monkeypatch.setattr(pool, "wait", wait_that_looks_too_early)
    spec = _spec_with_runs(tmp_path, visible=3, hidden=0)
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "zed.py").write_text(CRASHES_LOADING, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=1
    )
    assert not late[0]
    lines = workers_log.read_text(encoding="utf-8").splitlines()
    assert lines == ["jail zed visible", "run zed 0"]
    zed = report.cell("zed", "t").results
    assert all(r.status == "invalid" and r.during_load for r in zed)


SAYS_ITS_JAIL = """\
import os, sys
from roboscript import Mission, Wait, state

# The world's map is handed to the run in a folder of its jail's own.
print("JAIL", os.path.dirname(sys.argv[-1]))


class Idle(Mission):
    go = state(Wait(duration_s=0.2), initial=True, on_done="end")
    end = state(final="success")
"""


@pytest.mark.skipif(not warm_jails_supported(), reason="warm jails are Linux only")
def test_a_students_runs_share_a_jail_but_hidden_runs_get_their_own(tmp_path: Path) -> None:
    spec = tmp_path / "spec.yaml"
    spec.write_text(
        "test: t\nruns:\n  - {seed: 1}\n  - {seed: 2}\n  - {seed: 3, hidden: true}\n"
        "expect:\n  - outcome: success\n",
        encoding="utf-8",
    )
    folder = tmp_path / "class"
    folder.mkdir()
    (folder / "ann.py").write_text(SAYS_ITS_JAIL, encoding="utf-8")
    (folder / "bob.py").write_text(SAYS_ITS_JAIL, encoding="utf-8")
    report = grade_class(
        find_specs([str(spec)]), find_submissions([str(folder)]).submissions, jobs=2
    )
    jails = {
        (r.student, r.variant): re.search(r"JAIL (\S+)", r.debug)[1]  # type: ignore[index]
        for r in report.results
    }
    assert report.passed
    assert jails["ann", 0] == jails["ann", 1]  # one jail, imported once, for both
    assert jails["ann", 2] != jails["ann", 0]  # what a hidden run saw stays in its own
    assert jails["bob", 0] not in (jails["ann", 0], jails["ann", 2])


def test_a_killed_grader_keeps_every_finished_run(tmp_path: Path) -> None:
    import json
    import signal
    import subprocess
    import sys
    import time

    spec = tmp_path / "spec.yaml"
    variants = "".join(f"  - {{seed: {n}}}\n" for n in range(1, 4))
    spec.write_text(f"test: t\nruns:\n{variants}expect:\n  - outcome: success\n", encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    shutil.copy(MISSIONS / "square.yaml", folder / "ada.yaml")
    (folder / "zed.py").write_text(HANGS, encoding="utf-8")  # 2 s a run: time to be killed
    results = tmp_path / "results.jsonl"
    grader = subprocess.Popen(
        [
            *(sys.executable, "-m", "roboscript", "grade", str(spec), "--mission", str(folder)),
            *("--results", str(results), "--jobs", "1", "--quiet"),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        deadline = time.monotonic() + HANG_BOUND_S
        while time.monotonic() < deadline:
            if results.exists() and results.read_text().count("\n") >= 5:  # header + 4
                break
            time.sleep(0.05)
        os.killpg(grader.pid, signal.SIGKILL)
    finally:
        grader.wait(HANG_BOUND_S)
    lines = results.read_text(encoding="utf-8").splitlines()[1:]  # after the header
    assert len(lines) >= 4
    finished = [json.loads(line) for line in lines]  # every line is whole
    assert [r["student"] for r in finished[:3]] == ["ada", "ada", "ada"]
    assert all(r["status"] == "passed" for r in finished[:3])


def test_grading_from_a_folder_holding_a_roboscript_py_grades_as_anywhere_else(
    tmp_path: Path,
) -> None:
    # The teacher's own command, `roboscript grade`, started in a folder a student filled.
    command = Path(sys.executable).with_name("roboscript")
    if not command.exists():
        pytest.skip("the roboscript command is not installed beside this Python")
    spec = tmp_path / "forward.yaml"
    spec.write_text(
        "test: forward\nworld: empty\nrobot: mirto\nruns:\n  - {seed: 1}\n" + FORWARD_50CM_EXPECT,
        encoding="utf-8",
    )
    (tmp_path / "ana.yaml").write_text(FORWARD_50CM, encoding="utf-8")
    (tmp_path / "roboscript.py").write_text("print('a helper of my own')\n", encoding="utf-8")
    done = subprocess.run(
        [str(command), "grade", "forward.yaml", "--mission", "ana.yaml", "--json", "--quiet"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=HANG_BOUND_S,
        check=False,
    )
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert [r["status"] for r in json.loads(done.stdout)["runs"]] == ["passed"]


def test_a_class_grades_with_a_temporary_folder_too_long_for_a_socket(tmp_path: Path) -> None:
    # The fork server listens on a Unix socket in the temporary folder, and a socket's path is
    # at most 107 bytes: a deep TMPDIR made the whole class end in a traceback.
    deep = tmp_path / ("t" * 40) / ("m" * 40) / ("p" * 40)
    deep.mkdir(parents=True)
    (tmp_path / "class").mkdir()
    shutil.copy(MISSIONS / "square.yaml", tmp_path / "class" / "ana.yaml")
    env = dict(os.environ, TMPDIR=str(deep))
    spec = MISSIONS / "teacher" / "square" / "test.yaml"
    graded = subprocess.run(
        [sys.executable, "-m", "roboscript", "grade", str(spec),
         "--mission", str(tmp_path / "class"), "--json"],
        capture_output=True, text=True, env=env, timeout=HANG_BOUND_S, check=False,
    )  # fmt: skip
    assert graded.returncode == 0, graded.stderr
    assert "Traceback" not in graded.stderr
    assert [run["status"] for run in json.loads(graded.stdout)["runs"]] == ["passed"] * 3
