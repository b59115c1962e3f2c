"""Finding a class's submissions: who is who, and which mission runs in which test."""

from __future__ import annotations

import json
import os
import shutil
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from helpers import FORWARD_50CM, FORWARD_50CM_EXPECT, HANG_BOUND_S, MISSIONS

from roboscript.errors import InputError
from roboscript.grading.batch import (
    Submission,
    find_specs,
    find_submissions,
    grade_class,
    mission_for_test,
)
from roboscript.grading.record import RunResult
from roboscript.grading.shards import ResultsFile
from roboscript.grading.spec import load_test_spec

SQUARE = MISSIONS / "square.yaml"


def _names(found: list[Submission]) -> dict[str, list[str]]:
    return {s.student: [Path(m).name for m in s.missions] for s in found}


def test_a_class_folder_has_file_students_and_folder_students(tmp_path: Path) -> None:
    shutil.copy(SQUARE, tmp_path / "alice.yaml")
    shutil.copy(MISSIONS / "square.py", tmp_path / "bob.py")
    (tmp_path / "helper.py").write_text("def helps():\n    return 1\n")  # not a mission
    shutil.copy(MISSIONS / "teacher" / "square" / "test.yaml", tmp_path / "test.yaml")  # a spec
    carol = tmp_path / "carol"
    (carol / "behaviours").mkdir(parents=True)
    shutil.copy(MISSIONS / "zigzag.yaml", carol / "zigzag.yaml")
    shutil.copy(MISSIONS / "behaviours" / "zigzag.py", carol / "behaviours" / "zigzag.py")
    assert _names(find_submissions([str(tmp_path)]).submissions) == {
        "alice": ["alice.yaml"],
        "bob": ["bob.py"],
        "carol": ["zigzag.yaml"],
    }


def test_a_glob_of_same_named_files_names_students_by_folder(tmp_path: Path) -> None:
    for student in ("dan", "eve"):
        (tmp_path / student).mkdir()
        shutil.copy(SQUARE, tmp_path / student / "square.yaml")
    found = find_submissions([str(tmp_path / "*" / "square.yaml")]).submissions
    assert list(_names(found)) == ["dan", "eve"]


def test_nothing_found_is_an_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no mission matches"):
        find_submissions([str(tmp_path / "*.yaml")])
    with pytest.raises(InputError, match="no mission files in the folder"):
        find_submissions([str(tmp_path)])


def test_a_student_with_several_missions_runs_the_one_named_after_the_test() -> None:
    spec = load_test_spec(MISSIONS / "teacher" / "square" / "test.yaml")
    both = Submission("amy", ("amy/square_50cm.yaml", "amy/corridor.yaml"))
    assert mission_for_test(both, spec) == "amy/square_50cm.yaml"
    assert mission_for_test(Submission("bo", ("bo/anything.yaml",)), spec) == "bo/anything.yaml"
    assert mission_for_test(Submission("cy", ("cy/a.yaml", "cy/b.yaml")), spec) is None


@pytest.mark.skipif(os.geteuid() != 0, reason="only root's jails need files others can read")
def test_a_submission_the_sandbox_cannot_read_is_one_error_before_any_run(tmp_path: Path) -> None:
    from roboscript.grading.sandbox import detect_isolation

    if not detect_isolation().complete:
        pytest.skip("needs bubblewrap's full isolation")
    mission = tmp_path / "ada.yaml"
    mission.write_text((MISSIONS / "square.yaml").read_text(encoding="utf-8"), encoding="utf-8")
    mission.chmod(0o600)
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nexpect:\n  - outcome: success\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"cannot grade ada: .*chmod -R o\+rX"):
        grade_class(find_specs([str(spec)]), find_submissions([str(mission)]).submissions)


@pytest.mark.skipif(os.geteuid() != 0, reason="only root's jails need files others can read")
def test_one_submission_the_sandbox_cannot_read_is_that_students_result(tmp_path: Path) -> None:
    from helpers import run_cli

    from roboscript.grading.sandbox import detect_isolation

    if not detect_isolation().complete:
        pytest.skip("needs bubblewrap's full isolation")
    spec = tmp_path / "spec.yaml"
    spec.write_text("test: t\nworld: empty\nexpect:\n  - outcome: success\n", encoding="utf-8")
    folder = tmp_path / "class"
    folder.mkdir()
    for student in ("ada", "ben"):
        shutil.copy(MISSIONS / "teacher" / "square" / "good.yaml", folder / f"{student}.yaml")
    (folder / "ada.yaml").chmod(0o600)
    done = run_cli("grade", str(spec), "--mission", str(folder), "--json", "--hang-after", "30")
    runs = {r["student"]: r for r in json.loads(done.stdout)["runs"]}
    assert runs["ben"]["status"] == "passed", done.stderr
    assert runs["ada"]["status"] == "invalid"
    assert runs["ada"]["message"].startswith("the grader's sandbox cannot show this submission")
    assert str(tmp_path) not in runs["ada"]["message"]


STREAMED_SPEC = """\
test: patrol
runs:
  - {seed: 1}
  - {seed: 2, start: {heading: 30 deg}, hidden: true}
max_time: 60 s
expect:
  - outcome: success
  - max_duration: 25 s
"""
PATROL = """\
mission: patrol
initial: out
states:
  out:
    do: {drive: {distance: 60 cm, speed: 6 cm/s}}
    on: {done: turn}
  turn:
    do: {rotate: {angle: 180 deg}}
    on: {done: back}
  back:
    do: {drive: {distance: 60 cm, speed: 6 cm/s}}
    on: {done: finished}
  finished:
    final: success
"""
"""About 25 s of driving: a record and replay of tens of kilobytes, as a real exercise's."""


@pytest.fixture(scope="module")
def streamed(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One student graded for real with a results file as the store of the runs."""
    root = tmp_path_factory.mktemp("streamed")
    (root / "spec.yaml").write_text(STREAMED_SPEC, encoding="utf-8")
    (root / "class").mkdir()
    (root / "class" / "ada.yaml").write_text(PATROL, encoding="utf-8")
    specs = find_specs([str(root / "spec.yaml")])
    submissions = find_submissions([str(root / "class")]).submissions
    results = ResultsFile(root / "r.jsonl", specs, submissions)
    told: list[RunResult] = []
    report = grade_class(
        specs, submissions, 1, told.append, hang_after_s=HANG_BOUND_S, store=results
    )
    results.close()
    return {"root": root, "report": report, "told": told, "file": root / "r.jsonl"}


def test_a_graded_class_holds_summaries_and_reads_each_run_in_full_from_its_store(
    streamed: dict[str, Any],
) -> None:
    report = streamed["report"]
    assert [r.status for r in report.results] == ["passed", "passed"]
    # the report holds no record or replay: the results file does, one line per run
    assert all(r.record is None and r.replay is None for r in report.results)
    lines = streamed["file"].read_text(encoding="utf-8").splitlines()
    assert len(lines) == 3  # the header, then each run as it ended
    for result in report.results:
        full = report.in_full(result)
        assert full.record is not None and full.replay
        assert replace(full, record=None, replay=None, debug="") == result
    # whoever watches the grading is still told each run in full as it ends
    assert all(r.record is not None for r in streamed["told"])


def _synthetic_class(
    streamed: dict[str, Any], folder: Path, students: int
) -> tuple[Any, list[Any]]:
    """A class of ``students`` copies of the streamed class's student (the same files)."""
    from roboscript.grading.batch import Submission

    root = streamed["root"]
    specs = find_specs([str(root / "spec.yaml")])
    mission = folder / "m.yaml"
    mission.write_text(PATROL, encoding="utf-8")
    return specs, [Submission(f"s{i:04d}", (str(mission),)) for i in range(students)]


def _graded_peak_bytes(
    streamed: dict[str, Any], folder: Path, students: int, monkeypatch: pytest.MonkeyPatch
) -> int:
    """The most memory grading (with a results file) and writing every report of a class of
    ``students`` held (bytes, as Python's allocator counts them), each run a copy of a real
    run's full result handed over by a stand-in for the worker pool as it ends."""
    import tracemalloc

    from roboscript.grading import batch
    from roboscript.grading.html_report import write_html
    from roboscript.grading.json_report import write_report_json

    first = streamed["file"].read_text(encoding="utf-8").splitlines()[1]
    run = json.loads(first)

    def pool(tasks: Any, jobs: Any = None, on_result: Any = None, keep: Any = None) -> Any:
        kept = []
        for task in tasks:  # a new full result for each, as a worker sends it
            result = RunResult.from_dict({**run, "student": task.student})
            kept.append(result if keep is None else keep(result))
        return kept

    monkeypatch.setattr(batch, "run_tasks", pool)
    specs, submissions = _synthetic_class(streamed, folder, students)
    tracemalloc.start()
    try:
        results = ResultsFile(folder / "r.jsonl", specs, submissions)
        report = grade_class(specs, submissions, 1, store=results)
        write_html(report, folder / "html")
        with open(os.devnull, "w", encoding="utf-8") as sink:
            write_report_json(report, sink)
        results.close()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_grading_a_class_holds_one_runs_record_at_a_time_however_large_the_class(
    streamed: dict[str, Any], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Counted, not timed: what grading holds at its peak, for a class and the same class
    # eight times over. Held whole until the end, the runs' records and replays (tens of
    # kilobytes each) would make the peak grow with the class; streamed to the results
    # file as they end, it barely moves.
    peaks = []
    for students in (6, 48):
        folder = tmp_path / str(students)
        folder.mkdir()
        peaks.append(_graded_peak_bytes(streamed, folder, students, monkeypatch))
    assert peaks[1] < 2 * peaks[0], peaks


def test_grade_draws_runs_read_back_from_a_temporary_results_file_it_then_removes(
    streamed: dict[str, Any], tmp_path: Path
) -> None:
    # Without --results, --html still draws every run in full (read back one at a time from
    # a results file of its own), and that file is gone once the reports are written.
    import tempfile

    from helpers import run_cli

    root = streamed["root"]
    spool = Path(tempfile.mkdtemp(prefix="rs-"))  # short: the fork server's socket lives here
    try:
        done = run_cli(
            "grade", str(root / "spec.yaml"), "--mission", str(root / "class"),
            "--html", str(tmp_path / "html"), "--quiet", "--hang-after", str(HANG_BOUND_S),
            wrap=("env", f"TMPDIR={spool}"),
        )  # fmt: skip
        assert done.returncode == 0, done.stderr
        pages = sorted((tmp_path / "html" / "runs").iterdir())
        assert len(pages) == 2
        assert all("Where the robot went" in p.read_text(encoding="utf-8") for p in pages)
        assert not list(spool.glob("roboscript-grade-*"))
    finally:
        shutil.rmtree(spool, ignore_errors=True)


def test_a_file_changed_and_put_back_while_graded_leaves_the_runs_after_it_uncounted(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # a run that read the changed file may end after it is put back: every run of the
    # student's after the change is uncounted, and their files are not looked at again
    from roboscript.grading import batch

    spec = tmp_path / "forward.yaml"
    spec.write_text(
        "test: forward\nworld: empty\nruns:\n  - {seed: 1}\n  - {seed: 2}\n  - {seed: 3}\n"
        + FORWARD_50CM_EXPECT,
        encoding="utf-8",
    )
    mission = tmp_path / "class" / "ada" / "forward.yaml"
    mission.parent.mkdir(parents=True)
    mission.write_text(FORWARD_50CM, encoding="utf-8")
    written_ns = mission.stat().st_mtime_ns
    looks = [0]
    changed_file = batch.changed_file

    def counted(*args: Any) -> str:
        looks[0] += 1
        return changed_file(*args)

    def change_then_put_back(result: RunResult) -> None:
        if looks[0] == 1:
            mission.write_text(FORWARD_50CM + "# pushed late\n", encoding="utf-8")
        elif looks[0] == 2:
            mission.write_text(FORWARD_50CM, encoding="utf-8")
            os.utime(mission, ns=(written_ns, written_ns))

    monkeypatch.setattr(batch, "changed_file", counted)
    report = grade_class(
        find_specs([str(spec)]),
        find_submissions([str(tmp_path / "class")]).submissions,
        jobs=1,
        on_result=change_then_put_back,
    )
    assert [r.status for r in report.results] == ["passed", "invalid", "invalid"]
    assert looks[0] == 2
