"""Reports of a large class: the work grows with the runs (never their square), and every
report stays bounded and valid for thousands of runs. Built by hand (no simulation)."""

from __future__ import annotations

import csv
import io
import json
import xml.etree.ElementTree as ET
from dataclasses import fields, replace
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

from hand_graded import hand_spec, student_runs

from roboscript.grading.batch import ClassReport, Submission
from roboscript.grading.gradebook import gradebook_csv
from roboscript.grading.gradescope import write_gradescope
from roboscript.grading.html_report import write_html
from roboscript.grading.json_report import write_report_json
from roboscript.grading.junit import junit_xml
from roboscript.grading.prairielearn import write_prairielearn
from roboscript.grading.record import RunResult, Verdict
from roboscript.grading.spec import load_test_spec
from roboscript.grading.table import format_table

READS = [0]
"""How many times a run's ``student`` was read: the work of finding a student's runs."""


class _Counted(RunResult):
    """A run that counts the reads of its ``student`` (a search of the runs reads it once
    per run looked at)."""

    def __getattribute__(self, name: str) -> Any:
        if name == "student":
            READS[0] += 1
        return super().__getattribute__(name)


def _counted(result: RunResult) -> RunResult:
    return _Counted(**{f.name: getattr(result, f.name) for f in fields(result)})


def synthetic_class(tmp_path: Path, students: int, counted: bool = False) -> ClassReport:
    """A class of ``students`` (three runs each, every third one's run 2 crashed and run 3
    failed), as :mod:`hand_graded` makes one student's runs."""
    spec = hand_spec(tmp_path)
    names = [f"student-{i:05d}" for i in range(students)]
    results = [r for i, name in enumerate(names) for r in student_runs(spec, name, i % 3 > 0)]
    if counted:
        results = [_counted(r) for r in results]
    submissions = [Submission(name, (f"class/{name}.yaml",)) for name in names]
    return ClassReport([spec], submissions, results, dict(spec.worlds))


def _reads_reporting(tmp_path: Path, students: int) -> int:
    """The ``student`` reads of writing the table, the gradebook, JUnit and --json."""
    report = synthetic_class(tmp_path, students, counted=True)
    READS[0] = 0
    format_table(report)
    gradebook_csv(report)
    junit_xml(report)
    with (tmp_path / "report.json").open("w", encoding="utf-8") as stream:
        write_report_json(report, stream)
    write_html(report, tmp_path / f"html-{students}")
    return READS[0]


def test_reporting_a_class_looks_each_run_up_a_fixed_number_of_times(tmp_path: Path) -> None:
    # Counted, not timed: four times the class is four times the work. Searching every run
    # for each student's cell made it sixteen times (a class of thousands took hours).
    small = _reads_reporting(tmp_path, 30)
    large = _reads_reporting(tmp_path, 120)
    assert large <= 4.5 * small, (small, large)


CLASS_RUNS = 2001
"""A class of 667 students of three runs each."""


def test_every_class_report_of_two_thousand_runs_is_whole_valid_and_bounded(
    tmp_path: Path,
) -> None:
    # Bounded per run: a report of a large class grows with its runs, never faster, and each
    # file stays one any reader opens (JUnit and CSV parse, every row and case is there).
    report = synthetic_class(tmp_path, CLASS_RUNS // 3)
    students = len(report.submissions)
    assert len(report.results) == CLASS_RUNS

    table = format_table(report)
    assert len(table.splitlines()) == students + 3  # header, rows, blank line, summary
    assert len(table.encode("utf-8")) < 400 * students

    rows = list(csv.reader(io.StringIO(gradebook_csv(report))))
    assert len(rows) == students + 1 and {len(row) for row in rows} == {len(rows[0])}

    junit = junit_xml(report)
    suites = ET.fromstring(junit)
    assert len(suites.findall(".//testcase")) == CLASS_RUNS
    assert len(junit.encode("utf-8")) < 3_000 * CLASS_RUNS

    with (tmp_path / "report.json").open("w", encoding="utf-8") as stream:
        write_report_json(report, stream)
    whole = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert len(whole["runs"]) == CLASS_RUNS and len(whole["students"]) == students

    index = write_html(report, tmp_path / "html")
    pages = list((tmp_path / "html" / "runs").iterdir())
    assert len(pages) == CLASS_RUNS
    assert len(list((tmp_path / "html" / "students").iterdir())) == students
    assert index.stat().st_size < 2_000 * CLASS_RUNS
    for page in [index, *pages[:: CLASS_RUNS // 20]]:
        _check_html(page.read_text(encoding="utf-8"))


def test_one_submission_of_two_thousand_runs_gives_whole_platform_results(
    tmp_path: Path,
) -> None:
    # Gradescope and PrairieLearn grade one submission: ten tests of 200 runs each.
    specs = []
    for t in range(10):
        folder = tmp_path / f"test-{t}"
        folder.mkdir()
        runs = "".join(f"  - {{seed: {i}}}\n" for i in range(1, 201))
        (folder / "t.yaml").write_text(
            f"test: t{t}\npoints: 10\nruns:\n{runs}expect:\n  - outcome: success\n",
            encoding="utf-8",
        )
        specs.append(load_test_spec(folder / "t.yaml"))
    outcome = Verdict("outcome", True, detail="the mission ended in success")
    results = [
        spec.result(
            variant,
            student="ada",
            mission="ada.yaml",
            status="passed" if variant.index % 2 else "failed",
            score=1.0 if variant.index % 2 else 0.0,
            verdicts=(replace(outcome, passed=bool(variant.index % 2)),),
        )
        for spec in specs
        for variant in spec.variants
    ]
    report = ClassReport(specs, [Submission("ada", ("ada.yaml",))], results)
    gradescope = tmp_path / "gradescope.json"
    write_gradescope(report, gradescope)
    prairielearn = tmp_path / "prairielearn.json"
    write_prairielearn(report, prairielearn)
    for path, key, most in ((gradescope, "max_score", "score"), (prairielearn, "max_points", "")):
        data = json.loads(path.read_text(encoding="utf-8"))
        assert len(data["tests"]) == 2_000
        assert path.stat().st_size < 1_000 * 2_000
        assert round(sum(test[key] for test in data["tests"]), 4) == 100.0
        if most:
            assert data[most] == 50.0  # every other run passed
        else:
            assert data["score"] == 0.5


class _Balanced(HTMLParser):
    """Checks that every element opened is closed, in order (void elements aside)."""

    VOID = frozenset({"meta", "br", "img", "input", "link", "hr", "col", "source", "wbr"})

    def __init__(self) -> None:
        super().__init__()
        self.open: list[str] = []

    def handle_starttag(self, tag: str, attrs: Any) -> None:
        if tag not in self.VOID:
            self.open.append(tag)

    def handle_startendtag(self, tag: str, attrs: Any) -> None:
        pass

    def handle_endtag(self, tag: str) -> None:
        assert self.open and self.open[-1] == tag, (tag, self.open[-5:])
        self.open.pop()


def _check_html(text: str) -> None:
    parser = _Balanced()
    parser.feed(text)
    parser.close()
    assert parser.open == [], parser.open
